//! The fixed order of the DSMC engine's floating-point sums over its grains: fixed chunks
//! of [`SUM_CHUNK`] grains of the storage order, each summed from zero in storage order,
//! then the chunks' sums added in order. The bits do not depend on the number of threads;
//! a decomposed engine reproduces them over its ranks (`Domain::ordered_fold`).

/// Fixed chunk length of the deterministic reductions (independent of the thread count).
pub(crate) const SUM_CHUNK: usize = 4096;

use rayon::prelude::*;

/// The chunked fold of the values `elem(i)` (`E` words each) of `n` grains in storage
/// order: each chunk of [`SUM_CHUNK`] grains folded from zero by `fold` (in parallel over
/// chunks), then the chunks' accumulators (`A` words) added in order by `combine`, from
/// zero. The threaded engine's sums; `Domain::ordered_fold` gives the same bits over ranks.
pub(crate) fn ordered_fold<const E: usize, const A: usize>(
    n: usize,
    elem: impl Fn(usize) -> [f64; E] + Sync,
    fold: impl Fn(&mut [f64; A], &[f64; E]) + Sync,
    combine: impl Fn(&mut [f64; A], &[f64; A]),
) -> [f64; A] {
    let chunks: Vec<[f64; A]> = (0..n.div_ceil(SUM_CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut acc = [0.0; A];
            for i in c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n) {
                fold(&mut acc, &elem(i));
            }
            acc
        })
        .collect();
    let mut total = [0.0; A];
    for c in &chunks {
        combine(&mut total, c);
    }
    total
}
