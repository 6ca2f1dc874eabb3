//! The DSMC version of the 1D intruder (section 4 of the paper).
//!
//! `n_bath` bath velocities are drawn from the bath distribution. Trials happen at rate
//! `omega_max` (exponential waiting times, so the trial sequence is a Poisson process). A
//! trial picks a side `sigma = +1` (left, "-" side of G-6) or `-1` (right, "+" side) with
//! probability 1/2 and a bath particle `i` uniformly; with `v_i1 = v_i - v1` and
//! `omega_i1 = 2 rho |v_i1|`, the collision is accepted with probability
//! `Theta(v_i1 sigma) omega_i1 / omega_max`, and then G-17 updates the intruder. If
//! `omega_i1 > omega_max` the bound is raised, `omega_max <- omega_i1` (as in the paper).
//! The mean rate of accepted collisions is `(rho/n) sum_i |v_i - v1|`, the empirical
//! version of G-7.
//!
//! The bath is thermalised: after every accepted collision one bath slot chosen uniformly
//! *independently of the velocities* is redrawn from `f`, so that the stored velocities
//! remain an i.i.d. sample of `f` (redrawing the collision partner instead would bias the
//! sample towards slow particles). The finite-`n_bath` error vanishes as `n_bath` grows.

use rand_distr::Exp1;
use serde::{Deserialize, Serialize};

use super::bath::BathDistribution;
use super::bath::BathError;
use super::observables::{GridSeries, hist_push};
use super::one_d::{Intruder1dConfig, Intruder1dParams, Intruder1dSummary};
use super::theory;
use crate::engine::{Engine, EngineError, Progress};
use crate::observation::Observation;
use crate::random::{DYNAMICS, INITIAL_STATE, RngExt, Stream, stream};
use crate::stats::Histogram;

/// Configuration of the DSMC twin: the 1D intruder's parameters plus the bath sample size
/// (the scenario's `[intruder]` table with `model = "dsmc-twin"`, read by
/// `scenario::DsmcTwinTable`).
#[derive(Clone, Debug, PartialEq)]
pub struct DsmcTwinConfig {
    /// The physical system (same fields as the Gillespie 1D intruder; `method` is ignored).
    pub intruder: Intruder1dConfig,
    /// Number of stored bath velocities `n_bath` (section 4).
    pub bath_particles: usize,
}

impl Default for DsmcTwinConfig {
    fn default() -> Self {
        Self {
            intruder: Intruder1dConfig::default(),
            bath_particles: 10_000,
        }
    }
}

/// The DSMC twin of the 1D intruder; an [`Engine`] (serialisable, for checkpoints) with
/// the same scalars as [`super::Intruder1d`], so a scenario can switch between the two.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DsmcTwin {
    params: Intruder1dParams,
    bath_v: Vec<f64>,
    omega_max: f64,
    v1: f64,
    time: f64,
    /// Time of the next trial (exponential spacing at rate `omega_max`, drawn after each
    /// trial, so the trajectory does not depend on how `advance` calls are chunked).
    next_trial: f64,
    trials: u64,
    collisions: u64,
    bound_raises: u64,
    rng: Stream,
    dt: f64,
    /// Time discarded before the first sample.
    #[serde(default)]
    transient: f64,
    next_sample: f64,
    series: GridSeries<3>,
    histogram: Histogram,
    inv_bin_width: f64,
}

impl DsmcTwin {
    /// A new twin; the bath sample comes from `stream(seed, [INITIAL_STATE])`, the dynamics
    /// from `stream(seed, [DYNAMICS])`.
    pub fn new(cfg: &DsmcTwinConfig, seed: u64) -> Result<Self, BathError> {
        if cfg.bath_particles == 0 {
            return Err(BathError::Parameter("bath_particles must be >= 1".into()));
        }
        let params = Intruder1dParams::new(&cfg.intruder)?;
        let mut init = stream(seed, &[INITIAL_STATE]);
        let bath_v: Vec<f64> = (0..cfg.bath_particles)
            .map(|_| params.bath.sample(&mut init))
            .collect();
        let v1 = cfg.intruder.initial_velocity;
        let vmax = bath_v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let omega_max = 2.0 * params.rho * (vmax + v1.abs());
        let dt = cfg
            .intruder
            .sample_interval
            .unwrap_or(1.0 / (params.rho * params.mean_speed));
        let transient = cfg
            .intruder
            .transient
            .unwrap_or(50.0 * params.relaxation_time());
        let hmax = cfg
            .intruder
            .histogram_max
            .unwrap_or(6.0 * (params.bath_temperature / params.mass).sqrt());
        let mut rng = stream(seed, &[DYNAMICS]);
        let e: f64 = rng.sample(Exp1);
        Ok(Self {
            params,
            bath_v,
            omega_max,
            v1,
            time: 0.0,
            next_trial: e / omega_max,
            trials: 0,
            collisions: 0,
            bound_raises: 0,
            rng,
            dt,
            transient,
            next_sample: transient,
            series: GridSeries::new(64),
            histogram: Histogram::new(-hmax, hmax, cfg.intruder.histogram_bins),
            inv_bin_width: cfg.intruder.histogram_bins as f64 / (2.0 * hmax),
        })
    }

    /// Time discarded before the first sample (the resolved `transient`).
    pub(crate) fn transient(&self) -> f64 {
        self.transient
    }

    /// Records the grid points before `upto` (and at `upto` when `inclusive`).
    fn sample_grid(&mut self, upto: f64, inclusive: bool) {
        while self.next_sample < upto || (inclusive && self.next_sample == upto) {
            let v = self.v1;
            self.series.push([v, v * v, v * v * v * v]);
            hist_push(&mut self.histogram, self.inv_bin_width, v);
            self.next_sample += self.dt;
        }
    }

    /// Processes the pending trial and draws the time of the next one.
    fn trial(&mut self) {
        let n = self.bath_v.len();
        let rho = self.params.rho;
        let t = self.next_trial;
        self.sample_grid(t, false);
        self.time = t;
        self.trials += 1;
        let sigma = if self.rng.random::<bool>() { 1.0 } else { -1.0 };
        let i = self.rng.random_range(0..n);
        let rel = self.bath_v[i] - self.v1;
        let omega_i = 2.0 * rho * rel.abs();
        if omega_i > self.omega_max {
            self.omega_max = omega_i;
            self.bound_raises += 1;
        }
        if rel * sigma > 0.0 && self.rng.random::<f64>() * self.omega_max < omega_i {
            self.v1 += self.params.kick * rel; // G-17
            self.collisions += 1;
            let j = self.rng.random_range(0..n);
            self.bath_v[j] = self.params.bath.sample(&mut self.rng);
        }
        let e: f64 = self.rng.sample(Exp1);
        self.next_trial = t + e / self.omega_max;
    }

    /// Runs until `collisions` more collisions have been accepted, averaging on the grid.
    pub fn run_collisions(&mut self, collisions: u64) {
        let target = self.collisions + collisions;
        while self.collisions < target {
            self.trial();
        }
    }

    /// Number of times `omega_max` had to be raised.
    pub(crate) fn bound_raises(&self) -> u64 {
        self.bound_raises
    }

    /// Trials per accepted collision.
    pub(crate) fn trials_per_collision(&self) -> f64 {
        self.trials as f64 / self.collisions.max(1) as f64
    }

    /// Stationary averages (same observables as the Gillespie engine).
    pub fn summary(&self) -> Intruder1dSummary {
        let m = self.params.mass;
        let temperature = self.series.estimate(1).scaled(m);
        Intruder1dSummary {
            time: self.time,
            collisions: self.collisions,
            samples: self.series.samples(),
            mean_velocity: self.series.estimate(0),
            temperature_ratio: temperature.scaled(1.0 / self.params.bath_temperature),
            temperature,
            kurtosis: self.series.estimate_fn(|q| q[2] / (q[1] * q[1])),
            martin_piasecki_ratio: theory::martin_piasecki_ratio(
                self.params.restitution,
                m,
                self.params.bath_mass,
            ),
            histogram: self.histogram.clone(),
        }
    }
}

impl Engine for DsmcTwin {
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
            if !self.v1.is_finite() {
                return Err(EngineError::Numerical(format!(
                    "intruder velocity became {} at t = {}",
                    self.v1, self.time
                )));
            }
        }
        self.sample_grid(until, true);
        self.time = until;
        Ok(Progress::Reached)
    }
    /// The scalars of [`super::Intruder1d`] plus `bound_raises` and
    /// `trials_per_collision`.
    fn observe(&self) -> Observation {
        let s = self.summary();
        let quantities = vec![
            ("velocity".into(), self.v1),
            ("kinetic_energy".into(), self.kinetic_energy()),
            ("collisions".into(), self.collisions as f64),
            ("samples".into(), s.samples as f64),
            ("temperature".into(), s.temperature.mean),
            ("temperature_error".into(), s.temperature.error),
            ("temperature_ratio".into(), s.temperature_ratio.mean),
            ("temperature_ratio_error".into(), s.temperature_ratio.error),
            ("kurtosis".into(), s.kurtosis.mean),
            ("kurtosis_error".into(), s.kurtosis.error),
            ("martin_piasecki_ratio".into(), s.martin_piasecki_ratio),
            ("bound_raises".into(), self.bound_raises as f64),
            ("trials_per_collision".into(), self.trials_per_collision()),
        ];
        Observation::intruder(
            1,
            self.time(),
            self.events(),
            self.collisions(),
            self.kinetic_energy(),
            quantities,
        )
    }
    fn kinetic_energy(&self) -> f64 {
        0.5 * self.params.mass * self.v1 * self.v1
    }
}
