//! The speed-up model of a decomposed DSMC run: measured compute cost per particle-step
//! and measured traffic, plus assumed network figures, give the time of one step on `K`
//! ranks (a Hockney model, R. W. Hockney, Parallel Computing 20, 389 (1994): a message of
//! `b` bytes costs `alpha + b / bandwidth`; collectives after R. Thakur, R. Rabenseifner,
//! W. Gropp, Int. J. High Perform. Comput. Appl. 19, 49 (2005)).
//!
//! One step on the slowest rank:
//!
//! ```text
//! T(K) = t_c N_max(K)                                   compute (largest slab)
//!      + c_mig [alpha (ceil(log2 K) + 2) + 8 w m(K) / B]  migration
//!      + sum_g [2 alpha ceil(log2 K) + R_g(K) / B]        reductions (all-gathers)
//!      + 2 c(K) (alpha + 8 A / B)                         chained accumulators
//! S(K) = T(1) / T(K),  T(1) = t_c N
//! ```
//!
//! * `t_c`: measured compute seconds per particle-step on one rank;
//! * `N_max(K) = N ceil(P / K) / P`: particles of the thickest of the `K` slabs of `P`
//!   cell planes (with recursive bisection, `N / K`);
//! * migration: `c_mig` calls per step (measured), each an all-to-all of counts (Bruck:
//!   `ceil(log2 K)` messages) and the particles to the 2 neighbouring slabs; `m(K)` the
//!   migrants per rank per step, `w` words each: measured per slab face at the measured
//!   N, scaled with the face (`(N / N0)^((D-1)/D)` at fixed packing fraction; with
//!   recursive bisection the faces of a rank's block shrink as `K^(-1/D)`);
//! * reductions: the all-gathers of a run's step, each an all-gather of counts and one of
//!   data (`2 ceil(log2 K)` messages with recursive doubling), `R_g` the bytes a rank
//!   receives, computed from the exact layout of the chunked sums (below);
//! * chained accumulators: each of the step's two chunked sums passes a chunk's partial
//!   accumulator (`A` = 2 words) to the next rank, `c(K)` messages in sequence;
//! * `B` the bandwidth per rank, `alpha` the latency per message.
//!
//! The chunked sums (`granular::dsmc::domain`, `ordered_fold`) are, **as implemented**,
//! chained: a chunk of 4096 particles that spans a rank cut is folded by the ranks it
//! spans one after the other, its accumulator passed on point to point, and the
//! all-gather carries one accumulator per chunk (`R_g` about `8 A N / 4096` bytes, the
//! same on every rank). A rank sends its own open chunk before it waits for the one from
//! its predecessor, so `c(K)` is 1 while every rank holds 4096 particles or more, and
//! the longest run of ranks inside one chunk, plus one, below that (`ceil(4096 K / N)`
//! or one more). The **raw-values** variant is the earlier layout, kept for comparison:
//! every rank gathered the raw values of the chunk begun on an earlier rank, so with
//! `N / K < 4096` nearly every particle's values reached every rank and `R_g` grew as
//! `min(N, 2048 K)`.

/// Particles per chunk of the engine's deterministic sums (`SUM_CHUNK`).
pub const SUM_CHUNK: usize = 4096;

/// Words per rank of the tally gather (4 counters and 20 impact-parameter bins).
pub const TALLY_WORDS: usize = 24;

/// The assumed network, per rank.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Network {
    /// Latency per message (one step of a collective), seconds.
    pub latency: f64,
    /// Bandwidth per rank, bytes per second.
    pub bandwidth: f64,
}

/// How the ranks split the system and sum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Slabs of cell planes, chained sums (the code as it is).
    Slabs,
    /// Slabs, chunked sums gathering the raw values of the chunks that span a cut (the
    /// earlier code, for comparison).
    SlabsRawValues,
    /// Recursive bisection into blocks, chained sums (proposed).
    BisectionChained,
}

impl Variant {
    /// All variants, in the order of the tables.
    pub const ALL: [Variant; 3] = [
        Variant::Slabs,
        Variant::SlabsRawValues,
        Variant::BisectionChained,
    ];

    /// Name in tables and files.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Slabs => "slabs",
            Variant::SlabsRawValues => "slabs-raw-values",
            Variant::BisectionChained => "bisection-chained",
        }
    }
}

/// What the benchmark measured, the model's inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs {
    /// 2 or 3.
    pub dimension: usize,
    /// The measured case's particles.
    pub n0: f64,
    /// Cell planes along the cut axis at `n0`.
    pub planes0: f64,
    /// Compute seconds per particle-step on one rank.
    pub compute_per_particle_step: f64,
    /// Migrants per slab face per step at `n0` (each way summed).
    pub migrants_per_face: f64,
    /// Migration calls per step.
    pub migration_calls: f64,
    /// Reduction calls per step.
    pub reduction_calls: f64,
}

/// The words each rank contributes to the all-gather of one chunked sum (`E` words per
/// raw value, `A` per accumulator) with `n` particles split evenly over `k` ranks.
/// Chained (as implemented): the accumulators of the chunks that end on the rank. Raw
/// values (the earlier layout): a length word, the raw values of the chunk begun on an
/// earlier rank, the accumulators of the chunks that start on the rank.
fn fold_words(n: f64, k: usize, e: usize, a: usize, chained: bool) -> Vec<f64> {
    let n = n.round() as u128;
    let kk = k as u128;
    let c = SUM_CHUNK as u128;
    (0..kk)
        .map(|q| {
            let o = q * n / kk;
            let end = (q + 1) * n / kk;
            if chained {
                // Chunks whose last particle lies in `o .. end`.
                let ends = if end == n {
                    n.div_ceil(c) - o / c
                } else {
                    end / c - o / c
                };
                let ends = if end > o { ends } else { 0 };
                return (ends * a as u128) as f64;
            }
            let len = end - o;
            let starts = end.div_ceil(c) - o.div_ceil(c);
            let cont = if o.is_multiple_of(c) {
                0
            } else {
                len.min(c - o % c)
            };
            1.0 + (cont * e as u128) as f64 + (starts * a as u128) as f64
        })
        .collect()
}

/// Messages in sequence of one chained sum with `n` particles split evenly over `k`
/// ranks: every rank sends its open chunk at once, a rank lying wholly inside one chunk
/// (a pass-through) forwards it after receiving, so the longest run of pass-through ranks
/// plus one (ranks without particles are skipped); zero when no chunk spans a cut.
fn chain_steps(n: f64, k: usize) -> f64 {
    let n = n.round() as u128;
    let kk = k as u128;
    let c = SUM_CHUNK as u128;
    let (mut longest, mut run, mut any) = (0u128, 0u128, false);
    for q in 0..kk {
        let o = q * n / kk;
        let end = (q + 1) * n / kk;
        let open = end > o && end < n && !end.is_multiple_of(c);
        let through = open && !o.is_multiple_of(c) && o / c == end / c;
        any |= open;
        // A rank without particles is skipped: the chain goes on past it.
        if end > o {
            run = if through { run + 1 } else { 0 };
        }
        longest = longest.max(run);
    }
    if any { (longest + 1) as f64 } else { 0.0 }
}

/// Bytes the rank receiving most gets from an all-gather of `words` (per rank).
fn gather_received(words: &[f64]) -> f64 {
    let total: f64 = words.iter().sum();
    let least = words.iter().cloned().fold(f64::INFINITY, f64::min);
    8.0 * (total - least)
}

fn log2_ceil(k: usize) -> f64 {
    (k.max(1) as f64).log2().ceil()
}

impl Inputs {
    /// Cell planes along the cut axis at `n` particles (same packing fraction and
    /// particles per cell): `P0 (N / N0)^(1/D)`, floored.
    pub fn planes(&self, n: f64) -> f64 {
        (self.planes0 * (n / self.n0).powf(1.0 / self.dimension as f64)).floor()
    }

    /// The most ranks of a variant at `n` particles: the cell planes for slabs, the cells
    /// for blocks.
    pub fn max_ranks(&self, variant: Variant, n: f64) -> f64 {
        match variant {
            Variant::BisectionChained => self.planes(n).powi(self.dimension as i32),
            _ => self.planes(n),
        }
    }

    /// Migrants per rank per step on `k` ranks at `n` particles.
    pub fn migrants(&self, variant: Variant, n: f64, k: usize) -> f64 {
        if k < 2 {
            return 0.0;
        }
        let d = self.dimension as f64;
        let face = self.migrants_per_face * (n / self.n0).powf((d - 1.0) / d);
        match variant {
            Variant::BisectionChained => {
                (2.0 * d * face * (k as f64).powf(-1.0 / d)).min(2.0 * face)
            }
            _ => 2.0 * face,
        }
    }

    /// Seconds of one step on `k` ranks at `n` particles (`None` above the variant's
    /// rank limit): `(compute, migration, reductions)`.
    pub fn step_time(&self, variant: Variant, n: f64, k: usize, net: &Network) -> Option<[f64; 3]> {
        if k as f64 > self.max_ranks(variant, n) {
            return None;
        }
        let n_max = match variant {
            Variant::BisectionChained => n / k as f64,
            _ => {
                let p = self.planes(n);
                n * (p / k as f64).ceil() / p
            }
        };
        let compute = self.compute_per_particle_step * n_max;
        if k == 1 {
            return Some([compute, 0.0, 0.0]);
        }
        let (alpha, bw) = (net.latency, net.bandwidth);
        let lg = log2_ceil(k);
        let d = self.dimension;
        let record = 8.0 * (1 + 2 * d) as f64;
        let neighbours = match variant {
            Variant::BisectionChained => 3f64.powi(d as i32) - 1.0,
            _ => 2.0,
        };
        let migration = self.migration_calls
            * (alpha * (lg + neighbours) + record * self.migrants(variant, n, k) / bw);
        let chained = variant != Variant::SlabsRawValues;
        // The gathers of one step: two chunked sums (the mean velocity, D words per
        // value and per accumulator; the peculiar moments, 1 and 2), each after a
        // gather of the counts, the tally and the non-finite check.
        let mut gathers: Vec<Vec<f64>> = vec![
            vec![1.0; k],
            fold_words(n, k, d, d, chained),
            vec![1.0; k],
            fold_words(n, k, 1, 2, chained),
            vec![TALLY_WORDS as f64; k],
            vec![1.0; k],
        ];
        // Scale to the measured number of calls (a different engine configuration may
        // make more or fewer gathers; the extra ones are taken as one-word gathers).
        while (gathers.len() as f64) < self.reduction_calls.round() {
            gathers.push(vec![1.0; k]);
        }
        let mut reductions: f64 = gathers
            .iter()
            .map(|w| 2.0 * alpha * lg + gather_received(w) / bw)
            .sum();
        if chained {
            // Two chained sums per step: the open chunks' accumulators (2 words), the
            // longest sequence of messages.
            reductions += 2.0 * chain_steps(n, k) * (alpha + 16.0 / bw);
        }
        Some([compute, migration, reductions])
    }

    /// Speed-up `T(1) / T(k)` at `n` particles (`None` above the rank limit).
    pub fn speedup(&self, variant: Variant, n: f64, k: usize, net: &Network) -> Option<f64> {
        let t1: f64 = self.step_time(variant, n, 1, net)?.iter().sum();
        let tk: f64 = self.step_time(variant, n, k, net)?.iter().sum();
        Some(t1 / tk)
    }

    /// The first rank count (up to `k_max`) at which the efficiency `S / K` falls below
    /// `efficiency`, with the particles per rank there; `None` when it stays above.
    pub fn falls_below(
        &self,
        variant: Variant,
        n: f64,
        k_max: usize,
        efficiency: f64,
        net: &Network,
    ) -> Option<(usize, f64)> {
        (2..=k_max).find_map(|k| {
            let s = self.speedup(variant, n, k, net)?;
            (s / (k as f64) < efficiency).then_some((k, n / k as f64))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> Inputs {
        Inputs {
            dimension: 2,
            n0: 500_000.0,
            planes0: 224.0,
            compute_per_particle_step: 5e-8,
            migrants_per_face: 25.0,
            migration_calls: 1.0,
            reduction_calls: 6.0,
        }
    }

    const NET: Network = Network {
        latency: 2e-6,
        bandwidth: 1e9,
    };

    #[test]
    fn one_rank_is_the_reference_and_the_slab_limit_is_the_planes() {
        let m = inputs();
        for v in Variant::ALL {
            assert_eq!(m.speedup(v, 5e5, 1, &NET), Some(1.0));
        }
        assert!(m.speedup(Variant::Slabs, 5e5, 224, &NET).is_some());
        assert_eq!(m.speedup(Variant::Slabs, 5e5, 225, &NET), None);
        assert!(
            m.speedup(Variant::BisectionChained, 5e5, 1024, &NET)
                .is_some()
        );
    }

    #[test]
    fn fold_words_cover_every_particle_once() {
        // Chained: one accumulator per chunk, from the rank where it ends. Raw values: the
        // raw values plus one accumulator per chunk start are every particle's value or its
        // chunk's accumulator, once.
        for &(n, k) in &[
            (500_000.0, 7),
            (10_000.0, 64),
            (4096.0 * 3.0, 3),
            (5.0, 8),
            (8192.0, 2),
        ] {
            let w = fold_words(n, k, 1, 1, false);
            let raw_plus_starts: f64 = w.iter().map(|x| x - 1.0).sum();
            let chunks = (n / SUM_CHUNK as f64).ceil();
            let chained: f64 = fold_words(n, k, 1, 1, true).iter().sum();
            assert_eq!(chained, chunks, "n = {n}, k = {k}");
            assert!(raw_plus_starts >= chunks && raw_plus_starts <= n + chunks);
        }
        // Below one chunk per rank most values are gathered raw: only the particles of
        // a rank from a chunk start on (at most one rank's 500 per chunk) are folded.
        let (n, k) = (500_000.0, 1000);
        let chunks = (n / SUM_CHUNK as f64).ceil();
        let w = fold_words(n, k, 1, 1, false);
        let raw: f64 = w.iter().map(|x| x - 1.0).sum::<f64>() - chunks;
        assert!(raw >= n - chunks * (n / k as f64) && raw <= n, "{raw}");
    }

    #[test]
    fn chained_sums_scale_further_than_gathered_raw_values() {
        let m = inputs();
        let a = m
            .speedup(Variant::SlabsRawValues, 5e5, 128, &NET)
            .unwrap_or(0.0);
        let b = m.speedup(Variant::Slabs, 5e5, 128, &NET).unwrap_or(0.0);
        assert!(b > a, "{a} {b}");
        // Compute alone (no network cost) gives the slab imbalance only.
        let free = Network {
            latency: 0.0,
            bandwidth: f64::INFINITY,
        };
        let s = m.speedup(Variant::Slabs, 5e5, 112, &free).unwrap_or(0.0);
        assert!((s - 112.0).abs() < 1e-9, "{s}");
    }

    #[test]
    fn chain_steps_follow_the_ranks_inside_one_chunk() {
        // 4096 or more per rank: every rank sends at once, one message in sequence.
        assert_eq!(chain_steps(500_000.0, 2), 1.0);
        assert_eq!(chain_steps(500_000.0, 100), 1.0);
        // Cuts on chunk boundaries only: nothing to pass.
        assert_eq!(chain_steps(8192.0, 2), 0.0);
        assert_eq!(chain_steps(1000.0, 1), 0.0);
        // 1000 per rank: chunk 0 spans ranks 0 to 4, ranks 1 to 3 wholly inside it, so 4
        // messages in sequence.
        assert_eq!(chain_steps(16_000.0, 16), 4.0);
        // Below one particle per rank most ranks are empty and skipped: one chunk of 100
        // particles on 100 ranks, 99 messages in sequence.
        assert_eq!(chain_steps(100.0, 1000), 99.0);
    }
}
