//! Trajectories (`[output] trajectory`): one frame per snapshot in every format, the same
//! files from `RunDir::export_trajectories`, and a resumed run that cuts them back to its checkpoint.

use crate::common::tmp;
use granular::run::Run;
use granular::run::RunDir;
use granular::scenario::Scenario;
use granular::trajectory::Format;
use std::path::Path;

const RUN: &str = r#"
engine = "edmd"
dimension = 3
seed = 3

[box]
lengths = [1.0, 0.5, 0.5]
boundary = ["periodic", "wall", "periodic"]

[[species]]
name = "ball"
count = 200
packing_fraction = 0.05
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }

[collisions]
restitution = 0.9

[stop]
collisions_per_particle = 10.0

[output]
interval = 0.01
snapshot_every = 3
checkpoint_seconds = 1e-9
trajectory = ["xyz", "lammps", "gsd", "vtk"]
"#;

const FILES: [&str; 4] = [
    "trajectory.xyz",
    "trajectory.lammpstrj",
    "trajectory.gsd",
    "trajectory.pvd",
];

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join("trajectory").join(name)).unwrap()
}

fn snapshot_count(dir: &Path) -> usize {
    std::fs::read_dir(dir.join("snapshots")).unwrap().count()
}

#[test]
fn every_snapshot_is_a_frame_and_export_writes_the_same_files() {
    let s = Scenario::from_toml(RUN, &[]).unwrap();
    let dir = tmp("trajectory-run");
    Run::create(&dir, s)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let n = snapshot_count(&dir);
    assert!(n >= 3, "{n} snapshots");
    let xyz = String::from_utf8(read(&dir, "trajectory.xyz")).unwrap();
    assert_eq!(xyz.matches("Properties=").count(), n);
    assert!(xyz.contains("pbc=\"T F T\""));
    let dump = String::from_utf8(read(&dir, "trajectory.lammpstrj")).unwrap();
    assert_eq!(dump.matches("ITEM: TIMESTEP").count(), n);
    assert!(dump.contains("ITEM: BOX BOUNDS pp ff pp\n0 1\n0 0.5\n0 0.5\n"));
    let pvd = String::from_utf8(read(&dir, "trajectory.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), n);
    let vtp = std::fs::read_dir(dir.join("trajectory/vtp"))
        .unwrap()
        .count();
    assert_eq!(vtp, n);

    let copy = tmp("trajectory-export");
    std::fs::create_dir_all(copy.join("snapshots")).unwrap();
    std::fs::copy(dir.join("scenario.toml"), copy.join("scenario.toml")).unwrap();
    for e in std::fs::read_dir(dir.join("snapshots")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, copy.join("snapshots").join(p.file_name().unwrap())).unwrap();
    }
    let written = RunDir::new(&copy)
        .export_trajectories(&Format::ALL)
        .unwrap();
    assert_eq!(written.len(), 4);
    for name in FILES {
        assert!(read(&copy, name) == read(&dir, name), "{name} differs");
    }
}

#[test]
fn a_resumed_run_cuts_the_trajectories_back_to_its_checkpoint() {
    let s = Scenario::from_toml(RUN, &[]).unwrap();
    let (full, cut) = (tmp("trajectory-full"), tmp("trajectory-cut"));
    Run::create(&full, s.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    assert!(
        Run::create(&cut, s)
            .unwrap()
            .run_to_end(&mut |_| {}, Some(7))
            .is_err()
    );
    // What a process killed after the checkpoint leaves: bytes past the saved state.
    for name in ["trajectory.xyz", "trajectory.lammpstrj", "trajectory.gsd"] {
        let path = cut.join("trajectory").join(name);
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.extend_from_slice(b"a frame written after the checkpoint\n");
        std::fs::write(&path, bytes).unwrap();
    }
    Run::resume(&cut)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    for name in FILES {
        assert!(read(&full, name) == read(&cut, name), "{name} differs");
    }
}

#[test]
fn export_names_the_intruder_engine_and_a_missing_run() {
    let dir = tmp("trajectory-intruder");
    std::fs::write(
        dir.join("scenario.toml"),
        "engine = \"intruder\"\n[intruder]\nmodel = \"1d\"\nmass = 1.0\nbath_mass = 1.0\n\
         restitution = 0.5\nbath_density = 1.0\nbath = { kind = \"gaussian\", temperature = 0.5 }\n\
         [stop]\ncollisions = 1000\n",
    )
    .unwrap();
    let e = RunDir::new(&dir)
        .export_trajectories(&[Format::Xyz])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("intruder engine, which has no grain trajectories"),
        "{e}"
    );
    assert!(!dir.join("trajectory").exists());
    let e = RunDir::new(tmp("trajectory-empty"))
        .export_trajectories(&[Format::Gsd])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("scenario.toml") && e.contains("granular run"),
        "{e}"
    );
}
