//! The scenario format: one TOML file describes a run for any engine. Shared tables
//! (`[box]`, `[[species]]`, `[initial]`, `[collisions]`, `[stop]`, `[output]`) come first;
//! each engine owns its own table (`[edmd]`, ...). Every field is documented in
//! `docs/scenario.md`; unknown keys are errors.
//!
//! Loading goes: file text → `toml::Table` → `--set` overrides applied to the table →
//! typed [`Scenario`] (serde, unknown keys rejected) → [`Scenario::validate`]. Every error
//! names the key, the value, the line when it comes from the file, and the fix.

mod intruder;
mod observables;
mod overrides;

pub use intruder::IntruderSpec;
pub use overrides::apply_override;

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
    #[serde(default = "one")]
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
    /// Crater measure (Problem 4 of the hard-disk seed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crater: Option<CraterSpec>,
    /// Parameter scan run by `granular sweep`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSpec>,
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

/// `[sweep]`: run the scenario for each value of `key`, each with `seeds` seeds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// Dotted scenario key to vary, e.g. `species[0].velocity.velocity` or
    /// `collisions.restitution`.
    pub key: String,
    /// Values of the key (TOML values: numbers, arrays, ...).
    pub values: Vec<toml::Value>,
    /// Seeds per value (ensemble size).
    #[serde(default = "four")]
    pub seeds: usize,
    /// Observable plotted against the value (a key of `summary.json`'s `final`, or
    /// `crater_size`).
    #[serde(default = "kinetic")]
    pub observable: String,
}

impl SweepSpec {
    /// Checks that the sweep has values and seeds.
    pub(crate) fn validate(&self) -> Result<(), ScenarioError> {
        if self.values.is_empty() {
            return Err(ScenarioError::new(
                "sweep.values",
                "is empty; list the values to scan",
            ));
        }
        if self.seeds == 0 {
            return Err(ScenarioError::new(
                "sweep.seeds",
                "is 0; use at least 1 seed per value",
            ));
        }
        Ok(())
    }
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

/// Boundary kinds: one for all axes or one per axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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

/// Initial velocities of a species.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
pub enum VelocitySpec {
    /// All grains at rest.
    Zero,
    /// Speed `speed` in a uniformly random direction (Problem 1 of the hard-disk seed).
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
    /// Collisions per grain between two pooled samples of the equilibrium histogram
    /// (appendix C.2 of the seed: many collisions apart so samples are independent).
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
            histogram_sample_spacing: sample_spacing(),
            checkpoint_seconds: checkpoint(),
            impact_histograms: false,
            structure_factor: false,
            structure_factor_max_index: sk_max_index(),
            density_map: Vec::new(),
            observable_times: Vec::new(),
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
        match self.line {
            Some(l) => write!(f, "line {l}: `{}`: {}", self.key, self.message),
            None => write!(f, "`{}`: {}", self.key, self.message),
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
}

/// Finds the line of `key` (dotted, with `[i]` for arrays of tables) in TOML `source`.
pub fn locate(source: &str, key: &str) -> Option<usize> {
    // Split "species[1].velocity.speed" into table path and leaf.
    let parts: Vec<&str> = key.split('.').collect();
    let (leaf, tables) = parts.split_last()?;
    let leaf = leaf.split('[').next().unwrap_or(leaf);
    let mut section = String::new();
    let mut occurrence: Vec<(String, usize)> = Vec::new();
    let wanted: Vec<(String, Option<usize>)> = tables
        .iter()
        .map(|t| {
            let name = t.split('[').next().unwrap_or(t).to_string();
            let idx = t
                .split('[')
                .nth(1)
                .and_then(|s| s.trim_end_matches(']').parse().ok());
            (name, idx)
        })
        .collect();
    let wanted_header: String = wanted
        .iter()
        .map(|w| w.0.clone())
        .collect::<Vec<_>>()
        .join(".");
    let wanted_index = wanted.iter().find_map(|w| w.1).unwrap_or(0);
    let mut index_in_section = 0usize;
    let mut fallback = None;
    for (n, raw) in source.lines().enumerate() {
        let line = raw.trim();
        if line.starts_with('[') {
            let name = line
                .trim_matches(|c| c == '[' || c == ']')
                .trim()
                .to_string();
            let count = occurrence.iter_mut().find(|o| o.0 == name);
            index_in_section = match count {
                Some(o) => {
                    o.1 += 1;
                    o.1
                }
                None => {
                    occurrence.push((name.clone(), 0));
                    0
                }
            };
            section = name;
            if section == wanted_header && index_in_section == wanted_index && fallback.is_none() {
                fallback = Some(n + 1);
            }
            continue;
        }
        let in_section = section == wanted_header && index_in_section == wanted_index;
        let (k, _) = match line.split_once('=') {
            Some(kv) => kv,
            None => continue,
        };
        let k = k.trim();
        if in_section && k == leaf {
            return Some(n + 1);
        }
        // Dotted or inline forms: `velocity = { distribution = ... }` or `box.lengths = ...`.
        if in_section && line.contains(leaf) && tables.len() > wanted.len().saturating_sub(1) {
            fallback = fallback.or(Some(n + 1));
        }
        if section.is_empty() && (k == key || (wanted_header.is_empty() && k == leaf)) {
            return Some(n + 1);
        }
    }
    fallback
}

impl Scenario {
    /// Parses a scenario from TOML text, applies `--set KEY=VALUE` overrides and validates.
    pub fn from_toml(source: &str, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        // First pass on the text alone, so that type errors and unknown keys get a line.
        let mut table: toml::Table = toml::from_str(source).map_err(|e| toml_error(source, &e))?;
        if let Err(e) = toml::from_str::<Scenario>(source) {
            return Err(toml_error(source, &e));
        }
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        let scenario: Scenario = Scenario::deserialize(table).map_err(|e| {
            ScenarioError::new("--set", format!("after the overrides: {}", e.message()))
        })?;
        scenario.validate().map_err(|mut e| {
            e.line = locate(source, &e.key);
            e
        })?;
        Ok(scenario)
    }

    /// The resolved scenario as TOML (defaults filled in).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self)
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

    /// Checks every value; the error names the key, the value and the fix.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        if self.engine == EngineKind::Intruder {
            return intruder::validate(self);
        }
        intruder::check_unused(self)?;
        let d = self.dimension;
        if d != 2 && d != 3 {
            return Err(ScenarioError::new(
                "dimension",
                format!("is {d}; use 2 (disks) or 3 (spheres)"),
            ));
        }
        let lengths = self.lengths();
        if lengths.len() != d {
            return Err(ScenarioError::new(
                "box.lengths",
                format!(
                    "has {} entries for dimension {d}; give one length per axis",
                    lengths.len()
                ),
            ));
        }
        for (k, &l) in lengths.iter().enumerate() {
            if !(l > 0.0 && l.is_finite()) {
                return Err(ScenarioError::new(
                    "box.lengths".to_string(),
                    format!("entry {k} is {l}; lengths must be positive"),
                ));
            }
        }
        if self.axes().len() != d {
            return Err(ScenarioError::new(
                "box.boundary",
                format!(
                    "lists {} axes for dimension {d}; give one per axis or a single \"wall\"/\"periodic\"",
                    self.axes().len()
                ),
            ));
        }
        if self.species.is_empty() {
            return Err(ScenarioError::new(
                "species",
                "no [[species]] table; add at least one with name, count and radius",
            ));
        }
        let unit_interval = |key: &str, v: f64| {
            if (0.0..=1.0).contains(&v) {
                Ok(())
            } else {
                Err(ScenarioError::new(
                    key,
                    format!(
                        "is {v}; a restitution coefficient must lie in [0, 1] (1 = elastic, 0 = perfectly inelastic)"
                    ),
                ))
            }
        };
        unit_interval("collisions.restitution", self.collisions.restitution)?;
        if let Some(w) = self.collisions.wall_restitution {
            unit_interval("collisions.wall_restitution", w)?;
        }
        if let Some(w) = self.collisions.wall_tangential_restitution {
            unit_interval("collisions.wall_tangential_restitution", w)?;
        }
        if self.collisions.contact_duration.is_nan() || self.collisions.contact_duration < 0.0 {
            return Err(ScenarioError::new(
                "collisions.contact_duration",
                format!(
                    "is {}; t_c must be >= 0 (0 disables the TC model)",
                    self.collisions.contact_duration
                ),
            ));
        }
        if !self.gravity.is_empty() && self.gravity.len() != d {
            return Err(ScenarioError::new(
                "gravity",
                format!(
                    "has {} components; give {d} (one per axis) or leave it out",
                    self.gravity.len()
                ),
            ));
        }
        let mut names = std::collections::HashSet::new();
        for (s, sp) in self.species.iter().enumerate() {
            let key = |f: &str| format!("species[{s}].{f}");
            if !names.insert(sp.name.clone()) {
                return Err(ScenarioError::new(
                    key("name"),
                    format!(
                        "\"{}\" is used twice; give each species its own name",
                        sp.name
                    ),
                ));
            }
            if sp.count == 0 {
                return Err(ScenarioError::new(
                    key("count"),
                    "is 0; a species needs at least one grain",
                ));
            }
            match (sp.radius, sp.packing_fraction) {
                (Some(_), Some(_)) => {
                    return Err(ScenarioError::new(
                        key("radius"),
                        "and packing_fraction are both given; keep one",
                    ));
                }
                (None, None) => {
                    return Err(ScenarioError::new(
                        key("radius"),
                        "is missing; give radius or packing_fraction",
                    ));
                }
                (Some(r), None) if !(r > 0.0 && r.is_finite()) => {
                    return Err(ScenarioError::new(
                        key("radius"),
                        format!("is {r}; a radius must be positive"),
                    ));
                }
                (None, Some(p)) if !(p > 0.0 && p < 1.0) => {
                    return Err(ScenarioError::new(
                        key("packing_fraction"),
                        format!("is {p}; it must lie in (0, 1)"),
                    ));
                }
                _ => {}
            }
            if !(sp.mass > 0.0 && sp.mass.is_finite()) {
                return Err(ScenarioError::new(
                    key("mass"),
                    format!("is {}; a mass must be positive", sp.mass),
                ));
            }
            let r = self.radius(s);
            for (k, &l) in lengths.iter().enumerate() {
                if 2.0 * r > l {
                    return Err(ScenarioError::new(
                        key("radius"),
                        format!(
                            "is {r}: the grain does not fit in the box (axis {k} is {l} long); make it smaller than {}",
                            l / 2.0
                        ),
                    ));
                }
            }
            if let Some(region) = &sp.region {
                if region.lo.len() != d || region.hi.len() != d {
                    return Err(ScenarioError::new(
                        key("region"),
                        format!("needs lo and hi with {d} entries each"),
                    ));
                }
                #[allow(clippy::needless_range_loop)]
                for k in 0..d {
                    if !(region.lo[k] >= 0.0
                        && region.hi[k] <= lengths[k]
                        && region.hi[k] > region.lo[k])
                    {
                        return Err(ScenarioError::new(
                            key("region"),
                            format!(
                                "axis {k}: [{}, {}] must satisfy 0 <= lo < hi <= {}",
                                region.lo[k], region.hi[k], lengths[k]
                            ),
                        ));
                    }
                }
            }
            if !sp.positions.is_empty() {
                if sp.positions.len() != sp.count {
                    return Err(ScenarioError::new(
                        key("positions"),
                        format!(
                            "lists {} positions for count = {}; give one per grain",
                            sp.positions.len(),
                            sp.count
                        ),
                    ));
                }
                for (i, p) in sp.positions.iter().enumerate() {
                    if p.len() != d {
                        return Err(ScenarioError::new(
                            key("positions"),
                            format!("position {i} has {} components; give {d}", p.len()),
                        ));
                    }
                    for k in 0..d {
                        let walled = self.axes()[k] == crate::boundary::AxisKind::Wall;
                        if !(p[k] >= 0.0 && p[k] <= lengths[k])
                            || (walled && (p[k] < r || p[k] > lengths[k] - r))
                        {
                            return Err(ScenarioError::new(
                                key("positions"),
                                format!(
                                    "position {i} = {p:?} puts the grain (radius {r}) outside the box or into a wall along axis {k}"
                                ),
                            ));
                        }
                    }
                }
            }
            match &sp.velocity {
                VelocitySpec::FixedSpeed { speed } if speed.is_nan() || *speed < 0.0 => {
                    return Err(ScenarioError::new(
                        key("velocity.speed"),
                        format!("is {speed}; a speed must be >= 0"),
                    ));
                }
                VelocitySpec::MaxwellBoltzmann { temperature }
                    if temperature.is_nan() || *temperature < 0.0 =>
                {
                    return Err(ScenarioError::new(
                        key("velocity.temperature"),
                        format!("is {temperature}; a temperature must be >= 0"),
                    ));
                }
                VelocitySpec::Given { velocity } if velocity.len() != d => {
                    return Err(ScenarioError::new(
                        key("velocity.velocity"),
                        format!("has {} components; give {d}", velocity.len()),
                    ));
                }
                VelocitySpec::PerGrain { velocities }
                    if velocities.len() != sp.count || velocities.iter().any(|v| v.len() != d) =>
                {
                    return Err(ScenarioError::new(
                        key("velocity.velocities"),
                        format!("needs {} vectors of {d} components", sp.count),
                    ));
                }
                _ => {}
            }
        }
        if let Some(p) = self.initial.compress_from
            && !(p > 0.0 && p < 1.0)
        {
            return Err(ScenarioError::new(
                "initial.compress_from",
                format!(
                    "is {p}; give the packing fraction to start the compression from, in (0, 1)"
                ),
            ));
        }
        let stop = &self.stop;
        if stop.time.is_none()
            && stop.collisions.is_none()
            && stop.collisions_per_particle.is_none()
            && stop.events.is_none()
            && stop.energy_fraction.is_none()
            && stop.wall_seconds.is_none()
        {
            return Err(ScenarioError::new(
                "stop",
                "has no rule; set at least one of time, collisions, collisions_per_particle, events, energy_fraction, wall_seconds",
            ));
        }
        if let Some(f) = stop.energy_fraction
            && !(f > 0.0 && f < 1.0)
        {
            return Err(ScenarioError::new(
                "stop.energy_fraction",
                format!(
                    "is {f}; give the fraction of the initial energy at which to stop, in (0, 1)"
                ),
            ));
        }
        if self.output.interval.is_nan() || self.output.interval <= 0.0 {
            return Err(ScenarioError::new(
                "output.interval",
                format!("is {}; it must be positive", self.output.interval),
            ));
        }
        if self.engine == EngineKind::Dsmc {
            if self.species.len() != 1 {
                return Err(ScenarioError::new(
                    "species",
                    format!(
                        "has {} species; the DSMC engine takes one species of equal grains",
                        self.species.len()
                    ),
                ));
            }
            if let Some(t) = self.dsmc.time_step
                && (t.is_nan() || t <= 0.0)
            {
                return Err(ScenarioError::new(
                    "dsmc.time_step",
                    format!("is {t}; give a positive time step (well below the mean free time)"),
                ));
            }
            if let Some(l) = self.dsmc.cell_size
                && (l.is_nan() || l <= 0.0)
            {
                return Err(ScenarioError::new(
                    "dsmc.cell_size",
                    format!("is {l}; give a positive cell edge (below the mean free path)"),
                ));
            }
        }
        if let Some(c) = &self.crater {
            if !self.species.iter().any(|s| s.name == c.species) {
                return Err(ScenarioError::new(
                    "crater.species",
                    format!(
                        "\"{}\" is not a species of this scenario; use one of the [[species]] names",
                        c.species
                    ),
                ));
            }
            if c.displacement.is_nan() || c.displacement <= 0.0 {
                return Err(ScenarioError::new(
                    "crater.displacement",
                    format!("is {}; give a positive distance", c.displacement),
                ));
            }
        }
        if let Some(sw) = &self.sweep {
            sw.validate()?;
        }
        self.output.validate_observables(self.dimension)?;
        if self.output.histogram_bins == 0 {
            return Err(ScenarioError::new(
                "output.histogram_bins",
                "is 0; use at least 1",
            ));
        }
        Ok(())
    }
}

/// Converts a TOML/serde error into a scenario error with its line.
fn toml_error(source: &str, e: &toml::de::Error) -> ScenarioError {
    let line = e
        .span()
        .map(|s| source[..s.start.min(source.len())].matches('\n').count() + 1);
    let message = e.message().to_string();
    let key = message
        .split('`')
        .nth(1)
        .map(str::to_string)
        .unwrap_or_else(|| "scenario".to_string());
    let fix = if message.contains("unknown field") {
        " (check the spelling; docs/scenario.md lists every key)"
    } else if message.contains("missing field") {
        " (add it; docs/scenario.md describes it)"
    } else {
        ""
    };
    ScenarioError {
        key,
        message: format!("{message}{fix}"),
        line,
    }
}
