//! The cell grid: the box is cut into cells at least one contact distance wide, so that a
//! grain can only touch grains in its own or a neighbouring cell, or one of a few large
//! grains kept out of the cells ([`large_grain_cut`]). Each cell holds a singly
//! linked list of its grains (4 bytes per grain; cells hold about one grain, so unlinking
//! by walking the list is as fast as a doubly linked list and half the memory).
//!
//! Hand-written: neighbour search is, with the event queue, the core of the engine's speed.

use super::prefetch::prefetch_all;
use crate::boundary::SimulationBox;
use serde::{Deserialize, Serialize};

/// Most cells per grain (dilute systems get wider cells). 2 costs up to 8 bytes of cell
/// heads per grain; 1.25 would save 3 but measured 6 % slower at packing fraction 0.2 in
/// 2D (wider cells, more candidates per prediction).
pub const MAX_CELLS_PER_GRAIN: f64 = 2.0;

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
    /// one cell, so that a neighbour is never visited twice.
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
            let Some(k) = (0..D).filter(|&k| counts[k] > 1).min_by(|&a, &b| {
                let wa = bx.lengths[a] / counts[a] as f64;
                let wb = bx.lengths[b] / counts[b] as f64;
                wa.total_cmp(&wb)
            }) else {
                break;
            };
            let c = counts[k];
            let new = ((c as f64 / 1.1) as usize).clamp(1, c - 1);
            let new = if periodic[k] && new < 3 { 1 } else { new };
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

    /// Calls `f(j)` for every grain that grain `i` may touch (and possibly `i` itself):
    /// the grains of the cells around it and the large grains, or, for a large grain, the
    /// grains within its reach and the other large grains.
    pub fn for_each_candidate(&self, i: usize, mut f: impl FnMut(usize)) {
        let c = self.coords(i);
        if self.is_large(i) {
            let mut out = Candidates::default();
            self.gather_reach(i, &c, &mut out);
            out.as_slice().iter().for_each(|&j| f(j as usize));
        } else {
            self.for_each_neighbour(&c, &mut f);
            self.large.iter().for_each(|&j| f(j as usize));
        }
    }

    /// Appends to `out` every small grain large grain `i` (in cell `c`) can reach, and
    /// every other large grain: the cells up to its reach on either side of `c`, each
    /// once, wrapping on periodic axes and clipped at walls.
    pub fn gather_reach(&self, i: usize, c: &[u32; D], out: &mut Candidates) {
        let Some(q) = self.large.iter().position(|&l| l as usize == i) else {
            return;
        };
        let mut axes: [Vec<usize>; D] = std::array::from_fn(|_| Vec::new());
        for k in 0..D {
            let n = self.counts[k] as i64;
            let reach = self.reach[q * D + k] as i64;
            let ck = c[k] as i64;
            if self.periodic[k] && 2 * reach + 1 >= n {
                axes[k] = (0..n as usize).collect();
                continue;
            }
            for v in ck - reach..=ck + reach {
                if self.periodic[k] {
                    axes[k].push(v.rem_euclid(n) as usize);
                } else if (0..n).contains(&v) {
                    axes[k].push(v as usize);
                }
            }
        }
        let lens: [usize; D] = std::array::from_fn(|k| axes[k].len());
        if lens.contains(&0) {
            return;
        }
        out.append(|buf| {
            let mut idx = [0usize; D];
            let mut m = 0;
            loop {
                let mut flat = 0usize;
                for k in (0..D).rev() {
                    flat = flat * self.counts[k] + axes[k][idx[k]];
                }
                m = self.write_list(self.head[flat], buf, m)?;
                if !odometer_step(&mut idx, &lens) {
                    break;
                }
            }
            Some(m)
        });
        out.extend_from(&self.large);
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

    /// Appends to `out` every particle in the cells neighbouring (and including) cell
    /// `c`. Gathering the candidates first, then testing them, lets the processor fetch
    /// their records in parallel instead of one list link at a time.
    #[inline(always)]
    pub fn gather_neighbours(&self, c: &[u32; D], out: &mut Candidates) {
        // Two passes: first the heads of all the cells (independent loads, which the
        // processor overlaps), then the lists. Walking cell by cell waits for each head,
        // then for each link, behind a loop exit the branch predictor cannot guess (+6 %
        // at 10^5 spheres; within noise in 2D).
        let mut heads = [NONE; 27];
        let mut m = 0;
        self.for_each_neighbour_run(c, |first, len| {
            heads[m..m + len].copy_from_slice(&self.head[first..first + len]);
            m += len;
        });
        self.append_lists(&heads[..m], out);
    }

    /// Whether cell `c` is away from the grid's faces: its neighbours are at fixed flat
    /// offsets, without wrapping or clipping.
    #[inline(always)]
    fn interior(&self, c: &[u32; D]) -> bool {
        (0..D).all(|k| c[k] >= 1 && (c[k] as usize) + 2 <= self.counts[k])
    }

    /// Appends to `out` the particles of the cell lists starting at `heads`, in order.
    #[inline(always)]
    fn append_lists(&self, heads: &[u32], out: &mut Candidates) {
        out.append(|buf| {
            let mut k = 0;
            for &h in heads {
                k = self.write_list(h, buf, k)?;
            }
            Some(k)
        });
    }

    /// Appends to `out` every particle in the cells neighbouring (and including) cell
    /// `a` or cell `b`, each once: the candidates of both grains of a pair collision in
    /// one gather (in dense 2D about 11 grains instead of twice 8).
    #[inline(always)]
    pub fn gather_pair(&self, a: &[u32; D], b: &[u32; D], out: &mut Candidates) {
        if D == 2
            && self.interior(a)
            && self.interior(b)
            && (0..D).all(|k| a[k].abs_diff(b[k]) <= 1)
        {
            // Fast path (two grains in contact away from the grid's faces): rows of three
            // or four consecutive cells at fixed flat offsets, heads first (as in
            // `gather_neighbours`). At most 4 rows of 4 cells in 2D.
            let (x0, x1) = (a[0].min(b[0]) as usize, a[0].max(b[0]) as usize);
            let (y0, y1) = (a[1].min(b[1]) as usize, a[1].max(b[1]) as usize);
            let stride = self.counts[0];
            let mut heads = [NONE; 16];
            let mut m = 0;
            for y in y0 - 1..=y1 + 1 {
                // The columns of whichever grains have this row in their neighbourhood
                // (both on the rows between them).
                let near_a = y.abs_diff(a[1] as usize) <= 1;
                let near_b = y.abs_diff(b[1] as usize) <= 1;
                let (lo, hi) = match (near_a, near_b) {
                    (true, true) => (x0, x1),
                    (true, false) => (a[0] as usize, a[0] as usize),
                    _ => (b[0] as usize, b[0] as usize),
                };
                let first = y * stride + lo - 1;
                heads[m..m + 3].copy_from_slice(&self.head[first..first + 3]);
                m += 3;
                if hi > lo {
                    heads[m] = self.head[first + 3];
                    m += 1;
                }
            }
            self.append_lists(&heads[..m], out);
            return;
        }
        // Any other case: the cells of `a`'s neighbourhood, then those of `b`'s that are
        // not among them.
        let mut ranges_a = [[0usize; 3]; D];
        let mut lens_a = [0usize; D];
        let mut ranges_b = [[0usize; 3]; D];
        let mut lens_b = [0usize; D];
        for k in 0..D {
            lens_a[k] = self.adjacent(k, a[k] as usize, &mut ranges_a[k]);
            lens_b[k] = self.adjacent(k, b[k] as usize, &mut ranges_b[k]);
        }
        out.append(|buf| {
            let mut k = Some(0);
            self.for_each_cell_of(&ranges_a, &lens_a, |flat, _| {
                k = k.and_then(|k| self.write_list(self.head[flat], buf, k));
            });
            self.for_each_cell_of(&ranges_b, &lens_b, |flat, c| {
                let in_a = (0..D).all(|q| ranges_a[q][..lens_a[q]].contains(&c[q]));
                if !in_a {
                    k = k.and_then(|k| self.write_list(self.head[flat], buf, k));
                }
            });
            k
        });
    }

    /// Writes the particles of the cell list starting at `first` to `out[k..]`; returns
    /// the new end, or `None` when `out` is too short.
    #[inline(always)]
    fn write_list(&self, first: u32, out: &mut [u32], mut k: usize) -> Option<usize> {
        self.try_for_each_in_list(first, |j| {
            *out.get_mut(k)? = j as u32;
            k += 1;
            Some(())
        })?;
        Some(k)
    }

    /// Calls `f(j)` for every particle in the cells neighbouring (and including) cell `c`.
    #[inline(always)]
    pub fn for_each_neighbour(&self, c: &[u32; D], mut f: impl FnMut(usize)) {
        self.for_each_neighbour_run(c, |first, len| {
            for flat in first..first + len {
                self.for_each_in_cell(flat, &mut f);
            }
        });
    }

    /// Calls `f(first, len)` for runs of consecutive flat cell indices `first..first + len`
    /// that together cover every cell neighbouring (and including) cell `c`, each once:
    /// rows of three cells away from the grid's faces, single cells near them.
    #[inline(always)]
    fn for_each_neighbour_run(&self, c: &[u32; D], mut f: impl FnMut(usize, usize)) {
        // Fast path: a cell away from the grid's faces has its neighbours at fixed flat
        // offsets (no wrapping, no clipping): 3^(D-1) rows of three consecutive cells.
        if self.interior(c) {
            let mut stride = [1usize; D];
            for k in 1..D {
                stride[k] = stride[k - 1] * self.counts[k - 1];
            }
            let centre = self.flat(c);
            // Rows are numbered by the offsets along axes 1..D (axis 0 has one "offset").
            let mut rows = [3usize; D];
            rows[0] = 1;
            let mut idx = [0usize; D];
            loop {
                let mut row = centre - 1;
                for k in 1..D {
                    row = row + idx[k] * stride[k] - stride[k];
                }
                f(row, 3);
                if !odometer_step(&mut idx, &rows) {
                    return;
                }
            }
        }
        let mut ranges = [[0usize; 3]; D];
        let mut lens = [0usize; D];
        for k in 0..D {
            lens[k] = self.adjacent(k, c[k] as usize, &mut ranges[k]);
        }
        self.for_each_cell_of(&ranges, &lens, |flat, _| f(flat, 1));
    }

    /// Appends to `out` every particle in the cells that became neighbours of cell `c`
    /// when a grain entered it by a step `step` (+1 or -1) along `axis`: the layer of
    /// cells one further along `axis`, next to (and including) `c`'s position on the other
    /// axes. None past a wall.
    pub fn gather_layer(&self, c: &[u32; D], axis: usize, step: i32, out: &mut Candidates) {
        let mut ranges = [[0usize; 3]; D];
        let mut lens = [0usize; D];
        for k in 0..D {
            if k != axis {
                lens[k] = self.adjacent(k, c[k] as usize, &mut ranges[k]);
                continue;
            }
            let n = self.counts[k] as i64;
            let mut v = c[k] as i64 + step as i64;
            if self.periodic[k] {
                v = v.rem_euclid(n);
            } else if v < 0 || v >= n {
                return;
            }
            ranges[k][0] = v as usize;
            lens[k] = 1;
        }
        out.append(|buf| {
            let mut k = Some(0);
            self.for_each_cell_of(&ranges, &lens, |flat, _| {
                k = k.and_then(|k| self.write_list(self.head[flat], buf, k));
            });
            k
        });
    }

    /// The cells next to (and including) coordinate `ck` along axis `k`: -1, 0, +1,
    /// clipped at walls, wrapped on periodic axes; a single-cell axis has only 0. Writes
    /// them to `out` and returns how many.
    #[inline(always)]
    fn adjacent(&self, k: usize, ck: usize, out: &mut [usize; 3]) -> usize {
        let n = self.counts[k];
        if n == 1 {
            out[0] = 0;
            return 1;
        }
        let mut m = 0;
        if ck > 0 {
            out[m] = ck - 1;
            m += 1;
        } else if self.periodic[k] {
            out[m] = n - 1;
            m += 1;
        }
        out[m] = ck;
        m += 1;
        if ck + 1 < n {
            out[m] = ck + 1;
            m += 1;
        } else if self.periodic[k] {
            out[m] = 0;
            m += 1;
        }
        m
    }

    /// Calls `f(flat, coordinates)` for every cell whose coordinate along each axis `k` is
    /// one of `ranges[k][..lens[k]]`.
    #[inline(always)]
    fn for_each_cell_of(
        &self,
        ranges: &[[usize; 3]; D],
        lens: &[usize; D],
        mut f: impl FnMut(usize, &[usize; D]),
    ) {
        let mut idx = [0usize; D];
        loop {
            let c: [usize; D] = std::array::from_fn(|k| ranges[k][idx[k]]);
            let mut flat = 0usize;
            for k in (0..D).rev() {
                flat = flat * self.counts[k] + c[k];
            }
            f(flat, &c);
            if !odometer_step(&mut idx, lens) {
                return;
            }
        }
    }

    /// Calls `f(j)` for every particle in the cell with flat index `flat`.
    #[inline(always)]
    fn for_each_in_cell(&self, flat: usize, f: &mut impl FnMut(usize)) {
        self.for_each_in_list(self.head[flat], f);
    }

    /// Calls `f(j)` for every particle of the cell list starting at `first`.
    #[inline(always)]
    fn for_each_in_list(&self, first: u32, f: &mut impl FnMut(usize)) {
        let _ = self.try_for_each_in_list(first, |j| {
            f(j);
            Some(())
        });
    }

    /// Calls `f(j)` for the particles of the cell list starting at `first`, in order,
    /// until `f` returns `None` (then returns `None`).
    #[inline(always)]
    fn try_for_each_in_list(
        &self,
        first: u32,
        mut f: impl FnMut(usize) -> Option<()>,
    ) -> Option<()> {
        let mut j = first;
        while j != NONE {
            f(j as usize)?;
            j = self.next[j as usize];
        }
        Some(())
    }
}

/// The candidates of one prediction: a buffer that only grows, written through a slice.
/// A `Vec::push` per candidate re-reads and stores the vector's length and pointer
/// through memory (the compiler cannot tell them from the cell lists it reads), some 15
/// instructions each; here a candidate costs a bounds check and a store, and a list that
/// does not fit (rare: clusters, wide cells) doubles the buffer and is gathered again.
#[derive(Clone, Debug, Default)]
pub struct Candidates {
    buf: Vec<u32>,
    len: usize,
}

impl Candidates {
    /// Empties the list (keeps the buffer).
    #[inline(always)]
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// The candidates.
    #[inline(always)]
    pub fn as_slice(&self) -> &[u32] {
        &self.buf[..self.len]
    }

    /// Appends the candidates `js`.
    #[inline(always)]
    pub fn extend_from(&mut self, js: &[u32]) {
        self.append(|buf| {
            buf.get_mut(..js.len())?.copy_from_slice(js);
            Some(js.len())
        });
    }

    /// Appends one candidate.
    #[inline(always)]
    pub fn push(&mut self, j: u32) {
        self.append(|buf| {
            *buf.first_mut()? = j;
            Some(1)
        });
    }

    /// Appends what `write` puts at the start of the free part of the buffer: it returns
    /// how many, or `None` when the buffer is too short (which grows it and calls
    /// `write` again).
    #[inline(always)]
    fn append(&mut self, mut write: impl FnMut(&mut [u32]) -> Option<usize>) {
        loop {
            if let Some(m) = write(&mut self.buf[self.len..]) {
                self.len += m;
                return;
            }
            let grown = (2 * self.buf.len()).max(64);
            self.buf.resize(grown, NONE);
        }
    }
}

/// Advances the multi-index `idx` (axis 0 fastest, `idx[k] < lens[k]`); `false` once every
/// combination has been visited.
#[inline(always)]
fn odometer_step<const D: usize>(idx: &mut [usize; D], lens: &[usize; D]) -> bool {
    for k in 0..D {
        idx[k] += 1;
        if idx[k] < lens[k] {
            return true;
        }
        idx[k] = 0;
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::AxisKind;
    use crate::vector::Vector;
    use std::collections::BTreeSet;

    /// Coordinates of cell `f` (flat index, axis 0 fastest) of a grid with
    /// `per_axis` cells along every axis.
    fn cell_coords<const D: usize>(f: usize, per_axis: usize) -> [u32; D] {
        let mut c = [0u32; D];
        let mut r = f;
        for ck in c.iter_mut() {
            *ck = (r % per_axis) as u32;
            r /= per_axis;
        }
        c
    }

    fn neighbourhood<const D: usize>(g: &CellGrid<D>, c: &[u32; D]) -> BTreeSet<u32> {
        let mut out = Candidates::default();
        g.gather_neighbours(c, &mut out);
        out.as_slice().iter().copied().collect()
    }

    /// The layer a crossing gathers, with the cells the grain's old cell already had
    /// around it, is exactly the new cell's neighbourhood, on walled and periodic axes,
    /// at the faces and inside.
    fn layer_completes_the_neighbourhood<const D: usize>(kind: AxisKind, side: f64) {
        let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
        let cells_per_axis = side as usize;
        let total = cells_per_axis.pow(D as u32);
        // One grain per cell (grain = flat cell index).
        let mut g = CellGrid::<D>::new(&bx, 1.0, total);
        for f in 0..total {
            g.insert(f, cell_coords(f, cells_per_axis));
        }
        for f in 0..total {
            let old = g.coords(f);
            for axis in 0..D {
                for step in [-1i32, 1] {
                    let v = old[axis] as i64 + step as i64;
                    let n = cells_per_axis as i64;
                    if kind == AxisKind::Wall && (v < 0 || v >= n) {
                        continue;
                    }
                    let mut new = old;
                    new[axis] = v.rem_euclid(n) as u32;
                    let mut layer = Candidates::default();
                    g.gather_layer(&new, axis, step, &mut layer);
                    let layer: BTreeSet<u32> = layer.as_slice().iter().copied().collect();
                    let before = neighbourhood(&g, &old);
                    let after = neighbourhood(&g, &new);
                    assert!(layer.is_subset(&after), "{old:?} -> {new:?}");
                    let union: BTreeSet<u32> =
                        before.intersection(&after).chain(&layer).copied().collect();
                    assert_eq!(union, after, "{old:?} -> {new:?} along {axis}");
                }
            }
        }
    }

    /// Crowded cells (a cluster, or a few wide cells) overflow the candidate buffer,
    /// which grows and gathers again: every grain is still listed once, after the
    /// candidates already in the list.
    #[test]
    fn gather_grows_its_buffer_for_crowded_cells() {
        let bx = SimulationBox::<2>::uniform(Vector([5.0; 2]), AxisKind::Wall);
        let n = 300;
        let mut g = CellGrid::<2>::new(&bx, 1.0, n);
        // Grain i in cell (i mod 3, 0): 100 grains in each of three neighbouring cells.
        for i in 0..n {
            g.insert(i, [(i % 3) as u32, 0]);
        }
        let mut out = Candidates::default();
        out.push(u32::MAX - 7);
        g.gather_neighbours(&[1, 0], &mut out);
        let listed = out.as_slice();
        assert_eq!(listed.len(), n + 1);
        assert_eq!(listed[0], u32::MAX - 7);
        let unique: BTreeSet<u32> = listed[1..].iter().copied().collect();
        assert_eq!(unique, (0..n as u32).collect());
        out.clear();
        g.gather_layer(&[1, 0], 0, 1, &mut out);
        assert_eq!(out.as_slice().len(), 100);
        assert!(out.as_slice().iter().all(|&j| j % 3 == 2));
    }

    /// The pair gather lists every grain of the union of the two neighbourhoods once,
    /// for every pair of cells (adjacent or not), on walled and periodic grids.
    fn pair_gather_is_the_union<const D: usize>(kind: AxisKind, side: f64) {
        let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
        let cells_per_axis = side as usize;
        let total = cells_per_axis.pow(D as u32);
        // Two grains per cell (grains f and f + total in cell f).
        let mut g = CellGrid::<D>::new(&bx, 1.0, 2 * total);
        let coords = |f: usize| cell_coords::<D>(f, cells_per_axis);
        for f in 0..2 * total {
            g.insert(f, coords(f % total));
        }
        for fa in 0..total {
            for fb in 0..total {
                let (a, b) = (coords(fa), coords(fb));
                let mut out = Candidates::default();
                g.gather_pair(&a, &b, &mut out);
                let listed = out.as_slice();
                let unique: BTreeSet<u32> = listed.iter().copied().collect();
                assert_eq!(
                    unique.len(),
                    listed.len(),
                    "{a:?} {b:?}: a grain listed twice"
                );
                let union: BTreeSet<u32> = neighbourhood(&g, &a)
                    .union(&neighbourhood(&g, &b))
                    .copied()
                    .collect();
                assert_eq!(unique, union, "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn pair_gather_lists_both_neighbourhoods_once() {
        pair_gather_is_the_union::<2>(AxisKind::Wall, 6.0);
        pair_gather_is_the_union::<2>(AxisKind::Periodic, 6.0);
        pair_gather_is_the_union::<2>(AxisKind::Periodic, 3.0);
        pair_gather_is_the_union::<3>(AxisKind::Wall, 4.0);
        pair_gather_is_the_union::<3>(AxisKind::Periodic, 4.0);
    }

    /// The multiplication gives the quotient and remainder of `/` and `%` for counts and
    /// indices over the whole 32-bit range (powers of two, 1 and the extremes included),
    /// and a checkpoint stores the cell counts alone.
    #[test]
    fn count_divisor_divides_every_index_exactly() {
        use crate::random::{RngExt, stream};
        let mut rng = stream(11, &[0]);
        let mut counts = vec![
            1u32,
            2,
            3,
            7,
            64,
            105,
            1000,
            65_537,
            1 << 31,
            u32::MAX - 1,
            u32::MAX,
        ];
        counts.extend((0..200).map(|_| rng.random_range(1..=u32::MAX)));
        counts.extend((0..200).map(|_| rng.random_range(1..=4096u32)));
        for &n in &counts {
            let d = CountDivisor::from(n);
            let mut indices = vec![0, 1, n - 1, n, n.saturating_add(1), u32::MAX - 1, u32::MAX];
            indices.extend((1..4).map(|k| n.saturating_mul(k).saturating_sub(1)));
            indices.extend((0..500).map(|_| rng.random_range(0..=u32::MAX)));
            for f in indices {
                assert_eq!(d.div_rem(f), (f / n, f % n), "{f} / {n}");
            }
        }
        // Stored as the counts alone, the divisors rebuilt on reading.
        let grid = CellCounts::from([105, 7, 65_537]);
        let bytes = rmp_serde::to_vec(&grid).expect("serialise");
        let stored: Vec<usize> = rmp_serde::from_slice(&bytes).expect("counts");
        assert_eq!(stored, [105, 7, 65_537]);
        assert_eq!(
            rmp_serde::from_slice::<CellCounts<3>>(&bytes).expect("read"),
            grid
        );
    }

    /// Where `without_wrap` holds, every two points of the cells around the given cells
    /// are nearer directly than through the periodic faces (the minimum image is the
    /// plain difference); it holds away from the faces of a large grid.
    #[test]
    fn without_wrap_means_plain_differences() {
        let bx = SimulationBox::<2>::uniform(Vector([12.0, 9.0]), AxisKind::Periodic);
        let g = CellGrid::<2>::new(&bx, 1.0, 200);
        assert_eq!(g.counts, [12, 9]);
        let mut held = 0;
        for a in 0..12 * 9 {
            for b in 0..12 * 9 {
                let (ca, cb) = ([a % 12, a / 12], [b % 12, b / 12]);
                if !g.without_wrap(&[ca, cb]) {
                    continue;
                }
                held += 1;
                // Extreme points of the span of cells around both.
                for k in 0..2 {
                    let lo = ca[k].min(cb[k]) as f64 - 1.0;
                    let hi = ca[k].max(cb[k]) as f64 + 2.0;
                    let d = (hi - lo) * g.widths[k];
                    assert!(lo >= 0.0 && hi * g.widths[k] <= bx.lengths[k]);
                    assert!(d < 0.5 * bx.lengths[k], "{ca:?} {cb:?} axis {k}");
                }
            }
        }
        assert!(held > 100, "{held}");
        assert!(g.without_wrap(&[[5, 4]]));
        assert!(!g.without_wrap(&[[0, 4]]));
        assert!(!g.without_wrap(&[[5, 8]]));
        assert!(!g.without_wrap(&[[2, 4], [6, 4]]));
    }

    #[test]
    fn crossing_layer_completes_the_neighbourhood() {
        layer_completes_the_neighbourhood::<2>(AxisKind::Wall, 5.0);
        layer_completes_the_neighbourhood::<2>(AxisKind::Periodic, 5.0);
        layer_completes_the_neighbourhood::<2>(AxisKind::Periodic, 3.0);
        layer_completes_the_neighbourhood::<3>(AxisKind::Wall, 4.0);
        layer_completes_the_neighbourhood::<3>(AxisKind::Periodic, 4.0);
    }

    #[test]
    fn large_grains_are_split_off_only_when_few_and_much_larger() {
        // One kind: no split. Half and half (1:1.4): too many to test from every grain.
        assert_eq!(large_grain_cut::<2>(&[1.0; 100], 1e4), None);
        let mixture: Vec<f64> = (0..100)
            .map(|i| if i % 2 == 0 { 1.0 } else { 1.4 })
            .collect();
        assert_eq!(large_grain_cut::<2>(&mixture, 1e4), None);
        // The crater of Problem 4: 5000 bed grains and a 5 times larger projectile.
        let mut crater = vec![0.003989; 5000];
        crater.push(0.019945);
        assert_eq!(large_grain_cut::<2>(&crater, 1.0), Some(0.003989));
        // Two intruders of two sizes among 10^4 spheres: both large.
        let mut bath = vec![1.0; 10_000];
        bath.extend([8.0, 12.0]);
        assert_eq!(large_grain_cut::<3>(&bath, 1e6), Some(1.0));
        // A grain only slightly larger: the cells would hardly shrink.
        let mut near = vec![1.0; 1000];
        near.push(1.2);
        assert_eq!(large_grain_cut::<2>(&near, 1e4), None);
    }

    /// With large grains kept out of the lists, `for_each_candidate` still offers every
    /// pair within contact distance from at least one of its grains, walled and periodic.
    fn candidates_cover_every_contact<const D: usize>(kind: AxisKind) {
        use crate::random::stream;
        use rand::RngExt;
        let side = 20.0;
        let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
        let mut rng = stream(5, &[D as u64]);
        let mut radii = vec![0.5; 600];
        radii.extend([3.0, 4.5]);
        let positions: Vec<Vector<D>> = radii
            .iter()
            .map(|_| Vector(std::array::from_fn(|_| side * rng.random::<f64>())))
            .collect();
        let (mut g, cut) = CellGrid::<D>::for_radii(&bx, &radii, 1.0, true);
        assert!(cut.is_some(), "a split");
        for (i, x) in positions.iter().enumerate() {
            g.insert_grain(i, g.coords_of(&x.0), radii[i], cut);
        }
        assert_eq!(g.large(), &[600, 601]);
        let mut offered = BTreeSet::new();
        for i in 0..radii.len() {
            g.for_each_candidate(i, |j| {
                offered.insert((i.min(j), i.max(j)));
            });
        }
        let mut contacts = 0;
        for i in 0..radii.len() {
            for j in i + 1..radii.len() {
                let d = bx.separation(&positions[i], &positions[j]).norm();
                if d < radii[i] + radii[j] {
                    contacts += 1;
                    assert!(
                        offered.contains(&(i, j)),
                        "{D}D {kind:?}: pair ({i}, {j}) at {d}"
                    );
                }
            }
        }
        assert!(contacts > 50, "{contacts}");
        // The order of the cells puts every grain somewhere, large ones included.
        assert_eq!(g.cell_order().len(), radii.len());
    }

    #[test]
    fn large_grains_reach_every_grain_they_can_touch() {
        candidates_cover_every_contact::<2>(AxisKind::Wall);
        candidates_cover_every_contact::<2>(AxisKind::Periodic);
        candidates_cover_every_contact::<3>(AxisKind::Wall);
        candidates_cover_every_contact::<3>(AxisKind::Periodic);
    }
}
