//! The in-memory API: a simulation built from a scenario in code, advanced, observed and
//! recorded, with no file read back to learn an observable.

use granular::prelude::*;
use std::sync::{Arc, Mutex};

const GAS: &str = r#"
engine = "edmd"
dimension = 2
seed = 11
[[species]]
name = "small"
count = 150
radius = 0.01
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[[species]]
name = "large"
count = 50
radius = 0.02
mass = 4.0
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[stop]
collisions_per_particle = 20
[output]
interval = 0.05
"#;

fn gas(engine: &str) -> Scenario {
    let text = GAS.replace("engine = \"edmd\"", &format!("engine = \"{engine}\""));
    let text = if engine == "dsmc" {
        // DSMC has one species.
        text.split("[[species]]\nname = \"large\"")
            .next()
            .unwrap_or("")
            .to_string()
            + "[stop]\ncollisions_per_particle = 20\n[output]\ninterval = 0.05\n"
    } else {
        text
    };
    Scenario::from_toml(&text, &[]).expect("valid scenario")
}

#[test]
fn observing_changes_nothing() {
    for engine in ["edmd", "dsmc"] {
        let mut sim = Simulation::new(gas(engine)).expect("build");
        sim.advance(0.2).expect("advance");
        let a = sim.observe();
        let b = sim.observe();
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "{engine}");
        assert_eq!(a.time, 0.2, "{engine}");
        assert!(a.collisions > 0, "{engine}");
        // The same names in every engine.
        for key in [
            "time",
            "kinetic_energy",
            "temperature",
            "pair_collisions",
            "collisions_per_particle",
        ] {
            assert!(a.get(key).is_some(), "{engine}: {key}");
        }
    }
}

#[test]
fn state_is_in_input_order_with_the_scenario_species() {
    let sim = Simulation::new(gas("edmd")).expect("build");
    let snap = sim.snapshot().expect("grains");
    assert_eq!(snap.positions.len(), 200 * 2);
    assert_eq!(snap.species_names, ["small", "large"]);
    assert!(snap.species[..150].iter().all(|&s| s == 0));
    assert!(snap.species[150..].iter().all(|&s| s == 1));
    assert!(snap.radii[..150].iter().all(|&r| r == 0.01));
    assert!(snap.masses[150..].iter().all(|&m| m == 4.0));
    let obs = sim.observe();
    assert_eq!(obs.species.len(), 2);
    assert_eq!(obs.species[1].name, "large");
    assert_eq!(obs.species[1].grains, 50);
    // Per-species energies add up to the total.
    let k: f64 = obs
        .species
        .iter()
        .map(|s| s.kinetic_energy_per_grain * s.grains as f64)
        .sum();
    assert!((k - obs.kinetic_energy).abs() <= 1e-12 * obs.kinetic_energy);
}

/// The rates of a window are those of the differences of the cumulative counters.
#[test]
fn rates_come_from_two_observations() {
    let mut sim = Simulation::new(gas("edmd")).expect("build");
    sim.advance(0.1).expect("advance");
    let a = sim.observe();
    sim.advance(0.3).expect("advance");
    let b = sim.observe();
    let r = b.rates_since(&a);
    assert_eq!(r.interval, b.time - a.time);
    let expected = 2.0 * (b.collisions - a.collisions) as f64 / (200.0 * r.interval);
    assert_eq!(r.collision_frequency, expected);
    assert!(r.pressure > 0.0 && r.pressure.is_finite());
    // The default box has walls; its wall pressure is the momentum they took per area
    // and time.
    let area = 4.0; // the perimeter of the unit square
    let expected = (b.wall_impulse.unwrap() - a.wall_impulse.unwrap()) / (area * r.interval);
    assert_eq!(r.wall_pressure, expected);
    // An empty window has no rates.
    assert!(b.rates_since(&b).collision_frequency.is_nan());
}

/// `run()` in memory ends where `granular run` ends, with the same numbers.
#[test]
fn run_in_memory_equals_the_run_directory() {
    for engine in ["edmd", "dsmc"] {
        let mut sim = Simulation::new(gas(engine)).expect("build");
        let reason = sim.run().expect("run");
        assert_eq!(reason, StopReason::CollisionsPerParticle);
        let dir = crate::spine::tmp(&format!("api-{engine}"));
        let summary = Run::create(&dir, gas(engine))
            .expect("run directory")
            .run_to_end(&mut |_| {}, None)
            .expect("run");
        let obs = sim.observe();
        assert_eq!(summary.stop_reason, reason.as_str());
        assert_eq!(summary.events, obs.events, "{engine}");
        assert_eq!(summary.final_observables["time"], obs.time, "{engine}");
        assert_eq!(
            summary.final_observables["kinetic_energy"].to_bits(),
            obs.kinetic_energy.to_bits(),
            "{engine}"
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// An output of the user's own sees every output time, in order, and adds to the summary.
#[test]
fn an_attached_output_observes_every_output_time() {
    struct Times(Arc<Mutex<Vec<f64>>>);
    impl Output for Times {
        fn observe(&mut self, _: &Simulation, o: &Observation) -> Result<(), RunError> {
            self.0.lock().expect("lock").push(o.time);
            Ok(())
        }
        fn finish(&mut self, _: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
            summary.warnings.push("seen by the user's output".into());
            Ok(())
        }
    }
    let seen = Arc::new(Mutex::new(Vec::new()));
    let dir = crate::spine::tmp("api-attach");
    let mut run = Run::create(&dir, gas("edmd")).expect("run directory");
    run.attach(Box::new(Times(seen.clone())));
    let summary = run.run_to_end(&mut |_| {}, None).expect("run");
    let times = seen.lock().expect("lock").clone();
    assert_eq!(times.len() as u64, summary.outputs + 1);
    assert_eq!(times[0], 0.0);
    assert!(times.windows(2).all(|w| w[1] > w[0]));
    assert_eq!(summary.warnings, ["seen by the user's output"]);
    // The summary reads back typed.
    assert_eq!(
        granular::run::RunDir::new(&dir)
            .summary()
            .expect("summary")
            .outputs,
        summary.outputs
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_summary_names_the_resolved_radius_and_packing_fraction() {
    let text = GAS.replace("radius = 0.01", "packing_fraction = 0.1");
    let text = text.replace("radius = 0.02", "packing_fraction = 0.05");
    let dir = crate::spine::tmp("api-resolved");
    let scenario =
        Scenario::from_toml(&text, &["stop.collisions_per_particle=1".into()]).expect("valid");
    let summary = Run::create(&dir, scenario)
        .expect("run directory")
        .run_to_end(&mut |_| {}, None)
        .expect("run");
    let resolved = summary.resolved.expect("resolved block");
    assert!((resolved.packing_fraction - 0.15).abs() < 1e-12);
    let r = resolved.radius["small"];
    assert!((150.0 * std::f64::consts::PI * r * r - 0.1).abs() < 1e-12);
    let _ = std::fs::remove_dir_all(dir);
}

/// The single-array accessors give the snapshot's arrays, in input order, in both engines.
#[test]
fn positions_and_velocities_equal_the_snapshot() {
    for engine in ["edmd", "dsmc"] {
        let mut sim = Simulation::new(gas(engine)).expect("build");
        sim.advance(0.37).expect("advance");
        let snap = sim.snapshot().expect("grains");
        assert_eq!(
            sim.positions().expect("positions"),
            snap.positions,
            "{engine}"
        );
        assert_eq!(
            sim.velocities().expect("velocities"),
            snap.velocities,
            "{engine}"
        );
        // Into a buffer the caller owns: the same values; a buffer of the wrong length is
        // refused and left as it was.
        let mut out = vec![f64::NAN; snap.positions.len()];
        assert!(sim.positions_into(&mut out), "{engine}");
        assert_eq!(out, snap.positions, "{engine}");
        assert!(sim.velocities_into(&mut out), "{engine}");
        assert_eq!(out, snap.velocities, "{engine}");
        let mut short = vec![-1.0; snap.positions.len() - 1];
        assert!(!sim.positions_into(&mut short), "{engine}");
        assert!(short.iter().all(|&x| x == -1.0), "{engine}");
    }
}

/// DSMC sets its impact-parameter bins in its own table (`[edmd]` does not apply to it).
#[test]
fn dsmc_impact_bins_come_from_its_table() {
    let mut scenario = gas("dsmc");
    let granular::scenario::EngineSpec::Dsmc { dsmc, .. } = &mut scenario.engine else {
        panic!("a DSMC scenario")
    };
    dsmc.impact_bins = Some(7);
    let mut sim = Simulation::new(scenario).expect("build");
    sim.advance(0.1).expect("advance");
    assert_eq!(sim.impact_histogram().expect("histogram").counts.len(), 7);
    let default = Simulation::new(gas("dsmc")).expect("build");
    assert_eq!(
        default.impact_histogram().expect("histogram").counts.len(),
        20
    );
}
