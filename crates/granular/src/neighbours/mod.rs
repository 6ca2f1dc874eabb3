//! The cell grid: the box is cut into cells at least one contact distance wide, so that a
//! grain can only touch grains in its own or a neighbouring cell, or one of a few large
//! grains kept out of the cells ([`large_grain_cut`]). Each cell holds a singly
//! linked list of its grains (4 bytes per grain; cells hold about one grain, so unlinking
//! by walking the list is as fast as a doubly linked list and half the memory).
//!
//! Hand-written: neighbour search is, with the event queue, the core of the event-driven
//! engine's speed. Shared by the engine's predictions and the overlap check of initial
//! states (`setup::check_overlaps`), below both. [`gather`]: the candidates of a
//! prediction.

mod gather;

pub use gather::Candidates;

use crate::boundary::SimulationBox;
use crate::prefetch::prefetch_all;
use serde::{Deserialize, Serialize};

/// Most cells per grain (dilute systems get wider cells). 2 costs up to 8 bytes of cell
/// heads per grain; 1.25 would save 3 but measured 6 % slower at packing fraction 0.2 in
/// 2D (wider cells, more candidates per prediction).
pub const MAX_CELLS_PER_GRAIN: f64 = 2.0;

/// The fewest cells a periodic axis is coarsened to (where it is at least this many
/// contact distances long). With four or more, two grains in neighbouring cells are less
/// than half a box apart along the axis, so their minimum image cannot change while they
/// stay neighbours, and a pair that is not yet neighbours is tested afresh, at its current
/// image, by the cell crossing that makes it one: a contact predicted at one image is never
/// missed at the other. (A periodic axis shorter than four contact distances, a box of a
/// few grains, has one or three cells, and there two grains can meet through the image
/// the last prediction did not look at: a limitation, docs/edmd.md.)
pub const MIN_PERIODIC_CELLS: usize = 4;

/// Sentinel for "no particle".
pub const NONE: u32 = u32::MAX;

/// The list link of a large grain, which is in no cell list ([`CellGrid::insert_large`]).
const LARGE: u32 = u32::MAX - 1;

/// Most grains kept out of the cell lists as large grains ([`large_grain_cut`]): every
/// prediction of the other grains tests all of them.
pub const MAX_LARGE_GRAINS: usize = 16;

/// The radius above which grains are *large*, or `None` when no such split pays: a few
/// grains much larger than the rest (a projectile in a bed, an intruder in a bath) would
/// otherwise set the cell width, the largest contact distance, so that every prediction
/// of the small grains would test hundreds of them (a crater run with 10^5 bed grains
/// under a 22 times larger projectile: about 3 s in the engine for 10^5 collisions, 0.1 s
/// with the split).
///
/// With a cut at `r_c`, the cells are `2 r_c` wide, the grains above `r_c` (at most
/// `MAX_LARGE_GRAINS`) stay out of the cell lists, every other prediction tests them
/// all, and each of them searches the cells within its own reach. The cut minimises the
/// estimated candidates per prediction of a small grain, `n (3 w)^D + K` (`n` grains per
/// volume, `w` the cell width, never below the width of `MAX_CELLS_PER_GRAIN` cells
/// per grain, `K` large grains), and is taken only when it at least halves them.
pub fn large_grain_cut<const D: usize>(radii: &[f64], volume: f64) -> Option<f64> {
    let n = radii.len();
    if n == 0 {
        return None;
    }
    let density = n as f64 / volume;
    let floor_width = (volume / (MAX_CELLS_PER_GRAIN * n as f64)).powf(1.0 / D as f64);
    let cost = |cut: f64, large: usize| {
        density * (3.0 * (2.0 * cut).max(floor_width)).powi(D as i32) + large as f64
    };
    let mut sorted = radii.to_vec();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let no_split = cost(sorted[0], 0);
    let mut best: Option<(f64, f64)> = None;
    // The cut just below each of the largest grains: the `k` largest are large.
    for k in 1..=MAX_LARGE_GRAINS.min(n - 1) {
        let cut = sorted[k];
        if cut == sorted[k - 1] {
            continue;
        }
        let c = cost(cut, k);
        if best.is_none_or(|(b, _)| c < b) {
            best = Some((c, cut));
        }
    }
    best.filter(|&(c, _)| c <= 0.5 * no_split)
        .map(|(_, cut)| cut)
}

/// A regular grid of cells over the box.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CellGrid<const D: usize> {
    /// Cells per axis.
    pub counts: CellCounts<D>,
    /// Cell width per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub widths: [f64; D],
    /// Whether each axis wraps around.
    #[serde(with = "crate::vector::serde_array")]
    periodic: [bool; D],
    /// First grain of each cell (flat index, axis 0 fastest).
    head: Vec<u32>,
    /// Next grain in the same cell.
    next: Vec<u32>,
    /// Flat cell index of each grain.
    cell: Vec<u32>,
    /// The large grains ([`large_grain_cut`]): in no cell list; every other prediction
    /// tests all of them, and each searches the cells within its reach.
    #[serde(default)]
    large: Vec<u32>,
    /// Reach of each large grain in cells along each axis (`D` per grain, in the order
    /// of `large`): its own cell and `reach` cells on either side hold every grain it can
    /// touch while it stays in its cell.
    #[serde(default)]
    reach: Vec<u32>,
}

/// Cells per axis (`counts[k]`), each also ready to divide flat cell indices by
/// (`CountDivisor`). Stored, and checkpointed, as the counts alone.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<usize>", into = "Vec<usize>")]
pub struct CellCounts<const D: usize> {
    counts: [usize; D],
    divisors: [CountDivisor; D],
}

impl<const D: usize> From<[usize; D]> for CellCounts<D> {
    fn from(counts: [usize; D]) -> Self {
        let divisors = counts.map(|c| CountDivisor::from(c as u32));
        Self { counts, divisors }
    }
}

impl<const D: usize> TryFrom<Vec<usize>> for CellCounts<D> {
    type Error = String;
    fn try_from(v: Vec<usize>) -> Result<Self, String> {
        let n = v.len();
        let counts: [usize; D] = v
            .try_into()
            .map_err(|_| format!("expected {D} cell counts, found {n}"))?;
        Ok(counts.into())
    }
}

impl<const D: usize> From<CellCounts<D>> for Vec<usize> {
    fn from(c: CellCounts<D>) -> Vec<usize> {
        c.counts.to_vec()
    }
}

impl<const D: usize> std::ops::Index<usize> for CellCounts<D> {
    type Output = usize;
    #[inline(always)]
    fn index(&self, k: usize) -> &usize {
        &self.counts[k]
    }
}

impl<const D: usize> PartialEq<[usize; D]> for CellCounts<D> {
    fn eq(&self, other: &[usize; D]) -> bool {
        self.counts == *other
    }
}

/// Division of a flat cell index by a cell count without a division instruction: the
/// quotient is the high half of the index times `ceil(2^64 / n)`, exact for every 32-bit
/// index and count (Lemire, Kaser and Kurz, "Faster remainder by direct computation",
/// Softw. Pract. Exper. 49, 953 (2019), Theorem 1 with N = 32, F = 64). A grain's cell
/// coordinates come from its flat index at every prediction, where a 32-bit division sat
/// on the way from one event to the next: +1.5 % at 2D N = 10^4, φ = 0.7 (32 pairs of
/// alternating runs), none measurable at 3D N = 10^5 or 2D φ = 0.2.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CountDivisor {
    n: u32,
    /// `ceil(2^64 / n)`, or 0 for `n = 1` (whose quotient is the index itself).
    magic: u64,
}

impl From<u32> for CountDivisor {
    fn from(n: u32) -> Self {
        let n = n.max(1);
        let magic = if n > 1 { u64::MAX / n as u64 + 1 } else { 0 };
        Self { n, magic }
    }
}

impl CountDivisor {
    /// `(f / n, f % n)`.
    #[inline(always)]
    fn div_rem(self, f: u32) -> (u32, u32) {
        let q = if self.magic == 0 {
            f
        } else {
            ((self.magic as u128 * f as u128) >> 64) as u32
        };
        (q, f - q * self.n)
    }
}

impl<const D: usize> CellGrid<D> {
    /// A grid over `bx` with cells at least `min_width` wide (the largest contact
    /// distance), for `n` particles. Periodic axes with fewer than three cells collapse to
    /// one cell, so that a neighbour is never visited twice. The cap of
    /// [`MAX_CELLS_PER_GRAIN`] never coarsens a periodic axis below
    /// [`MIN_PERIODIC_CELLS`] cells.
    pub fn new(bx: &SimulationBox<D>, min_width: f64, n: usize) -> Self {
        let mut counts = [1usize; D];
        let mut widths = [0.0; D];
        let mut periodic = [false; D];
        // At most MAX_CELLS_PER_GRAIN cells per particle, so that memory stays O(N) in
        // sparse boxes.
        let max_cells = ((MAX_CELLS_PER_GRAIN * n as f64) as usize).clamp(1, u32::MAX as usize - 1);
        let max_cells = max_cells as f64;
        let mut total = 1.0;
        for k in 0..D {
            let l = bx.lengths[k];
            let mut c = ((l / min_width).floor() as usize).max(1);
            periodic[k] = bx.is_periodic(k);
            if periodic[k] && c < 3 {
                c = 1;
            }
            counts[k] = c;
            total *= c as f64;
        }
        while total > max_cells {
            // Coarsen the axis with the narrowest cells by about 10 %, so that cells stay
            // close to square.
            let coarsens = |k: usize| {
                if periodic[k] {
                    counts[k] > MIN_PERIODIC_CELLS
                } else {
                    counts[k] > 1
                }
            };
            let Some(k) = (0..D).filter(|&k| coarsens(k)).min_by(|&a, &b| {
                let wa = bx.lengths[a] / counts[a] as f64;
                let wb = bx.lengths[b] / counts[b] as f64;
                wa.total_cmp(&wb)
            }) else {
                break;
            };
            let c = counts[k];
            let new = ((c as f64 / 1.1) as usize).clamp(1, c - 1);
            let new = if periodic[k] {
                new.max(MIN_PERIODIC_CELLS)
            } else {
                new
            };
            total = total / c as f64 * new as f64;
            counts[k] = new;
        }
        for k in 0..D {
            widths[k] = bx.lengths[k] / counts[k] as f64;
        }
        let ncells = counts.iter().product();
        Self {
            counts: counts.into(),
            widths,
            periodic,
            head: vec![NONE; ncells],
            next: vec![NONE; n],
            cell: vec![0; n],
            large: Vec::new(),
            reach: Vec::new(),
        }
    }

    /// An empty grid for grains of `radii` (times `scale`, for growing radii), with cells
    /// one largest contact distance wide, and a margin of 1e-9 for round-off; with `split`,
    /// the cells fit all but the large grains of [`large_grain_cut`], whose cut it returns
    /// (grains go in with [`CellGrid::insert_grain`]).
    pub fn for_radii(
        bx: &SimulationBox<D>,
        radii: &[f64],
        scale: f64,
        split: bool,
    ) -> (Self, Option<f64>) {
        let cut = if split {
            large_grain_cut::<D>(radii, bx.volume())
        } else {
            None
        };
        let r_max = radii.iter().cloned().fold(0.0, f64::max);
        let width = 2.0 * cut.unwrap_or(r_max) * scale * (1.0 + 1e-9);
        (Self::new(bx, width, radii.len()), cut)
    }

    /// Puts grain `i`, of radius `radius`, into cell `c`: into the cell's list, or, above
    /// the grid's large-grain cut `cut` (from [`CellGrid::for_radii`]), as a large grain.
    pub fn insert_grain(&mut self, i: usize, c: [u32; D], radius: f64, cut: Option<f64>) {
        match cut {
            Some(cut) if radius > cut => self.insert_large(i, c, (radius + cut) * (1.0 + 1e-9)),
            _ => self.insert(i, c),
        }
    }

    /// Heap memory in bytes (cell heads, lists and cell indices).
    pub fn memory_bytes(&self) -> usize {
        (self.head.capacity()
            + self.next.capacity()
            + self.cell.capacity()
            + self.large.capacity()
            + self.reach.capacity())
            * 4
    }

    /// The large grains (kept out of the cell lists; empty in most systems).
    #[inline(always)]
    pub fn large(&self) -> &[u32] {
        &self.large
    }

    /// Whether grain `i` is a large grain.
    #[inline(always)]
    pub fn is_large(&self, i: usize) -> bool {
        !self.large.is_empty() && self.next[i] == LARGE
    }

    /// Puts large grain `i` in cell `c` without entering it in the cell's list: it can
    /// touch grains up to `contact` away (its radius plus the largest of the others).
    pub fn insert_large(&mut self, i: usize, c: [u32; D], contact: f64) {
        self.cell[i] = self.flat(&c) as u32;
        self.next[i] = LARGE;
        self.large.push(i as u32);
        for k in 0..D {
            // A grain `d` cells away along `k` is more than `(d - 1) w` away.
            let reach = (contact / self.widths[k]).ceil().max(1.0) as usize;
            self.reach.push(reach.min(self.counts[k]) as u32);
        }
    }

    /// The cell coordinates containing `x` (clamped into the grid).
    pub fn coords_of(&self, x: &[f64; D]) -> [u32; D] {
        let mut c = [0u32; D];
        for k in 0..D {
            let v = (x[k] / self.widths[k]).floor();
            c[k] = (v.max(0.0) as usize).min(self.counts[k] - 1) as u32;
        }
        c
    }

    /// Flat index of cell coordinates `c` (axis 0 fastest).
    #[inline(always)]
    pub fn flat(&self, c: &[u32; D]) -> usize {
        let mut idx = 0usize;
        for k in (0..D).rev() {
            idx = idx * self.counts[k] + c[k] as usize;
        }
        idx
    }

    /// Cell coordinates of grain `i`.
    #[inline(always)]
    pub fn coords(&self, i: usize) -> [u32; D] {
        let mut f = self.cell[i];
        let mut c = [0u32; D];
        for (k, ck) in c.iter_mut().enumerate() {
            if k + 1 == D {
                *ck = f;
            } else {
                (f, *ck) = self.counts.divisors[k].div_rem(f);
            }
        }
        c
    }

    /// Whether the grains of the cells around all of `cells` (each cell and its
    /// neighbours) are nearer to each other directly than through any periodic face: on
    /// every periodic axis those cells lie inside the grid without wrapping around, and
    /// span less than half the box. Then the minimum image of two such grains is their
    /// plain difference, and a search among them may skip it.
    #[inline(always)]
    pub fn without_wrap(&self, cells: &[[u32; D]]) -> bool {
        (0..D).all(|k| {
            if !self.periodic[k] {
                return true;
            }
            let lo = cells.iter().map(|c| c[k]).min().unwrap_or(0) as usize;
            let hi = cells.iter().map(|c| c[k]).max().unwrap_or(0) as usize;
            let n = self.counts[k];
            // `hi - lo + 3` cells, each `L / n` wide, against `L / 2`.
            lo >= 1 && hi + 2 <= n && 2 * (hi - lo + 3) < n
        })
    }

    /// Starts loading the cell index of particle `i` (a hint).
    #[inline(always)]
    pub fn prefetch_cell_index(&self, i: usize) {
        prefetch_all(&self.cell, &[i as u32]);
    }

    /// Starts loading the cell heads around particle `i` (a hint; its cell index should
    /// be in cache).
    #[inline(always)]
    pub fn prefetch_heads(&self, i: usize) {
        let c = self.coords(i);
        self.for_each_neighbour_run(&c, |first, len| {
            prefetch_all(&self.head, &[first as u32, (first + len - 1) as u32]);
        });
    }

    /// Starts loading the first grain's record and list link of every cell around
    /// particle `i` (a hint; the heads should already be in cache).
    #[inline(always)]
    pub fn prefetch_first_grains<T>(&self, i: usize, records: &[T]) {
        let c = self.coords(i);
        self.for_each_neighbour_run(&c, |first, len| {
            for &h in &self.head[first..first + len] {
                if h != NONE {
                    prefetch_all(records, &[h]);
                    prefetch_all(&self.next, &[h]);
                }
            }
        });
    }

    /// Puts particle `i` into cell `c`.
    pub fn insert(&mut self, i: usize, c: [u32; D]) {
        let f = self.flat(&c);
        self.next[i] = self.head[f];
        self.head[f] = i as u32;
        self.cell[i] = f as u32;
    }

    /// Takes particle `i` out of its cell.
    pub fn remove(&mut self, i: usize) {
        let f = self.cell[i] as usize;
        let mut p = self.head[f];
        if p == i as u32 {
            self.head[f] = self.next[i];
            return;
        }
        while p != NONE {
            let n = self.next[p as usize];
            if n == i as u32 {
                self.next[p as usize] = self.next[i];
                return;
            }
            p = n;
        }
        debug_assert!(false, "grain {i} not found in its cell");
    }

    /// Moves particle `i` one cell along `axis` in direction `step` (+1 or -1), wrapping on
    /// periodic axes. Returns whether the particle wrapped around the box.
    pub fn shift(&mut self, i: usize, axis: usize, step: i32) -> bool {
        let mut c = self.coords(i);
        let large = self.is_large(i);
        if !large {
            self.remove(i);
        }
        let n = self.counts[axis] as i64;
        let mut v = c[axis] as i64 + step as i64;
        let mut wrapped = false;
        if v < 0 {
            v += n;
            wrapped = true;
        } else if v >= n {
            v -= n;
            wrapped = true;
        }
        c[axis] = v as u32;
        if large {
            self.cell[i] = self.flat(&c) as u32;
        } else {
            self.insert(i, c);
        }
        wrapped
    }

    /// The grains in cell order (cell by cell, axis 0 fastest): the order in which the
    /// engine stores them after a spatial reordering.
    pub fn cell_order(&self) -> Vec<u32> {
        let mut order = Vec::with_capacity(self.next.len());
        for &h in &self.head {
            let mut j = h;
            while j != NONE {
                order.push(j);
                j = self.next[j as usize];
            }
        }
        order.extend_from_slice(&self.large);
        order
    }

    /// Relabels the grains: grain `i` becomes `new_of_old[i]`. Each cell's list is rebuilt
    /// in increasing new label.
    pub fn relabel(&mut self, new_of_old: &[u32]) {
        let n = self.cell.len();
        let mut cell = vec![0u32; n];
        for (i, &new) in new_of_old.iter().enumerate() {
            cell[new as usize] = self.cell[i];
        }
        for l in &mut self.large {
            *l = new_of_old[*l as usize];
        }
        self.head.fill(NONE);
        self.next.fill(NONE);
        for &l in &self.large {
            self.next[l as usize] = LARGE;
        }
        for i in (0..n).rev() {
            if self.next[i] == LARGE {
                continue;
            }
            let f = cell[i] as usize;
            self.next[i] = self.head[f];
            self.head[f] = i as u32;
        }
        self.cell = cell;
    }
}

#[cfg(test)]
mod tests;
