//! The collision law every engine calls: the pair impulse with normal restitution (HD-11),
//! the wall law with normal and tangential restitution (HD-3, HD-4), and the TC rule
//! against inelastic collapse (section 2.3 of the hard-disk assignment) with its counter; for
//! rough (spinning) grains the rule on the velocity of the contact point with normal and
//! tangential restitution (RS-1, [`rough`]).
//!
//! The event-driven engine resolves a collision at its exact contact; DSMC at the end of
//! its free flight (walls) or of its time step (pairs). Both call the functions below, so
//! that the same scenario applies the same law in both.

pub mod rough;

pub(crate) use rough::{Body, Spin, Tangential};

use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// How kinetic energy is lost in collisions.
///
/// Deserialised with defaults for missing keys (elastic, TC off).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CollisionLaw {
    /// Normal restitution coefficient ξ of grain-grain collisions, `0 <= ξ <= 1`
    /// (HD-11): the normal relative velocity is reversed and
    /// multiplied by ξ, the tangential one is unchanged; momentum is conserved.
    pub restitution: f64,
    /// Restitution of the wall-normal velocity component in grain-wall collisions
    /// (HD-3, HD-4: `v_n' = -e_w v_n`).
    pub wall_restitution: f64,
    /// Factor applied to the wall-tangential components in a wall collision
    /// (`v_t' = e_t v_t`). The hard-disk assignment's HD-3 and HD-4 multiply them by ξ too (so that with
    /// ξ = 0 a grain stops dead, test B.1); set it to 1 for smooth walls. For rough grains
    /// it multiplies the tangential velocity of the contact point instead (RS-1 at a wall
    /// with `β_w = -e_t`), which is the same thing for a grain that does not spin.
    pub wall_tangential_restitution: f64,
    /// Contact duration `t_c` of the TC model (section 2.3 of the hard-disk assignment, Luding and
    /// McNamara 1998): a collision of a grain less than `t_c` after its previous collision is
    /// elastic. Zero disables the model.
    pub contact_duration: f64,
    /// Tangential restitution β of grain-grain collisions, `-1 <= β <= 1` (RS-1): the
    /// tangential velocity of the contact point becomes `-β` times itself. `-1` (the
    /// default) is smooth grains, which never spin; `+1` perfectly rough. With
    /// [`Self::friction`] it is Walton's sticking value `β₀`.
    #[serde(skip_serializing_if = "is_smooth")]
    pub tangential_restitution: f64,
    /// Coulomb friction coefficient μ of Walton's rule (RS-7): the tangential impulse is at
    /// most μ times the normal one, so that β depends on the angle of impact. `None`: the
    /// constant β of [`Self::tangential_restitution`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

fn is_smooth(beta: &f64) -> bool {
    *beta == -1.0
}

impl Default for CollisionLaw {
    fn default() -> Self {
        Self {
            restitution: 1.0,
            wall_restitution: 1.0,
            wall_tangential_restitution: 1.0,
            contact_duration: 0.0,
            tangential_restitution: -1.0,
            friction: None,
        }
    }
}

impl CollisionLaw {
    /// The same restitution for pairs and walls, as in the hard-disk assignment (ξ everywhere).
    pub fn uniform(restitution: f64) -> Self {
        Self {
            restitution,
            wall_restitution: restitution,
            wall_tangential_restitution: restitution,
            contact_duration: 0.0,
            tangential_restitution: -1.0,
            friction: None,
        }
    }

    /// Whether every collision conserves the total (translational plus rotational)
    /// energy: `ξ = 1` with smooth walls, and for rough grains `β = ±1` without friction
    /// and `e_t = ±1` at the walls.
    pub fn is_elastic(&self) -> bool {
        if self.is_rough() {
            self.restitution == 1.0
                && self.friction.is_none()
                && self.tangential_restitution.abs() == 1.0
                && self.wall_restitution == 1.0
                && self.wall_tangential_restitution.abs() == 1.0
        } else {
            self.restitution == 1.0
                && self.wall_restitution == 1.0
                && self.wall_tangential_restitution == 1.0
        }
    }

    /// Whether grains are rough (they spin, and collisions exchange translational and
    /// rotational energy): `β > -1` or a friction coefficient. Smooth grains carry no
    /// angular velocities and no engine does any rotational work for them.
    pub fn is_rough(&self) -> bool {
        self.tangential_restitution != -1.0 || self.friction.is_some()
    }

    /// The tangential law of a grain-grain collision at restitution `beta` (the constant
    /// β of RS-1, or Walton's rule RS-7 with sticking value `beta`).
    #[inline(always)]
    pub(crate) fn tangential(&self, beta: f64) -> Tangential {
        match self.friction {
            None => Tangential::Constant(beta),
            Some(friction) => Tangential::Coulomb {
                friction,
                sticking: beta,
            },
        }
    }

    /// The TC rule with its counter for a collision of rough grains at `now` whose
    /// previous collisions happened at `last` (empty without the TC model): the normal
    /// restitution and the tangential law, or `(1, smooth)` within `t_c` of a previous
    /// collision: an elastic collision of smooth grains, which neither dissipates energy
    /// nor exchanges it between translation and rotation (McNamara and Luding, Phys. Rev.
    /// E 58, 2247 (1998)). A collision so made elastic that would otherwise have lost
    /// energy adds one to `tc_elastic`.
    #[inline(always)]
    pub(crate) fn rough_pair_now(
        &self,
        now: f64,
        last: &[f64],
        tc_elastic: &mut u64,
    ) -> (f64, Tangential) {
        if self.contact_duration > 0.0 && last.iter().any(|&t| now - t < self.contact_duration) {
            if !self.is_elastic_pair() {
                *tc_elastic += 1;
            }
            (1.0, Tangential::Constant(-1.0))
        } else {
            (
                self.restitution,
                self.tangential(self.tangential_restitution),
            )
        }
    }

    /// Whether a grain-grain collision conserves energy (`ξ = 1`, and `β = ±1` without
    /// friction for rough grains).
    fn is_elastic_pair(&self) -> bool {
        self.restitution == 1.0
            && (!self.is_rough()
                || (self.friction.is_none() && self.tangential_restitution.abs() == 1.0))
    }

    /// Whether the TC model is on (`contact_duration > 0`): the engines then keep every
    /// grain's last collision time.
    pub(crate) fn has_tc(&self) -> bool {
        self.contact_duration > 0.0
    }

    /// The restitution to use for a collision at `now` of grains whose previous collisions
    /// happened at `last` (TC model: elastic within `t_c` of a previous collision).
    /// Times in time units; `last` empty when the engine keeps no collision times.
    #[inline(always)]
    pub(crate) fn effective(&self, coefficient: f64, now: f64, last: &[f64]) -> f64 {
        if self.contact_duration > 0.0 && last.iter().any(|&t| now - t < self.contact_duration) {
            1.0
        } else {
            coefficient
        }
    }

    /// The TC rule with its counter for a pair collision at `now` (time units) of grains
    /// whose previous collisions happened at `last` (empty without the TC model): the pair
    /// restitution ξ of HD-11, or 1 within `t_c` of a previous collision. A collision made
    /// elastic that would otherwise have lost energy (`ξ < 1`) adds one to `tc_elastic`.
    #[inline(always)]
    pub(crate) fn pair_restitution(&self, now: f64, last: &[f64], tc_elastic: &mut u64) -> f64 {
        let xi = self.effective(self.restitution, now, last);
        if xi == 1.0 && self.restitution != 1.0 {
            *tc_elastic += 1;
        }
        xi
    }

    /// The TC rule with its counter for a wall collision at `now` of a grain whose previous
    /// collision happened at `last` (empty without the TC model): the wall's normal and
    /// tangential restitutions, both 1 when the TC model makes the collision elastic. A
    /// wall whose normal restitution is 1 is left as it is (its tangential factor applies
    /// whatever the TC model says), and only collisions made elastic that would otherwise
    /// have lost normal energy add one to `tc_elastic`.
    #[inline(always)]
    pub(crate) fn wall_restitution_now(
        &self,
        now: f64,
        last: &[f64],
        tc_elastic: &mut u64,
    ) -> WallRestitution {
        let normal = self.effective(self.wall_restitution, now, last);
        let tangential = if normal == 1.0 && self.wall_restitution != 1.0 {
            *tc_elastic += 1;
            1.0
        } else {
            self.wall_tangential_restitution
        };
        WallRestitution { normal, tangential }
    }
}

/// The two restitutions of one wall collision (after the TC rule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallRestitution {
    /// Factor `e_w` of HD-3/HD-4 on the wall-normal component, which is also reversed.
    pub normal: f64,
    /// Factor `e_t` on each wall-tangential component.
    pub tangential: f64,
}

impl WallRestitution {
    /// The velocity after a collision with a wall perpendicular to `axis` (HD-3, HD-4
    /// with separate normal and tangential factors): `v_axis' = -e_w v_axis`,
    /// `v_k' = e_t v_k` for every other axis `k`. Velocities in length / time.
    #[inline(always)]
    pub fn apply<const D: usize>(&self, v: &Vector<D>, axis: usize) -> Vector<D> {
        let mut out = *v;
        for k in 0..D {
            out[k] = if k == axis {
                -self.normal * v[k]
            } else {
                self.tangential * v[k]
            };
        }
        out
    }

    /// A wall collision of a rough grain (`body`, velocity `v`, spin `w`) with the wall
    /// perpendicular to `axis` on its `upper` (coordinate `L`) or lower side: RS-1 at a
    /// wall with `α_w` the normal factor and `β_w = -e_t` (the tangential factor
    /// multiplies the velocity of the contact point). Returns the energy dissipated.
    #[inline]
    pub(crate) fn apply_rough<const D: usize>(
        &self,
        axis: usize,
        upper: bool,
        body: &Body,
        v: &mut Vector<D>,
        w: &mut Spin,
    ) -> f64 {
        let mut n = Vector::<D>::zero();
        n[axis] = if upper { 1.0 } else { -1.0 };
        rough::collide_wall(
            self.normal,
            Tangential::Constant(-self.tangential),
            &n,
            body,
            v,
            w,
        )
    }
}

/// The change of the normal relative velocity in a pair collision with restitution `xi`
/// (HD-11): the normal component `u_n` of the relative velocity (any sign convention, any
/// scale: the law is linear) becomes `-xi u_n`, so it changes by `-(1 + xi) u_n`; the
/// tangential part is unchanged. Grain `i` of mass `m_i` takes the fraction
/// `m_j / (m_i + m_j)` of the change along the normal, its partner the rest with the
/// opposite sign, so that momentum is conserved.
#[inline(always)]
pub(crate) fn normal_velocity_change(xi: f64, normal_velocity: f64) -> f64 {
    -(1.0 + xi) * normal_velocity
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tc_rule_counts_only_collisions_it_makes_elastic() {
        let law = CollisionLaw {
            contact_duration: 0.5,
            ..CollisionLaw::uniform(0.8)
        };
        let mut n = 0;
        assert_eq!(law.pair_restitution(1.0, &[0.0, 0.2], &mut n), 0.8);
        assert_eq!(n, 0);
        assert_eq!(law.pair_restitution(1.0, &[0.0, 0.7], &mut n), 1.0);
        assert_eq!(n, 1);
        assert_eq!(law.pair_restitution(1.0, &[], &mut n), 0.8);
        let w = law.wall_restitution_now(1.0, &[0.9], &mut n);
        assert_eq!((w.normal, w.tangential, n), (1.0, 1.0, 2));
        let w = law.wall_restitution_now(1.0, &[0.1], &mut n);
        assert_eq!((w.normal, w.tangential, n), (0.8, 0.8, 2));
        // An elastic law is never counted.
        let mut m = 0;
        let elastic = CollisionLaw {
            contact_duration: 0.5,
            ..CollisionLaw::default()
        };
        assert_eq!(elastic.pair_restitution(1.0, &[0.9, 0.9], &mut m), 1.0);
        assert_eq!(m, 0);
    }

    /// The TC rule for rough grains: within `t_c` a collision is elastic and smooth
    /// (`α = 1`, `β = -1`), counted when it would otherwise have lost energy.
    #[test]
    fn tc_rule_makes_rough_collisions_elastic_and_smooth() {
        let law = CollisionLaw {
            contact_duration: 0.5,
            tangential_restitution: 0.4,
            ..CollisionLaw::uniform(0.8)
        };
        assert!(law.is_rough() && !law.is_elastic());
        let mut n = 0;
        assert_eq!(
            law.rough_pair_now(1.0, &[0.0, 0.2], &mut n),
            (0.8, Tangential::Constant(0.4))
        );
        assert_eq!(n, 0);
        assert_eq!(
            law.rough_pair_now(1.0, &[0.7, 0.0], &mut n),
            (1.0, Tangential::Constant(-1.0))
        );
        assert_eq!(n, 1);
        // Elastic perfectly rough grains lose nothing: not counted.
        let rough_elastic = CollisionLaw {
            contact_duration: 0.5,
            tangential_restitution: 1.0,
            ..CollisionLaw::default()
        };
        assert!(rough_elastic.is_elastic());
        rough_elastic.rough_pair_now(1.0, &[0.9], &mut n);
        assert_eq!(n, 1);
        // Walton's rule carries β as its sticking value.
        let walton = CollisionLaw {
            friction: Some(0.3),
            ..law.clone()
        };
        assert_eq!(
            walton.rough_pair_now(1.0, &[], &mut n).1,
            Tangential::Coulomb {
                friction: 0.3,
                sticking: 0.4
            }
        );
        assert!(!CollisionLaw::uniform(0.5).is_rough());
    }

    #[test]
    fn wall_law_scales_normal_and_tangential_components() {
        let w = WallRestitution {
            normal: 0.5,
            tangential: 0.25,
        };
        let v = w.apply(&Vector([2.0, -4.0, 8.0]), 1);
        assert_eq!(v.0, [0.5, 2.0, 2.0]);
        assert_eq!(normal_velocity_change(0.5, -2.0), 3.0);
    }
}
