//! The intruder engine through the scenario spine: `[intruder]` parsing and errors,
//! resume, and the DSMC twin against the Gillespie engine (same scenario, `model`
//! switched). Statistical tolerances: 4 combined standard errors as reported by the runs.

use granular::run::{Run, Summary};
use granular::scenario::Scenario;
use std::path::PathBuf;

const ONE_D: &str = r#"
engine = "intruder"
seed = 3

[intruder]
model = "1d"
mass = 1.0
restitution = 0.5
bath = { kind = "gaussian", temperature = 0.5 }

[stop]
collisions = 200000

[output]
interval = 2000.0
checkpoint_seconds = 1e-9
"#;

use crate::common::tmp;

fn run(dir: &std::path::Path, s: Scenario) -> Summary {
    Run::create(dir, s)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap()
}

fn with(overrides: &[&str]) -> Scenario {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scenario::from_toml(ONE_D, &o).unwrap()
}

#[test]
fn intruder_scenarios_round_trip_for_every_model() {
    for model in [
        &["intruder.model=\"1d\""][..],
        &[
            "intruder.model=\"dsmc-twin\"",
            "intruder.bath_particles=500",
        ][..],
        &[
            "intruder.model=\"needle\"",
            "intruder.bath=0",
            "intruder.bath_temperature=0.5",
        ][..],
    ] {
        // The needle has no `bath` table: replace it by a scalar and remove it below.
        let mut text = ONE_D.to_string();
        let mut o: Vec<String> = model.iter().map(|s| s.to_string()).collect();
        if o[0].contains("needle") {
            text = text.replace("bath = { kind = \"gaussian\", temperature = 0.5 }\n", "");
            o.retain(|s| !s.starts_with("intruder.bath="));
        }
        let s = Scenario::from_toml(&text, &o).expect("valid");
        let again = Scenario::from_toml(&s.to_toml(), &[]).expect("resolved scenario is valid");
        assert_eq!(s, again, "{model:?}");
    }
}

/// A disk (`dimension = 2`) or sphere (`dimension = 3`) scenario, with `overrides`.
fn ball(model: &str, bath: &str, overrides: &[&str]) -> Scenario {
    let d = if model == "sphere" { 3 } else { 2 };
    let text = format!(
        "engine = \"intruder\"\ndimension = {d}\nseed = 3\n[intruder]\nmodel = \"{model}\"\nrestitution = 0.5\nbath = {bath}\n[stop]\ncollisions = 100000\n[output]\ninterval = 500.0\ncheckpoint_seconds = 1e-9\n"
    );
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scenario::from_toml(&text, &o).unwrap()
}

#[test]
fn disk_and_sphere_scenarios_round_trip_and_resume() {
    let gaussian = "{ kind = \"gaussian\", temperature = 0.5 }";
    for (model, bath, o) in [
        (
            "disk",
            "{ kind = \"power-law\", temperature = 0.5 }",
            &[][..],
        ),
        ("sphere", gaussian, &["intruder.method=\"direct\""][..]),
        (
            "sphere",
            gaussian,
            &[
                "intruder.method=\"dsmc-twin\"",
                "intruder.bath_particles=300",
            ][..],
        ),
        (
            "disk",
            "{ kind = \"tabulated\", points = [[0.0, 0.0], [1.0, 1.0], [3.0, 0.0]] }",
            &[][..],
        ),
    ] {
        let s = ball(model, bath, o);
        let again = Scenario::from_toml(&s.to_toml(), &[]).expect("resolved scenario is valid");
        assert_eq!(s, again, "{model} {o:?}");
        let name = format!("{model}-{}", bath.len() + o.len());
        let (full, cut) = (tmp(&format!("{name}-full")), tmp(&format!("{name}-cut")));
        let a = run(&full, s.clone());
        assert!(
            Run::create(&cut, s)
                .unwrap()
                .run_to_end(&mut |_| {}, Some(5))
                .is_err()
        );
        let b = Run::resume(&cut)
            .unwrap()
            .run_to_end(&mut |_| {}, None)
            .unwrap();
        assert_eq!(
            crate::spine::final_bits(&a),
            crate::spine::final_bits(&b),
            "{name}"
        );
        assert_eq!(a.intruder, b.intruder, "{name}");
        let block = a.intruder.as_ref().expect("intruder block");
        assert_eq!(block.model, model);
        assert!(block.samples > 100, "{name}: {}", block.samples);
        let csv = |d: &PathBuf, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
        assert_eq!(
            csv(&full, "timeseries.csv"),
            csv(&cut, "timeseries.csv"),
            "{name}"
        );
        let hist = csv(&full, "intruder_histograms.csv");
        assert!(
            hist.contains("\nspeed,") && hist.contains("\nvelocity_y,"),
            "{name}"
        );
        assert_eq!(hist.contains("\nvelocity_z,"), model == "sphere", "{name}");
    }
}

/// A disk in a Gaussian bath through the scenario spine: the summary's block carries
/// G-40 to G-42 and the run meets them (4 batch-means errors).
#[test]
fn disk_scenario_summary_meets_martin_piasecki() {
    let s = ball(
        "disk",
        "{ kind = \"gaussian\", temperature = 0.5 }",
        &["stop.collisions=400000", "output.interval=5000.0"],
    );
    let a = run(&tmp("disk-theory"), s);
    let b = a.intruder.expect("intruder block");
    let (ratio, err) = (
        b.value("temperature_ratio").unwrap(),
        b.value("temperature_ratio_error").unwrap(),
    );
    assert_eq!(b.theory_temperature_ratio, Some(0.6));
    assert!((ratio - 0.6).abs() <= 4.0 * err, "{ratio} +- {err}");
    assert_eq!(b.theory_kurtosis, Some(2.0));
    let rate = b.value("collision_rate").unwrap();
    let rate_err = b.value("collision_rate_error").unwrap();
    let want = b.theory_collision_rate.unwrap();
    assert!(
        (rate - want).abs() <= 4.0 * rate_err,
        "{rate} +- {rate_err} vs {want}"
    );
    assert_eq!(b.histogram_reference, "maxwellian_g40");
}

#[test]
fn intruder_errors_name_the_field_value_and_fix() {
    let err = |o: &[&str]| {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        Scenario::from_toml(ONE_D, &o)
            .expect_err("invalid")
            .to_string()
    };
    let e = err(&["intruder.restitution=1.5"]);
    assert!(
        e.contains("intruder.restitution") && e.contains("1.5") && e.contains("[0, 1]"),
        "{e}"
    );
    let e = err(&["intruder.mass=-1"]);
    assert!(
        e.contains("intruder.mass") && e.contains("-1") && e.contains("positive"),
        "{e}"
    );
    let e = err(&["intruder.model=\"3d\""]);
    assert!(e.contains("\"3d\"") && e.contains("needle"), "{e}");
    let e = err(&["intruder.lenght=2"]);
    assert!(
        e.contains("intruder.lenght") && e.contains("unknown field"),
        "{e}"
    );
    let e = err(&["stop.energy_fraction=0.5"]);
    assert!(e.contains("stop.energy_fraction"), "{e}");
    let text = ONE_D.replace("mass = 1.0", "masss = 1.0");
    let e = Scenario::from_toml(&text, &[])
        .expect_err("unknown key")
        .to_string();
    assert!(e.contains("intruder.masss") && e.contains("line"), "{e}");
}

#[test]
fn intruder_resume_equals_the_uninterrupted_run() {
    for (name, o) in [
        ("1d", vec![]),
        (
            "twin",
            vec![
                "intruder.model=\"dsmc-twin\"",
                "intruder.bath_particles=1000",
            ],
        ),
    ] {
        let s = with(&o);
        let (full, cut) = (tmp(&format!("{name}-full")), tmp(&format!("{name}-cut")));
        let a = run(&full, s.clone());
        assert!(
            Run::create(&cut, s)
                .unwrap()
                .run_to_end(&mut |_| {}, Some(5))
                .is_err()
        );
        let b = Run::resume(&cut)
            .unwrap()
            .run_to_end(&mut |_| {}, None)
            .unwrap();
        assert_eq!(
            crate::spine::final_bits(&a),
            crate::spine::final_bits(&b),
            "{name}"
        );
        assert_eq!(a.intruder, b.intruder, "{name}");
        let csv = |d: &PathBuf| std::fs::read_to_string(d.join("timeseries.csv")).unwrap();
        assert_eq!(csv(&full), csv(&cut), "{name}");
    }
    // The needle has its own table.
    let text = r#"
engine = "intruder"
[intruder]
model = "needle"
mass = 0.5
restitution = 0.3
[stop]
collisions = 100000
[output]
interval = 500.0
"#;
    let s = Scenario::from_toml(text, &[]).unwrap();
    let (full, cut) = (tmp("needle-full"), tmp("needle-cut"));
    let a = run(&full, s.clone());
    assert!(
        Run::create(&cut, s)
            .unwrap()
            .run_to_end(&mut |_| {}, Some(3))
            .is_err()
    );
    let b = Run::resume(&cut)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert_eq!(crate::spine::final_bits(&a), crate::spine::final_bits(&b));
    assert_eq!(a.stop_reason, "collisions");
    // Killed between two outputs (checkpoints come between chunks of events).
    crate::spine::assert_resume_mid_interval(
        "intruder-1d",
        with(&["output.interval=1e9", "stop.events=1000000"]),
    );
}

/// Regression (issue 24): the needle's checkpoints grew with the run (6 MB after 9 s of
/// wall time, 19 MB after 50 s), because every block of 64 grid samples was kept. The
/// block means are now bounded (`MAX_BLOCKS`, the block length doubling): on a grid so
/// fine that the bound is reached early, the checkpoints of the second half of the run are
/// no larger than those of the first half, although the run holds several times more samples than the bound
/// by then, and the run resumes bit for bit.
#[test]
fn intruder_checkpoints_do_not_grow_with_the_run() {
    let text = r#"
engine = "intruder"
seed = 5
[intruder]
model = "needle"
mass = 0.5
restitution = 0.5
sample_interval = 2e-4
transient = 0.0
[stop]
collisions = 3000
[output]
interval = 200.0
checkpoint_seconds = 1e-9
"#;
    let s = Scenario::from_toml(text, &[]).unwrap();
    let dir = tmp("needle-size");
    let mut sizes: Vec<(f64, u64)> = Vec::new();
    let checkpoint = dir.join("checkpoint.msgpack");
    let a = Run::create(&dir, s.clone())
        .unwrap()
        .run_to_end(
            &mut |p| {
                if let Ok(m) = std::fs::metadata(&checkpoint) {
                    sizes.push((p.time, m.len()));
                }
            },
            None,
        )
        .unwrap();
    let end = sizes.last().map_or(0.0, |x| x.0);
    let half = |(t, _): &&(f64, u64)| *t < end / 2.0;
    let first: u64 = sizes.iter().filter(half).map(|x| x.1).max().unwrap();
    let second: u64 = sizes
        .iter()
        .filter(|x| !half(x))
        .map(|x| x.1)
        .max()
        .unwrap();
    let samples = a.intruder.as_ref().unwrap().samples as f64;
    let bound = (granular::intruder::observables::MAX_BLOCKS * 64) as f64;
    assert!(
        samples > 4.0 * bound,
        "{samples} samples: the bound is not reached"
    );
    assert!(
        sizes.len() >= 10 && second as f64 <= 1.05 * first as f64,
        "checkpoint bytes: {first} in the first half, {second} in the second: {sizes:?}"
    );
    assert!(second < 2_000_000, "{second} bytes");
    // Killed after five outputs, resumed: the same run.
    let cut = tmp("needle-size-cut");
    assert!(
        Run::create(&cut, s)
            .unwrap()
            .run_to_end(&mut |_| {}, Some(5))
            .is_err()
    );
    let b = Run::resume(&cut)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert_eq!(crate::spine::final_bits(&a), crate::spine::final_bits(&b));
    assert_eq!(a.intruder, b.intruder);
}

fn ratio(s: &Summary) -> (f64, f64) {
    let b = s.intruder.as_ref().expect("intruder block");
    (
        b.averages["temperature_ratio"].expect("ratio"),
        b.averages["temperature_ratio_error"].expect("error"),
    )
}

/// The DSMC twin (section 4) and the Gillespie engine give the same `T/T_B` within their
/// combined statistical errors, and both agree with G-18, through the run spine.
#[test]
fn dsmc_twin_engine_agrees_with_gillespie_engine() {
    let o = [
        "intruder.restitution=0.3",
        "intruder.mass=0.5",
        "stop.collisions=400000",
    ];
    let g = run(&tmp("g"), with(&o));
    let mut ot = o.to_vec();
    ot.extend([
        "intruder.model=\"dsmc-twin\"",
        "intruder.bath_particles=20000",
    ]);
    let t = run(&tmp("t"), with(&ot));
    let ((rg, eg), (rt, et)) = (ratio(&g), ratio(&t));
    assert!(eg > 0.0 && et > 0.0);
    assert!(
        (rg - rt).abs() <= 4.0 * (eg * eg + et * et).sqrt(),
        "Gillespie {rg} ± {eg}, DSMC twin {rt} ± {et}"
    );
    let eq18 = granular::intruder::theory::martin_piasecki_ratio(0.3, 0.5, 1.0);
    for (r, e) in [(rg, eg), (rt, et)] {
        assert!((r - eq18).abs() <= 4.0 * e, "{r} ± {e} vs Eq. 18 {eq18}");
    }
    assert_eq!(t.engine, "intruder");
    assert!(t.intruder.as_ref().unwrap().trials_per_collision.unwrap() >= 1.0);
}
