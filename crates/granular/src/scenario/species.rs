//! Validation of the `[[species]]` tables: name, count, size, mass, region, positions and
//! velocities of each species.

use super::validate::{finite, non_negative, positive};
use super::{Scenario, ScenarioError, SpeciesSpec, VelocitySpec};
use crate::boundary::AxisKind;

/// Longest species name.
pub(crate) const MAX_NAME_LEN: usize = 64;

/// Checks every species (at least one, names unique).
pub(super) fn validate(sc: &Scenario) -> Result<(), ScenarioError> {
    if sc.species().is_empty() {
        return Err(ScenarioError::new(
            "species",
            "no [[species]] table; add at least one with name, count and radius",
        ));
    }
    let mut names = std::collections::HashSet::new();
    for (s, sp) in sc.species().iter().enumerate() {
        let key = |f: &str| format!("species[{s}].{f}");
        name(&key("name"), &sp.name)?;
        if !names.insert(sp.name.as_str()) {
            return Err(ScenarioError::new(
                key("name"),
                format!(
                    "\"{}\" is used twice; give each species its own name",
                    sp.name
                ),
            ));
        }
        size(sc, s, &key)?;
        region(sc, sp, &key)?;
        positions(sc, s, &key)?;
        velocity(sc, sp, &key)?;
    }
    Ok(())
}

/// A species name appears in file names, CSV headers and column names
/// (`temperature.<name>`): ASCII letters, digits, `_` and `-`, not starting with `-`, at most
/// [`MAX_NAME_LEN`] characters.
pub fn name(key: &str, n: &str) -> Result<(), ScenarioError> {
    let ok = n.len() <= MAX_NAME_LEN
        && n.chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
        && n.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if ok {
        Ok(())
    } else {
        Err(ScenarioError::new(
            key,
            format!(
                "{n:?} is not a valid name; a species name holds only ASCII letters, digits, `_` and `-`, does not start with `-` and has 1 to {MAX_NAME_LEN} characters, e.g. \"light\", \"4m0\" or \"bed_grain\""
            ),
        ))
    }
}

/// Count, radius or packing fraction, mass, and the grain fitting in the box.
fn size(sc: &Scenario, s: usize, key: &dyn Fn(&str) -> String) -> Result<(), ScenarioError> {
    let sp = &sc.species()[s];
    if sp.count == 0 {
        return Err(ScenarioError::new(
            key("count"),
            "is 0; a species needs at least one grain",
        ));
    }
    match (sp.radius, sp.packing_fraction) {
        (Some(_), Some(_)) => {
            return Err(ScenarioError::new(
                key("radius"),
                "and packing_fraction are both given; keep one",
            ));
        }
        (None, None) => {
            return Err(ScenarioError::new(
                key("radius"),
                "is missing; give radius or packing_fraction",
            ));
        }
        (Some(r), None) => positive(&key("radius"), r, "a radius")?,
        (None, Some(p)) if !(p > 0.0 && p < 1.0) => {
            return Err(ScenarioError::new(
                key("packing_fraction"),
                format!("is {p}; it must lie in (0, 1)"),
            ));
        }
        _ => {}
    }
    positive(&key("mass"), sp.mass, "a mass")?;
    let r = sc.radius(s);
    let field = if sp.radius.is_some() {
        "radius"
    } else {
        "packing_fraction"
    };
    positive(&key(field), r, "the grain radius (from this key)")?;
    for (k, &l) in sc.lengths().iter().enumerate() {
        if 2.0 * r > l {
            return Err(ScenarioError::new(
                key("radius"),
                format!(
                    "is {r}: the grain does not fit in the box (axis {k} is {l} long); make it smaller than {}",
                    l / 2.0
                ),
            ));
        }
    }
    Ok(())
}

fn region(
    sc: &Scenario,
    sp: &SpeciesSpec,
    key: &dyn Fn(&str) -> String,
) -> Result<(), ScenarioError> {
    let Some(region) = &sp.region else {
        return Ok(());
    };
    let d = sc.dimension;
    let lengths = sc.lengths();
    if region.lo.len() != d || region.hi.len() != d {
        return Err(ScenarioError::new(
            key("region"),
            format!("needs lo and hi with {d} entries each"),
        ));
    }
    for (k, (&lo, &hi)) in region.lo.iter().zip(&region.hi).enumerate() {
        if !(lo >= 0.0 && hi <= lengths[k] && hi > lo) {
            return Err(ScenarioError::new(
                key("region"),
                format!(
                    "axis {k}: [{lo}, {hi}] must satisfy 0 <= lo < hi <= {}",
                    lengths[k]
                ),
            ));
        }
    }
    Ok(())
}

fn positions(sc: &Scenario, s: usize, key: &dyn Fn(&str) -> String) -> Result<(), ScenarioError> {
    let sp = &sc.species()[s];
    if sp.positions.is_empty() {
        return Ok(());
    }
    let (d, lengths, axes, r) = (sc.dimension, sc.lengths(), sc.axes(), sc.radius(s));
    if sp.positions.len() != sp.count {
        return Err(ScenarioError::new(
            key("positions"),
            format!(
                "lists {} positions for count = {}; give one per grain",
                sp.positions.len(),
                sp.count
            ),
        ));
    }
    if sp.positions.width() != d {
        return Err(ScenarioError::new(
            key("positions"),
            format!(
                "has {} components per grain; give {d} (one position per grain, in dimension {d})",
                sp.positions.width()
            ),
        ));
    }
    for (i, p) in sp.positions.iter().enumerate() {
        for k in 0..d {
            let walled = axes[k] == AxisKind::Wall;
            if !(p[k] >= 0.0 && p[k] <= lengths[k])
                || (walled && (p[k] < r || p[k] > lengths[k] - r))
            {
                return Err(ScenarioError::new(
                    key("positions"),
                    format!(
                        "position {i} = {p:?} puts the grain (radius {r}) outside the box or into a wall along axis {k}"
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn velocity(
    sc: &Scenario,
    sp: &SpeciesSpec,
    key: &dyn Fn(&str) -> String,
) -> Result<(), ScenarioError> {
    let d = sc.dimension;
    match &sp.velocity {
        VelocitySpec::Zero => Ok(()),
        VelocitySpec::FixedSpeed { speed } => {
            non_negative(&key("velocity.speed"), *speed, "a speed")
        }
        VelocitySpec::MaxwellBoltzmann { temperature } => {
            non_negative(&key("velocity.temperature"), *temperature, "a temperature")
        }
        VelocitySpec::Given { velocity } => {
            if velocity.len() != d {
                return Err(ScenarioError::new(
                    key("velocity.velocity"),
                    format!("has {} components; give {d}", velocity.len()),
                ));
            }
            for (k, &v) in velocity.iter().enumerate() {
                finite(
                    &format!("{}[{k}]", key("velocity.velocity")),
                    v,
                    "a velocity component",
                )?;
            }
            Ok(())
        }
        VelocitySpec::PerGrain { velocities } => {
            if velocities.len() != sp.count || velocities.width() != d {
                return Err(ScenarioError::new(
                    key("velocity.velocities"),
                    format!(
                        "needs {} vectors of {d} components (has {} of {})",
                        sp.count,
                        velocities.len(),
                        velocities.width()
                    ),
                ));
            }
            // The key is written only for a value at fault (a million grains are checked).
            let bad = |c: &f64| finite("", *c, "").is_err();
            if let Some(at) = velocities.values().iter().position(bad) {
                let (i, k) = (at / d, at % d);
                finite(
                    &format!("{}[{i}][{k}]", key("velocity.velocities")),
                    velocities.values()[at],
                    "a velocity component",
                )?;
            }
            Ok(())
        }
    }
}
