//! The bundled scenarios give the same `summary.json` numbers as before the library was
//! reshaped around the in-memory API, bit for bit. `tests/golden/NAME.json` holds the
//! summaries of the version before that change (b73b734), less the wall-clock figures,
//! with one documented rename (`docs/output.md`): DSMC's `final.collisions` is
//! `final.pair_collisions`, as in the event-driven engine. Keys added since (the blocks
//! `resolved` and `warnings`, DSMC's TC counter `final.tc_elastic_collisions`) are
//! allowed; any other difference fails. Regenerated since, each documented in
//! `docs/output.md`: the Maxwell-Boltzmann fit of the species not in a steady state replaced
//! by `scaled_speeds` (`dsmc-cooling`, `problem3-cooling`, `problem4-crater`); DSMC's
//! automatic time step following the mean free time (`dsmc-cooling`).
//! Extended since, with keys added only (no number of the files changed): the `averages`
//! block, the event-driven engine's `final.a2` and `final.a2.<species>`, and
//! `scaled_speeds.<species>.theory_a2`.
//!
//! The two scenarios of the DSMC seed's section 3.2 take minutes; they are not here.

use granular::scenario::Scenario;
use serde_json::Value;
use std::collections::BTreeMap;

const SCENARIOS: [&str; 7] = [
    "maxwell-boltzmann",
    "problem2-mixture",
    "problem3-cooling",
    "problem4-crater",
    "dsmc-cooling",
    "intruder-1d",
    "intruder-needle",
];

/// Keys (or whole blocks) a summary has that the golden one did not.
const ADDED: [&str; 3] = ["resolved", "warnings", "final.tc_elastic_collisions"];

/// Wall-clock figures and the version, which no two runs share.
const UNSTABLE: [&str; 4] = [
    "wall_seconds",
    "events_per_second",
    "collisions_per_second",
    "version",
];

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

#[test]
fn bundled_scenarios_give_the_golden_summaries() {
    let mut failures = Vec::new();
    for name in SCENARIOS {
        let text = crate::common::scenario_text(&format!("{name}.toml"));
        let scenario = Scenario::from_toml(&text, &[]).expect("bundled scenario");
        let (summary, dir) = crate::common::run(name, scenario);
        let _ = std::fs::remove_dir_all(dir);
        let golden_path = format!("{}/tests/golden/{name}.json", env!("CARGO_MANIFEST_DIR"));
        let golden: Value =
            serde_json::from_str(&std::fs::read_to_string(golden_path).expect("golden file"))
                .expect("golden JSON");
        let now = serde_json::to_value(&summary).expect("summary as JSON");
        let (mut a, mut b) = (BTreeMap::new(), BTreeMap::new());
        flatten(&golden, "", &mut a);
        flatten(&now, "", &mut b);
        for key in a.keys().chain(b.keys()) {
            let top = key.split('.').next().unwrap_or("");
            let added = ADDED.contains(&top) || ADDED.contains(&key.as_str());
            if UNSTABLE.contains(&top) || (added && !a.contains_key(key)) {
                continue;
            }
            if a.get(key) != b.get(key) {
                failures.push(format!(
                    "{name}: {key}: golden {:?}, now {:?}",
                    a.get(key),
                    b.get(key)
                ));
            }
        }
    }
    failures.dedup();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
