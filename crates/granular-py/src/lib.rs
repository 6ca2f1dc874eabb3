//! `granular._core`: the compiled half of the `granular` Python package (PyO3, stable ABI
//! for Python 3.10 and newer). The Python half (`python/granular/`) re-exports these names
//! with NumPy-friendly wrappers; users import `granular`, never `granular._core`.
//!
//! The binding holds no physics: scenarios, engines, theory and run directories all come
//! from the `granular` library; this crate only converts between Python and Rust.

mod cli;
mod convert;
mod errors;
mod rundir;
mod scenario;
mod simulation;
mod state;
mod sweep;
mod theory;

use pyo3::prelude::*;

/// The compiled core of the `granular` package (use `import granular`).
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ScenarioError", py.get_type::<errors::ScenarioError>())?;
    m.add("SimulationError", py.get_type::<errors::SimulationError>())?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_function(wrap_pyfunction!(sweep::run_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::merge_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(cli::cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::run_files, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::file_name, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::sweep_member, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::read_summary, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::read_table, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::read_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(rundir::read_snapshot, m)?)?;
    theory::register(m)?;
    Ok(())
}
