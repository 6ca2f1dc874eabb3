//! Exact and kinetic-theory results the engines are checked against.
//!
//! Formulas are for hard disks (`dimension = 2`) or spheres (`dimension = 3`) with
//! `k_B = 1`; derivations and references are in `docs/edmd.md` and `docs/dsmc.md`.

pub mod equilibrium;
pub mod haff;
pub mod sonine;
pub mod transport;
