//! Rough grains in a scenario: the keys `collisions.tangential_restitution`,
//! `collisions.friction`, `species[i].inertia` and `species[i].angular_velocity`, their
//! reader and their validation (`docs/scenario.md`, "Rough grains"; the rule is RS-1 of
//! `docs/rough.md`).

use super::validate::{finite, non_negative, num};
use super::{EngineKind, Scenario, ScenarioError};
use crate::collision_law::rough::{max_inertia, rotational_dof, uniform_inertia};
use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

/// Initial angular velocities of a species of rough grains.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "distribution", rename_all = "snake_case")]
pub enum AngularVelocitySpec {
    /// No spin.
    Zero,
    /// Every component Gaussian with variance `T_r / I` (`I = κ m R²`): the rotational
    /// temperature `temperature` per rotational degree of freedom (energy units).
    MaxwellBoltzmann {
        /// Rotational temperature `T_r`.
        temperature: f64,
    },
    /// The same angular velocity for every grain: one value (about `z`) for disks, three
    /// for spheres, radians per time unit.
    Given {
        /// `[ω_z]` or `[ω_x, ω_y, ω_z]`.
        angular_velocity: Vec<f64>,
    },
}

/// Every key an `angular_velocity` table may hold.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    distribution: Option<String>,
    temperature: Option<f64>,
    angular_velocity: Option<Vec<f64>>,
}

const DISTRIBUTIONS: &str =
    "\"zero\", \"maxwell_boltzmann\" (temperature) or \"given\" (angular_velocity)";

impl<'de> Deserialize<'de> for AngularVelocitySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let raw = Raw::deserialize(d)?;
        let Some(dist) = raw.distribution else {
            return Err(de::Error::custom(format!(
                "angular_velocity has no `distribution`; add distribution = {DISTRIBUTIONS}"
            )));
        };
        let extra = |k: &str| {
            de::Error::custom(format!(
                "angular_velocity key `{k}` does not apply to distribution = \"{dist}\"; remove it"
            ))
        };
        let missing = |k: &str| {
            de::Error::custom(format!(
                "angular_velocity distribution = \"{dist}\" needs `{k}`; add it (docs/scenario.md, rough grains)"
            ))
        };
        match dist.as_str() {
            "zero" => match (raw.temperature, raw.angular_velocity) {
                (Some(_), _) => Err(extra("temperature")),
                (_, Some(_)) => Err(extra("angular_velocity")),
                _ => Ok(AngularVelocitySpec::Zero),
            },
            "maxwell_boltzmann" => {
                if raw.angular_velocity.is_some() {
                    return Err(extra("angular_velocity"));
                }
                Ok(AngularVelocitySpec::MaxwellBoltzmann {
                    temperature: raw.temperature.ok_or_else(|| missing("temperature"))?,
                })
            }
            "given" => {
                if raw.temperature.is_some() {
                    return Err(extra("temperature"));
                }
                Ok(AngularVelocitySpec::Given {
                    angular_velocity: raw
                        .angular_velocity
                        .ok_or_else(|| missing("angular_velocity"))?,
                })
            }
            other => Err(de::Error::custom(format!(
                "angular_velocity distribution \"{other}\" is unknown; use {DISTRIBUTIONS}"
            ))),
        }
    }
}

/// `collisions.wall_tangential_restitution` of rough grains: a factor in [-1, 1] on the
/// tangential velocity of the contact point (`β_w = -e_t`; 1 smooth, -1 perfectly rough).
fn wall_tangential(w: f64) -> Result<(), ScenarioError> {
    if (-1.0..=1.0).contains(&w) {
        Ok(())
    } else {
        Err(ScenarioError::new(
            "collisions.wall_tangential_restitution",
            format!(
                "is {}; for rough grains it multiplies the tangential velocity of the contact point and must lie in [-1, 1] (1 = smooth wall, 0 = the contact point stops sliding, -1 = perfectly rough wall)",
                num(w)
            ),
        ))
    }
}

/// The rough keys: β in [-1, 1]; μ >= 0 with a β₀; κ in range; angular velocities only for
/// rough grains, with one value per rotational degree of freedom.
pub(super) fn validate(sc: &Scenario) -> Result<(), ScenarioError> {
    let c = sc.collisions();
    if let Some(w) = c.wall_tangential_restitution
        && c.law().is_rough()
    {
        wall_tangential(w)?;
    }
    if let Some(beta) = c.tangential_restitution
        && !(-1.0..=1.0).contains(&beta)
    {
        return Err(ScenarioError::new(
            "collisions.tangential_restitution",
            format!(
                "is {}; the tangential restitution β must lie in [-1, 1] (-1 = smooth grains that never spin, 0 = the contact point stops sliding, 1 = perfectly rough); pick a value in that range",
                num(beta)
            ),
        ));
    }
    if let Some(mu) = c.friction {
        non_negative(
            "collisions.friction",
            mu,
            "the Coulomb friction coefficient μ",
        )?;
        if c.tangential_restitution.is_none_or(|b| b == -1.0) {
            return Err(ScenarioError::new(
                "collisions.friction",
                format!(
                    "is {} but collisions.tangential_restitution (the sticking value β₀ of Walton's rule) is -1, so the grains would slide without ever sticking and stay smooth; give collisions.tangential_restitution > -1, e.g. 0.4",
                    num(mu)
                ),
            ));
        }
    }
    let rough = c.law().is_rough();
    if rough && sc.kind() == EngineKind::Dsmc {
        // DSMC's collision rule is that of one kind of grain: one κ too.
        let kappa = |s: usize| {
            sc.species()[s]
                .inertia
                .unwrap_or(uniform_inertia(sc.dimension))
        };
        for s in 1..sc.species().len() {
            if kappa(s) != kappa(0) {
                return Err(ScenarioError::new(
                    format!("species[{s}].inertia"),
                    format!(
                        "is {} but species[0] has κ = {}: the DSMC engine takes species of equal grains (one radius, one mass, one moment of inertia); give every species the same inertia (or use engine = \"edmd\" for a mixture)",
                        num(kappa(s)),
                        num(kappa(0))
                    ),
                ));
            }
        }
    }
    let d = sc.dimension;
    let smooth_fix = "the grains are smooth (collisions.tangential_restitution is -1 or absent); make them rough with collisions.tangential_restitution in (-1, 1], or remove the key";
    for (s, sp) in sc.species().iter().enumerate() {
        let key = |f: &str| format!("species[{s}].{f}");
        if let Some(k) = sp.inertia {
            if !rough {
                return Err(ScenarioError::new(
                    key("inertia"),
                    format!("is {} but {smooth_fix}", num(k)),
                ));
            }
            let max = max_inertia(d);
            if !(k > 0.0 && k <= max) {
                return Err(ScenarioError::new(
                    key("inertia"),
                    format!(
                        "is {}; the reduced moment of inertia κ = 4I/(mσ²) of a {} must lie in (0, {}] ({} for a uniform {}, {} for a {}); pick a value in that range",
                        num(k),
                        if d == 2 { "disk" } else { "sphere" },
                        if d == 2 { "1" } else { "2/3" },
                        if d == 2 { "1/2" } else { "2/5" },
                        if d == 2 { "disk" } else { "sphere" },
                        if d == 2 { "1" } else { "2/3" },
                        if d == 2 { "ring" } else { "hollow sphere" },
                    ),
                ));
            }
        }
        let Some(spin) = &sp.angular_velocity else {
            continue;
        };
        if !rough && *spin != AngularVelocitySpec::Zero {
            return Err(ScenarioError::new(
                key("angular_velocity"),
                format!("is given but {smooth_fix}"),
            ));
        }
        match spin {
            AngularVelocitySpec::Zero => {}
            AngularVelocitySpec::MaxwellBoltzmann { temperature } => non_negative(
                &key("angular_velocity.temperature"),
                *temperature,
                "a rotational temperature",
            )?,
            AngularVelocitySpec::Given { angular_velocity } => {
                let r = rotational_dof(d);
                if angular_velocity.len() != r {
                    return Err(ScenarioError::new(
                        key("angular_velocity.angular_velocity"),
                        format!(
                            "has {} components; give {r} ({})",
                            angular_velocity.len(),
                            if d == 2 {
                                "[ω_z]: a disk spins about the axis normal to the plane"
                            } else {
                                "[ω_x, ω_y, ω_z]"
                            }
                        ),
                    ));
                }
                for (k, w) in angular_velocity.iter().enumerate() {
                    finite(
                        &format!("{}[{k}]", key("angular_velocity.angular_velocity")),
                        *w,
                        "an angular velocity component",
                    )?;
                }
            }
        }
    }
    Ok(())
}
