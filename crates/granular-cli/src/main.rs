//! The `granular` binary: the command line of `granular_cli` (all of it lives in the library
//! so that the Python package runs the same commands as `python -m granular`).

use std::process::ExitCode;

fn main() -> ExitCode {
    let status = granular_cli::main_with_args(std::env::args_os());
    ExitCode::from(u8::try_from(status).unwrap_or(2))
}
