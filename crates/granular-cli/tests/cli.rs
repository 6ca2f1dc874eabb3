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
