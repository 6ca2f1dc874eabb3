//! The needle's configuration and the constants derived from it ([`NeedleParams`]), and
//! the total collision flux G-21 ([`total_flux`]) that the paper's sampler integrates.

use crate::intruder::bath::{BathDistribution, BathError, FRAC_1_SQRT_PI, Gaussian};
use crate::quadrature::gauss_legendre;
use serde::{Deserialize, Serialize};

/// Which exact event sampler drives the needle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NeedleMethod {
    /// Thinning against the rate bound `rho L (|v1| + |omega| L/4 + <|v|>)`.
    #[default]
    Thinning,
    /// The paper's algorithm, G-21 to G-26 with Newton-Raphson/bisection on G-23.
    Paper,
}

/// Configuration of the needle (the scenario's `[intruder]` table with `model = "needle"`
/// is read into it by `scenario::NeedleTable`).
#[derive(Clone, Debug, PartialEq)]
pub struct NeedleConfig {
    /// Needle mass `M` (mass units); Figs. 7-8 use `M/m = 0.1, 0.5, 1`.
    pub mass: f64,
    /// Bath particle mass `m` (mass units), 1 in the paper.
    pub bath_mass: f64,
    /// Needle length `L` (length units); the paper's G-22 takes `L = 1`.
    pub length: f64,
    /// Moment of inertia `I` about the centre (mass x length^2), G-28 and G-29. Default
    /// `M L^2 / 12` (thin uniform rod).
    pub moment_of_inertia: Option<f64>,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-29).
    pub restitution: f64,
    /// Bath areal number density `rho` (1/length^2), G-21.
    pub bath_density: f64,
    /// Bath temperature `T_B` (energy, `k_B = 1`): `a = m/(2 T_B)` in G-14. Default 0.5
    /// (`a = 1`, as in G-22).
    pub bath_temperature: f64,
    /// Initial centre-of-mass velocity `(v1x, v1y)` (velocity units).
    pub initial_velocity: [f64; 2],
    /// Initial angular velocity `omega` (1/time).
    pub initial_angular_velocity: f64,
    /// Initial orientation `theta_0` (radians), G-20.
    pub initial_angle: f64,
    /// Event sampler.
    pub method: NeedleMethod,
    /// Tolerance on `|int_0^t Phi + ln xi3|` in G-23, relative to `1 - ln xi3` (paper
    /// method only).
    pub time_tolerance: f64,
    /// Averaging grid spacing (time units). Default: mean collision time of a needle at
    /// rest, `sqrt(pi a)/(rho L)`.
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging (time units). Default:
    /// `100 (1 + max(M/m, 12 I/(m L^2))) / ((1 + alpha) rho L <|v|>)`.
    pub transient: Option<f64>,
    /// Histograms cover `[-h sigma, h sigma]` with `sigma` the equipartition width of each
    /// variable (`sqrt(T_B/M)`, `sqrt(T_B/I)`).
    pub histogram_width: f64,
    /// Number of histogram bins.
    pub histogram_bins: usize,
}

impl Default for NeedleConfig {
    fn default() -> Self {
        Self {
            mass: 1.0,
            bath_mass: 1.0,
            length: 1.0,
            moment_of_inertia: None,
            restitution: 0.5,
            bath_density: 1.0,
            bath_temperature: 0.5,
            initial_velocity: [0.0, 0.0],
            initial_angular_velocity: 0.0,
            initial_angle: 0.0,
            method: NeedleMethod::Thinning,
            time_tolerance: 1e-12,
            sample_interval: None,
            transient: None,
            histogram_width: 6.0,
            histogram_bins: 120,
        }
    }
}

/// Derived constants of a needle run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NeedleParams {
    /// Normal-velocity distribution of the bath.
    pub bath: Gaussian,
    /// `rho`.
    pub rho: f64,
    /// `M`.
    pub mass: f64,
    /// `m`.
    pub bath_mass: f64,
    /// `L`.
    pub length: f64,
    /// `I`.
    pub inertia: f64,
    /// `alpha`.
    pub restitution: f64,
    /// `T_B`.
    pub bath_temperature: f64,
    /// Event sampler.
    pub method: NeedleMethod,
    /// G-23 tolerance.
    pub time_tolerance: f64,
}

impl NeedleParams {
    /// From a configuration (validated).
    pub fn new(c: &NeedleConfig) -> Result<Self, BathError> {
        let pos = |name: &str, x: f64| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(BathError::Parameter(format!(
                    "{name} must be positive, got {x}"
                )))
            }
        };
        pos("mass", c.mass)?;
        pos("bath_mass", c.bath_mass)?;
        pos("length", c.length)?;
        pos("bath_density", c.bath_density)?;
        pos("bath_temperature", c.bath_temperature)?;
        pos("time_tolerance", c.time_tolerance)?;
        pos("histogram_width", c.histogram_width)?;
        let inertia = c
            .moment_of_inertia
            .unwrap_or(c.mass * c.length * c.length / 12.0);
        pos("moment_of_inertia", inertia)?;
        if !(0.0..=1.0).contains(&c.restitution) {
            return Err(BathError::Parameter(format!(
                "restitution must be in [0, 1], got {}",
                c.restitution
            )));
        }
        if c.histogram_bins == 0 {
            return Err(BathError::Parameter("histogram_bins must be >= 1".into()));
        }
        let finite = c.initial_velocity.iter().all(|x| x.is_finite())
            && c.initial_angular_velocity.is_finite()
            && c.initial_angle.is_finite();
        if !finite {
            return Err(BathError::Parameter("initial state must be finite".into()));
        }
        if let Some(dt) = c.sample_interval {
            pos("sample_interval", dt)?;
        }
        if let Some(t) = c.transient
            && !(t >= 0.0 && t.is_finite())
        {
            return Err(BathError::Parameter(format!(
                "transient must be >= 0, got {t}"
            )));
        }
        Ok(Self {
            bath: Gaussian::with_temperature(c.bath_temperature, c.bath_mass)?,
            rho: c.bath_density,
            mass: c.mass,
            bath_mass: c.bath_mass,
            length: c.length,
            inertia,
            restitution: c.restitution,
            bath_temperature: c.bath_temperature,
            method: c.method,
            time_tolerance: c.time_tolerance,
        })
    }

    /// Flux per unit length on both sides of a surface element moving with normal velocity
    /// `u`: `phi(u)` of G-16 (includes `rho`).
    #[inline]
    pub fn local_flux(&self, u: f64) -> f64 {
        self.rho * self.bath.flux(u)
    }

    /// Total flux `Phi` of G-21 for normal velocity `vn` and angular velocity `omega`.
    pub(crate) fn total_flux(&self, vn: f64, omega: f64) -> f64 {
        total_flux(self.rho, self.bath.a, self.length, vn, omega)
    }

    /// `int_0^tau Phi(t) dt` for a needle with velocity `v`, angular velocity `omega`,
    /// orientation `theta0` at `t = 0` (composite 8-point Gauss-Legendre, panels of at most
    /// 0.5 rad of rotation and of at most `0.5/sqrt(a)` change in `v_n`).
    pub(crate) fn integrated_flux(
        &self,
        v: [f64; 2],
        omega: f64,
        theta0: f64,
        t0: f64,
        t1: f64,
    ) -> f64 {
        if t1 <= t0 {
            return 0.0;
        }
        let speed = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let rate = omega.abs() * (1.0 + speed * self.bath.sqrt_a());
        let panels = ((t1 - t0) * rate / 0.5).ceil().clamp(1.0, 1e7) as usize;
        gauss_legendre(
            |t| {
                let (sn, cs) = (theta0 + omega * t).sin_cos();
                self.total_flux(v[1] * cs - v[0] * sn, omega)
            },
            t0,
            t1,
            panels,
        )
    }

    /// Solves G-23, `int_0^tau Phi = target`, by Newton-Raphson (G-24, initial guess
    /// `target/Phi(0)`) with a bisection fallback whenever a step leaves the bracket (which
    /// is how the paper's oscillations are cured). Returns `(tau, iterations)`; converged
    /// when `|int_0^tau Phi - target| <= tol (1 + target)`.
    pub fn collision_time(&self, v: [f64; 2], omega: f64, theta0: f64, target: f64) -> (f64, u32) {
        let phi_at = |t: f64| {
            let (sn, cs) = (theta0 + omega * t).sin_cos();
            self.total_flux(v[1] * cs - v[0] * sn, omega)
        };
        // Phi >= L phi(0) = rho L <|v|>, so tau <= target / (rho L <|v|>).
        let phi_min = self.rho * self.length * self.bath.mean_speed();
        let (mut lo, mut int_lo) = (0.0, 0.0);
        let mut hi = target / phi_min;
        let tol = self.time_tolerance * (1.0 + target);
        let mut t = (target / phi_at(0.0)).min(hi);
        for it in 1..=200u32 {
            let int_t = int_lo + self.integrated_flux(v, omega, theta0, lo, t);
            let r = int_t - target;
            if r.abs() <= tol {
                return (t, it);
            }
            if r < 0.0 {
                lo = t;
                int_lo = int_t;
            } else {
                hi = t;
            }
            let mut next = t - r / phi_at(t); // G-24
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if hi - lo <= 4.0 * f64::EPSILON * hi {
                return (next, it);
            }
            t = next;
        }
        (t, 200)
    }

    /// Thermal speed scale `<|v|>` of the normal bath velocity.
    pub fn mean_speed(&self) -> f64 {
        self.bath.mean_speed()
    }
}

/// `Psi(u) = (u^2/2 + 1/(4a)) erf(sqrt(a) u) + u exp(-a u^2)/(2 sqrt(pi a))`, the
/// antiderivative of `phi(u)/rho` (G-16).
#[inline]
fn flux_antiderivative(a: f64, u: f64) -> f64 {
    let s = a.sqrt();
    (0.5 * u * u + 0.25 / a) * libm::erf(s * u)
        + u * (-a * u * u).exp() * FRAC_1_SQRT_PI / (2.0 * s)
}

/// G-21 in closed form for any `a` and `L` (G-22 is the case `a = L = 1`):
/// `Phi = rho [Psi(v_n + omega L/2) - Psi(v_n - omega L/2)] / omega`, with the
/// antiderivative `Psi` of the flux (derivation in `docs/intruder.md`). When
/// `|omega| L sqrt(a) < 0.05` the difference quotient loses digits and the `x` integral is
/// done by 4-point Gauss-Legendre instead (error below 1e-13 relative there).
pub fn total_flux(rho: f64, a: f64, length: f64, vn: f64, omega: f64) -> f64 {
    let s = a.sqrt();
    let half = 0.5 * length;
    if (omega * length * s).abs() >= 0.05 {
        rho * (flux_antiderivative(a, vn + omega * half)
            - flux_antiderivative(a, vn - omega * half))
            / omega
    } else {
        const GL4: [(f64, f64); 4] = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
        ];
        let mut sum = 0.0;
        for (x, w) in GL4 {
            let u = s * (vn + omega * half * x);
            sum += w * ((-u * u).exp() * FRAC_1_SQRT_PI + u * libm::erf(u));
        }
        rho * half * sum / s
    }
}
