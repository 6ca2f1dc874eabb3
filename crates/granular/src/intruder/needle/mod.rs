//! The two-dimensional needle (section 3.2): mass `M`, length `L`, moment of inertia `I`,
//! in a Gaussian bath (G-14 for the velocity component normal to the needle) of point
//! particles of mass `m` and areal density `rho`.
//!
//! State: centre-of-mass velocity `v1 = (v1x, v1y)`, angular velocity `omega`, orientation
//! `theta`; the unit normal is `n = (-sin theta, cos theta)` so that
//! `v_n = v1 . n = v1y cos(theta) - v1x sin(theta)` (G-20), and the material point at
//! distance `x` from the centre moves with normal velocity `v_n + omega x`.
//!
//! Two exact event samplers ([`NeedleMethod`]):
//!
//! * `paper`: collision time from `int_0^t Phi = -ln(xi3)` (G-23) by Newton-Raphson
//!   (G-24) safeguarded by bisection, `Phi` from the closed form of G-21 for any `a`,
//!   `L` (see [`total_flux`]), its time integral by composite Gauss-Legendre quadrature;
//!   impact point by acceptance-rejection on G-25, side by G-26, bath velocity from
//!   `g_+-` (exact sampler of [`super::bath`]).
//! * `thinning` (default, faster): candidates at the constant rate
//!   `Lambda = rho L (|v1| + |omega| L/4 + <|v|>)`, the integral over the impact point `x`
//!   and the bath velocity `v` of the intensity `rho (|v1| + |omega x| + |v|) f(v)`, which
//!   is constant between collisions and bounds `rho |v - v_n(t) - omega x| f(v)` at every
//!   time (`|v_n| <= |v1|`). Each candidate gets `(x, v)` from that intensity (a
//!   three-component mixture, see `Needle::drive`) and is accepted with probability
//!   `|v - v_n(t) - omega x| / (|v1| + |omega x| + |v|)`. The accepted events have intensity
//!   `rho |v - v_n - omega x| f(v) dx dv` at time `t`, which is exactly the collision
//!   intensity whose integrals over `v` and `x` are G-21, G-25 and G-26, so the process is the
//!   same Markov process as the paper's, without Newton iterations or error functions.
//!
//! Collision (G-27 to G-29): `Delta p = -(1 + alpha) g.n / (1/m + 1/M + x^2/I)`,
//! `g.n = v_n + omega x - v` (relative normal velocity at the impact point),
//! `v1' = v1 + n Delta p / M`, `omega' = omega + x Delta p / I`.

mod params;

pub use params::{NeedleConfig, NeedleMethod, NeedleParams, total_flux};

use std::f64::consts::TAU;

use rand::Rng;
use serde::{Deserialize, Serialize};

use super::bath::{BathDistribution, BathError, Side, gaussian_h};
use super::observables::{Estimate, GridSeries, grid_points_before, hist_push_n};
use crate::engine::{Engine, EngineError, Progress};
use crate::observation::Observation;
use crate::random::{DYNAMICS, RngExt, Stream, exp1, std_normal, stream, unit_f64};
use crate::stats::Histogram;

/// `theta.rem_euclid(2 pi)`, value for value, without the division when `theta` is within
/// one turn of `[0, 2 pi)` (the usual case: it was reduced at the previous event). For
/// `theta` in `[2 pi, 4 pi)` the remainder is `theta - 2 pi`, exact by Sterbenz's lemma, and
/// for `theta` in `(-2 pi, 0)` it is `theta + 2 pi` rounded once, as `rem_euclid` computes.
#[inline]
fn wrap_angle(theta: f64) -> f64 {
    if (0.0..TAU).contains(&theta) {
        theta
    } else if (TAU..2.0 * TAU).contains(&theta) {
        theta - TAU
    } else if theta < 0.0 && theta > -TAU {
        theta + TAU
    } else {
        theta.rem_euclid(TAU)
    }
}

/// The needle as an [`Engine`] (serialisable, for checkpoints).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Needle {
    /// Parameters.
    pub params: NeedleParams,
    v: [f64; 2],
    omega: f64,
    theta: f64,
    /// Time at which `theta` was last updated.
    theta_time: f64,
    time: f64,
    next_event: f64,
    events: u64,
    collisions: u64,
    newton_iterations: u64,
    /// Cached `U = |v1| + |omega| L/4` and `1/(rho L (U + <|v|>))` (thinning), updated at
    /// every collision.
    bound: f64,
    inv_rate: f64,
    rng: Stream,
    dt: f64,
    transient: f64,
    /// The next grid point not yet sampled.
    next_sample: f64,
    /// Grid samples of `v^2, omega^2, v^2 omega^2, vx, vy, omega`.
    series: GridSeries<6>,
    component_hist: Histogram,
    omega_hist: Histogram,
}

/// Stationary averages of a needle run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NeedleSummary {
    /// Simulated time.
    pub time: f64,
    /// Collisions.
    pub collisions: u64,
    /// Grid samples.
    pub samples: u64,
    /// `T_tr = M <|v1|^2> / 2`.
    pub translational_temperature: Estimate,
    /// `T_rot = I <omega^2>`.
    pub rotational_temperature: Estimate,
    /// `T_tr / T_B`.
    pub translational_ratio: Estimate,
    /// `T_rot / T_B`.
    pub rotational_ratio: Estimate,
    /// `R = <v^2 omega^2> / (<v^2> <omega^2>)` (G-30).
    pub correlation: Estimate,
    /// Histogram of the velocity components `v1x` and `v1y` (both pushed).
    pub component_histogram: Histogram,
    /// Histogram of `omega`.
    pub omega_histogram: Histogram,
    /// Standard deviation of the best-fit (maximum-likelihood, zero-mean) Gaussian of one
    /// velocity component: `sqrt(<|v1|^2>/2)`.
    pub component_sigma: f64,
    /// Standard deviation of the best-fit Gaussian of `omega`: `sqrt(<omega^2>)`.
    pub omega_sigma: f64,
    /// Mean Newton-Raphson iterations per collision (paper method).
    pub newton_iterations_per_collision: f64,
}

impl Needle {
    /// A new needle; its random stream is `stream(seed, [DYNAMICS])`.
    pub fn new(cfg: &NeedleConfig, seed: u64) -> Result<Self, BathError> {
        let params = NeedleParams::new(cfg)?;
        let mean_speed = params.mean_speed();
        let collision_time = 1.0 / (params.rho * params.length * mean_speed);
        let dt = cfg.sample_interval.unwrap_or(collision_time);
        let slow = (params.mass / params.bath_mass)
            .max(12.0 * params.inertia / (params.bath_mass * params.length * params.length));
        let transient = cfg
            .transient
            .unwrap_or(100.0 * (1.0 + slow) * collision_time / (1.0 + params.restitution));
        let sv = (params.bath_temperature / params.mass).sqrt() * cfg.histogram_width;
        let sw = (params.bath_temperature / params.inertia).sqrt() * cfg.histogram_width;
        let mut n = Self {
            v: cfg.initial_velocity,
            omega: cfg.initial_angular_velocity,
            theta: cfg.initial_angle.rem_euclid(TAU),
            theta_time: 0.0,
            time: 0.0,
            next_event: 0.0,
            events: 0,
            collisions: 0,
            newton_iterations: 0,
            bound: 0.0,
            inv_rate: 0.0,
            rng: stream(seed, &[DYNAMICS]),
            dt,
            transient,
            next_sample: transient,
            series: GridSeries::new(64),
            component_hist: Histogram::new(-sv, sv, cfg.histogram_bins),
            omega_hist: Histogram::new(-sw, sw, cfg.histogram_bins),
            params,
        };
        n.refresh_bound();
        n.next_event = n.draw_next_event(0.0);
        Ok(n)
    }

    /// Centre-of-mass velocity.
    pub(crate) fn velocity(&self) -> [f64; 2] {
        self.v
    }
    /// Start of the averaging window.
    pub(crate) fn transient(&self) -> f64 {
        self.transient
    }
    /// Averaging grid spacing.
    pub(crate) fn sample_interval(&self) -> f64 {
        self.dt
    }
    /// Orientation at the current time, in `[0, 2 pi)`.
    pub(crate) fn angle(&self) -> f64 {
        (self.theta + self.omega * (self.time - self.theta_time)).rem_euclid(TAU)
    }

    fn refresh_bound(&mut self) {
        let p = &self.params;
        self.bound = self.bound_speed();
        self.inv_rate = 1.0 / (p.rho * p.length * (self.bound + p.bath.mean_speed()));
    }

    /// `|v1| + |omega| L/4`: the mean over the needle of the bound `|v1| + |omega x|` of the
    /// normal velocity of its points (see [`Self::drive`]).
    fn bound_speed(&self) -> f64 {
        (self.v[0] * self.v[0] + self.v[1] * self.v[1]).sqrt()
            + 0.25 * self.omega.abs() * self.params.length
    }

    /// Time of the next candidate (thinning) or collision (paper), from time `t`.
    fn draw_next_event(&mut self, t: f64) -> f64 {
        let e = exp1(&mut self.rng);
        match self.params.method {
            NeedleMethod::Thinning => t + e * self.inv_rate,
            NeedleMethod::Paper => {
                let theta_t = self.theta + self.omega * (t - self.theta_time);
                let (tau, it) = self.params.collision_time(self.v, self.omega, theta_t, e);
                self.newton_iterations += u64::from(it);
                t + tau
            }
        }
    }

    /// Adds the grid points not yet sampled before `upto` (or at it when `inclusive`), all
    /// with the current state (constant since the last collision).
    #[inline]
    fn sample_grid(&mut self, upto: f64, inclusive: bool) {
        let (n, t) = grid_points_before(self.next_sample, self.dt, upto, inclusive);
        if n > 0 {
            let [vx, vy] = self.v;
            let w = self.omega;
            let v2 = vx * vx + vy * vy;
            let w2 = w * w;
            self.series.push_n([v2, w2, v2 * w2, vx, vy, w], n);
            let h = &mut self.component_hist;
            let inv = h.counts.len() as f64 / (h.max - h.min);
            hist_push_n(h, inv, vx, n);
            hist_push_n(h, inv, vy, n);
            let h = &mut self.omega_hist;
            let inv = h.counts.len() as f64 / (h.max - h.min);
            hist_push_n(h, inv, w, n);
            self.next_sample = t;
        }
    }

    /// The event loop: stops before the first event after `until`, after `max_events`
    /// events or when the collision count reaches `max_collisions`. The generator and the
    /// state are local variables during the loop (kept in registers); the time grid is
    /// filled only at collisions and at the end, the state being constant in between.
    ///
    /// Thinning uses the candidate intensity `rho (|v1| + |omega x| + |v|) f(v)` in the
    /// impact point `x` and the bath velocity `v`: it bounds the collision intensity
    /// `rho |v - v_n(t) - omega x| f(v)` at every time because `|v_n(t)| <= |v1|` whatever the
    /// orientation, it is constant between collisions, and its total
    /// `Lambda = rho L (|v1| + |omega| L/4 + <|v|>)` is the smallest of the bounds that do not
    /// depend on the orientation. It is the sum of three intensities, sampled as a mixture:
    /// `rho |v1| f(v)` (mass `rho L |v1|`: `x` uniform, `v` from `f`), `rho |omega x| f(v)`
    /// (mass `rho |omega| L^2/4`: `|x| = (L/2) sqrt(U)`, random sign, `v` from `f`) and
    /// `rho |v| f(v)` (mass `rho L <|v|>`: `x` uniform, `v` from `|v| f/<|v|>`); a candidate
    /// is accepted with probability `|v - v_n(t) - omega x| / (|v1| + |omega x| + |v|)`, so the
    /// accepted events have exactly the collision intensity (G-21, G-25 and G-26).
    fn drive(
        &mut self,
        until: f64,
        max_events: u64,
        max_collisions: u64,
    ) -> Result<Progress, EngineError> {
        match self.params.method {
            NeedleMethod::Thinning => self.drive_with::<true>(until, max_events, max_collisions),
            NeedleMethod::Paper => self.drive_with::<false>(until, max_events, max_collisions),
        }
    }

    /// [`Self::drive`] for one sampler (a separate loop for each, so that the thinning loop
    /// keeps its generator in registers).
    fn drive_with<const THINNING: bool>(
        &mut self,
        until: f64,
        max_events: u64,
        max_collisions: u64,
    ) -> Result<Progress, EngineError> {
        let p = self.params.clone();
        let mut rng = self.rng.clone();
        let mut v = self.v;
        let mut omega = self.omega;
        let mut theta = self.theta;
        let mut theta_time = self.theta_time;
        let mut next_event = self.next_event;
        let mut time = self.time;
        let mut collisions = self.collisions;
        let mut newton = self.newton_iterations;
        let mut budget = max_events;
        let half = 0.5 * p.length;
        let mean_speed = p.bath.mean_speed();
        let rate_factor = p.rho * p.length;
        let inv_mass = 1.0 / p.mass;
        let inv_inertia = 1.0 / p.inertia;
        let reduced = 1.0 / p.bath_mass + 1.0 / p.mass;
        let kick = -(1.0 + p.restitution);
        let gauss_scale = std::f64::consts::FRAC_1_SQRT_2 / p.bath.sqrt_a();
        let speed_scale = 1.0 / p.bath.sqrt_a();
        // Thinning bound: |v1| and |omega| L/4, and 1/Lambda.
        let bounds = |v: [f64; 2], omega: f64| {
            let b0 = (v[0] * v[0] + v[1] * v[1]).sqrt();
            let bw = 0.5 * half * omega.abs();
            (b0, bw, 1.0 / (rate_factor * (b0 + bw + mean_speed)))
        };
        let (mut b0, mut bw, mut inv_rate) = bounds(v, omega);
        let outcome = loop {
            if next_event > until {
                break Ok(Progress::Reached);
            }
            if budget == 0 || collisions >= max_collisions {
                break Ok(Progress::BudgetExhausted);
            }
            budget -= 1;
            let te = next_event;
            time = te;
            let hit = if THINNING {
                let bits = rng.next_u64();
                let c = unit_f64(bits) * (b0 + bw + mean_speed);
                let (x, vb) = if c < b0 + bw {
                    let x = if c < b0 {
                        half * (2.0 * rng.random::<f64>() - 1.0)
                    } else {
                        // |x| with density 2|x|/(L/2)^2; the sign from the free low bit.
                        let r = half * rng.random::<f64>().sqrt();
                        f64::from_bits(r.to_bits() | (bits << 63))
                    };
                    (x, std_normal(&mut rng) * gauss_scale)
                } else {
                    let x = half * (2.0 * rng.random::<f64>() - 1.0);
                    let r = exp1(&mut rng).sqrt() * speed_scale;
                    (x, f64::from_bits(r.to_bits() | (bits << 63)))
                };
                let acc = rng.random::<f64>() * (b0 + omega.abs() * x.abs() + vb.abs());
                theta = wrap_angle(theta + omega * (te - theta_time));
                theta_time = te;
                let (sn, cs) = theta.sin_cos();
                let vn = v[1] * cs - v[0] * sn; // G-20
                if acc < (vb - vn - omega * x).abs() {
                    Some((x, vb, sn, cs, vn))
                } else {
                    None
                }
            } else {
                theta = wrap_angle(theta + omega * (te - theta_time));
                theta_time = te;
                let (sn, cs) = theta.sin_cos();
                let vn = v[1] * cs - v[0] * sn; // G-20
                // G-25: phi(vn + omega x) is convex in x, so its maximum is at an end.
                let fmax = p
                    .local_flux(vn - omega * half)
                    .max(p.local_flux(vn + omega * half));
                let x = loop {
                    let x = half * (2.0 * rng.random::<f64>() - 1.0);
                    if rng.random::<f64>() * fmax <= p.local_flux(vn + omega * x) {
                        break x;
                    }
                };
                let u = vn + omega * x;
                // G-26 (fluxes per unit density; rho cancels).
                let s = p.bath.sqrt_a();
                let plus = gaussian_h(s * u);
                let minus = gaussian_h(-s * u);
                let side = if rng.random::<f64>() * (plus + minus) < plus {
                    Side::Right
                } else {
                    Side::Left
                };
                let vb = p.bath.sample_colliding(side, u, &mut rng);
                Some((x, vb, sn, cs, vn))
            };
            if let Some((x, vb, sn, cs, vn)) = hit {
                // G-27 to G-29.
                let gn = vn + omega * x - vb;
                let dp = kick * gn / (reduced + x * x * inv_inertia);
                let dv = dp * inv_mass;
                let new_v = [v[0] - sn * dv, v[1] + cs * dv];
                let new_omega = omega + x * dp * inv_inertia;
                if !(new_v[0].is_finite() && new_v[1].is_finite() && new_omega.is_finite()) {
                    break Err(EngineError::Numerical(format!(
                        "needle state not finite at t = {te}"
                    )));
                }
                // Grid points before te see the state before the collision.
                self.v = v;
                self.omega = omega;
                self.sample_grid(te, false);
                v = new_v;
                omega = new_omega;
                collisions += 1;
                (b0, bw, inv_rate) = bounds(v, omega);
            }
            let e = exp1(&mut rng);
            next_event = if THINNING {
                te + e * inv_rate
            } else {
                let (tau, it) = p.collision_time(v, omega, theta, e);
                newton += u64::from(it);
                te + tau
            };
        };
        self.events += max_events - budget;
        self.rng = rng;
        self.v = v;
        self.omega = omega;
        self.theta = theta;
        self.theta_time = theta_time;
        self.next_event = next_event;
        self.time = time;
        self.collisions = collisions;
        self.newton_iterations = newton;
        self.refresh_bound();
        self.sample_grid(time, false);
        if let Ok(Progress::Reached) = outcome {
            self.sample_grid(until, true);
            self.time = until;
        }
        outcome
    }

    /// Runs until `collisions` more collisions have happened, averaging on the grid.
    pub fn run_collisions(&mut self, collisions: u64) -> Result<(), EngineError> {
        let target = self.collisions + collisions;
        self.drive(f64::INFINITY, u64::MAX, target).map(|_| ())
    }

    /// Stationary averages so far.
    pub fn summary(&self) -> NeedleSummary {
        let p = &self.params;
        let tt = self.series.estimate(0).scaled(0.5 * p.mass);
        let tr = self.series.estimate(1).scaled(p.inertia);
        let v2 = self.series.estimate(0).mean;
        let w2 = self.series.estimate(1).mean;
        NeedleSummary {
            time: self.time,
            collisions: self.collisions,
            samples: self.series.samples(),
            translational_ratio: tt.scaled(1.0 / p.bath_temperature),
            rotational_ratio: tr.scaled(1.0 / p.bath_temperature),
            translational_temperature: tt,
            rotational_temperature: tr,
            correlation: self.series.estimate_fn(|q| q[2] / (q[0] * q[1])),
            component_histogram: self.component_hist.clone(),
            omega_histogram: self.omega_hist.clone(),
            component_sigma: (0.5 * v2).sqrt(),
            omega_sigma: w2.sqrt(),
            newton_iterations_per_collision: self.newton_iterations as f64
                / self.collisions.max(1) as f64,
        }
    }
}

impl Engine for Needle {
    fn name(&self) -> &'static str {
        "intruder"
    }
    fn time(&self) -> f64 {
        self.time
    }
    fn events(&self) -> u64 {
        self.events
    }
    fn collisions(&self) -> u64 {
        self.collisions
    }
    fn particle_count(&self) -> usize {
        1
    }
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        self.drive(until, max_events, u64::MAX)
    }
    fn observe(&self) -> Observation {
        let s = self.summary();
        let quantities = vec![
            ("velocity_x".into(), self.v[0]),
            ("velocity_y".into(), self.v[1]),
            ("angular_velocity".into(), self.omega),
            ("angle".into(), self.angle()),
            ("kinetic_energy".into(), self.kinetic_energy()),
            ("collisions".into(), self.collisions as f64),
            ("samples".into(), s.samples as f64),
            (
                "translational_temperature".into(),
                s.translational_temperature.mean,
            ),
            (
                "translational_temperature_error".into(),
                s.translational_temperature.error,
            ),
            (
                "rotational_temperature".into(),
                s.rotational_temperature.mean,
            ),
            (
                "rotational_temperature_error".into(),
                s.rotational_temperature.error,
            ),
            ("correlation_r".into(), s.correlation.mean),
            ("correlation_r_error".into(), s.correlation.error),
        ];
        Observation::intruder(
            2,
            self.time(),
            self.events(),
            self.collisions(),
            self.kinetic_energy(),
            quantities,
        )
    }
    fn kinetic_energy(&self) -> f64 {
        let p = &self.params;
        0.5 * p.mass * (self.v[0] * self.v[0] + self.v[1] * self.v[1])
            + 0.5 * p.inertia * self.omega * self.omega
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// G-22 (a = L = 1) reproduced by the general closed form.
    #[test]
    fn general_flux_reduces_to_eq_22() {
        let erf = libm::erf;
        for &(vn, w) in &[(0.3f64, 0.7f64), (-1.2, 2.5), (2.0, -0.4)] {
            let e22 = (vn * vn / (2.0 * w) + w / 8.0 + vn / 2.0 + 1.0 / (4.0 * w))
                * erf(vn + w / 2.0)
                + (vn * vn / (2.0 * w) + w / 8.0 - vn / 2.0 + 1.0 / (4.0 * w)) * erf(-vn + w / 2.0)
                + (-vn * vn - w * w / 4.0).exp() / (4.0 * PI.sqrt())
                    * ((vn * w).exp() * (1.0 - 2.0 * vn / w)
                        + (-vn * w).exp() * (1.0 + 2.0 * vn / w));
            let ours = total_flux(1.0, 1.0, 1.0, vn, w);
            assert!(
                (ours - e22).abs() < 1e-13 * e22,
                "{vn} {w}: {ours} vs {e22}"
            );
        }
    }

    #[test]
    fn config_rejects_bad_values() {
        let bad = NeedleConfig {
            length: -1.0,
            ..Default::default()
        };
        assert!(Needle::new(&bad, 1).is_err());
    }

    #[test]
    fn small_omega_branch_is_continuous() {
        let a: f64 = 1.7;
        let l = 0.8;
        let w = 0.05 / (l * a.sqrt());
        let lo = total_flux(1.3, a, l, 0.4, w * (1.0 - 1e-9));
        let hi = total_flux(1.3, a, l, 0.4, w * (1.0 + 1e-9));
        assert!((lo - hi).abs() < 1e-11 * lo, "{lo} {hi}");
    }
}
