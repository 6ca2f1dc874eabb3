//! Direct Simulation Monte Carlo (DSMC) of granular gases, after M. Müller and
//! H. J. Herrmann, "DSMC - a stochastic algorithm for granular matter",
//! and G. A. Bird, *Molecular Gas Dynamics* (1976).
//!
//! Each time step `tau` splits into
//!
//! 1. **free flight** of every grain (exact under a constant acceleration), with
//!    specular, possibly inelastic, walls or periodic faces;
//! 2. **sorting** of the particle arrays by cell (stable parallel counting sort, see
//!    `cells`);
//! 3. **collisions** in every cell independently: `M_c` candidate pairs (DSMC-1, with the
//!    true cross-section, see `docs/dsmc.md`), each accepted with probability
//!    `|v_i - v_j| / v_max` (DSMC-2), with a random impact parameter and normal
//!    restitution `e`.
//!
//! Cells are processed on all rayon threads; cell `c` of step `s` draws from its own
//! random stream `(seed, [DYNAMICS, s, c])`, and all floating-point reductions are summed
//! over fixed chunks in a fixed order, so results are bit-identical for any thread count.
//!
//! Generic over the dimension `D` (2: disks, 3: spheres). One run can also be split over
//! ranks (MPI processes) by slabs of cells, bit-identical for any number of ranks: see
//! [`domain`].

pub(crate) mod cells;
mod collide;
pub mod config;
mod decomposed;
pub mod domain;
mod driving;
pub mod engine;
mod flight;
pub(crate) mod grains;
pub(crate) mod guards;
pub(crate) mod lattice;
pub(crate) mod observables;
pub(crate) mod parts;
pub(crate) mod setup;
mod species;
mod sums;

pub use crate::neighbours::CellCounts;
pub use cells::CellGrid;
pub use config::{DensityScope, DsmcConfig, VmaxMode};
pub use domain::{Balance, BalanceMode, Communicator};
pub(crate) use domain::{Domain, DomainError};
pub(crate) use engine::DsmcError;
pub use engine::{DsmcEngine, UniformGas};
pub use guards::{GuardKind, ValidityWarning};
pub use parts::EnginePart;
pub(crate) use parts::PartInfo;
pub use setup::RankLoad;
pub(crate) use setup::{GrainSetup, InitialSpin, InitialVelocity, Placement, SpeciesSetup};
pub(crate) use species::SpeciesTable;
