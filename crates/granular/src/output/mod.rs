//! Output files written by the runner and read back by analysis tools.
//!
//! * [`npz`]: NumPy `.npy` / `.npz` arrays, including whole [`crate::engine::Snapshot`]s.

pub mod npz;
