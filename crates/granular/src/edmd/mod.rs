//! Event-driven molecular dynamics (EDMD) of hard disks (`D = 2`) and spheres (`D = 3`),
//! after the hard-disk seed (`event-driven-hard-disk-gas.txt`).
//!
//! * [`engine`]: the event loop ([`Edmd`]);
//! * [`prediction`]: collision and crossing times (HD-1, HD-2, HD-7 to HD-10);
//! * [`queue`]: the event priority queue;
//! * `candidates`: the grain record and the earliest contact among a prediction's
//!   candidates (eight at a time with AVX-512, or four with AVX2, when there are many;
//!   for both grains of a 2D pair collision at once);
//! * [`prefetch`]: software prefetch of the records a prediction is about to read;
//! * [`cells`]: the cell grid for neighbour search;
//! * [`init`]: compression to dense states (placements and velocities are shared by all
//!   engines: [`crate::setup`]).

pub mod bench;
mod candidates;
pub mod cells;
pub mod engine;
pub mod init;
pub mod prediction;
pub mod prefetch;
pub mod queue;

pub use crate::particles::ParticleSet;
pub use engine::{Edmd, EdmdOptions, EventKind, Totals};
