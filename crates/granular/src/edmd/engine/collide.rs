//! The collision rules: a pair collision (HD-11) and a wall collision (HD-3, HD-4) under
//! the collision law and its TC rule, or, while the radii grow (compression), the elastic
//! reflection in the frame of the growing surfaces; for rough grains the rule on the
//! contact-point velocity (RS-1); the totals, the impact-parameter histogram and the
//! optional collision log.

use super::Edmd;
use crate::collision_law::rough::{self, Body, Tangential, set_spin, spin_at};
use crate::collision_law::{WallRestitution, normal_velocity_change};
use crate::neighbours::NONE;
use crate::vector::Vector;

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

impl<const D: usize> Edmd<D> {
    /// The pair restitution for a collision now of slots `a` and `b` under the TC rule of
    /// the collision law, counted in the totals.
    #[inline(always)]
    pub(super) fn pair_restitution(&mut self, a: usize, b: usize) -> f64 {
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
    pub(super) fn wall_restitution(&mut self, a: usize) -> WallRestitution {
        let tc = &mut self.totals.tc_elastic_collisions;
        if self.last_collision.is_empty() {
            return self.law.wall_restitution_now(self.now, &[], tc);
        }
        let last = [self.last_collision[a]];
        self.law.wall_restitution_now(self.now, &last, tc)
    }

    /// The normal restitution and tangential law of a collision now of rough slots `a`
    /// and `b` under the TC rule (elastic and smooth within `t_c`), counted in the totals.
    #[inline(always)]
    fn rough_restitution(&mut self, a: usize, b: usize) -> (f64, Tangential) {
        let tc = &mut self.totals.tc_elastic_collisions;
        if self.last_collision.is_empty() {
            return self.law.rough_pair_now(self.now, &[], tc);
        }
        let last = [self.last_collision[a], self.last_collision[b]];
        self.law.rough_pair_now(self.now, &last, tc)
    }

    /// Slot `s` as a rough collision sees it.
    #[inline(always)]
    fn body(&self, s: usize) -> Body {
        Body {
            mass: self.mass(s),
            radius: self.base_radius(s),
            inertia: self.kind_inertia[self.grains[s].kind as usize],
        }
    }

    /// Resolves a pair collision (HD-11; RS-1 for rough grains), both grains at `now`.
    pub(super) fn collide_pair(&mut self, i: usize, j: usize) {
        let dx = self.bx.separation(&self.grains[i].pos, &self.grains[j].pos);
        let dv = self.grains[j].vel - self.grains[i].vel;
        let d2 = dx.norm_squared();
        let b = dx.dot(&dv);
        if !self.spin.is_empty() && self.growth == 0.0 {
            self.collide_rough_pair(i, j, &dx, d2);
        } else {
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
        }
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

    /// A pair collision of rough grains (RS-1, `collision_law::rough::collide_pair`) along
    /// `dx` (from `i` to `j`, `|dx|² = d2`): velocities and spins, the energy lost
    /// (translational and rotational) and the virial `(x_i - x_j)·Δp_i = -dx·Δp_i` (only
    /// the normal impulse contributes). Never inlined: the smooth path of `collide_pair`
    /// must stay small enough for the event loop to inline it (docs/performance.md).
    #[inline(never)]
    fn collide_rough_pair(&mut self, i: usize, j: usize, dx: &Vector<D>, d2: f64) {
        let n = *dx * (1.0 / d2.sqrt());
        let (alpha, tangential) = self.rough_restitution(i, j);
        let (a, b) = (self.body(i), self.body(j));
        let (mut vi, mut vj) = (self.grains[i].vel, self.grains[j].vel);
        let (mut wi, mut wj) = (spin_at::<D>(&self.spin, i), spin_at::<D>(&self.spin, j));
        let before = vi;
        let lost = rough::collide_pair(
            alpha, tangential, &n, &a, &b, &mut vi, &mut vj, &mut wi, &mut wj,
        );
        self.grains[i].vel = vi;
        self.grains[j].vel = vj;
        set_spin::<D>(&mut self.spin, i, &wi);
        set_spin::<D>(&mut self.spin, j, &wj);
        self.totals.dissipated_energy += lost;
        self.totals.virial -= a.mass * dx.dot(&(vi - before));
    }

    /// The wall collision of rough slot `i` (RS-1 at a wall): its spin changes in place,
    /// its new velocity goes to `v_new`; returns the energy lost. Never inlined, as
    /// `collide_rough_pair`.
    #[inline(never)]
    fn collide_rough_wall(
        &mut self,
        i: usize,
        axis: usize,
        upper: bool,
        v_new: &mut Vector<D>,
    ) -> f64 {
        let w = self.wall_restitution(i);
        let mut spin = spin_at::<D>(&self.spin, i);
        let lost = w.apply_rough(axis, upper, &self.body(i), v_new, &mut spin);
        set_spin::<D>(&mut self.spin, i, &spin);
        lost
    }

    /// Resolves a wall collision (HD-3, HD-4; RS-1 at a wall for rough grains).
    pub(super) fn collide_wall(&mut self, i: usize, axis: usize, upper: bool) {
        let v = self.grains[i].vel;
        let m = self.mass(i);
        let k0 = 0.5 * m * v.norm_squared();
        let mut v_new = v;
        let mut lost = None;
        if self.growth == 0.0 && !self.spin.is_empty() {
            lost = Some(self.collide_rough_wall(i, axis, upper, &mut v_new));
        } else if self.growth == 0.0 {
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
        self.totals.dissipated_energy += match lost {
            Some(e) => e,
            None => k0 - 0.5 * m * v_new.norm_squared(),
        };
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
}
