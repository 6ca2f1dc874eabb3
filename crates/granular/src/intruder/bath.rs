//! Bath velocity distributions f(v) of the thermalised point particles (one velocity
//! component, the one normal to the intruder's surface), their side fluxes (G-5 to G-7) and
//! exact samplers of the velocity of the bath particle that collides (G-12 and G-13).
//!
//! All fluxes here are *per unit bath density*: multiply by `rho` to get G-5 to G-7.
//!
//! Sides: [`Side::Right`] is the paper's "+" side (G-5): bath particles with `v < v1`
//! that the intruder catches up with on its right; [`Side::Left`] is "-" (G-6).

use std::f64::consts::FRAC_2_SQRT_PI;

use serde::{Deserialize, Serialize};

use crate::random::{RngExt, Stream};

mod gaussian;
mod power_law;
mod tabulated;
pub(crate) use gaussian::gaussian_h;
pub use gaussian::{Gaussian, sample_w_gaussian};
pub use power_law::PowerLaw;
#[cfg(test)]
pub(crate) use power_law::power_law_cdf_scaled;
#[cfg(test)]
pub(crate) use tabulated::MAX_TABLE_MAGNITUDE;
pub use tabulated::Tabulated;
pub(crate) use tabulated::sample_linear_product;

/// `1/sqrt(pi)`.
pub(crate) const FRAC_1_SQRT_PI: f64 = 0.5 * FRAC_2_SQRT_PI;
/// `sqrt(pi)`.
pub(crate) const SQRT_PI: f64 = 1.772_453_850_905_516;

/// The side of the intruder hit by a bath particle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// "+" side (G-5, G-12): the bath particle has `v <= v1`.
    Right,
    /// "-" side (G-6, G-13): the bath particle has `v >= v1`.
    Left,
}

/// Why a bath distribution could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BathError {
    /// The table file could not be read.
    #[error("cannot read bath table {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A line of the table could not be parsed.
    #[error("bath table {path}, line {line}: {message}")]
    Parse {
        /// The file (or `<inline>`).
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The table is not a valid density.
    #[error("invalid bath table: {0}")]
    Invalid(String),
    /// A parameter is out of range.
    #[error("invalid bath parameter: {0}")]
    Parameter(String),
}

/// Interface of a bath velocity distribution (one velocity component).
pub trait BathDistribution {
    /// Probability density f(v).
    fn density(&self, v: f64) -> f64;
    /// Cumulative distribution `F(v) = int_{-inf}^{v} f`.
    fn cdf(&self, v: f64) -> f64;
    /// Survival function `1 - F(v)`, accurate in the upper tail.
    fn sf(&self, v: f64) -> f64 {
        1.0 - self.cdf(v)
    }
    /// `<v^2>` (the bath temperature is `m <v^2>`).
    fn second_moment(&self) -> f64;
    /// `<|v|>`; the collision rate of an intruder at rest is `rho <|v|>`.
    fn mean_speed(&self) -> f64;
    /// `phi_+(v1)/rho = int_{-inf}^{v1} (v1 - v) f(v) dv` (G-5).
    fn flux_plus(&self, v1: f64) -> f64;
    /// `phi_-(v1)/rho = int_{v1}^{inf} (v - v1) f(v) dv` (G-6).
    fn flux_minus(&self, v1: f64) -> f64;
    /// Total rate per unit density (G-7).
    fn flux(&self, v1: f64) -> f64 {
        self.flux_plus(v1) + self.flux_minus(v1)
    }
    /// Flux on one side.
    fn flux_side(&self, side: Side, v1: f64) -> f64 {
        match side {
            Side::Right => self.flux_plus(v1),
            Side::Left => self.flux_minus(v1),
        }
    }
    /// A bath velocity drawn from f.
    fn sample(&self, rng: &mut Stream) -> f64;
    /// A velocity drawn from the speed-weighted density `|v| f(v) / <|v|>`.
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64;
    /// A velocity from the thinning mark density `(w + |v|) f(v) / (w + <|v|>)` for
    /// `w >= 0` (`mean_speed` is `<|v|>`): the mixture of `f` (weight `w`) and of
    /// `|v| f / <|v|>` (weight `<|v|>`).
    #[inline]
    fn sample_mark(&self, w: f64, mean_speed: f64, rng: &mut Stream) -> f64 {
        if rng.random::<f64>() * (w + mean_speed) < w {
            self.sample(rng)
        } else {
            self.sample_speed_weighted(rng)
        }
    }
    /// An exact draw from g_+ (G-12) or g_- (G-13).
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64;
    /// Cumulative distribution function of g_side(., v1) (G-12, G-13) at `v` (tests, figures).
    ///
    /// Uses `int_{-inf}^{v} (v1 - w) f(w) dw = phi_+(v) + (v1 - v) F(v)` (and its mirror
    /// image), so it is exact whenever the fluxes and F are.
    fn colliding_cdf(&self, side: Side, v1: f64, v: f64) -> f64 {
        match side {
            Side::Right => {
                if v >= v1 {
                    1.0
                } else {
                    ((self.flux_plus(v) + (v1 - v) * self.cdf(v)) / self.flux_plus(v1)).min(1.0)
                }
            }
            Side::Left => {
                if v <= v1 {
                    0.0
                } else {
                    let upper = self.flux_minus(v) + (v - v1) * self.sf(v);
                    (1.0 - upper / self.flux_minus(v1)).max(0.0)
                }
            }
        }
    }
    /// Density g_side(v, v1) of G-12 and G-13.
    fn colliding_density(&self, side: Side, v1: f64, v: f64) -> f64 {
        let (w, phi) = match side {
            Side::Right => (v1 - v, self.flux_plus(v1)),
            Side::Left => (v - v1, self.flux_minus(v1)),
        };
        if w < 0.0 {
            0.0
        } else {
            w * self.density(v) / phi
        }
    }
}

// ---------------------------------------------------------------------------------------
// Configuration and the closed set of baths
// ---------------------------------------------------------------------------------------

/// Bath velocity distribution of an intruder engine (the scenario's `[intruder.bath]`
/// table is read into it by `scenario::BathTable`).
#[derive(Clone, Debug, PartialEq)]
pub enum BathConfig {
    /// Gaussian, G-14, `a = m / (2 T_B)`.
    Gaussian {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Power law, G-19, `a = m / T_B` (since `<v^2> = 1/a`).
    PowerLaw {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Piecewise-linear density through the points `(v, f)` (velocity units, density in
    /// 1/velocity), normalised ([`Tabulated::new`]).
    Tabulated {
        /// The points, velocities increasing.
        points: Vec<(f64, f64)>,
    },
}

impl Default for BathConfig {
    fn default() -> Self {
        // a = 1 with m = 1, as in the paper's figures.
        BathConfig::Gaussian { temperature: 0.5 }
    }
}

/// One of the supported baths (static dispatch); serialisable for checkpoints.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Bath {
    /// G-14.
    Gaussian(Gaussian),
    /// G-19.
    PowerLaw(PowerLaw),
    /// Tabulated.
    Tabulated(Box<Tabulated>),
}

impl BathConfig {
    /// Builds the bath for bath particles of mass `m`.
    pub(crate) fn build(&self, m: f64) -> Result<Bath, BathError> {
        Ok(match self {
            BathConfig::Gaussian { temperature } => {
                Bath::Gaussian(Gaussian::with_temperature(*temperature, m)?)
            }
            BathConfig::PowerLaw { temperature } => {
                Bath::PowerLaw(PowerLaw::with_temperature(*temperature, m)?)
            }
            BathConfig::Tabulated { points } => Bath::Tabulated(Box::new(Tabulated::new(points)?)),
        })
    }
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bath::Gaussian($b) => $e,
            Bath::PowerLaw($b) => $e,
            Bath::Tabulated($b) => $e,
        }
    };
}

impl BathDistribution for Bath {
    #[inline]
    fn density(&self, v: f64) -> f64 {
        dispatch!(self, b => b.density(v))
    }
    fn cdf(&self, v: f64) -> f64 {
        dispatch!(self, b => b.cdf(v))
    }
    fn sf(&self, v: f64) -> f64 {
        dispatch!(self, b => b.sf(v))
    }
    fn second_moment(&self) -> f64 {
        dispatch!(self, b => b.second_moment())
    }
    #[inline]
    fn mean_speed(&self) -> f64 {
        dispatch!(self, b => b.mean_speed())
    }
    #[inline]
    fn flux_plus(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux_plus(v1))
    }
    #[inline]
    fn flux_minus(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux_minus(v1))
    }
    #[inline]
    fn flux(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux(v1))
    }
    #[inline]
    fn sample(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample(rng))
    }
    #[inline]
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_speed_weighted(rng))
    }
    #[inline]
    fn sample_mark(&self, w: f64, mean_speed: f64, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_mark(w, mean_speed, rng))
    }
    #[inline]
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_colliding(side, v1, rng))
    }
}

#[cfg(test)]
mod tests {
    use super::gaussian::{h_asymptotic, h_direct, h_erfcx};
    use super::*;
    use crate::random::stream;

    #[test]
    fn power_law_cdf_is_continuous_and_normalised() {
        for &y in &[-2.0f64, 2.0] {
            let a = power_law_cdf_scaled(y - 1e-12);
            let b = power_law_cdf_scaled(y + 1e-12);
            assert!((a - b).abs() < 1e-10, "{y}: {a} {b}");
        }
        assert!((power_law_cdf_scaled(0.0) - 0.5).abs() < 1e-15);
        assert!(power_law_cdf_scaled(1e6) >= 1.0 - 1e-15);
        assert!(power_law_cdf_scaled(-1e6) > 0.0);
    }

    #[test]
    fn gaussian_h_branches_agree() {
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(rel(h_direct(-3.0), h_erfcx(-3.0)) < 1e-9);
        assert!(rel(h_asymptotic(-8.0), h_erfcx(-8.0)) < 1e-12);
    }

    #[test]
    fn linear_product_sampler_mean() {
        let mut rng = stream(3, &[1]);
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|_| sample_linear_product(1.0, 0.0, 1.0, 0.0, &mut rng))
            .sum::<f64>()
            / n as f64;
        // density 3 (1-t)^2: mean 1/4
        assert!((mean - 0.25).abs() < 4.0 * (3.0f64 / 80.0).sqrt() / (n as f64).sqrt());
    }

    /// The Gaussian thinning mark sampler (one random word for the mixture choice and the
    /// sign) draws `(w + |v|) f(v) / (w + <|v|>)`: chi-square against its exact CDF
    /// `(w F(v) + S(v)) / (w + <|v|>)`, `S(v) = int_{-inf}^v |u| f(u) du`.
    #[test]
    fn gaussian_mark_sampler_is_exact() {
        let g = Gaussian::new(1.7).unwrap();
        let ms = g.mean_speed();
        let s_cdf = |v: f64| {
            let tail = (-g.a * v * v).exp() * 0.5 * ms;
            if v < 0.0 { tail } else { ms - tail }
        };
        for (k, &w) in [0.0, 0.3, 2.5].iter().enumerate() {
            let mut rng = stream(21, &[k as u64]);
            let mut h = crate::stats::Histogram::new(-3.0, 3.0, 60);
            for _ in 0..400_000 {
                h.push(g.sample_mark(w, ms, &mut rng));
            }
            let c = crate::stats::chi_square_test(&h, |v| (w * g.cdf(v) + s_cdf(v)) / (w + ms));
            assert!(c.p_value > 1e-4, "w = {w}: {c:?}");
        }
    }

    #[test]
    fn table_bound_is_the_scenario_bound() {
        assert_eq!(MAX_TABLE_MAGNITUDE, crate::scenario::MAGNITUDE);
    }
}
