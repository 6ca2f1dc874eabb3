//! Hand-written readers of the scenario values whose derived readers gave vague errors:
//! `box.boundary` (an untagged enum: "did not match any variant of untagged enum") and a
//! species' `velocity` (an internally tagged enum: a misspelt `distribution` read as a
//! missing one). The errors name the value and the accepted values; the key and line come
//! from the parser's span (see `spans`).

use super::{BoundarySpec, VelocitySpec};
use crate::boundary::AxisKind;
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;

const BOUNDARY_HELP: &str = "use \"wall\" or \"periodic\" (every axis), or a list with one per axis, e.g. [\"periodic\", \"wall\"]";

fn axis_kind<E: de::Error>(s: &str) -> Result<AxisKind, E> {
    match s {
        "wall" => Ok(AxisKind::Wall),
        "periodic" => Ok(AxisKind::Periodic),
        other => Err(E::custom(format!(
            "boundary \"{other}\" is not a boundary kind; {BOUNDARY_HELP}"
        ))),
    }
}

struct BoundaryVisitor;

impl<'de> Visitor<'de> for BoundaryVisitor {
    type Value = BoundarySpec;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "\"wall\", \"periodic\" or a list of them, one per axis")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<BoundarySpec, E> {
        axis_kind(v).map(BoundarySpec::All)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<BoundarySpec, A::Error> {
        let mut axes = Vec::new();
        while let Some(s) = seq.next_element::<String>()? {
            axes.push(axis_kind(&s)?);
        }
        Ok(BoundarySpec::PerAxis(axes))
    }
}

impl<'de> Deserialize<'de> for BoundarySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(BoundaryVisitor)
    }
}

/// Every key a `velocity` table may hold; which apply depends on `distribution`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawVelocity {
    distribution: Option<String>,
    speed: Option<f64>,
    temperature: Option<f64>,
    velocity: Option<Vec<f64>>,
    velocities: Option<super::GrainVectors>,
}

const DISTRIBUTIONS: &str = "\"zero\", \"fixed_speed\" (speed), \"maxwell_boltzmann\" (temperature), \"given\" (velocity) or \"per_grain\" (velocities)";

impl RawVelocity {
    /// The keys given besides `distribution`.
    fn given(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        for (name, present) in [
            ("speed", self.speed.is_some()),
            ("temperature", self.temperature.is_some()),
            ("velocity", self.velocity.is_some()),
            ("velocities", self.velocities.is_some()),
        ] {
            if present {
                out.push(name);
            }
        }
        out
    }

    fn into_spec<E: de::Error>(self) -> Result<VelocitySpec, E> {
        let Some(dist) = self.distribution.clone() else {
            return Err(E::custom(format!(
                "velocity has no `distribution`; add distribution = {DISTRIBUTIONS}"
            )));
        };
        let wanted: &[&str] = match dist.as_str() {
            "zero" => &[],
            "fixed_speed" => &["speed"],
            "maxwell_boltzmann" => &["temperature"],
            "given" => &["velocity"],
            "per_grain" => &["velocities"],
            other => {
                return Err(E::custom(format!(
                    "velocity distribution \"{other}\" is unknown; use {DISTRIBUTIONS}"
                )));
            }
        };
        if let Some(extra) = self.given().into_iter().find(|k| !wanted.contains(k)) {
            return Err(E::custom(format!(
                "velocity key `{extra}` does not apply to distribution = \"{dist}\"; remove it{}",
                match wanted.first() {
                    Some(w) => format!(" (this distribution takes `{w}`)"),
                    None => String::new(),
                }
            )));
        }
        let missing = |k: &str| {
            E::custom(format!(
                "velocity distribution = \"{dist}\" needs `{k}`; add it (docs/scenario.md, [[species]])"
            ))
        };
        Ok(match dist.as_str() {
            "zero" => VelocitySpec::Zero,
            "fixed_speed" => VelocitySpec::FixedSpeed {
                speed: self.speed.ok_or_else(|| missing("speed"))?,
            },
            "maxwell_boltzmann" => VelocitySpec::MaxwellBoltzmann {
                temperature: self.temperature.ok_or_else(|| missing("temperature"))?,
            },
            "given" => VelocitySpec::Given {
                velocity: self.velocity.ok_or_else(|| missing("velocity"))?,
            },
            _ => VelocitySpec::PerGrain {
                velocities: self.velocities.ok_or_else(|| missing("velocities"))?,
            },
        })
    }
}

impl<'de> Deserialize<'de> for VelocitySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        RawVelocity::deserialize(d)?.into_spec()
    }
}

/// The whole range of `seed`: TOML integers are signed 64-bit, so seeds above `i64::MAX`
/// are written as a string of digits (`seed = "18446744073709551615"`), and read either way.
pub(super) mod seed {
    use super::*;

    /// What a seed may be, in the words of the scenario and the command line (`--seed`).
    pub const HELP: &str = "a seed is a whole number from 0 to 18446744073709551615 (2^64 - 1)";

    struct SeedVisitor;

    impl Visitor<'_> for SeedVisitor {
        type Value = u64;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str(HELP)
        }

        fn visit_u64<E: de::Error>(self, v: u64) -> Result<u64, E> {
            Ok(v)
        }

        fn visit_i64<E: de::Error>(self, v: i64) -> Result<u64, E> {
            u64::try_from(v).map_err(|_| E::custom(format!("is {v}; {HELP}")))
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<u64, E> {
            v.trim()
                .parse()
                .map_err(|_| E::custom(format!("is \"{v}\"; {HELP}")))
        }
    }

    /// Reads a seed from an integer or a string of digits.
    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
        d.deserialize_any(SeedVisitor)
    }

    /// Writes a seed as an integer, or as a string above `i64::MAX`.
    pub fn serialize<S: serde::Serializer>(v: &u64, s: S) -> Result<S::Ok, S::Error> {
        match i64::try_from(*v) {
            Ok(i) => s.serialize_i64(i),
            Err(_) => s.serialize_str(&v.to_string()),
        }
    }
}
