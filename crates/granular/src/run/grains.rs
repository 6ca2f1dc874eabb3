//! The grains an output reads, without gathering a decomposed run on one rank: each rank
//! holds the block of grain ids `r N / K .. (r + 1) N / K` (as for the snapshots,
//! [`crate::dsmc::DsmcEngine::id_block`]), and the outputs reduce over the blocks so that
//! every rank ends with the whole system's numbers, bit for bit those of the threaded run:
//!
//! * **counts** (histogram bins, density-map bins) are added over the ranks as integers
//!   ([`Grains::sum_histograms`], [`Grains::sum_u64`]): exact in any order;
//! * **sums in the order of the grain ids** (the speed statistics' `Σ m v²`, running means
//!   and variances, which the threaded run takes one grain after the other) are
//!   *chained* ([`Grains::chain`]): rank 0 folds its block, hands the accumulator to rank
//!   1, which continues with its own block, and so on; the last rank's accumulator goes
//!   to every rank. The additions are those of the threaded loop, in its order, so the
//!   bits are the same; the price is `K` small collectives and a fold that runs over the
//!   ranks one after the other (the same `N` additions the threaded run makes on one
//!   core).
//!
//! Not decomposed (the threaded build, the event-driven engine), the block is the whole
//! snapshot and both operations are plain local calls: one code path for both.

use crate::dsmc::Domain;
use crate::engine::Snapshot;
use crate::run::AnyEngine;
use crate::simulation::Simulation;
use crate::stats::Histogram;

/// This rank's block of grains in id order, with the reductions over all blocks.
pub(crate) struct Grains {
    /// The block's rows: grains `first .. first + len` in id (input) order; every
    /// per-grain array has the block's length, `species_names` is the whole list.
    pub snap: Snapshot,
    /// The id of the block's first grain.
    pub first: usize,
    /// Grains on all ranks.
    pub total: usize,
    /// The ranks, when the run is decomposed.
    domain: Option<Domain>,
}

impl Grains {
    /// The grains of `simulation` (collective when it is decomposed: every rank sends
    /// its particles to the owners of their ids); `None` for the intruder engines.
    pub(crate) fn of(simulation: &Simulation) -> Option<Grains> {
        match simulation.engine() {
            AnyEngine::Dsmc2(e) if e.domain().is_some() => Some(block_of(e)),
            AnyEngine::Dsmc3(e) if e.domain().is_some() => Some(block_of(e)),
            _ => simulation.snapshot().map(|snap| Grains {
                first: 0,
                total: snap.masses.len(),
                snap,
                domain: None,
            }),
        }
    }

    /// Grains in this rank's block.
    pub fn len(&self) -> usize {
        self.snap.masses.len()
    }

    /// `|v_i|²` of the block's grain `i`.
    pub(crate) fn speed_squared(&self, i: usize) -> f64 {
        let d = self.snap.dimension;
        self.snap.velocities[i * d..(i + 1) * d]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
    }

    /// The sequential fold of the grains in id order (collective): `fold(acc, block)`
    /// continues the accumulator `acc` (words) over the block's grains in order. Rank 0
    /// starts from `init`, each rank continues from the one before; every rank returns
    /// the final accumulator, bit for bit the one the loop over all grains gives.
    pub(crate) fn chain(
        &self,
        init: Vec<f64>,
        fold: impl FnOnce(Vec<f64>) -> Vec<f64>,
    ) -> Vec<f64> {
        let Some(domain) = &self.domain else {
            return fold(init);
        };
        let (me, k) = (domain.rank(), domain.size());
        let mut fold = Some(fold);
        let mut run = |acc: Vec<f64>| fold.take().map_or_else(Vec::new, |f| f(acc));
        let mut acc = if me == 0 { run(init) } else { Vec::new() };
        // Round q: rank q - 1 hands its accumulator on (to every rank: the last round is
        // the broadcast of the result).
        for q in 1..=k {
            let mine: &[f64] = if me == q - 1 { &acc } else { &[] };
            let mut parts = domain.all_gather(mine);
            let handed = std::mem::take(&mut parts[q - 1]);
            acc = if q == k {
                handed
            } else if me == q {
                run(handed)
            } else {
                acc
            };
        }
        acc
    }

    /// The rows of the block (`rows`: `width` words per grain, in id order) cut into the
    /// chunks of `chunk` consecutive ids of the whole system, `c chunk .. (c + 1) chunk`:
    /// the chunks that start in this block, whole, in order (collective: the rows of a
    /// chunk that runs on into later blocks are sent by their ranks to the rank where it
    /// starts). Not decomposed: every chunk. A fold per chunk, then over the chunks in
    /// order ([`Grains::chain`]), is then the threaded run's chunked fold.
    pub(crate) fn chunks_starting_here(
        &self,
        rows: &[f64],
        width: usize,
        chunk: usize,
    ) -> Vec<Vec<f64>> {
        let n = self.len();
        let lead = match self.first % chunk {
            0 => 0,
            r => (chunk - r).min(n),
        };
        let mut own: Vec<Vec<f64>> = rows[lead * width..]
            .chunks(chunk * width)
            .map(<[f64]>::to_vec)
            .collect();
        let Some(domain) = &self.domain else {
            return own;
        };
        let (me, k) = (domain.rank(), domain.size());
        let mut out = vec![Vec::new(); k];
        if lead > 0 {
            let start = self.first - self.first % chunk;
            out[block_owner(start, self.total, k)] = rows[..lead * width].to_vec();
        }
        let incoming = domain.exchange(out);
        if let Some(last) = own.last_mut() {
            for words in incoming.iter().skip(me + 1) {
                last.extend_from_slice(words);
            }
        }
        own
    }

    /// Integer counters summed over the ranks (exact).
    pub(crate) fn sum_u64(&self, local: Vec<u64>) -> Vec<u64> {
        match &self.domain {
            Some(d) => d.sum_u64(&local),
            None => local,
        }
    }

    /// Histograms filled with this rank's grains, summed over the ranks (bins,
    /// underflow and overflow: integers, exact).
    pub(crate) fn sum_histograms(&self, histograms: &mut [Histogram]) {
        if self.domain.is_none() {
            return;
        }
        let mut words = Vec::new();
        for h in histograms.iter() {
            words.extend_from_slice(&h.counts);
            words.extend([h.underflow, h.overflow]);
        }
        let mut total = self.sum_u64(words).into_iter();
        for h in histograms.iter_mut() {
            for c in h.counts.iter_mut() {
                *c = total.next().unwrap_or(0);
            }
            h.underflow = total.next().unwrap_or(0);
            h.overflow = total.next().unwrap_or(0);
        }
    }
}

/// The rank whose block of `n` ids (over `k` ranks: `q n / k .. (q + 1) n / k`) holds `id`.
fn block_owner(id: usize, n: usize, k: usize) -> usize {
    let block = |q: usize| q * n / k..(q + 1) * n / k;
    let mut q = (id * k / n.max(1)).min(k - 1);
    while q > 0 && block(q).start > id {
        q -= 1;
    }
    while q + 1 < k && block(q).end <= id {
        q += 1;
    }
    q
}

/// Adds `from`'s counts to `into` (histograms of the same bins).
pub(crate) fn add_counts(into: &mut Histogram, from: &Histogram) {
    for (a, b) in into.counts.iter_mut().zip(&from.counts) {
        *a += b;
    }
    into.underflow += from.underflow;
    into.overflow += from.overflow;
}

/// A decomposed engine's block of ids as a snapshot's rows (collective).
fn block_of<const D: usize>(e: &crate::dsmc::DsmcEngine<D>) -> Grains {
    use crate::engine::Engine;
    let block = e.id_block();
    let n = block.positions.len();
    let domain = e.domain().cloned();
    // One array after the other, each dropped once flat: a rank holds its block once
    // and one array twice at most.
    let flat =
        |v: Vec<crate::vector::Vector<D>>| -> Vec<f64> { v.iter().flat_map(|x| x.0).collect() };
    let positions = flat(block.positions);
    let velocities = flat(block.velocities);
    Grains {
        snap: Snapshot {
            time: e.time(),
            dimension: D,
            positions,
            velocities,
            radii: vec![e.radius(); n],
            masses: vec![e.mass(); n],
            species: (block.first as u32..(block.first + n) as u32)
                .map(|id| e.species().of(id))
                .collect(),
            species_names: e.species().names.clone(),
            angular_velocities: block.angular_velocities,
        },
        first: block.first,
        total: e.particle_count(),
        domain,
    }
}
