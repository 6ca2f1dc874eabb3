//! `[sweep]`: checked by `check` and `run` as well as by `sweep`: keys and values given
//! (one key, or several as a grid or zipped), seeds, every point a valid scenario, and an
//! observable that the run writes.

use super::spans::{parse_path, path_text};
use super::{EngineKind, Scenario, ScenarioError, ScenarioInput, SweepAxis, SweepMode, SweepSpec};

/// Most points a sweep may have (the product of the value counts in a grid): beyond it
/// the scan is an error that suggests `mode = "zip"`, fewer values or several sweeps.
pub(crate) const MAX_SWEEP_POINTS: usize = 10_000;

/// Columns of the many-grain engines' observations (`Observation::columns`; an engine
/// leaves out those it does not measure); `kinetic_energy_per_grain.<name>` and
/// `temperature.<name>` are added per species.
const GRAINS: &[&str] = &[
    "time",
    "kinetic_energy",
    "temperature",
    "pair_collisions",
    "wall_collisions",
    "collisions_per_particle",
    "collision_frequency",
    "mean_free_time",
    "pressure",
    "wall_pressure",
    "dissipated_energy",
    "a2",
    "steps",
    "vmax_exceeded",
    "tc_elastic_collisions",
];
/// ... the 1D intruder's (and its DSMC twin's).
const ONE_D: &[&str] = &[
    "time",
    "velocity",
    "kinetic_energy",
    "collisions",
    "samples",
    "temperature",
    "temperature_error",
    "temperature_ratio",
    "temperature_ratio_error",
    "kurtosis",
    "kurtosis_error",
    "martin_piasecki_ratio",
];
/// ... a disk's or sphere's (`velocity_z` added for the sphere) and its twin's.
const BALL: &[&str] = &[
    "time",
    "velocity_x",
    "velocity_y",
    "speed",
    "kinetic_energy",
    "collisions",
    "samples",
    "temperature",
    "temperature_error",
    "temperature_ratio",
    "temperature_ratio_error",
    "kurtosis",
    "kurtosis_error",
    "collision_rate",
    "collision_rate_error",
    "truncated_temperature",
    "truncated_temperature_error",
    "martin_piasecki_ratio",
    "maxwellian_kurtosis",
    "theory_collision_rate",
];
/// ... the DSMC twin's own.
const TWIN: &[&str] = &["bound_raises", "trials_per_collision"];
/// ... the needle's.
const NEEDLE: &[&str] = &[
    "time",
    "velocity_x",
    "velocity_y",
    "angular_velocity",
    "angle",
    "kinetic_energy",
    "collisions",
    "samples",
    "translational_temperature",
    "translational_temperature_error",
    "rotational_temperature",
    "rotational_temperature_error",
    "correlation_r",
    "correlation_r_error",
    "translational_temperature_ratio",
    "translational_temperature_ratio_error",
    "rotational_temperature_ratio",
    "rotational_temperature_ratio_error",
];

/// The observables a sweep of `sc` can plot: the columns of its `timeseries.csv` (the
/// final row is `summary.json`'s `final`) and `crater_size` with a `[crater]` table.
/// `a2.<name>` is the event-driven engine's, per species of a mixture.
pub fn sweep_observables(sc: &Scenario) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut add = |names: &[&str]| out.extend(names.iter().map(|s| s.to_string()));
    match (sc.kind(), sc.intruder()) {
        (EngineKind::Edmd | EngineKind::Dsmc, _) => {
            add(GRAINS);
            for sp in sc.species() {
                out.push(format!("kinetic_energy_per_grain.{}", sp.name));
                out.push(format!("temperature.{}", sp.name));
                if sc.kind() == EngineKind::Edmd && sc.species().len() > 1 {
                    out.push(format!("a2.{}", sp.name));
                }
            }
        }
        (EngineKind::Intruder, Some(super::IntruderSpec::Needle(_))) => add(NEEDLE),
        (
            EngineKind::Intruder,
            Some(spec @ (super::IntruderSpec::Disk(c) | super::IntruderSpec::Sphere(c))),
        ) => {
            add(BALL);
            if spec.dimension() == 3 {
                add(&["velocity_z"]);
            }
            if c.is_twin() {
                add(TWIN);
            }
        }
        (EngineKind::Intruder, Some(super::IntruderSpec::DsmcTwin(_))) => {
            add(ONE_D);
            add(TWIN);
        }
        (EngineKind::Intruder, _) => add(ONE_D),
    }
    if sc.crater().is_some() {
        out.push("crater_size".into());
    }
    out
}

impl SweepSpec {
    /// The swept keys with their values, in order: the one-key form (`key`, `values`) as
    /// a single axis; keys written as `--set` writes them (`species[0].mass`).
    pub fn axes(&self) -> Vec<SweepAxis> {
        let norm = |k: &str| parse_path(k).map_or_else(|_| k.to_string(), |p| path_text(&p));
        match &self.key {
            Some(k) if self.vary.is_empty() => vec![SweepAxis {
                key: norm(k),
                values: self.values.clone(),
            }],
            _ => self
                .vary
                .iter()
                .map(|a| SweepAxis {
                    key: norm(&a.key),
                    values: a.values.clone(),
                })
                .collect(),
        }
    }

    /// Number of points: the product of the value counts (grid) or the common length
    /// (zip).
    pub(crate) fn point_count(&self) -> usize {
        let axes = self.axes();
        match self.mode {
            _ if axes.is_empty() => 0,
            SweepMode::Grid => axes
                .iter()
                .fold(1usize, |n, a| n.saturating_mul(a.values.len())),
            SweepMode::Zip => axes.iter().map(|a| a.values.len()).min().unwrap_or(0),
        }
    }

    /// The points of the scan in order, each the values of [`SweepSpec::axes`]: in a grid
    /// the last key varies fastest (row-major), in zip mode point `i` takes the `i`-th
    /// value of every key.
    pub fn points(&self) -> Vec<Vec<toml::Value>> {
        let axes = self.axes();
        (0..self.point_count())
            .map(|p| match self.mode {
                SweepMode::Zip => axes.iter().map(|a| a.values[p].clone()).collect(),
                SweepMode::Grid => {
                    let mut rest = p;
                    let mut out = vec![toml::Value::Boolean(false); axes.len()];
                    for (slot, a) in out.iter_mut().zip(&axes).rev() {
                        *slot = a.values[rest % a.values.len()].clone();
                        rest /= a.values.len();
                    }
                    out
                }
            })
            .collect()
    }

    /// The scenario key of field `field` of axis `i` in error messages: `sweep.values`
    /// in the one-key form, `sweep.vary[i].values` otherwise.
    fn field(&self, i: usize, field: &str) -> String {
        if self.vary.is_empty() {
            format!("sweep.{field}")
        } else {
            format!("sweep.vary[{i}].{field}")
        }
    }

    /// Checks the form: one key or `[[sweep.vary]]`, values, no key twice, lists of one
    /// length in zip mode, at most [`MAX_SWEEP_POINTS`] points, seeds, the observable.
    pub(crate) fn validate(&self, sc: &Scenario) -> Result<(), ScenarioError> {
        self.check_form()?;
        let axes = self.axes();
        for (i, a) in axes.iter().enumerate() {
            if parse_path(&a.key).is_err() || a.key.starts_with("sweep") || a.key == "seed" {
                let why = if a.key == "seed" {
                    "the seed is set per member from `sweep.seeds` (member s gets derive(seed, s)); \
                     remove this key and set `seeds` instead"
                } else {
                    "give a dotted key such as collisions.restitution or species[0].mass"
                };
                return Err(ScenarioError::new(
                    self.field(i, "key"),
                    format!("\"{}\" is not a key a sweep can vary; {why}", a.key),
                ));
            }
            if a.values.is_empty() {
                return Err(ScenarioError::new(
                    self.field(i, "values"),
                    format!("is empty; list the values of {} to scan", a.key),
                ));
            }
            if let Some(j) = axes[..i].iter().position(|b| b.key == a.key) {
                return Err(ScenarioError::new(
                    self.field(i, "key"),
                    format!(
                        "\"{}\" is also sweep.vary[{j}].key; give each key once, with all its values in one list",
                        a.key
                    ),
                ));
            }
        }
        self.check_size(&axes)?;
        if self.seeds == 0 {
            return Err(ScenarioError::new(
                "sweep.seeds",
                "is 0; use at least 1 seed per point",
            ));
        }
        let known = sweep_observables(sc);
        if !known.contains(&self.observable) {
            return Err(ScenarioError::new(
                "sweep.observable",
                format!(
                    "\"{}\" is not written by this run; use one of: {}",
                    self.observable,
                    known.join(", ")
                ),
            ));
        }
        Ok(())
    }

    /// One key (`key` with `values`) or `[[sweep.vary]]`, not both, not neither.
    fn check_form(&self) -> Result<(), ScenarioError> {
        let one = self.key.is_some() || !self.values.is_empty();
        if one && !self.vary.is_empty() {
            let k = if self.key.is_some() { "key" } else { "values" };
            return Err(ScenarioError::new(
                format!("sweep.{k}"),
                "is given together with [[sweep.vary]]; sweep one key with `key` and `values`, \
                 or several with one [[sweep.vary]] table (key, values) each, not both",
            ));
        }
        if self.vary.is_empty() && self.key.is_none() {
            return Err(ScenarioError::new(
                "sweep.key",
                "is missing; give `key` and `values` (one key), or one [[sweep.vary]] table \
                 with `key` and `values` per key (docs/scenario.md)",
            ));
        }
        Ok(())
    }

    /// Zip lists of one length; a grid within [`MAX_SWEEP_POINTS`].
    fn check_size(&self, axes: &[SweepAxis]) -> Result<(), ScenarioError> {
        match self.mode {
            SweepMode::Zip => {
                let n = axes[0].values.len();
                if let Some(i) = axes.iter().position(|a| a.values.len() != n) {
                    return Err(ScenarioError::new(
                        self.field(i, "values"),
                        format!(
                            "has {} values ({}) but sweep.vary[0].values has {n} ({}); with \
                             mode = \"zip\" every list has the same length (point i takes the \
                             i-th value of each key); use mode = \"grid\" for every combination",
                            axes[i].values.len(),
                            axes[i].key,
                            axes[0].key
                        ),
                    ));
                }
            }
            SweepMode::Grid => {
                let n = self.point_count();
                if n > MAX_SWEEP_POINTS {
                    let sizes: Vec<String> =
                        axes.iter().map(|a| a.values.len().to_string()).collect();
                    return Err(ScenarioError::new(
                        if self.vary.is_empty() {
                            "sweep.values"
                        } else {
                            "sweep.vary"
                        },
                        format!(
                            "the grid has {} = {n} points, more than MAX_SWEEP_POINTS = \
                             {MAX_SWEEP_POINTS}; use fewer values, mode = \"zip\", or split \
                             the scan into several sweeps",
                            sizes.join(" x ")
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The scenario of one point of a sweep (without its `[sweep]` table), or the error.
fn member(
    input: &ScenarioInput<'_>,
    set: &[(&str, &toml::Value)],
    limits: bool,
) -> Result<Scenario, ScenarioError> {
    let extra: Vec<String> = set.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let mut s = input.assemble(&extra)?;
    s.sweep = None;
    s.validate().map_err(|e| e.at(input.text))?;
    if limits {
        s.cost().check_limits().map_err(|e| e.at(input.text))?;
    }
    Ok(s)
}

/// A member of the sweep of `source`: the scenario with `overrides` (the point's keys and
/// the member's seed among them), validated, without its `[sweep]` table (so that a
/// member directory is a plain run, and building one member does not check every other).
pub(crate) fn sweep_member(source: &str, overrides: &[String]) -> Result<Scenario, ScenarioError> {
    let input = ScenarioInput {
        text: source,
        overrides,
        ..ScenarioInput::default()
    };
    member(&input, &[], false)
}

/// Every value of every key, set alone on the scenario, must give a valid scenario (the
/// error names `sweep.values[i]` or `sweep.vary[k].values[i]`, or the key itself when
/// the scenario has no such key); with several keys, so must every point.
pub(super) fn check_members(
    input: &ScenarioInput<'_>,
    sw: &SweepSpec,
) -> Result<(), ScenarioError> {
    let (source, limits) = (input.text, input.limits);
    let axes = sw.axes();
    for (k, a) in axes.iter().enumerate() {
        for (i, v) in a.values.iter().enumerate() {
            if let Err(e) = member(input, &[(&a.key, v)], limits) {
                let last = a.key.rsplit(['.', '[']).next().unwrap_or_default();
                let unknown = e.message.contains(&format!("unknown field `{last}`"));
                let (key, what) = if unknown {
                    (
                        sw.field(k, "key"),
                        format!(
                            "\"{}\" is not a key of this scenario: `{}`: {}; correct the key",
                            a.key, e.key, e.message
                        ),
                    )
                } else {
                    (
                        format!("{}[{i}]", sw.field(k, "values")),
                        format!(
                            "{} = {v} gives an invalid scenario: `{}`: {}",
                            a.key, e.key, e.message
                        ),
                    )
                };
                return Err(ScenarioError::new(key, what).at(source));
            }
        }
    }
    if axes.len() > 1 {
        for (p, point) in sw.points().iter().enumerate() {
            let set: Vec<(&str, &toml::Value)> =
                axes.iter().map(|a| a.key.as_str()).zip(point).collect();
            if let Err(e) = member(input, &set, limits) {
                let at: Vec<String> = set.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                return Err(ScenarioError::new(
                    "sweep.vary",
                    format!(
                        "point {p} ({}) gives an invalid scenario: `{}`: {}; change the values \
                         or use mode = \"zip\" to leave this combination out",
                        at.join(", "),
                        e.key,
                        e.message
                    ),
                )
                .at(source));
            }
        }
    }
    Ok(())
}
