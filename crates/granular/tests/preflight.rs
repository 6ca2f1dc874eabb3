//! The pre-flight estimate (`Scenario::cost`) and logarithmic output spacing: the cooling
//! trap of issue 24 (`dsmc-cooling` to 250 collisions per grain wrote some 24 000 evenly
//! spaced outputs while Haff's law stretched the time to reach them) and the limits that
//! `--insist` lifts.

use granular::prelude::*;
use granular::scenario::{MAX_OUTPUTS, OutputSpacing};
use std::path::PathBuf;

fn cooling(overrides: &[&str]) -> Result<Scenario, granular::scenario::ScenarioError> {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml"),
    )
    .unwrap();
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scenario::from_toml(&text, &o)
}

/// Logarithmic spacing: output `k >= 1` at `interval * 10^((k - 1) / per_decade)`, and the
/// count up to a time is that of the grid.
#[test]
fn log_spacing_lays_out_per_decade_outputs() {
    let mut s = cooling(&["output.spacing=\"log\"", "output.per_decade=4"]).unwrap();
    assert_eq!(s.output.spacing, OutputSpacing::Log);
    let o = &s.output;
    assert_eq!(o.time(0), 0.0);
    assert_eq!(o.time(1), 0.01);
    assert!((o.time(5) / 0.1 - 1.0).abs() < 1e-12);
    assert!((o.time(9) / 1.0 - 1.0).abs() < 1e-12);
    assert_eq!(o.count_until(1.0), 9.0);
    s.output.spacing = OutputSpacing::Linear;
    assert_eq!(s.output.time(3), 3.0 * 0.01);
    // The resolved scenario keeps the spacing.
    let log = cooling(&["output.spacing=\"log\""]).unwrap();
    assert_eq!(Scenario::from_toml(&log.to_toml(), &[]).unwrap(), log);
    let e = cooling(&["output.per_decade=0"]).unwrap_err();
    assert_eq!(e.key, "output.per_decade", "{e}");
}

/// The cooling gas to 250 collisions per grain: the estimate (Haff's law) warns of the
/// evenly spaced outputs and names `output.spacing`; with `spacing = "log"` the run writes a
/// few dozen outputs, and costs (in DSMC time steps) within a few times an elastic gas
/// making the same number of collisions.
#[test]
fn a_cooling_gas_to_many_collisions_stays_cheap_with_log_spacing() {
    let base = ["species[0].count=4000", "stop.collisions_per_particle=250"];
    let linear = cooling(&base).unwrap();
    let cost = linear.cost();
    assert!(cost.cooling && cost.outputs > 1e4, "{:?}", cost.lines());
    let w = cost.warning(&linear).expect("a warning");
    assert!(
        w.contains("output.spacing = \"log\"") && w.contains("Haff"),
        "{w}"
    );

    let with = |extra: &[&str]| {
        let mut o = base.to_vec();
        o.extend_from_slice(extra);
        let mut sim = Simulation::new(cooling(&o).unwrap()).unwrap();
        sim.run().unwrap();
        let steps = sim.events() - sim.collisions();
        (sim.outputs_done(), steps, sim.time())
    };
    let (outputs, steps, t_end) = with(&["output.spacing=\"log\""]);
    let estimate = cooling(&[base[0], base[1], "output.spacing=\"log\""])
        .unwrap()
        .cost();
    assert!(estimate.warning(&linear).is_none() || estimate.outputs < 1e4);
    // Ten per decade from t = 0.01 to the end, and the stop.
    let grid = 1.0 + (10.0 * (t_end / 0.01).log10()).ceil();
    assert!(
        outputs as f64 <= grid && outputs < 200,
        "{outputs} outputs to t = {t_end}"
    );
    let (_, steady, _) = with(&["collisions.restitution=1.0"]);
    let ratio = steps as f64 / steady as f64;
    assert!(
        ratio < 3.0,
        "{steps} steps cooling, {steady} elastic (x{ratio})"
    );
}

/// Above a limit the scenario is refused, naming the key and `--insist`;
/// `from_toml_insisting` (what `--insist` reads with) accepts it, and the estimate shows
/// the outputs, bytes and work of each engine.
#[test]
fn limits_name_the_key_and_insisting_lifts_them() {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/maxwell-boltzmann.toml"),
    )
    .unwrap();
    let o = vec!["output.interval=1e-9".to_string()];
    let e = Scenario::from_toml(&text, &o).unwrap_err();
    assert_eq!(e.key, "output.interval", "{e}");
    assert!(
        e.message.contains("--insist") && e.message.contains("1e6"),
        "{e}"
    );
    let s = Scenario::from_toml_insisting(&text, &o).unwrap();
    let cost = s.cost();
    assert!(cost.outputs > MAX_OUTPUTS, "{:?}", cost.lines());
    assert!(cost.check_limits().is_err());
    // An event-driven run stopped only by its events: events and collisions estimated.
    let o = vec![
        "stop.events=1000000".to_string(),
        "stop.time=1e9".to_string(),
    ];
    let s = Scenario::from_toml(&text, &o).unwrap();
    let cost = s.cost();
    assert_eq!(cost.rule, "stop.events");
    let (events, what) = cost.steps.expect("events");
    assert_eq!(what, "events");
    assert!((events / 1e6 - 1.0).abs() < 1e-9, "{events}");
    assert!(cost.bytes > 0.0 && cost.end_time.is_finite());
    let lines = cost.lines().join("\n");
    assert!(
        lines.contains("outputs") && lines.contains("written"),
        "{lines}"
    );
    // Stopped only by the wall clock: bounded by a nominal speed, not unbounded.
    let o = vec![
        "stop.wall_seconds=10".to_string(),
        "stop.collisions_per_particle=1e6".to_string(),
    ];
    let cost = Scenario::from_toml(&text, &o).unwrap().cost();
    assert_eq!(cost.rule, "stop.wall_seconds");
    assert!(cost.outputs.is_finite() && cost.collisions.is_finite());
}
