//! `summary.json`, typed: what a finished run reports, read back by `sweep`, `plot`, the
//! Python package and anyone else with [`RunDir::summary`](super::RunDir::summary).
//!
//! Numbers that are not defined (a NaN: no window, no samples) are written as `null` and
//! read back as NaN (or `None` where the field is optional).

use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;

/// `null` in JSON for a NaN or infinite number, read back as NaN.
fn nan_from_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A map of numbers whose `null`s are read back as NaN.
fn nan_map_from_null<'de, D: Deserializer<'de>>(d: D) -> Result<BTreeMap<String, f64>, D::Error> {
    let raw = BTreeMap::<String, Option<f64>>::deserialize(d)?;
    Ok(raw
        .into_iter()
        .map(|(k, v)| (k, v.unwrap_or(f64::NAN)))
        .collect())
}

/// Pearson chi-square of the pooled equilibrium speeds of one species against the
/// Maxwell-Boltzmann law at the measured temperature (HD-12 in 2D, its `D`-dimensional
/// form otherwise).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaxwellBoltzmannFit {
    /// Temperature of the pooled samples, `Σ m v² / (D n)`.
    #[serde(deserialize_with = "nan_from_null")]
    pub temperature: f64,
    /// Speeds pooled.
    pub samples: u64,
    /// Snapshots pooled.
    pub snapshots: u64,
    /// Pearson's statistic.
    #[serde(deserialize_with = "nan_from_null")]
    pub chi_square: f64,
    /// Degrees of freedom (bins merged to at least five expected counts, minus one).
    pub degrees_of_freedom: usize,
    /// Probability of a statistic at least as large under the law.
    #[serde(deserialize_with = "nan_from_null")]
    pub p_value: f64,
}

/// Per-species averages over the pooled equilibrium samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeciesStatistics {
    /// Grain mass.
    pub mass: f64,
    /// Speeds pooled.
    pub samples: u64,
    /// Mean speed.
    #[serde(deserialize_with = "nan_from_null")]
    pub mean_speed: f64,
    /// Its standard error.
    #[serde(deserialize_with = "nan_from_null")]
    pub mean_speed_error: f64,
    /// Mean kinetic energy per grain.
    #[serde(deserialize_with = "nan_from_null")]
    pub mean_kinetic_energy: f64,
    /// Its standard error.
    #[serde(deserialize_with = "nan_from_null")]
    pub mean_kinetic_energy_error: f64,
    /// `2 <E> / D`.
    #[serde(deserialize_with = "nan_from_null")]
    pub temperature: f64,
    /// The Maxwell-Boltzmann mean speed at that temperature.
    #[serde(deserialize_with = "nan_from_null")]
    pub maxwell_boltzmann_mean_speed: f64,
}

/// The crater measure of a `[crater]` table: bed grains displaced since `t = 0`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CraterSummary {
    /// The bed species.
    pub species: String,
    /// The displacement threshold.
    pub displacement: f64,
    /// Grains of the bed species.
    pub grains: usize,
    /// Those displaced by more than the threshold.
    pub displaced: usize,
    /// `displaced / grains`.
    pub fraction: f64,
}

/// The `intruder` block: stationary averages with their errors, and the theory value
/// where one exists (`docs/output.md`). Fields of the other model are absent.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct IntruderSummary {
    /// `"1d"`, `"needle"`, `"dsmc-twin"`, `"disk"` or `"sphere"`.
    pub model: String,
    /// The reference density of `intruder_histograms.csv`.
    pub histogram_reference: String,
    /// Samples of the time averages.
    pub samples: u64,
    /// Mean and error of each average (1D and twin: temperature, temperature_ratio,
    /// kurtosis, mean_velocity; disk and sphere: temperature, temperature_ratio, kurtosis,
    /// collision_rate, truncated_temperature; needle: translational_temperature,
    /// rotational_temperature, their ratios to the bath, correlation_r), each with its
    /// `_error`, in the order written.
    #[serde(flatten)]
    pub averages: BTreeMap<String, Option<f64>>,
    /// Bath temperature (1D and twin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bath_temperature: Option<f64>,
    /// Theory value of `T/T_B` (G-18 for the Gaussian bath, the exact power-law case).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory_temperature_ratio: Option<f64>,
    /// Where the theory value comes from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory: Option<String>,
    /// `(measured - theory) / error` of the temperature ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature_ratio_z: Option<f64>,
    /// DSMC twin: raises of the bound of the rejection sampler.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound_raises: Option<u64>,
    /// DSMC twin: trials per accepted collision.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trials_per_collision: Option<f64>,
    /// Disk or sphere in a Gaussian bath: the Maxwellian kurtosis `(d + 2)/d` (G-41).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory_kurtosis: Option<f64>,
    /// Disk or sphere in a Gaussian bath: the mean collision rate at the G-40 temperature
    /// (G-42, collisions per unit time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory_collision_rate: Option<f64>,
    /// Needle: standard deviation of the best-fit Gaussian of a velocity component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_component_sigma: Option<f64>,
    /// Needle: the same for the angular velocity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity_sigma: Option<f64>,
}

impl IntruderSummary {
    /// A number of the block by its key in `summary.json` (an average, its `_error`, or
    /// one of the named fields); `None` where the model has none.
    pub fn value(&self, key: &str) -> Option<f64> {
        match key {
            "bath_temperature" => self.bath_temperature,
            "theory_temperature_ratio" => self.theory_temperature_ratio,
            "temperature_ratio_z" => self.temperature_ratio_z,
            "theory_kurtosis" => self.theory_kurtosis,
            "theory_collision_rate" => self.theory_collision_rate,
            "bound_raises" => self.bound_raises.map(|b| b as f64),
            "trials_per_collision" => self.trials_per_collision,
            "velocity_component_sigma" => self.velocity_component_sigma,
            "angular_velocity_sigma" => self.angular_velocity_sigma,
            "samples" => Some(self.samples as f64),
            _ => self.averages.get(key).copied().flatten(),
        }
    }
}

/// Values the scenario resolved at build time (a packing fraction turned into a radius):
/// the `resolved` block, written from the simulation's `crate::scenario::Resolved`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ResolvedSummary {
    /// Grain radius per species, by species name.
    pub radius: BTreeMap<String, f64>,
    /// Packing fraction of all grains in the box, `Σ N_s v_D(r_s) / V`.
    #[serde(deserialize_with = "nan_from_null")]
    pub packing_fraction: f64,
    /// DSMC: the contact value `χ` of the pair correlation, the Enskog factor of the
    /// collision rate (DSMC-1), at the packing fraction the engine uses, when it is on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_value: Option<f64>,
}

impl ResolvedSummary {
    /// The block of a simulation resolved as `resolved` (`None` for the intruder engine).
    pub fn of(resolved: &crate::scenario::Resolved) -> Option<ResolvedSummary> {
        let g = resolved.grains.as_ref()?;
        Some(ResolvedSummary {
            radius: g
                .species
                .iter()
                .map(|s| (s.name.clone(), s.radius))
                .collect(),
            packing_fraction: g.packing_fraction,
            contact_value: (g.dsmc.is_some() && g.enskog).then_some(g.chi),
        })
    }
}

/// Speeds of a gas that was not in a steady state, scaled by each snapshot's thermal speed
/// (`c = v / v_T(t)`, `scaled_speed_histograms.csv`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScaledSpeedSummary {
    /// Scaled speeds pooled.
    pub samples: u64,
    /// Snapshots pooled.
    pub snapshots: u64,
    /// Fourth cumulant `a2 = D/(D+2) <c⁴>/<c²>² - 1` of the pooled scaled speeds (DSMC-4).
    pub a2: f64,
    /// Lowest temperature of a pooled snapshot (energy units).
    pub temperature_min: f64,
    /// Highest temperature of a pooled snapshot (energy units).
    pub temperature_max: f64,
    /// The homogeneous cooling state's `a2` at the scenario's restitution, the first and
    /// the second estimate of van Noije and Ernst (1998) ([`crate::theory::sonine`]), for
    /// one species in a periodic box without gravity or TC model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory_a2: Option<[f64; 2]>,
}

/// The mean of one observable over the run after the equilibration time, with its
/// standard error by blocking (`crate::averaging`, `docs/output.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AverageValue {
    /// Mean of the samples (one per output time after the equilibration time).
    #[serde(deserialize_with = "nan_from_null")]
    pub mean: f64,
    /// Standard error of the mean; `null` where no valid estimate exists (`error_note`).
    pub error: Option<f64>,
    /// Why `error` is `null`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_note: Option<String>,
    /// Samples averaged.
    pub samples: u64,
    /// The block length the error comes from, in samples (0 without an error).
    pub block_length: u64,
    /// Whole blocks of that length.
    pub blocks: u64,
}

/// The `averages` block: run averages after the equilibration time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AveragesSummary {
    /// Time of the first sample averaged (`null`: no output after the equilibration time).
    #[serde(deserialize_with = "nan_from_null")]
    pub start_time: f64,
    /// The rule that set the equilibration time (`output.equilibration_time = ...`, or the
    /// default of the engine).
    pub equilibration: String,
    /// How errors are estimated.
    pub method: String,
    /// Mean and error per observable, by the column name of `timeseries.csv` (and
    /// `compressibility_factor`).
    pub observables: BTreeMap<String, AverageValue>,
}

/// The steady state of a driven gas (`[driving]`, [`crate::driving`]): the run averages
/// (the `averages` block's values, with their standard errors) beside the Sonine theory of
/// van Noije and Ernst (1998) for one species in a periodic box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SteadyStateSummary {
    /// `rescale` (homogeneous cooling state) or `white_noise` (heated gas).
    pub kind: String,
    /// Measured `a2` after the equilibration time (`null`: no sample).
    pub a2: Option<AverageValue>,
    /// The Sonine `a2` of the state ([`crate::theory::sonine`]): the HCS's second
    /// estimate (`rescale`), the heated gas's (`white_noise`).
    pub theory_a2: f64,
    /// `rescale`: the HCS's first estimate, for comparison.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theory_a2_first: Option<f64>,
    /// Measured temperature (energy units).
    pub temperature: Option<AverageValue>,
    /// `rescale`: the fixed temperature; `white_noise`: the temperature of the exact
    /// energy balance with the Sonine loss rate at `theory_a2`
    /// ([`crate::driving::GasTheory::white_noise_temperature`]).
    pub theory_temperature: f64,
    /// Measured cooling rate `zeta = 2 (loss rate) / (D N T)` (1 / time).
    pub cooling_rate: Option<AverageValue>,
    /// `zeta = (1-e²)/D omega(T) (1 + 3 a2/16)` at the measured mean temperature and
    /// `theory_a2` ([`crate::driving::GasTheory::cooling_rate`]); `null` when the run
    /// has no temperature sample (it ended before the equilibration time).
    pub theory_cooling_rate: Option<f64>,
    /// The contact value `chi` of the collision frequency the theory uses (1: dilute).
    pub chi: f64,
}

/// Rough grains (`docs/rough.md`): the measured temperature ratio and reduced cooling
/// rate of the run (averages after the equilibration time, with their standard errors)
/// beside the kinetic theory of one species of rough grains in a homogeneous gas: the
/// How a DSMC run split over MPI ranks shared its grains (`summary.json`'s `ranks`): the
/// memory of the busiest rank, which sets how many grains a node can take.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RanksSummary {
    /// Number of ranks.
    pub ranks: usize,
    /// The most grains each rank held at a time over the run, by rank: its own grains and,
    /// at a migration, at the set-up, at a re-cut or when the outputs read the grains by
    /// blocks of ids, those in its buffers besides (`Domain::peak_grains`).
    pub peak_grains: Vec<usize>,
    /// The largest peak over an even share `N / ranks`: 1 would be a perfectly even
    /// machine with no buffers; the memory per rank is this times `N / ranks` times the
    /// bytes per grain (docs/cluster.md).
    pub peak_over_even_share: f64,
    /// Grains each rank owns at the end, by rank.
    pub final_grains: Vec<usize>,
    /// Times the slab cuts moved to follow the grains (`dsmc.balance`).
    pub cuts_moved: u64,
}

/// Maxwellian approximation (RS-4/RS-5 for a cooling gas and the rescaled cooling state,
/// RS-6 for white noise) and the first Sonine approximation (RS-8, RS-9).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RoughSummary {
    /// `cooling` (free), `rescale` (the rescaled cooling state) or `white_noise`.
    pub state: String,
    /// α, β and κ (of the first species) the theory is evaluated at.
    pub normal_restitution: f64,
    /// β (Walton's sticking value β₀ when `friction` is set: then no theory is given).
    pub tangential_restitution: f64,
    /// κ of the first species.
    pub inertia: f64,
    /// Measured `T_r / T_t` (the `temperature_ratio` column).
    pub temperature_ratio: Option<AverageValue>,
    /// Maxwellian approximation: RS-4 (cooling states) or RS-6 (white noise).
    pub theory_temperature_ratio: Option<f64>,
    /// First Sonine approximation: RS-8 or RS-9 (`null` where it has no solution).
    pub theory_temperature_ratio_sonine: Option<f64>,
    /// Measured `ζ/ν`, the cooling rate of the total energy per collision of a grain (the
    /// `reduced_cooling_rate` column).
    pub reduced_cooling_rate: Option<AverageValue>,
    /// Maxwellian approximation of `ζ/ν` (RS-5; for white noise
    /// `d_t ζ_t / (d_t + d_r θ)` at RS-6).
    pub theory_reduced_cooling_rate: Option<f64>,
    /// Sonine approximation of `ζ/ν`, over the Sonine collision frequency
    /// `ν_M (1 - a20/16)` as a measured rate is.
    pub theory_reduced_cooling_rate_sonine: Option<f64>,
    /// The Sonine cumulants `[a20, a02, a11]` of the state (`a20` is the `a2` column).
    pub theory_cumulants_sonine: Option<[f64; 3]>,
    /// How far the theory can be trusted here.
    pub note: String,
}

/// What a finished run reports (`summary.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Engine name.
    pub engine: String,
    /// granular version.
    pub version: String,
    /// Seed.
    pub seed: u64,
    /// Dimension.
    pub dimension: usize,
    /// Number of particles.
    pub n: usize,
    /// Wall-clock seconds (all sessions of a resumed run).
    pub wall_seconds: f64,
    /// Events processed.
    pub events: u64,
    /// Events per wall-clock second.
    pub events_per_second: f64,
    /// Collisions (see [`crate::Observation::collisions`]).
    pub collisions: u64,
    /// Collisions per wall-clock second.
    pub collisions_per_second: f64,
    /// Which stop rule ended the run (`time`, `collisions_per_particle`, ...).
    pub stop_reason: String,
    /// Kinetic energy at `t = 0`.
    pub initial_kinetic_energy: f64,
    /// Observables at the end: the last row of `timeseries.csv`, by column.
    #[serde(rename = "final", deserialize_with = "nan_map_from_null")]
    pub final_observables: BTreeMap<String, f64>,
    /// Maxwell-Boltzmann goodness of fit per species.
    pub maxwell_boltzmann_fit: BTreeMap<String, MaxwellBoltzmannFit>,
    /// Per-species averages over the pooled equilibrium samples.
    pub species: BTreeMap<String, SpeciesStatistics>,
    /// Species whose pooled snapshots' temperatures spread beyond the steady tolerance
    /// (a cooling gas): their scaled speed statistics, in place of a Maxwell-Boltzmann fit.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub scaled_speeds: BTreeMap<String, ScaledSpeedSummary>,
    /// Crater measure, when the scenario has a `[crater]` table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crater: Option<CraterSummary>,
    /// Intruder engine: stationary averages with errors and the theory value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub intruder: Option<IntruderSummary>,
    /// Means and standard errors of the time series after the equilibration time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub averages: Option<AveragesSummary>,
    /// A driven gas (`[driving]`): its measured steady state beside kinetic theory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steady_state: Option<SteadyStateSummary>,
    /// Rough grains: the temperature ratio and cooling rate beside theory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rough: Option<RoughSummary>,
    /// Values resolved at build time (radius, packing fraction, contact value).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolved: Option<ResolvedSummary>,
    /// Warnings raised during the run (e.g. DSMC's validity conditions), also in `log.txt`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// A DSMC run over MPI ranks: how the ranks shared the grains (absent otherwise; the
    /// rest of the summary is the threaded run's, bit for bit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranks: Option<RanksSummary>,
    /// Parameters changed in flight (`Simulation::set` or `[[schedule]]`), in order: time,
    /// key, old and new value.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub changes: Vec<crate::in_flight::Change>,
    /// Outputs written (rows of `timeseries.csv` after the one at `t = 0`).
    pub outputs: u64,
    /// Snapshots written.
    pub snapshots: u64,
}

impl Summary {
    /// The final value of an observable by column name, or a summary field that sweeps
    /// tabulate (`crater_size`).
    pub fn observable(&self, name: &str) -> Option<f64> {
        if name == "crater_size" {
            return self.crater.as_ref().map(|c| c.displaced as f64);
        }
        self.final_observables.get(name).copied()
    }

    /// `final.contact_value` with its error: `g(σ)` of a one-species run with
    /// `output.pair_correlation` (`crate::structure`); `None` without it.
    pub fn contact_value(&self) -> Option<(f64, f64)> {
        self.value_with_error("contact_value")
    }

    /// `final.diffusion_coefficient` with its error (length²/time, from the MSD of a
    /// one-species run with `output.msd`, `crate::transport`); `None` without it.
    pub fn diffusion_coefficient(&self) -> Option<(f64, f64)> {
        self.value_with_error("diffusion_coefficient")
    }

    /// `final.<name>` and `final.<name>_error`.
    fn value_with_error(&self, name: &str) -> Option<(f64, f64)> {
        let f = &self.final_observables;
        Some((*f.get(name)?, *f.get(&format!("{name}_error"))?))
    }
}
