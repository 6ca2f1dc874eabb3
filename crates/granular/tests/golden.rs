//! The bundled scenarios give the golden outputs bit for bit: every scenario of
//! `scenarios/` that runs in seconds is run to its end, and its run directory is compared
//! with the files in `tests/golden/`:
//!
//! * `NAME.json`: the `summary.json` numbers, less the wall-clock figures and the version
//!   ([`UNSTABLE`]), compared key by key (a key added to the summary fails too);
//! * `NAME.sha256`: the SHA-256 of every other file of the run directory, in the format of
//!   `sha256sum` (`timeseries.csv`, the histograms, `scenario.toml`, ...; the whole bytes),
//!   and of every array of every snapshot (`snapshots/snapshot_NNNNNN.npz:positions.npy`:
//!   the bytes of the `.npy` member as NumPy reads it, header and data, independent of the
//!   zip container's compression). `log.txt` (wall-clock times) is not compared. A file or
//!   array missing or added fails.
//!
//! Shortened with overrides, because a full run takes a minute or more of CPU: the two
//! dilute DSMC steady states, `dsmc-hcs-rescaled` and `dsmc-white-noise`, stop at 30
//! instead of 300 collisions per grain (20 of them after the equilibration). The two
//! scenarios of section 3.2 of Müller & Herrmann's DSMC paper take minutes; they are not here.
//!
//! **Regenerating.** The golden files change only when an issue changes a trajectory or an
//! output on purpose, and then `docs/output.md` says what changed and why (old and new
//! values). Then, and only then:
//!
//! ```text
//! GRANULAR_REGENERATE_GOLDEN=1 cargo test --release -p granular --test physics -- golden
//! ```
//!
//! rewrites every `tests/golden/NAME.json` and `NAME.sha256` from the current code (each
//! test then passes); review `git diff crates/granular/tests/golden` before committing.
//! History: the summaries were those of b73b734 until d3439e0, with the regenerations
//! documented in `docs/output.md`; from d3439e0 on, all files of the run directory.

use granular::scenario::Scenario;
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

/// The environment variable that makes the tests rewrite the golden files.
const REGENERATE: &str = "GRANULAR_REGENERATE_GOLDEN";

/// Top-level keys of the summary that no two runs share: wall-clock figures, the version.
const UNSTABLE: [&str; 4] = [
    "wall_seconds",
    "events_per_second",
    "collisions_per_second",
    "version",
];

/// Files of the run directory that are not compared byte for byte: the log (wall-clock
/// times) and the summary (compared as JSON, less [`UNSTABLE`]).
const NOT_DIGESTED: [&str; 2] = ["log.txt", "summary.json"];

/// The overrides that shorten the two dilute DSMC steady states (module documentation).
const SHORT_DSMC: &[&str] = &["stop.collisions_per_particle=30"];

macro_rules! golden {
    ($($test:ident: $name:literal, $overrides:expr;)*) => {
        $(
            #[test]
            fn $test() {
                check($name, $overrides);
            }
        )*
    };
}

golden! {
    maxwell_boltzmann: "maxwell-boltzmann", &[];
    problem2_mixture: "problem2-mixture", &[];
    problem3_cooling: "problem3-cooling", &[];
    problem4_crater: "problem4-crater", &[];
    dsmc_cooling: "dsmc-cooling", &[];
    dsmc_hcs_rescaled: "dsmc-hcs-rescaled", SHORT_DSMC;
    dsmc_white_noise: "dsmc-white-noise", SHORT_DSMC;
    edmd_hcs_rescaled: "edmd-hcs-rescaled", &[];
    edmd_white_noise: "edmd-white-noise", &[];
    intruder_1d: "intruder-1d", &[];
    intruder_needle: "intruder-needle", &[];
    intruder_disk: "intruder-disk", &[];
    intruder_sphere: "intruder-sphere", &[];
    rough_hcs_edmd: "rough-hcs-edmd", &[];
    rough_hcs_dsmc: "rough-hcs-dsmc", &[];
}

/// Runs the bundled scenario `name` with `overrides` and compares its run directory with
/// the golden files (or rewrites them, with [`REGENERATE`] set).
fn check(name: &str, overrides: &[&str]) {
    let text = crate::common::scenario_text(&format!("{name}.toml"));
    let overrides: Vec<String> = overrides.iter().map(|s| (*s).to_string()).collect();
    let scenario = Scenario::from_toml(&text, &overrides).expect("bundled scenario");
    let (summary, dir) = crate::common::run(name, scenario);
    let digests = digest_run_directory(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let mut now = serde_json::to_value(&summary).expect("summary as JSON");
    if let Value::Object(map) = &mut now {
        for key in UNSTABLE {
            map.remove(key);
        }
    }
    // Through its text, as the golden file is read: the same number reads the same.
    let now: Value = serde_json::from_str(&now.to_string()).expect("summary JSON");

    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let (json_path, sha_path) = (
        golden.join(format!("{name}.json")),
        golden.join(format!("{name}.sha256")),
    );
    if std::env::var_os(REGENERATE).is_some_and(|v| !v.is_empty() && v != "0") {
        std::fs::write(&json_path, pretty(&now)).expect("write golden summary");
        let lines: String = digests
            .iter()
            .map(|(path, digest)| format!("{digest}  {path}\n"))
            .collect();
        std::fs::write(&sha_path, lines).expect("write golden digests");
        return;
    }

    let read = |path: &Path| {
        std::fs::read_to_string(path).unwrap_or_else(|e| {
            panic!(
                "{}: {e} (a new golden file is written by {REGENERATE}=1, see golden.rs)",
                path.display()
            )
        })
    };
    let golden_summary: Value = serde_json::from_str(&read(&json_path)).expect("golden JSON");
    let golden_digests: BTreeMap<String, String> = read(&sha_path)
        .lines()
        .filter_map(|line| line.split_once("  "))
        .map(|(digest, path)| (path.to_string(), digest.to_string()))
        .collect();

    let mut failures = Vec::new();
    let (mut a, mut b) = (BTreeMap::new(), BTreeMap::new());
    flatten(&golden_summary, "", &mut a);
    flatten(&now, "", &mut b);
    for key in a.keys().chain(b.keys().filter(|k| !a.contains_key(*k))) {
        if a.get(key) != b.get(key) {
            failures.push(format!(
                "summary.json: {key}: golden {:?}, now {:?}",
                a.get(key),
                b.get(key)
            ));
        }
    }
    for path in golden_digests
        .keys()
        .chain(digests.keys().filter(|k| !golden_digests.contains_key(*k)))
    {
        match (golden_digests.get(path), digests.get(path)) {
            (Some(g), Some(n)) if g == n => {}
            (Some(_), Some(_)) => failures.push(format!("{path}: the bytes differ")),
            (Some(_), None) => failures.push(format!("{path}: golden, not written now")),
            (None, _) => failures.push(format!("{path}: written now, not golden")),
        }
    }
    assert!(
        failures.is_empty(),
        "{name} differs from tests/golden (see golden.rs before regenerating):\n{}",
        failures.join("\n")
    );
}

/// The SHA-256 (lower-case hex) of every file under `dir` except [`NOT_DIGESTED`], by
/// path relative to `dir` (`/`-separated); a `.npz` file gives one entry per member,
/// `PATH:MEMBER`, of the member's uncompressed bytes.
fn digest_run_directory(dir: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).expect("run directory") {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                pending.push(path);
                continue;
            }
            let relative = path
                .strip_prefix(dir)
                .expect("inside the run directory")
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            if NOT_DIGESTED.contains(&relative.as_str()) {
                continue;
            }
            if relative.ends_with(".npz") {
                let file = std::fs::File::open(&path).expect("npz file");
                let mut zip = zip::ZipArchive::new(file).expect("npz is a zip archive");
                for index in 0..zip.len() {
                    let mut member = zip.by_index(index).expect("npz member");
                    let mut bytes = Vec::new();
                    member.read_to_end(&mut bytes).expect("npz member bytes");
                    out.insert(format!("{relative}:{}", member.name()), sha256(&bytes));
                }
            } else {
                let bytes = std::fs::read(&path).expect("run file");
                out.insert(relative, sha256(&bytes));
            }
        }
    }
    out
}

fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// `value` as indented JSON (one space per level) with a final newline.
fn pretty(value: &Value) -> Vec<u8> {
    use serde::Serialize;
    let mut out = Vec::new();
    let formatter = serde_json::ser::PrettyFormatter::with_indent(b" ");
    let mut serializer = serde_json::Serializer::with_formatter(&mut out, formatter);
    value.serialize(&mut serializer).expect("JSON");
    out.push(b'\n');
    out
}

fn flatten(v: &Value, prefix: &str, out: &mut BTreeMap<String, Value>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(x, &key, out);
            }
        }
        other => {
            out.insert(prefix.to_string(), other.clone());
        }
    }
}
