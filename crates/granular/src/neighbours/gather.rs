//! Gathering the candidates of a prediction: the grains of the cells around a grain (all
//! of them, the layer a crossing made adjacent, or the union around both grains of a
//! pair), the cells within a large grain's reach, and the buffer they are written into.

use super::{CellGrid, NONE};

impl<const D: usize> CellGrid<D> {
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
    pub(super) fn for_each_neighbour_run(&self, c: &[u32; D], mut f: impl FnMut(usize, usize)) {
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
