//! Parameters changed between two calls to `advance` ([`crate::Simulation::set`]) or at the
//! times of the scenario's `[[schedule]]` ([`crate::scenario::ScheduledChange`]): the
//! collision law, the driving's strength or temperature, gravity. A change is validated as
//! the same key in a scenario (the whole scenario with the new value is checked), takes
//! effect from the current time and is kept as a [`Change`] (time, key, old and new value)
//! for `log.txt` and `summary.json`. Counts, the dimension, the box, species and the
//! engine are fixed once a simulation exists.

use crate::build::AnyEngine;
use crate::driving::Driving;
use crate::scenario::{Scenario, ScenarioError};
use serde::{Deserialize, Serialize};

/// One parameter changed in flight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Change {
    /// Simulation time from which the new value holds.
    pub time: f64,
    /// The scenario key, e.g. `collisions.restitution`.
    pub key: String,
    /// The value before, as the scenario writes it (`unset` where it had none).
    pub old: String,
    /// The value after.
    pub new: String,
}

/// The value of the dotted `key` in the scenario as its TOML writes it, or `unset`.
fn written_value(scenario: &Scenario, key: &str) -> String {
    // Without the per-grain arrays, which no in-flight key is part of.
    let table: toml::Table = match scenario.without_arrays().0.to_toml().parse() {
        Ok(t) => t,
        Err(_) => return "unset".into(),
    };
    let mut value = Some(toml::Value::Table(table));
    for part in key.split('.') {
        value = value.and_then(|v| v.get(part).cloned());
    }
    value.map_or_else(|| "unset".into(), |v| v.to_string())
}

/// Checks the changes `assignments` (`(key, value)`, the value the right side in TOML, as
/// `granular run --set`) against `scenario` ([`crate::scenario::changed`]: keys that can
/// change in flight, the changed scenario valid as a whole), and applies them together to
/// the engine: the scenario with the new values and one [`Change`] per key, or the reason
/// they are refused (then nothing changed).
pub(crate) fn apply(
    scenario: &Scenario,
    engine: &mut AnyEngine,
    time: f64,
    assignments: &[(String, String)],
) -> Result<(Scenario, Vec<Change>), ScenarioError> {
    let candidate = crate::scenario::changed(scenario, assignments)?;
    let changes = assignments
        .iter()
        .map(|(key, _)| Change {
            time,
            key: key.clone(),
            old: written_value(scenario, key),
            new: written_value(&candidate, key),
        })
        .collect();
    let keys = || assignments.iter().map(|(k, _)| k.as_str());
    // The collision law first: the one change an engine may refuse (DSMC's TC model).
    if let Some(key) = keys().find(|k| k.starts_with("collisions.")) {
        let law = candidate.collisions().law();
        let dsmc = |r: Result<(), crate::dsmc::DsmcError>| {
            r.map_err(|e| ScenarioError {
                key: key.to_string(),
                message: e.to_string(),
                line: None,
            })
        };
        match engine {
            AnyEngine::Edmd2(e) => e.set_collision_law(law),
            AnyEngine::Edmd3(e) => e.set_collision_law(law),
            AnyEngine::Dsmc2(e) => dsmc(e.set_collision_law(law))?,
            AnyEngine::Dsmc3(e) => dsmc(e.set_collision_law(law))?,
            AnyEngine::Intruder(_) => {}
        }
    }
    if keys().any(|k| k.starts_with("driving."))
        && let Some(spec) = candidate.driving()
    {
        let present = match engine {
            AnyEngine::Edmd2(e) => e.driving().map(|s| s.driving.clone()),
            AnyEngine::Edmd3(e) => e.driving().map(|s| s.driving.clone()),
            AnyEngine::Dsmc2(e) => e.driving().map(|s| s.driving.clone()),
            AnyEngine::Dsmc3(e) => e.driving().map(|s| s.driving.clone()),
            AnyEngine::Intruder(_) => None,
        };
        let fallback = match present {
            Some(Driving::Rescale { temperature }) => temperature,
            _ => 1.0,
        };
        let driving = spec.driving(fallback);
        match engine {
            AnyEngine::Edmd2(e) => e.change_driving(driving),
            AnyEngine::Edmd3(e) => e.change_driving(driving),
            AnyEngine::Dsmc2(e) => e.change_driving(driving),
            AnyEngine::Dsmc3(e) => e.change_driving(driving),
            AnyEngine::Intruder(_) => {}
        }
    }
    if keys().any(|k| k == "gravity") {
        let g = candidate.gravity();
        match engine {
            AnyEngine::Edmd2(e) => e.set_gravity(g),
            AnyEngine::Edmd3(e) => e.set_gravity(g),
            AnyEngine::Dsmc2(e) => e.set_gravity(g),
            AnyEngine::Dsmc3(e) => e.set_gravity(g),
            AnyEngine::Intruder(_) => {}
        }
    }
    Ok((candidate, changes))
}
