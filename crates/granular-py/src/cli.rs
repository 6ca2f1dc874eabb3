//! The command line (`granular_cli`) from Python: `python -m granular ARGS`.

use crate::errors::guard;
use pyo3::prelude::*;

/// cli_main(args) -> int
///
/// Runs the `granular` command line with `args` (program name first) and returns its exit
/// status; the interpreter lock is released meanwhile. Output goes to the process's
/// stdout/stderr, as the binary's does.
#[pyfunction]
pub fn cli_main(py: Python<'_>, args: Vec<String>) -> PyResult<i32> {
    py.detach(|| {
        guard("the command line", || {
            Ok(granular_cli::main_with_args(args))
        })
    })
}
