//! `[[schedule]]`: parameters changed at given times of a run. A scheduled change is the
//! same, bit for bit, as `Simulation::set` at that time between two calls to `advance`;
//! a run interrupted between two entries resumes bit-identically and applies the rest;
//! `log.txt` and `summary.json` list every change once.

use granular::prelude::*;
use granular::run::RunDir;

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

/// A driven gas (white noise) of `engine` in 2D, quenched at t = 0.25 and heated harder at
/// t = 0.55; `schedule` false leaves the `[[schedule]]` out.
fn driven(engine: &str, schedule: bool) -> String {
    let count = if engine == "dsmc" { 2000 } else { 300 };
    let entries = if schedule {
        r#"
[[schedule]]
time = 0.25
set = { "collisions.restitution" = 0.6 }

[[schedule]]
time = 0.55
set = { "driving.strength" = 3.0, "collisions.restitution" = 0.8 }
"#
    } else {
        ""
    };
    format!(
        r#"
engine = "{engine}"
dimension = 2
seed = 11
box = {{ boundary = "periodic" }}
[collisions]
restitution = 0.9
[[species]]
name = "grain"
count = {count}
packing_fraction = 0.1
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[driving]
kind = "white_noise"
strength = 1.0
[stop]
time = 0.8
[output]
interval = 0.1
{entries}"#
    )
}

/// The changes of [`driven`]'s schedule, made by hand (the collision law before the
/// driving, as an entry makes them: the event-driven engine's kick interval follows the
/// mean free time under the law in force).
const BY_HAND: [(f64, &[(&str, &str)]); 2] = [
    (0.25, &[("collisions.restitution", "0.6")]),
    (
        0.55,
        &[
            ("collisions.restitution", "0.8"),
            ("driving.strength", "3.0"),
        ],
    ),
];

#[test]
fn a_schedule_is_set_between_two_advances() {
    for engine in ["edmd", "dsmc"] {
        let scheduled = Scenario::from_toml(&driven(engine, true), &[]).expect("scenario");
        let mut sim = Simulation::new(scheduled).expect("build");
        assert_eq!(sim.next_scheduled_time(), Some(0.25));
        assert_eq!(sim.run().expect("run"), StopReason::Time);
        assert_eq!(sim.next_scheduled_time(), None, "{engine}: all applied");

        // By hand: the same output grid (DSMC lands a shortened step on every time it is
        // asked to reach), the changes made with `set` at the same times.
        let plain = Scenario::from_toml(&driven(engine, false), &[]).expect("scenario");
        let mut hand = Simulation::new(plain).expect("build");
        let mut stops: Vec<f64> = (1..=8).map(|k| 0.1 * k as f64).collect();
        stops.extend(BY_HAND.iter().map(|(t, _)| *t));
        stops.sort_by(f64::total_cmp);
        for t in stops {
            hand.advance(t).expect("advance");
            for (_, changes) in BY_HAND.iter().filter(|(at, _)| *at == t) {
                for (key, value) in changes.iter() {
                    hand.set(key, value).expect("set");
                }
            }
        }
        assert_eq!(sim.time(), hand.time(), "{engine}");
        assert_eq!(sim.collisions(), hand.collisions(), "{engine}");
        assert_eq!(
            bits(&sim.velocities().expect("grains")),
            bits(&hand.velocities().expect("grains")),
            "{engine}: velocities"
        );
        assert_eq!(
            bits(&sim.positions().expect("grains")),
            bits(&hand.positions().expect("grains")),
            "{engine}: positions"
        );
        let keys: Vec<(f64, &str, &str, &str)> = sim
            .changes()
            .iter()
            .map(|c| (c.time, c.key.as_str(), c.old.as_str(), c.new.as_str()))
            .collect();
        assert_eq!(
            keys,
            [
                (0.25, "collisions.restitution", "0.9", "0.6"),
                (0.55, "collisions.restitution", "0.6", "0.8"),
                (0.55, "driving.strength", "1.0", "3.0"),
            ],
            "{engine}"
        );
        assert_eq!(sim.scenario().collisions().restitution, 0.8, "{engine}");
        assert_eq!(
            sim.initial_scenario().collisions().restitution,
            0.9,
            "{engine}: the scenario as it started"
        );
    }
}

/// A scheduled run interrupted between its two entries (a checkpoint at every chunk, the
/// run stopped after 4 outputs, t = 0.4) resumes to the same bits as the uninterrupted
/// run, and its log names each change once.
#[test]
fn a_scheduled_run_resumes_bit_identically() {
    for engine in ["edmd", "dsmc"] {
        let scenario = Scenario::from_toml(
            &driven(engine, true),
            &["output.checkpoint_seconds=1e-9".into()],
        )
        .expect("scenario");
        let whole_dir = crate::common::tmp("schedule-whole");
        let whole = Run::create(&whole_dir, scenario.clone())
            .expect("run")
            .run_to_end(&mut |_| {}, None)
            .expect("whole run");
        let dir = crate::common::tmp("schedule-resumed");
        let stopped = Run::create(&dir, scenario)
            .expect("run")
            .run_to_end(&mut |_| {}, Some(4));
        assert!(stopped.is_err(), "{engine}: stopped after 4 outputs");
        let resumed = Run::resume(&dir)
            .expect("resume")
            .run_to_end(&mut |_| {}, None)
            .expect("resumed run");
        assert_eq!(resumed.collisions, whole.collisions, "{engine}");
        assert_eq!(resumed.changes, whole.changes, "{engine}");
        assert_eq!(resumed.changes.len(), 3, "{engine}");
        let series = |d: &std::path::Path| {
            std::fs::read_to_string(RunDir::new(d).file(granular::run::RunFile::TimeSeries))
                .expect("time series")
        };
        assert_eq!(series(&dir), series(&whole_dir), "{engine}: timeseries.csv");
        let log = std::fs::read_to_string(dir.join("log.txt")).expect("log");
        for line in [
            "set collisions.restitution from 0.9 to 0.6 at t = 0.25",
            "set driving.strength from 1.0 to 3.0 at t = 0.55",
        ] {
            assert_eq!(log.matches(line).count(), 1, "{engine}: {line} in\n{log}");
        }
        // The directory keeps the scenario as written, schedule and all.
        let written = std::fs::read_to_string(dir.join("scenario.toml")).expect("scenario");
        assert!(written.contains("restitution = 0.9"), "{written}");
        assert!(written.contains("[[schedule]]"), "{written}");
        for d in [dir, whole_dir] {
            let _ = std::fs::remove_dir_all(d);
        }
    }
}

/// A simulation started from a state at a time after some entries applies those entries
/// at its start (the parameters in force at that time), the later ones on the way.
#[test]
fn a_state_set_after_an_entry_takes_its_values() {
    let scenario = Scenario::from_toml(&driven("dsmc", true), &[]).expect("scenario");
    let mut sim = Simulation::new(scenario.clone()).expect("build");
    sim.advance(0.3).expect("advance");
    let (x, v) = (
        sim.positions().expect("grains"),
        sim.velocities().expect("grains"),
    );
    let mut started = Simulation::from_state(scenario, 0.3, &x, &v).expect("from state");
    assert_eq!(started.next_scheduled_time(), Some(0.25), "not applied yet");
    started.advance(0.4).expect("advance");
    assert_eq!(started.scenario().collisions().restitution, 0.6);
    assert_eq!(started.changes()[0].time, 0.3, "applied at the start");
    assert_eq!(started.next_scheduled_time(), Some(0.55));
}

/// Rough grains whose tangential restitution a `[[schedule]]` changes (β = 0 -> 0.5 at
/// t = 0.25, smooth at t = 0.55) run bit for bit as with `set` at those times, and keep
/// their spins from the second entry on; a schedule that would make smooth grains rough
/// is refused when the scenario is read.
#[test]
fn a_schedule_of_the_tangential_restitution() {
    for engine in ["edmd", "dsmc"] {
        let count = if engine == "dsmc" { 2000 } else { 300 };
        let text = |schedule: &str| {
            format!(
                r#"
engine = "{engine}"
dimension = 2
seed = 3
box = {{ boundary = "periodic" }}
[collisions]
restitution = 0.9
tangential_restitution = 0.0
[[species]]
name = "grain"
count = {count}
packing_fraction = 0.1
inertia = 0.4
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
angular_velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[stop]
time = 0.8
[output]
interval = 0.1
{schedule}"#
            )
        };
        let schedule = r#"
[[schedule]]
time = 0.25
set = { "collisions.tangential_restitution" = 0.5 }

[[schedule]]
time = 0.55
set = { "collisions.tangential_restitution" = -1.0 }
"#;
        let mut sim = Simulation::new(Scenario::from_toml(&text(schedule), &[]).expect("scenario"))
            .expect("build");
        sim.run().expect("run");
        let mut hand =
            Simulation::new(Scenario::from_toml(&text(""), &[]).expect("scenario")).expect("build");
        let mut frozen = Vec::new();
        for t in [0.1, 0.2, 0.25, 0.3, 0.4, 0.5, 0.55, 0.6, 0.7, 0.8] {
            hand.advance(t).expect("advance");
            if t == 0.25 {
                hand.set("collisions.tangential_restitution", "0.5")
                    .expect("set");
            }
            if t == 0.55 {
                hand.set("collisions.tangential_restitution", "-1.0")
                    .expect("set");
                frozen = hand.snapshot().expect("grains").angular_velocities;
            }
        }
        let spins = |s: &Simulation| bits(&s.snapshot().expect("grains").angular_velocities);
        assert_eq!(sim.collisions(), hand.collisions(), "{engine}");
        assert_eq!(
            bits(&sim.velocities().expect("grains")),
            bits(&hand.velocities().expect("grains")),
            "{engine}: velocities"
        );
        assert_eq!(spins(&sim), spins(&hand), "{engine}: spins");
        assert_eq!(spins(&sim), bits(&frozen), "{engine}: smooth from t = 0.55");
        assert_eq!(sim.changes().len(), 2, "{engine}");

        let smooth = text(schedule).replace("tangential_restitution = 0.0\n", "");
        let smooth = smooth.replace("inertia = 0.4\n", "").replace(
            "angular_velocity = { distribution = \"maxwell_boltzmann\", temperature = 1.0 }\n",
            "",
        );
        let e = Scenario::from_toml(&smooth, &[]).expect_err("refused");
        let message = e.to_string();
        assert!(
            message.contains("schedule[0].set") && message.contains("cannot become rough"),
            "{engine}: {message}"
        );
    }
}
