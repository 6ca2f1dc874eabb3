//! Time-grid sampling of observables with batch-means error bars.

use serde::{Deserialize, Serialize};

use crate::stats::{Histogram, RunningStats, batch_means};

/// A mean with its statistical (one standard error) uncertainty.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// The estimate.
    pub mean: f64,
    /// One standard error.
    pub error: f64,
}

impl Estimate {
    /// Scales mean and error by a constant.
    pub fn scaled(self, k: f64) -> Self {
        Self {
            mean: self.mean * k,
            error: self.error * k.abs(),
        }
    }
    /// Distance to `x` in units of the error.
    pub fn z_score(&self, x: f64) -> f64 {
        (self.mean - x) / self.error
    }
}

/// Number of batches used for batch-means errors.
pub const BATCHES: usize = 32;

/// Accumulates `n` quantities sampled on a fixed time grid, in blocks of `block_len`
/// consecutive samples; the block means are the input of the batch-means error estimate
/// (`crate::stats::batch_means`), so the memory is `n * samples / block_len`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridSeries {
    n: usize,
    block_len: usize,
    in_block: usize,
    sums: Vec<f64>,
    /// Block means, `n` per block, block-major.
    blocks: Vec<f64>,
    /// Sum of all samples, per quantity (for the overall mean).
    totals: Vec<f64>,
    count: u64,
}

impl GridSeries {
    /// `n` quantities, blocks of `block_len` samples.
    pub fn new(n: usize, block_len: usize) -> Self {
        Self {
            n,
            block_len: block_len.max(1),
            in_block: 0,
            sums: vec![0.0; n],
            blocks: Vec::new(),
            totals: vec![0.0; n],
            count: 0,
        }
    }

    /// Adds one grid sample (`values.len() == n`).
    #[inline]
    pub fn push(&mut self, values: &[f64]) {
        for (s, &x) in self.sums.iter_mut().zip(values) {
            *s += x;
        }
        self.in_block += 1;
        self.count += 1;
        if self.in_block == self.block_len {
            let inv = 1.0 / self.block_len as f64;
            for (s, t) in self.sums.iter_mut().zip(self.totals.iter_mut()) {
                self.blocks.push(*s * inv);
                *t += *s;
                *s = 0.0;
            }
            self.in_block = 0;
        }
    }

    /// Number of samples.
    pub fn samples(&self) -> u64 {
        self.count
    }

    /// Mean of quantity `q` over all samples (NaN when empty).
    pub fn mean(&self, q: usize) -> f64 {
        if self.count == 0 {
            f64::NAN
        } else {
            (self.totals[q] + self.sums[q]) / self.count as f64
        }
    }

    /// Block means of quantity `q`.
    pub fn block_means(&self, q: usize) -> Vec<f64> {
        self.blocks
            .iter()
            .skip(q)
            .step_by(self.n)
            .copied()
            .collect()
    }

    /// Mean of quantity `q` over all samples and its batch-means standard error (NaN error
    /// with fewer than 2 complete blocks).
    pub fn estimate(&self, q: usize) -> Estimate {
        let blocks = self.block_means(q);
        let (_, error) = if blocks.len() >= 2 {
            batch_means(&blocks, BATCHES)
        } else {
            (f64::NAN, f64::NAN)
        };
        Estimate {
            mean: self.mean(q),
            error,
        }
    }

    /// Estimate of `g(means of the quantities)` from per-batch values of `g` (batch means
    /// of a smooth function; its bias is of order 1/(samples per batch)).
    pub fn estimate_fn(&self, g: impl Fn(&[f64]) -> f64) -> Estimate {
        let nblocks = self.blocks.len() / self.n.max(1);
        let overall: Vec<f64> = (0..self.n).map(|q| self.mean(q)).collect();
        let mean = g(&overall);
        if nblocks < 2 {
            return Estimate {
                mean,
                error: f64::NAN,
            };
        }
        let batches = BATCHES.min(nblocks);
        let per = nblocks / batches;
        let mut st = RunningStats::new();
        let mut buf = vec![0.0; self.n];
        for b in 0..batches {
            buf.iter_mut().for_each(|x| *x = 0.0);
            for k in b * per..(b + 1) * per {
                for (b, x) in buf
                    .iter_mut()
                    .zip(&self.blocks[k * self.n..(k + 1) * self.n])
                {
                    *b += x;
                }
            }
            buf.iter_mut().for_each(|x| *x /= per as f64);
            st.push(g(&buf));
        }
        Estimate {
            mean,
            error: st.standard_error(),
        }
    }
}

/// Adds `x` to a histogram with a precomputed `1/bin_width` (same binning as
/// [`Histogram::push`], without its division).
#[inline]
pub fn hist_push(h: &mut Histogram, inv_width: f64, x: f64) {
    if x < h.min {
        h.underflow += 1;
    } else {
        let i = ((x - h.min) * inv_width) as usize;
        match h.counts.get_mut(i) {
            Some(c) => *c += 1,
            None => h.overflow += 1,
        }
    }
}

/// A named-column table (the data of one figure or one curve set).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Table {
    /// What the table shows.
    pub title: String,
    /// Columns `(name, values)`, all of the same length.
    pub columns: Vec<(String, Vec<f64>)>,
}

impl Table {
    /// Empty table.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            columns: Vec::new(),
        }
    }
    /// Adds a column.
    pub fn push(&mut self, name: impl Into<String>, values: Vec<f64>) {
        self.columns.push((name.into(), values));
    }
    /// The column named `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.1.len())
    }
    /// CSV text with a header line.
    pub fn to_csv(&self) -> String {
        let mut s = self
            .columns
            .iter()
            .map(|c| c.0.as_str())
            .collect::<Vec<_>>()
            .join(",");
        s.push('\n');
        for r in 0..self.rows() {
            let row: Vec<String> = self
                .columns
                .iter()
                .map(|c| c.1.get(r).map_or(String::new(), |x| format!("{x}")))
                .collect();
            s.push_str(&row.join(","));
            s.push('\n');
        }
        s
    }
}
