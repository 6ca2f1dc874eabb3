//! The cell grid and the per-step counting sort that keeps particles ordered by cell.
//!
//! # Storage layout (and why)
//!
//! Particles live in a *structure of arrays* (one array per quantity: positions,
//! velocities, last-collision times) that is re-sorted by cell index after every
//! free-flight stage with a stable counting sort. Each cell then owns one contiguous
//! index range `start[c] .. start[c + 1]`, so
//!
//! * the collision stage hands disjoint slices of consecutive cells to rayon workers
//!   (no locks, no `unsafe`), and the result does not depend on how cells are grouped;
//! * the cells of a spatial sub-domain (a slab of consecutive cell indices, axis
//!   `D - 1` slowest) occupy one contiguous slice of every array, which is exactly what a
//!   domain decomposition over machines (MPI) must send or receive: the particles that
//!   left the slab are the tails of the sorted arrays, packable without a rewrite;
//! * successive steps touch memory sequentially (particles rarely change cell).

use crate::boundary::SimulationBox;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// A regular grid of `n_0 x ... x n_{D-1}` cells covering the box.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CellGrid<const D: usize> {
    /// Cells per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub dims: [usize; D],
    /// Cell edge per axis (`L_k / n_k`).
    #[serde(with = "crate::vector::serde_array")]
    pub edges: [f64; D],
    /// Inverse cell edges.
    #[serde(with = "crate::vector::serde_array")]
    inv_edges: [f64; D],
    /// Cell volume `V_c` (area in 2D).
    pub volume: f64,
}

impl<const D: usize> CellGrid<D> {
    /// Cells of requested edge `cell_size`: `n_k = max(1, floor(L_k / cell_size))` (with a
    /// relative tolerance of 1e-9 so that exact multiples are not rounded down).
    pub fn new(sim_box: &SimulationBox<D>, cell_size: f64) -> Self {
        let mut dims = [1usize; D];
        let mut edges = [0.0; D];
        let mut inv_edges = [0.0; D];
        for k in 0..D {
            let l = sim_box.lengths[k];
            let n = ((l / cell_size) * (1.0 + 1e-9)).floor().max(1.0) as usize;
            dims[k] = n;
            edges[k] = l / n as f64;
            inv_edges[k] = n as f64 / l;
        }
        Self {
            dims,
            edges,
            inv_edges,
            volume: edges.iter().product(),
        }
    }

    /// Total number of cells.
    pub fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Whether the grid has no cells (never, kept for clippy).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Linear index of the cell holding `x` (axis 0 fastest); positions on or beyond the
    /// upper face are put in the last cell.
    #[inline(always)]
    pub fn index(&self, x: &[f64; D]) -> u32 {
        let mut idx = 0usize;
        let mut stride = 1usize;
        for ((&xk, &inv), &n) in x.iter().zip(&self.inv_edges).zip(&self.dims) {
            // Signed on purpose: a saturating `f64 as usize` costs more instructions on
            // x86-64 (no unsigned conversion) than `as isize` and the clamp.
            let c = ((xk * inv) as isize).clamp(0, n as isize - 1);
            idx += c as usize * stride;
            stride *= n;
        }
        idx as u32
    }
}

/// [`CellGrid::index`] with the grid's constants held in locals, for the free flight's
/// loop: the same cell for every position (NaN, infinite and out-of-box ones included,
/// unit test), with the clamp done on the `f64` before its conversion to an integer.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellLookup<const D: usize> {
    inv_edges: [f64; D],
    /// `n_k - 1` as `f64` (exact: cell counts are far below `2^53`).
    last: [f64; D],
    strides: [u32; D],
}

impl<const D: usize> CellLookup<D> {
    pub(crate) fn new(grid: &CellGrid<D>) -> Self {
        let mut last = [0.0; D];
        let mut strides = [0u32; D];
        let mut stride = 1usize;
        for k in 0..D {
            last[k] = (grid.dims[k] - 1) as f64;
            strides[k] = stride as u32;
            stride *= grid.dims[k];
        }
        Self {
            inv_edges: grid.inv_edges,
            last,
            strides,
        }
    }

    /// The cell of `x`, equal to [`CellGrid::index`]: `trunc(x_k / h_k)` clamped to
    /// `[0, n_k - 1]`, NaN to 0. Here `f > 0 ? f : 0` (NaN and negatives to 0), then
    /// `f < n_k - 1 ? f : n_k - 1`; the clamped value is an integer or lies in
    /// `[0, n_k - 1)`, so its truncation is the truncation of the original clamped.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // four arrays indexed by the axis, as measured
    pub(crate) fn index(&self, x: &[f64; D]) -> u32 {
        let mut idx = 0u32;
        for k in 0..D {
            let f = x[k] * self.inv_edges[k];
            let f = if f > 0.0 { f } else { 0.0 };
            let f = if f < self.last[k] { f } else { self.last[k] };
            idx += (f as u32) * self.strides[k];
        }
        idx
    }
}

/// Scratch permutation of the counting sort (atomic so that chunks can scatter into it
/// in parallel without `unsafe`); cloning yields an empty buffer.
#[derive(Debug, Default)]
pub struct Permutation(pub Vec<AtomicU32>);

impl Clone for Permutation {
    fn clone(&self) -> Self {
        Self(Vec::new())
    }
}

/// A stable counting sort of particle indices by cell, done in parallel.
///
/// `cell_of` is split into `counts.len()` chunks of `chunk` particles; `counts[j]` holds
/// the per-cell occupation of chunk `j`. Returns `start`, the first sorted slot of each
/// cell (length `cells + 1`), and fills `perm` (reused between steps) with the permutation
/// `perm[k] = old index of the particle that goes to slot k`. The result is the unique stable order, independent of the chunking.
pub fn counting_sort(
    cell_of: &[u32],
    chunk: usize,
    counts: Vec<Vec<u32>>,
    cells: usize,
    perm: &mut Permutation,
) -> Vec<u32> {
    let n = cell_of.len();
    // offsets[j][c]: first slot of chunk j's particles of cell c.
    let mut start = vec![0u32; cells + 1];
    let mut offsets = counts;
    let mut acc = 0u32;
    for c in 0..cells {
        start[c] = acc;
        for o in offsets.iter_mut() {
            let cnt = o[c];
            o[c] = acc;
            acc += cnt;
        }
    }
    start[cells] = acc;
    debug_assert_eq!(acc as usize, n);
    if perm.0.len() != n {
        perm.0 = (0..n).map(|_| AtomicU32::new(0)).collect();
    }
    let perm = &perm.0;
    offsets
        .into_par_iter()
        .zip(cell_of.par_chunks(chunk.max(1)))
        .enumerate()
        .for_each(|(j, (mut off, cells_j))| {
            let base = (j * chunk) as u32;
            for (i, &c) in cells_j.iter().enumerate() {
                let slot = &mut off[c as usize];
                perm[*slot as usize].store(base + i as u32, Ordering::Relaxed);
                *slot += 1;
            }
        });
    start
}

/// The first sorted slot of each cell (length `cells + 1`) from the cells' occupations.
pub fn cell_starts(counts: &[u32]) -> Vec<u32> {
    let mut start = Vec::with_capacity(counts.len() + 1);
    let mut acc = 0u32;
    for &c in counts {
        start.push(acc);
        acc += c;
    }
    start.push(acc);
    start
}

/// The stable counting sort of one chunk done in a single pass, without a permutation:
/// particle `i` (storage order) goes to the next free slot of its cell `cell_of[i]`,
/// `dst[next[cell_of[i]]++] = src[i]`, for the three arrays at once. Gives the same order
/// as [`counting_sort`] followed by [`gather`], reading every array once, sequentially.
pub fn scatter3<A: Copy, B: Copy, C: Copy>(
    cell_of: &[u32],
    start: &[u32],
    src: (&[A], &[B], &[C]),
    dst: (&mut [A], &mut [B], &mut [C]),
) {
    let mut next = start[..start.len() - 1].to_vec();
    let (sa, sb, sc) = src;
    let (da, db, dc) = dst;
    for (i, &c) in cell_of.iter().enumerate() {
        let slot = &mut next[c as usize];
        let k = *slot as usize;
        *slot += 1;
        da[k] = sa[i];
        db[k] = sb[i];
        dc[k] = sc[i];
    }
}

/// [`scatter3`] for one array.
pub fn scatter1<T: Copy>(cell_of: &[u32], start: &[u32], src: &[T], dst: &mut [T]) {
    let mut next = start[..start.len() - 1].to_vec();
    for (&c, &x) in cell_of.iter().zip(src) {
        let slot = &mut next[c as usize];
        dst[*slot as usize] = x;
        *slot += 1;
    }
}

/// `dst[k] = src[perm[k]]` in parallel.
pub fn gather<T: Copy + Send + Sync>(src: &[T], perm: &[AtomicU32], dst: &mut [T]) {
    dst.par_chunks_mut(8192)
        .zip(perm.par_chunks(8192))
        .for_each(|(d, p)| {
            for (x, i) in d.iter_mut().zip(p) {
                *x = src[i.load(Ordering::Relaxed) as usize];
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass scatter gives exactly the permutation of the chunked parallel sort.
    #[test]
    fn scatter_matches_the_chunked_sort() {
        let cells = 37;
        let n = 1000;
        // A fixed pseudo-random cell assignment (a linear congruential sequence).
        let cell_of: Vec<u32> = (0..n as u64)
            .map(|i| ((i.wrapping_mul(6_364_136_223_846_793_005) >> 33) % cells) as u32)
            .collect();
        let ids: Vec<u32> = (0..n as u32).collect();
        let vals: Vec<f64> = ids.iter().map(|&i| i as f64 * 0.5).collect();
        let chunk = 128;
        let counts: Vec<Vec<u32>> = cell_of
            .chunks(chunk)
            .map(|c| {
                let mut k = vec![0u32; cells as usize];
                for &x in c {
                    k[x as usize] += 1;
                }
                k
            })
            .collect();
        let mut total = vec![0u32; cells as usize];
        for k in &counts {
            for (t, x) in total.iter_mut().zip(k) {
                *t += x;
            }
        }
        let mut perm = Permutation::default();
        let start = counting_sort(&cell_of, chunk, counts, cells as usize, &mut perm);
        let mut by_perm = vec![0u32; n];
        gather(&ids, &perm.0, &mut by_perm);
        assert_eq!(cell_starts(&total), start);
        let (mut a, mut b, mut c) = (vec![0u32; n], vec![0.0; n], vec![0u32; n]);
        scatter3(
            &cell_of,
            &start,
            (&ids, &vals, &cell_of),
            (&mut a, &mut b, &mut c),
        );
        assert_eq!(a, by_perm);
        assert!(b.iter().zip(&a).all(|(&v, &i)| v == i as f64 * 0.5));
        assert!(c.windows(2).all(|w| w[0] <= w[1]));
        let mut one = vec![0u32; n];
        scatter1(&cell_of, &start, &ids, &mut one);
        assert_eq!(one, by_perm);
    }

    /// The flight's lookup gives the grid's cell for every position, including the
    /// faces, just inside and outside them, NaN and infinities.
    #[test]
    fn lookup_matches_the_grid_index() {
        use crate::boundary::AxisKind;
        use crate::vector::Vector;
        let bx = SimulationBox::uniform(Vector([10.0, 7.3, 3.1]), AxisKind::Periodic);
        for size in [0.69, 1.0, 0.1, 2.5, 100.0] {
            let grid = CellGrid::<3>::new(&bx, size);
            let lookup = CellLookup::new(&grid);
            let mut values = vec![
                0.0,
                -0.0,
                f64::MIN_POSITIVE,
                -f64::MIN_POSITIVE,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                1e300,
                -1e300,
                f64::MAX,
            ];
            for k in 0..3 {
                let l = bx.lengths[k];
                for j in 0..=grid.dims[k] + 1 {
                    let face = j as f64 * grid.edges[k];
                    let mut y = face;
                    for _ in 0..4 {
                        values.push(y);
                        y = f64::from_bits(y.to_bits().wrapping_sub(1));
                    }
                    let mut y = face;
                    for _ in 0..4 {
                        values.push(y);
                        y = f64::from_bits(y.to_bits() + 1);
                    }
                }
                let mut y = l;
                for _ in 0..8 {
                    values.push(y);
                    y = f64::from_bits(y.to_bits() - 1);
                }
            }
            // A fixed pseudo-random set inside and around the box.
            let mut s = 0x1234_5678_9abc_def0u64;
            for _ in 0..20_000 {
                s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                values.push(((s >> 11) as f64 / (1u64 << 53) as f64) * 14.0 - 2.0);
            }
            for (i, &a) in values.iter().enumerate() {
                let b = values[(i * 7 + 3) % values.len()];
                let c = values[(i * 13 + 5) % values.len()];
                for x in [[a, b, c], [b, c, a], [c, a, b]] {
                    assert_eq!(lookup.index(&x), grid.index(&x), "{x:?}");
                }
            }
        }
    }
}
