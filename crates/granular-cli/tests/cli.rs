//! The `granular` binary end to end: run, check, resume and bench, and the errors users see.

use std::path::PathBuf;
use std::process::Command;

fn granular() -> Command {
    Command::new(env!("CARGO_BIN_EXE_granular"))
}

fn scenarios() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("granular-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn run_writes_the_run_directory() {
    let out = tmp("run");
    let status = granular()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args([
            "--set",
            "species[0].count=1000",
            "--set",
            "stop.collisions_per_particle=40",
            "--seed",
            "3",
        ])
        .status()
        .expect("runs");
    assert!(status.success());
    for f in [
        "scenario.toml",
        "summary.json",
        "timeseries.csv",
        "speed_histograms.csv",
        "impact_parameter.csv",
        "log.txt",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "engine",
        "version",
        "seed",
        "wall_seconds",
        "events",
        "events_per_second",
        "final",
    ] {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(summary["seed"], 3);
    assert_eq!(summary["engine"], "edmd");
    let fit = &summary["maxwell_boltzmann_fit"]["disk"];
    assert!(fit["p_value"].as_f64().unwrap() > 1e-3, "{fit}");
    assert!(std::fs::read_dir(out.join("snapshots")).unwrap().count() >= 2);
    let resolved = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
    assert!(resolved.contains("count = 1000") && resolved.contains("seed = 3"));
}

#[test]
fn check_reports_bad_values_with_key_value_line_and_fix() {
    let out = granular()
        .arg("check")
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args(["--set", "collisions.restitution=1.2"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("collisions.restitution") && err.contains("1.2") && err.contains("[0, 1]"),
        "{err}"
    );
    let dir = tmp("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    let text = std::fs::read_to_string(scenarios().join("maxwell-boltzmann.toml"))
        .unwrap()
        .replace("restitution = 1.0", "restitution = 1.0\nrestitushun = 2");
    std::fs::write(&bad, text).unwrap();
    let out = granular().arg("check").arg(&bad).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("restitushun") && err.contains("line "),
        "{err}"
    );
}

#[test]
fn check_prints_the_resolved_scenario() {
    let out = granular()
        .arg("check")
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("engine = \"edmd\"")
            && text.contains("[output]")
            && text.contains("checkpoint_seconds")
    );
}

#[test]
fn bench_prints_one_json_object_per_case() {
    let out = granular()
        .args([
            "bench",
            "edmd",
            "--dimension",
            "2",
            "--n",
            "2000",
            "--packing-fraction",
            "0.5",
            "--collisions-per-particle",
            "5",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = String::from_utf8_lossy(&out.stdout);
    let v: serde_json::Value = serde_json::from_str(line.trim()).unwrap();
    for key in [
        "dimension",
        "n",
        "packing_fraction",
        "collisions_per_second",
        "bytes_per_particle",
    ] {
        assert!(v.get(key).is_some(), "{key} missing in {v}");
    }
}

#[test]
fn every_bundled_scenario_is_valid() {
    for entry in std::fs::read_dir(scenarios()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let out = granular().arg("check").arg(&path).output().unwrap();
            assert!(
                out.status.success(),
                "{}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// The section-3.2 pair, shrunk: both engines write the opt-in observables of `[output]`
/// with the shapes documented in docs/output.md, and `granular compare` overlays them.
#[test]
fn observables_are_written_for_both_engines_and_compared() {
    use granular::output::npz::read_npz;
    let base = tmp("observables");
    let mut dirs = Vec::new();
    for engine in ["edmd", "dsmc"] {
        let out = base.join(engine);
        let status = granular()
            .args(["run", "--quiet", "--out"])
            .arg(&out)
            .arg(scenarios().join(format!("section32-{engine}.toml")))
            .args([
                "--set",
                "species[0].count=2000",
                "--set",
                "stop.time=0.06",
                "--set",
                "output.interval=0.01",
                "--set",
                "output.structure_factor_max_index=4",
                "--set",
                "output.density_map=[8, 4]",
                "--set",
                "output.observable_times=[0.02, 0.04, 0.06]",
                "--set",
                "dsmc.cell_size=0.1",
            ])
            .status()
            .expect("runs");
        assert!(status.success(), "{engine} run failed");
        let shape = |file: &str, name: &str| -> Vec<u64> {
            let arrays = read_npz(out.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
            arrays
                .iter()
                .find(|(n, _)| n == name)
                .unwrap_or_else(|| panic!("{file} lacks {name}"))
                .1
                .shape
                .clone()
        };
        // Observations at t = 0, 0.02, 0.04, 0.06: 4 S(k) rows and maps, 3 impact windows.
        assert_eq!(shape("impact_histograms.npz", "counts"), vec![3, 20]);
        assert_eq!(shape("impact_histograms.npz", "edges"), vec![21]);
        assert_eq!(shape("impact_histograms.npz", "t_end"), vec![3]);
        let k = shape("structure_factor.npz", "k")[0];
        assert!(k >= 4, "{k} shells");
        assert_eq!(shape("structure_factor.npz", "s"), vec![4, k]);
        assert_eq!(shape("density_maps.npz", "density"), vec![4, 4, 8]);
        assert_eq!(shape("density_maps.npz", "times"), vec![4]);
        // The windows add up to the run's collisions (all before the last output).
        let arrays = read_npz(out.join("impact_histograms.npz")).unwrap();
        let counts = arrays
            .iter()
            .find(|(n, _)| n == "counts")
            .unwrap()
            .1
            .clone();
        let total: f64 = counts.as_f64().unwrap().iter().sum();
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(
            total as u64,
            summary["collisions"].as_u64().unwrap(),
            "{engine}"
        );
        dirs.push(out);
    }
    let figures = base.join("figures");
    let status = granular()
        .arg("compare")
        .args(&dirs)
        .arg("--out")
        .arg(&figures)
        .status()
        .expect("runs");
    assert!(status.success());
    for f in [
        "energy.png",
        "energy_ratio.png",
        "impact_edmd.png",
        "impact_dsmc.png",
        "structure_factor_edmd.png",
        "structure_factor_dsmc.png",
        "structure_factor_peak.png",
        "density_maps.png",
    ] {
        let p = figures.join(f);
        assert!(
            std::fs::metadata(&p).is_ok_and(|m| m.len() > 1000),
            "{f} missing or empty"
        );
    }
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn bad_observable_keys_name_key_value_and_fix() {
    let out = granular()
        .arg("check")
        .arg(scenarios().join("section32-edmd.toml"))
        .args(["--set", "output.density_map=[64]"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("output.density_map") && err.contains("1 entries") && err.contains("[64, 64]"),
        "{err}"
    );
}
