//! Robustness of the command line: signals, checkpoints that cannot lie, the run
//! directory's lock and safety, and flags out of range.

use super::{granular, scenarios, tmp};
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// A run of a few seconds (4000 disks, 400 collisions per grain) with a checkpoint after
/// every chunk of events.
const LONG: [&str; 6] = [
    "--set",
    "species[0].count=4000",
    "--set",
    "stop.collisions_per_particle=400",
    "--set",
    "output.checkpoint_seconds=1e-9",
];

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn run_long(dir: &Path) -> Command {
    let mut c = granular();
    c.args(["run", "--quiet", "--out"])
        .arg(dir)
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args(LONG);
    c
}

fn resume(dir: &Path) -> Output {
    granular()
        .args(["resume", "--quiet"])
        .arg(dir)
        .output()
        .unwrap()
}

/// Starts the long run in `dir`, sends `signal` (`INT`, `TERM`) after its first
/// checkpoint, and returns how it ended.
fn interrupted(dir: &Path, signal: &str) -> Output {
    let child = run_long(dir)
        .stderr(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("checkpoint.msgpack");
    let start = std::time::Instant::now();
    while !checkpoint.is_file() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    let killed = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(killed.success());
    child.wait_with_output().unwrap()
}

/// The numbers of `summary.json` that do not depend on timing.
fn numbers(dir: &Path) -> serde_json::Value {
    let mut s = super::summary_of(dir);
    let o = s.as_object_mut().unwrap();
    for k in [
        "wall_seconds",
        "events_per_second",
        "collisions_per_second",
        "warnings",
    ] {
        o.remove(k);
    }
    s
}

#[test]
fn sigint_and_sigterm_checkpoint_and_resume_bit_for_bit() {
    let reference = tmp("signal-reference");
    let out = run_long(&reference).output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let series = std::fs::read(reference.join("timeseries.csv")).unwrap();
    for (signal, status) in [("INT", 130), ("TERM", 143)] {
        let dir = tmp(&format!("signal-{signal}"));
        let out = interrupted(&dir, signal);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(status), "{signal}: {err}");
        assert!(
            err.contains("interrupted at t = ")
                && err.contains(&format!("granular resume {}", dir.display())),
            "{err}"
        );
        assert!(dir.join("checkpoint.msgpack").is_file());
        assert!(!dir.join(".lock").exists() && !dir.join("summary.json").exists());
        let log = std::fs::read_to_string(dir.join("log.txt")).unwrap();
        assert!(log.contains("interrupted at t = "), "{log}");
        let out = resume(&dir);
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(numbers(&dir), numbers(&reference), "{signal}");
        assert!(
            std::fs::read(dir.join("timeseries.csv")).unwrap() == series,
            "{signal}: timeseries.csv differs"
        );
    }
}

#[test]
fn damaged_checkpoints_edited_scenarios_and_failed_writes_are_named() {
    let dir = tmp("damaged");
    let out = interrupted(&dir, "INT");
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    let path = dir.join("checkpoint.msgpack");
    let good = std::fs::read(&path).unwrap();
    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x10;
    let cases: [(Vec<u8>, &str); 4] = [
        (flipped, "is corrupt"),
        (good[..good.len() / 3].to_vec(), "is truncated"),
        (
            b"not a checkpoint\n".to_vec(),
            "is not a granular checkpoint",
        ),
        (
            [&good[..8], &[7, 0, 0, 0], &good[12..]].concat(),
            "format 7",
        ),
    ];
    for (bytes, what) in cases {
        std::fs::write(&path, bytes).unwrap();
        let err = stderr(&resume(&dir));
        assert!(
            err.contains(what) && err.contains("checkpoint.msgpack"),
            "{what}: {err}"
        );
    }
    std::fs::write(&path, &good).unwrap();
    // An edited scenario.toml is refused, naming the file and the way out.
    let scenario = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&scenario).unwrap();
    std::fs::write(&scenario, text.replace("seed = 1", "seed = 2")).unwrap();
    let out = resume(&dir);
    let err = stderr(&out);
    assert!(
        !out.status.success()
            && err.contains("scenario.toml was edited")
            && err.contains("NEW_DIR"),
        "{err}"
    );
    std::fs::write(&scenario, &text).unwrap();
    // A failed checkpoint write (the temporary file's place is taken): the previous
    // checkpoint stays, no temporary file is left, and the message says how to go on.
    let tmp_path = dir.join("checkpoint.msgpack.tmp");
    std::fs::create_dir(&tmp_path).unwrap();
    std::fs::write(tmp_path.join("occupied"), b"x").unwrap();
    let out = resume(&dir);
    let err = stderr(&out);
    assert!(
        !out.status.success()
            && err.contains("could not write the checkpoint")
            && err.contains("previous checkpoint is intact")
            && err.contains(&format!("granular resume {}", dir.display())),
        "{err}"
    );
    assert!(path.is_file() && !dir.join(".lock").exists());
    std::fs::remove_dir_all(&tmp_path).unwrap();
    let out = resume(&dir);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!path.exists() && !tmp_path.exists());
}

#[test]
fn resume_of_a_finished_or_missing_run_says_so() {
    let dir = tmp("finished");
    let out = granular()
        .args(["run", "--quiet", "--out"])
        .arg(&dir)
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args([
            "--set",
            "species[0].count=200",
            "--set",
            "stop.collisions_per_particle=5",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&resume(&dir));
    assert!(
        err.contains("the run is finished") && err.contains("--replace"),
        "{err}"
    );
    let err = stderr(&resume(&tmp("never-made")));
    assert!(err.contains("no such directory"), "{err}");
}

#[test]
fn the_run_directory_is_locked_and_never_foreign() {
    let scenario = scenarios().join("maxwell-boltzmann.toml");
    let quick = [
        "--set",
        "species[0].count=200",
        "--set",
        "stop.collisions_per_particle=5",
    ];
    let run = |dir: &Path, extra: &[&str]| {
        granular()
            .args(["run", "--quiet", "--out"])
            .arg(dir)
            .arg(&scenario)
            .args(quick)
            .args(extra)
            .output()
            .unwrap()
    };
    // A directory with other files, and the root, are refused before anything is written.
    let foreign = tmp("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    for dir in [foreign.as_path(), Path::new("/")] {
        let out = run(dir, &[]);
        let err = stderr(&out);
        assert!(
            out.status.code() == Some(2) && err.contains("neither empty nor a run directory"),
            "{err}"
        );
    }
    assert_eq!(std::fs::read_dir(&foreign).unwrap().count(), 1);
    // An earlier run is replaced only with --replace.
    let dir = tmp("replace");
    assert!(run(&dir, &[]).status.success());
    let err = stderr(&run(&dir, &[]));
    assert!(
        err.contains("holds a finished run") && err.contains("--replace"),
        "{err}"
    );
    assert!(run(&dir, &["--replace"]).status.success());
    // A live lock (held by this test's own process) refuses run and resume; the message
    // names its process.
    std::fs::write(dir.join(".lock"), format!("{}\n", std::process::id())).unwrap();
    let held = std::fs::File::open(dir.join(".lock")).unwrap();
    held.try_lock().unwrap();
    let out = run(&dir, &["--replace"]);
    let err = stderr(&out);
    assert!(
        !out.status.success()
            && err.contains("is in use")
            && err.contains(&std::process::id().to_string()),
        "{err}"
    );
    std::fs::write(dir.join("checkpoint.msgpack"), b"x").unwrap();
    let err = stderr(&resume(&dir));
    assert!(err.contains("is in use"), "{err}");
    std::fs::remove_file(dir.join("checkpoint.msgpack")).unwrap();
    drop(held);
    // A stale lock (its process is gone, so nothing holds it) is taken over and logged.
    std::fs::write(dir.join(".lock"), "4294967\n").unwrap();
    let out = run(&dir, &["--replace"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = std::fs::read_to_string(dir.join("log.txt")).unwrap();
    assert!(
        log.contains("stale lock") && log.contains("4294967"),
        "{log}"
    );
    assert!(!dir.join(".lock").exists());
}

/// A run killed with `kill -9` leaves its lock file behind: `resume` takes it over (the
/// system lock died with the process), says so in the log, and finishes the run as if it
/// had not been killed.
#[test]
fn a_lock_left_by_a_killed_run_is_taken_over_by_resume() {
    let dir = tmp("killed-lock");
    let mut child = run_long(&dir)
        .stderr(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("checkpoint.msgpack");
    let start = std::time::Instant::now();
    while !checkpoint.is_file() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let left = std::fs::read_to_string(dir.join(".lock")).unwrap();
    assert_eq!(left.trim(), child.id().to_string());
    let out = resume(&dir);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = std::fs::read_to_string(dir.join("log.txt")).unwrap();
    assert!(
        log.contains("stale lock") && log.contains(&format!("process {}", child.id())),
        "{log}"
    );
    assert!(!dir.join(".lock").exists() && dir.join("summary.json").is_file());
}

#[test]
fn seeds_cover_the_whole_u64_and_nothing_else() {
    let dir = tmp("seed-max");
    let out = granular()
        .args(["run", "--quiet", "--seed", "18446744073709551615", "--out"])
        .arg(&dir)
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args([
            "--set",
            "species[0].count=200",
            "--set",
            "stop.collisions_per_particle=5",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(super::summary_of(&dir)["seed"], u64::MAX);
    let check = granular()
        .arg("check")
        .arg(dir.join("scenario.toml"))
        .output()
        .unwrap();
    assert!(check.status.success(), "{}", stderr(&check));
    for bad in ["-1", "18446744073709551616", "1.5"] {
        let out = granular()
            .args(["run", "--seed", bad])
            .arg(scenarios().join("maxwell-boltzmann.toml"))
            .output()
            .unwrap();
        let err = stderr(&out);
        assert!(
            out.status.code() == Some(2)
                && err.contains("--seed")
                && err.contains("from 0 to 18446744073709551615"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn thread_counts_and_bench_sizes_are_checked() {
    let sweep = granular()
        .args(["sweep", "--threads", "0"])
        .arg(scenarios().join("problem3-cooling.toml"))
        .output()
        .unwrap();
    let err = stderr(&sweep);
    assert!(
        err.contains("--threads 0") && err.contains("at least 1"),
        "{err}"
    );
    let reproduce = granular()
        .args(["reproduce", "fig3", "--threads", "0", "--out"])
        .arg(tmp("reproduce-threads"))
        .output()
        .unwrap();
    assert!(
        stderr(&reproduce).contains("--threads 0"),
        "{}",
        stderr(&reproduce)
    );
    let cases: [(&[&str], &str); 9] = [
        (&["--n", "0"], "at least 16"),
        (&["--n", "1"], "at least 16"),
        (&["--n", "1e12"], "GB of memory"),
        (&["--n", "1000000000000"], "GB of memory"),
        (&["--n", "many"], "whole number"),
        (&["--packing-fraction", "0"], "(0, 0.78]"),
        (&["--packing-fraction", "0.95"], "(0, 0.78]"),
        (&["--packing-fraction", "1.5"], "(0, 0.78]"),
        (&["--packing-fraction", "NaN"], "(0, 0.78]"),
    ];
    for (args, what) in cases {
        let out = granular()
            .args(["bench", "edmd"])
            .args(args)
            .output()
            .unwrap();
        let err = stderr(&out);
        assert!(
            out.status.code() == Some(2) && err.contains(args[0]) && err.contains(what),
            "{args:?}: {err}"
        );
    }
    let out = granular()
        .args([
            "bench",
            "edmd",
            "--dimension",
            "3",
            "--packing-fraction",
            "0.6",
        ])
        .output()
        .unwrap();
    assert!(stderr(&out).contains("(0, 0.52]"), "{}", stderr(&out));
}

/// A full disk, where this test may mount a small tmpfs (as root): the checkpoint write
/// fails, the previous checkpoint stays intact, no temporary file is left, and the message
/// says to free space and resume. Elsewhere the failed write is simulated
/// (`damaged_checkpoints_edited_scenarios_and_failed_writes_are_named`).
#[test]
fn a_full_disk_keeps_the_previous_checkpoint() {
    let source = tmp("full-disk-source");
    let child = granular()
        .args(["run", "--quiet", "--out"])
        .arg(&source)
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .args(LONG)
        .args(["--set", "output.snapshot_every=1000000"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = source.join("checkpoint.msgpack");
    let start = std::time::Instant::now();
    while !checkpoint.is_file() && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(200));
    let _ = Command::new("kill")
        .arg("-INT")
        .arg(child.id().to_string())
        .status();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    let good = std::fs::read(&checkpoint).unwrap();
    let files: Vec<_> = std::fs::read_dir(&source)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    let used: u64 = files
        .iter()
        .map(|p| std::fs::metadata(p).unwrap().len().div_ceil(4096) * 4096)
        .sum();
    // Room for the run's files and half a checkpoint more.
    let size = used + 4096 * 8 + good.len() as u64 / 2;
    let disk = tmp("full-disk");
    std::fs::create_dir_all(&disk).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
        .arg(&disk)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("no tmpfs can be mounted here: the simulated write failure covers this");
        return;
    }
    let dir = disk.join("run");
    std::fs::create_dir_all(dir.join("snapshots")).unwrap();
    for f in &files {
        std::fs::copy(f, dir.join(f.file_name().unwrap())).unwrap();
    }
    for e in std::fs::read_dir(source.join("snapshots")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join("snapshots").join(p.file_name().unwrap())).unwrap();
    }
    let out = resume(&dir);
    let err = stderr(&out);
    let kept = std::fs::read(dir.join("checkpoint.msgpack")).ok();
    let tmp_left = dir.join("checkpoint.msgpack.tmp").exists();
    let _ = Command::new("umount").arg(&disk).status();
    assert!(
        out.status.code() == Some(2)
            && err.contains("No space left on device")
            && err.contains("previous checkpoint is intact")
            && err.contains("Free space")
            && err.contains(&format!("granular resume {}", dir.display())),
        "{err}"
    );
    assert!(
        kept.as_deref() == Some(&good[..]),
        "the previous checkpoint changed"
    );
    assert!(!tmp_left, "checkpoint.msgpack.tmp left behind");
}

/// A tabulated bath file spanning ±1e300 (issue 24: a panic in the histogram code) is an
/// error of `intruder.bath` that names the point and the fix, from `check` and `run`.
#[test]
fn a_tabulated_bath_file_out_of_range_is_named() {
    let dir = tmp("bath-range");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("bath.txt"),
        "# v f\n-1e300 1.0\n0.0 2.0\n1e300 1.0\n",
    )
    .unwrap();
    let scenario = dir.join("wide.toml");
    std::fs::write(
        &scenario,
        "engine = \"intruder\"\n[intruder]\nmodel = \"1d\"\nmass = 1.0\nrestitution = 0.5\n\
         bath = { kind = \"tabulated\", file = \"bath.txt\" }\n[stop]\ncollisions = 1000\n\
         [output]\ninterval = 100.0\n",
    )
    .unwrap();
    for args in [&["check"][..], &["run", "--quiet", "--out"][..]] {
        let mut c = granular();
        c.args(args);
        if args[0] == "run" {
            c.arg(dir.join("run"));
        }
        let out = c.arg(&scenario).output().unwrap();
        let err = stderr(&out);
        assert!(
            out.status.code() == Some(2)
                && err.contains("intruder.bath")
                && err.contains("-1e300")
                && err.contains("rescale the table"),
            "{args:?}: {err}"
        );
    }
}

/// A text file that is not a table, given as a tabulated bath (issue 37), is refused by
/// `check` and `run` naming `intruder.bath.file`, the file, its line and its column, for the
/// 1D intruder (a velocity table) and the disk (a speed table).
#[test]
fn a_text_file_given_as_a_bath_names_file_line_and_column() {
    let dir = tmp("bath-text");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("notes.md"),
        "# Bath measured on 3 March\n\n0.0 1.0\nthe second run was noisy\n",
    )
    .unwrap();
    for (model, top) in [("1d", ""), ("disk", "dimension = 2\n")] {
        let scenario = dir.join(format!("{model}.toml"));
        std::fs::write(
            &scenario,
            format!(
                "engine = \"intruder\"\n{top}[intruder]\nmodel = \"{model}\"\nmass = 1.0\nrestitution = 0.5\n\
                 bath = {{ kind = \"tabulated\", file = \"notes.md\" }}\n[stop]\ncollisions = 1000\n\
                 [output]\ninterval = 100.0\n"
            ),
        )
        .unwrap();
        for args in [&["check"][..], &["run", "--quiet", "--out"][..]] {
            let mut c = granular();
            c.args(args);
            if args[0] == "run" {
                c.arg(dir.join(format!("run-{model}")));
            }
            let out = c.arg(&scenario).output().unwrap();
            let err = stderr(&out);
            assert!(
                out.status.code() == Some(2)
                    && err.contains("intruder.bath")
                    && err.contains("notes.md")
                    && err.contains("line 4")
                    && err.contains("column 1")
                    && err.contains("`the` is not a number"),
                "{model} {args:?}: {err}"
            );
        }
    }
}

/// `check` prints the pre-flight estimate; a run above a cost limit is refused naming
/// the key and `--insist`, which lets `check` accept it.
#[test]
fn check_prints_the_estimate_and_insist_lifts_the_limits() {
    let scenario = scenarios().join("dsmc-cooling.toml");
    let out = granular().arg("check").arg(&scenario).output().unwrap();
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("estimate: stops by stop.collisions_per_particle")
            && err.contains("outputs")
            && err.contains("written")
            && err.contains("time steps"),
        "{err}"
    );
    // The values left to the engine, as comments after the resolved scenario.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("# dsmc.time_step (initial") && stdout.contains("# dsmc.cell_size"),
        "{stdout}"
    );
    let one_d = granular()
        .arg("check")
        .arg(scenarios().join("intruder-1d.toml"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&one_d.stdout);
    for key in ["sample_interval", "transient", "histogram_max"] {
        assert!(stdout.contains(&format!("# intruder.{key} = ")), "{stdout}");
    }
    let tiny = ["--set", "output.interval=1e-9"];
    let out = granular()
        .arg("check")
        .arg(&scenario)
        .args(tiny)
        .output()
        .unwrap();
    let err = stderr(&out);
    assert!(
        out.status.code() == Some(2) && err.contains("output.interval") && err.contains("--insist"),
        "{err}"
    );
    let out = granular()
        .arg("check")
        .arg(&scenario)
        .args(tiny)
        .arg("--insist")
        .output()
        .unwrap();
    let err = stderr(&out);
    assert!(
        out.status.success() && err.contains("above the limits, accepted by --insist"),
        "{err}"
    );
    // The cooling gas to 250 collisions per grain warns and proposes log spacing.
    let out = granular()
        .arg("check")
        .arg(&scenario)
        .args(["--set", "stop.collisions_per_particle=250"])
        .output()
        .unwrap();
    let err = stderr(&out);
    assert!(
        out.status.success() && err.contains("warning:") && err.contains("output.spacing"),
        "{err}"
    );
}

/// A cooling gas of 200 disks with the TC model (`contact_duration`), stopped when half its
/// energy is gone (a few collisions per grain), swept over `stop.time`. With the TC model
/// the estimate does not use Haff's law, and `stop.energy_fraction` gives no lower bound
/// on the end time, so the estimate takes `stop.time` as the end: at `1e13` about 10^16
/// collisions, above the limit of 10^12, although the energy rule ends the run early.
const SWEEP_OVER_A_LIMIT: &str = r#"engine = "edmd"
dimension = 2
seed = 7
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = 200
radius = 0.01
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[collisions]
restitution = 0.8
contact_duration = 1e-6
[stop]
time = 10.0
energy_fraction = 0.5
[output]
interval = 0.01
[sweep]
key = "stop.time"
values = [10.0, 1e13]
seeds = 1
observable = "temperature"
"#;

/// `granular sweep`: a point above a cost limit is refused before anything runs, naming
/// the point, the key and `--insist`; with `--insist` every point runs (and stops by its
/// energy rule, far below the estimate).
#[test]
fn sweep_refuses_a_point_above_the_limits_unless_insist() {
    let dir = tmp("sweep-insist");
    std::fs::create_dir_all(&dir).unwrap();
    let scenario = dir.join("sweep.toml");
    std::fs::write(&scenario, SWEEP_OVER_A_LIMIT).unwrap();
    let sweep = |out: &str, extra: &[&str]| {
        granular()
            .arg("sweep")
            .arg(&scenario)
            .arg("--out")
            .arg(dir.join(out))
            .args(["--threads", "1"])
            .args(extra)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("GRANULAR_SHARD")
            .output()
            .unwrap()
    };
    for (out, extra) in [("refused", &[][..]), ("shard", &["--shard", "2/2"][..])] {
        let refused = sweep(out, extra);
        let err = stderr(&refused);
        assert!(
            refused.status.code() == Some(2)
                && err.contains("sweep.values[1]")
                && err.contains(
                    "stop.time = 10000000000000.0 gives an invalid scenario: `stop.time`"
                )
                && err.contains("pair collisions")
                && err.contains("--insist"),
            "{extra:?}: {err}"
        );
        assert!(
            !dir.join(out).join("point_000").exists(),
            "{extra:?}: nothing runs"
        );
    }
    let ran = sweep("insisted", &["--insist"]);
    let err = stderr(&ran);
    assert!(ran.status.success(), "{err}");
    for p in ["point_000", "point_001"] {
        let summary =
            std::fs::read_to_string(dir.join("insisted").join(p).join("seed_000/summary.json"))
                .unwrap();
        let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
        assert_eq!(summary["stop_reason"], "energy_fraction", "{p}: {summary}");
    }
    // The sharded sweep takes --insist too, and `merge` reads its members.
    for i in ["1/2", "2/2"] {
        let shard = sweep("sharded", &["--insist", "--shard", i]);
        assert!(shard.status.success(), "{i}: {}", stderr(&shard));
    }
    let merged = granular()
        .arg("merge")
        .arg(dir.join("sharded"))
        .output()
        .unwrap();
    assert!(merged.status.success(), "{}", stderr(&merged));
    assert_eq!(
        std::fs::read(dir.join("sharded/sweep.csv")).unwrap(),
        std::fs::read(dir.join("insisted/sweep.csv")).unwrap()
    );
}

/// Words of Rust, not of the command line or the scenario: type names, serde's and the
/// standard library's phrases. No error message may contain one (issue 37).
const RUST_JARGON: [&str; 16] = [
    "usize",
    "u64",
    "u32",
    "u8",
    "i64",
    "i128",
    "f64",
    "f32",
    "struct ",
    "enum ",
    "RawVelocity",
    "`scenario`",
    "invalid digit",
    "any valid TOML value",
    "Option<",
    "Vec<",
];

/// The first Rust word in `message` (as a whole word: `u64` but not `mu64x`).
fn rust_jargon(message: &str) -> Option<&'static str> {
    RUST_JARGON.iter().copied().find(|w| {
        message.match_indices(w).any(|(i, _)| {
            let before = message[..i].chars().next_back();
            let after = message[i + w.len()..].chars().next();
            let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
            !word(before) && (w.ends_with(' ') || !word(after))
        })
    })
}

/// The corpus of bad command lines (`tests/bad_command_lines/cases.txt`): each exits with
/// status 2, shows its expected text and speaks no Rust ([`RUST_JARGON`]).
#[test]
fn every_bad_command_line_fails_with_its_expected_text() {
    let cases = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_command_lines/cases.txt"),
    )
    .unwrap();
    let mut failures = Vec::new();
    let mut n = 0;
    for line in cases
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let (args, expect) = line.split_once(" => ").expect("ARGUMENTS => EXPECTED");
        let dir = tmp("bad-command");
        let args: Vec<String> = args
            .split(' ')
            .map(|a| {
                a.replace("{scenarios}", &scenarios().to_string_lossy())
                    .replace("{tmp}", &dir.to_string_lossy())
            })
            .collect();
        let out = granular().args(&args).output().unwrap();
        let err = stderr(&out);
        if out.status.code() != Some(2) || !err.contains(expect) {
            failures.push(format!("{line}\n  status {:?}: {err}", out.status.code()));
        }
        if let Some(word) = rust_jargon(&err) {
            failures.push(format!("{line}\n  speaks Rust (`{word}`): {err}"));
        }
        n += 1;
    }
    assert!(n >= 20, "{n} cases");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A DSMC run whose grains would not fit in this machine's memory is refused before any
/// grain is created (9 x 10^8 grains need about 150 GB; fewer than 10^9 so that its two
/// snapshots stay below the 100 GB limit on bytes written, which is checked first), naming
/// the key, the estimate, the memory of this node, the ranks and nodes that would fit, and
/// `--insist`.
#[test]
fn dsmc_run_above_the_memory_is_refused_naming_the_ranks_that_fit() {
    let dir = tmp("dsmc-memory");
    let out = granular()
        .args(["run", "--quiet", "--out"])
        .arg(dir.join("run"))
        .arg(scenarios().join("dsmc-cooling.toml"))
        .args(["--set", "species[0].count=900000000"])
        .args(["--set", "stop.time=1e-9"])
        .output()
        .unwrap();
    // The message as one line (the terminal report may wrap it).
    let err = stderr(&out)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    for fragment in [
        "species[0].count",
        "the run holds all 9e8 grains",
        "bytes per grain",
        "GiB are available to each of the 1 ranks on this node",
        "run on at least",
        "nodes), or lower species[0].count",
        "--insist",
    ] {
        assert!(err.contains(fragment), "no {fragment:?} in: {err}");
    }
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(!dir.join("run/summary.json").exists());
}
