//! Parameters changed between two calls to `advance` ([`crate::Simulation::set`]): the
//! collision law, the driving's strength or temperature, gravity. A change is validated as
//! the same key in a scenario (the whole scenario with the new value is checked), takes
//! effect from the current time and is kept as a [`Change`] (time, key, old and new value)
//! for `log.txt` and `summary.json`. Counts, the dimension, the box, species and the
//! engine are fixed once a simulation exists.

use crate::build::AnyEngine;
use crate::driving::Driving;
use crate::scenario::{Scenario, ScenarioError};
use serde::{Deserialize, Serialize};

/// The keys that can change in flight, in the scenario's words.
pub const KEYS: [&str; 7] = [
    "collisions.restitution",
    "collisions.wall_restitution",
    "collisions.wall_tangential_restitution",
    "collisions.contact_duration",
    "driving.strength",
    "driving.temperature",
    "gravity",
];

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

fn refuse(key: &str, message: String) -> ScenarioError {
    ScenarioError {
        key: key.to_string(),
        message,
        line: None,
    }
}

/// The value of the dotted `key` in the scenario as its TOML writes it, or `unset`.
fn written_value(scenario: &Scenario, key: &str) -> String {
    let table: toml::Table = match scenario.to_toml().parse() {
        Ok(t) => t,
        Err(_) => return "unset".into(),
    };
    let mut value = Some(toml::Value::Table(table));
    for part in key.split('.') {
        value = value.and_then(|v| v.get(part).cloned());
    }
    value.map_or_else(|| "unset".into(), |v| v.to_string())
}

/// Checks `key = value` (the right side in TOML, as `granular run --set`) against
/// `scenario` and `engine`, and applies it to the engine: the scenario with the new value
/// and the change, or the reason it is refused (then nothing changed).
pub(crate) fn apply(
    scenario: &Scenario,
    engine: &mut AnyEngine,
    time: f64,
    key: &str,
    value: &str,
) -> Result<(Scenario, Change), ScenarioError> {
    if !KEYS.contains(&key) {
        return Err(refuse(
            key,
            format!(
                "cannot change in flight; the keys that can are {}. Counts, the dimension, the \
                 box, species, the seed and the engine are fixed once a simulation exists: \
                 build a new one (for example from a snapshot)",
                KEYS.join(", ")
            ),
        ));
    }
    if matches!(engine, AnyEngine::Intruder(_)) {
        return Err(refuse(
            key,
            "the intruder engine's parameters cannot change in flight; build a new simulation"
                .into(),
        ));
    }
    if key.starts_with("driving.") && scenario.driving().is_none() {
        return Err(refuse(
            key,
            "this scenario has no [driving] to change; a driving cannot be switched on in \
             flight (give [driving] in the scenario)"
                .into(),
        ));
    }
    let candidate =
        Scenario::from_toml_insisting(&scenario.to_toml(), &[format!("{key}={value}")])?;
    let change = Change {
        time,
        key: key.to_string(),
        old: written_value(scenario, key),
        new: written_value(&candidate, key),
    };
    if let Some(d) = key.strip_prefix("driving.") {
        let spec = candidate
            .driving()
            .ok_or_else(|| refuse(key, "this scenario has no [driving] to change".into()))?;
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
        let fits = matches!(
            (d, &driving),
            ("strength", Driving::WhiteNoise { .. }) | ("temperature", Driving::Rescale { .. })
        );
        if !fits {
            return Err(refuse(
                key,
                "does not belong to this scenario's driving (`strength` is the white noise's, \
                 `temperature` the rescaling's)"
                    .into(),
            ));
        }
        match engine {
            AnyEngine::Edmd2(e) => e.change_driving(driving),
            AnyEngine::Edmd3(e) => e.change_driving(driving),
            AnyEngine::Dsmc2(e) => e.change_driving(driving),
            AnyEngine::Dsmc3(e) => e.change_driving(driving),
            AnyEngine::Intruder(_) => {}
        }
    } else if key == "gravity" {
        let g = candidate.gravity();
        match engine {
            AnyEngine::Edmd2(e) => e.set_gravity(g),
            AnyEngine::Edmd3(e) => e.set_gravity(g),
            AnyEngine::Dsmc2(e) => e.set_gravity(g),
            AnyEngine::Dsmc3(e) => e.set_gravity(g),
            AnyEngine::Intruder(_) => {}
        }
    } else {
        let law = candidate.collisions().law();
        let dsmc =
            |r: Result<(), crate::dsmc::DsmcError>| r.map_err(|e| refuse(key, e.to_string()));
        match engine {
            AnyEngine::Edmd2(e) => e.set_collision_law(law),
            AnyEngine::Edmd3(e) => e.set_collision_law(law),
            AnyEngine::Dsmc2(e) => dsmc(e.set_collision_law(law))?,
            AnyEngine::Dsmc3(e) => dsmc(e.set_collision_law(law))?,
            AnyEngine::Intruder(_) => {}
        }
    }
    Ok((candidate, change))
}
