//! Fast versions of the four problems of the hard-disk assignment, run through the same
//! scenario files and runner as the CLI, asserting the physics; and sweeps.

use granular::run::Summary;
use granular::run::sweep::run_sweep;
use granular::scenario::Scenario;
use std::path::PathBuf;

use crate::common::{scenario_text, tmp};

fn run(name: &str, overrides: &[&str], dir: &str) -> (Summary, PathBuf) {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let s = Scenario::from_toml(&scenario_text(name), &o).expect("valid");
    crate::common::run(dir, s)
}

#[test]
fn problem1_speeds_pass_the_maxwell_boltzmann_test() {
    let (s, d) = run(
        "maxwell-boltzmann.toml",
        &["species[0].count=2000", "stop.collisions_per_particle=200"],
        "p1",
    );
    let fit = &s.maxwell_boltzmann_fit["disk"];
    assert!(fit.p_value > 1e-3, "{fit:?}");
    assert!(fit.samples >= 2000 * 30);
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn problem2_mixture_reaches_equipartition() {
    let (s, d) = run(
        "problem2-mixture.toml",
        &[
            "species[0].count=1000",
            "species[1].count=1000",
            "species[0].radius=0.008",
            "species[1].radius=0.008",
            "stop.collisions_per_particle=300",
        ],
        "p2",
    );
    let light = &s.species["m0"];
    let heavy = &s.species["4m0"];
    let (el, sl) = (light.mean_kinetic_energy, light.mean_kinetic_energy_error);
    let (eh, sh) = (heavy.mean_kinetic_energy, heavy.mean_kinetic_energy_error);
    // Equal within 3 combined standard errors (samples 5 collisions per grain apart).
    assert!(
        (el - eh).abs() < 3.0 * (sl * sl + sh * sh).sqrt(),
        "light {el} ± {sl}, heavy {eh} ± {sh}"
    );
    // Mean speeds: the heavy grains are slower by a factor 2 = sqrt(4).
    let ratio = light.mean_speed / heavy.mean_speed;
    let err = ratio
        * (light.mean_speed_error / light.mean_speed)
            .hypot(heavy.mean_speed_error / heavy.mean_speed);
    assert!(
        (ratio - 2.0).abs() < 4.0 * err,
        "speed ratio {ratio} ± {err}"
    );
    for fit in s.maxwell_boltzmann_fit.values() {
        assert!(fit.p_value > 1e-3, "{fit:?}");
    }
    let _ = std::fs::remove_dir_all(d);
}

/// Ratio of light to heavy mean kinetic energy per grain over the second half of the run,
/// with its standard error over seeds.
fn cooling_ratio(restitution: f64) -> (f64, f64) {
    let mut ratios = granular::stats::RunningStats::new();
    for seed in 0..4 {
        let overrides = [
            "species[0].count=1000".to_string(),
            "species[1].count=1000".into(),
            "species[0].radius=0.008".into(),
            "species[1].radius=0.008".into(),
            format!("collisions.restitution={restitution}"),
            format!("seed={}", 100 + seed),
            "output.interval=0.002".into(),
        ];
        let scenario = Scenario::from_toml(&scenario_text("problem3-cooling.toml"), &overrides)
            .expect("valid");
        let observations = crate::common::observations(scenario);
        let rows: Vec<Vec<f64>> = observations
            .iter()
            .map(|o| {
                let per_grain = |name: &str| {
                    o.species
                        .iter()
                        .find(|s| s.name == name)
                        .map_or(f64::NAN, |s| s.kinetic_energy_per_grain)
                };
                vec![per_grain("m0"), per_grain("4m0"), o.collisions_per_particle]
            })
            .collect();
        let (il, ih, ic) = (0, 1, 2);
        let late: Vec<&Vec<f64>> = rows.iter().filter(|r| r[ic] >= 10.0).collect();
        let r = late.iter().map(|r| r[il] / r[ih]).sum::<f64>() / late.len() as f64;
        ratios.push(r);
    }
    (ratios.mean(), ratios.standard_error())
}

#[test]
fn problem3_equipartition_holds_at_one_and_breaks_below() {
    let (r1, e1) = cooling_ratio(1.0);
    let (r8, e8) = cooling_ratio(0.8);
    assert!(
        (r1 - 1.0).abs() < 4.0 * e1 + 0.02,
        "ξ = 1: light/heavy energy ratio {r1} ± {e1}"
    );
    assert!(
        1.0 - r8 > 4.0 * e8,
        "ξ = 0.8: light/heavy energy ratio {r8} ± {e8} should fall below 1"
    );
}

fn crater_sweep(values: &str, threads: usize, dir: &str) -> Vec<granular::run::sweep::SweepRow> {
    let text = scenario_text("problem4-crater.toml");
    let o = vec![
        "species[1].count=2000".to_string(),
        "species[1].radius=0.00631".to_string(),
        "species[0].radius=0.03154".to_string(),
        "crater.displacement=0.01262".to_string(),
        format!("sweep.values={values}"),
        "sweep.seeds=3".to_string(),
    ];
    let d = tmp(dir);
    let rows = run_sweep(&d, &text, &o, threads, &|_, _| {}).expect("sweep");
    let _ = std::fs::remove_dir_all(d);
    rows
}

fn crater(row: &granular::run::sweep::SweepRow) -> (f64, f64) {
    let o = row
        .observables
        .iter()
        .find(|o| o.0 == "crater_size")
        .expect("crater_size");
    (o.1, o.2)
}

#[test]
fn problem4_crater_grows_with_projectile_mass() {
    let rows = crater_sweep("[5.0, 15.0, 30.0]", 0, "p4-mass");
    for w in rows.windows(2) {
        let ((a, ea), (b, eb)) = (crater(&w[0]), crater(&w[1]));
        assert!(
            b - a > 3.0 * (ea * ea + eb * eb).sqrt(),
            "crater {a} ± {ea} -> {b} ± {eb}"
        );
    }
}

#[test]
fn problem4_crater_does_not_depend_on_speed_without_a_velocity_scale() {
    // Hard grains without gravity have no velocity scale: the run at speed 4v, with t_c and
    // the output interval divided by 4, is the run at speed v with time divided by 4. A
    // factor 4 is exact in binary arithmetic, so the two craters agree exactly. (This is
    // why the bundled scan varies the projectile mass, not its speed.)
    let common = [
        "species[1].count=2000",
        "species[1].radius=0.00631",
        "species[0].radius=0.03154",
        "crater.displacement=0.01262",
    ];
    let slow: Vec<&str> = common
        .iter()
        .copied()
        .chain([
            "species[0].velocity.velocity=[0.0, -2.0]",
            "collisions.contact_duration=4e-7",
            "output.interval=0.02",
            "stop.time=20.0",
        ])
        .collect();
    let fast: Vec<&str> = common
        .iter()
        .copied()
        .chain([
            "species[0].velocity.velocity=[0.0, -8.0]",
            "collisions.contact_duration=1e-7",
            "output.interval=0.005",
            "stop.time=5.0",
        ])
        .collect();
    let (a, da) = run("problem4-crater.toml", &slow, "p4-slow");
    let (b, db) = run("problem4-crater.toml", &fast, "p4-fast");
    let (ca, cb) = (a.crater.unwrap(), b.crater.unwrap());
    assert_eq!(ca.displaced, cb.displaced);
    assert_eq!(a.collisions, b.collisions);
    assert!(ca.displaced > 100);
    let _ = (std::fs::remove_dir_all(da), std::fs::remove_dir_all(db));
}

#[test]
fn sweeps_give_identical_tables_with_one_and_two_threads() {
    let one = crater_sweep("[10.0, 30.0]", 1, "sweep-1");
    let two = crater_sweep("[10.0, 30.0]", 2, "sweep-2");
    assert_eq!(one, two);
}
