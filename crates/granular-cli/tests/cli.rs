//! The `granular` binary end to end: run, check, resume and bench, and the errors users see.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "cli/report.rs"]
mod report;
#[path = "cli/robust.rs"]
mod robust;
#[path = "cli/scaling.rs"]
mod scaling;
#[path = "cli/shards.rs"]
mod shards;
#[path = "cli/theory.rs"]
mod theory;

fn granular() -> Command {
    Command::new(env!("CARGO_BIN_EXE_granular"))
}

fn scenarios() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenarios")
}

/// Runs `granular check SCENARIO ARGS...`: its exit status and standard error.
fn check(scenario: &std::path::Path, args: &[&str]) -> (std::process::ExitStatus, String) {
    let out = granular()
        .arg("check")
        .arg(scenario)
        .args(args)
        .output()
        .unwrap();
    (
        out.status,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
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
    let (status, err) = check(
        &scenarios().join("maxwell-boltzmann.toml"),
        &["--set", "collisions.restitution=1.2"],
    );
    assert!(!status.success());
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
    let (status, err) = check(&bad, &[]);
    assert!(
        !status.success() && err.contains("restitushun") && err.contains("line "),
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

/// `granular bench edmd` on a small 2D case with `extra` options: its output.
fn bench_edmd(n: &str, phi: &str, extra: &[&str]) -> std::process::Output {
    granular()
        .args(["bench", "edmd", "--dimension", "2", "--n", n])
        .args(["--packing-fraction", phi, "--collisions-per-particle", "5"])
        .arg("--json")
        .args(extra)
        .output()
        .unwrap()
}

/// The one JSON object of a successful `bench edmd`.
fn bench_json(out: &std::process::Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim()).unwrap()
}

#[test]
fn bench_prints_one_json_object_per_case() {
    let v = bench_json(&bench_edmd("2000", "0.5", &[]));
    for key in [
        "dimension",
        "n",
        "packing_fraction",
        "collisions_per_second",
        "bytes_per_particle",
        "walls",
        "restitution",
        "size_ratio",
        "mass_ratio",
        "gravity",
    ] {
        assert!(v.get(key).is_some(), "{key} missing in {v}");
    }
}

#[test]
fn bench_runs_the_general_cases_and_refuses_bad_ones() {
    let general = [
        "--walls",
        "--restitution",
        "0.8",
        "--size-ratio",
        "1.4",
        "--mass-ratio",
        "3",
        "--gravity",
        "0.1",
    ];
    let v = bench_json(&bench_edmd("1000", "0.7", &general));
    assert_eq!(v["walls"], true);
    assert_eq!(v["restitution"], 0.8);
    assert_eq!(v["size_ratio"], 1.4);
    assert_eq!(v["mass_ratio"], 3.0);
    assert_eq!(v["gravity"], 0.1);
    for (flag, value) in [
        ("--restitution", "1.5"),
        ("--size-ratio", "0"),
        ("--mass-ratio", "0"),
        ("--gravity", "0.5"),
    ] {
        let out = bench_edmd("1000", "0.7", &[flag, value]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(flag) && err.contains(value), "{err}");
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
            ])
            // `[dsmc]` is an error in an event-driven scenario.
            .args(if engine == "dsmc" {
                &["--set", "dsmc.cell_size=0.1"][..]
            } else {
                &[][..]
            })
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
    let (status, err) = check(
        &scenarios().join("section32-edmd.toml"),
        &["--set", "output.density_map=[64]"],
    );
    assert!(!status.success());
    assert!(
        err.contains("output.density_map") && err.contains("1 entries") && err.contains("[64, 64]"),
        "{err}"
    );
}
fn summary_of(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// `granular run scenarios/intruder-1d.toml` at the paper's statistics (5e5 collisions,
/// well under a second): the run directory, the summary keys, and T/T_B against
/// Martin-Piasecki (G-18) within 4 of the run's own batch-means errors.
#[test]
fn intruder_run_checks_eq_18() {
    let out = tmp("intruder-1d");
    let status = granular()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(scenarios().join("intruder-1d.toml"))
        .status()
        .unwrap();
    assert!(status.success());
    for f in [
        "scenario.toml",
        "summary.json",
        "timeseries.csv",
        "intruder_histograms.csv",
        "intruder_histograms.npz",
        "log.txt",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let s = summary_of(&out);
    assert_eq!(s["engine"], "intruder");
    assert_eq!(s["stop_reason"], "collisions");
    let b = &s["intruder"];
    for key in [
        "model",
        "samples",
        "temperature",
        "temperature_error",
        "temperature_ratio",
        "temperature_ratio_error",
        "kurtosis",
        "kurtosis_error",
        "theory_temperature_ratio",
        "temperature_ratio_z",
    ] {
        assert!(
            b.get(key).is_some(),
            "summary.json intruder block lacks {key}"
        );
    }
    for key in [
        "temperature_ratio",
        "temperature_ratio_error",
        "martin_piasecki_ratio",
    ] {
        assert!(s["final"].get(key).is_some(), "final lacks {key}");
    }
    let (alpha, mass) = (0.5, 1.0);
    let eq18 = (1.0 + alpha) / (2.0 + (1.0 - alpha) / mass);
    let r = b["temperature_ratio"].as_f64().unwrap();
    let e = b["temperature_ratio_error"].as_f64().unwrap();
    assert!(e > 0.0 && e < 0.01, "error {e}");
    assert!(
        (r - eq18).abs() <= 4.0 * e,
        "T/T_B = {r} ± {e}, Eq. 18 = {eq18}"
    );
    assert_eq!(b["theory_temperature_ratio"].as_f64().unwrap(), eq18);
    assert_eq!(s["dimension"], 1, "the 1D intruder moves in one dimension");
    // The histogram on the time grid holds every grid sample (within its range).
    let csv = std::fs::read_to_string(out.join("intruder_histograms.csv")).unwrap();
    let counted: u64 = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse::<u64>().unwrap())
        .sum();
    let samples = b["samples"].as_u64().unwrap();
    assert!(counted <= samples && counted as f64 > 0.999 * samples as f64);
    let plot = granular().arg("plot").arg(&out).output().unwrap();
    assert!(
        plot.status.success(),
        "{}",
        String::from_utf8_lossy(&plot.stderr)
    );
    assert!(out.join("figures/histogram_velocity.png").is_file());
    assert!(out.join("figures/running_averages.png").is_file());
}

#[test]
fn intruder_needle_run_writes_its_observables() {
    let out = tmp("intruder-needle");
    let status = granular()
        .args(["run", "--quiet", "--out"])
        .arg(&out)
        .arg(scenarios().join("intruder-needle.toml"))
        .args([
            "--set",
            "stop.collisions=100000",
            "--set",
            "output.interval=500",
        ])
        .status()
        .unwrap();
    assert!(status.success());
    let b = &summary_of(&out)["intruder"];
    for key in [
        "translational_temperature_ratio",
        "translational_temperature_ratio_error",
        "rotational_temperature_ratio",
        "rotational_temperature_ratio_error",
        "correlation_r",
        "correlation_r_error",
    ] {
        assert!(b[key].as_f64().is_some_and(f64::is_finite), "{key}: {b}");
    }
    let csv = std::fs::read_to_string(out.join("intruder_histograms.csv")).unwrap();
    assert!(csv.contains("\nangular_velocity,") && csv.contains("\nvelocity_component,"));
}

#[test]
fn check_reports_bad_intruder_fields() {
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &["--set", "intruder.restitution=1.5"],
            &["intruder.restitution", "1.5", "[0, 1]"],
        ),
        (
            &["--set", "intruder.bath_density=0"],
            &["intruder.bath_density", "is 0", "positive"],
        ),
        (
            &["--set", "intruder.model=\"rod\""],
            &["intruder.model", "\"rod\"", "\"needle\""],
        ),
    ];
    for (args, wanted) in cases {
        let (status, err) = check(&scenarios().join("intruder-1d.toml"), args);
        assert_eq!(status.code(), Some(2));
        for w in wanted {
            assert!(err.contains(w), "{args:?}: `{w}` not in: {err}");
        }
    }
    // An unknown key in the file: named with its table and line.
    let dir = tmp("intruder-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scenarios().join("intruder-1d.toml"))
        .unwrap()
        .replace("\nmass = 1.0 ", "\nmasss = 1.0 ");
    std::fs::write(dir.join("bad.toml"), text).unwrap();
    let (status, err) = check(&dir.join("bad.toml"), &[]);
    assert!(
        !status.success() && err.contains("intruder.masss") && err.contains("line"),
        "{err}"
    );
}

/// A tabulated bath file is found relative to the scenario file, from any directory.
#[test]
fn intruder_tabulated_bath_file_is_relative_to_the_scenario() {
    let dir = tmp("intruder-tab");
    std::fs::create_dir_all(dir.join("sc")).unwrap();
    std::fs::write(dir.join("sc/bath.dat"), "# v f\n-1 0\n0 1\n1 0\n").unwrap();
    let text = std::fs::read_to_string(scenarios().join("intruder-1d.toml"))
        .unwrap()
        .replace(
            "bath = { kind = \"gaussian\", temperature = 0.5 }",
            "bath = { kind = \"tabulated\", file = \"bath.dat\" }",
        );
    std::fs::write(dir.join("sc/tab.toml"), text).unwrap();
    let out = granular()
        .current_dir(&dir)
        .args(["run", "--quiet", "sc/tab.toml", "--out", "run", "--set"])
        .arg("stop.collisions=20000")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = summary_of(&dir.join("run"));
    // Triangular density on [-1, 1]: <v^2> = 1/6, T_B = m <v^2>.
    assert!((s["intruder"]["bath_temperature"].as_f64().unwrap() - 1.0 / 6.0).abs() < 1e-12);
}

#[test]
fn intruder_sweep_over_restitution() {
    let dir = tmp("intruder-sweep");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scenarios().join("intruder-1d.toml")).unwrap()
        + "\n[sweep]\nkey = \"intruder.restitution\"\nvalues = [0.2, 0.8]\nseeds = 2\nobservable = \"temperature_ratio\"\n";
    std::fs::write(dir.join("sweep.toml"), text).unwrap();
    let out = granular()
        .args(["sweep", "--threads", "100000", "--out"])
        .arg(dir.join("out"))
        .arg(dir.join("sweep.toml"))
        .args(["--set", "stop.collisions=50000"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // More threads than cores are capped, with a note.
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("--threads 100000 capped at"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("intruder.restitution,temperature_ratio_mean"),
        "{stdout}"
    );
    let rows: Vec<f64> = stdout
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(rows.len(), 2);
    assert!(rows[0] < rows[1], "T/T_B grows with alpha: {rows:?}");
    let plot = granular()
        .arg("plot")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(
        plot.status.success(),
        "{}",
        String::from_utf8_lossy(&plot.stderr)
    );
}

/// `granular run --threads`: a DSMC run on one and on two worker threads writes the same
/// time series and summary (but for its wall-clock fields), bit for bit.
#[test]
fn run_threads_do_not_change_the_result() {
    let (a, b) = (tmp("threads-1"), tmp("threads-2"));
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/dsmc-cooling.toml");
    for (dir, threads) in [(&a, "1"), (&b, "2")] {
        let out = granular()
            .args(["run", "--quiet", "--threads", threads, "--out"])
            .arg(dir)
            .arg(&scenario)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let read = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    assert_eq!(read(&a, "timeseries.csv"), read(&b, "timeseries.csv"));
    let summary = |d: &Path| {
        let mut v: serde_json::Value = serde_json::from_str(&read(d, "summary.json")).unwrap();
        for k in ["wall_seconds", "events_per_second", "collisions_per_second"] {
            v.as_object_mut().unwrap().remove(k);
        }
        v
    };
    assert_eq!(summary(&a), summary(&b));
}

/// `granular reproduce fig3 --quick`: PNG, SVG and CSV with the theory column, and the
/// table does not depend on the number of threads.
#[test]
fn reproduce_fig3_quick() {
    let (a, b) = (tmp("reproduce-1"), tmp("reproduce-2"));
    for (dir, threads) in [(&a, "1"), (&b, "2")] {
        let out = granular()
            .args([
                "reproduce",
                "fig3",
                "--quick",
                "--threads",
                threads,
                "--out",
            ])
            .arg(dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        for f in ["fig3.png", "fig3.svg", "fig3.csv"] {
            assert!(dir.join(f).is_file(), "{f} missing");
        }
    }
    let csv = std::fs::read_to_string(a.join("fig3.csv")).unwrap();
    assert_eq!(csv, std::fs::read_to_string(b.join("fig3.csv")).unwrap());
    let header = csv.lines().nth(1).unwrap();
    assert!(
        header.starts_with("alpha,T_over_TB,T_over_TB_error,eq18"),
        "{header}"
    );
    assert_eq!(csv.lines().count(), 2 + 11);
    let png = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(a.join("fig3.png")).unwrap(),
    ));
    assert!(png.read_info().unwrap().info().width >= 1000);
    let bad = granular().args(["reproduce", "fig6"]).output().unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("fig7"));
}
