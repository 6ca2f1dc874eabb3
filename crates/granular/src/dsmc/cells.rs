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
            let c = ((xk * inv) as isize).clamp(0, n as isize - 1);
            idx += c as usize * stride;
            stride *= n;
        }
        idx as u32
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
