//! Sweeps from Python: the library's parallel sweep (all cores by default), with the
//! interpreter lock released while the members run; one shard of it; the merge.

use crate::errors::{guard, simulation_error, value_error};
use crate::scenario::PyScenario;
use granular::run::sweep::{self, Shard};
use pyo3::prelude::*;
use std::path::PathBuf;

/// One row of `sweep.csv`: the point, each key's value as written in the table, and
/// `(observable, mean, standard error)` per observable.
type Row = (usize, Vec<String>, Vec<(String, f64, f64)>);

/// run_sweep(scenario, out, threads=0, shard=None, insist=False) -> list[tuple[int, list[str], list[tuple[str, float, float]]]]
///
/// Runs the scenario's [sweep] into the directory `out` (the files of `granular sweep`),
/// returning the rows `(point, values, [(observable, mean, stderr)])`. Members already
/// finished in `out` are kept. With `shard = "I/N"` only that share of the members runs
/// and nothing is merged (the result is empty): `merge_sweep(out)` once every shard has
/// finished. A scenario or a sweep point above the pre-flight cost limits raises
/// ScenarioError unless `insist` (`granular sweep --insist`). `granular.run_sweep` wraps
/// this and returns `load_sweep(out)`.
#[pyfunction]
#[pyo3(signature = (scenario, out, threads = 0, shard = None, insist = false))]
pub fn run_sweep(
    py: Python<'_>,
    scenario: &PyScenario,
    out: PathBuf,
    threads: usize,
    shard: Option<String>,
    insist: bool,
) -> PyResult<Vec<Row>> {
    let shard = match shard {
        None => Shard::ALL,
        Some(s) => s
            .parse::<Shard>()
            .map_err(|e| value_error(format!("shard={s:?}: {e}")))?,
    };
    scenario.within_limits(py, insist)?;
    if let Some((key, _)) = scenario.arrays.first() {
        return Err(value_error(format!(
            "run_sweep: `{key}` is a NumPy array, which the members of a sweep cannot share \
             yet; save the arrays with numpy.savez and name them in the scenario instead \
             ({key} = {{ npz = \"/path/state.npz\", array = \"name\" }}, docs/scenario.md)"
        )));
    }
    let (text, overrides) = (scenario.source.clone(), scenario.overrides.clone());
    let origin = scenario.origin.clone();
    let fail = move |e: sweep::SweepError| match &origin {
        Some(o) => simulation_error(format!("{o}: {e}")),
        None => simulation_error(e),
    };
    let rows = py.detach(move || {
        guard("run_sweep", || {
            let options = sweep::SweepOptions {
                threads,
                shard,
                insist,
            };
            sweep::run_shard_with(&out, &text, &overrides, &options, &|_, _| {}).map_err(&fail)?;
            if shard.count > 1 {
                return Ok(Vec::new());
            }
            Ok(sweep::merge(&out, false).map_err(&fail)?.rows)
        })
    })?;
    Ok(rows
        .into_iter()
        .map(|r| (r.point, r.values, r.observables))
        .collect())
}

/// merge_sweep(out, allow_missing=False) -> list[str]
///
/// Builds `sweep.csv` and `sweep.json` in the sweep directory `out` from its finished
/// members (`granular merge`); returns the members missing (only with `allow_missing`;
/// without it, missing members raise SimulationError listing them).
#[pyfunction]
#[pyo3(signature = (out, allow_missing = false))]
pub fn merge_sweep(py: Python<'_>, out: PathBuf, allow_missing: bool) -> PyResult<Vec<String>> {
    py.detach(move || {
        guard("merge_sweep", || {
            sweep::merge(&out, allow_missing)
                .map(|m| m.meta.missing)
                .map_err(simulation_error)
        })
    })
}
