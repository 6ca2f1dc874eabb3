//! The file's layout of a scenario and which table belongs to which engine, in one place.
//!
//! A scenario file is flat: `engine = "..."` beside the tables of every engine. [`Layout`]
//! is that layout (serde; unknown keys rejected, defaults filled in); [`Layout::into_scenario`]
//! turns it into the typed [`Scenario`], whose [`EngineSpec`] holds only the tables of its
//! engine, and [`Layout::of`] writes a scenario back (only the tables its engine reads).
//! `engine` is a tagged choice: a table written for another engine (`[dsmc]` in an
//! event-driven run, `[[species]]` in an intruder run, ...) is an error that names the
//! table and the engine ([`check_table`] on the file's table, with its line; the same rule,
//! [`applies`], in [`Layout::into_scenario`] for a layout built otherwise).

use super::{
    BoxSpec, CollisionSpec, CraterSpec, DrivingSpec, DsmcSpec, EdmdSpec, EngineKind, EngineSpec,
    GrainsSpec, InitialSpec, IntruderSpec, OutputSpec, Scenario, ScenarioError, ScheduledChange,
    SpeciesSpec, StopSpec, SweepSpec, de,
};
use serde::{Deserialize, Serialize};

/// The scenario as the file lays it out: the fields in the file's order, each engine's
/// tables optional.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Layout {
    engine: EngineKind,
    #[serde(default = "two")]
    dimension: usize,
    #[serde(
        default = "one",
        deserialize_with = "de::seed::deserialize",
        serialize_with = "de::seed::serialize"
    )]
    seed: u64,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    description: String,
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    simulation_box: Option<BoxSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    species: Vec<SpeciesSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    initial: Option<InitialSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    collisions: Option<CollisionSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    gravity: Vec<f64>,
    #[serde(default)]
    stop: StopSpec,
    #[serde(default)]
    output: OutputSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    edmd: Option<EdmdSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    dsmc: Option<DsmcSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    intruder: Option<IntruderSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    crater: Option<CraterSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    sweep: Option<SweepSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    driving: Option<DrivingSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    schedule: Vec<ScheduledChange>,
}

fn two() -> usize {
    2
}
fn one() -> u64 {
    1
}

impl Layout {
    /// The typed scenario: the common part and its engine's tables (defaults for those
    /// left out). A table of another engine, or an intruder scenario without
    /// `[intruder]`, is an error.
    pub(super) fn into_scenario(self) -> Result<Scenario, ScenarioError> {
        let kind = self.engine;
        let present = [
            ("edmd", self.edmd.is_some()),
            ("dsmc", self.dsmc.is_some()),
            ("intruder", self.intruder.is_some()),
            ("box", self.simulation_box.is_some()),
            ("species", !self.species.is_empty()),
            ("initial", self.initial.is_some()),
            ("collisions", self.collisions.is_some()),
            ("gravity", !self.gravity.is_empty()),
            ("crater", self.crater.is_some()),
            ("driving", self.driving.is_some()),
            ("schedule", !self.schedule.is_empty()),
        ];
        if let Some((k, _)) = present.iter().find(|(k, p)| *p && !applies(k, kind)) {
            return Err(not_applicable(k, kind));
        }
        let grains = GrainsSpec {
            simulation_box: self.simulation_box.unwrap_or_default(),
            species: self.species,
            initial: self.initial.unwrap_or_default(),
            collisions: self.collisions.unwrap_or_default(),
            gravity: self.gravity,
            crater: self.crater,
            driving: self.driving,
            schedule: self.schedule,
        };
        let engine = match kind {
            EngineKind::Edmd => EngineSpec::Edmd {
                grains,
                edmd: self.edmd.unwrap_or_default(),
            },
            EngineKind::Dsmc => EngineSpec::Dsmc {
                grains,
                dsmc: self.dsmc.unwrap_or_default(),
            },
            EngineKind::Intruder => EngineSpec::Intruder(self.intruder.ok_or_else(|| {
                ScenarioError::new(
                    "intruder",
                    format!(
                        "is missing; engine = \"intruder\" needs an [intruder] table with model = {} (docs/scenario.md)",
                        super::intruder::MODELS
                    ),
                )
            })?),
        };
        Ok(Scenario {
            dimension: self.dimension,
            seed: self.seed,
            description: self.description,
            stop: self.stop,
            output: self.output,
            sweep: self.sweep,
            engine,
        })
    }

    /// The layout of `sc` as written: defaults filled in, only the tables its engine
    /// reads (the box only where it is not the default one).
    pub(super) fn of(sc: &Scenario) -> Layout {
        let mut out = Layout {
            engine: sc.kind(),
            dimension: sc.dimension,
            seed: sc.seed,
            description: sc.description.clone(),
            simulation_box: None,
            species: Vec::new(),
            initial: None,
            collisions: None,
            gravity: Vec::new(),
            stop: sc.stop.clone(),
            output: sc.output.clone(),
            edmd: sc.edmd().cloned(),
            dsmc: sc.dsmc().cloned(),
            intruder: sc.intruder().cloned(),
            crater: None,
            sweep: sc.sweep.clone(),
            driving: None,
            schedule: Vec::new(),
        };
        if let Some(g) = sc.grains() {
            out.simulation_box = (!g.simulation_box.is_default()).then(|| g.simulation_box.clone());
            out.species = g.species.clone();
            out.initial = Some(g.initial.clone());
            out.collisions = Some(g.collisions.clone());
            out.gravity = g.gravity.clone();
            out.crater = g.crater.clone();
            out.driving = g.driving.clone();
            out.schedule = g.schedule.clone();
        }
        out
    }
}

/// Keys every engine reads.
const COMMON: &[&str] = &[
    "engine",
    "dimension",
    "seed",
    "description",
    "stop",
    "output",
    "sweep",
];
/// Keys of the many-grain engines (`edmd`, `dsmc`).
const GRAINS: &[&str] = &[
    "box",
    "species",
    "initial",
    "collisions",
    "gravity",
    "crater",
    "driving",
    "schedule",
];

fn engine_name(e: EngineKind) -> &'static str {
    match e {
        EngineKind::Edmd => "edmd",
        EngineKind::Dsmc => "dsmc",
        EngineKind::Intruder => "intruder",
    }
}

/// Whether top-level `key` applies to `engine`.
pub(super) fn applies(key: &str, engine: EngineKind) -> bool {
    if COMMON.contains(&key) {
        return true;
    }
    match engine {
        EngineKind::Edmd => GRAINS.contains(&key) || key == "edmd",
        EngineKind::Dsmc => GRAINS.contains(&key) || key == "dsmc",
        EngineKind::Intruder => key == "intruder",
    }
}

/// The engines a top-level key belongs to, as the fix to suggest.
fn owners(key: &str) -> &'static str {
    match key {
        "edmd" => "engine = \"edmd\"",
        "dsmc" => "engine = \"dsmc\"",
        "intruder" => "engine = \"intruder\"",
        "driving" => "engine = \"dsmc\"",
        _ => "engine = \"edmd\" or \"dsmc\"",
    }
}

/// The error for top-level `key` in a scenario of `engine`.
pub(super) fn not_applicable(key: &str, engine: EngineKind) -> ScenarioError {
    let what = match key {
        "gravity" => "key gravity".to_string(),
        "species" => "table [[species]]".to_string(),
        "schedule" => "table [[schedule]]".to_string(),
        k => format!("table [{k}]"),
    };
    ScenarioError::new(
        key,
        format!(
            "{what} does not apply to engine \"{}\"; remove it or set {}",
            engine_name(engine),
            owners(key)
        ),
    )
}

/// Checks the top-level keys of the scenario table (after `--set`) against its engine.
/// An absent or unknown `engine` is left to the typed reader, which names it.
pub(super) fn check_table(table: &toml::Table) -> Result<(), ScenarioError> {
    let engine = match table.get("engine").and_then(|v| v.as_str()) {
        Some("edmd") => EngineKind::Edmd,
        Some("dsmc") => EngineKind::Dsmc,
        Some("intruder") => EngineKind::Intruder,
        _ => return Ok(()),
    };
    // Unknown keys are reported by the typed reader with the list of expected keys.
    let known = |k: &str| {
        COMMON.contains(&k) || GRAINS.contains(&k) || ["edmd", "dsmc", "intruder"].contains(&k)
    };
    match table.keys().find(|k| known(k) && !applies(k, engine)) {
        Some(k) => Err(match rough_intruder(table, k, engine) {
            Some(e) => e,
            None => not_applicable(k, engine),
        }),
        None => Ok(()),
    }
}

/// Rough grains asked of an intruder engine (`collisions.tangential_restitution` or
/// `collisions.friction` above their smooth values): the intruder and its bath are smooth.
fn rough_intruder(table: &toml::Table, key: &str, engine: EngineKind) -> Option<ScenarioError> {
    if engine != EngineKind::Intruder || key != "collisions" {
        return None;
    }
    let c = table.get("collisions")?.as_table()?;
    let (k, v) = ["tangential_restitution", "friction"]
        .iter()
        .find_map(|k| c.get(*k).map(|v| (*k, v)))?;
    Some(ScenarioError::new(
        format!("collisions.{k}"),
        format!(
            "is {v}, but the intruder engines model smooth grains only (no rotation, no tangential restitution); remove [collisions] and set the intruder's restitution in [intruder], or simulate rough grains with engine = \"edmd\""
        ),
    ))
}

/// Removes the top-level keys that do not apply to the engine from a serialised scenario
/// (the resolved scenario lists only what its engine reads).
pub(super) fn strip(table: &mut toml::Table, engine: EngineKind) {
    table.retain(|k, _| applies(k, engine));
}
