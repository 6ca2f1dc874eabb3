//! Which top-level tables and keys apply to which engine. `engine` is a tagged choice: a
//! table written for another engine (`[dsmc]` in an event-driven run, `[[species]]` in
//! an intruder run, ...) is an error that names the table and the engine.

use super::{EngineKind, Scenario, ScenarioError};

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
        Some(k) => Err(not_applicable(k, engine)),
        None => Ok(()),
    }
}

/// The same check on a typed scenario (built in code): a table of another engine that
/// differs from its default.
pub(super) fn check_fields(sc: &Scenario) -> Result<(), ScenarioError> {
    let e = sc.engine;
    let set = [
        ("edmd", sc.edmd != super::EdmdSpec::default()),
        ("dsmc", sc.dsmc != super::DsmcSpec::default()),
        ("intruder", sc.intruder.is_some()),
        ("box", !sc.simulation_box.is_default()),
        ("species", !sc.species.is_empty()),
        ("initial", sc.initial != super::InitialSpec::default()),
        (
            "collisions",
            sc.collisions != super::CollisionSpec::default(),
        ),
        ("gravity", !sc.gravity.is_empty()),
        ("crater", sc.crater.is_some()),
        ("driving", sc.driving.is_some()),
    ];
    match set.iter().find(|(k, present)| *present && !applies(k, e)) {
        Some((k, _)) => Err(not_applicable(k, e)),
        None => Ok(()),
    }
}

/// Removes the top-level keys that do not apply to the engine from a serialised scenario
/// (the resolved scenario lists only what its engine reads).
pub(super) fn strip(table: &mut toml::Table, engine: EngineKind) {
    table.retain(|k, _| applies(k, engine));
}
