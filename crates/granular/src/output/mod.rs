//! Output files written by the runner and read back by analysis tools.
//!
//! * [`npz`]: NumPy `.npy` / `.npz` arrays, including whole [`crate::engine::Snapshot`]s.
//! * [`number`]: numbers for the terminal and `log.txt` ([`format_number`]).

pub mod npz;
pub mod number;

pub use number::format_number;
