//! `granular sweep --shard I/N` (and a Slurm job array's environment) and `granular merge`:
//! shards merged give the unsharded table; bad shards and missing members are named.

use super::{granular, scenarios, tmp};
use std::path::Path;
use std::process::Output;

/// The 1D intruder with a two-key grid: eight members of 20 000 collisions.
fn scenario(dir: &Path) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let text = std::fs::read_to_string(scenarios().join("intruder-1d.toml")).unwrap()
        + "\n[sweep]\nseeds = 2\nobservable = \"temperature_ratio\"\n\
           [[sweep.vary]]\nkey = \"intruder.restitution\"\nvalues = [0.2, 0.8]\n\
           [[sweep.vary]]\nkey = \"stop.collisions\"\nvalues = [20000, 30000]\n";
    let path = dir.join("grid.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn sweep(scenario: &Path, out: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    granular()
        .arg("sweep")
        .arg(scenario)
        .arg("--out")
        .arg(out)
        .args(args)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("GRANULAR_SHARD")
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

fn ok(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    err
}

fn fails(out: &Output) -> String {
    assert!(!out.status.success(), "expected a failure");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn shards_and_slurm_tasks_merge_to_the_unsharded_table() {
    let dir = tmp("shards");
    let sc = scenario(&dir);
    let whole = sweep(&sc, &dir.join("all"), &[], &[]);
    ok(&whole);
    let stdout = String::from_utf8_lossy(&whole.stdout);
    assert!(
        stdout.starts_with("intruder.restitution,stop.collisions,temperature_ratio_mean,"),
        "{stdout}"
    );
    // Three shards by flag.
    let three = dir.join("three");
    for i in 1..=3 {
        let err = ok(&sweep(&sc, &three, &["--shard", &format!("{i}/3")], &[]));
        assert!(err.contains("granular merge"), "{err}");
    }
    // Two shards as the tasks of a Slurm job array --array=1-2.
    let two = dir.join("two");
    for task in ["1", "2"] {
        let env = [
            ("SLURM_ARRAY_TASK_ID", task),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ];
        let err = ok(&sweep(&sc, &two, &[], &env));
        assert!(err.contains("from SLURM_ARRAY_TASK_ID"), "{err}");
    }
    assert!(!three.join("sweep.csv").exists() && !two.join("sweep.csv").exists());
    for d in [&three, &two] {
        ok(&granular().arg("merge").arg(d).output().unwrap());
    }
    let table = |d: &Path| std::fs::read(d.join("sweep.csv")).unwrap();
    let meta = |d: &Path| std::fs::read(d.join("sweep.json")).unwrap();
    let all = dir.join("all");
    assert!(table(&all) == table(&three) && table(&all) == table(&two));
    assert!(meta(&all) == meta(&three) && meta(&all) == meta(&two));
    // `plot` reads the merged table.
    ok(&granular().arg("plot").arg(&two).output().unwrap());
    assert!(two.join("figures/sweep_temperature_ratio.png").is_file());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_shards_and_missing_members_are_named() {
    let dir = tmp("bad-shards");
    let sc = scenario(&dir);
    let out = dir.join("out");
    for (bad, why) in [
        ("0/3", "shard 0 of 3 does not exist"),
        ("4/3", "shards are numbered 1 to 3"),
        ("a/b", "\"a\" is not a whole number"),
        ("2", "no '/'"),
    ] {
        let err = fails(&sweep(&sc, &out, &["--shard", bad], &[]));
        assert!(err.contains("--shard") && err.contains(why), "{bad}: {err}");
    }
    let slurm = [
        ("SLURM_ARRAY_TASK_ID", "5"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
    ];
    let err = fails(&sweep(&sc, &out, &[], &slurm));
    assert!(
        err.contains("SLURM_ARRAY_TASK_ID=5") && err.contains("--shard"),
        "{err}"
    );
    let err = fails(&sweep(&sc, &out, &[], &[("GRANULAR_SHARD", "3/2")]));
    assert!(err.contains("GRANULAR_SHARD=3/2"), "{err}");
    // One shard of three, then a merge: the other members are listed by name.
    ok(&sweep(&sc, &out, &["--shard", "1/3"], &[]));
    let err = fails(&granular().arg("merge").arg(&out).output().unwrap());
    assert!(
        err.contains("5 of 8 members have not finished")
            && err.contains("point_000/seed_001 (not started)")
            && err.contains("--allow-missing"),
        "{err}"
    );
    assert!(!out.join("sweep.csv").exists());
    let partial = granular()
        .args(["merge", "--allow-missing"])
        .arg(&out)
        .output()
        .unwrap();
    let err = ok(&partial);
    assert!(
        err.contains("5 members missing") && err.contains("point_003/seed_001"),
        "{err}"
    );
    let json = std::fs::read_to_string(out.join("sweep.json")).unwrap();
    assert!(json.contains("\"missing\"") && json.contains("point_002/seed_001 (not started)"));
    let err = fails(&granular().arg("merge").arg(&dir).output().unwrap());
    assert!(err.contains("not a sweep directory"), "{err}");
    let _ = std::fs::remove_dir_all(dir);
}
