//! The scenario format: one TOML file describes a run for any engine. Shared tables
//! (`[box]`, `[[species]]`, `[initial]`, `[collisions]`, `[stop]`, `[output]`) come first;
//! each engine owns its own table (`[edmd]`, ...). Every field is documented in
//! `docs/scenario.md`; unknown keys are errors.
//!
//! Loading goes: file text → `toml::Table` → `--set` overrides applied to the table →
//! typed [`Scenario`] (serde, unknown keys rejected) → `Scenario::validate`. Every error
//! names the key, the value, the line when it comes from the file, and the fix.

pub(crate) mod advice;
mod de;
mod driving;
mod file;
mod grain_tables;
mod grain_vectors;
mod input;
mod intruder;
mod layout;
mod observables;
mod output;
mod overrides;
mod preflight;
mod resolve;
mod rough;
mod schedule;
mod spans;
mod species;
mod sweep;
mod validate;

use crate::dsmc::config::DsmcConfig;
pub use de::seed::HELP as SEED_HELP;
pub use driving::{DrivingKind, DrivingSpec};
pub use file::{file_overrides, read_text_file};
pub use grain_tables::{
    BoundarySpec, BoxSpec, CollisionSpec, InitialSpec, Placement, RegionSpec, SpeciesSpec,
    VelocitySpec,
};
pub use grain_vectors::{GrainVectors, VectorSource};
pub use input::{ScenarioInput, array_key};
pub use intruder::{
    BallMethodKey, BallTable, BathTable, DsmcTwinTable, IntruderSpec, NeedleTable, OneDTable,
    bath_file,
};
pub use output::{OutputSpacing, OutputSpec};
pub(crate) use overrides::apply_override;
pub(crate) use preflight::available_memory;
pub use preflight::{Cost, MAX_OUTPUTS};
pub use resolve::{
    Cooling, DrivingResolved, DsmcResolved, Grains, Resolved, RoughResolved, SpeciesResolved,
};
pub use rough::AngularVelocitySpec;
pub use schedule::ScheduledChange;
pub(crate) use schedule::changed;
pub use spans::locate;
pub(crate) use sweep::sweep_member;
pub use sweep::sweep_observables;
#[cfg(test)]
pub(crate) use validate::MAGNITUDE;

/// Whether `--set` assignment `o` (`KEY=VALUE`) set `key`, a table above it or a key below
/// it (`species.0.mass` and `species[0].mass` are the same key).
pub fn overridden(o: &str, key: &str) -> bool {
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
use std::path::Path;

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

/// A whole scenario: the part every engine reads (`dimension`, `seed`, `description`,
/// `[stop]`, `[output]`, `[sweep]`) and exactly one engine's part ([`EngineSpec`]), so that
/// a table that does not apply to the engine cannot exist once parsed. The file's flat
/// layout (`engine = "..."` beside the tables) is read and written by `scenario/layout.rs`,
/// the one place that knows which table belongs to which engine.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Spatial dimension: 2 (disks) or 3 (spheres).
    pub dimension: usize,
    /// Seed of all random streams; `granular run --seed` overrides it.
    pub seed: u64,
    /// Optional one-line description.
    pub description: String,
    /// When the run stops (the first rule met ends it).
    pub stop: StopSpec,
    /// What is written and how often.
    pub output: OutputSpec,
    /// Parameter scan run by `granular sweep`.
    pub sweep: Option<SweepSpec>,
    /// The engine (`engine = "edmd"`, `"dsmc"` or `"intruder"`) and the tables it reads.
    pub engine: EngineSpec,
}

/// The engine of a scenario and the tables only it reads.
#[derive(Clone, Debug, PartialEq)]
pub enum EngineSpec {
    /// Event-driven molecular dynamics: the grains and `[edmd]`.
    Edmd {
        /// The grains, their box and collision law.
        grains: GrainsSpec,
        /// `[edmd]`.
        edmd: EdmdSpec,
    },
    /// Direct Simulation Monte Carlo: the grains and `[dsmc]`.
    Dsmc {
        /// The grains, their box and collision law.
        grains: GrainsSpec,
        /// `[dsmc]`.
        dsmc: DsmcSpec,
    },
    /// The Gillespie intruder in a thermal bath: `[intruder]`.
    Intruder(IntruderSpec),
}

impl EngineSpec {
    /// Which engine.
    pub(crate) fn kind(&self) -> EngineKind {
        match self {
            EngineSpec::Edmd { .. } => EngineKind::Edmd,
            EngineSpec::Dsmc { .. } => EngineKind::Dsmc,
            EngineSpec::Intruder(_) => EngineKind::Intruder,
        }
    }
}

/// The tables of the many-grain engines (`edmd`, `dsmc`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GrainsSpec {
    /// `[box]`: the simulation box.
    pub simulation_box: BoxSpec,
    /// `[[species]]`: grain species (at least one).
    pub species: Vec<SpeciesSpec>,
    /// `[initial]`: how the initial state is built.
    pub initial: InitialSpec,
    /// `[collisions]`: the collision law.
    pub collisions: CollisionSpec,
    /// Uniform acceleration (gravity), one component per axis, length/time².
    pub gravity: Vec<f64>,
    /// `[crater]`: crater measure (Problem 4 of the hard-disk document).
    pub crater: Option<CraterSpec>,
    /// `[driving]`: a steady state of the gas (velocity rescaling or white noise).
    pub driving: Option<DrivingSpec>,
    /// `[[schedule]]`: parameters changed at given times, in time order.
    pub schedule: Vec<ScheduledChange>,
}

/// The grains' tables of an intruder scenario: none (every list empty, every table at its
/// default), so that code asking for them needs no engine test.
static NO_GRAINS: std::sync::LazyLock<GrainsSpec> = std::sync::LazyLock::new(GrainsSpec::default);

impl Scenario {
    /// Which engine runs the scenario.
    pub fn kind(&self) -> EngineKind {
        self.engine.kind()
    }

    /// The grains' tables (`None` for the intruder engine).
    pub(crate) fn grains(&self) -> Option<&GrainsSpec> {
        match &self.engine {
            EngineSpec::Edmd { grains, .. } | EngineSpec::Dsmc { grains, .. } => Some(grains),
            EngineSpec::Intruder(_) => None,
        }
    }

    /// The grains' tables, to change (`None` for the intruder engine).
    pub(crate) fn grains_mut(&mut self) -> Option<&mut GrainsSpec> {
        match &mut self.engine {
            EngineSpec::Edmd { grains, .. } | EngineSpec::Dsmc { grains, .. } => Some(grains),
            EngineSpec::Intruder(_) => None,
        }
    }

    /// The grains' tables, empty for the intruder engine.
    fn grains_or_none(&self) -> &GrainsSpec {
        self.grains().unwrap_or(&NO_GRAINS)
    }

    /// `[edmd]` of an event-driven scenario.
    pub(crate) fn edmd(&self) -> Option<&EdmdSpec> {
        match &self.engine {
            EngineSpec::Edmd { edmd, .. } => Some(edmd),
            _ => None,
        }
    }

    /// `[dsmc]` of a DSMC scenario.
    pub fn dsmc(&self) -> Option<&DsmcSpec> {
        match &self.engine {
            EngineSpec::Dsmc { dsmc, .. } => Some(dsmc),
            _ => None,
        }
    }

    /// `[intruder]` of an intruder scenario.
    pub fn intruder(&self) -> Option<&IntruderSpec> {
        match &self.engine {
            EngineSpec::Intruder(spec) => Some(spec),
            _ => None,
        }
    }

    /// `[[species]]` (empty for the intruder engine).
    pub fn species(&self) -> &[SpeciesSpec] {
        &self.grains_or_none().species
    }

    /// `[box]` (the default box for the intruder engine).
    pub(crate) fn simulation_box(&self) -> &BoxSpec {
        &self.grains_or_none().simulation_box
    }

    /// `[initial]` (its defaults for the intruder engine).
    pub(crate) fn initial(&self) -> &InitialSpec {
        &self.grains_or_none().initial
    }

    /// `[collisions]` (its defaults for the intruder engine).
    pub fn collisions(&self) -> &CollisionSpec {
        &self.grains_or_none().collisions
    }

    /// `gravity` (empty for the intruder engine).
    pub fn gravity(&self) -> &[f64] {
        &self.grains_or_none().gravity
    }

    /// `[crater]`.
    pub(crate) fn crater(&self) -> Option<&CraterSpec> {
        self.grains_or_none().crater.as_ref()
    }

    /// `[driving]`.
    pub fn driving(&self) -> Option<&DrivingSpec> {
        self.grains_or_none().driving.as_ref()
    }
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
    pub(crate) fn balance(&self) -> crate::dsmc::Balance {
        crate::dsmc::Balance {
            mode: self.balance,
            every: self
                .balance_every
                .unwrap_or(crate::dsmc::Balance::default().every),
        }
    }
}

impl DsmcSpec {
    /// The DSMC engine's configuration: this table's choices, the collision law and
    /// gravity of `grains`, and the step and cell size the scenario resolved
    /// (`resolved`; a step left out stays `None`: it follows the mean free time). The one
    /// conversion from the scenario to the engine.
    pub(crate) fn config(&self, grains: &GrainsSpec, resolved: &DsmcResolved) -> DsmcConfig {
        DsmcConfig {
            time_step: self.time_step,
            cell_size: Some(resolved.cell_size),
            // The same collision law as the event-driven engine: pair, wall (normal and
            // tangential) and TC rule.
            law: grains.collisions.law(),
            gravity: grains.gravity.clone(),
            vmax_mode: self.vmax_mode,
            enskog: self.enskog,
            free_volume: self.free_volume,
            density_scope: self.density_scope,
            consistent_boltzmann: self.consistent_boltzmann,
            impact_bins: resolved.impact_bins,
        }
    }

    /// Bins of the impact-parameter histogram: `dsmc.impact_bins`, or the event-driven
    /// engine's default.
    pub(crate) fn impact_bins(&self) -> usize {
        self.impact_bins.unwrap_or_else(impact_bins)
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

impl EdmdSpec {
    /// The event-driven engine's options: this table's, with the gravity of `grains`.
    /// The one conversion from the scenario to the engine.
    pub(crate) fn options(&self, grains: &GrainsSpec) -> crate::edmd::EdmdOptions {
        crate::edmd::EdmdOptions {
            gravity: grains.gravity.clone(),
            collapse_ratio: self.collapse_ratio,
            impact_bins: self.impact_bins,
            ..crate::edmd::EdmdOptions::default()
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
    pub(super) fn at(mut self, source: &str) -> Self {
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
        ScenarioInput {
            text: source,
            overrides,
            limits,
            ..ScenarioInput::default()
        }
        .read()
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
    /// `--insist`). Relative `.npz` paths are read from `base` (the run directory).
    pub fn from_resolved_toml(
        source: &str,
        base: Option<&Path>,
    ) -> Result<Scenario, ScenarioError> {
        let mut table: toml::Table =
            toml::from_str(source).map_err(|e| spans::parse_error(source, source, &e))?;
        if let Some(engine) = table
            .get("engine")
            .and_then(|v| EngineKind::deserialize(v.clone()).ok())
        {
            layout::strip(&mut table, engine);
        }
        ScenarioInput {
            text: &toml::to_string(&table).unwrap_or_default(),
            base,
            ..ScenarioInput::default()
        }
        .read()
    }

    /// Parses and applies the overrides, without validating the values.
    pub(super) fn parse(source: &str, overrides: &[String]) -> Result<Scenario, ScenarioError> {
        let mut table: toml::Table =
            toml::from_str(source).map_err(|e| spans::parse_error(source, source, &e))?;
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        layout::check_table(&table).map_err(|e| e.at(source))?;
        let layout = match layout::Layout::deserialize(table.clone()) {
            Ok(l) => l,
            Err(_) if overrides.is_empty() => {
                return Err(match toml::from_str::<layout::Layout>(source) {
                    Err(e) => spans::parse_error(source, source, &e),
                    Ok(_) => ScenarioError::new("", "the scenario could not be read"),
                });
            }
            Err(plain) => {
                // Locate the error in the overridden text, then in the file.
                let text = toml::to_string(&table).unwrap_or_default();
                let mut e = match toml::from_str::<layout::Layout>(&text) {
                    Err(e) => spans::parse_error(source, &text, &e),
                    Ok(_) => ScenarioError::new("--set", plain.message().to_string()),
                };
                if let Some(o) = overrides.iter().rev().find(|o| overridden(o, &e.key)) {
                    e.message = format!("{} (set by --set {o})", e.message);
                    e.line = None;
                }
                return Err(e);
            }
        };
        layout.into_scenario().map_err(|e| e.at(source))
    }

    /// The resolved scenario as TOML (defaults filled in; only the tables its engine
    /// reads).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(&layout::Layout::of(self))
            .unwrap_or_else(|e| format!("# could not serialise the scenario: {e}\n"))
    }

    /// Box edge lengths (default: unit).
    pub fn lengths(&self) -> Vec<f64> {
        if self.simulation_box().lengths.is_empty() {
            vec![1.0; self.dimension]
        } else {
            self.simulation_box().lengths.clone()
        }
    }

    /// Boundary kind per axis.
    pub fn axes(&self) -> Vec<crate::boundary::AxisKind> {
        match &self.simulation_box().boundary {
            BoundarySpec::All(k) => vec![*k; self.dimension],
            BoundarySpec::PerAxis(v) => v.clone(),
        }
    }

    /// Radius of species `s` (from `radius` or `packing_fraction`, KT-1 and KT-2:
    /// [`crate::theory::kinetic::radius_at_packing_fraction`] in its region).
    pub fn radius(&self, s: usize) -> f64 {
        let sp = &self.species()[s];
        if let Some(r) = sp.radius {
            return r;
        }
        let phi = sp.packing_fraction.unwrap_or(0.0);
        let volume: f64 = match &sp.region {
            Some(r) => r.lo.iter().zip(&r.hi).map(|(a, b)| b - a).product(),
            None => self.lengths().iter().product(),
        };
        crate::theory::kinetic::radius_at_packing_fraction(self.dimension, phi, volume, sp.count)
    }

    /// Total number of grains.
    pub fn particle_count(&self) -> usize {
        self.species().iter().map(|s| s.count).sum()
    }

    /// Checks every value, table by table, then the pre-flight rules (the stop rule can
    /// be reached, the outputs, collisions and memory are within the documented limits);
    /// the error names the key, the value and the fix.
    pub(crate) fn validate(&self) -> Result<(), ScenarioError> {
        if let Some(spec) = self.intruder() {
            intruder::validate(self, spec)?;
        } else {
            validate::dimension(self)?;
            validate::simulation_box(self)?;
            validate::collisions(self)?;
            rough::validate(self)?;
            validate::gravity(self)?;
            species::validate(self)?;
            validate::initial(self)?;
            validate::dsmc(self)?;
            validate::edmd(self)?;
            validate::crater(self)?;
            driving::validate(self)?;
            schedule::validate(self)?;
        }
        validate::stop(self)?;
        validate::output(self)?;
        if let Some(sw) = &self.sweep {
            sw.validate(self)?;
        }
        preflight::check(self)
    }
}
