//! Reading a scenario with what the text alone does not say: the directory its relative
//! `.npz` paths are read from, and per-grain arrays given by a program (NumPy) that never
//! become text.

use super::grain_vectors::GrainVectors;
use super::spans::{Segment, parse_path};
use super::{Scenario, ScenarioError, VelocitySpec, sweep};
use crate::output::npz::{NpzArray, NpzData, read_npz};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The keys that take per-grain arrays: `species[i].` followed by one of these.
pub(crate) const ARRAY_KEYS: [&str; 2] = ["positions", "velocity.velocities"];

/// A scenario's text and what comes with it; [`ScenarioInput::read`] parses, applies the
/// overrides, puts the given arrays in, reads the `.npz` members it names, and validates.
#[derive(Clone, Copy, Debug, Default)]
pub struct ScenarioInput<'a> {
    /// The TOML text.
    pub text: &'a str,
    /// `--set KEY=VALUE` overrides, in order.
    pub overrides: &'a [String],
    /// The directory relative `.npz` paths are read from (the scenario file's); `None`: the
    /// current directory.
    pub base: Option<&'a Path>,
    /// Per-grain arrays by key (`species[0].positions`, `species[0].velocity.velocities`),
    /// put in after the overrides: a given `velocity.velocities` makes the species'
    /// velocities per grain.
    pub arrays: &'a [(String, GrainVectors)],
    /// Whether the cost limits apply (false: `--insist`).
    pub limits: bool,
}

impl ScenarioInput<'_> {
    /// The scenario, validated; errors as [`Scenario::from_toml`]'s, and for the arrays
    /// naming the key, the file and the member.
    pub fn read(&self) -> Result<Scenario, ScenarioError> {
        let scenario = self.assemble(&[])?;
        scenario.validate().map_err(|e| e.at(self.text))?;
        if self.limits {
            scenario
                .cost()
                .check_limits()
                .map_err(|e| e.at(self.text))?;
        }
        if let Some(sw) = &scenario.sweep {
            sweep::check_members(self, sw)?;
        }
        Ok(scenario)
    }

    /// Parsed with the overrides and `extra` ones, the arrays put in and the `.npz`
    /// members read; not validated.
    pub(super) fn assemble(&self, extra: &[String]) -> Result<Scenario, ScenarioError> {
        let mut overrides = self.overrides.to_vec();
        overrides.extend_from_slice(extra);
        let mut scenario = Scenario::parse(self.text, &overrides)?;
        for (key, vectors) in self.arrays {
            scenario.put_array(key, vectors.clone())?;
        }
        read_files(&mut scenario, self.base).map_err(|e| e.at(self.text))?;
        Ok(scenario)
    }
}

/// The species index and which array `key` names, or the error that says which keys take
/// arrays.
pub fn array_key(key: &str) -> Result<(usize, &'static str), ScenarioError> {
    let refuse = || {
        ScenarioError::new(
            key,
            "does not take a per-grain array; arrays go to species[i].positions and \
             species[i].velocity.velocities",
        )
    };
    let path = parse_path(key).map_err(|m| ScenarioError::new(key, m))?;
    let [Segment::Key(species), Segment::Index(i), rest @ ..] = path.as_slice() else {
        return Err(refuse());
    };
    let rest: Vec<&str> = rest
        .iter()
        .map(|s| match s {
            Segment::Key(k) => Some(k.as_str()),
            Segment::Index(_) => None,
        })
        .collect::<Option<_>>()
        .ok_or_else(refuse)?;
    let rest = rest.join(".");
    match ARRAY_KEYS.iter().find(|k| **k == rest) {
        Some(k) if species == "species" => Ok((*i, k)),
        _ => Err(refuse()),
    }
}

impl Scenario {
    /// Puts `vectors` at `key` (`species[i].positions` or `species[i].velocity.velocities`;
    /// the latter makes the species' velocities per grain).
    pub(crate) fn put_array(
        &mut self,
        key: &str,
        vectors: GrainVectors,
    ) -> Result<(), ScenarioError> {
        let (s, which) = array_key(key)?;
        let count = self.species().len();
        let Some(sp) = self.grains_mut().and_then(|g| g.species.get_mut(s)) else {
            return Err(ScenarioError::new(
                key,
                format!("names species {s}, but the scenario has {count} species"),
            ));
        };
        if which == "positions" {
            sp.positions = vectors;
        } else {
            sp.velocity = VelocitySpec::PerGrain {
                velocities: vectors,
            };
        }
        Ok(())
    }

    /// A copy without its per-grain arrays, and the arrays by key: the copy's TOML and the
    /// arrays read back by [`ScenarioInput`] give this scenario again, without writing a
    /// million vectors as text.
    pub fn without_arrays(&self) -> (Scenario, Vec<(String, GrainVectors)>) {
        let mut bare = self.clone();
        let mut arrays = Vec::new();
        if let Some(g) = bare.grains_mut() {
            for (s, sp) in g.species.iter_mut().enumerate() {
                if !sp.positions.is_empty() {
                    let v = std::mem::take(&mut sp.positions);
                    arrays.push((format!("species[{s}].positions"), v));
                }
                if let VelocitySpec::PerGrain { velocities } = &mut sp.velocity {
                    let v = std::mem::take(velocities);
                    arrays.push((format!("species[{s}].velocity.velocities"), v));
                }
            }
        }
        (bare, arrays)
    }
}

/// Reads every `.npz` member the scenario names and has not read yet (each file once).
fn read_files(scenario: &mut Scenario, base: Option<&Path>) -> Result<(), ScenarioError> {
    let Some(grains) = scenario.grains_mut() else {
        return Ok(());
    };
    let mut files: BTreeMap<PathBuf, Vec<(String, NpzArray)>> = BTreeMap::new();
    for (s, sp) in grains.species.iter_mut().enumerate() {
        let velocities = match &mut sp.velocity {
            VelocitySpec::PerGrain { velocities } => Some(velocities),
            _ => None,
        };
        let slots = [
            (
                format!("species[{s}].positions"),
                "positions",
                Some(&mut sp.positions),
            ),
            (
                format!("species[{s}].velocity.velocities"),
                "velocities",
                velocities,
            ),
        ];
        for (key, default, vectors) in slots {
            let Some(vectors) = vectors else { continue };
            let Some((npz, member)) = vectors.unread(default) else {
                continue;
            };
            let path = match base {
                Some(b) if Path::new(npz).is_relative() => b.join(npz),
                _ => PathBuf::from(npz),
            };
            let npz = npz.to_string();
            if !files.contains_key(&path) {
                let arrays = read_npz(&path).map_err(|e| {
                    ScenarioError::new(
                        format!("{key}.npz"),
                        format!(
                            "is {npz:?}, which cannot be read ({e}); give the path of an .npz \
                             file, relative to the scenario file's directory"
                        ),
                    )
                })?;
                files.insert(path.clone(), arrays);
            }
            let arrays = &files[&path];
            let (values, width) = member_values(arrays, &member)
                .map_err(|m| ScenarioError::new(format!("{key}.array"), format!("{npz:?}: {m}")))?;
            vectors.fill(values, width);
        }
    }
    Ok(())
}

/// The float64 `(N, D)` values of member `name`, or what is wrong with it.
fn member_values(arrays: &[(String, NpzArray)], name: &str) -> Result<(Vec<f64>, usize), String> {
    let Some((_, a)) = arrays.iter().find(|(n, _)| n == name) else {
        let names: Vec<&str> = arrays.iter().map(|(n, _)| n.as_str()).collect();
        return Err(format!(
            "has no array {name:?}; its arrays are {names:?}: name one with `array = \"...\"`"
        ));
    };
    let NpzData::F64(values) = &a.data else {
        return Err(format!(
            "array {name:?} holds {}, not float64; save it as float64",
            a.data.type_name()
        ));
    };
    match a.shape.as_slice() {
        [_, d] if *d > 0 => Ok((values.clone(), *d as usize)),
        shape => Err(format!(
            "array {name:?} has shape {shape:?}; give an (N, D) array, one row per grain"
        )),
    }
}
