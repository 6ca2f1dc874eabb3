//! `[sweep]`: checked by `check` and `run` as well as by `sweep`: values and seeds given,
//! every value a valid scenario, and an observable that the run writes.

use super::{EngineKind, Scenario, ScenarioError, SweepSpec};

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
pub fn sweep_observables(sc: &Scenario) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut add = |names: &[&str]| out.extend(names.iter().map(|s| s.to_string()));
    match (sc.engine, &sc.intruder) {
        (EngineKind::Edmd | EngineKind::Dsmc, _) => {
            add(GRAINS);
            for sp in &sc.species {
                out.push(format!("kinetic_energy_per_grain.{}", sp.name));
                out.push(format!("temperature.{}", sp.name));
            }
        }
        (EngineKind::Intruder, Some(super::IntruderSpec::Needle(_))) => add(NEEDLE),
        (EngineKind::Intruder, Some(super::IntruderSpec::DsmcTwin(_))) => {
            add(ONE_D);
            add(TWIN);
        }
        (EngineKind::Intruder, _) => add(ONE_D),
    }
    if sc.crater.is_some() {
        out.push("crater_size".into());
    }
    out
}

impl SweepSpec {
    /// Checks that the sweep has values and seeds and names an observable of the run.
    pub(crate) fn validate(&self, sc: &Scenario) -> Result<(), ScenarioError> {
        if self.values.is_empty() {
            return Err(ScenarioError::new(
                "sweep.values",
                "is empty; list the values to scan",
            ));
        }
        if self.seeds == 0 {
            return Err(ScenarioError::new(
                "sweep.seeds",
                "is 0; use at least 1 seed per value",
            ));
        }
        if super::spans::parse_path(&self.key).is_err() || self.key.starts_with("sweep") {
            return Err(ScenarioError::new(
                "sweep.key",
                format!(
                    "\"{}\" is not a scenario key; give a dotted key such as collisions.restitution or species[0].mass",
                    self.key
                ),
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
}

/// Every value of the sweep, set on the scenario, must give a valid scenario.
pub(super) fn check_members(
    source: &str,
    overrides: &[String],
    sw: &SweepSpec,
) -> Result<(), ScenarioError> {
    for (i, v) in sw.values.iter().enumerate() {
        let mut o = overrides.to_vec();
        o.push(format!("{}={v}", sw.key));
        let member = Scenario::parse(source, &o).and_then(|s| {
            let mut s = s;
            s.sweep = None;
            s.validate()
        });
        if let Err(e) = member {
            return Err(ScenarioError::new(
                format!("sweep.values[{i}]"),
                format!(
                    "{} = {v} gives an invalid scenario: `{}`: {}",
                    sw.key, e.key, e.message
                ),
            )
            .at(source));
        }
    }
    Ok(())
}
