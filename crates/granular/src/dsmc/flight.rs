//! The free-flight stage of a DSMC step: every grain moves exactly under a constant
//! acceleration, and hard walls apply the shared wall law (HD-3, HD-4 with the TC rule of
//! [`crate::collision_law`]); periodic axes wrap.
//!
//! Positions are lattice words ([`Lattice`]): the displacement `v dt + g dt^2 / 2` of a
//! step is converted to lattice units (truncated towards zero, at most one unit of
//! `L / 2^(64 - b)`, see `lattice`) and added as an integer, so a periodic axis wraps
//! by the integer addition itself and the new cell comes from the words. Along a walled
//! axis a word above `2^63` means the grain crossed a wall; only such grains (and a grain
//! moving more than a quarter of the box in one step) take the `f64` path that applies the
//! wall law and converts back. Rough grains keep their angular velocities in flight and
//! hit a wall by RS-1 with the wall's α_w and β_w = -e_t
//! ([`crate::collision_law::WallRestitution::apply_rough`]).

use super::cells::CellIndex;
use super::grains::Columns;
use super::lattice::{Lattice, WALL_END, axis_cell};
use crate::boundary::{AxisKind, SimulationBox};
use crate::collision_law::{Body, CollisionLaw, Spin};
use crate::vector::Vector;

/// Largest displacement (in lattice units of the whole word) of the integer path: a
/// quarter of a periodic box, half of a walled one.
const LIMIT: f64 = (1u64 << 62) as f64;

/// What the free flight of one step needs (the same for every grain).
pub(crate) struct Flight<'a, const D: usize> {
    pub(crate) bx: &'a SimulationBox<D>,
    pub(crate) lattice: &'a Lattice<D>,
    pub(crate) cells: CellIndex<D>,
    pub(crate) law: &'a CollisionLaw,
    /// The grains as a rough wall collision sees them (rough grains only).
    pub(crate) body: Body,
    pub(crate) gravity: Vector<D>,
    /// Length of the step (time units).
    pub(crate) dt: f64,
    /// Time at the end of the step.
    pub(crate) t_end: f64,
}

impl<const D: usize> Flight<'_, D> {
    /// Moves the grains of `cols` (the last collision times are used only by wall hits
    /// with the TC model) and writes their new cells into `dest`: returns the number of
    /// wall collisions made elastic by the TC rule.
    pub(crate) fn fly(&self, cols: &mut Columns<'_, D>, dest: &mut [u32]) -> u64 {
        let accelerated = self.gravity.0.iter().any(|&a| a != 0.0);
        let walls = self.bx.axes.contains(&AxisKind::Wall);
        match (accelerated, walls) {
            (false, false) => self.fly_with::<false, false>(cols, dest),
            (true, false) => self.fly_with::<true, false>(cols, dest),
            (false, true) => self.fly_with::<false, true>(cols, dest),
            (true, true) => self.fly_with::<true, true>(cols, dest),
        }
    }

    /// [`Self::fly`] with the presence of gravity and of walls fixed at compile time.
    ///
    /// One axis at a time over the whole chunk (the per-axis constants stay in registers
    /// and each loop streams through two columns): the integer step of every grain, its
    /// cell coordinate added into `dest`, and the largest `|step|` of the axis. A chunk
    /// with a step beyond [`LIMIT`] (a grain crossing a quarter of the box in one step, or
    /// an infinite velocity) is undone and flown grain by grain; a grain that crossed a
    /// wall is undone and flown in `f64` ([`Self::fly_exactly`]). Without gravity the
    /// velocities are not written (a store stream saved).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // grain by grain over several columns
    fn fly_with<const ACCELERATED: bool, const WALLS: bool>(
        &self,
        cols: &mut Columns<'_, D>,
        dest: &mut [u32],
    ) -> u64 {
        let n = dest.len();
        let plan = self.plan();
        let mut largest = 0.0f64;
        let mut crossed: Vec<usize> = Vec::new();
        for k in 0..D {
            let vel = &cols.vel[k][..n];
            let pos = &mut cols.pos[k][..n];
            let m = if k == 0 {
                fly_axis::<ACCELERATED, WALLS, true, D>(&plan, k, vel, pos, dest, &mut crossed)
            } else {
                fly_axis::<ACCELERATED, WALLS, false, D>(&plan, k, vel, pos, dest, &mut crossed)
            };
            largest = largest.max(m);
        }
        let mut tc_elastic = 0;
        if largest >= LIMIT {
            // Undo every step, then fly grain by grain.
            for i in 0..n {
                self.undo(cols, i);
            }
            for i in 0..n {
                let fast = (0..D).all(|k| (self.step_of(&plan, cols.vel[k][i], k).1) < LIMIT);
                if fast && !self.crosses_a_wall(&plan, cols, i) {
                    for k in 0..D {
                        let (step, _) = self.step_of(&plan, cols.vel[k][i], k);
                        cols.pos[k][i] = cols.pos[k][i].wrapping_add(step);
                        if ACCELERATED {
                            cols.vel[k][i] += self.gravity[k] * self.dt;
                        }
                    }
                } else {
                    self.fly_exactly(cols, i, &mut tc_elastic);
                }
                dest[i] = self.cells.of(&std::array::from_fn(|k| cols.pos[k][i]));
            }
            return tc_elastic;
        }
        crossed.sort_unstable();
        crossed.dedup();
        for &i in &crossed {
            self.undo(cols, i);
            self.fly_exactly(cols, i, &mut tc_elastic);
            dest[i] = self.cells.of(&std::array::from_fn(|k| cols.pos[k][i]));
        }
        if ACCELERATED {
            // The velocities of the grains flown exactly are already updated.
            let mut from = 0;
            for &i in crossed.iter().chain(std::iter::once(&n)) {
                for k in 0..D {
                    let g = self.gravity[k] * self.dt;
                    for v in &mut cols.vel[k][from..i] {
                        *v += g;
                    }
                }
                from = i + 1;
            }
        }
        tc_elastic
    }

    /// The per-axis constants of the integer flight.
    fn plan(&self) -> Plan<D> {
        let dt = self.dt;
        let mut plan = Plan {
            scale: [0.0; D],
            drop: [0.0; D],
            walled: [false; D],
            mask: self.lattice.position_mask(),
            mult: [0; D],
            last: [0; D],
            stride: [0; D],
        };
        let (mult, last, stride) = self.cells.axes();
        for k in 0..D {
            plan.scale[k] = self.lattice.units(k) / self.lattice.length(k) * dt;
            plan.drop[k] = 0.5 * self.gravity[k] * dt * plan.scale[k];
            plan.walled[k] = !self.lattice.periodic(k);
            plan.mult[k] = mult[k];
            plan.last[k] = last[k];
            plan.stride[k] = stride[k] as u32;
        }
        plan
    }

    /// The integer step of velocity component `v` along axis `k` and `|d|` (lattice units).
    #[inline]
    fn step_of(&self, plan: &Plan<D>, v: f64, k: usize) -> (u64, f64) {
        let mut d = v * plan.scale[k];
        if self.gravity[k] != 0.0 {
            d += plan.drop[k];
        }
        ((d as i64 as u64) & plan.mask, d.abs())
    }

    /// Takes back the integer steps of grain `i` on every axis (the velocity is not yet
    /// changed, so the steps are recomputed exactly).
    fn undo(&self, cols: &mut Columns<'_, D>, i: usize) {
        let plan = self.plan();
        for k in 0..D {
            let (step, _) = self.step_of(&plan, cols.vel[k][i], k);
            cols.pos[k][i] = cols.pos[k][i].wrapping_sub(step);
        }
    }

    /// Whether grain `i`'s integer step takes it through a wall.
    fn crosses_a_wall(&self, plan: &Plan<D>, cols: &Columns<'_, D>, i: usize) -> bool {
        (0..D).any(|k| {
            plan.walled[k]
                && cols.pos[k][i].wrapping_add(self.step_of(plan, cols.vel[k][i], k).0) > WALL_END
        })
    }

    /// The flight of grain `i` in `f64` box coordinates: a wall hit (the wall law), or a
    /// displacement too large for the integer path (periodic axes wrap by `rem_euclid`).
    /// The position goes back to the lattice (its identity bits kept).
    #[cold]
    fn fly_exactly(&self, cols: &mut Columns<'_, D>, i: usize, tc_elastic: &mut u64) {
        let (g, dt) = (self.gravity, self.dt);
        let old: [u64; D] = std::array::from_fn(|k| cols.pos[k][i]);
        let mut x = self.lattice.position(&old);
        let mut u = Vector(std::array::from_fn(|k| cols.vel[k][i]));
        x = x.add_scaled(dt, &u).add_scaled(0.5 * dt * dt, &g);
        u = u.add_scaled(dt, &g);
        let last = cols.last.get_mut(i);
        let mut spin = cols.spin.as_ref().map(|s| s.get(i));
        self.confine(&mut x, &mut u, spin.as_mut(), last, tc_elastic);
        if let (Some(s), Some(w)) = (cols.spin.as_mut(), spin) {
            s.set(i, &w);
        }
        let keep = !self.lattice.position_mask();
        for k in 0..D {
            if x[k].is_finite() {
                cols.pos[k][i] = self.lattice.word(k, x[k]) | (old[k] & keep);
            }
            cols.vel[k][i] = u[k];
        }
    }

    /// Hard walls: the shared wall law (HD-3, HD-4 with the TC rule, see
    /// [`CollisionLaw::wall_restitution_now`]) applied at each crossing of a wall during
    /// the flight; periodic axes: wrap. A grain that ended the flight a distance `s` past a
    /// wall hit it `s / |v_n|` before the end of the step (exact without gravity): after
    /// the hit its normal speed is `e_w |v_n|` (its overshoot is mirrored and scaled by
    /// `e_w`) and its tangential velocity `e_t v_t` (its tangential displacement since the
    /// hit is scaled by `e_t`); the hit time is the one the TC rule sees and records. A
    /// rough grain (`spin`) takes RS-1 at the wall instead, and its tangential
    /// displacement since the hit follows its new tangential velocity.
    #[inline(always)]
    fn confine(
        &self,
        x: &mut Vector<D>,
        v: &mut Vector<D>,
        mut spin: Option<&mut Spin>,
        mut last: Option<&mut f64>,
        tc_elastic: &mut u64,
    ) {
        let bx = self.bx;
        // Tangential displacement to take back (only when e_t < 1).
        let mut shift = Vector::<D>::zero();
        let mut shifted = false;
        for k in 0..D {
            if bx.axes[k] != AxisKind::Wall {
                continue;
            }
            let l = bx.lengths[k];
            let mut guard = 0;
            while (x[k] < 0.0 || x[k] > l) && guard < 8 {
                let over = if x[k] < 0.0 { -x[k] } else { x[k] - l };
                let since = (over / v[k].abs()).min(self.dt);
                let w = match last.as_deref_mut() {
                    Some(t) => {
                        let hit = self.t_end - since;
                        let w = self.law.wall_restitution_now(hit, &[*t], tc_elastic);
                        *t = hit;
                        w
                    }
                    None => self.law.wall_restitution_now(self.t_end, &[], tc_elastic),
                };
                let e = w.normal;
                let upper = x[k] > l;
                if x[k] < 0.0 {
                    x[k] *= -e;
                } else {
                    x[k] = l - e * (x[k] - l);
                }
                if let Some(spin) = spin.as_deref_mut() {
                    let before = *v;
                    w.apply_rough(k, upper, &self.body, v, spin);
                    for t in (0..D).filter(|&t| t != k) {
                        shift[t] += (v[t] - before[t]) * since;
                    }
                    shifted = true;
                    guard += 1;
                    continue;
                }
                if w.tangential != 1.0 {
                    for t in (0..D).filter(|&t| t != k) {
                        shift[t] -= (1.0 - w.tangential) * v[t] * since;
                    }
                    shifted = true;
                }
                *v = w.apply(v, k);
                guard += 1;
            }
            x[k] = x[k].clamp(0.0, l);
        }
        for k in 0..D {
            if shifted {
                x[k] += shift[k];
            }
            let l = bx.lengths[k];
            match bx.axes[k] {
                AxisKind::Periodic => {
                    if x[k] >= l || x[k] < 0.0 {
                        x[k] = x[k].rem_euclid(l);
                        if x[k] >= l {
                            x[k] = 0.0;
                        }
                    }
                }
                AxisKind::Wall => {
                    if shifted {
                        x[k] = x[k].clamp(0.0, l);
                    }
                }
            }
        }
    }
}

/// The integer flight of one axis `k` over a chunk (see [`Flight::fly_with`]): each
/// grain's step added to its lattice word, its cell coordinate along `k` written into
/// `dest` (`FIRST`, the first axis) or added to it, the grains of a walled axis whose
/// word went past a wall pushed onto `crossed`; returns the largest `|step|`. Out
/// of line, so that the registers of this loop, which every grain passes through on
/// every axis of every step, do not depend on the rest of the flight (the columns of
/// rough grains, the wall law): inlined, the loop kept two of its pointers on the stack.
#[inline(never)]
fn fly_axis<const ACCELERATED: bool, const WALLS: bool, const FIRST: bool, const D: usize>(
    plan: &Plan<D>,
    k: usize,
    vel: &[f64],
    pos: &mut [u64],
    dest: &mut [u32],
    crossed: &mut Vec<usize>,
) -> f64 {
    let (scale, drop, mask) = (plan.scale[k], plan.drop[k], plan.mask);
    let (mult, last, stride) = (plan.mult[k], plan.last[k], plan.stride[k]);
    let walled = WALLS && plan.walled[k];
    let mut m = 0.0f64;
    for (i, ((&v, w), c)) in vel
        .iter()
        .zip(pos.iter_mut())
        .zip(dest.iter_mut())
        .enumerate()
    {
        let mut d = v * scale;
        if ACCELERATED {
            d += drop;
        }
        let a = d.abs();
        m = if a > m { a } else { m };
        // Exact truncation when |d| < 2^63 (else saturated, and the chunk is redone by
        // the caller); the identity bits of the step cleared.
        let step = (d as i64 as u64) & mask;
        let x = w.wrapping_add(step);
        *w = x;
        let cell = axis_cell(x & mask, mult, last) as u32 * stride;
        *c = if FIRST { cell } else { *c + cell };
        if walled && x > WALL_END {
            crossed.push(i);
        }
    }
    m
}

/// The per-axis constants of one step's integer flight.
struct Plan<const D: usize> {
    /// Lattice units (of the whole word) per unit of velocity: `units / L * dt`.
    scale: [f64; D],
    /// The displacement of gravity in lattice units, `g dt^2 / 2 * units / L`.
    drop: [f64; D],
    walled: [bool; D],
    /// The position bits of a word.
    mask: u64,
    /// The cell index's constants ([`CellIndex::axes`]).
    mult: [u64; D],
    last: [u64; D],
    stride: [u32; D],
}
