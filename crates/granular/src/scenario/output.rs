//! `[output]`: what a run writes and how often, and the layout of its output times.

use serde::{Deserialize, Serialize};

/// `[output]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Time between outputs (rows of `timeseries.csv`), time units.
    #[serde(default = "output_interval")]
    pub interval: f64,
    /// Write a snapshot every this many outputs (0: only the first and the last).
    #[serde(default)]
    pub snapshot_every: u64,
    /// Speed histograms: bins.
    #[serde(default = "bins")]
    pub histogram_bins: usize,
    /// Speed histograms: upper edge, in units of the initial root-mean-square speed.
    #[serde(default = "hist_max")]
    pub histogram_max_speed: f64,
    /// Collisions per grain before speeds enter the equilibrium histogram.
    #[serde(default = "equilibration")]
    pub equilibration_collisions_per_particle: f64,
    /// Time from which the time series enters the summary's `averages` (time units);
    /// absent: the first output after `equilibration_collisions_per_particle` collisions
    /// per grain (many-grain engines) or after the intruder's `transient`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equilibration_time: Option<f64>,
    /// Collisions per grain between two pooled samples of the equilibrium histogram
    /// (appendix C.2 of the hard-disk assignment: many collisions apart so samples are independent).
    #[serde(default = "sample_spacing")]
    pub histogram_sample_spacing: f64,
    /// Wall-clock seconds between checkpoints.
    #[serde(default = "checkpoint")]
    pub checkpoint_seconds: f64,
    /// Record the impact-parameter histogram of the collisions between observation times
    /// (`impact_histograms.npz`).
    #[serde(default)]
    pub impact_histograms: bool,
    /// Record the structure factor `S(k)` at observation times (`structure_factor.npz`).
    #[serde(default)]
    pub structure_factor: bool,
    /// Largest integer wave-vector component `|n_k|` of `S(k)` (`k = 2π n / L`).
    #[serde(default = "sk_max_index")]
    pub structure_factor_max_index: usize,
    /// Bins per axis of the density maps (`density_maps.npz`); empty: none.
    #[serde(default)]
    pub density_map: Vec<usize>,
    /// Observation times of the opt-in observables (the first output at or after each);
    /// empty: every output.
    #[serde(default)]
    pub observable_times: Vec<f64>,
    /// Trajectory formats written at every snapshot (`trajectory/`): any of `"xyz"`,
    /// `"lammps"`, `"gsd"`, `"vtk"`; empty: none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub trajectory: Vec<crate::output::TrajectoryFormat>,
    /// Spacing of the output times: `"linear"` (every `interval`) or `"log"` (the first
    /// at `interval`, then `per_decade` per decade of time).
    #[serde(default)]
    pub spacing: OutputSpacing,
    /// Outputs per decade of time with `spacing = "log"`.
    #[serde(default = "per_decade")]
    pub per_decade: u32,
    /// Record the pair correlation `g(r)` at observation times (`pair_correlation.csv`,
    /// the contact value in `summary.json`; event-driven engine).
    #[serde(default)]
    pub pair_correlation: bool,
    /// Bins of `g(r)` over `[0, r_max)`.
    #[serde(default = "pair_correlation_bins")]
    pub pair_correlation_bins: usize,
    /// `r_max` of `g(r)` in units of the largest contact distance `2 R_max`.
    #[serde(default = "pair_correlation_range")]
    pub pair_correlation_range: f64,
    /// Record the mean-square displacement and velocity autocorrelation at every output
    /// (`mean_square_displacement.csv`, `velocity_autocorrelation.csv`, the diffusion
    /// coefficient in `summary.json`).
    #[serde(default)]
    pub msd: bool,
    /// Lag window `[from, to]` (time units) of the diffusion coefficient's fit; empty:
    /// from 10 % to 50 % of the observed time span.
    #[serde(default)]
    pub msd_fit: Vec<f64>,
}

/// `output.spacing`: how the output times are laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputSpacing {
    /// `t_k = k * interval`.
    #[default]
    Linear,
    /// `t_k = interval * 10^((k - 1) / per_decade)`, `k >= 1`: equal steps of `ln t`, which
    /// for a gas cooling by Haff's law (HD-17) are equal steps of collisions per grain once
    /// `t >> t0`.
    Log,
}

impl OutputSpec {
    /// Time of output `k` (`k = 1` is the first after the start; `k = 0` is `t = 0`).
    pub fn time(&self, k: u64) -> f64 {
        match self.spacing {
            OutputSpacing::Linear => k as f64 * self.interval,
            OutputSpacing::Log if k == 0 => 0.0,
            OutputSpacing::Log => {
                self.interval * 10f64.powf((k - 1) as f64 / f64::from(self.per_decade.max(1)))
            }
        }
    }

    /// Outputs written up to time `t` (the last one at `t`), at least 1.
    pub fn count_until(&self, t: f64) -> f64 {
        let n = match self.spacing {
            OutputSpacing::Linear => (t / self.interval).ceil(),
            OutputSpacing::Log if t <= self.interval => 1.0,
            OutputSpacing::Log => {
                1.0 + (f64::from(self.per_decade) * (t / self.interval).log10()).ceil()
            }
        };
        n.max(1.0)
    }
}

fn per_decade() -> u32 {
    10
}

fn pair_correlation_bins() -> usize {
    200
}

fn pair_correlation_range() -> f64 {
    5.0
}

fn sk_max_index() -> usize {
    32
}

fn output_interval() -> f64 {
    0.1
}
fn bins() -> usize {
    50
}
fn hist_max() -> f64 {
    3.5
}
fn equilibration() -> f64 {
    10.0
}
fn sample_spacing() -> f64 {
    5.0
}
fn checkpoint() -> f64 {
    60.0
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            interval: output_interval(),
            snapshot_every: 0,
            histogram_bins: bins(),
            histogram_max_speed: hist_max(),
            equilibration_collisions_per_particle: equilibration(),
            equilibration_time: None,
            histogram_sample_spacing: sample_spacing(),
            checkpoint_seconds: checkpoint(),
            impact_histograms: false,
            structure_factor: false,
            structure_factor_max_index: sk_max_index(),
            density_map: Vec::new(),
            observable_times: Vec::new(),
            trajectory: Vec::new(),
            spacing: OutputSpacing::Linear,
            per_decade: per_decade(),
            pair_correlation: false,
            pair_correlation_bins: pair_correlation_bins(),
            pair_correlation_range: pair_correlation_range(),
            msd: false,
            msd_fit: Vec::new(),
        }
    }
}
