//! The bad-scenario corpus (`tests/bad_scenarios/*.toml`, the expected key and error text
//! in each file's header; no message speaks Rust, [`RUST_JARGON`]) and a property test of
//! the scenario reader: no input, from the file or from `--set`, makes it panic.

use granular::scenario::Scenario;
use proptest::prelude::*;
use std::path::Path;

/// Header lines of a corpus file: `# key: K`, `# expect: TEXT` (any number), `# set: KEY=VALUE`.
struct Case {
    key: String,
    expect: Vec<String>,
    set: Vec<String>,
}

fn header(text: &str) -> Case {
    let mut case = Case {
        key: String::new(),
        expect: Vec::new(),
        set: Vec::new(),
    };
    for line in text.lines().take_while(|l| l.starts_with('#')) {
        if let Some(k) = line.strip_prefix("# key: ") {
            case.key = k.to_string();
        } else if let Some(e) = line.strip_prefix("# expect: ") {
            case.expect.push(e.to_string());
        } else if let Some(s) = line.strip_prefix("# set: ") {
            case.set.push(s.to_string());
        }
    }
    case
}

/// Words of Rust, not of the scenario: type names, serde's and the standard library's
/// phrases. No error message may contain one (issue 37).
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

#[test]
fn rust_jargon_is_found_as_whole_words() {
    assert_eq!(
        rust_jargon("invalid type: integer, expected usize"),
        Some("usize")
    );
    assert_eq!(rust_jargon("expected struct RawVelocity"), Some("struct "));
    assert_eq!(
        rust_jargon("line 3: `scenario`: duplicate key"),
        Some("`scenario`")
    );
    assert_eq!(
        rust_jargon("a whole number, 0 or more; the f64 kind"),
        Some("f64")
    );
    assert_eq!(rust_jargon("the speed u64x and mu64 are fine"), None);
}

#[test]
fn every_bad_scenario_fails_naming_its_key_and_the_fix() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenarios");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("corpus directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 70, "corpus has {} files", files.len());
    let mut failures = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).expect("corpus file");
        let case = header(&text);
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        assert!(
            !case.key.is_empty() && !case.expect.is_empty(),
            "{name}: header without key or expect"
        );
        match Scenario::from_toml(&text, &case.set) {
            Ok(_) => failures.push(format!("{name}: accepted")),
            Err(e) => {
                let shown = e.to_string();
                if e.key != case.key {
                    failures.push(format!(
                        "{name}: key `{}`, expected `{}`: {shown}",
                        e.key, case.key
                    ));
                }
                for fragment in &case.expect {
                    if !shown.contains(fragment.as_str()) {
                        failures.push(format!("{name}: no {fragment:?} in: {shown}"));
                    }
                }
                if let Some(word) = rust_jargon(&shown) {
                    failures.push(format!("{name}: speaks Rust (`{word}`): {shown}"));
                }
                if e.key.is_empty() || !shown.contains(&format!("`{}`", e.key)) {
                    failures.push(format!("{name}: the error does not name its key: {shown}"));
                }
                // A key written in the file gets its line (an error of a `--set` value
                // has none: the value is not in the file).
                if case.set.is_empty()
                    && granular::scenario::locate(&text, &e.key).is_some()
                    && e.line.is_none()
                {
                    failures.push(format!("{name}: no line: {shown}"));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

const BASE: &str = r#"engine = "edmd"
dimension = 2
[box]
lengths = [1.0, 1.0]
[[species]]
name = "disk"
count = 10
radius = 0.01
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[stop]
time = 1.0
"#;

/// Keys and values that the random snippets and overrides combine.
fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("engine".to_string()),
        Just("dimension".to_string()),
        Just("seed".to_string()),
        Just("gravity".to_string()),
        Just("box.lengths".to_string()),
        Just("box.boundary".to_string()),
        Just("species[0].count".to_string()),
        Just("species[0].radius".to_string()),
        Just("species[0].mass".to_string()),
        Just("species[0].name".to_string()),
        Just("species[0].velocity".to_string()),
        Just("species[0].velocity.temperature".to_string()),
        Just("species[1].mass".to_string()),
        Just("collisions.restitution".to_string()),
        Just("stop.time".to_string()),
        Just("stop.collisions".to_string()),
        Just("output.interval".to_string()),
        Just("output.histogram_bins".to_string()),
        Just("dsmc.time_step".to_string()),
        Just("intruder.model".to_string()),
        Just("sweep.values".to_string()),
        "[a-z\\[\\]0-9._]{0,20}",
    ]
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("9223372036854775807".to_string()),
        Just("1e308".to_string()),
        Just("1e-308".to_string()),
        Just("\"edmd\"".to_string()),
        Just("\"dsmc\"".to_string()),
        Just("\"intruder\"".to_string()),
        Just("\"periodic\"".to_string()),
        Just("[1.0, 2.0]".to_string()),
        Just("[]".to_string()),
        Just("{ distribution = \"zero\" }".to_string()),
        Just("{}".to_string()),
        any::<f64>().prop_map(|x| format!("{x:?}")),
        any::<i64>().prop_map(|x| x.to_string()),
        "[ -~]{0,12}",
    ]
}

/// 1000 cases from a fixed seed, so that every test run tries the same inputs (CI included);
/// `PROPTEST_RNG_SEED=N` tries others.
fn config() -> ProptestConfig {
    let default = ProptestConfig::default();
    let rng_seed = if std::env::var_os("PROPTEST_RNG_SEED").is_some() {
        default.rng_seed
    } else {
        proptest::test_runner::RngSeed::Fixed(20_261_204)
    };
    ProptestConfig {
        cases: 1000,
        rng_seed,
        ..default
    }
}

/// `message` with the user's own words (the keys and values given) blanked out: a message
/// may quote what the user wrote (`got the text "u8"`), which is not jargon of ours.
fn without_user_text(message: &str, pairs: &[(String, String)]) -> String {
    let mut words: Vec<&str> = pairs
        .iter()
        .flat_map(|(k, v)| [k.as_str(), v.as_str()])
        .filter(|w| w.trim().len() >= 2)
        .collect();
    // (A word of one character cannot be jargon.) Longest first, so that a value is not
    // cut up by a shorter one inside it.
    words.sort_by_key(|w| std::cmp::Reverse(w.len()));
    words
        .into_iter()
        .fold(message.to_string(), |m, w| m.replace(w, " "))
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_overrides_never_panic(pairs in proptest::collection::vec((key(), value()), 0..4)) {
        let sets: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={v}")).collect();
        if let Err(e) = Scenario::from_toml(BASE, &sets) {
            let shown = without_user_text(&e.to_string(), &pairs);
            prop_assert!(rust_jargon(&shown).is_none(), "speaks Rust: {}", e);
        }
    }

    #[test]
    fn random_snippets_never_panic(lines in proptest::collection::vec((key(), value()), 0..6), junk in "[ -~\n]{0,40}") {
        let mut text = String::from(BASE);
        for (k, v) in &lines {
            text.push_str(&format!("{k} = {v}\n"));
        }
        if let Err(e) = Scenario::from_toml(&text, &[]) {
            let shown = without_user_text(&e.to_string(), &lines);
            prop_assert!(rust_jargon(&shown).is_none(), "speaks Rust: {}", e);
        }
        text.push_str(&junk);
        let _ = Scenario::from_toml(&text, &[]);
        // Cut anywhere (on a character boundary).
        for cut in [text.len() / 3, text.len() / 2] {
            if text.is_char_boundary(cut) {
                let _ = Scenario::from_toml(&text[..cut], &[]);
            }
        }
    }
}

/// Every bundled scenario is valid, its resolved text reads back to the same scenario,
/// and that text holds only the tables of its engine.
#[test]
fn bundled_scenarios_resolve_to_their_engine_tables() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("scenarios/") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("scenario");
        let s =
            Scenario::from_toml(&text, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let resolved = s.to_toml();
        let again = Scenario::from_toml(&resolved, &[])
            .unwrap_or_else(|e| panic!("{}: resolved: {e}\n{resolved}", path.display()));
        assert_eq!(s, again, "{}", path.display());
        let other = match s.kind() {
            granular::scenario::EngineKind::Edmd => "[dsmc]",
            granular::scenario::EngineKind::Dsmc => "[edmd]",
            granular::scenario::EngineKind::Intruder => "[collisions]",
        };
        // What older versions wrote: the other engines' tables with their defaults.
        let old_style = Scenario::from_resolved_toml(&format!("{resolved}\n{other}\n"), None)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(s, old_style, "{}", path.display());
        assert!(
            !resolved.contains(other),
            "{}: {other} in\n{resolved}",
            path.display()
        );
        n += 1;
    }
    assert!(n >= 9, "{n} bundled scenarios");
}

/// Errors of values given by `--set` name the key and the override; errors in the file
/// carry the line of the key.
#[test]
fn errors_carry_the_line_or_the_override() {
    let text = "engine = \"edmd\"\n[[species]]\nname = \"a\"\ncount = 10\nradius = 0.01\nvelocity = { distribution = \"maxwell_boltzmann\", temperature = 1.0 }\n[collisions]\nrestitution = 0.5\n[stop]\ntime = 1.0\n";
    let e = Scenario::from_toml(&text.replace("0.5", "2.0"), &[]).expect_err("restitution 2");
    assert_eq!(
        (e.key.as_str(), e.line),
        ("collisions.restitution", Some(8)),
        "{e}"
    );
    let e = Scenario::from_toml(text, &["collisions.restitution=abc".into()]).expect_err("abc");
    assert_eq!(e.key, "collisions.restitution", "{e}");
    assert!(
        e.message.contains("--set collisions.restitution=abc"),
        "{e}"
    );
    let e = Scenario::from_toml(text, &["species[0].velocity.temperature=-1".into()])
        .expect_err("T < 0");
    assert_eq!(e.key, "species[0].velocity.temperature", "{e}");
    assert!(e.message.contains("-1"), "{e}");
}

/// Every column an engine writes is an observable a sweep accepts (the list in the
/// scenario module follows `Observation::columns`).
#[test]
fn sweep_observables_cover_every_column() {
    use granular::prelude::*;
    let grains = |engine: &str| {
        format!(
            "engine = \"{engine}\"\n[box]\nlengths = [1.0, 1.0]\nboundary = \"wall\"\n[[species]]\nname = \"a\"\ncount = 40\nradius = 0.02\n[[species]]\nname = \"b\"\ncount = 1\nradius = 0.02\n[collisions]\nrestitution = 0.9\ncontact_duration = 1e-6\n[stop]\ntime = 0.05\n[output]\ninterval = 0.01\n"
        )
    };
    let texts = [
        grains("edmd"),
        grains("dsmc").replace("[[species]]\nname = \"b\"\ncount = 1\nradius = 0.02\n", ""),
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/intruder-1d.toml"),
        )
        .expect("1d"),
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/intruder-needle.toml"),
        )
        .expect("needle"),
    ];
    for text in &texts {
        let scenario = Scenario::from_toml(text, &[]).expect("valid");
        let known = granular::scenario::sweep_observables(&scenario);
        let mut simulation = Simulation::new(scenario).expect("builds");
        let first = simulation.observe();
        simulation.advance(0.02).expect("advances");
        let later = simulation.observe();
        let rates = later.rates_since(&first);
        for (name, _) in later.columns(Some(&rates)) {
            assert!(known.contains(&name), "{name} missing from {known:?}");
        }
    }
    // An intruder run with `twin` too.
    let twin = texts[2].replace(
        "model = \"1d\"",
        "model = \"dsmc-twin\"\nbath_particles = 500",
    );
    let scenario = Scenario::from_toml(&twin, &[]).expect("twin");
    let known = granular::scenario::sweep_observables(&scenario);
    let mut simulation = Simulation::new(scenario).expect("builds");
    simulation.advance(100.0).expect("advances");
    for (name, _) in simulation.observe().columns(None) {
        assert!(known.contains(&name), "{name} missing from {known:?}");
    }
}
