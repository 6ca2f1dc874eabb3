//! Sweeps from Python: the library's parallel sweep (all cores by default), with the
//! interpreter lock released while the members run.

use crate::errors::{guard, simulation_error};
use crate::scenario::PyScenario;
use pyo3::prelude::*;
use std::path::PathBuf;

/// One row of `sweep.csv`: the value (TOML text), its number, and
/// `(observable, mean, standard error, members)` per observable.
type Row = (String, f64, Vec<(String, f64, f64, u64)>);

/// run_sweep(scenario, out, threads=0) -> list[tuple[str, float, list[tuple[str, float, float, int]]]]
///
/// Runs the scenario's [sweep] into the directory `out` (the files of `granular sweep`),
/// returning the rows `(value, number, [(observable, mean, stderr, members)])`. Members
/// already finished in `out` are kept. `granular.run_sweep` wraps this and returns
/// `load_sweep(out)`.
#[pyfunction]
#[pyo3(signature = (scenario, out, threads = 0))]
pub fn run_sweep(
    py: Python<'_>,
    scenario: &PyScenario,
    out: PathBuf,
    threads: usize,
) -> PyResult<Vec<Row>> {
    let (text, overrides) = (scenario.source.clone(), scenario.overrides.clone());
    let origin = scenario.origin.clone();
    let rows = py.detach(move || {
        guard("run_sweep", || {
            granular::run::sweep::run_sweep(&out, &text, &overrides, threads, &|_, _| {}).map_err(
                |e| match &origin {
                    Some(o) => simulation_error(format!("{o}: {e}")),
                    None => simulation_error(e),
                },
            )
        })
    })?;
    Ok(rows
        .into_iter()
        .map(|r| (r.value, r.number, r.observables))
        .collect())
}
