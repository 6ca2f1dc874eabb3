//! Statistics shared by all engines: running moments, histograms, goodness of fit and
//! batch-means error bars.

use serde::{Deserialize, Serialize};

/// Running mean and variance (Welford's algorithm, numerically stable in one pass).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct RunningStats {
    /// Number of samples.
    pub count: u64,
    mean: f64,
    m2: f64,
}

impl RunningStats {
    /// Empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one sample.
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// The accumulator as three words (the count as its bits), to hand on between ranks.
    pub(crate) fn to_words(&self) -> [f64; 3] {
        [f64::from_bits(self.count), self.mean, self.m2]
    }

    /// The accumulator of [`RunningStats::to_words`].
    pub(crate) fn from_words(w: &[f64]) -> Self {
        Self {
            count: w[0].to_bits(),
            mean: w[1],
            m2: w[2],
        }
    }

    /// The sample mean (NaN when empty).
    pub fn mean(&self) -> f64 {
        if self.count == 0 { f64::NAN } else { self.mean }
    }

    /// The unbiased sample variance (NaN with fewer than two samples).
    pub(crate) fn variance(&self) -> f64 {
        if self.count < 2 {
            f64::NAN
        } else {
            self.m2 / (self.count - 1) as f64
        }
    }

    /// The standard error of the mean, assuming independent samples.
    pub fn standard_error(&self) -> f64 {
        (self.variance() / self.count as f64).sqrt()
    }
}

/// Mean and standard error of a correlated time series by the method of batch means
/// (Flyvbjerg-Petersen): the series is cut into `batches` consecutive blocks whose means
/// are nearly independent when each block is much longer than the correlation time.
pub fn batch_means(series: &[f64], batches: usize) -> (f64, f64) {
    let n = series.len();
    let batches = batches.max(2).min(n.max(1));
    let len = n / batches;
    if len == 0 {
        return (f64::NAN, f64::NAN);
    }
    let mut s = RunningStats::new();
    for b in 0..batches {
        let block = &series[b * len..(b + 1) * len];
        s.push(block.iter().sum::<f64>() / len as f64);
    }
    (s.mean(), s.standard_error())
}

/// A histogram with equal-width bins on `[min, max)`; values outside are counted apart.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Histogram {
    /// Lower edge of the first bin.
    pub min: f64,
    /// Upper edge of the last bin.
    pub max: f64,
    /// Counts per bin.
    pub counts: Vec<u64>,
    /// Samples below `min`.
    pub underflow: u64,
    /// Samples at or above `max`.
    pub overflow: u64,
}

impl Histogram {
    /// `bins` empty bins on `[min, max)`.
    pub fn new(min: f64, max: f64, bins: usize) -> Self {
        assert!(
            max > min && bins > 0,
            "histogram needs max > min and at least one bin"
        );
        Self {
            min,
            max,
            counts: vec![0; bins],
            underflow: 0,
            overflow: 0,
        }
    }

    /// Width of one bin.
    pub fn bin_width(&self) -> f64 {
        (self.max - self.min) / self.counts.len() as f64
    }

    /// Centre of bin `i`.
    pub fn bin_center(&self, i: usize) -> f64 {
        self.min + (i as f64 + 0.5) * self.bin_width()
    }

    /// Adds one sample.
    #[inline]
    pub fn push(&mut self, x: f64) {
        if x < self.min {
            self.underflow += 1;
        } else {
            let i = ((x - self.min) / self.bin_width()) as usize;
            if i < self.counts.len() {
                self.counts[i] += 1;
            } else {
                self.overflow += 1;
            }
        }
    }

    /// Total number of samples, including under- and overflow.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum::<u64>() + self.underflow + self.overflow
    }

    /// Probability density per bin (counts / (total * width)).
    pub fn density(&self) -> Vec<f64> {
        let norm = self.total() as f64 * self.bin_width();
        self.counts.iter().map(|&c| c as f64 / norm).collect()
    }

    /// Adds the counts of another histogram with identical bins.
    pub fn merge(&mut self, other: &Histogram) {
        assert_eq!(self.counts.len(), other.counts.len());
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.underflow += other.underflow;
        self.overflow += other.overflow;
    }
}

/// Result of Pearson's chi-square goodness-of-fit test.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ChiSquare {
    /// The chi-square statistic.
    pub statistic: f64,
    /// Degrees of freedom (bins used minus one).
    pub degrees_of_freedom: usize,
    /// Probability of a statistic at least this large if the model is right.
    pub p_value: f64,
}

impl ChiSquare {
    /// The same test when `fitted` parameters of the model were estimated from the same
    /// counts: that many degrees of freedom fewer (at least one), and the p-value for them.
    pub fn with_fitted_parameters(&self, fitted: usize) -> ChiSquare {
        let dof = self.degrees_of_freedom.saturating_sub(fitted).max(1);
        let p_value = if self.statistic.is_finite() {
            puruspe::gammq(dof as f64 / 2.0, self.statistic / 2.0)
        } else {
            0.0
        };
        ChiSquare {
            statistic: self.statistic,
            degrees_of_freedom: dof,
            p_value,
        }
    }
}

/// Pearson's chi-square test of a histogram against a model given by its cumulative
/// distribution function. Neighbouring bins are pooled until each expects at least five
/// counts (the usual validity condition), the tails outside the histogram included.
pub fn chi_square_test(hist: &Histogram, cdf: impl Fn(f64) -> f64) -> ChiSquare {
    let n = hist.total() as f64;
    let nb = hist.counts.len();
    // Cells: (observed, expected), starting with the underflow tail.
    let mut cells: Vec<(f64, f64)> = Vec::with_capacity(nb + 2);
    cells.push((hist.underflow as f64, n * cdf(hist.min)));
    for i in 0..nb {
        let lo = hist.min + i as f64 * hist.bin_width();
        let hi = lo + hist.bin_width();
        cells.push((hist.counts[i] as f64, n * (cdf(hi) - cdf(lo))));
    }
    cells.push((hist.overflow as f64, n * (1.0 - cdf(hist.max))));
    let mut pooled: Vec<(f64, f64)> = Vec::new();
    let mut acc = (0.0, 0.0);
    for c in cells {
        acc.0 += c.0;
        acc.1 += c.1;
        if acc.1 >= 5.0 {
            pooled.push(acc);
            acc = (0.0, 0.0);
        }
    }
    if acc.1 > 0.0 || acc.0 > 0.0 {
        match pooled.last_mut() {
            Some(last) => {
                last.0 += acc.0;
                last.1 += acc.1;
            }
            None => pooled.push(acc),
        }
    }
    let statistic: f64 = pooled
        .iter()
        .map(|&(o, e)| {
            if e > 0.0 {
                (o - e) * (o - e) / e
            } else if o > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        })
        .sum();
    let dof = pooled.len().saturating_sub(1).max(1);
    let p_value = if statistic.is_finite() {
        puruspe::gammq(dof as f64 / 2.0, statistic / 2.0)
    } else {
        0.0
    };
    ChiSquare {
        statistic,
        degrees_of_freedom: dof,
        p_value,
    }
}

/// `log10` of the chi-square survival function `p = Q(dof/2, statistic/2)` (the regularised
/// upper incomplete gamma function), finite where `p` itself underflows to 0 in `f64`
/// (`statistic` of thousands). Where `Q` is a normal number it is `log10(gammq)`; below,
/// the continued fraction of `Q` (Press et al., Numerical Recipes, 3rd ed., Eq. 6.2.7,
/// modified Lentz) is summed with its prefactor `exp(-x) x^a / Gamma(a)` taken in logarithms.
/// `-inf` for an infinite statistic.
pub fn chi_square_log10_p(statistic: f64, degrees_of_freedom: usize) -> f64 {
    let a = degrees_of_freedom.max(1) as f64 / 2.0;
    let x = statistic / 2.0;
    if !x.is_finite() {
        return f64::NEG_INFINITY;
    }
    let q = puruspe::gammq(a, x);
    if q >= f64::MIN_POSITIVE || x < a + 1.0 {
        return q.log10();
    }
    const TINY: f64 = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..10_000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < TINY {
            d = TINY;
        }
        c = b + an / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    (-x + a * x.ln() - puruspe::ln_gamma(a) + h.ln()) / std::f64::consts::LN_10
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    #[test]
    fn welford_matches_two_pass() {
        let xs = [1.0, 2.0, 4.0, 7.0];
        let mut s = RunningStats::new();
        xs.iter().for_each(|&x| s.push(x));
        assert!((s.mean() - 3.5).abs() < 1e-15);
        assert!((s.variance() - 7.0).abs() < 1e-12);
    }

    #[test]
    fn chi_square_accepts_uniform_and_rejects_wrong_model() {
        let mut rng = stream(1, &[9]);
        let mut h = Histogram::new(0.0, 1.0, 20);
        for _ in 0..100_000 {
            h.push(rng.random::<f64>());
        }
        let good = chi_square_test(&h, |x| x.clamp(0.0, 1.0));
        assert!(good.p_value > 1e-3, "{good:?}");
        let bad = chi_square_test(&h, |x| x.clamp(0.0, 1.0).powf(1.05));
        assert!(bad.p_value < 1e-6, "{bad:?}");
    }

    /// Where `p` is representable the log is `log10(p)`; where it underflows the continued
    /// fraction continues the same curve: Q(1, x) = exp(-x) exactly (2 dof), and for 10 dof
    /// the closed form Q(5, x) = exp(-x) (1 + x + x²/2 + x³/6 + x⁴/24).
    #[test]
    fn chi_square_log10_p_continues_past_the_underflow() {
        for stat in [3.0, 40.0, 700.0, 1400.0, 5000.0, 1e5] {
            let exact = -stat / 2.0 / std::f64::consts::LN_10;
            let got = chi_square_log10_p(stat, 2);
            assert!(
                (got - exact).abs() < 1e-9 * exact.abs().max(1.0),
                "{stat}: {got} {exact}"
            );
            let x: f64 = stat / 2.0;
            let poly = 1.0 + x + x * x / 2.0 + x.powi(3) / 6.0 + x.powi(4) / 24.0;
            let exact = (-x + poly.ln()) / std::f64::consts::LN_10;
            let got = chi_square_log10_p(stat, 10);
            assert!(
                (got - exact).abs() < 1e-9 * exact.abs().max(1.0),
                "{stat}: {got} {exact}"
            );
        }
        // The underflow itself: p is 0 in f64, its logarithm is not.
        assert_eq!(puruspe::gammq(1.0, 2500.0), 0.0);
        assert!(chi_square_log10_p(5000.0, 2).is_finite());
        assert_eq!(chi_square_log10_p(f64::INFINITY, 3), f64::NEG_INFINITY);
    }
}
