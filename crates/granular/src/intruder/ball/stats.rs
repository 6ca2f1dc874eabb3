//! Time-grid observables of a disk or sphere intruder (shared by the Gillespie engine and
//! its DSMC twin): temperature `T = M <|V|^2>/d`, kurtosis `<|V|^4>/<|V|^2>^2`, the collision
//! rate, the truncated temperature `M <min(|V|^2, h^2)>/d` (`h` the histogram edge: a
//! bounded quantity whose batch-means error stays valid when `|V|` has a heavy tail, as in
//! the power-law bath), and histograms of each velocity component and of the speed, all on
//! the grid `t_k = transient + k dt` (pseudocode step 2 of the paper), with batch-means
//! errors.

use serde::{Deserialize, Serialize};

use super::{BallParams, IsotropicBath};
use crate::intruder::observables::{Estimate, GridSeries, grid_points_before, hist_push_n};
use crate::intruder::theory::martin_piasecki_ratio;
use crate::stats::Histogram;
use crate::theory::intruder::{maxwellian_kurtosis, maxwellian_mean_collision_rate};

/// The grid samples of one run: `|V|^2`, `|V|^4`, the number of collisions in
/// `(t_{k-1}, t_k]` and `min(|V|^2, h^2)`, plus the histograms.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct BallStatistics {
    dimension: usize,
    dt: f64,
    transient: f64,
    next_sample: f64,
    series: GridSeries<4>,
    /// Collisions since the last grid point (counted from `transient - dt` on; a float,
    /// exact up to 2^53, as the series stores it).
    pending: f64,
    components: Vec<Histogram>,
    speed: Histogram,
    inv_width: f64,
    speed_inv_width: f64,
}

impl BallStatistics {
    /// Grid spacing `dt`, first grid point `transient`, histograms of `bins` bins on
    /// `[-h, h]` (components) and `[0, h]` (speed).
    pub(crate) fn new(dimension: usize, dt: f64, transient: f64, h: f64, bins: usize) -> Self {
        Self {
            dimension,
            dt,
            transient,
            next_sample: transient,
            series: GridSeries::new(64),
            pending: 0.0,
            components: vec![Histogram::new(-h, h, bins); dimension],
            speed: Histogram::new(0.0, h, bins),
            inv_width: bins as f64 / (2.0 * h),
            speed_inv_width: bins as f64 / h,
        }
    }

    /// Grid spacing.
    pub(crate) fn sample_interval(&self) -> f64 {
        self.dt
    }

    /// Start of the averaging window.
    pub(crate) fn transient(&self) -> f64 {
        self.transient
    }

    /// Upper edge `h` of the histograms.
    pub(crate) fn histogram_max(&self) -> f64 {
        self.speed.max
    }

    /// Records the grid points before `upto` (or at it when `inclusive`) at the velocity
    /// `v` of speed `speed` (constant since the last collision). The first of them receives
    /// the collisions counted since the previous grid point.
    #[inline(always)]
    pub(crate) fn sample_until<const D: usize>(
        &mut self,
        upto: f64,
        inclusive: bool,
        v: &[f64; D],
        speed: f64,
    ) {
        if self.next_sample > upto || (!inclusive && self.next_sample == upto) {
            return;
        }
        self.record(upto, inclusive, v, speed);
    }

    fn record<const D: usize>(&mut self, upto: f64, inclusive: bool, v: &[f64; D], speed: f64) {
        let (n, t) = grid_points_before(self.next_sample, self.dt, upto, inclusive);
        if n == 0 {
            return;
        }
        let v2 = speed * speed;
        let v4 = v2 * v2;
        let h = self.speed.max;
        let truncated = v2.min(h * h);
        self.series.push([v2, v4, self.pending, truncated]);
        if n > 1 {
            self.series.push_n([v2, v4, 0.0, truncated], n - 1);
        }
        self.pending = 0.0;
        if let Some(components) = self.components.get_mut(..D) {
            for (h, &x) in components.iter_mut().zip(v) {
                hist_push_n(h, self.inv_width, x, n);
            }
        }
        hist_push_n(&mut self.speed, self.speed_inv_width, speed, n);
        self.next_sample = t;
    }

    /// Counts a collision at time `t` (call after [`Self::sample_until`] for `t`).
    #[inline]
    pub(crate) fn count_collision(&mut self, t: f64) {
        if t > self.transient - self.dt {
            self.pending += 1.0;
        }
    }

    /// The averages so far, with the theory values for `params`.
    pub(crate) fn summary(&self, params: &BallParams, time: f64, collisions: u64) -> BallSummary {
        let d = self.dimension as f64;
        let tb = params.bath_temperature;
        let temperature = self.series.estimate(0).scaled(params.mass / d);
        let ratio = martin_piasecki_ratio(params.restitution, params.mass, params.bath_mass);
        let theory_collision_rate = match params.bath {
            IsotropicBath::Gaussian(_) => maxwellian_mean_collision_rate(
                self.dimension,
                params.radius,
                params.bath_density,
                tb,
                params.bath_mass,
                ratio * tb,
                params.mass,
            ),
            _ => f64::NAN,
        };
        BallSummary {
            dimension: self.dimension,
            time,
            collisions,
            samples: self.series.samples(),
            temperature_ratio: temperature.scaled(1.0 / tb),
            temperature,
            kurtosis: self.series.estimate_fn(|q| q[1] / (q[0] * q[0])),
            collision_rate: self.series.estimate(2).scaled(1.0 / self.dt),
            truncated_temperature: self.series.estimate(3).scaled(params.mass / d),
            martin_piasecki_ratio: ratio,
            maxwellian_kurtosis: maxwellian_kurtosis(self.dimension),
            theory_collision_rate,
            component_histograms: self.components.clone(),
            speed_histogram: self.speed.clone(),
        }
    }
}

/// Stationary averages of a disk or sphere intruder run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BallSummary {
    /// `d`.
    pub dimension: usize,
    /// Simulated time.
    pub time: f64,
    /// Collisions (the transient included).
    pub collisions: u64,
    /// Grid samples in the averages.
    pub samples: u64,
    /// `T = M <|V|^2>/d` (energy units).
    pub temperature: Estimate,
    /// `T / T_B`.
    pub temperature_ratio: Estimate,
    /// `<|V|^4>/<|V|^2>^2` (`(d+2)/d` for a Maxwellian, G-41).
    pub kurtosis: Estimate,
    /// Collisions per unit time in the averaging window (grid counts over `dt`).
    pub collision_rate: Estimate,
    /// `M <min(|V|^2, h^2)>/d`, `h` = the histogram edge (energy units).
    pub truncated_temperature: Estimate,
    /// G-40 (exact for the Gaussian bath).
    pub martin_piasecki_ratio: f64,
    /// G-41, `(d+2)/d`.
    pub maxwellian_kurtosis: f64,
    /// G-42 at the G-40 temperature (Gaussian bath; NaN otherwise).
    pub theory_collision_rate: f64,
    /// Histograms of `V_x`, `V_y` (, `V_z`) on the grid.
    pub component_histograms: Vec<Histogram>,
    /// Histogram of `|V|` on the grid.
    pub speed_histogram: Histogram,
}

impl BallSummary {
    /// The scalars in the engine's observation (names as in `summary.json` and Python).
    pub(crate) fn quantities(&self) -> Vec<(String, f64)> {
        vec![
            ("collisions".into(), self.collisions as f64),
            ("samples".into(), self.samples as f64),
            ("temperature".into(), self.temperature.mean),
            ("temperature_error".into(), self.temperature.error),
            ("temperature_ratio".into(), self.temperature_ratio.mean),
            (
                "temperature_ratio_error".into(),
                self.temperature_ratio.error,
            ),
            ("kurtosis".into(), self.kurtosis.mean),
            ("kurtosis_error".into(), self.kurtosis.error),
            ("collision_rate".into(), self.collision_rate.mean),
            ("collision_rate_error".into(), self.collision_rate.error),
            (
                "truncated_temperature".into(),
                self.truncated_temperature.mean,
            ),
            (
                "truncated_temperature_error".into(),
                self.truncated_temperature.error,
            ),
            ("martin_piasecki_ratio".into(), self.martin_piasecki_ratio),
            ("maxwellian_kurtosis".into(), self.maxwellian_kurtosis),
            ("theory_collision_rate".into(), self.theory_collision_rate),
        ]
    }
}
