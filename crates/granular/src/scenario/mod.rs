//! The scenario format: one TOML file describes a run for any engine. Shared tables
//! (`[box]`, `[[species]]`, `[initial]`, `[collisions]`, `[stop]`, `[output]`) come first;
//! each engine owns its own table (`[edmd]`, ...). Every field is documented in
//! `docs/scenario.md`; unknown keys are errors.
//!
//! Loading goes: file text → `toml::Table` → `--set` overrides applied to the table →
//! typed [`Scenario`] (serde, unknown keys rejected) → [`Scenario::validate`]. Every error
//! names the key, the value, the line when it comes from the file, and the fix.

pub(crate) mod advice;
mod de;
mod driving;
mod file;
mod intruder;
mod observables;
mod overrides;
mod preflight;
mod spans;
mod species;
mod sweep;
mod tables;
mod validate;

pub use de::seed::HELP as SEED_HELP;
pub use driving::{DrivingKind, DrivingSpec};
pub use file::{MAX_FILE_BYTES, read_text_file};
pub use intruder::{BathTable, DsmcTwinTable, IntruderSpec, NeedleTable, OneDTable, bath_file};
pub use overrides::apply_override;
pub use preflight::{
    Cost, EDMD_EVENTS_PER_COLLISION, FALLBACK_MEMORY, MAX_BYTES, MAX_COLLISIONS, MAX_OUTPUTS,
    NOMINAL_COLLISIONS_PER_SECOND, WARN_OUTPUTS, available_memory,
};
pub use spans::locate;
pub use species::MAX_NAME_LEN;
pub(crate) use sweep::sweep_member;
pub use sweep::{MAX_SWEEP_POINTS, sweep_observables};
pub use validate::{MAGNITUDE, MAX_BINS, MAX_HISTOGRAM_SPEED, MAX_PER_DECADE};

/// Whether `--set` assignment `o` set `key` or a table above it.
fn overridden(o: &str, key: &str) -> bool {
    let Some((k, _)) = o.split_once('=') else {
        return false;
    };
    let k = k.trim();
    let norm = |s: &str| {
        spans::parse_path(s)
            .map(|p| spans::path_text(&p))
            .unwrap_or_else(|_| s.to_string())
    };
    let (k, key) = (norm(k), norm(key));
    key == k
        || key.starts_with(&format!("{k}."))
        || key.starts_with(&format!("{k}["))
        || k.starts_with(&format!("{key}."))
}

use serde::{Deserialize, Serialize};
use std::fmt;

/// Which engine runs the scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EngineKind {
    /// Event-driven molecular dynamics (`granular::edmd`).
    Edmd,
    /// Direct Simulation Monte Carlo (`granular::dsmc`).
    Dsmc,
    /// Gillespie intruder in a thermal bath (`granular::intruder`); set up by `[intruder]`.
    Intruder,
}

/// A whole scenario.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Engine: `"edmd"`, `"dsmc"` or `"intruder"`.
    pub engine: EngineKind,
    /// Spatial dimension: 2 (disks) or 3 (spheres).
    #[serde(default = "two")]
    pub dimension: usize,
    /// Seed of all random streams; `granular run --seed` overrides it.
    #[serde(
        default = "one",
        deserialize_with = "de::seed::deserialize",
        serialize_with = "de::seed::serialize"
    )]
    pub seed: u64,
    /// Optional one-line description.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// The simulation box (not used by the intruder engine).
    #[serde(rename = "box", default, skip_serializing_if = "BoxSpec::is_default")]
    pub simulation_box: BoxSpec,
    /// Grain species (at least one; none for the intruder engine).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub species: Vec<SpeciesSpec>,
    /// How the initial state is built.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Collision law.
    #[serde(default)]
    pub collisions: CollisionSpec,
    /// Uniform acceleration (gravity), one component per axis, length/time².
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gravity: Vec<f64>,
    /// When the run stops (the first rule met ends it).
    #[serde(default)]
    pub stop: StopSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: OutputSpec,
    /// Options of the event-driven engine.
    #[serde(default)]
    pub edmd: EdmdSpec,
    /// Options of the DSMC engine (its numerics; the collision law, gravity, box and
    /// grains come from the shared tables).
    #[serde(default)]
    pub dsmc: DsmcSpec,
    /// The Gillespie intruder (`engine = "intruder"`): model, bath and parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub intruder: Option<IntruderSpec>,
    /// Crater measure (Problem 4 of the hard-disk assignment).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crater: Option<CraterSpec>,
    /// Parameter scan run by `granular sweep`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSpec>,
    /// A steady state of the gas (`[driving]`: velocity rescaling or white noise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driving: Option<DrivingSpec>,
}

/// The resolved scenario as written by [`Scenario::to_toml`]: the fields of [`Scenario`]
/// in its order, without the tables its engine does not read.
#[derive(Serialize)]
struct Resolved<'a> {
    engine: EngineKind,
    dimension: usize,
    #[serde(serialize_with = "de::seed::serialize")]
    seed: u64,
    #[serde(skip_serializing_if = "str::is_empty")]
    description: &'a str,
    #[serde(rename = "box", skip_serializing_if = "Option::is_none")]
    simulation_box: Option<&'a BoxSpec>,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    species: &'a [SpeciesSpec],
    #[serde(skip_serializing_if = "Option::is_none")]
    initial: Option<&'a InitialSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    collisions: Option<&'a CollisionSpec>,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    gravity: &'a [f64],
    stop: &'a StopSpec,
    output: &'a OutputSpec,
    #[serde(skip_serializing_if = "Option::is_none")]
    edmd: Option<&'a EdmdSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    dsmc: Option<&'a DsmcSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    intruder: Option<&'a IntruderSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    crater: Option<&'a CraterSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sweep: Option<&'a SweepSpec>,
    #[serde(skip_serializing_if = "Option::is_none")]
    driving: Option<&'a DrivingSpec>,
}

/// `[dsmc]`: numerical choices of the DSMC engine (see `docs/dsmc.md`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DsmcSpec {
    /// Time step τ; default one tenth of the initial mean free time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_step: Option<f64>,
    /// Requested cell edge L; default the smaller of the mean free path and the edge
    /// holding 10 grains on average.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cell_size: Option<f64>,
    /// `"cell"` (per cell and step, default) or `"global"` bound on relative speeds.
    #[serde(default)]
    pub vmax_mode: crate::dsmc::config::VmaxMode,
    /// Multiply DSMC-1 by the Enskog contact value χ(φ).
    #[serde(default)]
    pub enskog: bool,
    /// Use the free volume `V_c - V_b / ν_rcp` in DSMC-1.
    #[serde(default)]
    pub free_volume: bool,
    /// `"global"` (default) or `"cell"` packing fraction for the Enskog factor.
    #[serde(default)]
    pub density_scope: crate::dsmc::config::DensityScope,
    /// Consistent-Boltzmann advection: partners displaced by 2R along their momentum change.
    #[serde(default)]
    pub consistent_boltzmann: bool,
    /// Bins of the impact-parameter histogram `|b| / 2R`; default 20, as
    /// `edmd.impact_bins` of the event-driven engine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impact_bins: Option<usize>,
    /// Over MPI ranks, how the slab cuts follow the grains: `"count"` (default: equal
    /// grains per rank), `"time"` (equal measured compute time) or `"off"` (fixed cuts).
    /// Never changes the result.
    #[serde(default, skip_serializing_if = "is_default_balance")]
    pub balance: crate::dsmc::BalanceMode,
    /// Steps between two looks at the ranks' loads (default 20).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balance_every: Option<u64>,
}

fn is_default_balance(mode: &crate::dsmc::BalanceMode) -> bool {
    *mode == crate::dsmc::BalanceMode::default()
}

impl DsmcSpec {
    /// The load balance of a run over ranks (`balance`, `balance_every`).
    pub fn balance(&self) -> crate::dsmc::Balance {
        crate::dsmc::Balance {
            mode: self.balance,
            every: self
                .balance_every
                .unwrap_or(crate::dsmc::Balance::default().every),
        }
    }
}

/// `[crater]`: the crater size is the number of grains of `species` whose final position
/// lies farther than `displacement` from their initial position.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CraterSpec {
    /// Species forming the bed.
    pub species: String,
    /// Displacement threshold (length units), e.g. one bed-grain diameter.
    pub displacement: f64,
}

/// `[sweep]`: run the scenario at every point of a parameter scan, each point with
/// `seeds` seeds. One key (`key` + `values`) or several (`[[sweep.vary]]`, combined as
/// every combination, `mode = "grid"`, or element by element, `mode = "zip"`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// Dotted scenario key to vary (the one-key form), e.g.
    /// `species[0].velocity.velocity` or `collisions.restitution`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub key: Option<String>,
    /// Values of `key` (TOML values: numbers, arrays, ...).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub values: Vec<toml::Value>,
    /// Several keys, each with its values (instead of `key` and `values`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vary: Vec<SweepAxis>,
    /// How the keys' values combine: `"grid"` (every combination) or `"zip"`.
    #[serde(default)]
    pub mode: SweepMode,
    /// Seeds per point (ensemble size).
    #[serde(default = "four")]
    pub seeds: usize,
    /// Observable plotted against the value (a key of `summary.json`'s `final`, or
    /// `crater_size`).
    #[serde(default = "kinetic")]
    pub observable: String,
}

/// One swept key of `[[sweep.vary]]` and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepAxis {
    /// Dotted scenario key, as `--set` takes it.
    pub key: String,
    /// Its values (TOML values).
    pub values: Vec<toml::Value>,
}

/// How the values of several swept keys combine into points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SweepMode {
    /// Every combination (outer product; the first key varies slowest).
    #[default]
    Grid,
    /// The `i`-th values of every key together (all lists of one length).
    Zip,
}

fn four() -> usize {
    4
}
fn kinetic() -> String {
    "kinetic_energy".into()
}

fn two() -> usize {
    2
}
fn one() -> u64 {
    1
}

/// `[box]`: an axis-aligned box `[0, L_0] x ...`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Edge lengths, one per axis (length units). Default: the unit square/cube.
    #[serde(default)]
    pub lengths: Vec<f64>,
    /// `"wall"` or `"periodic"` for all axes, or a list with one entry per axis.
    #[serde(default = "default_boundary")]
    pub boundary: BoundarySpec,
}

fn default_boundary() -> BoundarySpec {
    BoundarySpec::All(crate::boundary::AxisKind::Wall)
}

impl Default for BoxSpec {
    fn default() -> Self {
        Self {
            lengths: Vec::new(),
            boundary: default_boundary(),
        }
    }
}

impl BoxSpec {
    /// Whether this is the default box (left out of the resolved scenario then).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// Boundary kinds: one for all axes or one per axis (read by a hand-written reader that
/// names the accepted values).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum BoundarySpec {
    /// The same on every axis.
    All(crate::boundary::AxisKind),
    /// One per axis.
    PerAxis(Vec<crate::boundary::AxisKind>),
}

/// `[[species]]`: a group of identical grains.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeciesSpec {
    /// Name used in outputs (`temperature.<name>`).
    pub name: String,
    /// Number of grains.
    pub count: usize,
    /// Radius (length units). Give either `radius` or `packing_fraction`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Packing fraction of this species in its region; sets the radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub packing_fraction: Option<f64>,
    /// Mass of one grain (mass units).
    #[serde(default = "unit")]
    pub mass: f64,
    /// Region `{ lo = [..], hi = [..] }` where the grains are placed; default: the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<RegionSpec>,
    /// Fixed positions, one `[x, y(, z)]` per grain (instead of a placement).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub positions: Vec<Vec<f64>>,
    /// Initial velocities.
    #[serde(default)]
    pub velocity: VelocitySpec,
}

fn unit() -> f64 {
    1.0
}

/// A box-aligned region.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Lower corner.
    pub lo: Vec<f64>,
    /// Upper corner.
    pub hi: Vec<f64>,
}

/// Initial velocities of a species (read by a hand-written reader: a misspelt key is
/// reported as unknown, with the expected keys).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "distribution", rename_all = "snake_case")]
pub enum VelocitySpec {
    /// All grains at rest.
    Zero,
    /// Speed `speed` in a uniformly random direction (Problem 1 of the hard-disk assignment).
    FixedSpeed {
        /// The common speed (length/time).
        speed: f64,
    },
    /// Maxwell-Boltzmann at `temperature` (energy units, `k_B = 1`).
    MaxwellBoltzmann {
        /// Temperature.
        temperature: f64,
    },
    /// The same given velocity for every grain of the species (e.g. a projectile).
    Given {
        /// Velocity vector.
        velocity: Vec<f64>,
    },
    /// One velocity per grain.
    PerGrain {
        /// Velocity vectors, one per grain.
        velocities: Vec<Vec<f64>>,
    },
}

impl Default for VelocitySpec {
    fn default() -> Self {
        VelocitySpec::MaxwellBoltzmann { temperature: 1.0 }
    }
}

/// How grains are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Random sequential placement without overlaps.
    Random,
    /// Square (cubic) lattice filling the region.
    Lattice,
}

/// `[initial]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// `"random"` or `"lattice"`.
    #[serde(default = "random_placement")]
    pub placement: Placement,
    /// If set, grains are first placed at this (lower) packing fraction and then grown to
    /// their radii with the event engine (Lubachevsky-Stillinger compression); needed for
    /// random dense states (2D above ~0.45, 3D above ~0.3). Periodic boxes, one species.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compress_from: Option<f64>,
    /// Subtract the centre-of-mass velocity.
    #[serde(default)]
    pub zero_momentum: bool,
    /// Random placement attempts per grain before giving up.
    #[serde(default = "attempts")]
    pub max_attempts: usize,
}

fn random_placement() -> Placement {
    Placement::Random
}
fn attempts() -> usize {
    100_000
}

impl Default for InitialSpec {
    fn default() -> Self {
        Self {
            placement: Placement::Random,
            compress_from: None,
            zero_momentum: false,
            max_attempts: attempts(),
        }
    }
}

/// `[collisions]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CollisionSpec {
    /// Grain-grain normal restitution ξ in [0, 1] (HD-11).
    #[serde(default = "unit")]
    pub restitution: f64,
    /// Wall normal restitution in [0, 1] (HD-3, HD-4); default: `restitution`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_restitution: Option<f64>,
    /// Factor on the wall-tangential velocity; default: the wall restitution, as in
    /// HD-3 and HD-4. Use 1 for smooth walls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_tangential_restitution: Option<f64>,
    /// TC-model contact duration t_c (time units); 0 disables it.
    #[serde(default)]
    pub contact_duration: f64,
}

impl Default for CollisionSpec {
    fn default() -> Self {
        Self {
            restitution: 1.0,
            wall_restitution: None,
            wall_tangential_restitution: None,
            contact_duration: 0.0,
        }
    }
}

impl CollisionSpec {
    /// The collision law with defaults resolved.
    pub fn law(&self) -> crate::collision_law::CollisionLaw {
        let wall = self.wall_restitution.unwrap_or(self.restitution);
        crate::collision_law::CollisionLaw {
            restitution: self.restitution,
            wall_restitution: wall,
            wall_tangential_restitution: self.wall_tangential_restitution.unwrap_or(wall),
            contact_duration: self.contact_duration,
            ..Default::default()
        }
    }
}

/// `[stop]`: the run ends when the first of these is met (checked at output times, except
/// `events` and `wall_seconds`, which are checked continuously).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Simulation time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// Pair collisions per grain (2 x collisions / N).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collisions_per_particle: Option<f64>,
    /// Number of events.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub events: Option<u64>,
    /// Number of collisions (pair collisions; intruder-bath collisions for the intruder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collisions: Option<u64>,
    /// Fraction of the initial kinetic energy remaining (e.g. 0.1 for the crater).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub energy_fraction: Option<f64>,
    /// Wall-clock seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_seconds: Option<f64>,
}

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

/// `[edmd]`: options of the event-driven engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdmdSpec {
    /// Inelastic-collapse threshold (see `EdmdOptions::collapse_ratio`).
    #[serde(default = "collapse")]
    pub collapse_ratio: f64,
    /// Bins of the impact-parameter histogram.
    #[serde(default = "impact_bins")]
    pub impact_bins: usize,
}

fn collapse() -> f64 {
    1e-6
}
fn impact_bins() -> usize {
    20
}

impl Default for EdmdSpec {
    fn default() -> Self {
        Self {
            collapse_ratio: collapse(),
            impact_bins: impact_bins(),
        }
    }
}

/// A scenario error: which key, what value, what to do, and where in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenarioError {
    /// Dotted key, e.g. `collisions.restitution` or `species[1].radius`.
    pub key: String,
    /// What is wrong and how to fix it.
    pub message: String,
    /// 1-based line in the scenario file, when known.
    pub line: Option<usize>,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // A key-less error (a TOML syntax error) names no key.
        let key = if self.key.is_empty() {
            String::new()
        } else {
            format!("`{}`: ", self.key)
        };
        match self.line {
            Some(l) => write!(f, "line {l}: {key}{}", self.message),
            None => write!(f, "{key}{}", self.message),
        }
    }
}

impl std::error::Error for ScenarioError {}

impl ScenarioError {
    fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            message: message.into(),
            line: None,
        }
    }

    /// Adds the line of the key in `source` when it is not known yet.
    fn at(mut self, source: &str) -> Self {
        if self.line.is_none() {
            self.line = locate(source, &self.key);
        }
        self
    }
}

impl Scenario {
    /// Parses a scenario from TOML text, applies `--set KEY=VALUE` overrides and validates.
    ///
    /// Errors carry the key (from the parser's span of the value or key at fault), the
    /// line in `source` when the key is written there, and the fix.
    pub fn from_toml(source: &str, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        Self::load(source, overrides, true)
    }

    /// [`Scenario::from_toml`] without the cost limits ([`Cost::check_limits`]: outputs,
    /// collisions and bytes), what `--insist` asks for. Every other check stays.
    pub fn from_toml_insisting(
        source: &str,
        overrides: &[String],
    ) -> Result<Scenario, ScenarioError> {
        Self::load(source, overrides, false)
    }

    /// Parses, applies the overrides and validates; with `limits`, also the cost limits,
    /// of the scenario and of every point of its sweep.
    fn load(source: &str, overrides: &[String], limits: bool) -> Result<Scenario, ScenarioError> {
        let scenario = Self::parse(source, overrides)?;
        scenario.validate().map_err(|e| e.at(source))?;
        if limits {
            scenario.cost().check_limits().map_err(|e| e.at(source))?;
        }
        if let Some(sw) = &scenario.sweep {
            sweep::check_members(source, overrides, sw, limits)?;
        }
        Ok(scenario)
    }

    /// The pre-flight estimate of what the run will cost (outputs, snapshots, bytes,
    /// collisions, events or time steps); see `docs/scenario.md`, "Limits".
    pub fn cost(&self) -> Cost {
        preflight::cost(self)
    }

    /// Reads a resolved scenario written by an earlier version (checkpoints, run
    /// directories): tables that do not apply to its engine, which older versions wrote
    /// with their defaults, are dropped before [`Scenario::from_toml`]'s checks. The cost
    /// limits are not checked again (the run was accepted when it started, perhaps with
    /// `--insist`).
    pub fn from_resolved_toml(source: &str) -> Result<Scenario, ScenarioError> {
        let mut table: toml::Table =
            toml::from_str(source).map_err(|e| spans::parse_error(source, source, &e))?;
        if let Some(engine) = table
            .get("engine")
            .and_then(|v| EngineKind::deserialize(v.clone()).ok())
        {
            tables::strip(&mut table, engine);
        }
        Self::from_toml_insisting(&toml::to_string(&table).unwrap_or_default(), &[])
    }

    /// Parses and applies the overrides, without validating the values.
    fn parse(source: &str, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        let mut table: toml::Table =
            toml::from_str(source).map_err(|e| spans::parse_error(source, source, &e))?;
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        tables::check_table(&table).map_err(|e| e.at(source))?;
        match Scenario::deserialize(table.clone()) {
            Ok(s) => Ok(s),
            Err(_) if overrides.is_empty() => Err(match toml::from_str::<Scenario>(source) {
                Err(e) => spans::parse_error(source, source, &e),
                Ok(_) => ScenarioError::new("", "the scenario could not be read"),
            }),
            Err(plain) => {
                // Locate the error in the overridden text, then in the file.
                let text = toml::to_string(&table).unwrap_or_default();
                let mut e = match toml::from_str::<Scenario>(&text) {
                    Err(e) => spans::parse_error(source, &text, &e),
                    Ok(_) => ScenarioError::new("--set", plain.message().to_string()),
                };
                if let Some(o) = overrides.iter().rev().find(|o| overridden(o, &e.key)) {
                    e.message = format!("{} (set by --set {o})", e.message);
                    e.line = None;
                }
                Err(e)
            }
        }
    }

    /// The resolved scenario as TOML (defaults filled in; only the tables its engine
    /// reads).
    pub fn to_toml(&self) -> String {
        let grains = self.engine != EngineKind::Intruder;
        let view = Resolved {
            engine: self.engine,
            dimension: self.dimension,
            seed: self.seed,
            description: &self.description,
            simulation_box: (grains && !self.simulation_box.is_default())
                .then_some(&self.simulation_box),
            species: if grains { &self.species } else { &[] },
            initial: grains.then_some(&self.initial),
            collisions: grains.then_some(&self.collisions),
            gravity: if grains { &self.gravity } else { &[] },
            stop: &self.stop,
            output: &self.output,
            edmd: (self.engine == EngineKind::Edmd).then_some(&self.edmd),
            dsmc: (self.engine == EngineKind::Dsmc).then_some(&self.dsmc),
            intruder: self.intruder.as_ref(),
            crater: self.crater.as_ref().filter(|_| grains),
            sweep: self.sweep.as_ref(),
            driving: self.driving.as_ref(),
        };
        toml::to_string_pretty(&view)
            .unwrap_or_else(|e| format!("# could not serialise the scenario: {e}\n"))
    }

    /// Box edge lengths (default: unit).
    pub fn lengths(&self) -> Vec<f64> {
        if self.simulation_box.lengths.is_empty() {
            vec![1.0; self.dimension]
        } else {
            self.simulation_box.lengths.clone()
        }
    }

    /// Boundary kind per axis.
    pub fn axes(&self) -> Vec<crate::boundary::AxisKind> {
        match &self.simulation_box.boundary {
            BoundarySpec::All(k) => vec![*k; self.dimension],
            BoundarySpec::PerAxis(v) => v.clone(),
        }
    }

    /// Radius of species `s` (from `radius` or `packing_fraction`).
    pub fn radius(&self, s: usize) -> f64 {
        let sp = &self.species[s];
        if let Some(r) = sp.radius {
            return r;
        }
        let phi = sp.packing_fraction.unwrap_or(0.0);
        let volume: f64 = match &sp.region {
            Some(r) => r.lo.iter().zip(&r.hi).map(|(a, b)| b - a).product(),
            None => self.lengths().iter().product(),
        };
        let unit_ball = match self.dimension {
            2 => std::f64::consts::PI,
            _ => 4.0 / 3.0 * std::f64::consts::PI,
        };
        (phi * volume / (sp.count.max(1) as f64 * unit_ball)).powf(1.0 / self.dimension as f64)
    }

    /// Total number of grains.
    pub fn particle_count(&self) -> usize {
        self.species.iter().map(|s| s.count).sum()
    }

    /// Checks every value, table by table, then the pre-flight rules (the stop rule can
    /// be reached, the outputs, collisions and memory are within the documented limits);
    /// the error names the key, the value and the fix.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        tables::check_fields(self)?;
        if self.engine == EngineKind::Intruder {
            intruder::validate(self)?;
        } else {
            validate::dimension(self)?;
            validate::simulation_box(self)?;
            validate::collisions(self)?;
            validate::gravity(self)?;
            species::validate(self)?;
            validate::initial(self)?;
            validate::dsmc(self)?;
            validate::edmd(self)?;
            validate::crater(self)?;
            driving::validate(self)?;
        }
        validate::stop(self)?;
        validate::output(self)?;
        if let Some(sw) = &self.sweep {
            sw.validate(self)?;
        }
        preflight::check(self)
    }
}
