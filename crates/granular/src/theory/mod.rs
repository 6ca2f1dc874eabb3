//! Kinetic-theory predictions shared by the engines' tests and analyses.
//!
//! Formulas are for `N` equal hard disks (`dimension = 2`) or spheres (`dimension = 3`)
//! of radius `R` (diameter `d = 2R`) and mass `m`, with `k_B = 1`; derivations and
//! references are in `docs/dsmc.md`.

pub mod haff;
