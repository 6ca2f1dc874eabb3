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
    /// Grains on all ranks.
    pub total: usize,
    /// The ranks, when the run is decomposed.
    domain: Option<Domain>,
}

impl Grains {
    /// The grains of `simulation` (collective when it is decomposed: every rank sends
    /// its particles to the owners of their ids); `None` for the intruder engines.
    pub fn of(simulation: &Simulation) -> Option<Grains> {
        match simulation.engine() {
            AnyEngine::Dsmc2(e) if e.domain().is_some() => Some(block_of(e)),
            AnyEngine::Dsmc3(e) if e.domain().is_some() => Some(block_of(e)),
            _ => simulation.snapshot().map(|snap| Grains {
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
    pub fn speed_squared(&self, i: usize) -> f64 {
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
    pub fn chain(&self, init: Vec<f64>, fold: impl FnOnce(Vec<f64>) -> Vec<f64>) -> Vec<f64> {
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

    /// Integer counters summed over the ranks (exact).
    pub fn sum_u64(&self, local: Vec<u64>) -> Vec<u64> {
        match &self.domain {
            Some(d) => d.sum_u64(&local),
            None => local,
        }
    }

    /// Histograms filled with this rank's grains, summed over the ranks (bins,
    /// underflow and overflow: integers, exact).
    pub fn sum_histograms(&self, histograms: &mut [Histogram]) {
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
    Grains {
        snap: Snapshot {
            time: e.time(),
            dimension: D,
            positions: block.positions.iter().flat_map(|x| x.0).collect(),
            velocities: block.velocities.iter().flat_map(|x| x.0).collect(),
            radii: vec![e.radius(); n],
            masses: vec![e.mass(); n],
            species: vec![0; n],
            species_names: vec![e.species_name().to_string()],
        },
        total: e.particle_count(),
        domain,
    }
}
