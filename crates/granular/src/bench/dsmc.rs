//! Throughput of the DSMC engine: on threads (`granular bench dsmc`, [`measure`]) and
//! split over the ranks of `mpirun` (`granular bench dsmc-ranks`, [`measure_decomposed`]).

use super::BenchError;
use crate::boundary::{AxisKind, SimulationBox};
use crate::dsmc::domain::{Communicator, Traffic};
use crate::dsmc::{DsmcConfig, DsmcEngine, UniformGas};
use crate::theory::haff;
use crate::vector::Vector;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One benchmark measurement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchResult {
    /// 2 or 3.
    pub dimension: usize,
    /// Number of particles.
    pub n: usize,
    /// Worker threads.
    pub threads: usize,
    /// Steps in the reported (fastest) segment.
    pub steps: u64,
    /// Wall time of the reported segment, seconds.
    pub seconds: f64,
    /// `n * steps / seconds`.
    pub particle_steps_per_second: f64,
    /// Accepted collisions per second.
    pub collisions_per_second: f64,
    /// Collisions suffered per particle per step, `2 C / (N steps)` (about 0.1 by construction).
    pub collisions_per_particle_step: f64,
    /// Bytes the engine holds per grain (its records, the sort's scratch column and
    /// destinations, the cells' offsets: `DsmcEngine::held_bytes` over `N`).
    #[serde(default)]
    pub bytes_per_grain: f64,
    /// This machine's copy bandwidth measured right after, bytes read plus bytes written
    /// per second ([`copy_bandwidth`] of two buffers the size of the grains' records).
    #[serde(default)]
    pub copy_bytes_per_second: f64,
}

/// The bandwidth of a plain copy between two buffers of `bytes` bytes each (STREAM's
/// "copy"): bytes read plus bytes written per second, the best of `repeats` copies on this
/// thread (a store to a line not in the cache also reads it, which the count leaves out,
/// as STREAM does).
pub fn copy_bandwidth(bytes: usize, repeats: usize) -> f64 {
    let words = (bytes / 8).max(1);
    let src: Vec<u64> = (0..words as u64).collect();
    let mut dst = vec![0u64; words];
    let mut best = f64::INFINITY;
    for r in 0..repeats.max(1) {
        let t = Instant::now();
        dst.copy_from_slice(&src);
        best = best.min(t.elapsed().as_secs_f64());
        // Keeps the copy observable.
        if dst[r % words] == u64::MAX {
            best = f64::INFINITY;
        }
    }
    16.0 * words as f64 / best
}

/// The benchmark set-up: periodic cube of `n` grains at packing fraction 0.01, `T = m = 1`,
/// about 10 particles per cell, time step 0.1 mean free times (each particle suffers 0.1
/// collisions per step on average, i.e. 0.05 pair collisions per particle), elastic.
pub fn setup<const D: usize>(n: usize, seed: u64) -> Result<DsmcEngine<D>, BenchError> {
    setup_at::<D>(n, 0.01, seed)
}

/// [`setup`] at packing fraction `phi`.
pub fn setup_at<const D: usize>(
    n: usize,
    phi: f64,
    seed: u64,
) -> Result<DsmcEngine<D>, BenchError> {
    let (config, bx, gas) = case_at::<D>(n, phi);
    Ok(DsmcEngine::new(
        config,
        bx,
        gas.n,
        gas.radius,
        gas.mass,
        gas.temperature,
        seed,
    )?)
}

/// The configuration, box and gas of [`setup_at`].
fn case_at<const D: usize>(n: usize, phi: f64) -> (DsmcConfig, SimulationBox<D>, UniformGas) {
    let radius = 1.0;
    let v = haff::grain_volume(D, radius);
    let side = (n as f64 * v / phi).powf(1.0 / D as f64);
    let density = n as f64 / side.powi(D as i32);
    let omega = haff::collision_frequency(D, density, radius, 1.0, 1.0, 1.0);
    let cell = (10.0 / density).powf(1.0 / D as f64);
    let config = DsmcConfig {
        time_step: crate::dsmc::config::automatic_time_step(omega),
        cell_size: Some(side / (side / cell).round().max(1.0)),
        ..DsmcConfig::default()
    };
    let bx = SimulationBox::uniform(Vector([side; D]), AxisKind::Periodic);
    let gas = UniformGas {
        n,
        radius,
        mass: 1.0,
        temperature: 1.0,
    };
    (config, bx, gas)
}

fn run<const D: usize>(
    n: usize,
    threads: usize,
    tangential_restitution: f64,
) -> Result<BenchResult, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    pool.install(|| {
        let mut e = setup::<D>(n, 1)?;
        if tangential_restitution != -1.0 {
            // Rough grains (uniform disks or spheres) spinning at the rotational
            // temperature T_r = T_t = 1 (equipartition: with β = 1 no energy moves between
            // translation and rotation and the collision rate stays that of the smooth
            // case); each component Gaussian with variance T_r / I, I = κ m R².
            let law = crate::collision_law::CollisionLaw {
                tangential_restitution,
                ..e.config().law.clone()
            };
            let r = crate::collision_law::rough::rotational_dof(D);
            let kappa = crate::collision_law::rough::uniform_inertia(D);
            let width = (1.0 / (kappa * e.mass() * e.radius() * e.radius())).sqrt();
            let mut rng = crate::random::stream(1, &[crate::random::INITIAL_STATE, 1]);
            let spins: Vec<f64> = (0..r * n)
                .map(|_| width * crate::random::std_normal(&mut rng))
                .collect();
            e.make_rough(law, kappa, &spins)?;
        }
        let tau = e.time_step();
        for _ in 0..2 {
            e.step(tau);
        }
        // Best of three timed segments (robust against other load on shared machines).
        let steps = (1e7 / n as f64).ceil().clamp(5.0, 1000.0) as u64;
        let mut seconds = f64::INFINITY;
        let mut coll = 0.0;
        for _ in 0..3 {
            let c0 = crate::engine::Engine::collisions(&e);
            let t = Instant::now();
            for _ in 0..steps {
                e.step(tau);
            }
            let s = t.elapsed().as_secs_f64();
            if s < seconds {
                seconds = s;
                coll = (crate::engine::Engine::collisions(&e) - c0) as f64;
            }
        }
        let held = e.held_bytes() as f64;
        let copy = copy_bandwidth(16 * D * n, 7);
        Ok(BenchResult {
            dimension: D,
            n,
            threads,
            steps,
            seconds,
            particle_steps_per_second: n as f64 * steps as f64 / seconds,
            collisions_per_second: coll / seconds,
            collisions_per_particle_step: 2.0 * coll / (n as f64 * steps as f64),
            bytes_per_grain: held / n as f64,
            copy_bytes_per_second: copy,
        })
    })
}

/// Peak bytes per particle of the DSMC bench on threads (positions, velocities, cells,
/// sort buffers), for the memory check before allocating.
pub const BYTES_PER_PARTICLE: f64 = 300.0;

/// Peak bytes per particle held by the ranks of [`measure_decomposed`] together: 2D 80
/// measured at N = 10^6 and 10^7 on 2 ranks (the slope of the peak resident memory; each
/// rank creates only its slab), 3D 112 at N = 10^6 and 4 x 10^6 (two more words of
/// state); rounded up.
pub fn decomposed_bytes_per_particle(dimension: usize) -> f64 {
    if dimension == 2 { 90.0 } else { 120.0 }
}

/// The cases of `granular bench dsmc` as `(dimension, particles, threads)`, in the order it
/// runs them: each given value alone, else 2D and 3D, 10^5, 10^6 and 10^7 particles, 1 and
/// 2 threads.
pub fn cases(
    dimension: Option<usize>,
    n: Option<usize>,
    threads: Option<usize>,
) -> Vec<(usize, usize, usize)> {
    let dims: Vec<usize> = dimension.map_or(vec![2, 3], |d| vec![d]);
    let ns: Vec<usize> = n.map_or(vec![100_000, 1_000_000, 10_000_000], |n| vec![n]);
    let ts: Vec<usize> = threads.map_or(vec![1, 2], |t| vec![t]);
    let mut out = Vec::new();
    for &d in &dims {
        for &n in &ns {
            for &t in &ts {
                out.push((d, n, t));
            }
        }
    }
    out
}

/// Times the DSMC engine with `n` particles in `dimension` dimensions on `threads` worker
/// threads (its own rayon pool): 2 warm-up steps, then three segments of about `1e7`
/// particle-steps each; the fastest segment is reported.
pub fn measure(dimension: usize, n: usize, threads: usize) -> Result<BenchResult, BenchError> {
    measure_rough(dimension, n, threads, -1.0)
}

/// [`measure`] with rough grains of tangential restitution `tangential_restitution` (β in
/// `[-1, 1]`; -1: smooth grains, as [`measure`]): uniform disks or spheres spinning at
/// `T_r = T_t = 1`, the collisions elastic in the normal direction.
pub fn measure_rough(
    dimension: usize,
    n: usize,
    threads: usize,
    tangential_restitution: f64,
) -> Result<BenchResult, BenchError> {
    match dimension {
        2 => run::<2>(n, threads, tangential_restitution),
        3 => run::<3>(n, threads, tangential_restitution),
        d => Err(BenchError::Dimension(d)),
    }
}

/// One rank's share of a [`DecomposedResult`]: per timed step, from the fastest segment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RankResult {
    /// The rank.
    pub rank: usize,
    /// Particles on this rank at the end of the segment.
    pub particles: usize,
    /// Wall time per step, seconds.
    pub seconds_per_step: f64,
    /// Time per step outside communication (free flight, sort, collisions, packing the
    /// migrants, the local part of the sums), seconds.
    pub compute_seconds_per_step: f64,
    /// Time per step inside migration calls (includes waiting for other ranks), seconds.
    pub migration_seconds_per_step: f64,
    /// Time per step inside reductions (includes waiting for other ranks), seconds.
    pub reduction_seconds_per_step: f64,
    /// `particles / compute_seconds_per_step`: this rank's particle-steps per second of
    /// computing.
    pub compute_particle_steps_per_second: f64,
    /// Bytes sent to other ranks by migration per step.
    pub migration_bytes_per_step: f64,
    /// Bytes sent to other ranks by reductions per step.
    pub reduction_bytes_per_step: f64,
    /// Bytes received from other ranks (migration and reductions) per step.
    pub bytes_received_per_step: f64,
    /// Particles sent to other ranks per step.
    pub migrants_per_step: f64,
    /// Migration calls per step (each one all-to-all exchange of counts and one of data
    /// over MPI).
    pub migration_calls_per_step: f64,
    /// Reduction calls per step (each one all-gather of counts and one of data over MPI).
    pub reduction_calls_per_step: f64,
    /// Resident memory of the rank's process at the end, bytes (`VmRSS`; NaN where the
    /// system does not say).
    pub resident_bytes: f64,
    /// Peak resident memory of the rank's process, bytes (`VmHWM`; the set-up creates only
    /// the rank's slab, [`DsmcEngine::new_decomposed`]).
    pub peak_resident_bytes: f64,
}

/// One measurement of a DSMC run split over ranks (the case of Fig. 1 of Müller & Herrmann's DSMC paper by
/// default): the slowest rank of the fastest segment, and every rank's breakdown.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DecomposedResult {
    /// 2 or 3.
    pub dimension: usize,
    /// Number of particles (all ranks).
    pub n: usize,
    /// Packing fraction.
    pub packing_fraction: f64,
    /// Ranks.
    pub ranks: usize,
    /// Worker threads per rank.
    pub threads: usize,
    /// Cell planes along the last axis (the most ranks the slabs allow).
    pub cell_planes: usize,
    /// Steps per timed segment (after 2 warm-up steps).
    pub steps: u64,
    /// Timed segments; the fastest is reported.
    pub segments: u64,
    /// Wall time of the fastest segment on its slowest rank, seconds.
    pub seconds: f64,
    /// `n * steps / seconds`.
    pub particle_steps_per_second: f64,
    /// Bytes sent to other ranks per step (migration and reductions), on the rank that
    /// sent most.
    pub bytes_per_rank_step: f64,
    /// Every rank's breakdown, in rank order.
    pub per_rank: Vec<RankResult>,
}

/// One step as a run takes it (`Engine::advance` without an explicit time step): the step
/// follows the mean free time (two chunked sums over the ranks), then the step, then the
/// check for non-finite velocities (one more gather).
fn run_step<const D: usize>(e: &mut DsmcEngine<D>) {
    e.follow_mean_free_time();
    e.step(e.time_step());
    let _ = e.first_non_finite();
}

/// Words of one rank's breakdown: seconds, then the [`Traffic`] fields, then particles and
/// the resident memory (now, peak).
fn rank_words(seconds: f64, t: &Traffic, particles: usize) -> [f64; 11] {
    let (rss, peak) = super::resident_memory();
    [
        seconds,
        t.migration_seconds,
        t.reduction_seconds,
        t.migration_bytes_sent as f64,
        t.reduction_bytes_sent as f64,
        (t.migration_bytes_received + t.reduction_bytes_received) as f64,
        t.migration_calls as f64,
        t.reduction_calls as f64,
        particles as f64,
        rss,
        peak,
    ]
}

fn run_decomposed<const D: usize>(
    n: usize,
    phi: f64,
    steps: u64,
    segments: u64,
    comm: std::sync::Arc<dyn Communicator>,
) -> Result<DecomposedResult, BenchError> {
    let ranks = comm.size();
    // Only this rank's slab is ever built (the same bits as `setup_at`, then decompose).
    let (config, bx, gas) = case_at::<D>(n, phi);
    let mut e = DsmcEngine::new_decomposed(config, bx, gas, 1, comm.clone())?;
    let cell_planes = *e.grid().dims.last().unwrap_or(&1);
    for _ in 0..2 {
        run_step(&mut e);
    }
    let traffic = |e: &DsmcEngine<D>| e.domain().map(|d| d.traffic()).unwrap_or_default();
    let mut best: Option<(f64, Vec<Vec<f64>>)> = None;
    for _ in 0..segments.max(1) {
        comm.all_gather(&[]);
        let t0 = traffic(&e);
        let t = Instant::now();
        for _ in 0..steps {
            run_step(&mut e);
        }
        let seconds = t.elapsed().as_secs_f64();
        let used = traffic(&e).since(&t0);
        let all = comm.all_gather(&rank_words(seconds, &used, e.grains().len()));
        let slowest = all.iter().map(|v| v[0]).fold(0.0, f64::max);
        if best.as_ref().is_none_or(|(s, _)| slowest < *s) {
            best = Some((slowest, all));
        }
    }
    let (seconds, all) = best.unwrap_or((f64::NAN, Vec::new()));
    let per = steps as f64;
    let record_bytes = 8.0 * (1 + 2 * D) as f64;
    let per_rank: Vec<RankResult> = all
        .iter()
        .enumerate()
        .map(|(rank, w)| {
            let compute = (w[0] - w[1] - w[2]) / per;
            RankResult {
                rank,
                particles: w[8] as usize,
                seconds_per_step: w[0] / per,
                compute_seconds_per_step: compute,
                migration_seconds_per_step: w[1] / per,
                reduction_seconds_per_step: w[2] / per,
                compute_particle_steps_per_second: w[8] / compute,
                migration_bytes_per_step: w[3] / per,
                reduction_bytes_per_step: w[4] / per,
                bytes_received_per_step: w[5] / per,
                migrants_per_step: w[3] / per / record_bytes,
                migration_calls_per_step: w[6] / per,
                reduction_calls_per_step: w[7] / per,
                resident_bytes: w[9],
                peak_resident_bytes: w[10],
            }
        })
        .collect();
    let bytes = per_rank
        .iter()
        .map(|r| r.migration_bytes_per_step + r.reduction_bytes_per_step)
        .fold(0.0, f64::max);
    Ok(DecomposedResult {
        dimension: D,
        n,
        packing_fraction: phi,
        ranks,
        threads: rayon::current_num_threads(),
        cell_planes,
        steps,
        segments: segments.max(1),
        seconds,
        particle_steps_per_second: n as f64 * per / seconds,
        bytes_per_rank_step: bytes,
        per_rank,
    })
}

/// Times the [`setup_at`] case (`n` grains at packing fraction `phi`) split over the
/// ranks of `comm` (collective): 2 warm-up steps, then `segments` segments of `steps`
/// steps, each step as a run takes it (time step following the mean free time, the
/// non-finite check); the fastest segment (by its slowest rank) is reported, with every
/// rank's compute and communication time and traffic, on every rank.
pub fn measure_decomposed(
    dimension: usize,
    n: usize,
    phi: f64,
    steps: u64,
    segments: u64,
    comm: std::sync::Arc<dyn Communicator>,
) -> Result<DecomposedResult, BenchError> {
    match dimension {
        2 => run_decomposed::<2>(n, phi, steps, segments, comm),
        3 => run_decomposed::<3>(n, phi, steps, segments, comm),
        d => Err(BenchError::Dimension(d)),
    }
}
