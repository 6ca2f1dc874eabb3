//! The DSMC twin of the disk and sphere intruders: section 4 of the paper in `d`
//! dimensions (G-45).
//!
//! `n_bath` bath velocities are drawn from `f`. Trials happen at rate `omega_max`
//! (exponential spacing). A trial picks an impact normal `n` uniformly on the unit sphere
//! (the `d`-dimensional "side chosen at random") and a bath particle `i` uniformly; with
//! `g_i = u_i - V` and `omega_i = rho S_{d-1} R^{d-1} |g_i.n|` the collision is accepted
//! with probability `Theta(-g_i.n) omega_i / omega_max`, and G-37 updates the intruder.
//! `omega_max` is raised when exceeded. The accepted collisions then have the rate density
//! `(rho/n) sum_i R^{d-1} max(0, -g_i.n) dOmega`, G-31 with `f` replaced by the stored
//! sample. After each accepted collision a uniformly chosen slot (independent of the
//! velocities) is redrawn from `f`, as in 1D, so the sample stays i.i.d. from `f`.

use serde::{Deserialize, Serialize};

use super::bath::{IsotropicDistribution, uniform_direction};
use super::engine::observe_ball;
use super::stats::{BallStatistics, BallSummary};
use super::{BallConfig, BallError, BallParams};
use crate::engine::{Engine, EngineError, Progress};
use crate::observation::Observation;
use crate::random::{DYNAMICS, INITIAL_STATE, RngExt, Stream, exp1, stream};
use crate::theory::intruder::intruder_surface;
use crate::vector::Vector;

/// Configuration of the twin: the intruder's parameters plus the bath sample size.
#[derive(Clone, Debug, PartialEq)]
pub struct BallDsmcTwinConfig {
    /// The physical system (`method` is not used).
    pub ball: BallConfig,
    /// Number of stored bath velocities `n_bath`.
    pub bath_particles: usize,
}

impl Default for BallDsmcTwinConfig {
    fn default() -> Self {
        Self {
            ball: BallConfig::default(),
            bath_particles: 10_000,
        }
    }
}

/// The DSMC twin of a disk (`D = 2`) or sphere (`D = 3`) intruder; an [`Engine`] with the
/// scalars of [`super::Ball`] plus `bound_raises` and `trials_per_collision`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BallDsmcTwin<const D: usize> {
    params: BallParams,
    bath_v: Vec<Vector<D>>,
    /// `rho S_{d-1} R^{d-1}`.
    surface_rate: f64,
    omega_max: f64,
    velocity: Vector<D>,
    time: f64,
    next_trial: f64,
    trials: u64,
    collisions: u64,
    bound_raises: u64,
    rng: Stream,
    stats: BallStatistics,
}

impl<const D: usize> BallDsmcTwin<D> {
    /// A new twin; the bath sample comes from `stream(seed, [INITIAL_STATE])`, the dynamics
    /// from `stream(seed, [DYNAMICS])`.
    pub fn new(cfg: &BallDsmcTwinConfig, seed: u64) -> Result<Self, BallError> {
        if cfg.bath_particles == 0 {
            return Err(BallError::new(
                "bath_particles",
                "is 0; store at least one bath velocity (e.g. 10000)",
            ));
        }
        let params = BallParams::new(&cfg.ball, D)?;
        let mut init = stream(seed, &[INITIAL_STATE]);
        let bath_v: Vec<Vector<D>> = (0..cfg.bath_particles)
            .map(|_| params.bath.sample_velocity::<D>(&mut init))
            .collect();
        let mut velocity = Vector::<D>::zero();
        for (k, x) in cfg.ball.initial_velocity.iter().enumerate() {
            velocity.0[k] = *x;
        }
        let surface_rate = params.bath_density * intruder_surface(D, params.radius);
        let vmax = bath_v.iter().fold(0.0f64, |m, u| m.max(u.dot(u).sqrt()));
        let omega_max = surface_rate * (vmax + velocity.dot(&velocity).sqrt());
        let dt = cfg
            .ball
            .sample_interval
            .unwrap_or_else(|| params.rest_collision_time());
        let transient = cfg
            .ball
            .transient
            .unwrap_or_else(|| 50.0 * params.relaxation_time());
        let h = cfg
            .ball
            .histogram_max
            .unwrap_or_else(|| 6.0 * (params.bath_temperature / params.mass).sqrt());
        let stats = BallStatistics::new(D, dt, transient, h, cfg.ball.histogram_bins);
        let mut rng = stream(seed, &[DYNAMICS]);
        let next_trial = exp1(&mut rng) / omega_max;
        Ok(Self {
            params,
            bath_v,
            surface_rate,
            omega_max,
            velocity,
            time: 0.0,
            next_trial,
            trials: 0,
            collisions: 0,
            bound_raises: 0,
            rng,
            stats,
        })
    }

    /// Processes the pending trial and draws the time of the next one.
    fn trial(&mut self) {
        let t = self.next_trial;
        self.time = t;
        self.trials += 1;
        let n = uniform_direction::<D>(&mut self.rng);
        let i = self.rng.random_range(0..self.bath_v.len());
        let g = self.bath_v[i] - self.velocity;
        let gn = g.dot(&n);
        let omega = self.surface_rate * gn.abs();
        if omega > self.omega_max {
            self.omega_max = omega;
            self.bound_raises += 1;
        }
        if gn < 0.0 && self.rng.random::<f64>() * self.omega_max < omega {
            self.stats
                .sample_until(t, false, &self.velocity.0, self.speed());
            self.stats.count_collision(t);
            self.velocity += n * (self.params.kick * gn); // G-37
            self.collisions += 1;
            let j = self.rng.random_range(0..self.bath_v.len());
            self.bath_v[j] = self.params.bath.sample_velocity::<D>(&mut self.rng);
        }
        self.next_trial = t + exp1(&mut self.rng) / self.omega_max;
    }

    /// Runs until `collisions` more collisions have been accepted, averaging on the grid.
    pub fn run_collisions(&mut self, collisions: u64) {
        let target = self.collisions + collisions;
        while self.collisions < target {
            self.trial();
        }
        self.stats
            .sample_until(self.time, false, &self.velocity.0, self.speed());
    }

    /// `|V|`.
    fn speed(&self) -> f64 {
        self.velocity.dot(&self.velocity).sqrt()
    }

    /// The mechanical parameters.
    pub(crate) fn params(&self) -> &BallParams {
        &self.params
    }

    /// Start of the averaging window.
    pub(crate) fn transient(&self) -> f64 {
        self.stats.transient()
    }

    /// Averaging grid spacing.
    pub(crate) fn sample_interval(&self) -> f64 {
        self.stats.sample_interval()
    }

    /// Upper edge of the velocity histograms.
    pub(crate) fn histogram_max(&self) -> f64 {
        self.stats.histogram_max()
    }

    /// Number of times `omega_max` was raised.
    pub(crate) fn bound_raises(&self) -> u64 {
        self.bound_raises
    }

    /// Trials per accepted collision.
    pub(crate) fn trials_per_collision(&self) -> f64 {
        self.trials as f64 / self.collisions.max(1) as f64
    }

    /// Stationary averages (the observables of the Gillespie engine).
    pub fn summary(&self) -> BallSummary {
        self.stats.summary(&self.params, self.time, self.collisions)
    }
}

impl<const D: usize> Engine for BallDsmcTwin<D> {
    fn name(&self) -> &'static str {
        "intruder"
    }
    fn time(&self) -> f64 {
        self.time
    }
    /// Trials (accepted or not).
    fn events(&self) -> u64 {
        self.trials
    }
    fn collisions(&self) -> u64 {
        self.collisions
    }
    fn particle_count(&self) -> usize {
        1
    }
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        let mut budget = max_events;
        while self.next_trial <= until {
            if budget == 0 {
                return Ok(Progress::BudgetExhausted);
            }
            budget -= 1;
            self.trial();
            if !self.velocity.0.iter().all(|x| x.is_finite()) {
                return Err(EngineError::Numerical(format!(
                    "intruder velocity became {:?} at t = {}",
                    self.velocity.0, self.time
                )));
            }
        }
        self.stats
            .sample_until(until, true, &self.velocity.0, self.speed());
        self.time = until;
        Ok(Progress::Reached)
    }
    fn observe(&self) -> Observation {
        let mut quantities = observe_ball(&self.velocity, self.kinetic_energy(), &self.summary());
        quantities.push(("bound_raises".into(), self.bound_raises as f64));
        quantities.push(("trials_per_collision".into(), self.trials_per_collision()));
        Observation::intruder(
            D,
            self.time,
            self.trials,
            self.collisions,
            self.kinetic_energy(),
            quantities,
        )
    }
    fn kinetic_energy(&self) -> f64 {
        0.5 * self.params.mass * self.velocity.dot(&self.velocity)
    }
}
