//! Disk (2D) and sphere (3D) intruders: a smooth ball of radius `R` and mass `M` in a bath
//! of point particles of mass `m`, number density `rho` and isotropic velocity distribution
//! `f(u)` (`docs/intruder.md`, "Disk and sphere intruders", equations G-31 to G-45).
//!
//! * `bath`: the isotropic baths (Gaussian, power law G-43, tabulated speeds G-44);
//! * `engine`: the Gillespie engine [`Ball`] (`Ball<2>` a disk, `Ball<3>` a sphere);
//! * [`figures`]: the data of the two figures of `granular reproduce` for disks and spheres;
//! * `twin`: its DSMC twin [`BallDsmcTwin`] (section 4 of the paper in `d` dimensions);
//! * `stats`: the time-grid observables both share.
//!
//! A collision with a bath particle of velocity `u` at the impact normal `n` (outward)
//! changes the intruder velocity by G-37,
//! `V' = V + (1 + alpha) m/(m + M) ((u - V).n) n`; the rate density of collisions is G-31,
//! `rho R^{d-1} f(u) max(0, (V - u).n) d^d u dOmega(n)`.
//!
//! The engines take the plain [`BallConfig`] (no scenario types, no files).

pub(crate) mod bath;
pub(crate) mod engine;
pub mod figures;
pub(crate) mod stats;
pub(crate) mod twin;

use serde::{Deserialize, Serialize};

pub(crate) use bath::IsotropicDistribution;
pub use bath::{GaussianBath, IsotropicBath, IsotropicBathConfig, PowerLawBath, SpeedTable};
pub use engine::Ball;
pub use stats::BallSummary;
pub use twin::{BallDsmcTwin, BallDsmcTwinConfig};

use crate::intruder::bath::{BathDistribution, Gaussian, Side};
use crate::random::{RngExt, Stream};
use crate::theory::intruder::{intruder_cross_section, unit_sphere_area};
use crate::vector::Vector;
use bath::uniform_direction;

/// A parameter of a disk or sphere intruder that is out of range: the configuration key
/// (relative to `[intruder]`) and what is wrong, with the fix.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}` {message}")]
pub struct BallError {
    /// The key, e.g. `radius` or `bath.points`.
    pub key: String,
    /// What is wrong and how to fix it (starts with "is ..." or names the part).
    pub message: String,
}

impl BallError {
    /// An error for `key`.
    pub(crate) fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            message: message.into(),
        }
    }
}

/// Which exact event sampler drives a disk or sphere intruder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BallMethod {
    /// Thinning against the rate bound `rho sigma_d (|V| + <c>)` (G-38), any bath.
    #[default]
    Thinning,
    /// The paper's algorithm in `d` dimensions: waiting time from the closed-form rate
    /// (G-32, G-33), impact normal from G-36, bath normal velocity from G-12. Gaussian bath
    /// only (the closed form and the one-component marginal are needed).
    Direct,
}

/// Configuration of a disk or sphere intruder (plain values; the scenario's `[intruder]`
/// table with `model = "disk"` or `"sphere"` fills it).
#[derive(Clone, Debug, PartialEq)]
pub struct BallConfig {
    /// Intruder radius `R` (length units).
    pub radius: f64,
    /// Intruder mass `M` (mass units).
    pub mass: f64,
    /// Bath particle mass `m` (mass units).
    pub bath_mass: f64,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-37).
    pub restitution: f64,
    /// Bath number density `rho` (1/length^d).
    pub bath_density: f64,
    /// The bath's velocity distribution.
    pub bath: IsotropicBathConfig,
    /// Initial intruder velocity `V(0)`, `d` components (empty: at rest).
    pub initial_velocity: Vec<f64>,
    /// Averaging grid spacing (time units). Default: the mean collision time of an
    /// intruder at rest, `1/(rho sigma_d <c>)`.
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging starts (time units). Default: 50 velocity
    /// relaxation times `d (m + M)/((1 + alpha) m rho sigma_d <c>)`.
    pub transient: Option<f64>,
    /// Event sampler.
    pub method: BallMethod,
    /// Upper edge `h` of the velocity histograms (components on `[-h, h]`, speed on
    /// `[0, h]`; velocity units). Default: 6 thermal speeds `sqrt(T_B/M)`.
    pub histogram_max: Option<f64>,
    /// Number of histogram bins.
    pub histogram_bins: usize,
}

impl Default for BallConfig {
    fn default() -> Self {
        Self {
            radius: 0.5,
            mass: 1.0,
            bath_mass: 1.0,
            restitution: 0.5,
            bath_density: 1.0,
            bath: IsotropicBathConfig::default(),
            initial_velocity: Vec::new(),
            sample_interval: None,
            transient: None,
            method: BallMethod::Thinning,
            histogram_max: None,
            histogram_bins: 120,
        }
    }
}

fn positive(key: &str, x: f64, what: &str) -> Result<(), BallError> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(BallError::new(
            key,
            format!("is {x}; {what} must be positive and finite"),
        ))
    }
}

impl BallConfig {
    /// Checks the parameters for a ball in `dimension` (2 or 3) dimensions.
    pub(crate) fn validate(&self, dimension: usize) -> Result<(), BallError> {
        positive("radius", self.radius, "the intruder radius R")?;
        positive("mass", self.mass, "the intruder mass M")?;
        positive("bath_mass", self.bath_mass, "the bath particle mass m")?;
        positive(
            "bath_density",
            self.bath_density,
            "the bath number density rho",
        )?;
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(BallError::new(
                "restitution",
                format!(
                    "is {}; the coefficient of restitution alpha must lie in [0, 1] (1 = elastic)",
                    self.restitution
                ),
            ));
        }
        if !(self.initial_velocity.is_empty() || self.initial_velocity.len() == dimension) {
            return Err(BallError::new(
                "initial_velocity",
                format!(
                    "has {} components; give {dimension} (one per axis) or leave it out (at rest)",
                    self.initial_velocity.len()
                ),
            ));
        }
        if self.initial_velocity.iter().any(|x| !x.is_finite()) {
            return Err(BallError::new(
                "initial_velocity",
                format!("is {:?}; give finite components", self.initial_velocity),
            ));
        }
        if let Some(dt) = self.sample_interval {
            positive("sample_interval", dt, "the averaging grid spacing")?;
        }
        if let Some(t) = self.transient
            && !(t >= 0.0 && t.is_finite())
        {
            return Err(BallError::new(
                "transient",
                format!("is {t}; give the time discarded before averaging, >= 0"),
            ));
        }
        if let Some(h) = self.histogram_max {
            positive("histogram_max", h, "the histogram half-width")?;
        }
        if self.histogram_bins == 0 {
            return Err(BallError::new(
                "histogram_bins",
                "is 0; use at least 1 bin (default 120)",
            ));
        }
        if self.method == BallMethod::Direct
            && !matches!(self.bath, IsotropicBathConfig::Gaussian { .. })
        {
            return Err(BallError::new(
                "method",
                "is \"direct\", which needs the Gaussian bath (its closed-form rate G-33 and one-component marginal); use method = \"thinning\" for this bath",
            ));
        }
        Ok(())
    }
}

/// Mechanical parameters of a disk or sphere intruder and its bath, resolved once.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BallParams {
    /// `d`, 2 (disk) or 3 (sphere).
    pub dimension: usize,
    /// The bath.
    pub bath: IsotropicBath,
    /// `R`.
    pub radius: f64,
    /// `M`.
    pub mass: f64,
    /// `m`.
    pub bath_mass: f64,
    /// `alpha`.
    pub restitution: f64,
    /// `rho`.
    pub bath_density: f64,
    /// `rho sigma_d` (G-32): the collision rate per unit mean relative speed.
    pub rate_factor: f64,
    /// `(1 + alpha) m/(m + M)`, the factor of G-37.
    pub kick: f64,
    /// `<c>` of the bath.
    pub mean_speed: f64,
    /// `T_B = m <c^2>/d`.
    pub bath_temperature: f64,
    /// Event sampler.
    pub method: BallMethod,
    /// The Gaussian bath's one-component marginal (G-14), for the direct method.
    pub marginal: Option<Gaussian>,
}

impl BallParams {
    /// From a configuration, in `dimension` 2 or 3.
    pub(crate) fn new(cfg: &BallConfig, dimension: usize) -> Result<Self, BallError> {
        cfg.validate(dimension)?;
        let bath = cfg.bath.build(dimension, cfg.bath_mass)?;
        let marginal = match &bath {
            IsotropicBath::Gaussian(g) => Some(g.marginal()?),
            _ => None,
        };
        Ok(Self {
            dimension,
            mean_speed: bath.mean_speed(),
            bath_temperature: bath.temperature(cfg.bath_mass),
            bath,
            radius: cfg.radius,
            mass: cfg.mass,
            bath_mass: cfg.bath_mass,
            restitution: cfg.restitution,
            bath_density: cfg.bath_density,
            rate_factor: cfg.bath_density * intruder_cross_section(dimension, cfg.radius),
            kick: (1.0 + cfg.restitution) * cfg.bath_mass / (cfg.bath_mass + cfg.mass),
            method: cfg.method,
            marginal,
        })
    }

    /// Velocity relaxation time `d / (kick rho sigma_d <c>)` (time units).
    pub(crate) fn relaxation_time(&self) -> f64 {
        self.dimension as f64 / (self.kick * self.rate_factor * self.mean_speed)
    }

    /// Mean collision time of an intruder at rest, `1/(rho sigma_d <c>)`.
    pub(crate) fn rest_collision_time(&self) -> f64 {
        1.0 / (self.rate_factor * self.mean_speed)
    }

    /// The collision rate `phi_d(V) = rho sigma_d <|u - V|>` at intruder speed `speed`
    /// (G-32 with G-33 or G-34; collisions per unit time).
    pub(crate) fn collision_rate(&self, speed: f64) -> f64 {
        self.rate_factor * self.bath.mean_relative_speed(speed)
    }
}

/// `((u - V).n) n` for an impact normal `n` drawn given the relative velocity
/// `g = u - V` (`g_norm = |g| > 0`): the impact parameter uniform on the `(d-1)`-ball of
/// radius `R` perpendicular to `g` (G-35), i.e. `n` with density proportional to
/// `max(0, -g.n)`.
///
/// * 2D: `b` uniform on `[-1, 1]`, `n = -sqrt(1 - b^2) g/|g| + b g_perp/|g|`, so
///   `(g.n) n = (1 - b^2) g - b sqrt(1 - b^2) g_perp`.
/// * 3D: `n = (w - g/|g|)/|w - g/|g||` with `w` uniform on the unit sphere has the law of
///   G-35 (Archimedes: `z = w.g/|g|` is uniform on `[-1, 1]`, and
///   `cos^2 chi = (n.g/|g|)^2 = (1 - z)/2` is uniform, which is a uniform impact parameter),
///   and then `(g.n) n = (g - |g| w)/2`: isotropic scattering of the relative velocity.
#[inline]
pub(crate) fn impact_projection<const D: usize>(
    g: Vector<D>,
    g_norm: f64,
    rng: &mut Stream,
) -> Vector<D> {
    if D == 2 {
        let b = 2.0 * rng.random::<f64>() - 1.0;
        let c2 = 1.0 - b * b;
        let bs = b * c2.sqrt();
        let mut out = Vector::<D>::zero();
        out.0[0] = c2 * g.0[0] + bs * g.0[1];
        out.0[1] = c2 * g.0[1] - bs * g.0[0];
        out
    } else {
        let w = uniform_direction::<D>(rng);
        (g - w * g_norm) * 0.5
    }
}

/// A unit vector `n` with density proportional to `max(0, axis.n)` on the sphere
/// (`axis` a unit vector): `n = sqrt(1 - b^2) axis + b axis_perp` with `b` uniform on
/// `[-1, 1]` in 2D, `(axis + w)/|axis + w|` with `w` uniform on the sphere in 3D (as in
/// [`impact_projection`]).
#[inline]
pub(crate) fn cosine_weighted_direction<const D: usize>(
    axis: Vector<D>,
    rng: &mut Stream,
) -> Vector<D> {
    if D == 2 {
        let b = 2.0 * rng.random::<f64>() - 1.0;
        let c = (1.0 - b * b).sqrt();
        let mut out = Vector::<D>::zero();
        out.0[0] = c * axis.0[0] - b * axis.0[1];
        out.0[1] = c * axis.0[1] + b * axis.0[0];
        out
    } else {
        loop {
            let n = axis + uniform_direction::<D>(rng);
            let n2 = n.dot(&n);
            if n2 > 0.0 {
                return n * (1.0 / n2.sqrt());
            }
        }
    }
}

/// The direct method's collision (G-36 then G-12), for the Gaussian bath with
/// one-component marginal `marginal`: returns `((u - V).n) n`.
///
/// The impact normal has density `R^{d-1} rho phi_+(V.n) / phi_d(V)` (G-36, `phi_+` of
/// G-15 for the marginal), drawn by rejection from the envelope
/// `max(V.n, 0) + phi_+(0) >= phi_+(V.n)` (G-39): a mixture of the cosine law about
/// `V/|V|` (weight `|V| sigma_d(1)`) and the uniform law (weight `S_{d-1} phi_+(0)`),
/// accepted with probability `phi_+(V.n) / (max(V.n, 0) + phi_+(0))`, at least 1/2 on
/// average. The bath particle's normal velocity then follows G-12 at `v1 = V.n` (the
/// exact sampler of the marginal); its tangential components do not enter G-37.
#[inline]
pub(crate) fn direct_collision<const D: usize>(
    marginal: &Gaussian,
    v: Vector<D>,
    speed: f64,
    rng: &mut Stream,
) -> Vector<D> {
    let phi0 = marginal.flux_plus(0.0);
    let w_cos = speed * intruder_cross_section(D, 1.0);
    let w_uni = unit_sphere_area(D) * phi0;
    let axis = if speed > 0.0 {
        v * (1.0 / speed)
    } else {
        Vector::zero()
    };
    let (n, x) = loop {
        let n = if rng.random::<f64>() * (w_cos + w_uni) < w_cos {
            cosine_weighted_direction::<D>(axis, rng)
        } else {
            uniform_direction::<D>(rng)
        };
        let x = v.dot(&n);
        if rng.random::<f64>() * (x.max(0.0) + phi0) <= marginal.flux_plus(x) {
            break (n, x);
        }
    };
    let u_n = marginal.sample_colliding(Side::Right, x, rng);
    n * (u_n - x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use crate::stats::{Histogram, chi_square_test};

    /// G-35: for a fixed `g`, the impact projection has `g.n/|g| = -cos chi` with the law of
    /// a uniform impact parameter: `sin chi = b` uniform (2D), `sin^2 chi` uniform (3D); and
    /// `(g.n) n` is parallel to `n` with `|.| = |g.n|`.
    #[test]
    fn impact_parameter_is_uniform() {
        fn check<const D: usize>() {
            let mut rng = stream(9, &[D as u64]);
            let mut g = Vector::<D>::zero();
            for k in 0..D {
                g.0[k] = 0.3 + k as f64;
            }
            let gn = g.dot(&g).sqrt();
            let mut h = Histogram::new(0.0, 1.0, 50);
            for _ in 0..200_000 {
                let p = impact_projection::<D>(g, gn, &mut rng);
                // p = (g.n) n: |p| = |g.n| = |g| cos chi, and g.p = (g.n)^2 >= 0.
                let cos_chi = p.dot(&p).sqrt() / gn;
                assert!(g.dot(&p) >= -1e-12);
                let b = (1.0 - cos_chi * cos_chi).max(0.0).sqrt();
                h.push(b);
            }
            // Reduced impact parameter b: uniform in 2D, density 2b in 3D.
            let t = chi_square_test(&h, |b| crate::theory::haff::impact_parameter_cdf(D, b));
            assert!(t.p_value > 1e-4, "D = {D}: {t:?}");
        }
        check::<2>();
        check::<3>();
    }

    /// G-36 by rejection: the component `x = V.n/|V|` of the drawn normal against its
    /// exact law `phi_+(|V| x)` times the measure of `x` (arcsine in 2D, uniform in 3D),
    /// whose CDF is computed by quadrature.
    #[test]
    fn direct_impact_normal_follows_g36() {
        use crate::quadrature::gauss_legendre;
        fn check<const D: usize>(speed: f64) {
            let g = Gaussian::new(1.0).unwrap();
            let mut rng = stream(11, &[D as u64, (10.0 * speed) as u64]);
            let mut v = Vector::<D>::zero();
            v.0[0] = speed;
            let mut h = Histogram::new(-1.0, 1.0, 40);
            // The normal is returned times (u_n - x); recover it by sign and norm: draw the
            // direction separately through the same rejection with the u_n step skipped.
            let phi0 = g.flux_plus(0.0);
            let w_cos = speed * intruder_cross_section(D, 1.0);
            let w_uni = unit_sphere_area(D) * phi0;
            let axis = v * (1.0 / speed);
            for _ in 0..100_000 {
                let x = loop {
                    let n = if rng.random::<f64>() * (w_cos + w_uni) < w_cos {
                        cosine_weighted_direction::<D>(axis, &mut rng)
                    } else {
                        uniform_direction::<D>(&mut rng)
                    };
                    let x = v.dot(&n);
                    if rng.random::<f64>() * (x.max(0.0) + phi0) <= g.flux_plus(x) {
                        break x;
                    }
                };
                h.push(x / speed);
            }
            // Density of mu = cos angle: 3D uniform measure, 2D (1 - mu^2)^{-1/2}; in 2D
            // substitute mu = cos(theta) to integrate smoothly.
            let mass = |mu: f64| -> f64 {
                if D == 3 {
                    gauss_legendre(|m| g.flux_plus(speed * m), -1.0, mu, 64)
                } else {
                    let th = mu.clamp(-1.0, 1.0).acos();
                    gauss_legendre(
                        |t| g.flux_plus(speed * t.cos()),
                        th,
                        std::f64::consts::PI,
                        64,
                    )
                }
            };
            let total = mass(1.0);
            let t = chi_square_test(&h, |mu| mass(mu.clamp(-1.0, 1.0)) / total);
            assert!(t.p_value > 1e-4, "D = {D}, |V| = {speed}: {t:?}");
        }
        for s in [0.3, 2.0] {
            check::<2>(s);
            check::<3>(s);
        }
    }

    /// G-36 integrates to G-32: `R^{d-1} int dOmega phi_+(V.n) = sigma_d <|u - V|>` for the
    /// Gaussian (the identity the direct method relies on).
    #[test]
    fn surface_integral_of_side_flux_is_the_rate() {
        use crate::quadrature::gauss_legendre;
        use crate::theory::intruder::gaussian_mean_relative_speed;
        let g = Gaussian::new(1.3).unwrap();
        for speed in [0.0, 0.4, 2.5] {
            let two_d = gauss_legendre(
                |t| g.flux_plus(speed * t.cos()),
                0.0,
                2.0 * std::f64::consts::PI,
                64,
            );
            let three_d = 2.0
                * std::f64::consts::PI
                * gauss_legendre(|mu| g.flux_plus(speed * mu), -1.0, 1.0, 64);
            let rel = |a: f64, b: f64| ((a - b) / b).abs();
            assert!(rel(two_d, 2.0 * gaussian_mean_relative_speed(2, 1.3, speed)) < 1e-12);
            assert!(
                rel(
                    three_d,
                    std::f64::consts::PI * gaussian_mean_relative_speed(3, 1.3, speed)
                ) < 1e-12
            );
        }
    }
}
