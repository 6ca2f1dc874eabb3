//! Per-grain arrays that are not scenario text: positions and velocities read from an
//! `.npz` file (`{ npz = "...", array = "..." }`) or given by a program
//! (`ScenarioInput::arrays`, what the Python package passes for NumPy arrays) make the same
//! scenario, and the same bits, as the same numbers written inline; a run directory keeps
//! them in `initial_state.npz`, named by its `scenario.toml`, which runs again bit for bit.

use granular::output::npz::{NpzArray, write_npz};
use granular::prelude::*;
use granular::run::RunDir;
use granular::scenario::{GrainVectors, ScenarioInput, VectorSource, file_overrides};
use std::path::Path;

/// `n` disks (2D) or spheres (3D) on a jittered lattice with given velocities, as the
/// scenario's text with `positions` and `velocities` replaced by `arrays`.
fn scenario_text(engine: &str, d: usize, arrays: &str) -> String {
    format!(
        r#"
engine = "{engine}"
dimension = {d}
seed = 3
[collisions]
restitution = 0.8
[[species]]
name = "grain"
count = {N}
radius = 0.01
{arrays}
[stop]
time = 0.5
[output]
interval = 0.25
"#
    )
}

const N: usize = 64;

/// Row-major positions on a lattice (well apart) and velocities of `N` grains.
fn arrays(d: usize) -> (Vec<f64>, Vec<f64>) {
    let side = (N as f64).powf(1.0 / d as f64).ceil() as usize;
    let mut x = Vec::new();
    let mut v = Vec::new();
    for i in 0..N {
        let mut k = i;
        for a in 0..d {
            x.push((0.5 + (k % side) as f64) / side as f64 + 0.001 * (a as f64));
            k /= side;
            v.push(((i * 7 + a * 3) % 11) as f64 / 11.0 - 0.45);
        }
    }
    (x, v)
}

fn inline(values: &[f64], d: usize) -> String {
    let rows: Vec<String> = values
        .chunks(d)
        .map(|r| {
            format!(
                "[{}]",
                r.iter()
                    .map(|x| format!("{x:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
        .collect();
    format!("[{}]", rows.join(", "))
}

fn final_state(scenario: Scenario) -> (Vec<f64>, Vec<f64>) {
    let mut sim = Simulation::new(scenario).expect("builds");
    sim.advance(0.5).expect("advances");
    (
        sim.positions().expect("grains"),
        sim.velocities().expect("grains"),
    )
}

#[test]
fn inline_npz_and_given_arrays_are_the_same_scenario_and_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    for (engine, d) in [("edmd", 2), ("edmd", 3), ("dsmc", 2)] {
        let (x, v) = arrays(d);
        let text = scenario_text(
            engine,
            d,
            &format!(
                "positions = {}\nvelocity = {{ distribution = \"per_grain\", velocities = {} }}",
                inline(&x, d),
                inline(&v, d)
            ),
        );
        let written = Scenario::from_toml(&text, &[]).expect("inline arrays");

        let npz = dir.path().join(format!("{engine}{d}.npz"));
        write_npz(
            &npz,
            &[
                ("positions", NpzArray::f64_2d(x.clone(), N, d).unwrap()),
                ("v", NpzArray::f64_2d(v.clone(), N, d).unwrap()),
            ],
        )
        .unwrap();
        let name = npz.file_name().unwrap().to_str().unwrap();
        let by_file = scenario_text(
            engine,
            d,
            &format!(
                "positions = {{ npz = \"{name}\" }}\nvelocity = {{ distribution = \"per_grain\", \
                 velocities = {{ npz = \"{name}\", array = \"v\" }} }}"
            ),
        );
        let from_file = ScenarioInput {
            text: &by_file,
            base: Some(dir.path()),
            limits: true,
            ..Default::default()
        }
        .read()
        .expect("arrays from the .npz file");
        assert!(matches!(
            from_file.species()[0].positions.source(),
            VectorSource::Npz { .. }
        ));

        let given = [
            (
                "species[0].positions".to_string(),
                GrainVectors::given(x.clone(), d).unwrap(),
            ),
            (
                "species.0.velocity.velocities".to_string(),
                GrainVectors::given(v.clone(), d).unwrap(),
            ),
        ];
        let bare = scenario_text(engine, d, "");
        let from_program = ScenarioInput {
            text: &bare,
            arrays: &given,
            limits: true,
            ..Default::default()
        }
        .read()
        .expect("given arrays");

        assert_eq!(from_file, written, "{engine} {d}D: npz");
        assert_eq!(from_program, written, "{engine} {d}D: given");
        let reference = final_state(written);
        assert_eq!(final_state(from_file), reference, "{engine} {d}D: npz bits");
        assert_eq!(
            final_state(from_program),
            reference,
            "{engine} {d}D: given bits"
        );
    }
}

#[test]
fn a_run_directory_keeps_given_arrays_in_initial_state_npz_and_runs_again_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = 2;
    let (x, v) = arrays(d);
    let given = [
        (
            "species[0].positions".to_string(),
            GrainVectors::given(x.clone(), d).unwrap(),
        ),
        (
            "species[0].velocity.velocities".to_string(),
            GrainVectors::given(v, d).unwrap(),
        ),
    ];
    let bare = scenario_text("edmd", d, "");
    let scenario = ScenarioInput {
        text: &bare,
        arrays: &given,
        limits: true,
        ..Default::default()
    }
    .read()
    .unwrap();

    let first = dir.path().join("first");
    Run::create(&first, scenario.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let text = std::fs::read_to_string(first.join("scenario.toml")).unwrap();
    assert!(
        text.contains(
            "[species.positions]\nnpz = \"initial_state.npz\"\narray = \"species[0].positions\""
        ),
        "{text}"
    );
    assert!(first.join("initial_state.npz").is_file());
    let run = RunDir::new(&first);
    assert_eq!(
        run.scenario().unwrap(),
        scenario,
        "read back from the run directory"
    );

    // `granular run first/scenario.toml` from another working directory: the relative
    // `initial_state.npz` is the run directory's (file_overrides, as the command line does).
    let path = first.join("scenario.toml");
    let base = ScenarioInput {
        text: &text,
        base: path.parent(),
        ..Default::default()
    }
    .read()
    .unwrap();
    let absolute = file_overrides(&path, &base);
    assert_eq!(absolute.len(), 2, "{absolute:?}");
    let again = Scenario::from_toml(&text, &absolute).unwrap();
    assert_eq!(again, scenario);
    let second = dir.path().join("second");
    Run::create(&second, again)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    // Interrupted after its first output and resumed: the checkpoint names the arrays in
    // the run directory too.
    let third = dir.path().join("third");
    let _ = Run::create(&third, scenario.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, Some(1));
    Run::resume(&third)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    for f in ["timeseries.csv", "snapshots/snapshot_000002.npz"] {
        let reference = std::fs::read(first.join(f)).unwrap();
        assert_eq!(reference, std::fs::read(second.join(f)).unwrap(), "{f}");
        assert_eq!(
            reference,
            std::fs::read(third.join(f)).unwrap(),
            "{f} resumed"
        );
    }
    assert_eq!(
        std::fs::read(first.join("initial_state.npz")).unwrap(),
        std::fs::read(second.join("initial_state.npz")).unwrap()
    );
}

#[test]
fn bad_npz_arrays_are_refused_naming_the_key_and_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let npz = dir.path().join("state.npz");
    write_npz(
        &npz,
        &[
            ("positions", NpzArray::f64_2d(arrays(2).0, N, 2).unwrap()),
            ("flat", NpzArray::f64_1d(vec![0.5; N])),
            ("ids", NpzArray::u32_1d(vec![0; N])),
            ("few", NpzArray::f64_2d(vec![0.5; 20], 10, 2).unwrap()),
            ("wide", NpzArray::f64_2d(vec![0.5; 3 * N], N, 3).unwrap()),
        ],
    )
    .unwrap();
    let read = |positions: &str, base: Option<&Path>| {
        ScenarioInput {
            text: &scenario_text("edmd", 2, &format!("positions = {positions}")),
            base,
            ..Default::default()
        }
        .read()
        .unwrap_err()
    };
    let cases = [
        (
            "{ npz = \"missing.npz\" }",
            "species[0].positions.npz",
            "cannot be read",
        ),
        (
            "{ npz = \"state.npz\", array = \"nope\" }",
            "species[0].positions.array",
            "its arrays are",
        ),
        (
            "{ npz = \"state.npz\", array = \"flat\" }",
            "species[0].positions.array",
            "give an (N, D) array",
        ),
        (
            "{ npz = \"state.npz\", array = \"ids\" }",
            "species[0].positions.array",
            "not float64",
        ),
        (
            "{ npz = \"state.npz\", array = \"few\" }",
            "species[0].positions",
            "lists 10 positions for count = 64",
        ),
        (
            "{ npz = \"state.npz\", array = \"wide\" }",
            "species[0].positions",
            "give 2",
        ),
        (
            "{ npz = \"state.npz\", member = \"x\" }",
            "species[0].positions",
            "npz = ",
        ),
    ];
    for (value, key, says) in cases {
        let e = read(value, Some(dir.path()));
        assert_eq!(e.key, key, "{value}: {e}");
        assert!(e.message.contains(says), "{value}: {e}");
    }
    // A relative path without a base is the current directory's.
    let e = read("{ npz = \"state.npz\" }", None);
    assert_eq!(e.key, "species[0].positions.npz", "{e}");
    let e = Scenario::from_toml(
        &scenario_text("edmd", 2, "positions = [[0.5, 0.5], [0.2]]"),
        &[],
    )
    .unwrap_err();
    assert!(
        e.message.contains("row 1 has 1 numbers where row 0 has 2"),
        "{e}"
    );
    // A program's array at a key that takes none.
    let wrong = [(
        "species[0].radius".to_string(),
        GrainVectors::given(vec![0.5; 2 * N], 2).unwrap(),
    )];
    let e = ScenarioInput {
        text: &scenario_text("edmd", 2, ""),
        arrays: &wrong,
        ..Default::default()
    }
    .read()
    .unwrap_err();
    assert!(e.message.contains("does not take a per-grain array"), "{e}");
}
