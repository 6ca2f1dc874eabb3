//! Sweeps over several keys (grid and zip), shards and the merge: the table depends only
//! on the finished members, never on how the sweep was split; missing members are named.

use crate::common::tmp;
use granular::run::sweep::{Shard, SweepError, SweepTable, merge, run_shard, run_sweep};
use granular::scenario::Scenario;
use std::path::Path;

/// 60 disks, two collisions per grain: a member takes milliseconds.
const BASE: &str = r#"
engine = "edmd"
dimension = 2
seed = 11
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = 60
radius = 0.01
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[collisions]
restitution = 0.9
[stop]
collisions_per_particle = 2.0
[output]
interval = 0.05
"#;

const GRID: &str = r#"
[sweep]
seeds = 2
observable = "temperature"
[[sweep.vary]]
key = "collisions.restitution"
values = [0.6, 0.95]
[[sweep.vary]]
key = "species.0.mass"
values = [1.0, 2.0, 4.0]
"#;

fn grid() -> String {
    format!("{BASE}{GRID}")
}

#[test]
fn a_grid_is_every_combination_and_zip_pairs_the_lists() {
    let sc = Scenario::from_toml(&grid(), &[]).expect("grid");
    let spec = sc.sweep.expect("sweep");
    let keys: Vec<String> = spec.axes().into_iter().map(|a| a.key).collect();
    assert_eq!(keys, ["collisions.restitution", "species[0].mass"]);
    let points: Vec<String> = spec
        .points()
        .iter()
        .map(|p| format!("{}/{}", p[0], p[1]))
        .collect();
    assert_eq!(
        points,
        [
            "0.6/1.0", "0.6/2.0", "0.6/4.0", "0.95/1.0", "0.95/2.0", "0.95/4.0"
        ]
    );
    let zip = grid()
        .replace("seeds = 2", "seeds = 2\nmode = \"zip\"")
        .replace("values = [1.0, 2.0, 4.0]", "values = [1.0, 2.0]");
    let spec = Scenario::from_toml(&zip, &[]).unwrap().sweep.unwrap();
    let points: Vec<String> = spec
        .points()
        .iter()
        .map(|p| format!("{}/{}", p[0], p[1]))
        .collect();
    assert_eq!(points, ["0.6/1.0", "0.95/2.0"]);
    // The one-key form is the one-axis case.
    let one = format!("{BASE}[sweep]\nkey = \"collisions.restitution\"\nvalues = [0.5, 0.7]\n");
    let spec = Scenario::from_toml(&one, &[]).unwrap().sweep.unwrap();
    assert_eq!(spec.axes().len(), 1);
    assert_eq!(spec.points().len(), 2);
}

fn merged(dir: &Path, shards: usize) -> (Vec<u8>, Vec<u8>) {
    let text = grid();
    if shards == 0 {
        run_sweep(dir, &text, &[], 2, &|_, _| {}).expect("sweep");
    } else {
        for i in 1..=shards {
            let shard = Shard {
                index: i,
                count: shards,
            };
            run_shard(dir, &text, &[], 1, shard, &|_, _| {}).expect("shard");
        }
        merge(dir, false).expect("merge");
    }
    let read = |f: &str| std::fs::read(dir.join(f)).expect(f);
    (read("sweep.csv"), read("sweep.json"))
}

#[test]
fn sharded_sweeps_merge_to_the_unsharded_table_byte_for_byte() {
    let dirs = [tmp("sweep-all"), tmp("sweep-3"), tmp("sweep-2")];
    let all = merged(&dirs[0], 0);
    let three = merged(&dirs[1], 3);
    let two = merged(&dirs[2], 2);
    assert!(all == three, "3 shards differ from the unsharded sweep");
    assert!(all == two, "2 shards differ from the unsharded sweep");

    // The table, read with the csv crate as it is: one header row, columns named by key.
    let mut reader = csv::Reader::from_reader(all.0.as_slice());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        header[..4],
        [
            "point",
            "collisions.restitution",
            "species[0].mass",
            "members"
        ]
    );
    assert!(header.contains(&"temperature_mean".to_string()));
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 6);
    assert_eq!(
        (&rows[4][1], &rows[4][2], &rows[4][3]),
        ("0.95", "2.0", "2")
    );

    // The typed reader gives the same numbers, with the sidecar.
    let table = SweepTable::read(&dirs[0]).expect("read");
    assert_eq!(table.keys, ["collisions.restitution", "species[0].mass"]);
    assert_eq!(table.meta.mode, "grid");
    assert_eq!(table.meta.member_seeds.len(), 2);
    assert_eq!(table.meta.keys[1].dimension.as_deref(), Some("mass"));
    assert!(table.meta.missing.is_empty());
    assert_eq!(table.rows[5].numbers, [0.95, 4.0]);
    let (t, e) = table.observable("temperature").expect("temperature");
    assert!(
        t.iter()
            .zip(&e)
            .all(|(t, e)| t.is_finite() && e.is_finite())
    );
    // Physics: at the same masses, lower restitution leaves a colder gas (same seeds).
    for m in 0..3 {
        assert!(t[m] < t[m + 3], "e = 0.6 colder than 0.95: {t:?}");
    }
    // Member directories are plain run directories, without the sweep table.
    let member = std::fs::read_to_string(dirs[0].join("point_004/seed_001/scenario.toml")).unwrap();
    assert!(
        !member.contains("[sweep]") && member.contains("mass = 2.0"),
        "{member}"
    );
    for d in dirs {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn merging_an_incomplete_sweep_names_the_missing_members() {
    let dir = tmp("sweep-missing");
    let shard = Shard { index: 2, count: 3 };
    let ran = run_shard(&dir, &grid(), &[], 1, shard, &|_, _| {}).expect("shard");
    assert_eq!(
        ran.members,
        [
            "point_000/seed_001",
            "point_002/seed_000",
            "point_003/seed_001",
            "point_005/seed_000"
        ]
    );
    match merge(&dir, false) {
        Err(SweepError::Missing { missing, total, .. }) => {
            assert_eq!(total, 12);
            assert_eq!(missing.len(), 8);
            assert_eq!(missing[0], "point_000/seed_000 (not started)");
            let shown = SweepError::Missing {
                dir: dir.clone(),
                missing,
                total,
            }
            .to_string();
            assert!(shown.contains("8 of 12 members") && shown.contains("--allow-missing"));
        }
        other => panic!("expected missing members, got {other:?}"),
    }
    assert!(!dir.join("sweep.csv").exists());
    let partial = merge(&dir, true).expect("partial merge");
    assert_eq!(partial.meta.missing.len(), 8);
    let members: Vec<u64> = partial.rows.iter().map(|r| r.members).collect();
    assert_eq!(members, [1, 0, 1, 1, 0, 1]);
    // Another scenario in the same directory is refused.
    let other = run_shard(
        &dir,
        &grid(),
        &["stop.collisions_per_particle=3.0".into()],
        1,
        shard,
        &|_, _| {},
    );
    assert!(
        matches!(other, Err(SweepError::OtherSweep { .. })),
        "{other:?}"
    );
    let empty = tmp("sweep-none");
    assert!(matches!(
        merge(&empty, false),
        Err(SweepError::NotASweep { .. })
    ));
    let _ = (std::fs::remove_dir_all(dir), std::fs::remove_dir_all(empty));
}
