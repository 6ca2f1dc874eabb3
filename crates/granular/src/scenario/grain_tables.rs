//! The tables that describe the grains of the many-grain engines (`edmd`, `dsmc`): `[box]`,
//! `[[species]]` (with their initial velocities), `[initial]` and `[collisions]`. Read by
//! serde or by the hand-written readers of `de.rs`; checked by `validate.rs` and
//! `species.rs`.

use super::{AngularVelocitySpec, GrainVectors};
use serde::{Deserialize, Serialize};

/// `[box]`: an axis-aligned box `[0, L_0] x ...`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Edge lengths, one per axis (length units). Default: the unit square/cube.
    #[serde(default)]
    pub lengths: Vec<f64>,
    /// `"wall"` or `"periodic"` for all axes, or a list with one entry per axis.
    #[serde(default = "default_boundary")]
    pub boundary: BoundarySpec,
}

fn default_boundary() -> BoundarySpec {
    BoundarySpec::All(crate::boundary::AxisKind::Wall)
}

impl Default for BoxSpec {
    fn default() -> Self {
        Self {
            lengths: Vec::new(),
            boundary: default_boundary(),
        }
    }
}

impl BoxSpec {
    /// Whether this is the default box (left out of the resolved scenario then).
    pub(crate) fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// Boundary kinds: one for all axes or one per axis (read by a hand-written reader that
/// names the accepted values).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum BoundarySpec {
    /// The same on every axis.
    All(crate::boundary::AxisKind),
    /// One per axis.
    PerAxis(Vec<crate::boundary::AxisKind>),
}

/// `[[species]]`: a group of identical grains.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeciesSpec {
    /// Name used in outputs (`temperature.<name>`).
    pub name: String,
    /// Number of grains.
    pub count: usize,
    /// Radius (length units). Give either `radius` or `packing_fraction`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Packing fraction of this species in its region; sets the radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub packing_fraction: Option<f64>,
    /// Mass of one grain (mass units).
    #[serde(default = "unit")]
    pub mass: f64,
    /// Region `{ lo = [..], hi = [..] }` where the grains are placed; default: the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<RegionSpec>,
    /// Fixed positions, one `[x, y(, z)]` per grain (instead of a placement).
    #[serde(default, skip_serializing_if = "GrainVectors::is_empty")]
    pub positions: GrainVectors,
    /// Initial velocities.
    #[serde(default)]
    pub velocity: VelocitySpec,
    /// Reduced moment of inertia `κ = 4I/(mσ²)` of rough grains (RS-1): in (0, 1] for
    /// disks, (0, 2/3] for spheres; default 1/2 (uniform disk) or 2/5 (uniform sphere).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// Initial angular velocities of rough grains; default: none (zero spin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity: Option<AngularVelocitySpec>,
}

fn unit() -> f64 {
    1.0
}

/// A box-aligned region.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Lower corner.
    pub lo: Vec<f64>,
    /// Upper corner.
    pub hi: Vec<f64>,
}

/// Initial velocities of a species (read by a hand-written reader: a misspelt key is
/// reported as unknown, with the expected keys).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "distribution", rename_all = "snake_case")]
pub enum VelocitySpec {
    /// All grains at rest.
    Zero,
    /// Speed `speed` in a uniformly random direction (Problem 1 of the hard-disk assignment).
    FixedSpeed {
        /// The common speed (length/time).
        speed: f64,
    },
    /// Maxwell-Boltzmann at `temperature` (energy units, `k_B = 1`).
    MaxwellBoltzmann {
        /// Temperature.
        temperature: f64,
    },
    /// The same given velocity for every grain of the species (e.g. a projectile).
    Given {
        /// Velocity vector.
        velocity: Vec<f64>,
    },
    /// One velocity per grain.
    PerGrain {
        /// Velocity vectors, one per grain (inline, an `.npz` member or given by a program).
        velocities: GrainVectors,
    },
}

impl Default for VelocitySpec {
    fn default() -> Self {
        VelocitySpec::MaxwellBoltzmann { temperature: 1.0 }
    }
}

/// How grains are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// Random sequential placement without overlaps.
    Random,
    /// Square (cubic) lattice filling the region.
    Lattice,
}

/// `[initial]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// `"random"` or `"lattice"`.
    #[serde(default = "random_placement")]
    pub placement: Placement,
    /// If set, grains are first placed at this (lower) packing fraction and then grown to
    /// their radii with the event engine (Lubachevsky-Stillinger compression); needed for
    /// random dense states (2D above ~0.45, 3D above ~0.3). Periodic boxes, one species.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compress_from: Option<f64>,
    /// Subtract the centre-of-mass velocity.
    #[serde(default)]
    pub zero_momentum: bool,
    /// Random placement attempts per grain before giving up.
    #[serde(default = "attempts")]
    pub max_attempts: usize,
}

fn random_placement() -> Placement {
    Placement::Random
}
fn attempts() -> usize {
    100_000
}

impl Default for InitialSpec {
    fn default() -> Self {
        Self {
            placement: Placement::Random,
            compress_from: None,
            zero_momentum: false,
            max_attempts: attempts(),
        }
    }
}

/// `[collisions]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CollisionSpec {
    /// Grain-grain normal restitution ξ in [0, 1] (HD-11).
    #[serde(default = "unit")]
    pub restitution: f64,
    /// Wall normal restitution in [0, 1] (HD-3, HD-4); default: `restitution`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_restitution: Option<f64>,
    /// Factor on the wall-tangential velocity; default: the wall restitution, as in
    /// HD-3 and HD-4. Use 1 for smooth walls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_tangential_restitution: Option<f64>,
    /// TC-model contact duration t_c (time units); 0 disables it.
    #[serde(default)]
    pub contact_duration: f64,
    /// Tangential restitution β in [-1, 1] of grain-grain collisions (RS-1): above -1 the
    /// grains are rough and rotate; default -1 (smooth grains).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential_restitution: Option<f64>,
    /// Coulomb friction coefficient μ >= 0 of Walton's rule (RS-7), with
    /// `tangential_restitution` as the sticking value β₀; absent: a constant β.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
}

impl Default for CollisionSpec {
    fn default() -> Self {
        Self {
            restitution: 1.0,
            wall_restitution: None,
            wall_tangential_restitution: None,
            contact_duration: 0.0,
            tangential_restitution: None,
            friction: None,
        }
    }
}

impl CollisionSpec {
    /// The collision law with defaults resolved.
    pub fn law(&self) -> crate::collision_law::CollisionLaw {
        let wall = self.wall_restitution.unwrap_or(self.restitution);
        crate::collision_law::CollisionLaw {
            restitution: self.restitution,
            wall_restitution: wall,
            wall_tangential_restitution: self.wall_tangential_restitution.unwrap_or(wall),
            contact_duration: self.contact_duration,
            tangential_restitution: self.tangential_restitution.unwrap_or(-1.0),
            friction: self.friction,
        }
    }
}
