//! Helpers shared by the integration tests: temporary run directories, the bundled
//! scenarios, and a run of a scenario to its end.

use granular::run::{Run, Summary};
use granular::scenario::Scenario;
use std::path::PathBuf;

/// A fresh, empty directory under the system's temporary directory, unique to this call
/// (named after `name` for a reader of a failed test); the caller removes it.
pub fn tmp(name: &str) -> PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("granular-{name}-"))
        .tempdir()
        .expect("temporary directory")
        .keep()
}

/// The text of a bundled scenario, `scenarios/NAME`.
pub fn scenario_text(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    std::fs::read_to_string(&path).expect("bundled scenario")
}

/// Runs `scenario` to its end in a new directory named after `name`; returns the summary
/// and the directory (the caller removes it).
pub fn run(name: &str, scenario: Scenario) -> (Summary, PathBuf) {
    let dir = tmp(name);
    let summary = Run::create(&dir, scenario)
        .expect("run directory")
        .run_to_end(&mut |_| {}, None)
        .expect("run");
    (summary, dir)
}

/// The observations of `scenario` run in memory to its stop rule: at `t = 0` and at every
/// output time, as the rows of its `timeseries.csv` would be (no file is written).
pub fn observations(scenario: Scenario) -> Vec<granular::Observation> {
    use granular::simulation::RunHooks;
    struct Collect(Vec<granular::Observation>);
    impl RunHooks for Collect {
        type Error = granular::engine::EngineError;
        fn at_output(&mut self, s: &granular::Simulation) -> Result<(), Self::Error> {
            self.0.push(s.observe());
            Ok(())
        }
    }
    let mut simulation = granular::Simulation::new(scenario).expect("build");
    let mut hooks = Collect(vec![simulation.observe()]);
    simulation.run_with(&mut hooks).expect("run");
    hooks.0
}

/// How far the exact `a2` of the Boltzmann equation lies from the linear Sonine estimates
/// at `e = 0.5`-`0.8`: the HCS's second estimate is followed by DSMC within 0.002-0.004
/// (Montanero and Santos, Granular Matter 2, 53 (2000); our 8-seed measurement in
/// `docs/dsmc.md`: 0.0746 ± 0.0009 against 0.0766 in 2D); the heated gas's estimate within
/// about 0.003 (same reference, their Fig. 2 at `e >= 0.5`). The allowance of the
/// steady-state tests of both engines (steady.rs, steady_edmd.rs).
pub const SONINE_TRUNCATION: f64 = 0.004;

/// Standard errors of a steady-state average allowed between it and its theory (the
/// steady-state tests of both engines).
pub const STANDARD_ERRORS: f64 = 4.0;

/// Mean and standard error of a steady-state series from 10 batch means (at least 100
/// samples, 10 per batch; each batch must be longer than the series' correlation time,
/// which the callers' sampling windows ensure).
pub fn batch_estimate(series: &[f64]) -> (f64, f64) {
    assert!(series.len() >= 100, "{} samples", series.len());
    granular::stats::batch_means(series, 10)
}

/// Asserts that `estimate = (mean, standard error)` lies within [`STANDARD_ERRORS`]
/// standard errors plus the `model` allowance (the theory's own error, in the units of
/// `theory`) of `theory`; `what` names the quantity in the message.
pub fn assert_within_errors(what: &str, estimate: (f64, f64), theory: f64, model: f64) {
    let (mean, sd) = estimate;
    assert!(
        (mean - theory).abs() < STANDARD_ERRORS * sd + model,
        "{what} = {mean} ± {sd}, theory {theory} (allowed: {STANDARD_ERRORS} sd + {model})"
    );
}
