//! Python exceptions with the command line's messages, and the guard that turns a Rust
//! panic into a Python exception (never an abort).

use granular::engine::EngineError;
use granular::grain_state::StateError;
use granular::run::BuildError;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    granular,
    ScenarioError,
    PyValueError,
    "A scenario is invalid: the message names the key, the value, the line (when the scenario \
came from a file or text) and the fix, exactly as `granular check` prints it. Attributes: \
`key` (dotted key, e.g. 'collisions.restitution'), `line` (1-based line or None), `reason` \
(the message without key and line)."
);

pyo3::create_exception!(
    granular,
    SimulationError,
    PyRuntimeError,
    "A simulation could not be built, could not go on, or could not write its files: the \
message is the command line's (for example inelastic collapse with what to change)."
);

/// The Python form of a scenario error; `origin` (a file name) prefixes the message as the
/// command line does.
pub fn scenario_error(
    py: Python<'_>,
    e: &granular::scenario::ScenarioError,
    origin: Option<&str>,
) -> PyErr {
    let message = match origin {
        Some(o) => format!("{o}: {e}"),
        None => e.to_string(),
    };
    let err = ScenarioError::new_err(message);
    let value = err.value(py);
    // Attribute setting on a fresh exception instance cannot fail in practice; if it does,
    // the message still carries everything.
    let _ = value.setattr("key", e.key.clone());
    let _ = value.setattr("line", e.line);
    let _ = value.setattr("reason", e.message.clone());
    err
}

/// A simulation error from any displayable Rust error.
pub fn simulation_error(e: impl std::fmt::Display) -> PyErr {
    SimulationError::new_err(e.to_string())
}

/// A `ValueError` naming the argument, its value and the fix.
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// Runs `f`, turning a panic into a `SimulationError` that says it is a bug (the object
/// that panicked may be left half-updated; the message says so).
pub fn guard<T>(what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let detail = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "no message".into());
            Err(SimulationError::new_err(format!(
                "internal error in {what}: {detail} (a bug in granular: please report it with \
the scenario; the simulation object may be inconsistent, build a new one)"
            )))
        }
    }
}

/// A failed build as a Python exception: ScenarioError for a scenario value, SimulationError
/// otherwise (prefixed with the scenario file).
pub fn build_error(py: Python<'_>, e: BuildError, origin: Option<&str>) -> PyErr {
    match e {
        BuildError::Scenario(s) => scenario_error(py, &s, origin),
        other => simulation_error(match origin {
            Some(o) => format!("{o}: {other}"),
            None => other.to_string(),
        }),
    }
}

/// An engine that stopped as a SimulationError.
pub fn engine_error(e: EngineError) -> PyErr {
    simulation_error(format!("{e}\n(fix the scenario and rerun)"))
}

/// A refused state as a Python exception: SimulationError where the engine cannot take
/// one, ValueError where the arrays are wrong.
pub fn state_error(e: StateError) -> PyErr {
    match e {
        StateError::NoGrains { .. } | StateError::Engine(_) | StateError::Build(_) => {
            simulation_error(e)
        }
        other => value_error(other.to_string()),
    }
}
