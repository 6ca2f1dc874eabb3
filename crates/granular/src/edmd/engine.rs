//! The event-driven engine.
//!
//! Algorithm (section 3 of the hard-disk seed, in the one-event-per-particle form of
//! Lubachevsky 1991 and Smallenburg 2022):
//! * every particle carries a local clock: its stored position and velocity are valid at
//!   its own time `time[i]`, and it is advanced only when an event involves it;
//! * every particle has exactly one scheduled event, its earliest: a pair collision, a
//!   wall collision or a cell crossing; the [`EventQueue`] orders particles by it;
//! * a pair event stores the partner's collision counter at prediction time; if the
//!   partner has collided since, the event is stale (section 3.2 of the seed) and the
//!   particle is simply re-predicted;
//! * neighbours are found through a [`CellGrid`] whose cells are at least one contact
//!   distance wide, so one prediction checks O(1) grains, never all N.
//!
//! Times are kept relative to a moving origin (`origin`), which is shifted every few
//! collisions per particle, so that after 10^9 collisions event times still carry full
//! double precision.

use super::cells::{CellGrid, NONE};
use super::prediction::{downward_crossing, pair_contact_time, upward_crossing};
use super::queue::EventQueue;
use crate::boundary::SimulationBox;
use crate::collision_law::CollisionLaw;
use crate::engine::{Engine, EngineError, Progress, Scalar, Snapshot};
use crate::stats::Histogram;
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// What a particle's scheduled event is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// Nothing will ever happen to this particle (it is at rest, without gravity).
    Nothing,
    /// Collision with particle `partner`, valid while its counter equals `partner_counter`.
    Pair {
        /// The other particle.
        partner: u32,
        /// The partner's collision counter when the event was predicted.
        partner_counter: u64,
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

/// Everything that defines the grains at the start of a run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ParticleSet<const D: usize> {
    /// Centre positions, inside the box.
    pub positions: Vec<Vector<D>>,
    /// Velocities.
    pub velocities: Vec<Vector<D>>,
    /// Radii (> 0).
    pub radii: Vec<f64>,
    /// Masses (> 0).
    pub masses: Vec<f64>,
    /// Species index of each grain into `species_names`.
    pub species: Vec<u32>,
    /// Species names.
    pub species_names: Vec<String>,
}

impl<const D: usize> ParticleSet<D> {
    /// Number of grains.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
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
}

impl Default for EdmdOptions {
    fn default() -> Self {
        Self {
            gravity: Vec::new(),
            collapse_ratio: 1e-6,
            impact_bins: 20,
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

/// Values at the previous call of `scalars()`, to report rates over the output interval.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct LastSample {
    time: f64,
    pair_collisions: u64,
    wall_collisions: u64,
    virial: f64,
    wall_impulse: f64,
}

/// Inelastic-collapse detector state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct CollapseWatch {
    window_start_events: u64,
    window_start_time: f64,
}

/// Events per collapse-detector window.
const COLLAPSE_WINDOW: u64 = 1 << 16;

/// Event-driven molecular dynamics of hard disks (`D = 2`) or spheres (`D = 3`).
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
    // Per-particle state (structure of arrays, 32-bit indices).
    pos: Vec<Vector<D>>,
    vel: Vec<Vector<D>>,
    time: Vec<f64>,
    counter: Vec<u64>,
    radius: Vec<f64>,
    mass: Vec<f64>,
    species: Vec<u32>,
    last_collision: Vec<f64>,
    last_partner: Vec<u32>,
    event: Vec<EventKind>,
    queue: EventQueue,
    cells: CellGrid<D>,
    species_names: Vec<String>,
    // Clock: absolute time = origin + now.
    now: f64,
    origin: f64,
    events_since_rebase: u64,
    totals: Totals,
    impact: Histogram,
    last: LastSample,
    collapse: CollapseWatch,
    max_radius: f64,
    min_radius: f64,
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
        let cells = CellGrid::new(&bx, 2.0 * max_radius * radius_scale * (1.0 + 1e-9), n);
        let impact = Histogram::new(0.0, 1.0 + 1e-12, options.impact_bins.max(1));
        let mut engine = Self {
            law,
            gravity,
            has_gravity,
            growth,
            options,
            pos: particles.positions,
            vel: particles.velocities,
            time: vec![0.0; n],
            counter: vec![0; n],
            radius: particles.radii,
            mass: particles.masses,
            species: particles.species,
            last_collision: vec![f64::NEG_INFINITY; n],
            last_partner: vec![NONE; n],
            event: vec![EventKind::Nothing; n],
            queue: EventQueue::new(n),
            cells,
            species_names: particles.species_names,
            now: 0.0,
            origin: 0.0,
            events_since_rebase: 0,
            totals: Totals::default(),
            impact,
            last: LastSample::default(),
            collapse: CollapseWatch::default(),
            max_radius,
            min_radius,
            bx,
        };
        for i in 0..n {
            let mut x = engine.pos[i];
            engine.bx.wrap(&mut x);
            engine.pos[i] = x;
            let c = engine.cells.coords_of(&x.0);
            engine.cells.insert(i, c);
        }
        for i in 0..n {
            engine.predict(i);
        }
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

    /// Number of grains.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Masses of the grains.
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Species of the grains.
    pub fn species(&self) -> &[u32] {
        &self.species
    }

    /// Species names.
    pub fn species_names(&self) -> &[String] {
        &self.species_names
    }

    /// Current radius of grain `i` (differs from the initial one only during compression).
    #[inline(always)]
    fn radius_now(&self, i: usize) -> f64 {
        if self.growth == 0.0 {
            self.radius[i]
        } else {
            self.radius[i] * (1.0 + self.growth * self.now)
        }
    }

    /// Radii at the current time.
    pub fn radii(&self) -> Vec<f64> {
        (0..self.len()).map(|i| self.radius_now(i)).collect()
    }

    /// Position of grain `i` at the current time (not stored: observing never perturbs the
    /// trajectory).
    #[inline(always)]
    pub fn position(&self, i: usize) -> Vector<D> {
        let dt = self.now - self.time[i];
        let mut x = self.pos[i].add_scaled(dt, &self.vel[i]);
        if self.has_gravity {
            x = x.add_scaled(0.5 * dt * dt, &self.gravity);
        }
        self.bx.wrap(&mut x);
        x
    }

    /// Velocity of grain `i` at the current time.
    #[inline(always)]
    pub fn velocity(&self, i: usize) -> Vector<D> {
        if self.has_gravity {
            self.vel[i].add_scaled(self.now - self.time[i], &self.gravity)
        } else {
            self.vel[i]
        }
    }

    /// Unwrapped position at the current time (may lie outside the box by round-off).
    #[inline(always)]
    fn position_raw(&self, i: usize) -> Vector<D> {
        let dt = self.now - self.time[i];
        let x = self.pos[i].add_scaled(dt, &self.vel[i]);
        if self.has_gravity {
            x.add_scaled(0.5 * dt * dt, &self.gravity)
        } else {
            x
        }
    }

    /// Brings grain `i`'s stored state to the current time.
    #[inline(always)]
    fn advance_particle(&mut self, i: usize) {
        let dt = self.now - self.time[i];
        if dt != 0.0 {
            let x = self.position_raw(i);
            let v = self.velocity(i);
            self.pos[i] = x;
            self.vel[i] = v;
        }
        self.time[i] = self.now;
    }

    /// Predicts grain `i`'s earliest event from its state at the current time (which must
    /// be stored, `time[i] == now`) and puts it in the queue.
    fn predict(&mut self, i: usize) {
        debug_assert_eq!(self.time[i], self.now);
        let xi = self.pos[i];
        let vi = self.vel[i];
        let ri = self.radius_now(i);
        let rate_i = self.radius[i] * self.growth;
        let half_g = self.gravity * 0.5;
        let mut best = f64::INFINITY;
        let mut kind = EventKind::Nothing;
        let coords = self.cells.coords[i];
        for k in 0..D {
            let n = self.cells.counts[k];
            let periodic = self.bx.is_periodic(k);
            let w = self.cells.widths[k];
            let ck = coords[k] as usize;
            let (v, a) = (vi[k], half_g[k]);
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
                    kind = EventKind::CellCrossing {
                        axis: k as u8,
                        upward: true,
                    };
                }
            }
            if periodic || ck > 0 {
                let lo = ck as f64 * w;
                if let Some(t) = downward_crossing(xi[k] - lo, v, a)
                    && t < best
                {
                    best = t;
                    kind = EventKind::CellCrossing {
                        axis: k as u8,
                        upward: false,
                    };
                }
            }
            if !periodic {
                let l = self.bx.lengths[k];
                if let Some(t) = upward_crossing(xi[k] + ri - l, v + rate_i, a)
                    && t < best
                {
                    best = t;
                    kind = EventKind::Wall {
                        axis: k as u8,
                        upper: true,
                    };
                }
                if let Some(t) = downward_crossing(xi[k] - ri, v - rate_i, a)
                    && t < best
                {
                    best = t;
                    kind = EventKind::Wall {
                        axis: k as u8,
                        upper: false,
                    };
                }
            }
        }
        let partner_of_i = self.last_partner[i];
        let mut best_pair = best;
        let mut partner = NONE;
        self.cells.for_each_neighbour(&coords, |j| {
            if j == i || (partner_of_i == j as u32 && self.last_partner[j] == i as u32) {
                return;
            }
            let xj = self.position_raw(j);
            let vj = self.velocity(j);
            let dx = self.bx.separation(&xi, &xj);
            let dv = vj - vi;
            let (sigma, sigma_rate) = if self.growth == 0.0 {
                (ri + self.radius[j], 0.0)
            } else {
                (
                    ri + self.radius_now(j),
                    rate_i + self.radius[j] * self.growth,
                )
            };
            if let Some(t) = pair_contact_time(
                dx.dot(&dv),
                dx.norm_squared(),
                dv.norm_squared(),
                sigma,
                sigma_rate,
            ) && t < best_pair
            {
                best_pair = t;
                partner = j as u32;
            }
        });
        if partner != NONE {
            best = best_pair;
            kind = EventKind::Pair {
                partner,
                partner_counter: self.counter[partner as usize],
            };
        }
        self.event[i] = kind;
        self.queue.update(i, self.now + best);
    }

    /// Processes the earliest event. The clock must already be at its time.
    fn process(&mut self, i: usize) -> Result<(), EngineError> {
        self.totals.events += 1;
        self.events_since_rebase += 1;
        match self.event[i] {
            EventKind::Nothing => {
                return Err(EngineError::Numerical(format!(
                    "particle {i} scheduled an empty event at a finite time"
                )));
            }
            EventKind::Pair {
                partner,
                partner_counter,
            } => {
                let j = partner as usize;
                self.advance_particle(i);
                if self.counter[j] != partner_counter {
                    self.predict(i);
                    return Ok(());
                }
                self.advance_particle(j);
                self.collide_pair(i, j);
                self.predict(i);
                self.predict(j);
            }
            EventKind::Wall { axis, upper } => {
                self.advance_particle(i);
                self.collide_wall(i, axis as usize, upper);
                self.predict(i);
            }
            EventKind::CellCrossing { axis, upward } => {
                self.advance_particle(i);
                let k = axis as usize;
                if self.cells.shift(i, k, if upward { 1 } else { -1 }) {
                    let l = self.bx.lengths[k];
                    self.pos[i][k] += if upward { -l } else { l };
                }
                self.predict(i);
            }
        }
        Ok(())
    }

    /// Resolves a pair collision (Eq. 11 of the hard-disk seed), both grains at `now`.
    fn collide_pair(&mut self, i: usize, j: usize) {
        let dx = self.bx.separation(&self.pos[i], &self.pos[j]);
        let dv = self.vel[j] - self.vel[i];
        let d2 = dx.norm_squared();
        let b = dx.dot(&dv);
        let d = d2.sqrt();
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let mu = mi * mj / (mi + mj);
        // Normal relative velocity u_n (negative when approaching) and its change.
        let un = b / d;
        let du = if self.growth == 0.0 {
            let xi = self.law.effective(
                self.law.restitution,
                self.now,
                &[self.last_collision[i], self.last_collision[j]],
            );
            if xi == 1.0 && self.law.restitution != 1.0 {
                self.totals.tc_elastic_collisions += 1;
            }
            -(1.0 + xi) * un
        } else {
            // Lubachevsky-Stillinger: elastic reflection in the frame of the growing
            // surfaces, so that they separate at least as fast as they grow.
            let rate = (self.radius[i] + self.radius[j]) * self.growth;
            2.0 * (rate - un)
        };
        let n = dx * (1.0 / d);
        self.vel[i] = self.vel[i].add_scaled(-mu / mi * du, &n);
        self.vel[j] = self.vel[j].add_scaled(mu / mj * du, &n);
        let un_after = un + du;
        self.totals.dissipated_energy += 0.5 * mu * (un * un - un_after * un_after);
        self.totals.virial += mu * du * d;
        self.totals.pair_collisions += 1;
        let dv2 = dv.norm_squared();
        if dv2 > 0.0 {
            let cos2 = (b * b / (d2 * dv2)).min(1.0);
            self.impact.push((1.0 - cos2).sqrt());
        }
        self.counter[i] += 1;
        self.counter[j] += 1;
        self.last_collision[i] = self.now;
        self.last_collision[j] = self.now;
        self.last_partner[i] = j as u32;
        self.last_partner[j] = i as u32;
    }

    /// Resolves a wall collision (Eqs. 3-4 of the hard-disk seed).
    fn collide_wall(&mut self, i: usize, axis: usize, upper: bool) {
        let v = self.vel[i];
        let k0 = 0.5 * self.mass[i] * v.norm_squared();
        let mut v_new = v;
        if self.growth == 0.0 {
            let e = self.law.effective(
                self.law.wall_restitution,
                self.now,
                &[self.last_collision[i]],
            );
            let et = if e == 1.0 && self.law.wall_restitution != 1.0 {
                self.totals.tc_elastic_collisions += 1;
                1.0
            } else {
                self.law.wall_tangential_restitution
            };
            for k in 0..D {
                v_new[k] = if k == axis { -e * v[k] } else { et * v[k] };
            }
        } else {
            let rate = self.radius[i] * self.growth;
            v_new[axis] = if upper {
                -v[axis] - 2.0 * rate
            } else {
                -v[axis] + 2.0 * rate
            };
        }
        self.vel[i] = v_new;
        self.totals.wall_impulse += self.mass[i] * (v[axis] - v_new[axis]).abs();
        self.totals.dissipated_energy += k0 - 0.5 * self.mass[i] * v_new.norm_squared();
        self.totals.wall_collisions += 1;
        self.counter[i] += 1;
        self.last_collision[i] = self.now;
        self.last_partner[i] = NONE;
    }

    /// Moves the time origin to the current time: all grains are advanced to `now`, and
    /// every stored time is shifted, so that times stay small numbers.
    fn rebase(&mut self) {
        if self.growth != 0.0 || self.now == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
            self.time[i] = 0.0;
            self.last_collision[i] -= self.now;
        }
        self.queue.shift(self.now);
        self.collapse.window_start_time -= self.now;
        self.last.time -= self.now;
        self.origin += self.now;
        self.now = 0.0;
        self.events_since_rebase = 0;
    }

    /// Total kinetic energy, `Σ m v² / 2`.
    pub fn kinetic_energy_now(&self) -> f64 {
        (0..self.len())
            .map(|i| 0.5 * self.mass[i] * self.velocity(i).norm_squared())
            .sum()
    }

    /// Total momentum.
    pub fn momentum(&self) -> Vector<D> {
        let mut p = Vector::zero();
        for i in 0..self.len() {
            p = p.add_scaled(self.mass[i], &self.velocity(i));
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
            self.cells.for_each_neighbour(&self.cells.coords[i], |j| {
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

    fn check_collapse(&mut self) -> Result<(), EngineError> {
        let events = self.totals.events - self.collapse.window_start_events;
        if events < COLLAPSE_WINDOW {
            return Ok(());
        }
        let elapsed = self.now - self.collapse.window_start_time;
        self.collapse.window_start_events = self.totals.events;
        self.collapse.window_start_time = self.now;
        if self.law.is_elastic() || self.growth != 0.0 {
            return Ok(());
        }
        let total_mass: f64 = self.mass.iter().sum();
        let v_typ = (2.0 * self.kinetic_energy_now() / total_mass).sqrt();
        if v_typ == 0.0 {
            return Ok(());
        }
        // Time those events take at one collision per grain per time a grain needs to
        // cross its own diameter at the typical speed: a generous upper bound on rates.
        let natural = events as f64 / self.len() as f64 * 2.0 * self.min_radius / v_typ;
        if elapsed < self.options.collapse_ratio * natural {
            let tau = self.mean_free_time_so_far();
            let suggestion = if tau.is_finite() {
                1e-3 * tau
            } else {
                1e-3 * 2.0 * self.min_radius / v_typ
            };
            return Err(EngineError::Collapse(format!(
                "inelastic collapse at t = {:.6e}: the last {events} events advanced the time by only {elapsed:.3e} \
                 (grains collide ever faster in a shrinking cluster; restitution {}, contact_duration (t_c) {}). \
                 Enable the TC model with collisions.contact_duration = {suggestion:.1e} \
                 (about 1e-3 of the mean free time {tau:.3e}), or raise the restitution.",
                self.origin + self.now,
                self.law.restitution,
                self.law.contact_duration,
            )));
        }
        Ok(())
    }

    /// Ends Lubachevsky-Stillinger growth: radii are frozen at their current values.
    pub(crate) fn freeze_growth(&mut self) {
        if self.growth == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
        }
        for i in 0..self.len() {
            self.radius[i] = self.radius_now(i);
        }
        self.growth = 0.0;
        self.max_radius = self.radius.iter().cloned().fold(0.0, f64::max);
        self.min_radius = self.radius.iter().cloned().fold(f64::INFINITY, f64::min);
        for i in 0..self.len() {
            self.predict(i);
        }
    }

    /// Multiplies all velocities by `factor` (thermostat used during compression).
    pub(crate) fn scale_velocities(&mut self, factor: f64) {
        for i in 0..self.len() {
            self.advance_particle(i);
            self.vel[i] = self.vel[i] * factor;
            self.counter[i] += 1;
        }
        for i in 0..self.len() {
            self.predict(i);
        }
    }

    /// Takes the grains out of the engine (positions and velocities at the current time).
    pub fn particle_set(&self) -> ParticleSet<D> {
        ParticleSet {
            positions: (0..self.len()).map(|i| self.position(i)).collect(),
            velocities: (0..self.len()).map(|i| self.velocity(i)).collect(),
            radii: self.radii(),
            masses: self.mass.clone(),
            species: self.species.clone(),
            species_names: self.species_names.clone(),
        }
    }

    /// Heap memory held by the engine's per-particle and per-cell arrays, in bytes
    /// (positions, velocities, clocks, counters, radii, masses, species, TC times,
    /// partners, events, queue and cell lists): what `granular bench edmd` reports per
    /// particle.
    pub fn memory_bytes(&self) -> usize {
        fn bytes<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        bytes(&self.pos)
            + bytes(&self.vel)
            + bytes(&self.time)
            + bytes(&self.counter)
            + bytes(&self.radius)
            + bytes(&self.mass)
            + bytes(&self.species)
            + bytes(&self.last_collision)
            + bytes(&self.last_partner)
            + bytes(&self.event)
            + self.queue.memory_bytes()
            + self.cells.memory_bytes()
    }

    /// Kinetic energy and grain count per species.
    pub fn species_kinetic_energy(&self) -> Vec<(f64, usize)> {
        let mut out = vec![(0.0, 0usize); self.species_names.len().max(1)];
        for i in 0..self.len() {
            let s = self.species[i] as usize;
            if s < out.len() {
                out[s].0 += 0.5 * self.mass[i] * self.velocity(i).norm_squared();
                out[s].1 += 1;
            }
        }
        out
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

    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        if self.events_since_rebase >= 8 * self.len() as u64 + 1024 {
            self.rebase();
        }
        let until = until - self.origin;
        for _ in 0..max_events {
            let Some((i, t)) = self.queue.min() else {
                self.now = self.now.max(until);
                return Ok(Progress::Reached);
            };
            if t > until {
                self.now = self.now.max(until);
                return Ok(Progress::Reached);
            }
            if t < self.now {
                return Err(EngineError::Numerical(format!(
                    "event of particle {i} scheduled at {t:e}, before the current time {:e}",
                    self.now
                )));
            }
            self.now = t;
            self.process(i)?;
            if self.totals.events & (COLLAPSE_WINDOW - 1) == 0 {
                self.check_collapse()?;
            }
        }
        Ok(Progress::BudgetExhausted)
    }

    fn scalars(&mut self) -> Vec<Scalar> {
        let t = self.time();
        let n = self.len() as f64;
        let volume = self.bx.volume();
        let kinetic = self.kinetic_energy_now();
        let temperature = 2.0 * kinetic / (D as f64 * n);
        let mut out: Vec<Scalar> = vec![
            ("time".into(), t),
            ("kinetic_energy".into(), kinetic),
            ("temperature".into(), temperature),
        ];
        let per_species = self.species_kinetic_energy();
        if self.species_names.len() > 1 {
            for (s, (k, count)) in per_species.iter().enumerate() {
                let name = &self.species_names[s];
                let c = (*count).max(1) as f64;
                out.push((format!("kinetic_energy_per_grain.{name}"), k / c));
                out.push((format!("temperature.{name}"), 2.0 * k / (D as f64 * c)));
            }
        }
        let dt = t - (self.origin + self.last.time);
        let d_pair = self.totals.pair_collisions - self.last.pair_collisions;
        let (pressure, collision_rate, wall_pressure) = if dt > 0.0 {
            let virial = self.totals.virial - self.last.virial;
            let p = (2.0 * kinetic + virial / dt) / (D as f64 * volume);
            let rate = 2.0 * d_pair as f64 / (n * dt);
            let wall_area: f64 = (0..D)
                .filter(|&k| !self.bx.is_periodic(k))
                .map(|k| 2.0 * volume / self.bx.lengths[k])
                .sum();
            let wp = if wall_area > 0.0 {
                (self.totals.wall_impulse - self.last.wall_impulse) / (wall_area * dt)
            } else {
                f64::NAN
            };
            (p, rate, wp)
        } else {
            (f64::NAN, f64::NAN, f64::NAN)
        };
        out.extend([
            ("pair_collisions".into(), self.totals.pair_collisions as f64),
            ("wall_collisions".into(), self.totals.wall_collisions as f64),
            (
                "collisions_per_particle".into(),
                2.0 * self.totals.pair_collisions as f64 / n,
            ),
            ("collision_frequency".into(), collision_rate),
            (
                "mean_free_time".into(),
                if collision_rate > 0.0 {
                    1.0 / collision_rate
                } else {
                    f64::NAN
                },
            ),
            ("pressure".into(), pressure),
            ("wall_pressure".into(), wall_pressure),
            ("dissipated_energy".into(), self.totals.dissipated_energy),
            (
                "tc_elastic_collisions".into(),
                self.totals.tc_elastic_collisions as f64,
            ),
        ]);
        self.last = LastSample {
            time: self.now,
            pair_collisions: self.totals.pair_collisions,
            wall_collisions: self.totals.wall_collisions,
            virial: self.totals.virial,
            wall_impulse: self.totals.wall_impulse,
        };
        out
    }

    fn kinetic_energy(&mut self) -> f64 {
        self.kinetic_energy_now()
    }

    fn snapshot(&mut self) -> Option<Snapshot> {
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
            masses: self.mass.clone(),
            species: self.species.clone(),
            species_names: self.species_names.clone(),
        })
    }
}
