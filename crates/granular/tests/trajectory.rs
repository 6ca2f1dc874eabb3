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

/// Rough grains: a 2D event-driven run and a 3D DSMC run, spinning from the start.
fn rough_scenario(dimension: usize) -> Scenario {
    let text = if dimension == 2 {
        r#"
engine = "edmd"
dimension = 2
seed = 4

[box]
lengths = [1.0, 1.0]
boundary = ["periodic", "wall"]

[[species]]
name = "disk"
count = 150
packing_fraction = 0.05
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 0.5 }

[[species]]
name = "ring"
count = 50
radius = 0.01
inertia = 0.9
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "given", angular_velocity = [3.0] }

[collisions]
restitution = 0.9
tangential_restitution = 0.3

[stop]
collisions_per_particle = 6.0

[output]
interval = 0.01
snapshot_every = 3
trajectory = ["xyz", "lammps", "gsd", "vtk"]
"#
    } else {
        r#"
engine = "dsmc"
dimension = 3
seed = 12

[box]
lengths = [1.0, 1.0, 1.0]
boundary = ["periodic", "periodic", "wall"]

[[species]]
name = "grain"
count = 3000
packing_fraction = 0.02
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 0.5 }

[collisions]
restitution = 0.8
tangential_restitution = 0.4
wall_restitution = 0.9
wall_tangential_restitution = -0.5

[stop]
collisions_per_particle = 3.0

[output]
interval = 0.02
snapshot_every = 3
trajectory = ["xyz", "lammps", "gsd", "vtk"]
"#
    };
    Scenario::from_toml(text, &[]).unwrap()
}

/// The angular velocity of every grain of every frame of a text trajectory: the last three
/// numbers of each grain line (`omega` of extended XYZ, `omegax omegay omegaz` of the dump);
/// a frame's grain lines follow the line holding `header`, and its number of grains is
/// `skip` lines above that one.
fn text_spins(text: &str, header: &str, skip: usize) -> Vec<Vec<[f64; 3]>> {
    let lines: Vec<&str> = text.lines().collect();
    let mut frames = Vec::new();
    let mut k = 0;
    while k < lines.len() {
        let at = (k..lines.len())
            .find(|&j| lines[j].contains(header))
            .unwrap_or(lines.len());
        if at == lines.len() {
            break;
        }
        let n: usize = lines[at - skip].trim().parse().unwrap();
        let rows = &lines[at + 1..at + 1 + n];
        frames.push(
            rows.iter()
                .map(|r| {
                    let v: Vec<f64> = r
                        .split_whitespace()
                        .rev()
                        .take(3)
                        .map(|x| x.parse().unwrap())
                        .collect();
                    [v[2], v[1], v[0]]
                })
                .collect(),
        );
        k = at + 1 + n;
    }
    frames
}

/// Rough grains: every format carries each frame's angular velocities, equal to the
/// snapshot's to the last bit in the text formats (`(0, 0, ω_z)` for disks), and `granular
/// export` writes the same files from the snapshots.
#[test]
fn rough_runs_write_the_snapshots_angular_velocities_in_every_format() {
    for d in [2, 3] {
        let dir = tmp(&format!("trajectory-rough{d}"));
        Run::create(&dir, rough_scenario(d))
            .unwrap()
            .run_to_end(&mut |_| {}, None)
            .unwrap();
        let mut snapshots: Vec<_> = std::fs::read_dir(dir.join("snapshots"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        snapshots.sort();
        assert!(snapshots.len() >= 3, "{d}D: {} snapshots", snapshots.len());
        let spins: Vec<Vec<[f64; 3]>> = snapshots
            .iter()
            .map(|p| {
                let s = granular::run::read_snapshot(p).unwrap();
                let r = if d == 2 { 1 } else { 3 };
                assert_eq!(s.angular_velocities.len(), r * s.radii.len());
                s.angular_velocities
                    .chunks(r)
                    .map(|w| {
                        if d == 2 {
                            [0.0, 0.0, w[0]]
                        } else {
                            [w[0], w[1], w[2]]
                        }
                    })
                    .collect()
            })
            .collect();
        assert!(spins[0].iter().any(|w| w[2] != 0.0));
        let xyz = String::from_utf8(read(&dir, "trajectory.xyz")).unwrap();
        assert!(xyz.contains("id:I:1:omega:R:3 Time="));
        assert_eq!(
            text_spins(&xyz, "Properties=", 1),
            spins,
            "{d}D extended XYZ"
        );
        let dump = String::from_utf8(read(&dir, "trajectory.lammpstrj")).unwrap();
        assert_eq!(
            text_spins(
                &dump,
                "ITEM: ATOMS id type x y z vx vy vz radius mass omegax omegay omegaz",
                5
            ),
            spins,
            "{d}D LAMMPS dump"
        );
        let gsd = read(&dir, "trajectory.gsd");
        assert!(gsd.windows(16).any(|w| w == b"particles/angmom"));
        let vtp = std::fs::read_to_string(dir.join("trajectory/vtp/snapshot_000000.vtp")).unwrap();
        let first: Vec<String> = spins[0].iter().flatten().map(|w| w.to_string()).collect();
        let start = vtp
            .find("Name=\"angular_velocity\" NumberOfComponents=\"3\"")
            .unwrap();
        let body = &vtp[start..];
        let body = &body[body.find('>').unwrap() + 1..body.find('<').unwrap()];
        assert_eq!(
            body.split_whitespace().collect::<Vec<_>>(),
            first,
            "{d}D VTK"
        );

        let copy = tmp(&format!("trajectory-rough{d}-export"));
        std::fs::create_dir_all(copy.join("snapshots")).unwrap();
        std::fs::copy(dir.join("scenario.toml"), copy.join("scenario.toml")).unwrap();
        for p in &snapshots {
            std::fs::copy(p, copy.join("snapshots").join(p.file_name().unwrap())).unwrap();
        }
        RunDir::new(&copy)
            .export_trajectories(&Format::ALL)
            .unwrap();
        for name in FILES {
            assert!(
                read(&copy, name) == read(&dir, name),
                "{d}D: {name} differs"
            );
        }
    }
}
