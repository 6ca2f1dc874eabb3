//! Rough grains in the DSMC engine (RS-1 to RS-9, `docs/rough.md`): equipartition of
//! elastic perfectly rough grains, spins untouched by β = -1, the homogeneous cooling and
//! white-noise states against the Maxwellian and first Sonine theory (the checks of
//! `tests/rough.rs` for the event-driven engine, with the same allowances), agreement with
//! the dilute event-driven engine, and the same bits for any number of threads and ranks
//! and through a checkpoint.
//!
//! The gases are dilute DSMC (Boltzmann, no Enskog factor) of 10⁴ grains in a unit box
//! about 5 mean free paths wide, about 100 grains per cell, with a time step of 1/50 of
//! the mean free time: DSMC's collisional loss per step is biased by up to `0.75 ζ τ`
//! (`docs/dsmc.md`), below 0.6 % of ζ/ν here at the largest ζ/ν (0.4 at α = 0.5, β = 1),
//! a third of the allowance of the Sonine theory.

use crate::common::{STANDARD_ERRORS, batch_estimate, observations};
use crate::rough::{
    EDMD_HCS, dimension_keys, hcs_of_engine_matches_theory, hcs_overrides, measured, scenario,
    uniform_gas, white_noise_of_engine_matches_theory,
};
use granular::boundary::{AxisKind, SimulationBox};
use granular::collision_law::CollisionLaw;
use granular::dsmc::{DsmcConfig, DsmcEngine};
use granular::engine::Engine;
use granular::scenario::Scenario;
use granular::theory::haff;
use granular::vector::Vector;

/// Grains of every statistical run.
const GRAINS: usize = 10_000;

/// A dilute DSMC gas of rough grains held in its homogeneous cooling state by rescaling
/// (the DSMC twin of `tests/rough.rs`'s `EDMD_HCS`); sizes and times from
/// [`dsmc_overrides`].
const DSMC_HCS: &str = r#"
engine = "dsmc"
dimension = 2
seed = 3
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "grain"
count = 10000
radius = 1e-4
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[initial]
zero_momentum = true
[collisions]
restitution = 0.9
tangential_restitution = 0.0
[dsmc]
cell_size = 0.1
time_step = 0.01
[driving]
kind = "rescale"
temperature = 1.0
[stop]
collisions_per_particle = 120.0
[output]
interval = 0.05
equilibration_collisions_per_particle = 20.0
"#;

/// The dimension, the roughness and the sizes of a DSMC run at translational temperature
/// `temperature`: the radius that makes the mean free path a fifth of the box
/// (`1/(2√2 n R)` in 2D, `1/(√2 π n σ²)` in 3D), cells of half a mean free path, a time
/// step of 1/50 and an output interval of 1/2 mean free time (`1/ν`, KT-5).
fn dsmc_overrides(d: usize, alpha: f64, beta: f64, temperature: f64) -> Vec<String> {
    let (n, radius) = (GRAINS as f64, radius(d));
    let nu = haff::collision_frequency(d, n, radius, temperature, 1.0, 1.0);
    let mut over = dimension_keys(d);
    over.extend([
        format!("species[0].radius={radius}"),
        format!("collisions.restitution={alpha}"),
        format!("collisions.tangential_restitution={beta}"),
        format!("dsmc.time_step={}", 0.02 / nu),
        format!("output.interval={}", 0.5 / nu),
    ]);
    over
}

/// The radius of [`dsmc_overrides`]: the mean free path a fifth of the unit box.
fn radius(d: usize) -> f64 {
    let (n, lambda) = (GRAINS as f64, 0.2);
    if d == 2 {
        1.0 / (2.0 * 2f64.sqrt() * n * lambda)
    } else {
        0.5 / (2f64.sqrt() * std::f64::consts::PI * n * lambda).sqrt()
    }
}

fn dsmc_hcs(d: usize, alpha: f64, beta: f64) -> Scenario {
    scenario(DSMC_HCS, &dsmc_overrides(d, alpha, beta, 1.0))
}

/// Elastic perfectly rough grains (α = β = 1) starting without spin relax to
/// equipartition: `T_r/T_t = N/(N-1)` (the total momentum, conserved by DSMC's
/// collisions, is zero: `d_t` translational degrees of freedom are frozen). DSMC's
/// collisions conserve energy and momentum and its rate `|g·n|` is Boltzmann's, so its
/// equilibrium is that of the gas. Batch means after 10 collisions per grain, 4 errors.
#[test]
fn dsmc_perfectly_rough_elastic_grains_reach_equipartition() {
    for d in [2, 3] {
        let mut over = dsmc_overrides(d, 1.0, 1.0, 0.5);
        over.push("stop.collisions_per_particle=70".into());
        let text = DSMC_HCS
            .replace("[driving]\nkind = \"rescale\"\ntemperature = 1.0\n", "")
            .replace(
                "angular_velocity = { distribution = \"maxwell_boltzmann\", temperature = 1.0 }\n",
                "",
            );
        let obs = observations(scenario(&text, &over));
        assert_eq!(obs[0].rotational_temperature, Some(0.0));
        let late: Vec<f64> = obs
            .iter()
            .filter(|o| o.collisions_per_particle > 10.0)
            .map(|o| o.rotational_temperature.expect("rough") / o.temperature)
            .collect();
        let (mean, err) = batch_estimate(&late);
        let expected = GRAINS as f64 / (GRAINS as f64 - 1.0);
        eprintln!(
            "DSMC {d}D α = β = 1: T_r/T_t = {mean:.5} ± {err:.5} over {} samples (expected {expected:.5})",
            late.len()
        );
        assert!(
            (mean - expected).abs() < STANDARD_ERRORS * err,
            "DSMC {d}D: T_r/T_t = {mean} ± {err}, expected {expected}"
        );
    }
}

/// β = -1 leaves every angular velocity bit for bit untouched, at pairs and walls: rough
/// grains under Walton's rule with sticking value -1 (which always gives β = -1 yet
/// keeps the grains rough) and smooth walls (`e_t = 1`, β_w = -1), inelastic, in a box
/// walled along its last axis; with β = 0.5 the same run does change them.
fn spins_untouched<const D: usize>() {
    let run = |beta: f64, friction: Option<f64>| {
        let n = 4000;
        let mut bx = SimulationBox::<D>::uniform(Vector([1.0; D]), AxisKind::Periodic);
        bx.axes[D - 1] = AxisKind::Wall;
        let config = DsmcConfig {
            cell_size: Some(0.1),
            ..DsmcConfig::default()
        };
        let radius = if D == 2 { 2e-4 } else { 5e-3 };
        let mut e = DsmcEngine::<D>::new(config, bx, n, radius, 1.0, 1.0, 5).unwrap();
        let law = CollisionLaw {
            tangential_restitution: beta,
            friction,
            wall_tangential_restitution: 1.0,
            ..CollisionLaw::uniform(0.8)
        };
        let r = D * (D - 1) / 2;
        let spins: Vec<f64> = (0..r * n).map(|k| (k as f64 * 0.37).sin()).collect();
        e.make_rough(law, if D == 2 { 0.5 } else { 0.4 }, &spins)
            .unwrap();
        let tau = e.time_step();
        for _ in 0..200 {
            e.step(tau);
        }
        assert!(
            e.collisions() > 4 * n as u64,
            "{} collisions",
            e.collisions()
        );
        (spins, e.angular_velocities())
    };
    let (before, after) = run(-1.0, Some(0.3));
    assert!(before == after, "{D}D: β = -1 changed a spin");
    let (before, after) = run(0.5, None);
    assert!(before != after, "{D}D: β = 0.5 changed no spin");
}

#[test]
fn dsmc_smooth_limit_leaves_spins_untouched() {
    spins_untouched::<2>();
    spins_untouched::<3>();
}

/// The homogeneous cooling state of rough disks and spheres in DSMC at the issue's four
/// (α, β), against RS-4/RS-5 and RS-8 with the allowances of `tests/rough.rs`.
#[test]
fn dsmc_homogeneous_cooling_state_of_rough_grains_matches_theory() {
    for d in [2, 3] {
        hcs_of_engine_matches_theory(d, "DSMC ", |alpha, beta| dsmc_hcs(d, alpha, beta));
    }
}

/// The white-noise driven rough gas in DSMC (kicks on the translational velocities after
/// every step), against RS-6 and RS-9 as in `tests/rough.rs`. The run starts at the
/// steady temperatures of RS-6 (`RoughGas::white_noise_temperature`), whose collision
/// frequency sets the step and the output interval.
#[test]
fn dsmc_white_noise_state_of_rough_grains_matches_theory() {
    white_noise_of_engine_matches_theory("DSMC ", |d, alpha, beta| {
        let gas = uniform_gas(d, alpha, beta);
        let nu1 = haff::collision_frequency(d, GRAINS as f64, radius(d), 1.0, 1.0, 1.0);
        let t = gas.white_noise_temperature(1.0, 1.0, GRAINS, nu1);
        let theta = gas.white_noise_temperature_ratio();
        let mut over = dsmc_overrides(d, alpha, beta, t);
        over.extend([
            "driving.kind=\"white_noise\"".into(),
            "driving.strength=1.0".into(),
            format!("species[0].velocity.temperature={t}"),
            format!("species[0].angular_velocity.temperature={}", theta * t),
        ]);
        let text = DSMC_HCS.replace("temperature = 1.0\n[stop]", "[stop]");
        scenario(&text, &over)
    });
}

/// DSMC and the dilute event-driven engine (`tests/rough.rs`'s runs) agree on θ and ζ/ν
/// of the cooling state within their errors (4 combined standard errors; the Enskog
/// factor of the event-driven gas, 1.005, divides out of both), at (α, β) = (0.9, 0.5) in
/// 2D and (0.7, 0.5) in 3D.
#[test]
fn dsmc_and_event_driven_rough_grains_agree() {
    let mut failures = Vec::new();
    for (d, alpha, beta) in [(2, 0.9, 0.5), (3, 0.7, 0.5)] {
        let (dt, dz) = measured(dsmc_hcs(d, alpha, beta));
        let (et, ez) = measured(scenario(EDMD_HCS, &hcs_overrides(d, alpha, beta)));
        for (what, a, b) in [("θ", dt, et), ("ζ/ν", dz, ez)] {
            let tol = STANDARD_ERRORS * (a.1 * a.1 + b.1 * b.1).sqrt();
            eprintln!(
                "{d}D α = {alpha} β = {beta} {what}: DSMC {:.4} ± {:.4}, event-driven {:.4} ± {:.4}",
                a.0, a.1, b.0, b.1
            );
            if (a.0 - b.0).abs() > tol {
                failures.push(format!(
                    "{d}D α = {alpha} β = {beta} {what}: DSMC {:.4} ± {:.4} against event-driven {:.4} ± {:.4} (tolerance {tol:.4})",
                    a.0, a.1, b.0, b.1
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A rough DSMC gas with everything on: walls along the last axis that are rough
/// themselves (`wall_tangential_restitution = -0.5`, β_w = 0.5), gravity, the TC model,
/// spins from a Maxwellian, snapshots with angular velocities.
fn everything_rough(d: usize) -> Scenario {
    let text = format!(
        r#"
        engine = "dsmc"
        dimension = {d}
        seed = 9
        gravity = {gravity}
        [box]
        lengths = {lengths}
        boundary = {boundary}
        [[species]]
        name = "grain"
        count = 6000
        packing_fraction = 0.05
        velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
        angular_velocity = {{ distribution = "maxwell_boltzmann", temperature = 2.0 }}
        [collisions]
        restitution = 0.8
        tangential_restitution = 0.3
        wall_restitution = 0.9
        wall_tangential_restitution = -0.5
        contact_duration = 1e-3
        [dsmc]
        cell_size = 0.1
        [stop]
        time = 0.2
        [output]
        interval = 0.05
        snapshot_every = 1
        equilibration_collisions_per_particle = 0.0
        "#,
        gravity = if d == 2 {
            "[0.0, -2.0]"
        } else {
            "[0.0, 0.0, -2.0]"
        },
        lengths = if d == 2 {
            "[1.0, 1.0]"
        } else {
            "[1.0, 1.0, 1.0]"
        },
        boundary = if d == 2 {
            r#"["periodic", "wall"]"#
        } else {
            r#"["periodic", "periodic", "wall"]"#
        },
    );
    Scenario::from_toml(&text, &[]).expect("valid scenario")
}

/// Every file of a run directory but the log and the summary (compared without its
/// clock), by name.
fn run_files(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in ["", "snapshots"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if e.path().is_file() && name != "log.txt" && name != "summary.json" {
                out.push((format!("{sub}/{name}"), std::fs::read(e.path()).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// The rough gas of [`everything_rough`] gives the same bits on 1 and 2 threads and split
/// over 2 and 3 ranks (threads of this process as ranks): `summary.json` but for its clock,
/// `timeseries.csv` and every snapshot (angular velocities included), byte for byte.
#[test]
fn rough_dsmc_is_bit_identical_for_any_number_of_threads_and_ranks() {
    use granular::run::Run;
    for d in [2, 3] {
        let scenario = everything_rough(d);
        let threaded = |threads: usize| {
            let dir = crate::common::tmp("rough-threads");
            crate::dsmc::in_pool(threads, || {
                Run::create(&dir, scenario.clone())
                    .unwrap()
                    .run_to_end(&mut |_| {}, None)
                    .unwrap();
            });
            dir
        };
        let one = threaded(1);
        let files = run_files(&one);
        assert!(
            files.iter().any(|(n, _)| n.starts_with("snapshots/")),
            "no snapshot written"
        );
        let snap = granular::output::npz::read_snapshot(
            one.join("snapshots").join(
                files
                    .iter()
                    .rev()
                    .find(|(n, _)| n.starts_with("snapshots/"))
                    .map(|(n, _)| n.trim_start_matches("snapshots/").to_string())
                    .unwrap(),
            ),
        )
        .unwrap();
        assert_eq!(snap.angular_velocities.len(), 6000 * d * (d - 1) / 2);
        let summary = crate::decomposed::summary_without_clock(&one);
        let two = threaded(2);
        assert!(run_files(&two) == files, "{d}D: 2 threads differ from 1");
        assert_eq!(crate::decomposed::summary_without_clock(&two), summary);
        for k in [2, 3] {
            let shared = crate::common::tmp("rough-ranks");
            let own = crate::common::tmp("rough-ranks-own");
            crate::decomposed::on_ranks(k, |comm, _| {
                let rank = comm.rank();
                let dir = crate::decomposed::rank_dir(rank, &shared, &own, false);
                let mut run = Run::create(&dir, scenario.clone()).unwrap();
                run.decompose(comm, &shared).unwrap();
                run.run_to_end(&mut |_| {}, None).unwrap();
            });
            let got = run_files(&shared);
            let names = |f: &[(String, Vec<u8>)]| f.iter().map(|x| x.0.clone()).collect::<Vec<_>>();
            assert_eq!(names(&got), names(&files), "{d}D {k} ranks: other files");
            for ((name, a), (_, b)) in got.iter().zip(&files) {
                assert!(
                    a == b,
                    "{d}D {k} ranks: {name} differs from the threaded run's"
                );
            }
            assert_eq!(
                crate::decomposed::summary_without_clock(&shared),
                summary,
                "{d}D {k} ranks: summary.json"
            );
            for dir in [shared, own] {
                let _ = std::fs::remove_dir_all(dir);
            }
        }
        for dir in [one, two] {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// A rough DSMC run killed in the middle of an output interval and resumed from its
/// checkpoint ends with the same bits (the angular velocities are part of the grains'
/// records in the checkpoint).
#[test]
fn rough_dsmc_run_resumes_bit_identical() {
    let o: Vec<String> = [
        "output.interval=1e6",
        "output.checkpoint_seconds=1e-9",
        "stop.collisions_per_particle=40",
        "stop.events=1000000",
    ]
    .map(String::from)
    .to_vec();
    crate::spine::assert_resume_mid_interval("rough-dsmc", scenario(DSMC_HCS, &o));
}
