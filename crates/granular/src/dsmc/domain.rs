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
//! The threaded engine sums over fixed chunks of `SUM_CHUNK` (4096) particles of the
//! global storage order, each chunk from zero in storage order, then adds the chunks'
//! accumulators in order. Here (`Domain::ordered_fold`, **chained sums**) each rank folds
//! the chunks that start on it; a chunk that spans a rank cut is continued by the next
//! rank holding particles, which receives the chunk's partial accumulator (point to
//! point, [`Communicator::send`]) and folds its own leading particles into it, and so on
//! through as many ranks as the chunk spans (fewer than 4096 particles on a rank; ranks
//! without particles are skipped). The rank holding a chunk's last particle thus has the
//! chunk's exact accumulator. One all-gather then carries one accumulator per chunk, in
//! chunk order, and every rank adds them in that order, as the threaded engine does.
//! Per sum and rank: one gather of the particle counts (1 word), at most one accumulator
//! sent to the next rank and one received (`A` words each), and the accumulators of the
//! chunks that end on the rank. Counters are integers (exact in any order) and maxima are
//! order-free. So the time step, the observables and the trajectory are bit for bit those
//! of the threaded engine, for any number of ranks.
//!
//! The communication itself is behind [`Communicator`], implemented over MPI by the
//! command line's `mpi` feature: this crate needs no MPI.

mod balance;
pub use balance::{Balance, BalanceMode, TIME_SHARE_CAP};
pub(crate) use balance::{IMBALANCE, balanced_cuts, time_cuts};

use super::sums::SUM_CHUNK;
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
    /// Sends `words` to rank `to` (`to != rank()`), point to point and not collective:
    /// only `to` calls [`Communicator::receive`] for it. Messages from one rank to another
    /// arrive in the order sent. May return before `to` receives; the chained sums send
    /// only to later ranks, so a blocking send cannot deadlock.
    fn send(&self, to: usize, words: &[f64]);
    /// The next words rank `from` sent to this one with [`Communicator::send`] (waits for
    /// them).
    fn receive(&self, from: usize) -> Vec<f64>;
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
    /// The grains this rank holds, and the most it held.
    held: Arc<Held>,
    /// How the cuts follow the grains.
    pub(crate) balance: Balance,
    /// The last re-cut (or the decomposition): its time and the communication seconds
    /// and steps then, for [`BalanceMode::Time`].
    mark: (Instant, f64),
    /// Re-cuts so far.
    recuts: u64,
    /// The last load report ([`Domain::load_report`]): its time and the communication
    /// seconds then.
    report_mark: Arc<Mutex<(Instant, f64)>>,
}

/// The most grains one rank held at a time: its own and those in migration buffers
/// (see [`Domain::peak_grains`]).
#[derive(Debug, Default)]
struct Held {
    now: std::sync::atomic::AtomicUsize,
    peak: std::sync::atomic::AtomicUsize,
}

/// What one rank has communicated so far, by purpose: **migration** (the point-to-point
/// exchange after every free flight) and **reductions** (every gather over the ranks:
/// counters, maxima, the chunked sums of the observables and of the adaptive time step,
/// and the chained sums' accumulators passed to the next rank). Counted at the
/// [`Communicator`] calls; the time is the wall time spent inside them, so it includes
/// waiting for the slowest rank (load imbalance shows up as communication).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Traffic {
    /// Bytes sent to other ranks by migrations (8 per word).
    pub migration_bytes_sent: u64,
    /// Bytes received from other ranks by migrations.
    pub migration_bytes_received: u64,
    /// Migration calls ([`Communicator::exchange`]).
    pub migration_calls: u64,
    /// Seconds spent inside migration calls.
    pub migration_seconds: f64,
    /// Bytes sent to other ranks by reductions (a gathered word counts once per other
    /// rank it reaches; a chained sum's accumulator once).
    pub reduction_bytes_sent: u64,
    /// Bytes received from other ranks by reductions.
    pub reduction_bytes_received: u64,
    /// Reduction calls ([`Communicator::all_gather`]).
    pub reduction_calls: u64,
    /// Seconds spent inside reduction calls and chained-sum messages (sending and
    /// waiting to receive).
    pub reduction_seconds: f64,
    /// Chained-sum messages sent ([`Communicator::send`]: a chunk's accumulator passed to
    /// the next rank holding particles).
    #[serde(default)]
    pub reduction_messages: u64,
}

impl Traffic {
    /// The counters accumulated since `earlier` (`self - earlier`, field by field).
    pub(crate) fn since(&self, earlier: &Traffic) -> Traffic {
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
            reduction_messages: self.reduction_messages - earlier.reduction_messages,
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
        Domain::for_ids(comm, n_global).with_grid(dims)
    }

    /// The ranks of `comm` before there is a cell grid: one plane per rank, so that
    /// [`Domain::ordered_fold`] sums over the ranks' blocks of grain ids (the set-up's
    /// sums, `dsmc::setup`). [`Domain::with_grid`] then cuts the grid.
    pub(crate) fn for_ids(comm: Arc<dyn Communicator>, n_global: usize) -> Domain {
        let k = comm.size().max(1);
        let r = comm.rank();
        Domain {
            cells: r..r + 1,
            comm,
            plane_owner: (0..k as u32).collect(),
            stride: 1,
            n_global,
            traffic: Arc::default(),
            held: Arc::default(),
            balance: Balance::default(),
            mark: (Instant::now(), 0.0),
            recuts: 0,
            report_mark: Arc::new(Mutex::new((Instant::now(), 0.0))),
        }
    }

    /// This domain's ranks on the grid of `dims` cells per axis, cut into slabs of equal
    /// numbers of planes along the last axis (the counters carry over). Errors when there
    /// are more ranks than planes.
    pub(crate) fn with_grid(self, dims: &[usize]) -> Result<Domain, DomainError> {
        let k = self.size().max(1);
        let planes = *dims.last().unwrap_or(&1);
        if k > planes {
            return Err(DomainError::TooManyRanks { ranks: k, planes });
        }
        let cuts: Vec<usize> = (0..=k).map(|r| r * planes / k).collect();
        let mut d = Domain {
            stride: dims[..dims.len() - 1].iter().product(),
            plane_owner: vec![0; planes],
            cells: 0..0,
            ..self
        };
        d.set_cuts(&cuts);
        Ok(d)
    }

    /// Cuts the planes into slabs: rank `r` owns the planes `cuts[r] .. cuts[r + 1]`
    /// (`cuts` rises from 0 to the number of planes, `size() + 1` entries).
    pub(crate) fn set_cuts(&mut self, cuts: &[usize]) {
        for (r, w) in cuts.windows(2).enumerate() {
            for o in &mut self.plane_owner[w[0]..w[1]] {
                *o = r as u32;
            }
        }
        let r = self.rank();
        self.cells = cuts[r] * self.stride..cuts[r + 1] * self.stride;
    }

    /// The planes each rank owns: `cuts[r] .. cuts[r + 1]` for rank `r`.
    pub(crate) fn cuts(&self) -> Vec<usize> {
        (0..=self.size())
            .map(|r| self.plane_owner.partition_point(|&o| (o as usize) < r))
            .collect()
    }

    /// Cell planes along the last axis.
    pub(crate) fn planes(&self) -> usize {
        self.plane_owner.len()
    }

    /// Records that this rank now holds `grains` grains (its own and those in buffers).
    pub(crate) fn hold(&self, grains: usize) {
        use std::sync::atomic::Ordering::Relaxed;
        self.held.now.store(grains, Relaxed);
        self.held.peak.fetch_max(grains, Relaxed);
    }

    /// The most grains this rank has held at a time so far: its own, and at a migration
    /// (after a free flight, at the set-up, at a re-cut of the slabs, when grains are
    /// sent to the owners of their ids for an output) those in the buffers besides.
    /// Counted where the engine allocates grain arrays; an array over all grains (a
    /// gather of the whole system) counts `N`.
    pub fn peak_grains(&self) -> usize {
        self.held.peak.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Every rank's peak grains ([`Domain::peak_grains`]) and its grains now (`local`), by
    /// rank (collective).
    pub(crate) fn peaks(&self, local: usize) -> Vec<(usize, usize)> {
        self.comm
            .all_gather(&[self.peak_grains() as f64, local as f64])
            .iter()
            .map(|v| (v[0] as usize, v[1] as usize))
            .collect()
    }

    /// How the work is shared since the last report (collective): every rank's grains
    /// (`local`) and the share of the wall time it spent inside communication, which
    /// includes waiting for the slowest rank. Returns `(largest / mean grains, the
    /// smallest and the largest share of time in communication, cuts moved so far)`.
    pub(crate) fn load_report(&self, local: usize) -> (f64, f64, f64, u64) {
        let t = self.traffic();
        let comm = t.migration_seconds + t.reduction_seconds;
        let share = {
            let mut mark = self.report_mark.lock().unwrap_or_else(|e| e.into_inner());
            let wall = mark.0.elapsed().as_secs_f64();
            let s = if wall > 0.0 {
                (comm - mark.1) / wall
            } else {
                0.0
            };
            *mark = (Instant::now(), comm);
            s
        };
        let parts = self.comm.all_gather(&[local as f64, share]);
        let grains: Vec<f64> = parts.iter().map(|v| v[0]).collect();
        let mean = grains.iter().sum::<f64>() / grains.len().max(1) as f64;
        let most = grains.iter().copied().fold(0.0, f64::max);
        let shares = parts.iter().map(|v| v[1]);
        let lo = shares.clone().fold(f64::INFINITY, f64::min);
        let hi = shares.fold(0.0, f64::max);
        let balance = if mean > 0.0 { most / mean } else { 1.0 };
        (balance, lo, hi, self.recuts)
    }

    /// How many times the cuts have moved.
    pub fn recuts(&self) -> u64 {
        self.recuts
    }

    /// The planes this rank owns.
    pub(crate) fn own_planes(&self) -> std::ops::Range<usize> {
        self.cells.start / self.stride..self.cells.end / self.stride
    }

    /// The plane of linear cell `cell`.
    #[inline]
    pub(crate) fn plane(&self, cell: u32) -> usize {
        cell as usize / self.stride
    }

    /// Moves the cuts if the load is uneven (collective): `counts` are this rank's grains
    /// per own plane. With [`BalanceMode::Count`] a plane's load is its grains; with
    /// [`BalanceMode::Time`] its grains times its owner's compute seconds per grain since
    /// the last look (wall time less the time spent in communication, which includes
    /// waiting for the slowest rank), the cuts then capped at [`TIME_SHARE_CAP`] times the
    /// mean grains per rank ([`time_cuts`]). Every rank gathers every plane's grains (one
    /// word per plane, and one per rank for its seconds per grain) and computes the same
    /// cuts ([`balanced_cuts`]); they move when the most
    /// loaded rank carries more than [`IMBALANCE`] times the mean. Returns whether they
    /// moved. The caller then migrates the grains whose plane changed owner.
    pub(crate) fn rebalance(&mut self, counts: &[u64]) -> bool {
        let k = self.size();
        if k < 2 || self.balance.mode == BalanceMode::Off {
            return false;
        }
        let mine: u64 = counts.iter().sum();
        let t = self.traffic();
        let comm_seconds = t.migration_seconds + t.reduction_seconds;
        let compute = (self.mark.0.elapsed().as_secs_f64() - (comm_seconds - self.mark.1)).max(0.0);
        let per_grain = match self.balance.mode {
            BalanceMode::Time if mine > 0 => compute / mine as f64,
            _ => 1.0,
        };
        // This rank's grains per own plane, then its seconds per grain.
        let mut local: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
        local.push(per_grain);
        let parts = self.all_gather(&local);
        self.mark = (Instant::now(), {
            let t = self.traffic();
            t.migration_seconds + t.reduction_seconds
        });
        let mut grains = Vec::with_capacity(self.planes());
        let mut loads = Vec::with_capacity(self.planes());
        for part in &parts {
            let Some((&cost, own)) = part.split_last() else {
                return false;
            };
            grains.extend_from_slice(own);
            loads.extend(own.iter().map(|&c| c * cost));
        }
        if loads.len() != self.planes() {
            return false;
        }
        let rank_loads: Vec<f64> = parts
            .iter()
            .map(|v| {
                v.split_last()
                    .map_or(0.0, |(&c, own)| c * own.iter().sum::<f64>())
            })
            .collect();
        let total: f64 = rank_loads.iter().sum();
        let most = rank_loads.iter().copied().fold(0.0, f64::max);
        // No grains, or no time measured yet: nothing to share.
        if total <= 0.0 || most <= IMBALANCE * total / k as f64 {
            return false;
        }
        let cuts = match self.balance.mode {
            BalanceMode::Time => time_cuts(&grains, &loads, k),
            _ => balanced_cuts(&loads, k),
        };
        if cuts == self.cuts() {
            return false;
        }
        self.set_cuts(&cuts);
        self.recuts += 1;
        true
    }

    /// The number of grains in each plane of the whole grid (collective), from this
    /// rank's grains in every plane (`local`, one count per plane): a reduce-scatter
    /// (rank `q` sums the counts of its share of the planes) and a gather of the shares,
    /// so a rank receives about `2 P` words, not `K P`.
    pub(crate) fn plane_totals(&self, local: &[u64]) -> Vec<u64> {
        let k = self.size();
        let p = local.len();
        let share = |q: usize| q * p / k..(q + 1) * p / k;
        let outgoing: Vec<Vec<f64>> = (0..k)
            .map(|q| local[share(q)].iter().map(|&c| f64::from_bits(c)).collect())
            .collect();
        let mut mine = vec![0u64; share(self.rank()).len()];
        for part in self.exchange(outgoing) {
            for (m, w) in mine.iter_mut().zip(part) {
                *m += w.to_bits();
            }
        }
        let words: Vec<f64> = mine.iter().map(|&c| f64::from_bits(c)).collect();
        self.all_gather(&words)
            .concat()
            .into_iter()
            .map(f64::to_bits)
            .collect()
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.comm.rank()
    }

    /// The number of ranks.
    pub fn size(&self) -> usize {
        self.comm.size()
    }

    /// What this rank has communicated so far (see [`Traffic`]).
    pub(crate) fn traffic(&self) -> Traffic {
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

    /// The smallest of every rank's `local` value, `None` when no rank has one
    /// (collective): the first grain id at fault over all ranks.
    pub(crate) fn min_over_ranks(&self, local: Option<u64>) -> Option<u64> {
        let word = f64::from_bits(local.unwrap_or(u64::MAX));
        self.all_gather(&[word])
            .iter()
            .map(|v| v[0].to_bits())
            .min()
            .filter(|&m| m != u64::MAX)
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

    /// Sends `words` to rank `to` (point to point, a chained sum's accumulator), counting
    /// the words and the time as reduction traffic.
    fn send(&self, to: usize, words: &[f64]) {
        let t = Instant::now();
        self.comm.send(to, words);
        let seconds = t.elapsed().as_secs_f64();
        self.record(|c| {
            c.reduction_bytes_sent += 8 * words.len() as u64;
            c.reduction_messages += 1;
            c.reduction_seconds += seconds;
        });
    }

    /// The next words rank `from` sent to this one (waits for them), counted as
    /// reduction traffic.
    fn receive(&self, from: usize) -> Vec<f64> {
        let t = Instant::now();
        let words = self.comm.receive(from);
        let seconds = t.elapsed().as_secs_f64();
        self.record(|c| {
            c.reduction_bytes_received += 8 * words.len() as u64;
            c.reduction_seconds += seconds;
        });
        words
    }

    /// The chunked fold of the threaded engine over the global storage order, on every
    /// rank: `elem(i)` is the value (`E` words) of local particle `i`, `fold` adds one
    /// value to a chunk's accumulator (`A` words, starting at zero) and `combine` adds a
    /// chunk's accumulator to the total (starting at zero), both in storage order.
    /// Bit-identical to folding every [`SUM_CHUNK`] particles of the whole system, then
    /// the chunks in order.
    ///
    /// **Chained**: a chunk that spans a rank cut is folded by the ranks it spans one
    /// after the other; its accumulator passes from each to the next rank holding
    /// particles (point to point, `A` words; ranks without particles are skipped), which
    /// continues the fold with its own values. The rank holding a chunk's last particle
    /// thus has the chunk's accumulator, exactly as the threaded engine's; every rank then
    /// contributes the accumulators of the chunks that end on it to one all-gather (one
    /// accumulator per chunk, in chunk order by rank order), and every rank combines them
    /// in order. A rank sends its own open chunk before it waits for the chunk continuing
    /// from an earlier rank, so the messages of a step overlap and only a chunk that
    /// spans more than two ranks (fewer than [`SUM_CHUNK`] particles on a rank) makes a
    /// sequence of messages.
    pub(crate) fn ordered_fold<const E: usize, const A: usize>(
        &self,
        n_local: usize,
        elem: impl Fn(usize) -> [f64; E] + Sync,
        fold: impl Fn(&mut [f64; A], &[f64; E]) + Sync,
        combine: impl Fn(&mut [f64; A], &[f64; A]),
    ) -> [f64; A] {
        let counts = self.counts(n_local);
        let layout = ChainLayout::new(&counts, self.rank());
        let run = |acc: &mut [f64; A], range: std::ops::Range<usize>| {
            for k in range {
                fold(acc, &elem(k));
            }
        };
        // The chunks that start on this rank, folded in parallel (the last may be open).
        let starts: Vec<[f64; A]> = layout
            .own_chunks()
            .par_iter()
            .map(|r| {
                let mut acc = [0.0; A];
                run(&mut acc, r.clone());
                acc
            })
            .collect();
        let mut ends: Vec<[f64; A]> = Vec::with_capacity(starts.len() + 1);
        let complete = starts.len() - usize::from(layout.open_tail());
        if let (true, Some(to), Some(open)) = (layout.open_tail(), layout.next, starts.last()) {
            self.send(to, open);
        }
        if let Some(from) = layout.previous {
            let words = self.receive(from);
            let mut acc: [f64; A] = words.as_slice().try_into().unwrap_or([f64::NAN; A]);
            run(&mut acc, 0..layout.head);
            match layout.next {
                // The whole rank continues a chunk that goes on after it.
                Some(to) if layout.head == n_local => self.send(to, &acc),
                _ => ends.push(acc),
            }
        }
        ends.extend_from_slice(&starts[..complete]);
        let words: Vec<f64> = ends.iter().flatten().copied().collect();
        let mut total = [0.0; A];
        for part in self.all_gather(&words) {
            for a in part.chunks_exact(A) {
                combine(&mut total, &a.try_into().unwrap_or([f64::NAN; A]));
            }
        }
        total
    }
}

/// Where one rank's particles lie among the chunks of [`SUM_CHUNK`] of the global storage
/// order, and whom it passes an open chunk to ([`Domain::ordered_fold`]).
#[derive(Clone, Debug, PartialEq, Eq)]
struct ChainLayout {
    /// Particles on this rank.
    n: usize,
    /// Leading local particles that continue a chunk begun on an earlier rank.
    head: usize,
    /// Whether the last local particle's chunk goes on on a later rank.
    open: bool,
    /// The nearest earlier rank with particles, when the head is not empty.
    previous: Option<usize>,
    /// The nearest later rank with particles, when the last chunk goes on there.
    next: Option<usize>,
}

impl ChainLayout {
    /// The layout of `rank` given every rank's particle count.
    fn new(counts: &[usize], rank: usize) -> ChainLayout {
        let offset: usize = counts[..rank].iter().sum();
        let total: usize = counts.iter().sum();
        let n = counts[rank];
        let end = offset + n;
        let head = if n == 0 {
            0
        } else {
            ((SUM_CHUNK - offset % SUM_CHUNK) % SUM_CHUNK).min(n)
        };
        let open = n > 0 && end < total && !end.is_multiple_of(SUM_CHUNK);
        ChainLayout {
            n,
            head,
            open,
            previous: (head > 0)
                .then(|| (0..rank).rev().find(|&q| counts[q] > 0))
                .flatten(),
            next: open
                .then(|| (rank + 1..counts.len()).find(|&q| counts[q] > 0))
                .flatten(),
        }
    }

    /// The local ranges of the chunks that start on this rank (after the head), in order.
    fn own_chunks(&self) -> Vec<std::ops::Range<usize>> {
        (self.head..self.n)
            .step_by(SUM_CHUNK)
            .map(|s| s..(s + SUM_CHUNK).min(self.n))
            .collect()
    }

    /// Whether the last chunk that starts on this rank goes on on a later rank.
    fn open_tail(&self) -> bool {
        self.open && self.head < self.n
    }
}

#[cfg(test)]
mod tests;
