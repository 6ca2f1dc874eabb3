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
