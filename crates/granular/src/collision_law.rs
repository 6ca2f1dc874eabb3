//! Collision laws shared by the engines: normal restitution for grain pairs and walls, and
//! the TC model against inelastic collapse.

use serde::{Deserialize, Serialize};

/// How kinetic energy is lost in collisions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CollisionLaw {
    /// Normal restitution coefficient ξ of grain-grain collisions, `0 <= ξ <= 1`
    /// (HD-11): the normal relative velocity is reversed and
    /// multiplied by ξ, the tangential one is unchanged; momentum is conserved.
    pub restitution: f64,
    /// Restitution of the wall-normal velocity component in grain-wall collisions
    /// (HD-3, HD-4).
    pub wall_restitution: f64,
    /// Factor applied to the wall-tangential components in a wall collision. HD-3 and
    /// HD-4 multiply them by ξ too (so that with ξ = 0 a grain stops dead, test B.1);
    /// set it to 1 for smooth walls.
    pub wall_tangential_restitution: f64,
    /// Contact duration `t_c` of the TC model (section 2.3 of the hard-disk seed, Luding and
    /// McNamara 1998): a collision of a grain less than `t_c` after its previous collision is
    /// elastic. Zero disables the model.
    pub contact_duration: f64,
}

impl Default for CollisionLaw {
    fn default() -> Self {
        Self {
            restitution: 1.0,
            wall_restitution: 1.0,
            wall_tangential_restitution: 1.0,
            contact_duration: 0.0,
        }
    }
}

impl CollisionLaw {
    /// The same restitution for pairs and walls, as in the seed (ξ everywhere).
    pub fn uniform(restitution: f64) -> Self {
        Self {
            restitution,
            wall_restitution: restitution,
            wall_tangential_restitution: restitution,
            contact_duration: 0.0,
        }
    }

    /// Whether every collision is elastic.
    pub fn is_elastic(&self) -> bool {
        self.restitution == 1.0
            && self.wall_restitution == 1.0
            && self.wall_tangential_restitution == 1.0
    }

    /// The restitution to use for a collision at `now` of grains whose previous collisions
    /// happened at `last` (TC model: elastic within `t_c` of a previous collision).
    #[inline(always)]
    pub fn effective(&self, coefficient: f64, now: f64, last: &[f64]) -> f64 {
        if self.contact_duration > 0.0 && last.iter().any(|&t| now - t < self.contact_duration) {
            1.0
        } else {
            coefficient
        }
    }
}
