//! The event-driven engine.
//!
//! Algorithm (section 3 of the hard-disk seed, in the one-event-per-particle form of
//! Lubachevsky 1991 and Smallenburg 2022):
//! * every particle carries a local clock: its stored position and velocity are valid at
//!   its own time `time[i]`, and it is advanced only when an event involves it;
//! * every particle has exactly one scheduled event, its earliest: a pair collision, a
//!   wall collision or a cell crossing; the `EventQueue` orders particles by it;
//! * a pair event stores the partner's collision counter at prediction time; if the
//!   partner has collided since, the event is stale (section 3.2 of the seed) and the
//!   particle is simply re-predicted;
//! * neighbours are found through a `CellGrid` whose cells are at least one contact
//!   distance wide, so one prediction checks O(1) grains, never all N.
//!
//! Times are kept relative to a moving origin (`origin`), which is shifted every few
//! collisions per particle, so that after 10^9 collisions event times still carry full
//! double precision.

use super::candidates::{Grain, Probe, earliest_contact, earliest_contacts_pair};
use super::cells::{Candidates, CellGrid, NONE};
use super::prediction::{downward_crossing, pair_contact_time, upward_crossing};
use super::prefetch::{CACHE_LINE, prefetch_all};
use super::queue::EventQueue;
use crate::boundary::SimulationBox;
use crate::collision_law::{CollisionLaw, WallRestitution, normal_velocity_change};
use crate::engine::{Engine, EngineError, Progress, Snapshot};
use crate::observation::{Observation, SpeciesObservation};
use crate::particles::ParticleSet;
use crate::stats::Histogram;
use crate::vector::Vector;
use aligned_vec::{AVec, ConstAlign};
use serde::{Deserialize, Serialize};
use std::hint::select_unpredictable;

/// What a particle's scheduled event is (the public, decoded form of the internal
/// `Scheduled`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// Nothing will ever happen to this particle (it is at rest, without gravity).
    Nothing,
    /// Collision with particle `partner`, valid while its counter equals `partner_counter`.
    Pair {
        /// The other particle (grain id).
        partner: u32,
        /// The partner's collision counter when the event was predicted.
        partner_counter: u32,
    },
    /// Collision with the wall at the low (`upper = false`) or high end of `axis`.
    Wall {
        /// Axis perpendicular to the wall.
        axis: u8,
        /// Whether it is the wall at `x = L` (else `x = 0`).
        upper: bool,
    },
    /// The centre crosses into the neighbouring cell along `axis`.
    CellCrossing {
        /// Axis crossed.
        axis: u8,
        /// Whether the particle moves up (`+1`) or down (`-1`) the axis.
        upward: bool,
    },
}

/// First code of the non-pair events in [`Scheduled::code`]; grain indices stay below it.
const FIRST_SPECIAL: u32 = 1 << 31;
/// Cell-crossing codes: `CROSSING + ((2 axis + upward) << HINT_BITS) + hint`, where the
/// hint is the best pair partner of the prediction that scheduled the crossing (see
/// [`Search::Layer`]), [`HINT_NO_PAIR`] or [`HINT_NONE`].
const CROSSING: u32 = FIRST_SPECIAL;
/// Bits of a crossing code that hold the hint.
const HINT_BITS: u32 = 28;
/// Hint of a crossing scheduled without a usable pair bound: the crossing re-predicts in
/// full.
const HINT_NONE: u32 = (1 << HINT_BITS) - 1;
/// Hint of a crossing scheduled by a prediction that found no pair at all.
const HINT_NO_PAIR: u32 = HINT_NONE - 1;
/// End of the crossing codes (2 directions on each of at most 3 axes).
const CROSSING_END: u32 = CROSSING + (6 << HINT_BITS);
/// Wall codes: `WALL + 2 axis + upper`.
const WALL: u32 = CROSSING_END;
/// Code of "nothing scheduled".
const NOTHING: u32 = u32::MAX;

/// The code of a crossing along `axis` (up or down), without a hint.
#[inline(always)]
fn crossing_code(axis: usize, upward: bool) -> u32 {
    CROSSING + ((2 * axis as u32 + upward as u32) << HINT_BITS)
}

/// `if condition { a } else { b }`, without a branch in 2D (`D == 2`). A boundary
/// event's conditions (the sign of a velocity component; which axis's boundary comes
/// first) are coin tosses, and in 2D selects instead of branches measured +1.5-4 % (2D
/// N = 10^4 to 10^6, in one process); in 3D they measured 0.5-4 % slower (3D N = 10^5),
/// so there the branch stays.
#[inline(always)]
fn choose<const D: usize, T>(condition: bool, a: T, b: T) -> T {
    if D == 2 {
        select_unpredictable(condition, a, b)
    } else if condition {
        a
    } else {
        b
    }
}

/// Axis, direction and hint of a crossing code.
#[inline(always)]
fn decode_crossing(code: u32) -> (usize, bool, u32) {
    let dir = (code - CROSSING) >> HINT_BITS;
    ((dir / 2) as usize, dir % 2 == 1, code & HINT_NONE)
}

/// Which grains a prediction tests as partners.
#[derive(Clone, Copy)]
enum Search {
    /// Every grain of the cells around the grain's cell.
    Full,
    /// After a cell crossing: only the grains of the layer of cells that the crossing made
    /// adjacent, plus `known`, the best partner of the last prediction (`None`: it found
    /// none). Exact because the grain has not collided since that prediction: a grain of
    /// the cells that stay adjacent either has not collided either, and then its contact
    /// time is no earlier than `known`'s (which has not collided: its counter is checked),
    /// or it has, and then it tested this grain itself when it re-predicted. Costs 3 of 9
    /// cells in 2D, 9 of 27 in 3D; no memory (the hint rides in the crossing's code).
    Layer {
        axis: usize,
        step: i32,
        known: Option<u32>,
    },
}

/// A scheduled event in 8 bytes: a partner index (or a code above every index for walls,
/// cell crossings and "nothing") and the partner's collision counter at prediction time
/// (for a crossing with a hint: the hinted partner's counter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Scheduled {
    code: u32,
    partner_counter: u32,
}

impl Scheduled {
    const NOTHING: Scheduled = Scheduled {
        code: NOTHING,
        partner_counter: 0,
    };
}

/// One collision in the optional collision log ([`Edmd::record_collisions`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionRecord {
    /// Absolute time of the collision.
    pub time: f64,
    /// Grain id.
    pub i: u32,
    /// Partner grain id, or `None` for a wall.
    pub j: Option<u32>,
}

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

/// Inelastic-collapse detector state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct CollapseWatch {
    window_start_events: u64,
    window_start_time: f64,
    /// Pair collisions and time since the start of the run at the starts of the last two
    /// windows (the earlier one first), for the mean free time before a collapse: the
    /// collapse's own collisions, in the window that detects it and perhaps the one before,
    /// would shrink it by orders of magnitude. Only for the advice, so not in checkpoints:
    /// the first windows after a resume fall back to the run's mean free time.
    #[serde(skip)]
    starts: [Option<(u64, f64)>; 2],
}

/// Events per collapse-detector window in systems of up to 2^14 grains; larger ones
/// watch over 4 events per grain ([`Edmd::collapse_window`]).
const COLLAPSE_WINDOW: u64 = 1 << 16;

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
/// (the order of the input [`ParticleSet`], of snapshots and of every public accessor)
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
    /// The steady-state driving ([`crate::driving`], `super::driving`); `None`: free.
    #[serde(default)]
    pub(super) driving: Option<super::driving::EdmdDriving>,
}

impl<const D: usize> Edmd<D> {
    /// Builds the engine from grains in a box. The grains must not overlap (see
    /// [`crate::edmd::init`] for placements); the caller validates inputs.
    pub fn new(
        bx: SimulationBox<D>,
        particles: ParticleSet<D>,
        law: CollisionLaw,
        options: EdmdOptions,
    ) -> Self {
        Self::with_growth(bx, particles, law, options, 0.0, 1.0)
    }

    /// Like [`Edmd::new`], with radii growing at relative rate `growth` and cells sized for
    /// radii up to `radius_scale` times the initial ones (compression).
    pub(crate) fn with_growth(
        bx: SimulationBox<D>,
        particles: ParticleSet<D>,
        law: CollisionLaw,
        options: EdmdOptions,
        growth: f64,
        radius_scale: f64,
    ) -> Self {
        let n = particles.len();
        assert!(
            (n as u64) < FIRST_SPECIAL as u64,
            "the event-driven engine holds fewer than {FIRST_SPECIAL} grains"
        );
        let mut gravity = Vector::zero();
        for (k, g) in options.gravity.iter().enumerate().take(D) {
            gravity[k] = *g;
        }
        let has_gravity = gravity.norm_squared() > 0.0;
        let max_radius = particles.radii.iter().cloned().fold(0.0, f64::max);
        let min_radius = particles
            .radii
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        // Grain kinds: distinct (radius, mass, species), numbered by first appearance.
        let mut kinds: std::collections::HashMap<(u64, u64, u32), u32> = Default::default();
        let (mut kind_radius, mut kind_mass, mut kind_species) = (vec![], vec![], vec![]);
        let mut grains = Records::with_capacity(RECORD_ALIGN, n);
        for i in 0..n {
            let (r, m) = (particles.radii[i], particles.masses[i]);
            let s = particles.species.get(i).copied().unwrap_or(0);
            let kind = *kinds
                .entry((r.to_bits(), m.to_bits(), s))
                .or_insert_with(|| {
                    kind_radius.push(r);
                    kind_mass.push(m);
                    kind_species.push(s);
                    (kind_radius.len() - 1) as u32
                });
            let mut x = particles.positions[i];
            bx.wrap(&mut x);
            grains.push(Grain {
                pos: x,
                vel: particles.velocities[i],
                time: 0.0,
                counter: 0,
                kind,
            });
        }
        // A few grains much larger than the rest stay out of the cell lists, so that
        // the cells fit the others (`cells::large_grain_cut`; not while radii grow).
        let (cells, cut) = CellGrid::for_radii(&bx, &particles.radii, radius_scale, growth == 0.0);
        let impact = Histogram::new(0.0, 1.0 + 1e-12, options.impact_bins.max(1));
        let last_collision = if law.contact_duration > 0.0 {
            vec![f64::NEG_INFINITY; n]
        } else {
            Vec::new()
        };
        let mut engine = Self {
            law,
            gravity,
            has_gravity,
            growth,
            options,
            grains,
            event: vec![Scheduled::NOTHING; n],
            last_partner: vec![NONE; n],
            last_collision,
            id: (0..n as u32).collect(),
            slot: std::sync::OnceLock::new(),
            kind_radius,
            kind_mass,
            kind_species,
            queue: EventQueue::new(n),
            cells,
            species_names: particles.species_names,
            now: 0.0,
            origin: 0.0,
            events_since_rebase: 0,
            totals: Totals::default(),
            impact,
            collapse: CollapseWatch::default(),
            max_radius,
            min_radius,
            bx,
            log: None,
            candidates: Candidates::default(),
            driving: None,
        };
        for i in 0..n {
            let c = engine.cells.coords_of(&engine.grains[i].pos.0);
            let r = engine.base_radius(i);
            engine.cells.insert_grain(i, c, r, cut);
        }
        engine.reorder();
        for i in 0..n {
            engine.predict(i);
        }
        engine.queue.rebuild(engine.now);
        engine
    }

    /// The box.
    pub fn simulation_box(&self) -> &SimulationBox<D> {
        &self.bx
    }

    /// The collision law.
    pub fn collision_law(&self) -> &CollisionLaw {
        &self.law
    }

    /// Replaces the collision law (takes effect from the next collision).
    pub fn set_collision_law(&mut self, law: CollisionLaw) {
        if law.contact_duration > 0.0 && self.last_collision.is_empty() {
            self.last_collision = vec![f64::NEG_INFINITY; self.len()];
        }
        self.law = law;
    }

    /// Running totals (collision counts, virial, dissipated energy).
    pub fn totals(&self) -> &Totals {
        &self.totals
    }

    /// Histogram of the normalised impact parameter `b / σ` of all pair collisions so far.
    pub fn impact_histogram(&self) -> &Histogram {
        &self.impact
    }

    /// Clears the impact-parameter histogram (to measure it over a time window).
    pub fn reset_impact_histogram(&mut self) {
        let bins = self.impact.counts.len();
        self.impact = Histogram::new(0.0, 1.0 + 1e-12, bins);
    }

    /// Starts (or stops, with `false`) recording every collision in a log, in the order
    /// processed ([`Edmd::collision_log`]). For tests and diagnostics: it grows without
    /// bound.
    pub fn record_collisions(&mut self, on: bool) {
        self.log = if on { Some(Vec::new()) } else { None };
    }

    /// The collisions recorded since [`Edmd::record_collisions`] was switched on.
    pub fn collision_log(&self) -> &[CollisionRecord] {
        self.log.as_deref().unwrap_or(&[])
    }

    /// Number of grains.
    pub fn len(&self) -> usize {
        self.grains.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.grains.is_empty()
    }

    /// Masses of the grains, by id.
    pub fn masses(&self) -> Vec<f64> {
        self.by_id(|e, s| e.mass(s))
    }

    /// Species of the grains, by id.
    pub fn species(&self) -> Vec<u32> {
        self.by_id(|e, s| e.kind_species[e.grains[s].kind as usize])
    }

    /// Species names.
    pub fn species_names(&self) -> &[String] {
        &self.species_names
    }

    /// The scheduled event of grain `id` (partners as grain ids).
    pub fn scheduled_event(&self, id: usize) -> EventKind {
        let e = self.event[self.slot_of(id)];
        match e.code {
            NOTHING => EventKind::Nothing,
            c if c >= WALL => EventKind::Wall {
                axis: ((c - WALL) / 2) as u8,
                upper: (c - WALL) % 2 == 1,
            },
            c if c >= CROSSING => {
                let (axis, upward, _) = decode_crossing(c);
                EventKind::CellCrossing {
                    axis: axis as u8,
                    upward,
                }
            }
            c => EventKind::Pair {
                partner: self.id[c as usize],
                partner_counter: e.partner_counter,
            },
        }
    }

    /// `f(self, slot)` for every grain, in id order.
    fn by_id<T>(&self, f: impl Fn(&Self, usize) -> T) -> Vec<T> {
        self.slots().iter().map(|&s| f(self, s as usize)).collect()
    }

    /// The slot of each grain id (see the field `slot`).
    fn slots(&self) -> &[u32] {
        self.slot.get_or_init(|| {
            let mut slot = vec![0u32; self.id.len()];
            for (s, &g) in self.id.iter().enumerate() {
                slot[g as usize] = s as u32;
            }
            slot
        })
    }

    /// The slot of grain `id`.
    fn slot_of(&self, id: usize) -> usize {
        self.slots()[id] as usize
    }

    #[inline(always)]
    fn mass(&self, s: usize) -> f64 {
        self.kind_mass[self.grains[s].kind as usize]
    }

    #[inline(always)]
    fn base_radius(&self, s: usize) -> f64 {
        self.kind_radius[self.grains[s].kind as usize]
    }

    /// Current radius of slot `s` (differs from the initial one only during compression).
    #[inline(always)]
    fn radius_now(&self, s: usize) -> f64 {
        if self.growth == 0.0 {
            self.base_radius(s)
        } else {
            self.base_radius(s) * (1.0 + self.growth * self.now)
        }
    }

    /// Radii at the current time, by id.
    pub fn radii(&self) -> Vec<f64> {
        self.by_id(|e, s| e.radius_now(s))
    }

    /// Position of grain `id` at the current time (not stored: observing never perturbs
    /// the trajectory).
    pub fn position(&self, id: usize) -> Vector<D> {
        let mut x = self.position_raw(self.slot_of(id));
        self.bx.wrap(&mut x);
        x
    }

    /// Velocity of grain `id` at the current time.
    pub fn velocity(&self, id: usize) -> Vector<D> {
        self.velocity_slot(self.slot_of(id))
    }

    #[inline(always)]
    fn velocity_slot(&self, s: usize) -> Vector<D> {
        let g = &self.grains[s];
        if self.has_gravity {
            g.vel.add_scaled(self.now - g.time, &self.gravity)
        } else {
            g.vel
        }
    }

    /// Unwrapped position of slot `s` at the current time (HD-6; may lie outside the box by
    /// round-off).
    #[inline(always)]
    fn position_raw(&self, s: usize) -> Vector<D> {
        let g = &self.grains[s];
        let dt = self.now - g.time;
        let x = g.pos.add_scaled(dt, &g.vel);
        if self.has_gravity {
            x.add_scaled(0.5 * dt * dt, &self.gravity)
        } else {
            x
        }
    }

    /// Brings slot `s`'s stored state to the current time.
    #[inline(always)]
    fn advance_particle(&mut self, s: usize) {
        let dt = self.now - self.grains[s].time;
        if dt != 0.0 {
            let x = self.position_raw(s);
            let v = self.velocity_slot(s);
            let g = &mut self.grains[s];
            g.pos = x;
            g.vel = v;
        }
        self.grains[s].time = self.now;
    }

    /// Predicts slot `i`'s earliest event from its state at the current time (which must
    /// be stored, `time == now`) and puts it in the queue.
    fn predict(&mut self, i: usize) {
        let key = self.predict_with(i, Search::Full);
        self.queue.update(i, key);
    }

    /// [`Edmd::predict`] testing the partners `search` says, without the queue: returns
    /// the event's time, for the caller to put in the queue.
    fn predict_with(&mut self, i: usize, search: Search) -> f64 {
        debug_assert_eq!(self.grains[i].time, self.now);
        let coords = self.cells.coords(i);
        let (best, code) = self.boundary_event(i, &coords);
        // The earliest pair at any time (not only before the boundary event): a crossing
        // keeps it as the bound for its own prediction.
        let mut best_pair = f64::INFINITY;
        let mut partner = NONE;
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        let has_large = !self.cells.large().is_empty();
        if has_large {
            self.gather_with_large(i, &coords, search, &mut candidates);
        } else {
            self.gather(&coords, search, &mut candidates);
        }
        let candidates_now = candidates.as_slice();
        prefetch_all(&self.grains, candidates_now);
        if self.growth == 0.0 {
            // A layer search may test a hinted partner beyond the neighbouring cells, and
            // large grains lie anywhere.
            let wrap =
                has_large || !matches!(search, Search::Full) || !self.cells.without_wrap(&[coords]);
            let probe = self.probe(i, wrap);
            (best_pair, partner) = earliest_contact(
                &self.grains,
                &self.kind_radius,
                candidates_now,
                &probe,
                best_pair,
            );
        } else {
            // Lubachevsky-Stillinger compression: radii grow with time.
            let Grain {
                pos: xi, vel: vi, ..
            } = self.grains[i];
            let (ri, rate_i, now) = (
                self.radius_now(i),
                self.base_radius(i) * self.growth,
                self.now,
            );
            let skip = self.separating_partner(i);
            for &j in candidates_now {
                if j == i as u32 || j == skip {
                    continue;
                }
                let xj = self.position_raw(j as usize);
                let dx = self.bx.separation(&xi, &xj);
                let dv = self.velocity_slot(j as usize) - vi;
                let rj = self.base_radius(j as usize);
                let t = pair_contact_time(
                    dx.dot(&dv),
                    dx.norm_squared(),
                    dv.norm_squared(),
                    ri + rj * (1.0 + self.growth * now),
                    rate_i + rj * self.growth,
                )
                .unwrap_or(f64::INFINITY);
                if t < best_pair {
                    best_pair = t;
                    partner = j;
                }
            }
        }
        self.candidates = candidates;
        self.schedule(i, best, code, best_pair, partner)
    }

    /// The candidates of slot `i` (in cell `coords`) in a system with large grains
    /// (`cells::large_grain_cut`): for a large grain, the cells within its reach and the
    /// other large grains; for any other grain, what `search` says and every large grain.
    /// Out of line, so that the usual systems' predictions stay as they were.
    #[inline(never)]
    #[cold]
    fn gather_with_large(
        &self,
        i: usize,
        coords: &[u32; D],
        search: Search,
        candidates: &mut Candidates,
    ) {
        if self.cells.is_large(i) {
            self.cells.gather_reach(i, coords, candidates);
            return;
        }
        self.gather(coords, search, candidates);
        candidates.extend_from(self.cells.large());
    }

    /// The candidates `search` says, around cell `coords` (large grains aside).
    #[inline(always)]
    fn gather(&self, coords: &[u32; D], search: Search, candidates: &mut Candidates) {
        match search {
            Search::Full => self.cells.gather_neighbours(coords, candidates),
            Search::Layer { axis, step, known } => {
                self.cells.gather_layer(coords, axis, step, candidates);
                if let Some(j) = known {
                    candidates.push(j);
                }
            }
        }
    }

    /// [`Edmd::predict`] for both grains of a pair collision (`i` first, then `j`, as
    /// two calls would), in 2D: one gather of the union of their neighbourhoods and one
    /// pass over it that tests each candidate against both (`earliest_contacts_pair`;
    /// +3-6 % in 2D, slower in 3D). Each grain also tests its partner's neighbours, which
    /// stays exact: a contact found with one of them is real (that grain must cross into
    /// the neighbourhood first, which changes no velocity), and a pair beyond the grain's
    /// own crossing only becomes the crossing's hint, whose bound then holds over more
    /// grains than the layer search needs. Grains with growing radii, and systems with
    /// large grains (`cells::large_grain_cut`), take the one-grain path.
    fn predict_pair(&mut self, i: usize, j: usize) {
        if D != 2 || self.growth != 0.0 || !self.cells.large().is_empty() {
            let key_i = self.predict_with(i, Search::Full);
            let key_j = self.predict_with(j, Search::Full);
            self.queue.update_pair(i, key_i, j, key_j);
            return;
        }
        debug_assert!(self.grains[i].time == self.now && self.grains[j].time == self.now);
        let coords_i = self.cells.coords(i);
        let coords_j = self.cells.coords(j);
        let (best_i, code_i) = self.boundary_event(i, &coords_i);
        let (best_j, code_j) = self.boundary_event(j, &coords_j);
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        self.cells
            .gather_pair(&coords_i, &coords_j, &mut candidates);
        let candidates_now = candidates.as_slice();
        prefetch_all(&self.grains, candidates_now);
        let wrap = !self.cells.without_wrap(&[coords_i, coords_j]);
        let [(pair_i, partner_i), (pair_j, partner_j)] = earliest_contacts_pair(
            &self.grains,
            &self.kind_radius,
            candidates_now,
            [&self.probe(i, wrap), &self.probe(j, wrap)],
        );
        self.candidates = candidates;
        let key_i = self.schedule(i, best_i, code_i, pair_i, partner_i);
        let key_j = self.schedule(j, best_j, code_j, pair_j, partner_j);
        self.queue.update_pair(i, key_i, j, key_j);
    }

    /// What a contact search needs to know about slot `i` (its state stored at the
    /// current time) and the box; `wrap`: whether its candidates may need the minimum
    /// image.
    #[inline(always)]
    fn probe(&self, i: usize, wrap: bool) -> Probe<'_, D> {
        Probe {
            slot: i as u32,
            skip: self.separating_partner(i),
            pos: self.grains[i].pos,
            vel: self.grains[i].vel,
            radius: self.radius_now(i),
            now: self.now,
            gravity: self.has_gravity.then_some(self.gravity),
            bx: &self.bx,
            wrap,
        }
    }

    /// The earliest boundary event of slot `i` (in cell `coords`, its state stored at
    /// the current time): a cell crossing or a wall collision (HD-1, HD-2), as (time
    /// from now, code), or `(∞, NOTHING)`.
    #[inline(always)]
    fn boundary_event(&self, i: usize, coords: &[u32; D]) -> (f64, u32) {
        let Grain {
            pos: xi, vel: vi, ..
        } = self.grains[i];
        let ri = self.radius_now(i);
        let rate_i = self.base_radius(i) * self.growth;
        let half_g = self.gravity * 0.5;
        let mut best = f64::INFINITY;
        let mut code = NOTHING;
        for k in 0..D {
            let n = self.cells.counts[k];
            let periodic = self.bx.is_periodic(k);
            let w = self.cells.widths[k];
            let ck = coords[k] as usize;
            let (v, a) = (vi[k], half_g[k]);
            if a == 0.0 && rate_i == 0.0 {
                // Uniform motion along k: only the boundaries ahead can be reached. The
                // arithmetic of `upward_crossing`/`downward_crossing` with a = 0, without
                // their branches on the sign of v (a coin toss; see `choose`).
                if v != 0.0 {
                    let up = v > 0.0;
                    // The cell boundary ahead (none at a walled face: the wall comes first).
                    let has_cell = periodic || if up { ck + 1 < n } else { ck > 0 };
                    let ahead = ck + up as usize;
                    let bound = choose::<D, _>(ahead == n, self.bx.lengths[k], ahead as f64 * w);
                    let t = (-(xi[k] - bound) / v).max(0.0);
                    let earlier = has_cell & (t < best);
                    best = choose::<D, _>(earlier, t, best);
                    code = choose::<D, _>(earlier, crossing_code(k, up), code);
                    if !periodic {
                        let c = choose::<D, _>(up, xi[k] + ri - self.bx.lengths[k], xi[k] - ri);
                        let t = (-c / v).max(0.0);
                        let earlier = t < best;
                        best = choose::<D, _>(earlier, t, best);
                        code = choose::<D, _>(earlier, WALL + 2 * k as u32 + up as u32, code);
                    }
                }
                continue;
            }
            // Cell boundaries (walled box faces excluded: the wall comes first).
            if periodic || ck + 1 < n {
                let hi = if ck + 1 == n {
                    self.bx.lengths[k]
                } else {
                    (ck + 1) as f64 * w
                };
                if let Some(t) = upward_crossing(xi[k] - hi, v, a)
                    && t < best
                {
                    best = t;
                    code = crossing_code(k, true);
                }
            }
            if periodic || ck > 0 {
                let lo = ck as f64 * w;
                if let Some(t) = downward_crossing(xi[k] - lo, v, a)
                    && t < best
                {
                    best = t;
                    code = crossing_code(k, false);
                }
            }
            if !periodic {
                let l = self.bx.lengths[k];
                if let Some(t) = upward_crossing(xi[k] + ri - l, v + rate_i, a)
                    && t < best
                {
                    best = t;
                    code = WALL + 2 * k as u32 + 1;
                }
                if let Some(t) = downward_crossing(xi[k] - ri, v - rate_i, a)
                    && t < best
                {
                    best = t;
                    code = WALL + 2 * k as u32;
                }
            }
        }
        (best, code)
    }

    /// The partner slot `i` must not be tested against: the partner of its last
    /// collision while the two are each other's last partners (they are separating, and
    /// round-off must not make them collide again: at restitution 0 they would, forever,
    /// at zero time intervals), or `NONE`.
    #[inline(always)]
    fn separating_partner(&self, i: usize) -> u32 {
        let p = self.last_partner[i];
        if p != NONE && self.last_partner[p as usize] == i as u32 {
            p
        } else {
            NONE
        }
    }

    /// Schedules slot `i`'s earliest event: the boundary event `(best, code)` or, if
    /// earlier, the pair contact `(best_pair, partner)` (`partner == NONE`: none found).
    /// A crossing carries the pair as the hint of its layer search. Returns the event's
    /// time, for the caller to put in the queue.
    #[inline(always)]
    fn schedule(
        &mut self,
        i: usize,
        mut best: f64,
        mut code: u32,
        best_pair: f64,
        partner: u32,
    ) -> f64 {
        let now = self.now;
        let mut partner_counter = 0;
        if partner != NONE && best_pair < best {
            best = best_pair;
            code = partner;
            partner_counter = self.grains[partner as usize].counter;
        } else if (CROSSING..CROSSING_END).contains(&code) {
            code += if self.growth != 0.0 || self.len() >= HINT_NO_PAIR as usize {
                HINT_NONE
            } else if partner == NONE {
                HINT_NO_PAIR
            } else {
                partner_counter = self.grains[partner as usize].counter;
                partner
            };
        }
        self.event[i] = Scheduled {
            code,
            partner_counter,
        };
        now + best
    }

    /// Processes the earliest event, of slot `i`. The clock must already be at its time.
    fn process(&mut self, i: usize) -> Result<(), EngineError> {
        self.totals.events += 1;
        self.events_since_rebase += 1;
        let Scheduled {
            code,
            partner_counter,
        } = self.event[i];
        if code < FIRST_SPECIAL {
            let j = code as usize;
            self.advance_particle(i);
            if self.grains[j].counter != partner_counter {
                self.predict(i);
                return Ok(());
            }
            self.advance_particle(j);
            self.collide_pair(i, j);
            self.predict_pair(i, j);
        } else if code < CROSSING_END {
            self.advance_particle(i);
            let (k, upward, hint) = decode_crossing(code);
            let step = if upward { 1 } else { -1 };
            if self.cells.shift(i, k, step) {
                let l = self.bx.lengths[k];
                self.grains[i].pos[k] += if upward { -l } else { l };
            }
            let search = match hint {
                HINT_NONE => Search::Full,
                HINT_NO_PAIR => Search::Layer {
                    axis: k,
                    step,
                    known: None,
                },
                j if self.grains[j as usize].counter == partner_counter => Search::Layer {
                    axis: k,
                    step,
                    known: Some(j),
                },
                _ => Search::Full,
            };
            let key = self.predict_with(i, search);
            self.queue.update(i, key);
        } else if code != NOTHING {
            self.advance_particle(i);
            self.collide_wall(i, ((code - WALL) / 2) as usize, (code - WALL) % 2 == 1);
            self.predict(i);
        } else {
            return Err(EngineError::Numerical(format!(
                "particle {} scheduled an empty event at a finite time",
                self.id[i]
            )));
        }
        Ok(())
    }

    /// The pair restitution for a collision now of slots `a` and `b` under the TC rule of
    /// the collision law, counted in the totals.
    #[inline(always)]
    fn pair_restitution(&mut self, a: usize, b: usize) -> f64 {
        let tc = &mut self.totals.tc_elastic_collisions;
        if self.last_collision.is_empty() {
            return self.law.pair_restitution(self.now, &[], tc);
        }
        let last = [self.last_collision[a], self.last_collision[b]];
        self.law.pair_restitution(self.now, &last, tc)
    }

    /// The wall restitutions for a collision now of slot `a` under the TC rule of the
    /// collision law, counted in the totals.
    #[inline(always)]
    fn wall_restitution(&mut self, a: usize) -> WallRestitution {
        let tc = &mut self.totals.tc_elastic_collisions;
        if self.last_collision.is_empty() {
            return self.law.wall_restitution_now(self.now, &[], tc);
        }
        let last = [self.last_collision[a]];
        self.law.wall_restitution_now(self.now, &last, tc)
    }

    /// Resolves a pair collision (HD-11), both grains at `now`.
    fn collide_pair(&mut self, i: usize, j: usize) {
        let dx = self.bx.separation(&self.grains[i].pos, &self.grains[j].pos);
        let dv = self.grains[j].vel - self.grains[i].vel;
        let d2 = dx.norm_squared();
        let b = dx.dot(&dv);
        let (mi, mj) = (self.mass(i), self.mass(j));
        let mu = mi * mj / (mi + mj);
        // The normal relative velocity is u_n = b / d (negative when approaching), and
        // its change du = g d along the unit normal dx / d, so the velocities change by
        // -+ (mu / m) g dx: with g = -(1 + xi) b / d², no square root on the way from
        // one event to the next.
        let g = if self.growth == 0.0 {
            let xi = self.pair_restitution(i, j);
            normal_velocity_change(xi, b) / d2
        } else {
            // Lubachevsky-Stillinger: elastic reflection in the frame of the growing
            // surfaces, so that they separate at least as fast as they grow.
            let rate = (self.base_radius(i) + self.base_radius(j)) * self.growth;
            let d = d2.sqrt();
            2.0 * (rate - b / d) / d
        };
        self.grains[i].vel = self.grains[i].vel.add_scaled(-mu / mi * g, &dx);
        self.grains[j].vel = self.grains[j].vel.add_scaled(mu / mj * g, &dx);
        // u_n² - u_n'² = (b² - (b + g d²)²) / d², and the virial mu du d = mu g d².
        let b_after = b + g * d2;
        self.totals.dissipated_energy += 0.5 * mu * (b * b - b_after * b_after) / d2;
        self.totals.virial += mu * g * d2;
        self.totals.pair_collisions += 1;
        let dv2 = dv.norm_squared();
        if dv2 > 0.0 {
            let cos2 = (b * b / (d2 * dv2)).min(1.0);
            self.impact.push((1.0 - cos2).sqrt());
        }
        self.grains[i].counter = self.grains[i].counter.wrapping_add(1);
        self.grains[j].counter = self.grains[j].counter.wrapping_add(1);
        if !self.last_collision.is_empty() {
            self.last_collision[i] = self.now;
            self.last_collision[j] = self.now;
        }
        self.last_partner[i] = j as u32;
        self.last_partner[j] = i as u32;
        if let Some(log) = &mut self.log {
            log.push(CollisionRecord {
                time: self.origin + self.now,
                i: self.id[i],
                j: Some(self.id[j]),
            });
        }
    }

    /// Resolves a wall collision (HD-3, HD-4).
    fn collide_wall(&mut self, i: usize, axis: usize, upper: bool) {
        let v = self.grains[i].vel;
        let m = self.mass(i);
        let k0 = 0.5 * m * v.norm_squared();
        let mut v_new = v;
        if self.growth == 0.0 {
            v_new = self.wall_restitution(i).apply(&v, axis);
        } else {
            let rate = self.base_radius(i) * self.growth;
            v_new[axis] = if upper {
                -v[axis] - 2.0 * rate
            } else {
                -v[axis] + 2.0 * rate
            };
        }
        self.grains[i].vel = v_new;
        self.totals.wall_impulse += m * (v[axis] - v_new[axis]).abs();
        self.totals.dissipated_energy += k0 - 0.5 * m * v_new.norm_squared();
        self.totals.wall_collisions += 1;
        self.grains[i].counter = self.grains[i].counter.wrapping_add(1);
        if !self.last_collision.is_empty() {
            self.last_collision[i] = self.now;
        }
        self.last_partner[i] = NONE;
        if let Some(log) = &mut self.log {
            log.push(CollisionRecord {
                time: self.origin + self.now,
                i: self.id[i],
                j: None,
            });
        }
    }

    /// Prefetch in stages for the events about to come, which in large systems are cache
    /// misses (+8-29 % at 10^5-10^6 grains; see `docs/edmd.md`). First stage: the grain
    /// the queue's look-ahead has reached (its event comes up in the next bucket): its
    /// record, its scheduled event and its cell index. Second stage, one event later, for
    /// the grain of the first stage (whose event and cell index are now in cache): its
    /// partner's record and queue links (which the partner's update reads to unlink it
    /// from its bucket: +1-3 % at 10^6 grains) and the cell heads around it. `coming`
    /// carries the first stage's grain to the second, `earlier` the second's to the
    /// third. Hints only: a grain relabelled or re-predicted meanwhile costs a useless
    /// prefetch, never a wrong result.
    #[inline(always)]
    fn prefetch_coming(&self, coming: &mut usize, earlier: &mut usize) {
        // Third stage, in 2D only, one more event later (the heads are now in cache): the
        // first grain of each of the 9 neighbouring cells, its record and list link
        // (+5-7 % at 10^6 disks, +2 % at 10^5), and the cell heads around the partner
        // (+4-7 % at 10^6, -1 % at 10^5). In 3D the 27 cells' prefetches cost more than
        // they save (-3 % at 10^6 spheres and -8 % at 10^5 for the first grains; -3 % at
        // 10^5 for the partner's heads).
        if D == 2
            && let Some(e) = self.event.get(*earlier)
        {
            self.cells.prefetch_first_grains(*earlier, &self.grains);
            if e.code < FIRST_SPECIAL {
                self.cells.prefetch_heads(e.code as usize);
            }
        }
        *earlier = *coming;
        if let Some(e) = self.event.get(*coming) {
            if e.code < FIRST_SPECIAL {
                prefetch_all(&self.grains, &[e.code]);
                prefetch_all(&self.last_collision, &[e.code]);
                self.queue.prefetch_links(e.code);
                if D == 2 {
                    self.cells.prefetch_cell_index(e.code as usize);
                }
            }
            self.cells.prefetch_heads(*coming);
        }
        *coming = match self.queue.ahead() {
            Some(h) => {
                prefetch_all(&self.grains, &[h as u32]);
                prefetch_all(&self.event, &[h as u32]);
                prefetch_all(&self.last_collision, &[h as u32]);
                self.cells.prefetch_cell_index(h);
                h
            }
            None => usize::MAX,
        };
    }

    /// Moves the time origin to the current time: all grains are advanced to `now`, and
    /// every stored time is shifted, so that times stay small numbers. Then re-sorts the
    /// grains in cell order.
    fn rebase(&mut self) {
        if self.growth != 0.0 || self.now == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
            self.grains[i].time = 0.0;
        }
        for t in &mut self.last_collision {
            *t -= self.now;
        }
        self.queue.shift(self.now, 0.0);
        self.collapse.window_start_time -= self.now;
        self.origin += self.now;
        self.now = 0.0;
        self.events_since_rebase = 0;
        self.reorder();
    }

    /// Spatial reordering: stores the grains in cell order, so that the grains a
    /// prediction visits are close in memory. Only slots change; every event, counter and
    /// clock moves with its grain, so the trajectory is the same.
    fn reorder(&mut self) {
        let order = self.cells.cell_order();
        let n = self.len();
        if order.len() != n {
            return;
        }
        let mut new_of_old = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_of_old[old as usize] = new as u32;
        }
        let map = |x: u32| {
            if x < FIRST_SPECIAL {
                new_of_old[x as usize]
            } else if x < CROSSING_END {
                // A crossing: relabel its partner hint, if it holds one.
                let (_, _, hint) = decode_crossing(x);
                if hint < HINT_NO_PAIR {
                    x - hint + new_of_old[hint as usize]
                } else {
                    x
                }
            } else {
                x
            }
        };
        self.grains =
            Records::from_iter(RECORD_ALIGN, order.iter().map(|&o| self.grains[o as usize]));
        let event = order
            .iter()
            .map(|&o| {
                let e = self.event[o as usize];
                Scheduled {
                    code: map(e.code),
                    partner_counter: e.partner_counter,
                }
            })
            .collect();
        self.event = event;
        let last_partner = order
            .iter()
            .map(|&o| map(self.last_partner[o as usize]))
            .collect();
        self.last_partner = last_partner;
        if !self.last_collision.is_empty() {
            let lc = order
                .iter()
                .map(|&o| self.last_collision[o as usize])
                .collect();
            self.last_collision = lc;
        }
        self.id = order.iter().map(|&o| self.id[o as usize]).collect();
        self.slot = std::sync::OnceLock::new();
        self.queue.relabel(&new_of_old, self.now);
        self.cells.relabel(&new_of_old);
    }

    /// Total kinetic energy, `Σ m v² / 2`.
    pub fn kinetic_energy_now(&self) -> f64 {
        (0..self.len())
            .map(|s| 0.5 * self.mass(s) * self.velocity_slot(s).norm_squared())
            .sum()
    }

    /// Total momentum.
    pub fn momentum(&self) -> Vector<D> {
        let mut p = Vector::zero();
        for s in 0..self.len() {
            p = p.add_scaled(self.mass(s), &self.velocity_slot(s));
        }
        p
    }

    /// The largest overlap `σ_ij - |x_i - x_j|` over all touching pairs at the current time
    /// (zero or round-off for a correct run), and the largest wall penetration.
    pub fn max_overlap(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..self.len() {
            let xi = self.position_raw(i);
            let ri = self.radius_now(i);
            for k in 0..D {
                if !self.bx.is_periodic(k) {
                    worst = worst.max(ri - xi[k]).max(xi[k] + ri - self.bx.lengths[k]);
                }
            }
            self.cells.for_each_candidate(i, |j| {
                if j > i {
                    let d = self.bx.separation(&xi, &self.position_raw(j)).norm();
                    worst = worst.max(ri + self.radius_now(j) - d);
                }
            });
        }
        worst
    }

    /// Mean time between collisions of one grain over the whole run so far.
    pub fn mean_free_time_so_far(&self) -> f64 {
        let t = self.origin + self.now;
        if self.totals.pair_collisions == 0 {
            f64::INFINITY
        } else {
            self.len() as f64 * t / (2.0 * self.totals.pair_collisions as f64)
        }
    }

    /// Events per collapse-detector window: at least 4 per grain, because each check
    /// reads every grain (the kinetic energy and the total mass). With a fixed 2^16, 10^6
    /// inelastic disks spent 14 % of their time on those reads and the cache misses after
    /// them.
    fn collapse_window(&self) -> u64 {
        COLLAPSE_WINDOW.max(4 * self.len() as u64)
    }

    fn check_collapse(&mut self) -> Result<(), EngineError> {
        let events = self.totals.events - self.collapse.window_start_events;
        if events < self.collapse_window() {
            return Ok(());
        }
        let elapsed = self.now - self.collapse.window_start_time;
        self.collapse.window_start_events = self.totals.events;
        self.collapse.window_start_time = self.now;
        let before = self.collapse.starts[0];
        self.collapse.starts = [
            self.collapse.starts[1],
            Some((self.totals.pair_collisions, self.origin + self.now)),
        ];
        if self.law.is_elastic() || self.growth != 0.0 {
            return Ok(());
        }
        let total_mass: f64 = (0..self.len()).map(|s| self.mass(s)).sum();
        let v_typ = (2.0 * self.kinetic_energy_now() / total_mass).sqrt();
        // Grains all at rest have no time scale, unless their events took no time at all
        // (a grain stopped on a perfectly inelastic floor under gravity).
        if v_typ == 0.0 && elapsed > 0.0 {
            return Ok(());
        }
        // Time those events take at one collision per grain per time a grain needs to
        // cross its own diameter at the typical speed: a generous upper bound on rates.
        let natural = events as f64 / self.len() as f64 * 2.0 * self.min_radius / v_typ;
        if elapsed < self.options.collapse_ratio * natural {
            // The mean free time up to two windows ago, before the collapse began.
            let tau = match before {
                Some((c, t)) if c > 0 => self.len() as f64 * t / (2.0 * c as f64),
                _ => self.mean_free_time_so_far(),
            };
            let tau = if tau.is_finite() {
                tau
            } else {
                2.0 * self.min_radius / v_typ
            };
            return Err(EngineError::Collapse(format!(
                "inelastic collapse at t = {:.6e}: the last {events} events advanced the time by \
                 only {elapsed:.3e} (grains collide ever faster in a shrinking cluster; \
                 restitution {}). {}",
                self.origin + self.now,
                self.law.restitution,
                self.collapse_advice(tau),
            )));
        }
        Ok(())
    }

    /// What to change after a collapse, given the mean free time `tau` before it. Without
    /// the TC model: `t_c` = 10^-3 `tau` for a freely cooling gas, and 0.1 `tau` under
    /// gravity, where the grains come to rest in a bed that rattles ever faster (there
    /// 10^-3 `tau` only delays the collapse until the bed forms; measured in
    /// `docs/edmd.md`). With the model on, ten times its `t_c`: one taken from `tau` could
    /// be shorter than the `t_c` that failed, when the collapse has shrunk `tau`.
    /// Collisions closer than `t_c` are elastic (section 2.3 of the hard-disk seed), so
    /// every advice trades some dissipation for stability.
    fn collapse_advice(&self, tau: f64) -> String {
        let t_c = self.law.contact_duration;
        let falls_on_a_wall = (0..D).any(|k| self.gravity[k] != 0.0 && !self.bx.is_periodic(k));
        if falls_on_a_wall && self.law.wall_restitution == 0.0 {
            // A grain that lands keeps no normal velocity, gravity presses it into the wall
            // again at once, and an elastic reflection of nothing is nothing: no t_c helps.
            "With collisions.wall_restitution = 0 under gravity, a grain that lands on a wall \
             stops there and hits it again at zero intervals, which no TC model can stop: \
             set collisions.wall_restitution above 0 (a landed grain then bounces ever lower \
             until the TC model makes its bounces elastic)."
                .to_string()
        } else if t_c > 0.0 {
            format!(
                "The TC model is on (t_c = {t_c}) but too short to stop it: set \
                 collisions.contact_duration = {:.1e} (ten times longer; keep it well below \
                 the mean free time of the grains in motion, since collisions closer than t_c \
                 are elastic), or raise the restitution.",
                10.0 * t_c
            )
        } else if self.has_gravity {
            format!(
                "Enable the TC model: grains that come to rest under gravity need \
                 collisions.contact_duration = {:.1e} (about 0.1 of the mean free time \
                 {tau:.3e}; collisions closer than t_c are elastic), or raise the restitution.",
                0.1 * tau
            )
        } else {
            format!(
                "Enable the TC model with collisions.contact_duration = {:.1e} (about 1e-3 of \
                 the mean free time {tau:.3e}), or raise the restitution.",
                1e-3 * tau
            )
        }
    }

    /// Ends Lubachevsky-Stillinger growth: radii are frozen at their current values.
    pub(crate) fn freeze_growth(&mut self) {
        if self.growth == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
        }
        let scale = 1.0 + self.growth * self.now;
        for r in &mut self.kind_radius {
            *r *= scale;
        }
        self.growth = 0.0;
        self.max_radius = self.kind_radius.iter().cloned().fold(0.0, f64::max);
        self.min_radius = self
            .kind_radius
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        for i in 0..self.len() {
            self.predict(i);
        }
        self.queue.rebuild(self.now);
    }

    /// Multiplies all velocities by `factor` (thermostat used during compression).
    pub(crate) fn scale_velocities(&mut self, factor: f64) {
        self.change_velocities(|_, v| v * factor);
    }

    /// Replaces every grain's velocity `v` by `f(id, v)` at the current time, then
    /// predicts every grain's next event again and rebuilds the calendar (no event is
    /// skipped: the positions do not move, only the future changes). Without gravity.
    pub(crate) fn change_velocities(&mut self, mut f: impl FnMut(u32, Vector<D>) -> Vector<D>) {
        for i in 0..self.len() {
            self.advance_particle(i);
            let id = self.id[i];
            let g = &mut self.grains[i];
            g.vel = f(id, g.vel);
            g.counter = g.counter.wrapping_add(1);
        }
        for i in 0..self.len() {
            self.predict(i);
        }
        self.queue.rebuild(self.now);
    }

    /// Mass of grain `id`.
    pub fn mass_of(&self, id: usize) -> f64 {
        self.mass(self.slot_of(id))
    }

    /// Takes the grains out of the engine (positions and velocities at the current time),
    /// in id order.
    pub fn particle_set(&self) -> ParticleSet<D> {
        ParticleSet {
            positions: (0..self.len()).map(|i| self.position(i)).collect(),
            velocities: (0..self.len()).map(|i| self.velocity(i)).collect(),
            radii: self.radii(),
            masses: self.masses(),
            species: self.species(),
            species_names: self.species_names.clone(),
        }
    }

    /// Heap memory held by the engine's per-particle and per-cell arrays, in bytes
    /// (grain records, events, partners, TC times, id maps, kinds, queue and cell lists):
    /// what `granular bench edmd` reports per particle.
    pub fn memory_bytes(&self) -> usize {
        fn bytes<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        self.grains.capacity() * std::mem::size_of::<Grain<D>>()
            + bytes(&self.event)
            + bytes(&self.last_partner)
            + bytes(&self.last_collision)
            + bytes(&self.id)
            + self.slot.get().map_or(0, bytes)
            + bytes(&self.kind_radius)
            + bytes(&self.kind_mass)
            + bytes(&self.kind_species)
            + self.queue.memory_bytes()
            + self.cells.memory_bytes()
    }

    /// The fourth cumulant `a2` of the peculiar velocities, of all grains and per species
    /// ([`crate::moments::a2_by_species`]).
    pub fn a2_by_species(&self) -> (f64, Vec<f64>) {
        let species = self.species_names.len().max(1);
        crate::moments::a2_by_species::<D>(self.len(), species, |i| {
            let s = self.kind_species[self.grains[i].kind as usize] as usize;
            (s, self.mass(i), self.velocity_slot(i))
        })
    }

    /// Kinetic energy and grain count per species.
    pub fn species_kinetic_energy(&self) -> Vec<(f64, usize)> {
        let mut out = vec![(0.0, 0usize); self.species_names.len().max(1)];
        for i in 0..self.len() {
            let s = self.kind_species[self.grains[i].kind as usize] as usize;
            if s < out.len() {
                out[s].0 += 0.5 * self.mass(i) * self.velocity_slot(i).norm_squared();
                out[s].1 += 1;
            }
        }
        out
    }
}

impl<const D: usize> Edmd<D> {
    /// The event loop: events up to `until` (absolute time), at most `max_events`.
    pub(super) fn advance_events(
        &mut self,
        until: f64,
        max_events: u64,
    ) -> Result<Progress, EngineError> {
        let interval = self
            .options
            .reorder_interval
            .unwrap_or(8 * self.len() as u64 + 1024);
        let mut until_now = until - self.origin;
        // Large systems: prefetch what the events about to come will read (see
        // `prefetch_coming`).
        let look_ahead = self.queue.looks_ahead();
        let mut coming = usize::MAX;
        let mut earlier = usize::MAX;
        for _ in 0..max_events {
            let Some((i, t)) = self.queue.min() else {
                self.now = self.now.max(until_now);
                return Ok(Progress::Reached);
            };
            if look_ahead {
                self.prefetch_coming(&mut coming, &mut earlier);
            }
            if t > until_now {
                self.now = self.now.max(until_now);
                return Ok(Progress::Reached);
            }
            if t < self.now {
                return Err(EngineError::Numerical(format!(
                    "event of particle {} scheduled at {t:e}, before the current time {:e}",
                    self.id[i], self.now
                )));
            }
            self.now = t;
            self.process(i)?;
            if self.totals.events & (COLLAPSE_WINDOW - 1) == 0 {
                self.check_collapse()?;
            }
            // At a fixed event count, so that the trajectory does not depend on how the
            // run is cut into `advance` calls.
            if self.events_since_rebase >= interval {
                self.rebase();
                until_now = until - self.origin;
            }
        }
        Ok(Progress::BudgetExhausted)
    }
}

impl<const D: usize> Engine for Edmd<D> {
    fn name(&self) -> &'static str {
        "edmd"
    }

    fn time(&self) -> f64 {
        self.origin + self.now
    }

    fn events(&self) -> u64 {
        self.totals.events
    }

    fn collisions(&self) -> u64 {
        self.totals.pair_collisions
    }

    fn particle_count(&self) -> usize {
        self.len()
    }

    /// Events up to `until`; a steady-state driving ([`Edmd::set_driving`]) acts at its
    /// fixed times in between.
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        if self.driving.is_some() {
            self.advance_driven(until, max_events)
        } else {
            self.advance_events(until, max_events)
        }
    }

    fn observe(&self) -> Observation {
        let n = self.len();
        let volume = self.bx.volume();
        let kinetic = self.kinetic_energy_now();
        let (a2, species_a2) = self.a2_by_species();
        let species = if self.species_names.len() > 1 {
            self.species_kinetic_energy()
                .iter()
                .enumerate()
                .map(|(s, &(k, count))| {
                    let c = count.max(1) as f64;
                    SpeciesObservation {
                        name: self.species_names[s].clone(),
                        grains: count,
                        kinetic_energy_per_grain: k / c,
                        temperature: 2.0 * k / (D as f64 * c),
                        a2: species_a2.get(s).copied(),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let wall_area: f64 = (0..D)
            .filter(|&k| !self.bx.is_periodic(k))
            .map(|k| 2.0 * volume / self.bx.lengths[k])
            .sum();
        Observation {
            engine: "edmd".into(),
            dimension: D,
            particles: n,
            time: self.time(),
            events: self.totals.events,
            collisions: self.totals.pair_collisions,
            collisions_per_particle: 2.0 * self.totals.pair_collisions as f64 / n as f64,
            kinetic_energy: kinetic,
            temperature: 2.0 * kinetic / (D as f64 * n as f64),
            species,
            wall_collisions: Some(self.totals.wall_collisions),
            dissipated_energy: Some(self.totals.dissipated_energy),
            tc_elastic_collisions: Some(self.totals.tc_elastic_collisions),
            virial: Some(self.totals.virial),
            wall_impulse: Some(self.totals.wall_impulse),
            volume,
            wall_area,
            a2: Some(a2),
            dsmc: None,
            engine_specific: self
                .driving
                .as_ref()
                .map(|d| vec![("injected_energy".to_string(), d.state.injected_energy)])
                .unwrap_or_default(),
        }
    }

    fn kinetic_energy(&self) -> f64 {
        self.kinetic_energy_now()
    }

    fn impact_histogram(&self) -> Option<crate::stats::Histogram> {
        Some(Edmd::impact_histogram(self).clone())
    }

    /// Gathers the records by grain id through the slot table (`particles::gather_by_slot`,
    /// built on the first query after a reordering and kept until the next), prefetching
    /// the records a few grains ahead: the output is written in order, on all of rayon's
    /// workers. (A scatter in slot order, the earlier way, scanned the whole order once
    /// per worker and wrote each row at random.)
    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        let grains: &[Grain<D>] = &self.grains;
        let ahead = |next: &[u32]| super::prefetch::prefetch_all(grains, next);
        if velocities {
            crate::particles::gather_by_slot::<D>(self.slots(), out, ahead, |s| {
                self.velocity_slot(s).0
            });
        } else {
            crate::particles::gather_by_slot::<D>(self.slots(), out, ahead, |s| {
                let mut x = self.position_raw(s);
                self.bx.wrap(&mut x);
                x.0
            });
        }
        true
    }

    fn snapshot(&self) -> Option<Snapshot> {
        let n = self.len();
        let mut positions = Vec::with_capacity(n * D);
        let mut velocities = Vec::with_capacity(n * D);
        for i in 0..n {
            positions.extend_from_slice(&self.position(i).0);
            velocities.extend_from_slice(&self.velocity(i).0);
        }
        Some(Snapshot {
            time: self.time(),
            dimension: D,
            positions,
            velocities,
            radii: self.radii(),
            masses: self.masses(),
            species: self.species(),
            species_names: self.species_names.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edmd::bench::equilibrated_fluid;
    use crate::edmd::queue::CalendarQueue;

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
