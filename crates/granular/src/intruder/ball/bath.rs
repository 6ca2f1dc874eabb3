//! Isotropic bath velocity distributions `f(u)` in `d` dimensions (2 or 3) for the disk and
//! sphere intruders: the Gaussian (G-14 in every component), the isotropic power law
//! (G-43) and a speed distribution given by a table (G-44). Each knows its speed
//! distribution `P(c)` (`c = |u|`), its moments, the mean relative speed `<|u - V|>` of an
//! intruder at velocity `V` (G-33 closed form for the Gaussian, the quadrature G-34
//! otherwise) and exact samplers of `f` and of the speed-weighted `|u| f(u) / <c>`, from
//! which the engines draw the colliding bath particle (G-35, G-38).
//!
//! Plain configuration ([`IsotropicBathConfig`]): temperatures and table points, no file
//! names (the scenario layer reads files).

use rand_distr::Gamma;
use serde::{Deserialize, Serialize};

use super::BallError;
use crate::intruder::bath::{Gaussian, sample_linear_product};
use rand::Rng;

use crate::random::{RngExt, Stream, std_normal};
use crate::theory::equilibrium;
use crate::theory::intruder::{gaussian_mean_relative_speed, isotropic_mean_relative_speed};
use crate::vector::Vector;

/// The bath of a disk or sphere intruder, as configured.
#[derive(Clone, Debug, PartialEq)]
pub enum IsotropicBathConfig {
    /// Gaussian, `f(u) = (a/pi)^{d/2} exp(-a u^2)`, `a = m/(2 T_B)` (G-14 per component).
    Gaussian {
        /// Bath temperature `T_B = m <u_x^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Isotropic power law G-43, `f(u) ∝ (1 + a^2 u^4)^{-(d+3)/4}` (G-19 in 1D).
    PowerLaw {
        /// Bath temperature `T_B = m <u_x^2> = m <u^2>/d` (energy units).
        temperature: f64,
    },
    /// Speed distribution `P(c)` through the points `(c_k, P_k)`, linear in between, zero
    /// outside, normalised (G-44). Speeds in velocity units, `P` in 1/velocity.
    Tabulated {
        /// The points `(c_k, P_k)`, speeds increasing, `c_k >= 0`, `P_k >= 0`.
        points: Vec<(f64, f64)>,
    },
}

impl Default for IsotropicBathConfig {
    fn default() -> Self {
        // a = 1 with m = 1, as the 1D default.
        IsotropicBathConfig::Gaussian { temperature: 0.5 }
    }
}

/// What an isotropic bath offers the engines. `dimension()` is 2 or 3; speeds are `|u|`.
pub(crate) trait IsotropicDistribution {
    /// Dimension `d` of the velocity space.
    fn dimension(&self) -> usize;
    /// `<c> = <|u|>` (velocity units).
    fn mean_speed(&self) -> f64;
    /// `<c^2> = <|u|^2>` (velocity^2); the bath temperature is `m <c^2> / d`.
    fn mean_square_speed(&self) -> f64;
    /// Speed density `P(c)` (1/velocity).
    fn speed_density(&self, c: f64) -> f64;
    /// `int_0^c P`.
    #[cfg(test)]
    fn speed_cdf(&self, c: f64) -> f64;
    /// A speed drawn from `P`.
    fn sample_speed(&self, rng: &mut Stream) -> f64;
    /// A speed drawn from `c P(c) / <c>`.
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64;
    /// `<|u - V|>` at intruder speed `|V| = speed` (G-33 or G-34; velocity units).
    fn mean_relative_speed(&self, speed: f64) -> f64;

    /// A velocity drawn from `f`: a speed from `P` in a uniform direction.
    #[inline]
    fn sample_velocity<const D: usize>(&self, rng: &mut Stream) -> Vector<D> {
        uniform_direction::<D>(rng) * self.sample_speed(rng)
    }

    /// A velocity `u` drawn from the thinning mark density `(w + |u|) f(u) / (w + <c>)` for
    /// `w >= 0` (G-38): `f` with probability `w / (w + <c>)`, else `|u| f / <c>`; returned
    /// with its speed `|u|`.
    #[inline]
    fn sample_mark<const D: usize>(
        &self,
        w: f64,
        mean_speed: f64,
        rng: &mut Stream,
    ) -> (Vector<D>, f64) {
        let speed = if rng.random::<f64>() * (w + mean_speed) < w {
            self.sample_speed(rng)
        } else {
            self.sample_speed_weighted(rng)
        };
        (uniform_direction::<D>(rng) * speed, speed)
    }
}

/// A unit vector uniform on the sphere `S^{D-1}`: von Neumann's squaring of a point uniform
/// in the unit disk in 2D (`((x^2 - y^2), 2xy)/(x^2 + y^2)`, no square root), Marsaglia's
/// method in 3D (`(2x sqrt(1-s), 2y sqrt(1-s), 1 - 2s)`, `s = x^2 + y^2 < 1`), normalised
/// normal deviates otherwise.
#[inline]
pub(crate) fn uniform_direction<const D: usize>(rng: &mut Stream) -> Vector<D> {
    let mut out = Vector::<D>::zero();
    if D == 2 || D == 3 {
        // x and y from the two 32-bit halves of one random word: uniform on the grid
        // (k + 1/2) 2^-31 - 1 of (-1, 1) (never 0, symmetric).
        const SCALE: f64 = 1.0 / 2_147_483_648.0;
        let (x, y, s) = loop {
            let bits = rng.next_u64();
            // (through u32: a 32-bit integer converts to f64 in one instruction)
            let x = (f64::from((bits >> 32) as u32) + 0.5) * SCALE - 1.0;
            let y = (f64::from(bits as u32) + 0.5) * SCALE - 1.0;
            let s = x * x + y * y;
            if s < 1.0 {
                break (x, y, s);
            }
        };
        if D == 2 {
            out.0[0] = (x * x - y * y) / s;
            out.0[1] = 2.0 * x * y / s;
        } else {
            let r = 2.0 * (1.0 - s).sqrt();
            out.0[0] = x * r;
            out.0[1] = y * r;
            out.0[2] = 1.0 - 2.0 * s;
        }
        return out;
    }
    loop {
        let mut n2 = 0.0;
        for k in 0..D {
            let z = std_normal(rng);
            out.0[k] = z;
            n2 += z * z;
        }
        if n2 > 0.0 {
            return out * (1.0 / n2.sqrt());
        }
    }
}

// ---------------------------------------------------------------------------------------
// Gaussian
// ---------------------------------------------------------------------------------------

/// The Gaussian bath `f(u) = (a/pi)^{d/2} exp(-a u^2)`, `a = m/(2 T_B)`: every component is
/// G-14 with the same `a`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GaussianBath {
    dimension: usize,
    /// `a` (inverse velocity squared).
    pub a: f64,
    /// `1/sqrt(2a)`, the standard deviation of a component.
    sigma: f64,
    mean_speed: f64,
}

impl GaussianBath {
    /// The Gaussian of parameter `a > 0` in `dimension` 2 or 3.
    pub(crate) fn new(dimension: usize, a: f64) -> Self {
        Self {
            dimension,
            a,
            sigma: (0.5 / a).sqrt(),
            mean_speed: equilibrium::mean_speed(dimension, 1.0, 0.5 / a),
        }
    }

    /// The one-component marginal, G-14 with the same `a` (its side fluxes G-15 and the
    /// exact sampler of G-12 serve the direct method's impact-normal step, G-36).
    pub(crate) fn marginal(&self) -> Result<Gaussian, BallError> {
        Gaussian::new(self.a).map_err(|e| BallError::new("bath.temperature", e.to_string()))
    }
}

impl IsotropicDistribution for GaussianBath {
    fn dimension(&self) -> usize {
        self.dimension
    }
    #[inline]
    fn mean_speed(&self) -> f64 {
        self.mean_speed
    }
    fn mean_square_speed(&self) -> f64 {
        self.dimension as f64 / (2.0 * self.a)
    }
    fn speed_density(&self, c: f64) -> f64 {
        equilibrium::speed_density(self.dimension, c, 1.0, 0.5 / self.a)
    }
    #[cfg(test)]
    fn speed_cdf(&self, c: f64) -> f64 {
        equilibrium::speed_cdf(self.dimension, c, 1.0, 0.5 / self.a)
    }
    fn sample_speed(&self, rng: &mut Stream) -> f64 {
        let mut n2 = 0.0;
        for _ in 0..self.dimension {
            let z = std_normal(rng);
            n2 += z * z;
        }
        self.sigma * n2.sqrt()
    }
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        // c P(c) ∝ c^d exp(-a c^2): the chi distribution with d + 1 degrees of freedom.
        let mut n2 = 0.0;
        for _ in 0..=self.dimension {
            let z = std_normal(rng);
            n2 += z * z;
        }
        self.sigma * n2.sqrt()
    }
    fn mean_relative_speed(&self, speed: f64) -> f64 {
        gaussian_mean_relative_speed(self.dimension, self.a, speed)
    }
    /// `D` normal deviates times `1/sqrt(2a)`.
    #[inline]
    fn sample_velocity<const D: usize>(&self, rng: &mut Stream) -> Vector<D> {
        let mut u = Vector::<D>::zero();
        for k in 0..D {
            u.0[k] = self.sigma * std_normal(rng);
        }
        u
    }
    /// `f`: `D` normal deviates; `|u| f / <c>`: `D + 1` normal deviates `z`, the first `D`
    /// rescaled to the length of all `D + 1` (the direction of `z_1..z_D` is uniform and
    /// independent of `|z|`, which has the chi law of `D + 1` degrees of freedom, the
    /// speed-weighted Maxwell law).
    #[inline]
    fn sample_mark<const D: usize>(
        &self,
        w: f64,
        mean_speed: f64,
        rng: &mut Stream,
    ) -> (Vector<D>, f64) {
        let mut u = Vector::<D>::zero();
        let mut n2 = 0.0;
        for k in 0..D {
            let z = std_normal(rng);
            u.0[k] = z;
            n2 += z * z;
        }
        let norm = n2.sqrt();
        if rng.random::<f64>() * (w + mean_speed) < w {
            return (u * self.sigma, self.sigma * norm);
        }
        let extra = std_normal(rng);
        let speed = self.sigma * (n2 + extra * extra).sqrt();
        (u * (speed / norm), speed)
    }
}

// ---------------------------------------------------------------------------------------
// Power law
// ---------------------------------------------------------------------------------------

/// The isotropic power law G-43, `f(u) = C_d (1 + a^2 |u|^4)^{-(d+3)/4}` with
/// `C_d = 4 a^{d/2} / (S_{d-1} B(d/4, 3/4))`. In 1D it is G-19. Its speed `c` has
/// `t = a^2 c^4 ~ BetaPrime(d/4, 3/4)`, so `P(c) ~ c^-4` and each component has the
/// `|u_x|^-4` tail of G-19; `<c^2> = B((d+2)/4, 1/4) / (a B(d/4, 3/4))` (finite),
/// `<c> = B((d+1)/4, 1/2) / (sqrt(a) B(d/4, 3/4))`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLawBath {
    dimension: usize,
    /// `a` (inverse velocity squared).
    pub a: f64,
    /// `B(d/4, 3/4)`.
    beta: f64,
    mean_speed: f64,
    mean_square_speed: f64,
}

impl PowerLawBath {
    /// The power law of parameter `a > 0` in `dimension` 2 or 3.
    pub(crate) fn new(dimension: usize, a: f64) -> Self {
        let d = dimension as f64;
        let beta = puruspe::beta(d / 4.0, 0.75);
        Self {
            dimension,
            a,
            beta,
            mean_speed: puruspe::beta((d + 1.0) / 4.0, 0.5) / (a.sqrt() * beta),
            mean_square_speed: puruspe::beta((d + 2.0) / 4.0, 0.25) / (a * beta),
        }
    }

    /// The parameter `a` of the bath of temperature `T_B = m <c^2>/d` (G-43):
    /// `a = m B((d+2)/4, 1/4) / (d T_B B(d/4, 3/4))` (`m / T_B` in 1D, as for G-19).
    pub(crate) fn parameter_for_temperature(
        dimension: usize,
        temperature: f64,
        bath_mass: f64,
    ) -> f64 {
        let d = dimension as f64;
        bath_mass * puruspe::beta((d + 2.0) / 4.0, 0.25)
            / (d * temperature * puruspe::beta(d / 4.0, 0.75))
    }

    /// `t = X / Y`, `X ~ Gamma(p)`, `Y ~ Gamma(q)`: a BetaPrime(p, q) deviate.
    fn beta_prime(p: f64, q: f64, rng: &mut Stream) -> f64 {
        let (gp, gq) = match (Gamma::new(p, 1.0), Gamma::new(q, 1.0)) {
            (Ok(gp), Ok(gq)) => (gp, gq),
            // The shapes are fixed positive constants (d/4, 3/4, (d+1)/4, 1/2).
            _ => unreachable!("positive Gamma shapes"),
        };
        let x: f64 = rng.sample(gp);
        let y: f64 = rng.sample(gq);
        x / y
    }
}

impl IsotropicDistribution for PowerLawBath {
    fn dimension(&self) -> usize {
        self.dimension
    }
    fn mean_speed(&self) -> f64 {
        self.mean_speed
    }
    fn mean_square_speed(&self) -> f64 {
        self.mean_square_speed
    }
    /// `P(c) = 4 a^{d/2} c^{d-1} (1 + a^2 c^4)^{-(d+3)/4} / B(d/4, 3/4)`.
    fn speed_density(&self, c: f64) -> f64 {
        if c < 0.0 {
            return 0.0;
        }
        let d = self.dimension as f64;
        let y = self.a.sqrt() * c;
        4.0 * self.a.sqrt() * y.powf(d - 1.0) * (1.0 + y.powi(4)).powf(-(d + 3.0) / 4.0) / self.beta
    }
    /// `I_{t/(1+t)}(d/4, 3/4)` (regularised incomplete beta), `t = a^2 c^4`.
    #[cfg(test)]
    fn speed_cdf(&self, c: f64) -> f64 {
        if c <= 0.0 {
            return 0.0;
        }
        let t = (self.a * c * c).powi(2);
        puruspe::betai(self.dimension as f64 / 4.0, 0.75, t / (1.0 + t))
    }
    fn sample_speed(&self, rng: &mut Stream) -> f64 {
        let t = Self::beta_prime(self.dimension as f64 / 4.0, 0.75, rng);
        t.sqrt().sqrt() / self.a.sqrt()
    }
    /// `c P(c)`: `t ~ BetaPrime((d+1)/4, 1/2)`.
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        let t = Self::beta_prime((self.dimension as f64 + 1.0) / 4.0, 0.5, rng);
        t.sqrt().sqrt() / self.a.sqrt()
    }
    fn mean_relative_speed(&self, speed: f64) -> f64 {
        isotropic_mean_relative_speed(
            self.dimension,
            speed,
            &|c| self.speed_density(c),
            &[0.0, f64::INFINITY],
            1.0 / self.a.sqrt(),
        )
    }
}

// ---------------------------------------------------------------------------------------
// Tabulated speed distribution
// ---------------------------------------------------------------------------------------

/// Largest magnitude of a table value: beyond it `c^3 P` may overflow.
const TABLE_MAGNITUDE: f64 = 1e100;

/// A speed distribution `P(c)` given by points, linear in between, zero outside
/// `[c_0, c_n]`, normalised (G-44): `f(u) = P(|u|) / (S_{d-1} |u|^{d-1})`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeedTable {
    dimension: usize,
    c: Vec<f64>,
    p: Vec<f64>,
    /// `int_{c_0}^{c_k} P`.
    cumulative: Vec<f64>,
    /// `int_{c_0}^{c_k} c P`.
    cumulative_speed: Vec<f64>,
    mean_square_speed: f64,
}

impl SpeedTable {
    /// Builds the normalised table; errors name `bath.points` and the offending point.
    pub(crate) fn new(dimension: usize, points: &[(f64, f64)]) -> Result<Self, BallError> {
        let bad = |m: String| Err(BallError::new("bath.points", m));
        if points.len() < 2 {
            return bad(format!(
                "has {} point(s); a speed distribution needs at least two points [c, P(c)]",
                points.len()
            ));
        }
        for (i, &(c, p)) in points.iter().enumerate() {
            if !c.is_finite() || !p.is_finite() {
                return bad(format!(
                    "point {i} is [{c}, {p}]; speeds and densities must be finite numbers"
                ));
            }
            if c < 0.0 {
                return bad(format!(
                    "point {i} has speed {c}; the table is the distribution P(c) of the speed c = |u| >= 0 in {dimension} dimensions (not of one velocity component): give speeds >= 0"
                ));
            }
            if p < 0.0 {
                return bad(format!(
                    "point {i} has density {p}; a speed distribution P(c) is never negative: give values >= 0"
                ));
            }
            if c > TABLE_MAGNITUDE || p > TABLE_MAGNITUDE {
                return bad(format!(
                    "point {i} is [{c:e}, {p:e}], beyond 1e100, where the moments c^2 P of the table overflow; rescale the table to units in which the bath's speeds are of order 1"
                ));
            }
            if i > 0 && c <= points[i - 1].0 {
                return bad(format!(
                    "point {i} has speed {c} after {}; the speeds must increase strictly",
                    points[i - 1].0
                ));
            }
        }
        let c: Vec<f64> = points.iter().map(|x| x.0).collect();
        let raw: Vec<f64> = points.iter().map(|x| x.1).collect();
        let norm: f64 = (0..c.len() - 1)
            .map(|k| 0.5 * (c[k + 1] - c[k]) * (raw[k] + raw[k + 1]))
            .sum();
        if !(norm > 0.0 && norm.is_finite()) {
            return bad(
                "integrates to zero, so it cannot be normalised to a speed distribution: give at least one positive density".into(),
            );
        }
        let p: Vec<f64> = raw.iter().map(|x| x / norm).collect();
        let n = c.len();
        let (mut cumulative, mut cumulative_speed) = (vec![0.0; n], vec![0.0; n]);
        let mut mean_square_speed = 0.0;
        for k in 0..n - 1 {
            let (a, b, fa, fb) = (c[k], c[k + 1], p[k], p[k + 1]);
            let h = b - a;
            cumulative[k + 1] = cumulative[k] + 0.5 * h * (fa + fb);
            cumulative_speed[k + 1] =
                cumulative_speed[k] + h * (fa * (2.0 * a + b) + fb * (a + 2.0 * b)) / 6.0;
            // int_0^1 (a + t h)^2 (fa (1 - t) + fb t) h dt
            mean_square_speed += h
                * (fa * (a * a / 2.0 + a * h / 3.0 + h * h / 12.0)
                    + fb * (a * a / 2.0 + 2.0 * a * h / 3.0 + h * h / 4.0));
        }
        Ok(Self {
            dimension,
            c,
            p,
            cumulative,
            cumulative_speed,
            mean_square_speed,
        })
    }

    /// The piece `k` with `w_k <= u < w_{k+1}` of a cumulative table.
    fn piece(weights: &[f64], u: f64) -> usize {
        weights
            .partition_point(|&w| w <= u)
            .saturating_sub(1)
            .min(weights.len() - 2)
    }
}

impl IsotropicDistribution for SpeedTable {
    fn dimension(&self) -> usize {
        self.dimension
    }
    fn mean_speed(&self) -> f64 {
        *self.cumulative_speed.last().unwrap_or(&0.0)
    }
    fn mean_square_speed(&self) -> f64 {
        self.mean_square_speed
    }
    fn speed_density(&self, c: f64) -> f64 {
        let n = self.c.len();
        if c < self.c[0] || c > self.c[n - 1] {
            return 0.0;
        }
        let k = Self::piece(&self.c, c);
        let t = (c - self.c[k]) / (self.c[k + 1] - self.c[k]);
        self.p[k] + t * (self.p[k + 1] - self.p[k])
    }
    #[cfg(test)]
    fn speed_cdf(&self, c: f64) -> f64 {
        let n = self.c.len();
        if c <= self.c[0] {
            return 0.0;
        }
        if c >= self.c[n - 1] {
            return 1.0;
        }
        let k = Self::piece(&self.c, c);
        let p_c = self.speed_density(c);
        self.cumulative[k] + 0.5 * (c - self.c[k]) * (self.p[k] + p_c)
    }
    fn sample_speed(&self, rng: &mut Stream) -> f64 {
        let n = self.c.len();
        let k = Self::piece(
            &self.cumulative,
            rng.random::<f64>() * self.cumulative[n - 1],
        );
        let t = sample_linear_product(1.0, 1.0, self.p[k], self.p[k + 1], rng);
        self.c[k] + t * (self.c[k + 1] - self.c[k])
    }
    /// `c P(c)` on a piece is the product of two linear functions: the exact Bernstein
    /// mixture of `sample_linear_product`.
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        let n = self.c.len();
        let u = rng.random::<f64>() * self.cumulative_speed[n - 1];
        let k = Self::piece(&self.cumulative_speed, u);
        let (a, b) = (self.c[k], self.c[k + 1]);
        let t = sample_linear_product(a, b, self.p[k], self.p[k + 1], rng);
        a + t * (b - a)
    }
    fn mean_relative_speed(&self, speed: f64) -> f64 {
        let scale = (self.mean_square_speed / self.dimension as f64).sqrt();
        isotropic_mean_relative_speed(
            self.dimension,
            speed,
            &|c| self.speed_density(c),
            &self.c,
            scale,
        )
    }
}

// ---------------------------------------------------------------------------------------
// The closed set of baths
// ---------------------------------------------------------------------------------------

/// One of the isotropic baths (static dispatch in the engines); serialisable for
/// checkpoints.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum IsotropicBath {
    /// Gaussian.
    Gaussian(GaussianBath),
    /// Power law G-43.
    PowerLaw(PowerLawBath),
    /// Tabulated speed distribution G-44.
    Tabulated(Box<SpeedTable>),
}

impl IsotropicBathConfig {
    /// The bath in `dimension` 2 or 3 for bath particles of mass `bath_mass`.
    pub(crate) fn build(
        &self,
        dimension: usize,
        bath_mass: f64,
    ) -> Result<IsotropicBath, BallError> {
        let temperature_ok = |t: f64| {
            if t > 0.0 && t.is_finite() {
                Ok(t)
            } else {
                Err(BallError::new(
                    "bath.temperature",
                    format!("is {t}; the bath temperature T_B must be positive and finite"),
                ))
            }
        };
        Ok(match self {
            IsotropicBathConfig::Gaussian { temperature } => {
                let t = temperature_ok(*temperature)?;
                IsotropicBath::Gaussian(GaussianBath::new(dimension, bath_mass / (2.0 * t)))
            }
            IsotropicBathConfig::PowerLaw { temperature } => {
                let t = temperature_ok(*temperature)?;
                IsotropicBath::PowerLaw(PowerLawBath::new(
                    dimension,
                    PowerLawBath::parameter_for_temperature(dimension, t, bath_mass),
                ))
            }
            IsotropicBathConfig::Tabulated { points } => {
                IsotropicBath::Tabulated(Box::new(SpeedTable::new(dimension, points)?))
            }
        })
    }
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            IsotropicBath::Gaussian($b) => $e,
            IsotropicBath::PowerLaw($b) => $e,
            IsotropicBath::Tabulated($b) => $e,
        }
    };
}

impl IsotropicDistribution for IsotropicBath {
    fn dimension(&self) -> usize {
        dispatch!(self, b => b.dimension())
    }
    fn mean_speed(&self) -> f64 {
        dispatch!(self, b => b.mean_speed())
    }
    fn mean_square_speed(&self) -> f64 {
        dispatch!(self, b => b.mean_square_speed())
    }
    fn speed_density(&self, c: f64) -> f64 {
        dispatch!(self, b => b.speed_density(c))
    }
    #[cfg(test)]
    fn speed_cdf(&self, c: f64) -> f64 {
        dispatch!(self, b => b.speed_cdf(c))
    }
    fn sample_speed(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_speed(rng))
    }
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_speed_weighted(rng))
    }
    fn mean_relative_speed(&self, speed: f64) -> f64 {
        dispatch!(self, b => b.mean_relative_speed(speed))
    }
    fn sample_velocity<const D: usize>(&self, rng: &mut Stream) -> Vector<D> {
        dispatch!(self, b => b.sample_velocity::<D>(rng))
    }
    fn sample_mark<const D: usize>(
        &self,
        w: f64,
        mean_speed: f64,
        rng: &mut Stream,
    ) -> (Vector<D>, f64) {
        dispatch!(self, b => b.sample_mark::<D>(w, mean_speed, rng))
    }
}

impl IsotropicBath {
    /// The bath temperature `T_B = m <c^2> / d` for bath particles of mass `bath_mass`.
    pub fn temperature(&self, bath_mass: f64) -> f64 {
        bath_mass * self.mean_square_speed() / self.dimension() as f64
    }

    /// The kind, as the scenario names it: `"gaussian"`, `"power-law"`, `"tabulated"`.
    pub fn kind(&self) -> &'static str {
        match self {
            IsotropicBath::Gaussian(_) => "gaussian",
            IsotropicBath::PowerLaw(_) => "power-law",
            IsotropicBath::Tabulated(_) => "tabulated",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use crate::stats::{Histogram, chi_square_test};
    use std::f64::consts::PI;

    fn baths(dimension: usize) -> Vec<IsotropicBath> {
        let table: Vec<(f64, f64)> =
            vec![(0.0, 0.0), (0.5, 1.0), (1.0, 1.5), (2.0, 0.5), (3.0, 0.0)];
        vec![
            IsotropicBathConfig::Gaussian { temperature: 0.7 }
                .build(dimension, 1.3)
                .unwrap(),
            IsotropicBathConfig::PowerLaw { temperature: 0.7 }
                .build(dimension, 1.3)
                .unwrap(),
            IsotropicBathConfig::Tabulated { points: table }
                .build(dimension, 1.3)
                .unwrap(),
        ]
    }

    /// The moments and the temperature: `m <c^2>/d = T_B` for the Gaussian and the power
    /// law, `<c>` and `<c^2>` against quadrature of `P`, `P` normalised.
    #[test]
    fn moments_match_quadrature_of_the_speed_density() {
        use crate::quadrature::gauss_legendre;
        for d in [2usize, 3] {
            for (i, b) in baths(d).iter().enumerate() {
                if i < 2 {
                    assert!(
                        (b.temperature(1.3) - 0.7).abs() < 1e-12,
                        "d = {d} {}",
                        b.kind()
                    );
                }
                // t = c/(1+c) maps [0, inf) to [0, 1).
                let moment = |k: i32| {
                    gauss_legendre(
                        |t| {
                            let c = t / (1.0 - t);
                            b.speed_density(c) * c.powi(k) / ((1.0 - t) * (1.0 - t))
                        },
                        0.0,
                        1.0,
                        4000,
                    )
                };
                let rel = |x: f64, y: f64| ((x - y) / y).abs();
                assert!(rel(moment(0), 1.0) < 1e-6, "d = {d} {}: norm", b.kind());
                assert!(
                    rel(moment(1), b.mean_speed()) < 1e-6,
                    "d = {d} {}",
                    b.kind()
                );
                if i != 1 {
                    // (the power law's c^2 P ~ c^-2 converges too slowly for this map)
                    assert!(
                        rel(moment(2), b.mean_square_speed()) < 1e-6,
                        "d = {d} {}",
                        b.kind()
                    );
                }
                assert!(rel(b.speed_cdf(b.mean_speed() * 40.0), 1.0) < 1e-3);
            }
        }
    }

    /// The speed samplers, plain and speed-weighted, against their exact CDFs (Pearson's
    /// chi-square; the weighted CDF by quadrature of `c P`).
    #[test]
    fn speed_samplers_are_exact() {
        use crate::quadrature::gauss_legendre;
        for d in [2usize, 3] {
            for (i, b) in baths(d).iter().enumerate() {
                let mut rng = stream(17, &[d as u64, i as u64]);
                let hi = 4.0 * b.mean_speed();
                let mut plain = Histogram::new(0.0, hi, 40);
                let mut weighted = Histogram::new(0.0, hi, 40);
                for _ in 0..100_000 {
                    plain.push(b.sample_speed(&mut rng));
                    weighted.push(b.sample_speed_weighted(&mut rng));
                }
                let c1 = chi_square_test(&plain, |c| b.speed_cdf(c));
                assert!(c1.p_value > 1e-4, "d = {d} {}: {c1:?}", b.kind());
                let mean = b.mean_speed();
                let wcdf = |c: f64| {
                    if c <= 0.0 {
                        0.0
                    } else {
                        gauss_legendre(|x| x * b.speed_density(x), 0.0, c, 64) / mean
                    }
                };
                let c2 = chi_square_test(&weighted, wcdf);
                assert!(c2.p_value > 1e-4, "d = {d} {} weighted: {c2:?}", b.kind());
            }
        }
    }

    /// The Gaussian's specialised vector samplers draw isotropic vectors with the right
    /// speed laws (plain and speed-weighted marks), and `uniform_direction` is isotropic.
    #[test]
    fn vector_samplers_are_isotropic_with_the_right_speeds() {
        fn check<const D: usize>(b: &IsotropicBath) {
            let mut rng = stream(5, &[D as u64]);
            let mean = b.mean_speed();
            let mut speed = Histogram::new(0.0, 4.0 * mean, 40);
            let mut component = Histogram::new(-1.0, 1.0, 40);
            let w = 0.8 * mean;
            for _ in 0..100_000 {
                let (u, c): (Vector<D>, f64) = b.sample_mark::<D>(w, mean, &mut rng);
                assert!((c - u.dot(&u).sqrt()).abs() <= 1e-12 * c);
                speed.push(c);
                component.push(u.0[D - 1] / c);
            }
            // Mark speed law: (w P + c P)/(w + <c>).
            let cdf = |c: f64| {
                let part =
                    crate::quadrature::gauss_legendre(|x| x * b.speed_density(x), 0.0, c, 64);
                (w * b.speed_cdf(c) + part) / (w + mean)
            };
            let t = chi_square_test(&speed, cdf);
            assert!(t.p_value > 1e-4, "D = {D} {}: {t:?}", b.kind());
            // One component of a uniform unit vector: uniform in 3D, arcsine in 2D.
            let dir_cdf = |x: f64| {
                let x = x.clamp(-1.0, 1.0);
                if D == 3 {
                    0.5 * (x + 1.0)
                } else {
                    0.5 + x.asin() / PI
                }
            };
            let t = chi_square_test(&component, dir_cdf);
            assert!(t.p_value > 1e-4, "D = {D} {} direction: {t:?}", b.kind());
        }
        for b in baths(2) {
            check::<2>(&b);
        }
        for b in baths(3) {
            check::<3>(&b);
        }
    }

    /// A table that is not a speed distribution is refused, naming the point.
    #[test]
    fn bad_tables_are_refused() {
        let err = |pts: &[(f64, f64)]| SpeedTable::new(3, pts).unwrap_err().to_string();
        assert!(err(&[(-1.0, 1.0), (1.0, 1.0)]).contains("speed -1"));
        assert!(err(&[(0.0, 1.0), (1.0, -1.0)]).contains("density -1"));
        assert!(err(&[(0.0, 0.0), (1.0, 0.0)]).contains("cannot be normalised"));
        assert!(err(&[(0.0, 1.0)]).contains("at least two"));
        assert!(err(&[(1.0, 1.0), (0.5, 1.0)]).contains("increase"));
    }
}
