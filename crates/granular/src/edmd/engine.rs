//! The event-driven engine.
//!
//! Algorithm (section 3 of the hard-disk assignment, in the one-event-per-particle form of
//! Lubachevsky 1991 and Smallenburg 2022):
//! * every particle carries a local clock: its stored position and velocity are valid at
//!   its own time `time[i]`, and it is advanced only when an event involves it;
//! * every particle has exactly one scheduled event, its earliest: a pair collision, a
//!   wall collision or a cell crossing; the `EventQueue` orders particles by it;
//! * a pair event stores the partner's collision counter at prediction time; if the
//!   partner has collided since, the event is stale (section 3.2 of the assignment) and the
//!   particle is simply re-predicted;
//! * neighbours are found through a `CellGrid` whose cells are at least one contact
//!   distance wide, so one prediction checks O(1) grains, never all N.
//!
//! Times are kept relative to a moving origin (`origin`), which is shifted every few
//! collisions per particle, so that after 10^9 collisions event times still carry full
//! double precision.
//!
//! The engine's files, one concept each (all `impl Edmd` blocks of the one struct
//! declared here):
//! * `construct`: building the engine; `access`: the grains by id and by slot, each at the
//!   current time from its local clock;
//! * `events`: the 8-byte scheduled event and its codes; `predict`: a grain's earliest
//!   event (boundary events and pair contacts); `dispatch`: the event loop;
//! * `collide`: the pair and wall collision rules (TC rule, compression's growth);
//! * `look_ahead`: prefetch for the coming events; `layout`: time-origin shifts and the
//!   spatial reordering of the grains;
//! * `collapse`: the inelastic-collapse detector; `compress`: the end of growth;
//!   `velocities`: velocities changed from outside the event loop; `in_flight`: gravity
//!   and the driving changed between two advances; `restart`: grains set
//!   from outside (a new state at a given time);
//! * `observe`, `diagnostics`, `as_engine`: observables, checks, the [`Engine`] trait.
//!
//! [`Engine`]: crate::engine::Engine

mod access;
mod as_engine;
mod collapse;
mod collide;
mod compress;
mod construct;
mod diagnostics;
mod dispatch;
mod drive;
mod events;
mod in_flight;
mod layout;
mod look_ahead;
mod observe;
mod predict;
mod restart;
mod velocities;

pub use collide::CollisionRecord;

use super::candidates::Grain;
use super::queue::EventQueue;
use crate::boundary::SimulationBox;
use crate::collision_law::CollisionLaw;
use crate::neighbours::{Candidates, CellGrid};
use crate::prefetch::CACHE_LINE;
use crate::stats::Histogram;
use crate::vector::Vector;
use aligned_vec::{AVec, ConstAlign};
use collapse::CollapseWatch;
use events::Scheduled;
use serde::{Deserialize, Serialize};

/// Options of the event-driven engine that are not part of the collision law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdmdOptions {
    /// Uniform acceleration (gravity), length / time².
    pub gravity: Vec<f64>,
    /// Inelastic-collapse detector: the run stops when a window of events advances the
    /// time by less than `collapse_ratio` times the time those events would take at the
    /// typical collision rate. Collapse makes this ratio fall geometrically to zero.
    pub collapse_ratio: f64,
    /// Histogram bins of the impact parameter `b / σ` of pair collisions.
    pub impact_bins: usize,
    /// Events between two shifts of the time origin, each followed by a spatial
    /// reordering of the grains; `None`: `8 N + 1024` (about six collisions per grain).
    #[serde(default)]
    pub reorder_interval: Option<u64>,
}

impl Default for EdmdOptions {
    fn default() -> Self {
        Self {
            gravity: Vec::new(),
            collapse_ratio: 1e-6,
            impact_bins: 20,
            reorder_interval: None,
        }
    }
}

/// Running totals the engine keeps for observables.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Totals {
    /// All events processed (collisions, cell crossings, stale predictions).
    pub events: u64,
    /// Grain-grain collisions.
    pub pair_collisions: u64,
    /// Grain-wall collisions.
    pub wall_collisions: u64,
    /// Collisions made elastic by the TC model.
    pub tc_elastic_collisions: u64,
    /// Σ over pair collisions of `(x_i - x_j) · Δp_i` (collisional virial), energy units.
    pub virial: f64,
    /// Σ over wall collisions of the normal momentum transferred to the walls.
    pub wall_impulse: f64,
    /// Kinetic energy lost in inelastic collisions.
    pub dissipated_energy: f64,
}

/// Alignment of the grain records in bytes: one cache line, so that a 64-byte sphere
/// record occupies one line, not two. (The system allocator returns large blocks 16 bytes
/// past a 64-byte boundary, which put every sphere record across two lines; aligned,
/// 10^6 spheres run 14-17 % faster and 10^5 about 7 %. Disk records, 48 bytes, lie
/// across two lines one time in two either way.)
const RECORD_ALIGN: usize = CACHE_LINE;

/// The grain records, aligned to [`RECORD_ALIGN`].
type Records<const D: usize> = AVec<Grain<D>, ConstAlign<RECORD_ALIGN>>;

/// Event-driven molecular dynamics of hard disks (`D = 2`) or spheres (`D = 3`).
///
/// Memory layout (what `granular bench edmd` reports as bytes per particle): one
/// `Grain` record per grain (48 bytes in 2D, 64 in 3D; the array starts at a cache-line
/// boundary), an 8-byte scheduled event, the last partner (4), the event queue (below
/// 2^16 grains a tournament tree, 8 plus 4-8 for the winners; from there on a calendar,
/// 16 plus 4 per bucket, 1.0-2.0 per grain), the cell grid (about 12) and the grain id of
/// each slot (4); radii and masses live in a table of grain kinds (distinct `(radius,
/// mass, species)`), and the TC model's last-collision times are kept only when the model
/// is on. The inverse map (slot of each id, 4 more) exists only between an output that
/// asks for grains by id and the next reordering.
///
/// Grains are stored in cell order and re-sorted every few collisions per grain (spatial
/// reordering), so that a prediction reads neighbours that are close in memory: this
/// keeps the rate at 10^6 grains within a factor of two of the rate at 10^4. Grain *ids*
/// (the order of the input [`ParticleSet`](crate::particles::ParticleSet), of snapshots and of every public accessor)
/// never change; internal indices ("slots") do.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Edmd<const D: usize> {
    bx: SimulationBox<D>,
    law: CollisionLaw,
    gravity: Vector<D>,
    has_gravity: bool,
    /// Radius growth rate per unit radius (Lubachevsky-Stillinger compression), 1/time:
    /// `r_i(t) = radius[i] * (1 + growth * t)` on the internal clock.
    growth: f64,
    options: EdmdOptions,
    grains: Records<D>,
    event: Vec<Scheduled>,
    last_partner: Vec<u32>,
    /// Time of each grain's last collision (TC model only; empty otherwise).
    last_collision: Vec<f64>,
    /// Grain id of each slot.
    id: Vec<u32>,
    /// Slot of each grain id: built on the first query by id (outputs) and dropped at the
    /// next reordering, so that the event loop's memory does not hold it.
    #[serde(skip)]
    slot: std::sync::OnceLock<Vec<u32>>,
    kind_radius: Vec<f64>,
    kind_mass: Vec<f64>,
    kind_species: Vec<u32>,
    /// Rough grains only (empty for smooth ones, which carry no rotation): the reduced
    /// moment of inertia κ of each kind, and the angular velocity of each slot, `d_r`
    /// values per slot (`collision_law::rough::spin_at`). Free flight leaves spins alone.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    kind_inertia: Vec<f64>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    spin: Vec<f64>,
    queue: EventQueue,
    cells: CellGrid<D>,
    species_names: Vec<String>,
    // Clock: absolute time = origin + now.
    now: f64,
    origin: f64,
    events_since_rebase: u64,
    totals: Totals,
    impact: Histogram,

    collapse: CollapseWatch,
    max_radius: f64,
    min_radius: f64,
    /// Collision log (tests and diagnostics), not checkpointed.
    #[serde(skip)]
    log: Option<Vec<CollisionRecord>>,
    /// Scratch list of neighbour candidates of one prediction.
    #[serde(skip)]
    candidates: Candidates,
    /// The steady-state driving ([`crate::driving`], `super::driving`, applied by
    /// `engine/drive.rs`); `None`: free.
    #[serde(default)]
    driving: Option<super::driving::EdmdDriving>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::edmd::equilibrated_fluid;
    use crate::edmd::queue::CalendarQueue;
    use crate::engine::Engine;

    /// The same fluid run with the calendar queue instead of the tournament tree: the
    /// same collisions, in the same order, at the same times to the last bit.
    fn same_trajectory_with_the_calendar<const D: usize>(n: usize, phi: f64) {
        let mut tournament = equilibrated_fluid::<D>(n, phi, 11).expect("fluid");
        assert!(matches!(tournament.queue, EventQueue::Tournament(_)));
        let mut calendar = tournament.clone();
        let mut q = CalendarQueue::new(n);
        for i in 0..n {
            q.update(i, tournament.queue.key(i));
        }
        q.rebuild(calendar.now);
        calendar.queue = EventQueue::Calendar(q);
        for engine in [&mut tournament, &mut calendar] {
            engine.record_collisions(true);
            // Several time-origin shifts and reorderings (every 8 N events).
            engine
                .advance(f64::INFINITY, 40 * n as u64)
                .expect("advance");
        }
        assert!(tournament.collision_log().len() > 10 * n);
        assert_eq!(tournament.collision_log(), calendar.collision_log());
        assert!(matches!(calendar.queue, EventQueue::Calendar(_)));
    }

    #[test]
    fn the_queue_does_not_change_the_trajectory() {
        same_trajectory_with_the_calendar::<2>(400, 0.7);
        same_trajectory_with_the_calendar::<2>(300, 0.2);
        same_trajectory_with_the_calendar::<3>(500, 0.45);
    }
}
