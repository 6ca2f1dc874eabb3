//! Domain decomposition of the DSMC engine over ranks (MPI processes): slabs of cell
//! planes, particle migration after every free flight, and reductions that give the same
//! bits as the threaded engine for any number of ranks.
//!
//! # Decomposition
//!
//! The cell grid is cut into `K` slabs of whole cell planes along the **last axis**
//! (`y` in 2D, `z` in 3D): rank `r` owns the planes `floor(r P / K) .. floor((r + 1) P / K)`
//! of the `P` planes. The last axis is the slowest of the linear cell index
//! (`CellGrid::index`), so a slab is one contiguous range
//! of cell indices and the particles of rank 0, 1, ..., `K - 1` in their storage order,
//! put one after the other, are exactly the storage order of the threaded engine. Every
//! step keeps this true:
//!
//! 1. free flight of the local particles (as the threaded engine);
//! 2. **migration**: a particle whose new cell belongs to another rank is sent there; each
//!    rank puts what it receives in the order of the source ranks, its own remaining
//!    particles at its own rank's place (the order of the global storage);
//! 3. the stable counting sort by cell, which thus gives every cell the same particles
//!    *in the same order* as the threaded engine;
//! 4. collisions in the owned cells, each cell with its own random stream
//!    `(seed, [DYNAMICS, step, cell])`.
//!
//! # Reductions
//!
//! The threaded engine sums over fixed chunks of `SUM_CHUNK` particles of the global
//! storage order, then over the chunks in order. Here each rank folds the parts of chunks
//! that *start* on it, and hands on the raw values of a chunk that started on an earlier
//! rank; every rank then finishes the same folds in the same order
//! (`Domain::ordered_fold`). Counters are integers (exact in any order) and maxima are
//! order-free. So the time step, the observables and the trajectory are bit for bit those
//! of the threaded engine, for any number of ranks.
//!
//! The communication itself is behind [`Communicator`], implemented over MPI by the
//! command line's `mpi` feature: this crate needs no MPI.

use super::engine::SUM_CHUNK;
use rayon::prelude::*;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The collective operations a decomposed engine needs. Every rank calls each of them in
/// the same order (they are collective); payloads are `f64` words (integers travel as
/// their bits, [`f64::from_bits`]).
pub trait Communicator: Send + Sync + std::fmt::Debug {
    /// This rank, `0 .. size()`.
    fn rank(&self) -> usize;
    /// The number of ranks.
    fn size(&self) -> usize;
    /// Every rank's `local`, indexed by rank, on every rank.
    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>>;
    /// Sends `outgoing[q]` to rank `q` (`outgoing.len() == size()`); returns what every
    /// rank sent to this one, indexed by the source rank.
    fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>>;
}

/// A rank's share of a decomposed engine: which cell planes it owns and how to talk to
/// the others.
#[derive(Clone, Debug)]
pub struct Domain {
    pub(crate) comm: Arc<dyn Communicator>,
    /// Owner rank of each cell plane along the last axis.
    plane_owner: Vec<u32>,
    /// Cells per plane (the product of the other axes' cell counts).
    pub(crate) stride: usize,
    /// The owned cells `first .. end` (linear indices).
    pub(crate) cells: std::ops::Range<usize>,
    /// Particles on all ranks (constant).
    pub(crate) n_global: usize,
    /// What this rank has communicated so far, for the benchmarks.
    traffic: Arc<Mutex<Traffic>>,
}

/// What one rank has communicated so far, by purpose: **migration** (the point-to-point
/// exchange after every free flight) and **reductions** (every gather over the ranks:
/// counters, maxima, the chunked sums of the observables and of the adaptive time step).
/// Counted at the [`Communicator`] calls; the time is the wall time spent inside them, so
/// it includes waiting for the slowest rank (load imbalance shows up as communication).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Traffic {
    /// Bytes sent to other ranks by migrations (8 per word).
    pub migration_bytes_sent: u64,
    /// Bytes received from other ranks by migrations.
    pub migration_bytes_received: u64,
    /// Migration calls ([`Communicator::exchange`]).
    pub migration_calls: u64,
    /// Seconds spent inside migration calls.
    pub migration_seconds: f64,
    /// Bytes sent to other ranks by reductions (a gathered word counts once per other
    /// rank it reaches).
    pub reduction_bytes_sent: u64,
    /// Bytes received from other ranks by reductions.
    pub reduction_bytes_received: u64,
    /// Reduction calls ([`Communicator::all_gather`]).
    pub reduction_calls: u64,
    /// Seconds spent inside reduction calls.
    pub reduction_seconds: f64,
}

impl Traffic {
    /// The counters accumulated since `earlier` (`self - earlier`, field by field).
    pub fn since(&self, earlier: &Traffic) -> Traffic {
        Traffic {
            migration_bytes_sent: self.migration_bytes_sent - earlier.migration_bytes_sent,
            migration_bytes_received: self.migration_bytes_received
                - earlier.migration_bytes_received,
            migration_calls: self.migration_calls - earlier.migration_calls,
            migration_seconds: self.migration_seconds - earlier.migration_seconds,
            reduction_bytes_sent: self.reduction_bytes_sent - earlier.reduction_bytes_sent,
            reduction_bytes_received: self.reduction_bytes_received
                - earlier.reduction_bytes_received,
            reduction_calls: self.reduction_calls - earlier.reduction_calls,
            reduction_seconds: self.reduction_seconds - earlier.reduction_seconds,
        }
    }
}

/// Why a decomposition is impossible.
#[derive(Debug, thiserror::Error)]
pub enum DomainError {
    /// More ranks than cell planes along the cut.
    #[error(
        "{ranks} ranks but only {planes} cell planes along the last axis (the axis the \
         slabs cut): run on at most {planes} ranks, or make the cells smaller \
         (dsmc.cell_size) or the box longer along its last axis"
    )]
    TooManyRanks {
        /// Ranks asked for.
        ranks: usize,
        /// Cell planes along the last axis.
        planes: usize,
    },
    /// An engine other than DSMC under several ranks.
    #[error(
        "the {engine} engine cannot be split over {ranks} ranks: only `engine = \"dsmc\"` \
         is decomposed. Run it on one rank, or spread many runs over the ranks with a \
         (sharded) sweep: `granular sweep` (see docs/cluster.md)"
    )]
    NotDecomposable {
        /// The engine's name.
        engine: &'static str,
        /// Ranks asked for.
        ranks: usize,
    },
}

impl Domain {
    /// The slab of `comm.rank()` in a grid of `dims` cells per axis (the last axis is cut).
    pub(crate) fn new(
        comm: Arc<dyn Communicator>,
        dims: &[usize],
        n_global: usize,
    ) -> Result<Domain, DomainError> {
        let k = comm.size().max(1);
        let planes = *dims.last().unwrap_or(&1);
        if k > planes {
            return Err(DomainError::TooManyRanks { ranks: k, planes });
        }
        let stride: usize = dims[..dims.len() - 1].iter().product();
        let first_plane = |r: usize| r * planes / k;
        let mut plane_owner = vec![0u32; planes];
        for r in 0..k {
            for o in &mut plane_owner[first_plane(r)..first_plane(r + 1)] {
                *o = r as u32;
            }
        }
        let r = comm.rank();
        Ok(Domain {
            cells: first_plane(r) * stride..first_plane(r + 1) * stride,
            comm,
            plane_owner,
            stride,
            n_global,
            traffic: Arc::default(),
        })
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.comm.rank()
    }

    /// The number of ranks.
    pub fn size(&self) -> usize {
        self.comm.size()
    }

    /// Bytes this rank has sent to the others so far (8 per word; migration and
    /// reductions), for the benchmarks.
    pub fn bytes_sent(&self) -> u64 {
        let t = self.traffic();
        t.migration_bytes_sent + t.reduction_bytes_sent
    }

    /// What this rank has communicated so far (see [`Traffic`]).
    pub fn traffic(&self) -> Traffic {
        *self.traffic.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn record(&self, add: impl FnOnce(&mut Traffic)) {
        add(&mut self.traffic.lock().unwrap_or_else(|e| e.into_inner()));
    }

    /// The largest of every rank's `local` (order-free, so exact).
    pub(crate) fn max_f64(&self, local: f64) -> f64 {
        self.all_gather(&[local])
            .iter()
            .map(|v| v[0])
            .fold(local, f64::max)
    }

    /// The rank owning linear cell `cell`.
    #[inline]
    pub(crate) fn owner(&self, cell: u32) -> usize {
        self.plane_owner[cell as usize / self.stride] as usize
    }

    /// Every rank's `local` (collective), counting the words and the time.
    pub(crate) fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        let t = Instant::now();
        let parts = self.comm.all_gather(local);
        let seconds = t.elapsed().as_secs_f64();
        let me = self.rank();
        let received: usize = parts
            .iter()
            .enumerate()
            .filter(|&(q, _)| q != me)
            .map(|(_, v)| v.len())
            .sum();
        self.record(|c| {
            c.reduction_bytes_sent += 8 * (local.len() * (self.size() - 1)) as u64;
            c.reduction_bytes_received += 8 * received as u64;
            c.reduction_calls += 1;
            c.reduction_seconds += seconds;
        });
        parts
    }

    /// Point-to-point exchange (collective), counting the words and the time.
    pub(crate) fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let me = self.rank();
        let others = |parts: &[Vec<f64>]| -> u64 {
            parts
                .iter()
                .enumerate()
                .filter(|&(q, _)| q != me)
                .map(|(_, v)| v.len() as u64)
                .sum()
        };
        let sent = others(&outgoing);
        let t = Instant::now();
        let incoming = self.comm.exchange(outgoing);
        let seconds = t.elapsed().as_secs_f64();
        let received = others(&incoming);
        self.record(|c| {
            c.migration_bytes_sent += 8 * sent;
            c.migration_bytes_received += 8 * received;
            c.migration_calls += 1;
            c.migration_seconds += seconds;
        });
        incoming
    }

    /// The sum of integer counters over all ranks (exact).
    pub(crate) fn sum_u64(&self, local: &[u64]) -> Vec<u64> {
        let words: Vec<f64> = local.iter().map(|&x| f64::from_bits(x)).collect();
        let mut total = vec![0u64; local.len()];
        for part in self.all_gather(&words) {
            for (t, w) in total.iter_mut().zip(part) {
                *t += w.to_bits();
            }
        }
        total
    }

    /// The number of particles on each rank, in rank order.
    pub(crate) fn counts(&self, n_local: usize) -> Vec<usize> {
        self.all_gather(&[f64::from_bits(n_local as u64)])
            .iter()
            .map(|v| v[0].to_bits() as usize)
            .collect()
    }

    /// The chunked fold of the threaded engine over the global storage order, on every
    /// rank: `elem(i)` is the value (`E` words) of local particle `i`, `fold` adds one
    /// value to a chunk's accumulator (`A` words, starting at zero) and `combine` adds a
    /// chunk's accumulator to the total (starting at zero), both in storage order.
    /// Bit-identical to folding every [`SUM_CHUNK`] particles of the whole system, then
    /// the chunks in order.
    pub(crate) fn ordered_fold<const E: usize, const A: usize>(
        &self,
        n_local: usize,
        elem: impl Fn(usize) -> [f64; E] + Sync,
        fold: impl Fn(&mut [f64; A], &[f64; E]) + Sync,
        combine: impl Fn(&mut [f64; A], &[f64; A]),
    ) -> [f64; A] {
        let counts = self.counts(n_local);
        let offset: usize = counts[..self.rank()].iter().sum();
        // Pieces of the local range cut at the global chunk boundaries.
        let mut pieces = Vec::new();
        let mut i = 0;
        while i < n_local {
            let g = offset + i;
            let end = (i + SUM_CHUNK - g % SUM_CHUNK).min(n_local);
            pieces.push((i, end));
            i = end;
        }
        // Words: [continuation length, its raw values..., then one accumulator per piece
        // that starts a chunk].
        let cont = match pieces.first() {
            Some(&(s, e)) if !(offset + s).is_multiple_of(SUM_CHUNK) => e - s,
            _ => 0,
        };
        let folded: Vec<[f64; A]> = pieces
            .par_iter()
            .skip(usize::from(cont > 0))
            .map(|&(s, e)| {
                let mut acc = [0.0; A];
                for k in s..e {
                    fold(&mut acc, &elem(k));
                }
                acc
            })
            .collect();
        let mut words = Vec::with_capacity(1 + cont * E + folded.len() * A);
        words.push(cont as f64);
        for k in 0..cont {
            words.extend_from_slice(&elem(k));
        }
        for a in &folded {
            words.extend_from_slice(a);
        }
        let parts = self.all_gather(&words);
        // Finish every chunk in order: a chunk's accumulator continues with the raw
        // values of the ranks after the one it started on.
        let mut chunks: Vec<[f64; A]> = Vec::new();
        for part in &parts {
            let cont = part[0] as usize;
            let raw = &part[1..1 + cont * E];
            if let Some(acc) = chunks.last_mut() {
                for v in raw.chunks_exact(E) {
                    let v: [f64; E] = v.try_into().unwrap_or([0.0; E]);
                    fold(acc, &v);
                }
            }
            for a in part[1 + cont * E..].chunks_exact(A) {
                chunks.push(a.try_into().unwrap_or([0.0; A]));
            }
        }
        let mut total = [0.0; A];
        for c in &chunks {
            combine(&mut total, c);
        }
        total
    }
}
