//! The DSMC decomposition over ranks without MPI: K ranks as K threads of this process
//! (an in-process `Communicator`), each with its slab of the same engine, against the
//! undecomposed engine. The trajectory must be bit-identical for every K (the MPI build's
//! own test, over `mpirun`, is `scripts/test-mpi`). Short runs (a few dozen steps): every
//! step is some ten collectives, and a thread barrier is slow on a loaded machine.

use granular::collision_law::CollisionLaw;
use granular::dsmc::{Communicator, DensityScope, DsmcConfig, DsmcEngine, UniformGas, VmaxMode};
use granular::engine::Engine;
use granular::{AxisKind, SimulationBox, Vector};
use std::sync::{Arc, Barrier, Mutex};

/// K ranks as threads: every collective writes its part into shared slots, waits for the
/// others, reads, and waits again before the slots are reused.
#[derive(Debug)]
struct Threads {
    rank: usize,
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    size: usize,
    barrier: Barrier,
    /// `slots[from][to]`.
    slots: Mutex<Vec<Vec<Vec<f64>>>>,
    /// Point-to-point messages in flight, `mail[from * size + to]`, oldest first.
    mail: Mutex<Vec<std::collections::VecDeque<Vec<f64>>>>,
    /// Signalled when a message is posted.
    posted: std::sync::Condvar,
}

impl Threads {
    fn world(size: usize) -> Vec<Threads> {
        let shared = Arc::new(Shared {
            size,
            barrier: Barrier::new(size),
            slots: Mutex::new(vec![vec![Vec::new(); size]; size]),
            mail: Mutex::new(vec![Default::default(); size * size]),
            posted: std::sync::Condvar::new(),
        });
        (0..size)
            .map(|rank| Threads {
                rank,
                shared: shared.clone(),
            })
            .collect()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Vec<Vec<f64>>>> {
        self.shared
            .slots
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl Communicator for Threads {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        self.exchange(vec![local.to_vec(); self.size()])
    }

    fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        self.lock()[self.rank] = outgoing;
        self.shared.barrier.wait();
        let received = self
            .lock()
            .iter()
            .map(|row| row[self.rank].clone())
            .collect();
        self.shared.barrier.wait();
        received
    }

    fn send(&self, to: usize, words: &[f64]) {
        let mut mail = self
            .shared
            .mail
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        mail[self.rank * self.shared.size + to].push_back(words.to_vec());
        self.shared.posted.notify_all();
    }

    fn receive(&self, from: usize) -> Vec<f64> {
        let box_index = from * self.shared.size + self.rank;
        let mut mail = self
            .shared
            .mail
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        loop {
            if let Some(words) = mail[box_index].pop_front() {
                return words;
            }
            mail = self
                .shared
                .posted
                .wait(mail)
                .unwrap_or_else(std::sync::PoisonError::into_inner);
        }
    }
}

/// Walls across the cut with gravity along it, the TC model, Enskog with the cell's
/// density, free volume, consistent-Boltzmann advection, global `v_max`.
fn walled_2d() -> (DsmcConfig, SimulationBox<2>) {
    let config = DsmcConfig {
        law: CollisionLaw {
            restitution: 0.8,
            wall_restitution: 0.9,
            contact_duration: 1e-4,
            ..CollisionLaw::default()
        },
        gravity: vec![0.0, -2.0],
        enskog: true,
        density_scope: DensityScope::Cell,
        free_volume: true,
        consistent_boltzmann: true,
        vmax_mode: VmaxMode::Global,
        ..DsmcConfig::default()
    };
    let mut bx = SimulationBox::uniform(Vector([1.0, 1.0]), AxisKind::Wall);
    bx.axes[0] = AxisKind::Periodic;
    (config, bx)
}

fn periodic_3d() -> (DsmcConfig, SimulationBox<3>) {
    let config = DsmcConfig {
        law: CollisionLaw {
            restitution: 0.9,
            ..CollisionLaw::default()
        },
        enskog: true,
        consistent_boltzmann: true,
        ..DsmcConfig::default()
    };
    (
        config,
        SimulationBox::uniform(Vector([1.0, 1.0, 1.0]), AxisKind::Periodic),
    )
}

/// The observables and the whole state of `engine` after advancing it to each of `times`
/// (the state gathered from all ranks when decomposed).
fn history<const D: usize>(engine: &mut DsmcEngine<D>, times: &[f64]) -> Vec<Vec<u64>> {
    let mut out = Vec::new();
    for &t in times {
        engine.advance(t, u64::MAX).expect("the run goes on");
        let o = engine.observe();
        let whole = engine.whole();
        let mut bits: Vec<u64> = [o.kinetic_energy, o.temperature, o.a2.unwrap_or(0.0)]
            .iter()
            .map(|x| x.to_bits())
            .collect();
        bits.extend([o.collisions, o.events, engine.vmax_exceeded()]);
        // A driven gas's energy tally (empty without a driving).
        bits.extend(o.engine_specific.iter().map(|(_, x)| x.to_bits()));
        bits.extend(engine.impact_histogram().counts.iter().copied());
        for (x, v) in whole.positions().iter().zip(whole.velocities()) {
            bits.extend(x.0.iter().chain(&v.0).map(|c| c.to_bits()));
        }
        bits.extend(whole.ids().iter().map(|&i| u64::from(i)));
        out.push(bits);
    }
    out
}

fn check_rank_counts<const D: usize>(build: impl Fn() -> DsmcEngine<D> + Sync, times: &[f64]) {
    let reference = history(&mut build(), times);
    for k in 1..=4 {
        let results: Vec<Vec<Vec<u64>>> = std::thread::scope(|s| {
            let handles: Vec<_> = Threads::world(k)
                .into_iter()
                .map(|comm| {
                    let build = &build;
                    s.spawn(move || {
                        let mut e = build();
                        e.decompose(Arc::new(comm)).expect("enough cell planes");
                        history(&mut e, times)
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a rank panicked"))
                .collect()
        });
        for (rank, r) in results.iter().enumerate() {
            assert!(
                r == &reference,
                "{D}D, {k} ranks: rank {rank} differs from the undecomposed engine"
            );
        }
    }
}

#[test]
fn decomposed_walled_2d_is_bit_identical_for_1_to_4_ranks() {
    let (config, bx) = walled_2d();
    check_rank_counts(
        || DsmcEngine::<2>::new(config.clone(), bx.clone(), 3000, 0.004, 1.0, 1.0, 5).unwrap(),
        &[0.004, 0.01, 0.02],
    );
}

#[test]
fn decomposed_periodic_3d_is_bit_identical_for_1_to_4_ranks() {
    let (config, bx) = periodic_3d();
    check_rank_counts(
        || DsmcEngine::<3>::new(config.clone(), bx.clone(), 3000, 0.01, 1.0, 1.0, 9).unwrap(),
        &[0.01, 0.02],
    );
}

/// A checkpoint holds the whole engine: restored from `whole()` of 3 ranks and split over
/// 2, the run continues exactly as the undecomposed one.
#[test]
fn decomposed_state_moves_to_another_rank_count() {
    let (config, bx) = walled_2d();
    let build = || DsmcEngine::<2>::new(config.clone(), bx.clone(), 3000, 0.004, 1.0, 1.0, 5);
    let mut plain = build().unwrap();
    let reference = history(&mut plain, &[0.006, 0.015]);
    let middle: DsmcEngine<2> = std::thread::scope(|s| {
        let handles: Vec<_> = Threads::world(3)
            .into_iter()
            .map(|comm| {
                s.spawn(move || {
                    let mut e = build().unwrap();
                    e.decompose(Arc::new(comm)).unwrap();
                    e.advance(0.006, u64::MAX).unwrap();
                    e.whole()
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap())
            .next()
            .unwrap()
    });
    let resumed: Vec<Vec<Vec<u64>>> = std::thread::scope(|s| {
        let handles: Vec<_> = Threads::world(2)
            .into_iter()
            .map(|comm| {
                let mut e = middle.clone();
                s.spawn(move || {
                    e.decompose(Arc::new(comm)).unwrap();
                    history(&mut e, &[0.015])
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for r in &resumed {
        assert!(r[0] == reference[1], "resumed on 2 ranks differs");
    }
}

#[test]
fn more_ranks_than_cell_planes_is_an_error_naming_both() {
    let (mut config, bx) = walled_2d();
    config.cell_size = Some(0.5);
    let comm = Threads::world(3).into_iter().next().unwrap();
    let mut e = DsmcEngine::<2>::new(config, bx, 100, 0.004, 1.0, 1.0, 5).unwrap();
    let err = e.decompose(Arc::new(comm)).unwrap_err().to_string();
    assert!(err.contains("3 ranks but only 2 cell planes"), "{err}");
}

/// The steady-state drivings (`granular::driving`) act after every step with per-grain
/// kick streams and ordered reductions: a white-noise (2D) and a rescaled (3D) gas are
/// bit-identical for 1 to 4 ranks, and so is the driving's energy tally.
#[test]
fn decomposed_driven_gases_are_bit_identical_for_1_to_4_ranks() {
    use granular::driving::Driving;
    let (mut config, _) = periodic_3d();
    config.law.restitution = 0.6;
    let bx2 = SimulationBox::uniform(Vector([1.0, 1.0]), AxisKind::Periodic);
    let cfg2 = DsmcConfig {
        law: CollisionLaw::uniform(0.6),
        ..DsmcConfig::default()
    };
    check_rank_counts(
        || {
            let mut e =
                DsmcEngine::<2>::new(cfg2.clone(), bx2.clone(), 3000, 0.004, 1.0, 1.0, 5).unwrap();
            e.set_driving(Some(Driving::WhiteNoise { strength: 3.0 }));
            e
        },
        &[0.004, 0.01, 0.02],
    );
    let bx3 = SimulationBox::uniform(Vector([1.0, 1.0, 1.0]), AxisKind::Periodic);
    check_rank_counts(
        || {
            let mut e =
                DsmcEngine::<3>::new(config.clone(), bx3.clone(), 3000, 0.01, 1.0, 1.0, 9).unwrap();
            e.set_driving(Some(Driving::Rescale { temperature: 1.0 }));
            e
        },
        &[0.01, 0.02],
    );
}

/// A rank that records the most words it received in one collective: a rank that
/// gathered every particle would receive at least `N (1 + 2 D)` words at once.
#[derive(Debug)]
struct Counting {
    inner: Threads,
    most: Arc<std::sync::atomic::AtomicUsize>,
}

impl Counting {
    fn note(&self, received: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let words = received.iter().map(Vec::len).sum();
        self.most
            .fetch_max(words, std::sync::atomic::Ordering::Relaxed);
        received
    }
}

impl Communicator for Counting {
    fn rank(&self) -> usize {
        self.inner.rank
    }

    fn size(&self) -> usize {
        self.inner.size()
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        self.note(self.inner.all_gather(local))
    }

    fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        self.note(self.inner.exchange(outgoing))
    }

    fn send(&self, to: usize, words: &[f64]) {
        self.inner.send(to, words);
    }

    fn receive(&self, from: usize) -> Vec<f64> {
        let words = self.inner.receive(from);
        self.most
            .fetch_max(words.len(), std::sync::atomic::Ordering::Relaxed);
        words
    }
}

/// Runs `f(communicator, the most words it received)` on `k` ranks (threads).
pub(crate) fn on_ranks<T: Send>(
    k: usize,
    f: impl Fn(Arc<dyn Communicator>, &std::sync::atomic::AtomicUsize) -> T + Sync,
) -> Vec<T> {
    std::thread::scope(|s| {
        let f = &f;
        let handles: Vec<_> = Threads::world(k)
            .into_iter()
            .map(|inner| {
                s.spawn(move || {
                    let most = Arc::new(std::sync::atomic::AtomicUsize::new(0));
                    let comm = Counting {
                        inner,
                        most: most.clone(),
                    };
                    f(Arc::new(comm), &most)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a rank panicked"))
            .collect()
    })
}

const RUN_GRAINS: usize = 3000;

fn run_scenario() -> granular::scenario::Scenario {
    let text = format!(
        r#"
        engine = "dsmc"
        dimension = 2
        seed = 5
        gravity = [0.0, -2.0]
        [box]
        lengths = [1.0, 1.0]
        boundary = ["periodic", "wall"]
        [[species]]
        name = "grain"
        count = {RUN_GRAINS}
        packing_fraction = 0.1
        velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
        [collisions]
        restitution = 0.8
        wall_restitution = 0.9
        contact_duration = 1e-4
        [dsmc]
        enskog = true
        consistent_boltzmann = true
        [stop]
        time = 0.05
        [output]
        interval = 0.005
        snapshot_every = 2
        checkpoint_seconds = 1e-9
        equilibration_collisions_per_particle = 1e9
        msd = true
        trajectory = ["gsd", "xyz"]
        "#
    );
    granular::scenario::Scenario::from_toml(&text, &[]).expect("valid scenario")
}

/// This rank's directory: the shared run directory on rank 0, `own` elsewhere (with a
/// copy of the shared directory's files when `copy`, as the command line's ranks do).
pub(crate) fn rank_dir(
    rank: usize,
    shared: &std::path::Path,
    own: &std::path::Path,
    copy: bool,
) -> std::path::PathBuf {
    if rank == 0 {
        return shared.to_path_buf();
    }
    let dir = own.join(format!("rank{rank}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    if copy {
        for entry in std::fs::read_dir(shared).unwrap().flatten() {
            let target = dir.join(entry.file_name());
            if entry.path().is_dir() {
                std::fs::create_dir_all(&target).unwrap();
            } else if entry.file_name() != ".lock" {
                std::fs::copy(entry.path(), &target).unwrap();
            }
        }
    }
    dir
}

/// A run over 3 ranks writes its checkpoints in parts and its snapshots by blocks of ids
/// (no rank ever receives all particles at once), stops after 2 outputs; resumed from the
/// parts on 2 ranks it ends with the threaded run's time series and snapshots, bit for bit.
#[test]
fn decomposed_run_writes_parts_and_resumes_on_another_rank_count() {
    use granular::run::{Run, RunError, read_snapshot};
    let threaded = crate::common::tmp("threaded");
    Run::create(&threaded, run_scenario())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let shared = crate::common::tmp("ranks");
    let own = crate::common::tmp("ranks-own");
    // A gather of every particle would receive N (1 + 2 D) words in one collective.
    let whole = RUN_GRAINS * 5;
    let most = on_ranks(3, |comm, most| {
        let rank = comm.rank();
        let mut run = Run::create(&rank_dir(rank, &shared, &own, false), run_scenario()).unwrap();
        run.decompose(comm, &shared).unwrap();
        match run.run_to_end(&mut |_| {}, Some(2)) {
            Err(RunError::Checkpoint { message, .. }) if message.contains("on request") => {}
            other => panic!("rank {rank}: expected the test interruption, got {other:?}"),
        }
        most.load(std::sync::atomic::Ordering::Relaxed)
    });
    // The engine's parts (the MSD's per-grain state is in `.rows.msgpack` files beside).
    let parts: Vec<_> = std::fs::read_dir(shared.join("checkpoint.parts"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|f| !f.contains(".rows."))
        .collect();
    assert_eq!(
        parts.len(),
        3,
        "one part per rank of the last checkpoint: {parts:?}"
    );
    let most_resumed = on_ranks(2, |comm, most| {
        let rank = comm.rank();
        let dir = rank_dir(rank, &shared, &own, true);
        let run = Run::resume_decomposed(&dir, &shared, comm).unwrap();
        run.run_to_end(&mut |_| {}, None).unwrap();
        most.load(std::sync::atomic::Ordering::Relaxed)
    });
    // The most a rank receives at once while the run sets its outputs up and writes its
    // checkpoints and snapshots: its block of ids for a snapshot or the speed histograms
    // (N / K records); the chained sums pass and gather a few accumulators; a gather of
    // the whole system would be `whole`.
    assert_eq!(most.len(), 3);
    for (k, most) in [(3, &most), (2, &most_resumed)] {
        for (rank, &w) in most.iter().enumerate() {
            assert!(
                w < whole,
                "{k} ranks: rank {rank} received {w} words in one collective, as many as \
                 all particles' records ({whole})"
            );
        }
    }
    let read = |d: &std::path::Path, f: &str| std::fs::read(d.join(f)).unwrap();
    for f in [
        "timeseries.csv",
        "mean_square_displacement.csv",
        "velocity_autocorrelation.csv",
        "trajectory/trajectory.gsd",
        "trajectory/trajectory.xyz",
    ] {
        assert!(
            read(&shared, f) == read(&threaded, f),
            "{f}: resumed on 2 ranks, not the threaded run's bytes"
        );
    }
    assert!(
        !shared.join("checkpoint.parts").exists(),
        "parts left after the end"
    );
    let mut names: Vec<_> = std::fs::read_dir(threaded.join("snapshots"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    names.sort();
    let ours = std::fs::read_dir(shared.join("snapshots"))
        .unwrap()
        .flatten()
        .count();
    assert_eq!(ours, names.len(), "snapshot files (and no block left over)");
    assert!(names.len() >= 3);
    for name in &names {
        let a = read_snapshot(threaded.join("snapshots").join(name)).unwrap();
        let b = read_snapshot(shared.join("snapshots").join(name)).unwrap();
        assert!(
            a.positions == b.positions
                && a.velocities == b.velocities
                && a.radii == b.radii
                && a.masses == b.masses
                && a.species == b.species
                && a.species_names == b.species_names
                && a.time.to_bits() == b.time.to_bits(),
            "{name:?} differs from the threaded run's"
        );
        let f = format!("snapshots/{}", name.to_string_lossy());
        assert!(
            read(&shared, &f) == read(&threaded, &f),
            "{f}: not the same bytes"
        );
    }
    for d in [threaded, shared, own] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// Grains of `outputs_scenario`: more than two chunks of 4096 ids, so that chunks of the
/// `S(k)` sums run across the blocks of 3 ranks.
const OUTPUT_GRAINS: usize = 10_000;

/// The walled, driven-by-gravity gas of `run_scenario` with every output that reads the
/// grains by blocks on: the speed histograms pool every output (the gas cools, so the
/// speeds scaled by each snapshot's thermal speed are written too), `S(k)` and a density
/// map at every output; no checkpoints.
fn outputs_scenario() -> granular::scenario::Scenario {
    let text = format!(
        r#"
        engine = "dsmc"
        dimension = 2
        seed = 5
        gravity = [0.0, -2.0]
        [box]
        lengths = [1.0, 1.0]
        boundary = ["periodic", "wall"]
        [[species]]
        name = "grain"
        count = {OUTPUT_GRAINS}
        packing_fraction = 0.1
        velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
        [collisions]
        restitution = 0.8
        wall_restitution = 0.9
        [dsmc]
        enskog = true
        [stop]
        time = 0.04
        [output]
        interval = 0.01
        equilibration_collisions_per_particle = 0.0
        histogram_sample_spacing = 1e-6
        structure_factor = true
        structure_factor_max_index = 4
        density_map = [6, 5]
        "#
    );
    granular::scenario::Scenario::from_toml(&text, &[]).expect("valid scenario")
}

/// `summary.json` without its wall-clock fields and the `ranks` block (how the ranks of a
/// decomposed run shared the grains; absent in a threaded run).
pub(crate) fn summary_without_clock(dir: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    let mut v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    if let Some(o) = v.as_object_mut() {
        for k in [
            "wall_seconds",
            "events_per_second",
            "collisions_per_second",
            "ranks",
        ] {
            o.remove(k);
        }
    }
    v
}

/// The outputs that read the grains (the speed histograms at set-up and pooled at every
/// output, the scaled speeds, `S(k)`, the density map) on 2 and 3 ranks: no rank ever receives as many words in
/// one collective as all particles' records (set-up included), and `summary.json` and
/// every file they write are the threaded run's, byte for byte.
#[test]
fn decomposed_outputs_gather_no_rank_and_match_the_threaded_run() {
    use granular::run::Run;
    let scenario = outputs_scenario();
    let threaded = crate::common::tmp("outputs-threaded");
    Run::create(&threaded, scenario.clone())
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let files = [
        "timeseries.csv",
        "speed_histograms.csv",
        "velocity_histograms.csv",
        "scaled_speed_histograms.csv",
        "structure_factor.npz",
        "density_maps.npz",
    ];
    for f in files {
        assert!(threaded.join(f).exists(), "the threaded run wrote no {f}");
    }
    let whole = OUTPUT_GRAINS * 5;
    for k in [2, 3] {
        let shared = crate::common::tmp("outputs-ranks");
        let own = crate::common::tmp("outputs-ranks-own");
        let most = on_ranks(k, |comm, most| {
            let rank = comm.rank();
            let mut run =
                Run::create(&rank_dir(rank, &shared, &own, false), scenario.clone()).unwrap();
            run.decompose(comm, &shared).unwrap();
            run.run_to_end(&mut |_| {}, None).unwrap();
            most.load(std::sync::atomic::Ordering::Relaxed)
        });
        for (rank, &w) in most.iter().enumerate() {
            assert!(
                w < whole,
                "{k} ranks: rank {rank} received {w} words in one collective, as many as \
                 all particles' records ({whole})"
            );
        }
        assert_eq!(
            summary_without_clock(&shared),
            summary_without_clock(&threaded),
            "{k} ranks: summary.json differs from the threaded run's"
        );
        for f in files {
            let a = std::fs::read(threaded.join(f)).unwrap();
            let b = std::fs::read(shared.join(f)).unwrap();
            assert!(a == b, "{k} ranks: {f} differs from the threaded run's");
        }
        for d in [shared, own] {
            let _ = std::fs::remove_dir_all(d);
        }
    }
    let _ = std::fs::remove_dir_all(threaded);
}

/// `new_decomposed` on each of `k = 1..=4` ranks creates exactly the slab that
/// `decompose` keeps of the whole `new` engine (particles, storage order, cell ranges, TC
/// times, time step, grid, validity warnings), without receiving a single particle from
/// another rank, and then runs the whole engine's trajectory bit for bit (with `driving`
/// set after the set-up, as a run does).
fn check_slab_setup<const D: usize>(
    config: &DsmcConfig,
    bx: &SimulationBox<D>,
    gas: UniformGas,
    driving: Option<granular::driving::Driving>,
    times: &[f64],
) {
    let seed = 11;
    let whole = || {
        let mut e = DsmcEngine::<D>::new(
            config.clone(),
            bx.clone(),
            gas.n,
            gas.radius,
            gas.mass,
            gas.temperature,
            seed,
        )
        .unwrap();
        e.set_driving(driving.clone());
        e
    };
    let reference = history(&mut whole(), times);
    for k in 1..=4 {
        let results = on_ranks(k, |comm, most| {
            let mut slab = DsmcEngine::<D>::new_decomposed(
                config.clone(),
                bx.clone(),
                gas,
                seed,
                comm.clone(),
            )
            .unwrap();
            slab.set_driving(driving.clone());
            let received = most.load(std::sync::atomic::Ordering::Relaxed);
            let mut cut = whole();
            cut.decompose(comm).unwrap();
            let set_up = |e: &DsmcEngine<D>| {
                format!(
                    "{:?} {:?} {} {:?} {} {:?} {}",
                    e.part(),
                    e.driving(),
                    e.time_step().to_bits(),
                    e.grid().dims,
                    e.enskog_factor().to_bits(),
                    e.validity_warnings(),
                    e.particle_count()
                )
            };
            let same = set_up(&slab) == set_up(&cut);
            (
                same,
                received,
                slab.positions().len(),
                history(&mut slab, times),
            )
        });
        let mut held = 0;
        for (rank, (same, received, local, h)) in results.iter().enumerate() {
            assert!(
                same,
                "{D}D, {k} ranks: rank {rank}'s set-up is not the whole engine's slab"
            );
            // A gather of the whole system would be N (1 + 2 D) words at once; the set-up's
            // reductions (the validity check's temperature) receive at most N D here.
            assert!(
                *received < gas.n * (1 + 2 * D),
                "{D}D, {k} ranks: rank {rank} received {received} words in one collective \
                 during the set-up, as many as all particles' records"
            );
            assert!(
                h == &reference,
                "{D}D, {k} ranks: rank {rank}'s trajectory differs from the whole engine's"
            );
            held += local;
        }
        assert_eq!(held, gas.n, "{D}D, {k} ranks: every grain on one rank");
    }
}

#[test]
fn slab_setup_is_the_slab_of_the_whole_setup_for_1_to_4_ranks() {
    // 2D: walls across the cut, gravity, the TC model, Enskog, free volume, automatic
    // time step and cell size (the initial temperature's sums).
    let (config, bx) = walled_2d();
    let gas = UniformGas {
        n: 3000,
        radius: 0.004,
        mass: 1.0,
        temperature: 1.0,
    };
    check_slab_setup(&config, &bx, gas, None, &[0.004, 0.01]);
    // 3D periodic, automatic time step; then walled along the cut with a fixed time step
    // and cell size, another mass and temperature, driven by white noise.
    let (mut config, mut bx) = periodic_3d();
    let gas = UniformGas {
        n: 3000,
        radius: 0.01,
        mass: 1.0,
        temperature: 1.0,
    };
    check_slab_setup(&config, &bx, gas, None, &[0.01, 0.02]);
    bx.axes[2] = AxisKind::Wall;
    config.time_step = Some(2e-3);
    config.cell_size = Some(0.125);
    config.gravity = vec![0.0, 0.0, -1.0];
    let gas = UniformGas {
        n: 2500,
        radius: 0.01,
        mass: 2.0,
        temperature: 0.5,
    };
    let noise = granular::driving::Driving::WhiteNoise { strength: 3.0 };
    check_slab_setup(&config, &bx, gas, Some(noise), &[0.006]);
}

#[test]
fn slab_setup_with_more_ranks_than_cell_planes_is_an_error_naming_both() {
    let (mut config, bx) = walled_2d();
    config.cell_size = Some(0.5);
    let gas = UniformGas {
        n: 100,
        radius: 0.004,
        mass: 1.0,
        temperature: 1.0,
    };
    let comm = Threads::world(3).into_iter().next().unwrap();
    let err = DsmcEngine::<2>::new_decomposed(config, bx, gas, 5, Arc::new(comm))
        .unwrap_err()
        .to_string();
    assert!(err.contains("3 ranks but only 2 cell planes"), "{err}");
}

/// Grains of [`mixed_scenario`].
const MIXED_GRAINS: usize = 6000;

/// Two species of equal grains in two regions (the lower one Maxwellian at temperature
/// 1, the upper one at a fixed speed), placed at random, a snapshot at every second
/// output; `driven`: a periodic box with white-noise driving, else walls across the cut
/// with gravity along it (driving needs a periodic box). `set`: overrides.
fn mixed_scenario(driven: bool, set: &[&str]) -> granular::scenario::Scenario {
    let (boundary, gravity, law, driving) = if driven {
        (
            r#""periodic""#,
            "",
            "",
            "[driving]\nkind = \"white_noise\"\nstrength = 1.0",
        )
    } else {
        (
            r#"["periodic", "wall"]"#,
            "gravity = [0.0, -1.0]",
            "wall_restitution = 0.9",
            "",
        )
    };
    let text = format!(
        r#"
        engine = "dsmc"
        dimension = 2
        seed = 9
        {gravity}
        [box]
        lengths = [1.0, 1.0]
        boundary = {boundary}
        [[species]]
        name = "low"
        count = {}
        radius = 0.002
        region = {{ lo = [0.0, 0.0], hi = [1.0, 0.4] }}
        velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
        [[species]]
        name = "high"
        count = {}
        radius = 0.002
        region = {{ lo = [0.0, 0.7], hi = [1.0, 1.0] }}
        velocity = {{ distribution = "fixed_speed", speed = 1.5 }}
        [collisions]
        restitution = 0.8
        {law}
        [stop]
        time = 0.03
        [output]
        interval = 0.003
        snapshot_every = 4
        equilibration_collisions_per_particle = 0.0
        msd = true
        trajectory = ["gsd"]
        {driving}
        "#,
        MIXED_GRAINS * 2 / 3,
        MIXED_GRAINS / 3
    );
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    granular::scenario::Scenario::from_toml(&text, &set).expect("valid scenario")
}

/// Records, at the end of a run, the most grains its rank held at a time and how often
/// the cuts moved.
struct Peak(Arc<Mutex<(usize, u64)>>);

impl granular::Output for Peak {
    fn observe(
        &mut self,
        _: &granular::Simulation,
        _: &granular::Observation,
    ) -> Result<(), granular::RunError> {
        Ok(())
    }

    fn finish(
        &mut self,
        simulation: &granular::Simulation,
        _: &mut granular::Summary,
    ) -> Result<(), granular::RunError> {
        if let Some(d) = simulation.engine().domain() {
            *self.0.lock().unwrap() = (d.peak_grains(), d.recuts());
        }
        Ok(())
    }
}

/// Runs `scenario` on `k` ranks, each creating only its own grains, into `shared`;
/// returns every rank's peak grains and re-cuts.
fn run_on_ranks(
    k: usize,
    scenario: &granular::scenario::Scenario,
    shared: &std::path::Path,
) -> Vec<(usize, u64)> {
    use granular::run::Run;
    let own = crate::common::tmp("on-ranks-own");
    let peaks = on_ranks(k, |comm, _| {
        let rank = comm.rank();
        let dir = rank_dir(rank, shared, &own, false);
        let mut run = Run::create_on(&dir, scenario.clone(), Some(comm), shared, None).unwrap();
        let peak = Arc::new(Mutex::new((0, 0)));
        run.attach(Box::new(Peak(peak.clone())));
        run.run_to_end(&mut |_| {}, None).unwrap();
        *peak.lock().unwrap()
    });
    let _ = std::fs::remove_dir_all(own);
    peaks
}

/// The files of a run directory that must be the threaded run's, byte for byte.
fn same_files(a: &std::path::Path, b: &std::path::Path, what: &str) {
    assert_eq!(
        summary_without_clock(a),
        summary_without_clock(b),
        "{what}: summary.json differs from the threaded run's"
    );
    for f in [
        "timeseries.csv",
        "speed_histograms.csv",
        "velocity_histograms.csv",
        "mean_square_displacement.csv",
        "velocity_autocorrelation.csv",
        "trajectory/trajectory.gsd",
    ] {
        assert!(
            std::fs::read(a.join(f)).unwrap() == std::fs::read(b.join(f)).unwrap(),
            "{what}: {f} differs from the threaded run's"
        );
    }
    // The other trajectory formats, where the run writes them.
    let vtp: Vec<String> = std::fs::read_dir(a.join("trajectory/vtp"))
        .map(|d| {
            d.flatten()
                .map(|e| format!("trajectory/vtp/{}", e.file_name().to_string_lossy()))
                .collect()
        })
        .unwrap_or_default();
    for f in [
        "trajectory/trajectory.xyz",
        "trajectory/trajectory.lammpstrj",
        "trajectory/trajectory.pvd",
    ]
    .into_iter()
    .map(String::from)
    .chain(vtp)
    {
        if a.join(&f).exists() {
            assert!(
                std::fs::read(a.join(&f)).unwrap() == std::fs::read(b.join(&f)).unwrap(),
                "{what}: {f} differs from the threaded run's"
            );
        }
    }
    let mut names: Vec<_> = std::fs::read_dir(a.join("snapshots"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    names.sort();
    assert!(names.len() >= 3, "{what}: snapshots {names:?}");
    for name in names {
        let f = std::path::Path::new("snapshots").join(name);
        assert!(
            std::fs::read(a.join(&f)).unwrap() == std::fs::read(b.join(&f)).unwrap(),
            "{what}: {} differs from the threaded run's",
            f.display()
        );
    }
}

/// Every rank creates only its own grains (two species in two regions, random placement,
/// walls, gravity, driving; the MSD and a GSD trajectory on): on 1 to 4 ranks, with the cuts following the grains by count
/// (the default: the regions leave the middle of the box empty, so equal slabs would load
/// the ranks unevenly), by measured time, or fixed, the run writes the threaded run's
/// files bit for bit; no rank ever holds more than its share of the grains and one
/// migration's buffers (far from all of them).
#[test]
fn per_rank_setup_is_the_threaded_run_for_any_ranks_and_cuts() {
    use granular::run::Run;
    for driven in [false, true] {
        let threaded = crate::common::tmp("mixed-threaded");
        Run::create(&threaded, mixed_scenario(driven, &[]))
            .unwrap()
            .run_to_end(&mut |_| {}, None)
            .unwrap();
        let cases: &[(usize, &str)] = if driven {
            &[(2, "count"), (4, "time")]
        } else {
            &[
                (1, "count"),
                (2, "count"),
                (3, "count"),
                (4, "count"),
                (3, "off"),
            ]
        };
        for &(k, balance) in cases {
            check_mixed_on_ranks(&threaded, driven, k, balance);
        }
        let _ = std::fs::remove_dir_all(threaded);
    }
}

/// Rough grains created by each rank (spinning from the start, walls and gravity): their
/// angular velocities go to their ranks with the rest of the record, in every round of
/// the set-up's exchange, and the run writes the threaded run's files bit for bit (the
/// trajectories in every format, with the spins that rank 0 reads from the ranks' blocks).
#[test]
fn rough_per_rank_setup_is_the_threaded_run() {
    use granular::run::Run;
    let spin = r#"{ distribution = "maxwell_boltzmann", temperature = 1.0 }"#;
    let set = [
        "collisions.tangential_restitution=0.5".to_string(),
        format!("species[0].angular_velocity={spin}"),
        format!("species[1].angular_velocity={spin}"),
        r#"output.trajectory=["gsd", "xyz", "lammps", "vtk"]"#.to_string(),
    ];
    let set: Vec<&str> = set.iter().map(String::as_str).collect();
    let threaded = crate::common::tmp("rough-threaded");
    Run::create(&threaded, mixed_scenario(false, &set))
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    for k in [2, 3] {
        let shared = crate::common::tmp("rough-ranks");
        run_on_ranks(k, &mixed_scenario(false, &set), &shared);
        same_files(&threaded, &shared, &format!("rough grains on {k} ranks"));
        let _ = std::fs::remove_dir_all(shared);
    }
    let _ = std::fs::remove_dir_all(threaded);
}

/// [`per_rank_setup_is_the_threaded_run_for_any_ranks_and_cuts`] on `k` ranks.
fn check_mixed_on_ranks(threaded: &std::path::Path, driven: bool, k: usize, balance: &str) {
    {
        let set = format!("dsmc.balance=\"{balance}\"");
        let scenario = mixed_scenario(driven, &[&set, "dsmc.balance_every=3"]);
        let shared = crate::common::tmp("mixed-ranks");
        let peaks = run_on_ranks(k, &scenario, &shared);
        let what = format!("{k} ranks, balance {balance}, driven {driven}");
        same_files(threaded, &shared, &what);
        // summary.json's `ranks` block: every rank's peak as the rank itself counted it.
        let summary: granular::Summary = serde_json::from_str(
            &std::fs::read_to_string(shared.join("summary.json")).expect("summary.json"),
        )
        .expect("summary");
        let ranks = summary.ranks.expect("a ranks block");
        assert_eq!(ranks.ranks, k, "{what}");
        let counted: Vec<usize> = peaks.iter().map(|p| p.0).collect();
        assert_eq!(ranks.peak_grains, counted, "{what}");
        assert_eq!(
            ranks.final_grains.iter().sum::<usize>(),
            MIXED_GRAINS,
            "{what}"
        );
        assert_eq!(ranks.cuts_moved, peaks[0].1, "{what}");
        let even = MIXED_GRAINS as f64 / k as f64;
        let most = *counted.iter().max().unwrap_or(&0) as f64;
        assert!(
            (ranks.peak_over_even_share - most / even).abs() < 1e-12,
            "{what}"
        );
        if k > 1 && balance == "count" {
            for (rank, &(peak, _)) in peaks.iter().enumerate() {
                // Balanced (own grains within 5 % of N / K): its own grains, its block of
                // ids (N / K, at the set-up and when the outputs read the grains by
                // blocks) and the buffers of one exchange: at most 3 N / K and a margin,
                // which on 4 ranks is well below N.
                let bound = 3 * MIXED_GRAINS / k + MIXED_GRAINS / (4 * k);
                assert!(
                    peak > 0 && peak <= bound,
                    "{what}: rank {rank} held {peak} grains at a time (bound {bound})"
                );
                if k == 4 {
                    assert!(peak < MIXED_GRAINS, "{what}: rank {rank} held {peak}");
                }
            }
        }
        if k > 1 && balance == "time" {
            // By time the cuts share the measured time, not the grains, but never give a
            // rank more than TIME_SHARE_CAP (2) times the mean grains: its own grains, as
            // many in the buffers of an exchange, and a block of ids (N / K), with the
            // same margin as above.
            let own = (granular::dsmc::domain::TIME_SHARE_CAP * MIXED_GRAINS as f64) as usize / k;
            let bound = 2 * own + MIXED_GRAINS / k + MIXED_GRAINS / (4 * k);
            for (rank, &(peak, _)) in peaks.iter().enumerate() {
                assert!(
                    peak > 0 && peak <= bound,
                    "{what}: rank {rank} held {peak} grains at a time (bound {bound})"
                );
            }
        }
        let _ = std::fs::remove_dir_all(shared);
    }
}
