//! The one-dimensional intruder (section 3.1): a particle of mass `M` in a bath of point
//! particles of mass `m`, density `rho` and velocity distribution `f` (G-5 to G-17).
//!
//! Two exact event samplers, selected by [`Method1d`]:
//!
//! * `direct`, the paper's algorithm: waiting time `-ln(xi1)/phi(v1)` (G-10), side with
//!   probability `phi_+/phi` (G-11), bath velocity from `g_+-` (G-12 and G-13);
//! * `thinning` (default, faster, no error function): candidate events at the constant
//!   rate `Lambda = rho (|v1| + <|v|>) >= phi(v1)` (because `|v - v1| <= |v1| + |v|`), each
//!   with a mark `v` of density `(|v1| + |v|) f(v) / (|v1| + <|v|>)` (a two-component
//!   mixture of `f` and of `|v| f / <|v|>`), accepted with probability
//!   `|v - v1| / (|v1| + |v|)`. The accepted events form a Poisson process with intensity
//!   `Lambda * mark density * acceptance = rho |v - v1| f(v)` in `v`, which is exactly the
//!   collision kernel of G-8 (total rate G-7; the side is the sign of `v1 - v`, so the
//!   side and the bath velocity are jointly distributed as G-11 to G-13). Rejected candidates
//!   leave the state unchanged and `v1` is constant between accepted events, so the bound
//!   stays valid. Acceptance `phi(v1)/Lambda`: 1 at `v1 = 0`, >= 0.648 for the Gaussian (minimum at sqrt(a)|v1| = 0.66).
//!
//! After a collision with a bath particle of velocity `v`:
//! `v1' = v1 + (1 + alpha) m/(m + M) (v - v1)` (G-17 with the bath mass `m` kept).
//!
//! Averages are taken on a fixed time grid (pseudocode step 2 of the paper): grid points
//! `t_k = transient + k dt`, the intruder velocity being constant between collisions.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::bath::{Bath, BathConfig, BathDistribution, BathError, Gaussian, Side};
use super::observables::{Estimate, GridSeries, grid_points_before, hist_push_n};
use super::theory;
use crate::engine::{Engine, EngineError, Progress};
use crate::observation::Observation;
use crate::random::{DYNAMICS, INITIAL_STATE, MEMBER, RngExt, Stream, exp1, stream};
use crate::stats::{Histogram, RunningStats};

/// Which exact event sampler drives the 1D intruder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method1d {
    /// Thinning against the rate bound `rho (|v1| + <|v|>)` (exact, fastest).
    #[default]
    Thinning,
    /// The paper's algorithm, G-10 to G-13.
    Direct,
}

/// Configuration of the 1D intruder (the scenario's `[intruder]` table with `model = "1d"`
/// is read into it by `scenario::OneDTable`).
#[derive(Clone, Debug, PartialEq)]
pub struct Intruder1dConfig {
    /// Intruder mass `M` (mass units). Paper: `M = 1` (Fig. 3), `M = 1/2` (Fig. 5).
    pub mass: f64,
    /// Bath particle mass `m` (mass units); the paper takes `m = 1` (after G-17).
    pub bath_mass: f64,
    /// Coefficient of restitution `alpha` in `[0, 1]` (G-17).
    pub restitution: f64,
    /// Bath number density `rho` (1/length), G-5 and G-6.
    pub bath_density: f64,
    /// Bath velocity distribution: Gaussian (G-14), power law (G-19) or tabulated.
    /// Default: Gaussian with `a = 1` (`T_B = m/2`).
    pub bath: BathConfig,
    /// Initial intruder velocity `v1(0)` (velocity units).
    pub initial_velocity: f64,
    /// Averaging grid spacing `delta t` (time units, pseudocode step 2). Default: the mean
    /// collision time of an intruder at rest, `1/(rho <|v|>)` ("a convenient choice").
    pub sample_interval: Option<f64>,
    /// Time discarded before averaging starts (time units). Default: 50 velocity
    /// relaxation times `(m + M)/((1 + alpha) m rho <|v|>)`.
    pub transient: Option<f64>,
    /// Event sampler.
    pub method: Method1d,
    /// Histogram range `[-h, h]` of the intruder velocity (velocity units). Default:
    /// 6 thermal speeds `sqrt(T_B/M)` (more for heavy-tailed baths: set it).
    pub histogram_max: Option<f64>,
    /// Number of histogram bins.
    pub histogram_bins: usize,
}

impl Default for Intruder1dConfig {
    fn default() -> Self {
        Self {
            mass: 1.0,
            bath_mass: 1.0,
            restitution: 0.5,
            bath_density: 1.0,
            bath: BathConfig::default(),
            initial_velocity: 0.0,
            sample_interval: None,
            transient: None,
            method: Method1d::Thinning,
            histogram_max: None,
            histogram_bins: 120,
        }
    }
}

impl Intruder1dConfig {
    /// Checks the parameters.
    pub(crate) fn validate(&self) -> Result<(), BathError> {
        let bad = |m: String| Err(BathError::Parameter(m));
        if !(self.mass > 0.0 && self.mass.is_finite()) {
            return bad(format!("mass must be positive, got {}", self.mass));
        }
        if !(self.bath_mass > 0.0 && self.bath_mass.is_finite()) {
            return bad(format!(
                "bath_mass must be positive, got {}",
                self.bath_mass
            ));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad(format!(
                "restitution must be in [0, 1], got {}",
                self.restitution
            ));
        }
        if !(self.bath_density > 0.0 && self.bath_density.is_finite()) {
            return bad(format!(
                "bath_density must be positive, got {}",
                self.bath_density
            ));
        }
        if let Some(dt) = self.sample_interval
            && !(dt > 0.0 && dt.is_finite())
        {
            return bad(format!("sample_interval must be positive, got {dt}"));
        }
        if let Some(t) = self.transient
            && !(t >= 0.0 && t.is_finite())
        {
            return bad(format!("transient must be >= 0, got {t}"));
        }
        if self.histogram_bins == 0 {
            return bad("histogram_bins must be >= 1".into());
        }
        if !self.initial_velocity.is_finite() {
            return bad("initial_velocity must be finite".into());
        }
        Ok(())
    }
}

/// Mechanical parameters shared by all intruders of one run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Intruder1dParams {
    /// The bath.
    pub bath: Bath,
    /// `rho`.
    pub rho: f64,
    /// `M`.
    pub mass: f64,
    /// `m`.
    pub bath_mass: f64,
    /// `alpha`.
    pub restitution: f64,
    /// `(1 + alpha) m / (m + M)`, the factor of G-17.
    pub kick: f64,
    /// `<|v|>` of the bath.
    pub mean_speed: f64,
    /// `T_B = m <v^2>`.
    pub bath_temperature: f64,
    /// Event sampler.
    pub method: Method1d,
}

impl Intruder1dParams {
    /// From a configuration.
    pub(crate) fn new(cfg: &Intruder1dConfig) -> Result<Self, BathError> {
        cfg.validate()?;
        let bath = cfg.bath.build(cfg.bath_mass)?;
        let mean_speed = bath.mean_speed();
        Ok(Self {
            bath_temperature: cfg.bath_mass * bath.second_moment(),
            bath,
            rho: cfg.bath_density,
            mass: cfg.mass,
            bath_mass: cfg.bath_mass,
            restitution: cfg.restitution,
            kick: (1.0 + cfg.restitution) * cfg.bath_mass / (cfg.bath_mass + cfg.mass),
            mean_speed,
            method: cfg.method,
        })
    }

    /// Velocity relaxation time `(m + M)/((1 + alpha) m rho <|v|>)`.
    pub(crate) fn relaxation_time(&self) -> f64 {
        1.0 / (self.kick * self.rho * self.mean_speed)
    }

    /// `1/rate` of candidate events at intruder velocity `v1`: `1/(rho (|v1| + <|v|>))`
    /// (thinning) or `1/phi(v1)` (G-10). Constant between collisions.
    #[inline]
    fn inverse_rate<B: BathDistribution>(&self, bath: &B, v1: f64) -> f64 {
        match self.method {
            Method1d::Thinning => self.inverse_rate_with::<B, true>(bath, v1),
            Method1d::Direct => self.inverse_rate_with::<B, false>(bath, v1),
        }
    }

    /// [`Self::inverse_rate`] for thinning (`THINNING`) or the direct method.
    #[inline]
    fn inverse_rate_with<B: BathDistribution, const THINNING: bool>(
        &self,
        bath: &B,
        v1: f64,
    ) -> f64 {
        if THINNING {
            1.0 / (self.rho * (v1.abs() + self.mean_speed))
        } else {
            1.0 / (self.rho * bath.flux(v1))
        }
    }

    /// Processes the candidate event; returns the new velocity if a collision happened.
    #[inline]
    fn event<B: BathDistribution, const THINNING: bool>(
        &self,
        bath: &B,
        v1: f64,
        rng: &mut Stream,
    ) -> Option<f64> {
        let v = if THINNING {
            let av1 = v1.abs();
            let v = bath.sample_mark(av1, self.mean_speed, rng);
            if rng.random::<f64>() * (av1 + v.abs()) >= (v - v1).abs() {
                return None;
            }
            v
        } else {
            let plus = bath.flux_plus(v1);
            let minus = bath.flux_minus(v1);
            let side = if rng.random::<f64>() * (plus + minus) < plus {
                Side::Right // G-11
            } else {
                Side::Left
            };
            bath.sample_colliding(side, v1, rng) // G-12 and G-13
        };
        Some(v1 + self.kick * (v - v1)) // G-17
    }
}

/// The 1D intruder as an [`Engine`] (serialisable, for checkpoints).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Intruder1d {
    /// Parameters.
    pub params: Intruder1dParams,
    v1: f64,
    time: f64,
    next_event: f64,
    events: u64,
    collisions: u64,
    rng: Stream,
    dt: f64,
    transient: f64,
    /// The next grid point not yet sampled.
    next_sample: f64,
    /// Grid samples of `v1, v1^2, v1^4`.
    series: GridSeries<3>,
    histogram: Histogram,
    inv_bin_width: f64,
}

/// Stationary averages of a 1D intruder run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Intruder1dSummary {
    /// Simulated time.
    pub time: f64,
    /// Collisions.
    pub collisions: u64,
    /// Grid samples used in the averages.
    pub samples: u64,
    /// `<v1>`.
    pub mean_velocity: Estimate,
    /// `T = M <v1^2>`.
    pub temperature: Estimate,
    /// `T / T_B`.
    pub temperature_ratio: Estimate,
    /// `<v1^4>/<v1^2>^2` (3 for a Gaussian).
    pub kurtosis: Estimate,
    /// G-18 (generalised to `m`), for reference (exact for the Gaussian bath).
    pub martin_piasecki_ratio: f64,
    /// Histogram of `v1` on the time grid.
    pub histogram: Histogram,
}

impl Intruder1d {
    /// A new intruder; its random stream is `stream(seed, [DYNAMICS])`.
    pub fn new(cfg: &Intruder1dConfig, seed: u64) -> Result<Self, BathError> {
        let params = Intruder1dParams::new(cfg)?;
        Ok(Self::with_params(
            params,
            cfg,
            stream(seed, &[DYNAMICS]),
            cfg.initial_velocity,
        ))
    }

    /// A new intruder from prepared parameters and a given stream and initial velocity.
    pub(crate) fn with_params(
        params: Intruder1dParams,
        cfg: &Intruder1dConfig,
        mut rng: Stream,
        v1: f64,
    ) -> Self {
        let dt = cfg
            .sample_interval
            .unwrap_or(1.0 / (params.rho * params.mean_speed));
        let transient = cfg.transient.unwrap_or(50.0 * params.relaxation_time());
        let hmax = cfg
            .histogram_max
            .unwrap_or(6.0 * (params.bath_temperature / params.mass).sqrt());
        let next_event = exp1(&mut rng) * params.inverse_rate(&params.bath, v1);
        Self {
            v1,
            time: 0.0,
            next_event,
            events: 0,
            collisions: 0,
            rng,
            dt,
            transient,
            next_sample: transient,
            series: GridSeries::new(64),
            histogram: Histogram::new(-hmax, hmax, cfg.histogram_bins),
            inv_bin_width: cfg.histogram_bins as f64 / (2.0 * hmax),
            params,
        }
    }

    /// Current intruder velocity.
    pub(crate) fn velocity(&self) -> f64 {
        self.v1
    }

    /// Averaging grid spacing.
    pub(crate) fn sample_interval(&self) -> f64 {
        self.dt
    }

    /// Start of the averaging window.
    pub(crate) fn transient(&self) -> f64 {
        self.transient
    }

    /// Upper edge `h` of the velocity histogram `[-h, h]`.
    pub(crate) fn histogram_max(&self) -> f64 {
        self.histogram.max
    }

    /// Adds the grid points not yet sampled that lie before `upto` (or at it when
    /// `inclusive`), all at the current velocity (constant since the last collision).
    #[inline]
    fn sample_grid(&mut self, upto: f64, inclusive: bool) {
        let (n, t) = grid_points_before(self.next_sample, self.dt, upto, inclusive);
        if n > 0 {
            let v = self.v1;
            let v2 = v * v;
            self.series.push_n([v, v2, v2 * v2], n);
            hist_push_n(&mut self.histogram, self.inv_bin_width, v, n);
            self.next_sample = t;
        }
    }

    /// The event loop, monomorphised for the bath type. Stops before the first event
    /// after `until`, after `max_events` events or when the collision count reaches
    /// `max_collisions`; grid sampling only when `sample`. The generator and the state
    /// live in local variables during the loop (so they stay in registers), and the time
    /// grid is filled only at collisions and at the end: the velocity does not change at
    /// rejected candidates.
    #[inline]
    fn drive<B: BathDistribution, const THINNING: bool>(
        &mut self,
        bath: &B,
        until: f64,
        max_events: u64,
        max_collisions: u64,
        sample: bool,
    ) -> Result<Progress, EngineError> {
        let mut rng = self.rng.clone();
        let mut v1 = self.v1;
        let mut next_event = self.next_event;
        let mut time = self.time;
        let mut collisions = self.collisions;
        let mut budget = max_events;
        let mut inv_rate = self.params.inverse_rate_with::<B, THINNING>(bath, v1);
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
            if let Some(v) = self.params.event::<B, THINNING>(bath, v1, &mut rng) {
                if !v.is_finite() {
                    break Err(EngineError::Numerical(format!(
                        "intruder velocity became {v} at t = {te}"
                    )));
                }
                if sample {
                    // Grid points before te see the old velocity.
                    self.v1 = v1;
                    self.sample_grid(te, false);
                }
                v1 = v;
                collisions += 1;
                inv_rate = self.params.inverse_rate_with::<B, THINNING>(bath, v);
            }
            next_event = te + exp1(&mut rng) * inv_rate; // G-10 (or the thinning rate)
        };
        // On an error, the event that failed is counted and its random numbers are used,
        // but the velocity and the next event time are left as they were.
        self.events += max_events - budget;
        self.rng = rng;
        self.v1 = v1;
        self.next_event = next_event;
        self.collisions = collisions;
        self.time = time;
        if sample {
            self.sample_grid(time, false);
        }
        if let Ok(Progress::Reached) = outcome {
            if sample {
                self.sample_grid(until, true);
            }
            self.time = until;
        }
        outcome
    }

    /// Runs [`Self::drive`] with the bath moved out of `params` (so the loop is
    /// specialised to the bath type without cloning it).
    fn drive_dispatch(
        &mut self,
        until: f64,
        max_events: u64,
        max_collisions: u64,
        sample: bool,
    ) -> Result<Progress, EngineError> {
        let placeholder = Bath::Gaussian(match Gaussian::new(1.0) {
            Ok(g) => g,
            Err(e) => return Err(EngineError::Numerical(e.to_string())),
        });
        let bath = std::mem::replace(&mut self.params.bath, placeholder);
        let (u, e, c, s) = (until, max_events, max_collisions, sample);
        let r = match (&bath, self.params.method) {
            (Bath::Gaussian(b), Method1d::Thinning) => self.drive::<_, true>(b, u, e, c, s),
            (Bath::Gaussian(b), Method1d::Direct) => self.drive::<_, false>(b, u, e, c, s),
            (Bath::PowerLaw(b), Method1d::Thinning) => self.drive::<_, true>(b, u, e, c, s),
            (Bath::PowerLaw(b), Method1d::Direct) => self.drive::<_, false>(b, u, e, c, s),
            (Bath::Tabulated(b), Method1d::Thinning) => {
                self.drive::<_, true>(b.as_ref(), u, e, c, s)
            }
            (Bath::Tabulated(b), Method1d::Direct) => {
                self.drive::<_, false>(b.as_ref(), u, e, c, s)
            }
        };
        self.params.bath = bath;
        r
    }

    /// Advances to `until` without any averaging (used by ensembles).
    pub(crate) fn evolve_to(&mut self, until: f64) {
        // Errors only signal a non-finite velocity, impossible for finite parameters; the
        // state is left at the failing event in that case.
        let _ = self.drive_dispatch(until, u64::MAX, u64::MAX, false);
    }

    /// Runs until `collisions` more collisions have happened (then stops right after the
    /// last one), averaging on the grid.
    pub fn run_collisions(&mut self, collisions: u64) {
        let target = self.collisions + collisions;
        // Stops before the next event; the time is that of the last collision.
        let _ = self.drive_dispatch(f64::INFINITY, u64::MAX, target, true);
    }

    /// The stationary averages so far.
    pub fn summary(&self) -> Intruder1dSummary {
        let m = self.params.mass;
        let tb = self.params.bath_temperature;
        let temperature = self.series.estimate(1).scaled(m);
        Intruder1dSummary {
            time: self.time,
            collisions: self.collisions,
            samples: self.series.samples(),
            mean_velocity: self.series.estimate(0),
            temperature_ratio: temperature.scaled(1.0 / tb),
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

impl Engine for Intruder1d {
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
        self.drive_dispatch(until, max_events, u64::MAX, true)
    }
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

// ---------------------------------------------------------------------------------------
// Ensembles of independent intruders: the transient F(v1, t) of G-8
// ---------------------------------------------------------------------------------------

/// Initial velocity distribution of the walkers of an ensemble.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum InitialVelocity {
    /// All walkers start at `velocity`.
    Delta {
        /// Initial velocity (velocity units).
        velocity: f64,
    },
    /// Gaussian of intruder temperature `temperature = M <v1^2>`.
    Gaussian {
        /// Initial intruder temperature (energy units).
        temperature: f64,
    },
    /// The bath velocity distribution itself.
    Bath,
}

/// The ensemble's distribution at the output times.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnsembleResult {
    /// Output times.
    pub times: Vec<f64>,
    /// `F(v1, t)` at each output time (histogram over walkers).
    pub histograms: Vec<Histogram>,
    /// `T(t) = M <v1^2>` with its error over independent walkers.
    pub temperature: Vec<Estimate>,
    /// `<v1>(t)` with its error over independent walkers.
    pub mean_velocity: Vec<Estimate>,
    /// The walkers' velocities, `velocities[k][w]` at output time `k` (independent
    /// samples of `F(v1, t_k)`).
    pub velocities: Vec<Vec<f64>>,
}

/// Runs `walkers` independent intruders (walker `w` uses the streams
/// `stream(seed, [INITIAL_STATE, w])` and `stream(seed, [MEMBER, w])`, so results do not
/// depend on the number of threads) and records their velocities at `times` (increasing).
pub fn run_ensemble(
    cfg: &Intruder1dConfig,
    initial: &InitialVelocity,
    walkers: usize,
    times: &[f64],
    seed: u64,
) -> Result<EnsembleResult, BathError> {
    let params = Intruder1dParams::new(cfg)?;
    if times.windows(2).any(|w| w[1] < w[0]) || times.iter().any(|t| t.is_nan() || *t < 0.0) {
        return Err(BathError::Parameter(
            "output times must be >= 0 and increasing".into(),
        ));
    }
    if let InitialVelocity::Gaussian { temperature } = initial
        && (temperature.is_nan() || *temperature < 0.0)
    {
        return Err(BathError::Parameter(
            "initial temperature must be >= 0".into(),
        ));
    }
    let per_walker: Vec<Vec<f64>> = (0..walkers)
        .into_par_iter()
        .map(|w| {
            let mut init = stream(seed, &[INITIAL_STATE, w as u64]);
            let v0 = match initial {
                InitialVelocity::Delta { velocity } => *velocity,
                InitialVelocity::Gaussian { temperature } => {
                    let z: f64 = init.sample(rand_distr::StandardNormal);
                    z * (temperature / params.mass).sqrt()
                }
                InitialVelocity::Bath => params.bath.sample(&mut init),
            };
            let mut walker =
                Intruder1d::with_params(params.clone(), cfg, stream(seed, &[MEMBER, w as u64]), v0);
            times
                .iter()
                .map(|&t| {
                    walker.evolve_to(t);
                    walker.v1
                })
                .collect()
        })
        .collect();
    let hmax = cfg
        .histogram_max
        .unwrap_or(6.0 * (params.bath_temperature / params.mass).sqrt());
    let mut result = EnsembleResult {
        times: times.to_vec(),
        histograms: Vec::new(),
        temperature: Vec::new(),
        mean_velocity: Vec::new(),
        velocities: Vec::new(),
    };
    for k in 0..times.len() {
        let mut h = Histogram::new(-hmax, hmax, cfg.histogram_bins);
        let (mut s1, mut s2) = (RunningStats::new(), RunningStats::new());
        for v in per_walker.iter().map(|p| p[k]) {
            h.push(v);
            s1.push(v);
            s2.push(params.mass * v * v);
        }
        result.histograms.push(h);
        result
            .velocities
            .push(per_walker.iter().map(|p| p[k]).collect());
        result.mean_velocity.push(Estimate {
            mean: s1.mean(),
            error: s1.standard_error(),
        });
        result.temperature.push(Estimate {
            mean: s2.mean(),
            error: s2.standard_error(),
        });
    }
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advance_is_independent_of_output_chunking() {
        let cfg = Intruder1dConfig {
            transient: Some(0.0),
            ..Default::default()
        };
        let mut a = Intruder1d::new(&cfg, 5).unwrap();
        let mut b = Intruder1d::new(&cfg, 5).unwrap();
        a.advance(100.0, u64::MAX).unwrap();
        for k in 1..=100 {
            while b.advance(k as f64, 7).unwrap() == Progress::BudgetExhausted {}
        }
        assert_eq!(a.velocity(), b.velocity());
        assert_eq!(a.collisions(), b.collisions());
        assert_eq!(a.summary().samples, b.summary().samples);
    }

    #[test]
    fn config_rejects_bad_values() {
        let bad = Intruder1dConfig {
            restitution: 1.5,
            ..Default::default()
        };
        assert!(Intruder1d::new(&bad, 1).is_err());
    }
}
