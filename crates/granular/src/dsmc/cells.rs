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

use super::lattice::{Lattice, axis_cell};
use crate::boundary::SimulationBox;
use std::ops::Range;

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

/// Cells along an axis of length `length` for the requested edge `cell_size`: as many as
/// fit (at least one; a length within 1e-9 of a multiple of the edge counts as that
/// multiple), so that the cells' edge `length / n` is at least `cell_size`.
pub(crate) fn cells_along(length: f64, cell_size: f64) -> usize {
    ((length / cell_size) * (1.0 + 1e-9)).floor().max(1.0) as usize
}

impl<const D: usize> CellGrid<D> {
    /// Cells of requested edge `cell_size`: `n_k = max(1, floor(L_k / cell_size))` (with a
    /// relative tolerance of 1e-9 so that exact multiples are not rounded down).
    pub(crate) fn new(sim_box: &SimulationBox<D>, cell_size: f64) -> Self {
        let mut dims = [1usize; D];
        let mut edges = [0.0; D];
        let mut inv_edges = [0.0; D];
        for k in 0..D {
            let l = sim_box.lengths[k];
            let n = cells_along(l, cell_size);
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
    #[cfg(test)]
    pub(crate) fn index(&self, x: &[f64; D]) -> u32 {
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

/// The cell of a grain from its lattice words ([`Lattice`]): exact integer arithmetic,
/// the same for every rank and thread, so that every cell index of the engine comes from
/// here.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellIndex<const D: usize> {
    /// The position bits of a word.
    mask: u64,
    /// Per axis: `n_k` (periodic) or `2 n_k` (walled), see [`Lattice::cell_multipliers`].
    mult: [u64; D],
    /// Per axis: `n_k - 1`.
    last: [u64; D],
    /// Per axis: the stride of the linear index (axis 0 fastest).
    strides: [u64; D],
}

impl<const D: usize> CellIndex<D> {
    pub(crate) fn new(grid: &CellGrid<D>, lattice: &Lattice<D>) -> Self {
        let mut last = [0u64; D];
        let mut strides = [0u64; D];
        let mut stride = 1u64;
        for k in 0..D {
            last[k] = grid.dims[k] as u64 - 1;
            strides[k] = stride;
            stride *= grid.dims[k] as u64;
        }
        Self {
            mask: lattice.position_mask(),
            mult: lattice.cell_multipliers(&grid.dims),
            last,
            strides,
        }
    }

    /// The per-axis multipliers, last cells and strides.
    pub(crate) fn axes(&self) -> ([u64; D], [u64; D], [u64; D]) {
        (self.mult, self.last, self.strides)
    }

    /// The cell of word `w` along axis `k`.
    #[inline(always)]
    pub(crate) fn axis(&self, k: usize, w: u64) -> u64 {
        axis_cell(w & self.mask, self.mult[k], self.last[k])
    }

    /// The linear cell index of a grain with lattice words `w`.
    #[inline(always)]
    pub(crate) fn of(&self, w: &[u64; D]) -> u32 {
        let mut c = 0u64;
        for (k, &wk) in w.iter().enumerate() {
            c += self.axis(k, wk) * self.strides[k];
        }
        c as u32
    }
}

/// The slots of one step's sort by cell (stable: the grains of each cell keep the order
/// of their storage, arrivals from lower ranks first and from higher ranks last, which is
/// the order of the whole system's storage, whatever the ranks and threads).
///
/// `dest[i]` is the new cell of grain `i` (any cell index), `arrivals[..before]` the cells
/// of the grains arriving from lower ranks and `arrivals[before..]` from higher ranks, all
/// in their storage order; `cells` the cells this sort owns. Replaces each cell by the
/// grain's slot (grains whose cell is not owned get the slot one past the last, see
/// [`super::grains::Grains::reorder`]), sets `start` to the first slot of each owned cell
/// (relative to `cells.start`) followed by the number of grains, and returns that number.
pub(crate) fn assign_slots(
    dest: &mut [u32],
    arrivals: &mut [u32],
    before: usize,
    cells: Range<usize>,
    start: &mut Vec<u32>,
) -> usize {
    let (c0, m) = (cells.start as u32, cells.len());
    start.clear();
    start.resize(m + 1, 0);
    let counts = &mut start[..m];
    for &c in arrivals.iter() {
        if let Some(k) = counts.get_mut(c.wrapping_sub(c0) as usize) {
            *k += 1;
        }
    }
    for &c in dest.iter() {
        if let Some(k) = counts.get_mut(c.wrapping_sub(c0) as usize) {
            *k += 1;
        }
    }
    let mut acc = 0u32;
    for s in start.iter_mut() {
        let n = *s;
        *s = acc;
        acc += n;
    }
    let n = acc;
    // `start` counts up as slots are handed out (each cell's entry ends at the next
    // cell's first slot) and is shifted back afterwards.
    let next = &mut start[..m];
    let mut hand_out = |cs: &mut [u32]| {
        for c in cs.iter_mut() {
            *c = match next.get_mut(c.wrapping_sub(c0) as usize) {
                Some(s) => {
                    let slot = *s;
                    *s += 1;
                    slot
                }
                None => n,
            };
        }
    };
    let (lower, higher) = arrivals.split_at_mut(before);
    hand_out(lower);
    hand_out(dest);
    hand_out(higher);
    start.copy_within(0..m, 1);
    start[0] = 0;
    start[m] = n;
    n as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::AxisKind;
    use crate::vector::Vector;

    /// The slots are the stable counting sort: cells in order, each cell's grains in the
    /// order lower arrivals, own grains, higher arrivals; foreign cells leave.
    #[test]
    fn slots_are_the_stable_sort_by_cell() {
        let n = 1000usize;
        let cells = 10..47usize;
        // A fixed pseudo-random cell assignment (a linear congruential sequence), some of
        // it outside the owned cells.
        let lcg = |i: u64| ((i.wrapping_mul(6_364_136_223_846_793_005) >> 33) % 60) as u32;
        let mut dest: Vec<u32> = (0..n as u64).map(lcg).collect();
        let mut arrivals: Vec<u32> = (0..30u64).map(|i| 10 + lcg(i + 7) % 37).collect();
        let all: Vec<u32> = arrivals[..12]
            .iter()
            .chain(&dest)
            .chain(&arrivals[12..])
            .copied()
            .collect();
        let mut start = Vec::new();
        let before = dest.clone();
        let total = assign_slots(&mut dest, &mut arrivals, 12, cells.clone(), &mut start);
        let slots: Vec<u32> = arrivals[..12]
            .iter()
            .chain(&dest)
            .chain(&arrivals[12..])
            .copied()
            .collect();
        // The reference: a stable sort of the owned entries by cell.
        let mut order: Vec<usize> = (0..all.len())
            .filter(|&k| cells.contains(&(all[k] as usize)))
            .collect();
        order.sort_by_key(|&k| all[k]);
        assert_eq!(total, order.len());
        for (slot, &k) in order.iter().enumerate() {
            assert_eq!(slots[k] as usize, slot);
        }
        for (k, &c) in before.iter().enumerate() {
            if !cells.contains(&(c as usize)) {
                assert_eq!(dest[k] as usize, total);
            }
        }
        for (j, c) in cells.clone().enumerate() {
            let first = order
                .iter()
                .position(|&k| all[k] as usize >= c)
                .unwrap_or(total);
            assert_eq!(start[j] as usize, first);
        }
        assert_eq!(start[cells.len()] as usize, total);
    }

    /// The lattice cell is the grid's cell of the lattice point away from the faces, and
    /// the far wall is in the last cell.
    #[test]
    fn lattice_cells_match_the_grid() {
        for axes in [[AxisKind::Periodic; 3], [AxisKind::Wall; 3]] {
            let bx = SimulationBox {
                lengths: Vector([10.0, 7.3, 3.1]),
                axes,
            };
            let lattice = Lattice::new(&bx, 5000);
            for size in [0.69, 1.0, 0.1, 2.5, 100.0] {
                let grid = CellGrid::<3>::new(&bx, size);
                let index = CellIndex::new(&grid, &lattice);
                let mut s = 0x1234_5678_9abc_def0u64;
                for id in 0..5000u32 {
                    let mut x = Vector::<3>::zero();
                    for k in 0..3 {
                        s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                        x[k] = (s >> 11) as f64 / (1u64 << 53) as f64 * bx.lengths[k];
                    }
                    let w = lattice.words(&x, id);
                    let p = lattice.position(&w);
                    let near_face = (0..3).any(|k| {
                        let f = p[k] / grid.edges[k];
                        (f - f.round()).abs() < 1e-9
                    });
                    if !near_face {
                        assert_eq!(index.of(&w), grid.index(&p.0), "{x:?}");
                    }
                }
                if axes[0] == AxisKind::Wall {
                    let w = lattice.words(&bx.lengths, 0);
                    assert_eq!(index.of(&w) as usize, grid.len() - 1);
                }
            }
        }
    }
}
