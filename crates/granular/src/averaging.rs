//! Means and standard errors of correlated time series in constant memory: the blocking
//! method of H. Flyvbjerg and H. G. Petersen, J. Chem. Phys. 91, 461 (1989), run online.
//!
//! Level `k` of a `Blocking` accumulator holds the running mean and variance of the
//! means of consecutive blocks of `2^k` samples, and the one half-finished block that
//! waits for its partner; a sample enters level 0 and, paired with the one waiting there,
//! goes on to level 1 as the mean of the pair, and so on. Memory is `O(log N)` and the
//! state is a few numbers per level, so a checkpoint restores it bit for bit.
//!
//! The standard error at level `k`, `σ_k = sqrt(Var(block means) / n_k)` with `n_k` whole
//! blocks, grows with `k` until the blocks are longer than the correlation time and then
//! stays on a plateau (Flyvbjerg-Petersen). The block length is chosen from the data by
//! the criterion of M. Lee, G. Drummond and R. Needs (Phys. Rev. B 83, 245114 (2011),
//! section III; the rule of the `pyblock` package): the smallest `B = 2^k` with
//! `B³ > 2 N (σ_k / σ_0)⁴`, among the levels with at least `MIN_BLOCKS` blocks. No error
//! is given when no level qualifies, or when a longer block length gives an error larger
//! than the chosen one by more than three of its own uncertainties
//! `σ_k' / sqrt(2 (n_k' - 1))` (no plateau: a drift, such as a cooling gas's temperature,
//! or a correlation time comparable to the run).

use crate::stats::RunningStats;
use serde::{Deserialize, Serialize};

/// Fewest blocks at the chosen level (the error of the error is then at most
/// `1 / sqrt(2 × 7) ≈ 27 %`).
pub(crate) const MIN_BLOCKS: u64 = 8;

/// One level of the blocking transformation: blocks of `2^k` samples.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Level {
    /// Mean and variance of the whole blocks' means.
    stats: RunningStats,
    /// The mean of a block waiting for its partner.
    pending: Option<f64>,
}

/// The blocking accumulator of one observable (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Blocking {
    levels: Vec<Level>,
}

/// Mean and standard error of a series, with the block length the error comes from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BlockingEstimate {
    /// Samples.
    pub samples: u64,
    /// Mean of all samples.
    pub mean: f64,
    /// Standard error of the mean at the chosen block length; `None` where no block
    /// length gives a valid estimate (`note` says why).
    pub error: Option<f64>,
    /// The uncertainty of `error`, `error / sqrt(2 (blocks - 1))`.
    pub error_of_error: Option<f64>,
    /// Chosen block length, in samples (0 when none).
    pub block_length: u64,
    /// Whole blocks of that length.
    pub blocks: u64,
    /// Why there is no error, when there is none.
    pub note: Option<String>,
}

impl Blocking {
    /// An empty accumulator.
    pub(crate) fn new() -> Blocking {
        Blocking::default()
    }

    /// Adds one sample (non-finite samples are the caller's to leave out).
    pub(crate) fn push(&mut self, x: f64) {
        let mut value = x;
        let mut k = 0;
        loop {
            if k == self.levels.len() {
                self.levels.push(Level::default());
            }
            let level = &mut self.levels[k];
            level.stats.push(value);
            match level.pending.take() {
                None => {
                    level.pending = Some(value);
                    return;
                }
                Some(first) => {
                    value = 0.5 * (first + value);
                    k += 1;
                }
            }
        }
    }

    /// Samples pushed.
    pub(crate) fn samples(&self) -> u64 {
        self.levels.first().map_or(0, |l| l.stats.count)
    }

    /// Mean of all samples (NaN when empty).
    pub(crate) fn mean(&self) -> f64 {
        self.levels.first().map_or(f64::NAN, |l| l.stats.mean())
    }

    /// `(block length, blocks, standard error)` of every level with at least two blocks.
    pub(crate) fn levels(&self) -> Vec<(u64, u64, f64)> {
        self.levels
            .iter()
            .enumerate()
            .filter(|(_, l)| l.stats.count >= 2)
            .map(|(k, l)| (1u64 << k, l.stats.count, l.stats.standard_error()))
            .collect()
    }

    /// Mean and standard error, the block length chosen as the module documentation says.
    pub(crate) fn estimate(&self) -> BlockingEstimate {
        let samples = self.samples();
        let mut out = BlockingEstimate {
            samples,
            mean: self.mean(),
            error: None,
            error_of_error: None,
            block_length: 0,
            blocks: 0,
            note: None,
        };
        let levels: Vec<(u64, u64, f64)> = self
            .levels()
            .into_iter()
            .filter(|&(_, n, _)| n >= MIN_BLOCKS)
            .collect();
        let Some(&(_, _, naive)) = levels.first() else {
            out.note = Some(format!(
                "{samples} samples after the equilibration time: at least {MIN_BLOCKS} are \
                 needed for an error; run longer or lower output.interval"
            ));
            return out;
        };
        if naive == 0.0 {
            // A constant series (an exactly conserved quantity): its mean has no error.
            out.error = Some(0.0);
            out.error_of_error = Some(0.0);
            out.block_length = 1;
            out.blocks = samples;
            return out;
        }
        let n = samples as f64;
        let chosen = levels
            .iter()
            .position(|&(b, _, s)| (b as f64).powi(3) > 2.0 * n * (s / naive).powi(4));
        let Some(k) = chosen else {
            out.note = Some(format!(
                "no block length of at least {MIN_BLOCKS} blocks is longer than the correlation \
                 time ({samples} samples): run longer for an error"
            ));
            return out;
        };
        let (b, blocks, error) = levels[k];
        let uncertainty = |s: f64, m: u64| s / (2.0 * (m as f64 - 1.0)).sqrt();
        if let Some(&(b2, _, s2)) = levels[k + 1..]
            .iter()
            .find(|&&(_, m, s)| s > error + 3.0 * uncertainty(s, m))
        {
            out.note = Some(format!(
                "no plateau: the error grows from {error:.3e} (blocks of {b} samples) to \
                 {s2:.3e} (blocks of {b2}); the series drifts (not a steady state) or is \
                 correlated over a good part of the run"
            ));
            return out;
        }
        out.error = Some(error);
        out.error_of_error = Some(uncertainty(error, blocks));
        out.block_length = b;
        out.blocks = blocks;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::RngExt;
    use rand_distr::StandardNormal;

    /// The AR(1) process `x_t = φ x_{t-1} + ε_t`, mean 0, whose mean has the variance
    /// `σ_ε² / (1-φ)² / N` for long series.
    fn ar1(seed: u64, n: usize, phi: f64) -> Vec<f64> {
        let mut rng = stream(seed, &[7]);
        let mut x = 0.0;
        // Start in the stationary distribution.
        x += rng.sample::<f64, _>(StandardNormal) / (1.0 - phi * phi).sqrt();
        (0..n)
            .map(|_| {
                x = phi * x + rng.sample::<f64, _>(StandardNormal);
                x
            })
            .collect()
    }

    #[test]
    fn mean_and_levels_are_those_of_the_series() {
        let xs = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0];
        let mut b = Blocking::new();
        xs.iter().for_each(|&x| b.push(x));
        assert_eq!(b.samples(), 8);
        assert_eq!(b.mean(), 4.5);
        let levels = b.levels();
        // Blocks of 2: 1.5, 3.5, 5.5, 7.5; of 4: 2.5, 6.5.
        assert_eq!(levels[1].0, 2);
        assert_eq!(levels[1].1, 4);
        let mut s = RunningStats::new();
        [1.5, 3.5, 5.5, 7.5].iter().for_each(|&x| s.push(x));
        assert_eq!(levels[1].2, s.standard_error());
        assert_eq!((levels[2].0, levels[2].1), (4, 2));
    }

    /// The exact standard error of the mean of an AR(1) series is found, and the z-scores
    /// of 200 independent series are standard normal (mean, variance, and no outlier).
    #[test]
    fn ar1_z_scores_are_standard_normal() {
        let (n, phi) = (1 << 14, 0.8);
        let exact = 1.0 / (1.0 - phi) / (n as f64).sqrt();
        let mut z = RunningStats::new();
        let mut ratio = RunningStats::new();
        for seed in 0..200 {
            let mut b = Blocking::new();
            ar1(seed, n, phi).iter().for_each(|&x| b.push(x));
            let e = b.estimate();
            let error = e.error.expect("an error for a stationary series");
            let zi = e.mean / error;
            assert!(zi.abs() < 4.5, "seed {seed}: z = {zi}");
            z.push(zi);
            ratio.push(error / exact);
        }
        // 200 z's: the mean within 4/sqrt(200), the variance within 4 sqrt(2/199) of 1
        // (widened by the ~15 % scatter of each error estimate).
        assert!(z.mean().abs() < 4.0 / 200f64.sqrt(), "mean z {}", z.mean());
        assert!(
            (z.variance() - 1.0).abs() < 4.0 * (2.0f64 / 199.0).sqrt() + 0.15,
            "var z {}",
            z.variance()
        );
        // The error itself, averaged over the seeds, within 5 % of the exact one.
        assert!(
            (ratio.mean() - 1.0).abs() < 0.05,
            "error / exact {}",
            ratio.mean()
        );
    }

    #[test]
    fn a_drift_has_no_error() {
        let mut b = Blocking::new();
        (0..4096).for_each(|i| b.push((-(i as f64) / 1000.0).exp()));
        let e = b.estimate();
        assert!(e.error.is_none() && e.note.is_some(), "{e:?}");
    }

    #[test]
    fn too_few_samples_have_no_error() {
        let mut b = Blocking::new();
        (0..5).for_each(|i| b.push(i as f64));
        let e = b.estimate();
        assert!(e.error.is_none() && e.note.is_some());
        assert_eq!(e.mean, 2.0);
    }

    #[test]
    fn a_constant_series_has_zero_error() {
        let mut b = Blocking::new();
        (0..100).for_each(|_| b.push(2.5));
        let e = b.estimate();
        assert_eq!((e.mean, e.error), (2.5, Some(0.0)));
    }
}
