//! The free-flight stage of a DSMC step: every grain moves exactly under a constant
//! acceleration, and hard walls apply the shared wall law (HD-3, HD-4 with the TC rule of
//! [`crate::collision_law`]); periodic axes wrap.

use super::cells::{CellGrid, CellLookup};
use crate::boundary::{AxisKind, SimulationBox};
use crate::collision_law::CollisionLaw;
use crate::vector::Vector;

/// What the free flight of one step needs (the same for every grain).
pub(crate) struct Flight<'a, const D: usize> {
    pub(crate) bx: &'a SimulationBox<D>,
    pub(crate) grid: &'a CellGrid<D>,
    pub(crate) law: &'a CollisionLaw,
    pub(crate) gravity: Vector<D>,
    /// Length of the step (time units).
    pub(crate) dt: f64,
    /// Time at the end of the step.
    pub(crate) t_end: f64,
}

impl<const D: usize> Flight<'_, D> {
    /// Moves one chunk of grains (positions `p`, velocities `v`, last collision times `l`,
    /// empty without the TC model), records their cells in `c`: the chunk's cell
    /// occupations and its count of wall collisions made elastic by the TC rule.
    pub(crate) fn fly(
        &self,
        p: &mut [Vector<D>],
        v: &mut [Vector<D>],
        c: &mut [u32],
        l: &mut [f64],
    ) -> (Vec<u32>, u64) {
        if self.bx.axes.iter().all(|&a| a == AxisKind::Periodic) {
            return (self.fly_periodic(p, v, c), 0);
        }
        let (g, dt) = (self.gravity, self.dt);
        let mut cnt = vec![0u32; self.grid.len()];
        let mut tc_elastic = 0;
        for (k, ((x, u), ci)) in p.iter_mut().zip(v.iter_mut()).zip(c.iter_mut()).enumerate() {
            *x = x.add_scaled(dt, u).add_scaled(0.5 * dt * dt, &g);
            *u = u.add_scaled(dt, &g);
            let last = l.get_mut(k);
            self.confine(x, u, last, &mut tc_elastic);
            let cell = self.grid.index(&x.0);
            *ci = cell;
            cnt[cell as usize] += 1;
        }
        (cnt, tc_elastic)
    }

    /// [`Self::fly`] in a box periodic along every axis (no walls, so the collision
    /// times of the TC rule are untouched): the same arithmetic as the general path,
    /// without its per-axis dispatch. Without gravity the velocities are not written
    /// back (`u + dt * 0` is `u`, up to the sign of an exact zero component, which no
    /// result depends on), which saves a store stream.
    fn fly_periodic(&self, p: &mut [Vector<D>], v: &mut [Vector<D>], c: &mut [u32]) -> Vec<u32> {
        if self.gravity.0.iter().any(|&a| a != 0.0) {
            self.fly_periodic_with::<true>(p, v, c)
        } else {
            self.fly_periodic_with::<false>(p, v, c)
        }
    }

    /// [`Self::fly_periodic`] with the presence of gravity fixed at compile time.
    #[inline(always)]
    fn fly_periodic_with<const ACCELERATED: bool>(
        &self,
        p: &mut [Vector<D>],
        v: &mut [Vector<D>],
        c: &mut [u32],
    ) -> Vec<u32> {
        let (g, dt) = (self.gravity, self.dt);
        let lengths = self.bx.lengths.0;
        // For `y >= 0` (not a negative zero) the bit patterns order like the values, and
        // a negative number, a negative zero or NaN has a pattern above `L`'s: so
        // `bits(y) >= bits(L)` holds whenever `y >= L || y < 0` does (the wrap's test),
        // and for a few more values (-0.0, NaN) that the exact test below leaves alone.
        let length_bits = lengths.map(f64::to_bits);
        let cells = CellLookup::new(self.grid);
        let mut cnt = vec![0u32; self.grid.len()];
        for ((x, u), ci) in p.iter_mut().zip(v.iter_mut()).zip(c.iter_mut()) {
            let mut y = x.add_scaled(dt, u).add_scaled(0.5 * dt * dt, &g);
            if ACCELERATED {
                *u = u.add_scaled(dt, &g);
            }
            let mut out = false;
            for (&yk, &lb) in y.0.iter().zip(&length_bits) {
                out |= yk.to_bits() >= lb;
            }
            if out {
                for (yk, &l) in y.0.iter_mut().zip(&lengths) {
                    if *yk >= l || *yk < 0.0 {
                        *yk = yk.rem_euclid(l);
                        if *yk >= l {
                            *yk = 0.0;
                        }
                    }
                }
            }
            *x = y;
            let cell = cells.index(&y.0);
            *ci = cell;
            if let Some(k) = cnt.get_mut(cell as usize) {
                *k += 1;
            }
        }
        cnt
    }

    /// Hard walls: the shared wall law (HD-3, HD-4 with the TC rule, see
    /// [`CollisionLaw::wall_restitution_now`]) applied at each crossing of a wall during
    /// the flight; periodic axes: wrap. A grain that ended the flight a distance `s` past a
    /// wall hit it `s / |v_n|` before the end of the step (exact without gravity): after
    /// the hit its normal speed is `e_w |v_n|` (its overshoot is mirrored and scaled by
    /// `e_w`) and its tangential velocity `e_t v_t` (its tangential displacement since the
    /// hit is scaled by `e_t`); the hit time is the one the TC rule sees and records.
    #[inline(always)]
    fn confine(
        &self,
        x: &mut Vector<D>,
        v: &mut Vector<D>,
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
                if x[k] < 0.0 {
                    x[k] *= -e;
                } else {
                    x[k] = l - e * (x[k] - l);
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
