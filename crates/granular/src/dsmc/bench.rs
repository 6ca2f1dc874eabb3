//! Throughput benchmark of the DSMC engine (for `granular bench dsmc`).

use super::config::DsmcConfig;
use super::engine::DsmcEngine;
use crate::boundary::{AxisKind, SimulationBox};
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
}

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// Unsupported dimension.
    #[error("dimension {0} is not supported (2 or 3)")]
    Dimension(usize),
    /// The thread pool could not be built.
    #[error(transparent)]
    Pool(#[from] rayon::ThreadPoolBuildError),
    /// The engine could not be built.
    #[error(transparent)]
    Engine(#[from] super::engine::DsmcError),
    /// The engine could not be split over the ranks.
    #[error(transparent)]
    Domain(#[from] super::domain::DomainError),
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
    let radius = 1.0;
    let v = haff::grain_volume(D, radius);
    let side = (n as f64 * v / phi).powf(1.0 / D as f64);
    let density = n as f64 / side.powi(D as i32);
    let omega = haff::collision_frequency(D, density, radius, 1.0, 1.0, 1.0);
    let cell = (10.0 / density).powf(1.0 / D as f64);
    let config = DsmcConfig {
        time_step: Some(0.1 / omega),
        cell_size: Some(side / (side / cell).round().max(1.0)),
        ..DsmcConfig::default()
    };
    let bx = SimulationBox::uniform(Vector([side; D]), AxisKind::Periodic);
    Ok(DsmcEngine::new(config, bx, n, radius, 1.0, 1.0, seed)?)
}

fn run<const D: usize>(n: usize, threads: usize) -> Result<BenchResult, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    pool.install(|| {
        let mut e = setup::<D>(n, 1)?;
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
        Ok(BenchResult {
            dimension: D,
            n,
            threads,
            steps,
            seconds,
            particle_steps_per_second: n as f64 * steps as f64 / seconds,
            collisions_per_second: coll / seconds,
            collisions_per_particle_step: 2.0 * coll / (n as f64 * steps as f64),
        })
    })
}

/// Times the DSMC engine with `n` particles in `dimension` dimensions on `threads` worker
/// threads (its own rayon pool): 2 warm-up steps, then three segments of about `1e7`
/// particle-steps each; the fastest segment is reported.
pub fn measure(dimension: usize, n: usize, threads: usize) -> Result<BenchResult, BenchError> {
    match dimension {
        2 => run::<2>(n, threads),
        3 => run::<3>(n, threads),
        d => Err(BenchError::Dimension(d)),
    }
}

/// One strong-scaling measurement of a DSMC run split over ranks.
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
    /// Steps timed (after 2 warm-up steps).
    pub steps: u64,
    /// Wall time of the timed steps on the slowest rank, seconds.
    pub seconds: f64,
    /// `n * steps / seconds`.
    pub particle_steps_per_second: f64,
    /// Bytes sent to other ranks per step (migration and reductions), on the rank that
    /// sent most.
    pub bytes_per_rank_step: f64,
}

fn run_decomposed<const D: usize>(
    n: usize,
    phi: f64,
    steps: u64,
    comm: std::sync::Arc<dyn super::domain::Communicator>,
) -> Result<DecomposedResult, BenchError> {
    let ranks = comm.size();
    let mut e = setup_at::<D>(n, phi, 1)?;
    e.decompose(comm.clone())?;
    let tau = e.time_step();
    for _ in 0..2 {
        e.step(tau);
    }
    let bytes0 = e.domain().map_or(0, |d| d.bytes_sent());
    comm.all_gather(&[]);
    let t = Instant::now();
    for _ in 0..steps {
        e.step(tau);
    }
    let seconds = t.elapsed().as_secs_f64();
    let bytes = (e.domain().map_or(0, |d| d.bytes_sent()) - bytes0) as f64 / steps as f64;
    let all = comm.all_gather(&[seconds, bytes]);
    let seconds = all.iter().map(|v| v[0]).fold(0.0, f64::max);
    let bytes = all.iter().map(|v| v[1]).fold(0.0, f64::max);
    Ok(DecomposedResult {
        dimension: D,
        n,
        packing_fraction: phi,
        ranks,
        threads: rayon::current_num_threads(),
        steps,
        seconds,
        particle_steps_per_second: n as f64 * steps as f64 / seconds,
        bytes_per_rank_step: bytes,
    })
}

/// Times `steps` steps of the [`setup_at`] case (`n` grains at packing fraction `phi`)
/// split over the ranks of `comm` (collective), after 2 warm-up steps; the slowest rank's
/// time and the largest traffic are reported, on every rank.
pub fn measure_decomposed(
    dimension: usize,
    n: usize,
    phi: f64,
    steps: u64,
    comm: std::sync::Arc<dyn super::domain::Communicator>,
) -> Result<DecomposedResult, BenchError> {
    match dimension {
        2 => run_decomposed::<2>(n, phi, steps, comm),
        3 => run_decomposed::<3>(n, phi, steps, comm),
        d => Err(BenchError::Dimension(d)),
    }
}
