//! The Gillespie engine of a disk (`Ball<2>`) or sphere (`Ball<3>`) intruder.
//!
//! Two exact event samplers ([`BallMethod`]):
//!
//! * `thinning` (default, any bath): candidate events at the constant rate
//!   `Lambda = rho sigma_d (|V| + <c>)`, each with a mark `u` of density
//!   `(|V| + |u|) f(u) / (|V| + <c>)`, accepted with probability `|u - V| / (|V| + |u|)`
//!   (G-38; at most 1 by the triangle inequality). Accepted candidates have intensity
//!   `rho sigma_d |u - V| f(u) d^d u`, the total rate G-32 times the colliding velocity
//!   density G-35; the impact normal then follows from a uniform impact parameter (G-35),
//!   so together they sample G-31 exactly. `V` changes only at accepted candidates, so the
//!   bound stays valid between them.
//! * `direct` (the paper's structure, Gaussian bath): waiting time `-ln(xi)/phi_d(V)` with
//!   the closed form G-33 (G-10 in `d` dimensions), impact normal from G-36, the bath
//!   particle's normal velocity from G-12 at `v1 = V.n`.
//!
//! Both end with G-37. Averages on the time grid as in 1D ([`super::stats`]).

use serde::{Deserialize, Serialize};

use super::bath::{GaussianBath, IsotropicBath, IsotropicDistribution};
use super::stats::{BallStatistics, BallSummary};
use super::{BallConfig, BallError, BallMethod, BallParams, direct_collision, impact_projection};
use crate::engine::{Engine, EngineError, Progress};
use crate::intruder::bath::Gaussian;
use crate::observation::Observation;
use crate::random::{DYNAMICS, RngExt, Stream, exp1, stream};
use crate::vector::Vector;

/// A disk (`D = 2`) or sphere (`D = 3`) intruder as an [`Engine`] (serialisable, for
/// checkpoints).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ball<const D: usize> {
    /// Parameters.
    pub params: BallParams,
    velocity: Vector<D>,
    /// `|V|`, kept with the velocity.
    speed: f64,
    time: f64,
    next_event: f64,
    events: u64,
    collisions: u64,
    rng: Stream,
    stats: BallStatistics,
}

impl<const D: usize> Ball<D> {
    /// A new intruder; its random stream is `stream(seed, [DYNAMICS])`.
    pub fn new(cfg: &BallConfig, seed: u64) -> Result<Self, BallError> {
        Self::with_stream(cfg, stream(seed, &[DYNAMICS]))
    }

    /// A new intruder drawing from the given stream.
    pub(crate) fn with_stream(cfg: &BallConfig, mut rng: Stream) -> Result<Self, BallError> {
        let params = BallParams::new(cfg, D)?;
        let mut velocity = Vector::<D>::zero();
        for (k, x) in cfg.initial_velocity.iter().enumerate() {
            velocity.0[k] = *x;
        }
        let speed = velocity.dot(&velocity).sqrt();
        let dt = cfg
            .sample_interval
            .unwrap_or_else(|| params.rest_collision_time());
        let transient = cfg
            .transient
            .unwrap_or_else(|| 50.0 * params.relaxation_time());
        let h = cfg
            .histogram_max
            .unwrap_or_else(|| 6.0 * (params.bath_temperature / params.mass).sqrt());
        let stats = BallStatistics::new(D, dt, transient, h, cfg.histogram_bins);
        let next_event = exp1(&mut rng) * Self::inverse_rate(&params, speed);
        Ok(Self {
            params,
            velocity,
            speed,
            time: 0.0,
            next_event,
            events: 0,
            collisions: 0,
            rng,
            stats,
        })
    }

    /// `1/Lambda` (thinning, G-38) or `1/phi_d(V)` (direct, G-32 with G-33).
    #[inline]
    fn inverse_rate(params: &BallParams, speed: f64) -> f64 {
        match params.method {
            BallMethod::Thinning => 1.0 / (params.rate_factor * (speed + params.mean_speed)),
            BallMethod::Direct => 1.0 / params.collision_rate(speed),
        }
    }

    /// Current intruder velocity.
    pub(crate) fn velocity(&self) -> &[f64] {
        &self.velocity.0
    }

    /// Averaging grid spacing.
    pub(crate) fn sample_interval(&self) -> f64 {
        self.stats.sample_interval()
    }

    /// Start of the averaging window.
    pub(crate) fn transient(&self) -> f64 {
        self.stats.transient()
    }

    /// Upper edge of the velocity histograms.
    pub(crate) fn histogram_max(&self) -> f64 {
        self.stats.histogram_max()
    }

    /// The event loop, monomorphised for the bath and the sampler. Stops before the first
    /// event after `until`, after `max_events` events or at `max_collisions` collisions.
    #[inline]
    fn drive<B: IsotropicDistribution, const THINNING: bool>(
        &mut self,
        bath: &B,
        marginal: Option<&Gaussian>,
        until: f64,
        max_events: u64,
        max_collisions: u64,
    ) -> Result<Progress, EngineError> {
        let mut rng = self.rng.clone();
        let mut v = self.velocity;
        let mut speed = self.speed;
        let mut next_event = self.next_event;
        let mut time = self.time;
        let mut collisions = self.collisions;
        let mut budget = max_events;
        let kick = self.params.kick;
        let mean_speed = self.params.mean_speed;
        let rate_factor = self.params.rate_factor;
        // (`params.bath` is moved out during the loop: use `bath`.)
        let inverse_rate = |speed: f64| {
            if THINNING {
                1.0 / (rate_factor * (speed + mean_speed))
            } else {
                1.0 / (rate_factor * bath.mean_relative_speed(speed))
            }
        };
        let mut inv_rate = inverse_rate(speed);
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
            let change = if THINNING {
                let (u, u_norm): (Vector<D>, f64) =
                    bath.sample_mark::<D>(speed, mean_speed, &mut rng);
                let g = u - v;
                let g2 = g.dot(&g);
                // Accept with |g| / (|V| + |u|), compared squared (both sides >= 0).
                let bound = rng.random::<f64>() * (speed + u_norm);
                if bound * bound < g2 {
                    Some(impact_projection::<D>(g, g2.sqrt(), &mut rng))
                } else {
                    None
                }
            } else {
                marginal.map(|m| direct_collision::<D>(m, v, speed, &mut rng))
            };
            if let Some(p) = change {
                let new_v = v + p * kick; // G-37
                if !new_v.0.iter().all(|x| x.is_finite()) {
                    break Err(EngineError::Numerical(format!(
                        "intruder velocity became {:?} at t = {te}",
                        new_v.0
                    )));
                }
                // Grid points before te see the old velocity.
                self.stats.sample_until(te, false, &v.0, speed);
                self.stats.count_collision(te);
                v = new_v;
                speed = v.dot(&v).sqrt();
                collisions += 1;
                inv_rate = inverse_rate(speed);
            }
            next_event = te + exp1(&mut rng) * inv_rate;
        };
        self.events += max_events - budget;
        self.rng = rng;
        self.velocity = v;
        self.speed = speed;
        self.next_event = next_event;
        self.collisions = collisions;
        self.time = time;
        self.stats.sample_until(time, false, &v.0, speed);
        if let Ok(Progress::Reached) = outcome {
            self.stats.sample_until(until, true, &v.0, speed);
            self.time = until;
        }
        outcome
    }

    /// Runs [`Self::drive`] for the bath and method of the parameters.
    fn drive_dispatch(
        &mut self,
        until: f64,
        max_events: u64,
        max_collisions: u64,
    ) -> Result<Progress, EngineError> {
        // The bath moves out of `params` for the loop (specialised to its type, no clone).
        let placeholder = IsotropicBath::Gaussian(GaussianBath::new(D, 1.0));
        let bath = std::mem::replace(&mut self.params.bath, placeholder);
        let marginal = self.params.marginal;
        let (u, e, c) = (until, max_events, max_collisions);
        let outcome = match (&bath, self.params.method) {
            (IsotropicBath::Gaussian(b), BallMethod::Thinning) => {
                self.drive::<_, true>(b, None, u, e, c)
            }
            (IsotropicBath::Gaussian(b), BallMethod::Direct) => {
                self.drive::<_, false>(b, marginal.as_ref(), u, e, c)
            }
            (IsotropicBath::PowerLaw(b), _) => self.drive::<_, true>(b, None, u, e, c),
            (IsotropicBath::Tabulated(b), _) => self.drive::<_, true>(b.as_ref(), None, u, e, c),
        };
        self.params.bath = bath;
        outcome
    }

    /// Runs until `collisions` more collisions have happened (stops right after the last),
    /// averaging on the grid.
    pub fn run_collisions(&mut self, collisions: u64) -> Result<(), EngineError> {
        let target = self.collisions + collisions;
        self.drive_dispatch(f64::INFINITY, u64::MAX, target)
            .map(|_| ())
    }

    /// The stationary averages so far.
    pub fn summary(&self) -> BallSummary {
        self.stats.summary(&self.params, self.time, self.collisions)
    }
}

/// The observation's velocity components and speed, then the summary's scalars.
pub(super) fn observe_ball<const D: usize>(
    velocity: &Vector<D>,
    kinetic_energy: f64,
    summary: &BallSummary,
) -> Vec<(String, f64)> {
    let names = ["velocity_x", "velocity_y", "velocity_z"];
    let mut q: Vec<(String, f64)> = velocity
        .0
        .iter()
        .zip(names)
        .map(|(x, n)| (n.to_string(), *x))
        .collect();
    q.push(("speed".into(), velocity.dot(velocity).sqrt()));
    q.push(("kinetic_energy".into(), kinetic_energy));
    q.extend(summary.quantities());
    q
}

impl<const D: usize> Engine for Ball<D> {
    fn name(&self) -> &'static str {
        "intruder"
    }
    fn time(&self) -> f64 {
        self.time
    }
    /// Candidate events (thinning) or collisions (direct).
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
        self.drive_dispatch(until, max_events, u64::MAX)
    }
    fn observe(&self) -> Observation {
        let quantities = observe_ball(&self.velocity, self.kinetic_energy(), &self.summary());
        Observation::intruder(
            D,
            self.time,
            self.events,
            self.collisions,
            self.kinetic_energy(),
            quantities,
        )
    }
    fn kinetic_energy(&self) -> f64 {
        0.5 * self.params.mass * self.speed * self.speed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advance_is_independent_of_output_chunking() {
        let cfg = BallConfig {
            transient: Some(0.0),
            ..Default::default()
        };
        let mut a = Ball::<3>::new(&cfg, 5).unwrap();
        let mut b = Ball::<3>::new(&cfg, 5).unwrap();
        a.advance(100.0, u64::MAX).unwrap();
        for k in 1..=100 {
            while b.advance(k as f64, 7).unwrap() == Progress::BudgetExhausted {}
        }
        assert_eq!(a.velocity(), b.velocity());
        assert_eq!(a.collisions(), b.collisions());
        // Same grid samples; their sums may differ in the last bit (n equal samples are
        // added as one product or one by one, depending on where a chunk ends).
        let (sa, sb) = (a.summary(), b.summary());
        assert_eq!(sa.samples, sb.samples);
        assert_eq!(sa.speed_histogram, sb.speed_histogram);
        assert_eq!(sa.collision_rate.mean, sb.collision_rate.mean);
        assert!((sa.temperature.mean - sb.temperature.mean).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_name_their_key() {
        let bad = |cfg: BallConfig| Ball::<2>::new(&cfg, 1).unwrap_err().key;
        assert_eq!(
            bad(BallConfig {
                radius: 0.0,
                ..Default::default()
            }),
            "radius"
        );
        assert_eq!(
            bad(BallConfig {
                initial_velocity: vec![1.0, 2.0, 3.0],
                ..Default::default()
            }),
            "initial_velocity"
        );
        assert_eq!(
            bad(BallConfig {
                method: BallMethod::Direct,
                bath: super::super::IsotropicBathConfig::PowerLaw { temperature: 1.0 },
                ..Default::default()
            }),
            "method"
        );
    }
}
