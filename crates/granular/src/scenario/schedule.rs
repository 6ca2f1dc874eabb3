//! `[[schedule]]`: parameters changed at given times of a run, the same changes that
//! [`crate::Simulation::set`] makes between two calls to `advance`, written in the
//! scenario so that a protocol (a quench of the restitution, a jump of the driving) runs
//! from the command line, and checkpoints and resumed runs carry it.
//!
//! ```toml
//! [[schedule]]
//! time = 2.0
//! set = { "collisions.restitution" = 0.5 }
//!
//! [[schedule]]
//! time = 5.0
//! set = { "driving.strength" = 0.2, "gravity" = [0.0, -1.0] }
//! ```
//!
//! An entry acts from its `time` on: the run stops its engine exactly there (an event-driven
//! run at that instant, DSMC with a step shortened to land on it), changes the keys, and
//! goes on. The output at that time (if any) still shows the state reached under the old
//! values. The keys are those of [`IN_FLIGHT_KEYS`]; each entry's values are checked when
//! the scenario is read, as the scenario with every change up to that entry applied.

use super::{Scenario, ScenarioError, ScenarioInput};
use serde::{Deserialize, Serialize};

/// The keys that can change once a simulation exists (by [`crate::Simulation::set`] or
/// `[[schedule]]`), in the scenario's words.
pub(crate) const IN_FLIGHT_KEYS: [&str; 9] = [
    "collisions.restitution",
    "collisions.tangential_restitution",
    "collisions.friction",
    "collisions.wall_restitution",
    "collisions.wall_tangential_restitution",
    "collisions.contact_duration",
    "driving.strength",
    "driving.temperature",
    "gravity",
];

/// The most entries a `[[schedule]]` may have (each is checked as a whole scenario when
/// the scenario is read).
pub(crate) const MAX_SCHEDULE_ENTRIES: usize = 10_000;

/// One `[[schedule]]` entry: from `time` on, the keys of `set` take their values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduledChange {
    /// Simulation time from which the new values hold (time units).
    pub time: f64,
    /// The keys (dotted scenario keys, quoted: `"collisions.restitution"`) and their new
    /// values.
    pub set: toml::Table,
}

impl ScheduledChange {
    /// The changes as `(key, value)` pairs, the value written as in TOML (the right side
    /// of `--set key=value`).
    pub(crate) fn assignments(&self) -> Vec<(String, String)> {
        self.set
            .iter()
            .map(|(k, v)| (k.clone(), v.to_string()))
            .collect()
    }
}

fn refuse(key: &str, message: impl Into<String>) -> ScenarioError {
    ScenarioError::new(key, message)
}

/// `scenario` with the changes in flight `assignments` (`(key, value)`, the value as TOML
/// text) made: each key one of [`IN_FLIGHT_KEYS`], and the scenario with the new values
/// checked whole, as a scenario file with those values would be (without the cost
/// limits: the run was accepted when it started). The schedule itself is kept as it is.
/// Rough grains may become smooth (`collisions.tangential_restitution = -1`: their
/// angular velocities stay as they are from then on, and the changed scenario drops the
/// species' `inertia` and `angular_velocity`, which smooth grains do not take); smooth
/// grains carry no angular velocities and cannot become rough. The error names the key
/// and why it cannot take the value; nothing is changed then.
pub(crate) fn changed(
    scenario: &Scenario,
    assignments: &[(String, String)],
) -> Result<Scenario, ScenarioError> {
    let Some(grains) = scenario.grains() else {
        let key = assignments.first().map_or("", |(k, _)| k.as_str());
        return Err(refuse(
            key,
            "the intruder engine's parameters cannot change in flight; build a new simulation",
        ));
    };
    for (key, _) in assignments {
        if !IN_FLIGHT_KEYS.contains(&key.as_str()) {
            return Err(refuse(
                key,
                format!(
                    "cannot change in flight; the keys that can are {}. Counts, the \
                     dimension, the box, species, the seed and the engine are fixed once a \
                     simulation exists: build a new one (for example from a snapshot)",
                    IN_FLIGHT_KEYS.join(", ")
                ),
            ));
        }
        if let Some(d) = key.strip_prefix("driving.") {
            let Some(driving) = &grains.driving else {
                return Err(refuse(
                    key,
                    "this scenario has no [driving] to change; a driving cannot be switched \
                     on in flight (give [driving] in the scenario)",
                ));
            };
            let fits = matches!(
                (d, driving.kind),
                ("strength", super::DrivingKind::WhiteNoise)
                    | ("temperature", super::DrivingKind::Rescale)
            );
            if !fits {
                let (own, other) = match d {
                    "strength" => ("white_noise", "rescale"),
                    _ => ("rescale", "white_noise"),
                };
                return Err(refuse(
                    key,
                    format!(
                        "applies to kind = \"{own}\" only, and this scenario's driving is \
                         kind = \"{other}\" (`strength` is the white noise's, `temperature` \
                         the rescaling's); the kind of driving cannot change in flight"
                    ),
                ));
            }
        }
    }
    // The scenario without its schedule, so that checking the changed scenario does not
    // check the schedule again (which changes it in turn).
    // Its per-grain arrays (which cannot change in flight) go along as arrays, not as text.
    let (mut base, arrays) = scenario.without_arrays();
    let was_rough = scenario.collisions().law().is_rough();
    let schedule = base
        .grains_mut()
        .map(|g| std::mem::take(&mut g.schedule))
        .unwrap_or_default();
    let overrides: Vec<String> = assignments
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    let reread = |base: &Scenario| {
        ScenarioInput {
            text: &base.to_toml(),
            overrides: &overrides,
            arrays: &arrays,
            ..ScenarioInput::default()
        }
        .read()
    };
    let mut out = match reread(&base) {
        Ok(out) => out,
        // Rough grains made smooth: their κ and initial spins are no keys of smooth
        // grains (the engine keeps both).
        Err(e) if was_rough && e.key.starts_with("species[") => {
            if let Some(g) = base.grains_mut() {
                for sp in &mut g.species {
                    sp.inertia = None;
                    sp.angular_velocity = None;
                }
            }
            let out = reread(&base)?;
            if out.collisions().law().is_rough() {
                return Err(e);
            }
            out
        }
        Err(e) => return Err(e),
    };
    if !was_rough && out.collisions().law().is_rough() {
        let key = assignments
            .iter()
            .map(|(k, _)| k.as_str())
            .find(|k| *k == "collisions.tangential_restitution" || *k == "collisions.friction")
            .unwrap_or("collisions.tangential_restitution");
        return Err(refuse(
            key,
            "would make the grains rough, but they are smooth \
             (collisions.tangential_restitution = -1 until now) and carry no angular \
             velocities, so they cannot become rough in flight; start the run with rough \
             grains (collisions.tangential_restitution in (-1, 1]: it can then change in \
             flight, to -1 as well)",
        ));
    }
    if let Some(g) = out.grains_mut() {
        g.schedule = schedule;
    }
    Ok(out)
}

/// Checks `[[schedule]]`: times from 0 on, strictly increasing and before `stop.time`;
/// every entry sets at least one key; and the scenario with the changes up to each entry
/// is a valid scenario (each key one that can change in flight).
pub(super) fn validate(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(grains) = sc.grains() else {
        return Ok(());
    };
    let schedule = &grains.schedule;
    if schedule.is_empty() {
        return Ok(());
    }
    if schedule.len() > MAX_SCHEDULE_ENTRIES {
        return Err(refuse(
            "schedule",
            format!(
                "has {} entries, more than the {MAX_SCHEDULE_ENTRIES} allowed; merge changes \
                 that happen together into one entry's `set`",
                schedule.len()
            ),
        ));
    }
    let mut state = sc.clone();
    if let Some(g) = state.grains_mut() {
        g.schedule.clear();
    }
    let mut previous: Option<f64> = None;
    for (k, entry) in schedule.iter().enumerate() {
        let time_key = format!("schedule[{k}].time");
        let t = entry.time;
        if !(t.is_finite() && t >= 0.0) {
            return Err(refuse(
                &time_key,
                format!("is {t}; give the simulation time (0 or later) from which `set` holds"),
            ));
        }
        if let Some(p) = previous.filter(|&p| t <= p) {
            return Err(refuse(
                &time_key,
                format!(
                    "is {t}, not after schedule[{}].time = {p}: list the entries in time \
                     order, one per time (changes made together go in one entry's `set`)",
                    k - 1
                ),
            ));
        }
        if let Some(stop) = sc.stop.time.filter(|&s| t >= s) {
            return Err(refuse(
                &time_key,
                format!(
                    "is {t}, not before stop.time = {stop}: the change would never act; \
                     remove the entry or lengthen the run"
                ),
            ));
        }
        previous = Some(t);
        let set_key = format!("schedule[{k}].set");
        if entry.set.is_empty() {
            return Err(refuse(
                &set_key,
                "is empty; give the keys to change and their values, e.g. \
                 set = { \"collisions.restitution\" = 0.5 }",
            ));
        }
        state = changed(&state, &entry.assignments()).map_err(|e| {
            refuse(
                &set_key,
                format!("sets `{}` at t = {t}: {}", e.key, e.message),
            )
        })?;
    }
    Ok(())
}
