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
    pub(crate) fn scaled(self, k: f64) -> Self {
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

/// The grid points `next, next + dt, next + 2 dt, ...` (accumulated one addition at a
/// time, as the samplers always did) that lie before `upto`, or at it when `inclusive`:
/// returns their number and the first grid point after them.
#[inline]
pub(crate) fn grid_points_before(next: f64, dt: f64, upto: f64, inclusive: bool) -> (u64, f64) {
    let mut t = next;
    let mut n = 0u64;
    while t < upto || (inclusive && t == upto) {
        n += 1;
        t += dt;
    }
    (n, t)
}

/// Number of batches used for batch-means errors.
pub(crate) const BATCHES: usize = 32;

/// Most block means a `GridSeries` keeps: when it has this many, adjacent pairs are
/// merged into blocks twice as long. A run's memory and checkpoint therefore stay bounded
/// (at most `N * MAX_BLOCKS` numbers, 1.5 MB for the needle's six quantities) whatever its
/// length; runs with fewer than `MAX_BLOCKS * 64` samples (2.1 million, the bundled
/// scenarios among them) are not affected.
pub const MAX_BLOCKS: usize = 1 << 15;

/// Accumulates `N` quantities sampled on a fixed time grid, in blocks of `block_len`
/// consecutive samples; the block means are the input of the batch-means error estimate
/// (`crate::stats::batch_means`). At [`MAX_BLOCKS`] blocks the block length doubles (pairs
/// of blocks merged), so the memory is at most `N * MAX_BLOCKS` numbers; the batch means
/// stay means of equally long runs of consecutive samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "GridSeriesData", try_from = "GridSeriesData")]
pub(crate) struct GridSeries<const N: usize> {
    block_len: u32,
    in_block: u32,
    sums: [f64; N],
    /// Block means, block-major.
    blocks: Vec<[f64; N]>,
    /// Sum of the completed blocks' sums (for the overall mean).
    totals: [f64; N],
    count: u64,
}

/// Serialised form of a [`GridSeries`] (serde derives do not cover `[f64; N]` for a
/// generic `N`): the fixed-size arrays as vectors, blocks flattened block-major.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct GridSeriesData {
    block_len: u32,
    in_block: u32,
    sums: Vec<f64>,
    blocks: Vec<f64>,
    totals: Vec<f64>,
    count: u64,
}

impl<const N: usize> From<GridSeries<N>> for GridSeriesData {
    fn from(g: GridSeries<N>) -> Self {
        Self {
            block_len: g.block_len,
            in_block: g.in_block,
            sums: g.sums.to_vec(),
            blocks: g.blocks.iter().flatten().copied().collect(),
            totals: g.totals.to_vec(),
            count: g.count,
        }
    }
}

impl<const N: usize> TryFrom<GridSeriesData> for GridSeries<N> {
    type Error = String;
    fn try_from(d: GridSeriesData) -> Result<Self, String> {
        let array = |v: &[f64]| -> Result<[f64; N], String> {
            v.try_into()
                .map_err(|_| format!("grid series: expected {N} values, found {}", v.len()))
        };
        if N == 0 || !d.blocks.len().is_multiple_of(N) {
            return Err(format!(
                "grid series: {} block values are not a multiple of {N}",
                d.blocks.len()
            ));
        }
        Ok(Self {
            block_len: d.block_len.max(1),
            in_block: d.in_block,
            sums: array(&d.sums)?,
            blocks: d
                .blocks
                .chunks(N)
                .map(array)
                .collect::<Result<Vec<_>, String>>()?,
            totals: array(&d.totals)?,
            count: d.count,
        })
    }
}

impl<const N: usize> GridSeries<N> {
    /// Blocks of `block_len` samples.
    pub(crate) fn new(block_len: u32) -> Self {
        Self {
            block_len: block_len.max(1),
            in_block: 0,
            sums: [0.0; N],
            blocks: Vec::new(),
            totals: [0.0; N],
            count: 0,
        }
    }

    /// Adds one grid sample.
    #[inline]
    pub(crate) fn push(&mut self, values: [f64; N]) {
        for (s, x) in self.sums.iter_mut().zip(values) {
            *s += x;
        }
        self.in_block += 1;
        self.count += 1;
        if self.in_block == self.block_len {
            self.close_block();
        }
    }

    /// Adds `n` grid samples that all have the same `values` (the state is constant between
    /// collisions): the same sums and block boundaries as `n` calls of [`Self::push`], up to
    /// floating-point rounding (`n x` instead of `x + ... + x`).
    #[inline]
    pub(crate) fn push_n(&mut self, values: [f64; N], n: u64) {
        let mut left = n;
        loop {
            // Samples that fit in the current block (may be 0: then nothing changes).
            let take = left.min(u64::from(self.block_len - self.in_block));
            let w = f64::from(take as u32);
            for (s, x) in self.sums.iter_mut().zip(values) {
                *s += w * x;
            }
            self.in_block += take as u32;
            self.count += take;
            left -= take;
            if self.in_block == self.block_len {
                self.close_block();
            }
            if left == 0 {
                return;
            }
        }
    }

    #[cold]
    fn close_block(&mut self) {
        let inv = 1.0 / f64::from(self.block_len);
        let mut means = [0.0; N];
        for ((m, t), s) in means.iter_mut().zip(&mut self.totals).zip(&mut self.sums) {
            *m = *s * inv;
            *t += *s;
            *s = 0.0;
        }
        self.blocks.push(means);
        self.in_block = 0;
        if self.blocks.len() >= MAX_BLOCKS {
            self.merge_pairs();
        }
    }

    /// Halves the number of blocks by averaging adjacent pairs (an odd last block is kept
    /// apart in `sums`, as the start of the next, longer block) and doubles `block_len`.
    #[cold]
    fn merge_pairs(&mut self) {
        let Some(longer) = self.block_len.checked_mul(2) else {
            return; // 2^31 samples per block: more blocks rather than an overflow
        };
        let odd = self.blocks.len() % 2 == 1;
        if odd {
            // The last block goes back into the open sums (its samples, not yet closed).
            let last = self.blocks.pop().unwrap_or([0.0; N]);
            let len = f64::from(self.block_len);
            for ((s, t), m) in self.sums.iter_mut().zip(&mut self.totals).zip(last) {
                *s += m * len;
                *t -= m * len;
            }
            self.in_block += self.block_len;
        }
        let merged: Vec<[f64; N]> = self
            .blocks
            .chunks_exact(2)
            .map(|p| {
                let mut m = [0.0; N];
                for (q, x) in m.iter_mut().enumerate() {
                    *x = 0.5 * (p[0][q] + p[1][q]);
                }
                m
            })
            .collect();
        self.blocks = merged;
        self.block_len = longer;
    }

    /// Number of samples.
    pub(crate) fn samples(&self) -> u64 {
        self.count
    }

    /// Mean of quantity `q` over all samples (NaN when empty).
    pub(crate) fn mean(&self, q: usize) -> f64 {
        if self.count == 0 {
            f64::NAN
        } else {
            (self.totals[q] + self.sums[q]) / self.count as f64
        }
    }

    /// Block means of quantity `q`.
    pub(crate) fn block_means(&self, q: usize) -> Vec<f64> {
        self.blocks.iter().map(|b| b[q]).collect()
    }

    /// Mean of quantity `q` over all samples and its batch-means standard error (NaN error
    /// with fewer than 2 complete blocks).
    pub(crate) fn estimate(&self, q: usize) -> Estimate {
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
    pub(crate) fn estimate_fn(&self, g: impl Fn(&[f64; N]) -> f64) -> Estimate {
        let nblocks = self.blocks.len();
        let mut overall = [0.0; N];
        for (q, o) in overall.iter_mut().enumerate() {
            *o = self.mean(q);
        }
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
        for b in 0..batches {
            let mut buf = [0.0; N];
            for block in &self.blocks[b * per..(b + 1) * per] {
                for (x, y) in buf.iter_mut().zip(block) {
                    *x += y;
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
pub(crate) fn hist_push(h: &mut Histogram, inv_width: f64, x: f64) {
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

/// [`hist_push`] of `n` equal samples.
///
/// The bin index goes through `i64` (one `cvttsd2si` on x86-64, where a direct `f64` to
/// `usize` conversion takes about ten instructions): the same index for every
/// `x >= h.min`, huge values still fall in `overflow` and NaN in bin 0, as with `usize`.
#[inline]
pub(crate) fn hist_push_n(h: &mut Histogram, inv_width: f64, x: f64, n: u64) {
    if x < h.min {
        h.underflow += n;
    } else {
        let i = ((x - h.min) * inv_width) as i64 as usize;
        match h.counts.get_mut(i) {
            Some(c) => *c += n,
            None => h.overflow += n,
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
    pub(crate) fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            columns: Vec::new(),
        }
    }
    /// Adds a column.
    pub(crate) fn push(&mut self, name: impl Into<String>, values: Vec<f64>) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `push_n` gives the blocks and means of `n` calls of `push`.
    #[test]
    fn push_n_matches_push() {
        let mut batched = GridSeries::<1>::new(7);
        let mut single = GridSeries::<1>::new(7);
        for k in 0..5000u64 {
            let (x, n) = ((k % 5) as f64, (k * 7919) % 13);
            batched.push_n([x], n);
            for _ in 0..n {
                single.push([x]);
            }
        }
        assert_eq!(batched.samples(), single.samples());
        assert_eq!(batched.block_means(0).len(), single.block_means(0).len());
        for (a, b) in batched.block_means(0).iter().zip(single.block_means(0)) {
            assert!((a - b).abs() < 1e-12, "{a} {b}");
        }
        assert!((batched.mean(0) - single.mean(0)).abs() < 1e-12);
    }

    /// Past `MAX_BLOCKS` blocks the block length doubles: the blocks stay bounded and each
    /// is still the mean of one run of consecutive samples (checked on the ramp `x_k = k`,
    /// whose block means are known exactly), and the overall mean is that of all samples.
    #[test]
    fn blocks_stay_bounded_and_consecutive() {
        let len = 4u32;
        let mut g = GridSeries::<1>::new(len);
        let samples = 5 * MAX_BLOCKS as u64 * u64::from(len) + 3;
        for k in 0..samples {
            g.push([k as f64]);
        }
        let blocks = g.block_means(0);
        assert!(blocks.len() <= MAX_BLOCKS && blocks.len() >= MAX_BLOCKS / 2);
        let per = u64::from(g.block_len);
        assert_eq!(
            per,
            8 * u64::from(len),
            "block length after three doublings"
        );
        for (b, &m) in blocks.iter().enumerate() {
            let first = b as u64 * per;
            let exact = first as f64 + (per - 1) as f64 / 2.0;
            assert_eq!(m, exact, "block {b}");
        }
        assert_eq!(g.samples(), samples);
        assert_eq!(g.mean(0), (samples - 1) as f64 / 2.0);
        // The serialised size is bounded too.
        let bytes = rmp_serde::to_vec(&g).unwrap().len();
        assert!(bytes < 10 * MAX_BLOCKS, "{bytes} bytes");
    }
}
