//! Event-driven molecular dynamics (EDMD) of hard disks (`D = 2`) and spheres (`D = 3`),
//! after the hard-disk assignment (`event-driven-hard-disk-gas.txt`).
//!
//! * `engine`: the event loop ([`Edmd`]);
//! * [`init`]: compression to dense states (placements and velocities are shared by all
//!   engines: `crate::setup`).
//!
//! The internals are private to the crate: `prediction` (collision and crossing times,
//! HD-1, HD-2, HD-7 to HD-10), `queue` (the event priority queue: a tournament tree or a
//! calendar), `candidates` (the grain record and the earliest contact among a
//! prediction's candidates, eight at a time with AVX-512 or four with AVX2 when there are
//! many, both grains of a 2D pair collision at once). The cell grid of the neighbour
//! search (`neighbours`) and the software prefetch (`prefetch`) are
//! shared with the overlap check of initial states. `docs/edmd.md` describes them.

mod candidates;
pub(crate) mod driving;
pub(crate) mod engine;
pub mod init;
pub(crate) mod prediction;
pub(crate) mod queue;

/// Internal thresholds and tests' hooks, not a stable API (the integration tests check
/// the queue's switch-over sizes and the large-grain cut through them).
#[doc(hidden)]
pub mod internals {
    pub use super::queue::{LOOK_AHEAD_MIN_GRAINS, TOURNAMENT_MAX_GRAINS};
    pub use crate::neighbours::large_grain_cut;
}

pub use crate::particles::ParticleSet;
pub use engine::{CollisionRecord, Edmd, EdmdOptions, Totals};
