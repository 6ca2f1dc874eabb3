//! Exact and kinetic-theory results the engines are checked against.
//!
//! Formulas are for hard disks (`dimension = 2`) or spheres (`dimension = 3`) with
//! `k_B = 1`; derivations and references are in `docs/edmd.md`, `docs/dsmc.md` and (rough grains)
//! `docs/rough.md`.

pub mod equilibrium;
pub mod haff;
pub mod rough;
pub mod sonine;
pub mod transport;
