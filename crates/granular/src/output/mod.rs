//! Output files written by the runner and read back by analysis tools.
//!
//! * [`npz`]: NumPy `.npy` / `.npz` arrays, including whole [`crate::engine::Snapshot`]s.
//! * `number`: numbers for the terminal and `log.txt` ([`format_number`]).
//! * `trajectory_format`: the names of the trajectory formats ([`TrajectoryFormat`]).

pub mod npz;
pub(crate) mod number;
pub(crate) mod trajectory_format;

pub use number::format_number;
pub use trajectory_format::TrajectoryFormat;
