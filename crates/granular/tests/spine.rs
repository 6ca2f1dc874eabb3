//! The scenario format, run directory, determinism and resume.

use granular::run::Run;
use granular::scenario::Scenario;
use std::path::PathBuf;

const GOOD: &str = r#"
engine = "edmd"
dimension = 2
seed = 5

[box]
lengths = [1.0, 1.0]
boundary = "periodic"

[[species]]
name = "light"
count = 300
packing_fraction = 0.15
mass = 1.0
velocity = { distribution = "fixed_speed", speed = 1.0 }

[[species]]
name = "heavy"
count = 300
packing_fraction = 0.15
mass = 4.0
velocity = { distribution = "fixed_speed", speed = 0.5 }

[collisions]
restitution = 0.9

[stop]
collisions_per_particle = 30.0

[output]
interval = 0.01
snapshot_every = 10
checkpoint_seconds = 1e-9
"#;

pub(crate) use crate::common::tmp;

fn error_of(text: &str, overrides: &[&str]) -> granular::scenario::ScenarioError {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scenario::from_toml(text, &o).expect_err("expected an error")
}

#[test]
fn good_scenario_resolves_and_round_trips() {
    let s = Scenario::from_toml(GOOD, &[]).expect("valid");
    assert_eq!(s.particle_count(), 600);
    let again = Scenario::from_toml(&s.to_toml(), &[]).expect("resolved scenario is valid");
    assert_eq!(s, again);
}

#[test]
fn bad_values_are_reported_with_key_value_line_and_fix() {
    let e = error_of(GOOD, &["collisions.restitution=1.5"]);
    assert_eq!(e.key, "collisions.restitution");
    assert!(
        e.message.contains("1.5") && e.message.contains("[0, 1]"),
        "{e}"
    );
    assert_eq!(e.line, Some(25), "{e}");

    let typo = GOOD.replace("restitution = 0.9", "restitutoin = 0.9");
    let e = error_of(&typo, &[]);
    assert!(
        e.message.contains("unknown field") && e.message.contains("restitutoin"),
        "{e}"
    );
    assert_eq!(e.line, Some(25));

    let wrong_type = GOOD.replace(
        "count = 300\npacking_fraction = 0.15\nmass = 4.0",
        "count = \"many\"\npacking_fraction = 0.15\nmass = 4.0",
    );
    let e = error_of(&wrong_type, &[]);
    assert_eq!(e.line, Some(19), "{e}");

    let e = error_of(
        GOOD,
        &["species[1].radius=-0.1", "species[1].packing_fraction=0.0"],
    );
    assert!(
        e.to_string().contains("packing_fraction") || e.to_string().contains("radius"),
        "{e}"
    );

    let e = error_of(GOOD, &["species.0.mass=-1"]);
    assert_eq!(e.key, "species[0].mass");
    assert!(e.message.contains("positive"));

    let big = GOOD.replace(
        "packing_fraction = 0.15\nmass = 1.0",
        "radius = 0.7\nmass = 1.0",
    );
    let e = error_of(&big, &[]);
    assert!(e.message.contains("does not fit"), "{e}");
}

#[test]
fn overlapping_given_positions_are_rejected() {
    let text = GOOD.replace(
        "count = 300\npacking_fraction = 0.15\nmass = 1.0",
        "count = 2\nradius = 0.1\npositions = [[0.5, 0.5], [0.55, 0.5]]\nmass = 1.0",
    );
    let s = Scenario::from_toml(&text, &[]).expect("valid values");
    let err = granular::run::build(&s).expect_err("overlap");
    assert!(err.to_string().contains("overlap"), "{err}");
}

#[test]
fn compression_places_all_species_together_at_the_start_density() {
    // Two sizes (1 : 1.4, equal counts) filling 0.80 of a periodic box, placed at 0.30
    // together and compressed. Placing each species alone at 0.30 (an earlier version)
    // made 0.60, beyond random sequential placement, which failed.
    let text = r#"
engine = "edmd"
dimension = 2
seed = 4
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "small"
count = 500
packing_fraction = 0.2703
[[species]]
name = "large"
count = 500
packing_fraction = 0.5297
[initial]
compress_from = 0.3
[stop]
collisions_per_particle = 1.0
"#;
    let s = Scenario::from_toml(text, &[]).expect("valid");
    let (bx, set) = granular::run::initial_particles::<2>(&s).expect("compressed state");
    let phi = granular::edmd::init::packing_fraction::<2>(&set.radii, bx.volume());
    assert!((phi - 0.8).abs() < 1e-9, "packing fraction {phi}");
    assert!((set.radii[500] / set.radii[0] - 1.4).abs() < 1e-3);
    // No two grains overlap (initial_particles checks it; here once more, directly).
    for i in 0..set.len() {
        for j in 0..i {
            let d = bx.separation(&set.positions[i], &set.positions[j]).norm();
            assert!(
                d >= (set.radii[i] + set.radii[j]) * (1.0 - 1e-9),
                "{i} and {j}"
            );
        }
    }
}

#[test]
fn species_are_placed_largest_first_whatever_their_order() {
    // A 3D bidisperse gas at packing fraction 0.27 (100 grains of radius ratio 3.2 at 0.20,
    // 4000 small ones at 0.07). Placing the small species first (the order of the file)
    // left no room for the first large grain after 10^5 attempts; largest first, both
    // orders place every grain, and at the same positions (each species draws from the
    // stream in the same order, whatever the order of the file).
    let species = |name: &str, count: usize, phi: f64| {
        format!("[[species]]\nname = \"{name}\"\ncount = {count}\npacking_fraction = {phi}\n")
    };
    let head = "engine = \"edmd\"\ndimension = 3\nseed = 3\n[box]\nlengths = [1.0, 1.0, 1.0]\n\
                boundary = \"periodic\"\n[stop]\ncollisions_per_particle = 1.0\n";
    let (small, large) = (species("small", 4000, 0.07), species("large", 100, 0.20));
    let small_first = Scenario::from_toml(&format!("{head}{small}{large}"), &[]).expect("valid");
    let large_first = Scenario::from_toml(&format!("{head}{large}{small}"), &[]).expect("valid");
    let (bx, a) = granular::run::initial_particles::<3>(&small_first).expect("small listed first");
    let (_, b) = granular::run::initial_particles::<3>(&large_first).expect("large listed first");
    let phi = granular::edmd::init::packing_fraction::<3>(&a.radii, bx.volume());
    assert!((phi - 0.27).abs() < 1e-9, "packing fraction {phi}");
    // The grains keep the order of the file: species as listed, grains in order.
    assert_eq!(a.species[0], 0);
    assert_eq!(a.species[4000], 1);
    assert!(a.radii[4000] > 3.0 * a.radii[0]);
    assert_eq!(a.positions[..4000], b.positions[100..]);
    assert_eq!(a.positions[4000..], b.positions[..100]);
    for i in 0..a.len() {
        for j in 0..i {
            let d = bx.separation(&a.positions[i], &a.positions[j]).norm();
            assert!(d >= a.radii[i] + a.radii[j], "{i} and {j} overlap");
        }
    }
}

fn final_state(dir: &std::path::Path) -> (String, String) {
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    (summary["final"].to_string(), csv)
}

#[test]
fn same_scenario_and_seed_give_identical_results() {
    let s = Scenario::from_toml(GOOD, &[]).unwrap();
    let (a, b) = (tmp("det-a"), tmp("det-b"));
    Run::create(&a, s.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    Run::create(&b, s)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert_eq!(final_state(&a), final_state(&b));
    let other = Scenario::from_toml(GOOD, &["seed=6".into()]).unwrap();
    let c = tmp("det-c");
    Run::create(&c, other)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert_ne!(final_state(&a).0, final_state(&c).0);
}

#[test]
fn resume_equals_the_uninterrupted_run() {
    let s = Scenario::from_toml(GOOD, &[]).unwrap();
    let (full, cut) = (tmp("full"), tmp("cut"));
    Run::create(&full, s.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let interrupted = Run::create(&cut, s)
        .unwrap()
        .run_to_end(&mut |_| {}, Some(7));
    assert!(interrupted.is_err(), "the run should stop after 7 outputs");
    // Simulate rows written after the checkpoint by a killed process: resume drops them.
    Run::resume(&cut)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let (a, b) = (final_state(&full), final_state(&cut));
    assert_eq!(a.0, b.0);
    for (k, (x, y)) in a.1.lines().zip(b.1.lines()).enumerate() {
        assert_eq!(x, y, "timeseries row {k}");
    }
    assert_eq!(a.1.lines().count(), b.1.lines().count());
    let snap_a = granular::run::read_snapshot(full.join("snapshots/snapshot_000020.npz")).unwrap();
    let snap_b = granular::run::read_snapshot(cut.join("snapshots/snapshot_000020.npz")).unwrap();
    assert_eq!(snap_a.positions, snap_b.positions);
    assert_eq!(
        snap_a.species_names,
        vec!["light".to_string(), "heavy".to_string()]
    );
}

/// Copies a run directory (its files and `snapshots/`): what a process killed at that
/// moment leaves behind.
fn copy_run_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to.join("snapshots")).unwrap();
    for sub in [from.to_path_buf(), from.join("snapshots")] {
        for entry in std::fs::read_dir(&sub).unwrap() {
            let path = entry.unwrap().path();
            // The lock of a killed process names a process that is gone (taken over on
            // resume); here the process is this test, still running: not copied.
            if path.is_file() && !path.ends_with(".lock") {
                let rel = path.strip_prefix(from).unwrap();
                std::fs::copy(&path, to.join(rel)).unwrap();
            }
        }
    }
}

/// The final observables of a summary bit for bit (NaN, e.g. the wall pressure of a
/// periodic box, equals NaN here).
pub(crate) fn final_bits(s: &granular::Summary) -> Vec<(String, u64)> {
    s.final_observables
        .iter()
        .map(|(k, v)| (k.clone(), v.to_bits()))
        .collect()
}

/// Runs `s` whole, and again killed after its third chunk of events (the directory then
/// holds the second chunk's checkpoint), resumed from there, and finished: the two must
/// agree. `s` should have one output interval longer than the whole run, which stops by
/// its event count, and `checkpoint_seconds = 1e-9` (after every chunk), so that each checkpoint falls inside
/// the interval.
pub(crate) fn assert_resume_mid_interval(name: &str, s: Scenario) {
    let (full, cut, killed) = (
        tmp(&format!("{name}-mid-full")),
        tmp(&format!("{name}-mid-cut")),
        tmp(&format!("{name}-mid-killed")),
    );
    let a = Run::create(&full, s.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let mut chunks = 0;
    let mut killed_at = 0.0;
    Run::create(&cut, s)
        .unwrap()
        .run_to_end(
            &mut |p| {
                chunks += 1;
                if chunks == 3 {
                    copy_run_dir(&cut, &killed);
                    killed_at = p.time;
                }
            },
            None,
        )
        .unwrap();
    assert!(
        chunks > 3,
        "{name}: the run must take more than three chunks ({chunks})"
    );
    let resumed = Run::resume(&killed).unwrap();
    let t = resumed.simulation().time();
    assert!(
        t > 0.0 && t < killed_at,
        "{name}: the checkpoint must lie inside the first interval, before the kill: \
         t = {t}, killed at {killed_at}"
    );
    let b = resumed.run_to_end(&mut |_| {}, None).unwrap();
    assert_eq!(final_bits(&a), final_bits(&b), "{name}");
    assert_eq!(a.events, b.events, "{name}");
    assert_eq!(final_state(&full), final_state(&killed), "{name}");
}

#[test]
fn resume_from_the_middle_of_an_output_interval_equals_the_uninterrupted_run() {
    let o: Vec<String> = vec![
        "collisions.restitution=1.0".into(),
        "output.interval=1e6".into(),
        "stop.events=1000000".into(),
    ];
    assert_resume_mid_interval("edmd", Scenario::from_toml(GOOD, &o).unwrap());
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml"),
    )
    .unwrap();
    let o: Vec<String> = vec![
        "species[0].count=3000".into(),
        // Elastic: a cooled gas takes ever longer steps, with ever fewer collisions each.
        "collisions.restitution=1.0".into(),
        "output.interval=1e6".into(),
        "output.checkpoint_seconds=1e-9".into(),
        "stop.events=800000".into(),
    ];
    assert_resume_mid_interval("dsmc", Scenario::from_toml(&text, &o).unwrap());
}

#[test]
fn dsmc_resume_equals_the_uninterrupted_run() {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml"),
    )
    .unwrap();
    let o: Vec<String> = vec![
        "species[0].count=3000".into(),
        "stop.time=0.5".into(),
        "output.interval=0.05".into(),
    ];
    let s = Scenario::from_toml(&text, &o).unwrap();
    let (full, cut) = (tmp("dsmc-full"), tmp("dsmc-cut"));
    Run::create(&full, s.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert!(
        Run::create(&cut, s)
            .unwrap()
            .run_to_end(&mut |_| {}, Some(4))
            .is_err()
    );
    Run::resume(&cut)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let (a, b) = (final_state(&full), final_state(&cut));
    assert_eq!(a, b);
}

/// A resumed run's summary keeps the warnings about its set-up: DSMC's validity warnings
/// of the initial state (cells larger than the mean free path) and the pre-flight warning
/// (a cooling gas with evenly spaced outputs), the same as the uninterrupted run's.
#[test]
fn a_resumed_run_keeps_the_set_up_warnings() {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml"),
    )
    .unwrap();
    let o: Vec<String> = vec![
        "species[0].count=2000".into(),
        "dsmc.cell_size=0.25".into(),
        "stop.time=0.3".into(),
        "output.interval=0.03".into(),
    ];
    let warned = Scenario::from_toml(&text, &o).unwrap();
    // The same gas to 250 collisions per grain, stopped (and checkpointed) after three
    // outputs: its pre-flight warning is the cooling one.
    let mut far = o.clone();
    far[2] = "stop.collisions_per_particle=250".into();
    let cooling = Scenario::from_toml(&text, &far).unwrap();
    assert!(
        cooling.cost().warning(&cooling).is_some(),
        "cooling warning"
    );
    for (name, s, cut_at) in [("validity", warned, 4), ("preflight", cooling, 3)] {
        let (full, cut) = (
            tmp(&format!("warn-{name}-full")),
            tmp(&format!("warn-{name}-cut")),
        );
        let expected = if name == "validity" {
            let a = Run::create(&full, s.clone())
                .unwrap()
                .run_to_end(&mut |_| {}, None)
                .unwrap();
            a.warnings
        } else {
            // Too long to finish here: the warnings it starts with are the summary's.
            Run::create(&full, s.clone()).unwrap().warnings().to_vec()
        };
        assert!(!expected.is_empty(), "{name}: the run should warn");
        assert!(
            Run::create(&cut, s.clone())
                .unwrap()
                .run_to_end(&mut |_| {}, Some(cut_at))
                .is_err(),
            "{name}: interrupted"
        );
        let resumed = Run::resume(&cut).unwrap();
        assert_eq!(resumed.warnings(), &expected[..], "{name}");
        if name == "validity" {
            let b = resumed.run_to_end(&mut |_| {}, None).unwrap();
            assert_eq!(b.warnings, expected, "{name}: summary");
            let on_disk: granular::Summary =
                serde_json::from_str(&std::fs::read_to_string(cut.join("summary.json")).unwrap())
                    .unwrap();
            assert_eq!(on_disk.warnings, expected, "{name}: summary.json");
        }
    }
}

#[test]
fn checkpoint_of_another_format_is_named_as_such() {
    let dir = tmp("old-checkpoint");
    let scenario = Scenario::from_toml(GOOD, &[]).expect("valid");
    let mut run = Run::create(&dir, scenario).expect("run directory");
    run.checkpoint().expect("checkpoint");
    drop(run);
    let path = dir.join("checkpoint.msgpack");
    let bytes = std::fs::read(&path).expect("checkpoint file");
    // The header: magic, format (u32, little-endian), length, CRC-32; then the payload,
    // a msgpack map of four (0x84) whose first key is "format" (0xa6 + 6 bytes).
    assert_eq!(&bytes[..8], granular::run::checkpoint::MAGIC);
    assert_eq!(bytes[8] as u32, granular::run::CHECKPOINT_FORMAT);
    assert_eq!(&bytes[24..32], b"\x84\xa6format");
    let mut newer = bytes.clone();
    newer[8] = 0x63;
    // Formats up to 7 had no header: the bare payload with its format number.
    let mut legacy = bytes[24..].to_vec();
    legacy[8] = 0x07;
    for (damaged, format) in [(newer, "format 99"), (legacy, "format 7")] {
        std::fs::write(&path, &damaged).expect("write");
        let Err(e) = Run::resume(&dir) else {
            panic!("a checkpoint of another format must not resume");
        };
        let msg = e.to_string();
        assert!(
            msg.contains(format) && msg.contains("another version"),
            "{msg}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
