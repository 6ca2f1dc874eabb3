//! Exact and kinetic-theory results the engines are checked against.
//!
//! Formulas are for hard disks (`dimension = 2`) or spheres (`dimension = 3`) with
//! `k_B = 1`; derivations and references are in `docs/edmd.md`, `docs/dsmc.md`, (rough grains)
//! `docs/rough.md` and (disk and sphere intruders, `intruder`, any dimension 1 to 3)
//! `docs/intruder.md`.

pub mod equilibrium;
pub mod haff;
pub mod hard_wall;
pub mod intruder;
pub mod kinetic;
pub mod relaxation;
pub mod rough;
pub mod sonine;
pub mod stability;
pub mod transport;
