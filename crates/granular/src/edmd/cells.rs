//! The cell grid: the box is cut into cells at least one contact distance wide, so that a
//! grain can only touch grains in its own or a neighbouring cell. Each cell holds a doubly
//! linked list of its grains (O(1) moves when a grain crosses a cell boundary).
//!
//! Hand-written: neighbour search is, with the event queue, the core of the engine's speed.

use crate::boundary::SimulationBox;
use serde::{Deserialize, Serialize};

/// Sentinel for "no particle".
pub const NONE: u32 = u32::MAX;

/// A regular grid of cells over the box.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CellGrid<const D: usize> {
    /// Cells per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub counts: [usize; D],
    /// Cell width per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub widths: [f64; D],
    /// Whether each axis wraps around.
    #[serde(with = "crate::vector::serde_array")]
    periodic: [bool; D],
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Cell coordinates of each particle.
    #[serde(with = "crate::vector::serde_vec_array")]
    pub coords: Vec<[u32; D]>,
}

impl<const D: usize> CellGrid<D> {
    /// A grid over `bx` with cells at least `min_width` wide (the largest contact
    /// distance), for `n` particles. Periodic axes with fewer than three cells collapse to
    /// one cell, so that a neighbour is never visited twice.
    pub fn new(bx: &SimulationBox<D>, min_width: f64, n: usize) -> Self {
        let mut counts = [1usize; D];
        let mut widths = [0.0; D];
        let mut periodic = [false; D];
        // Keep the grid at most ~2 cells per particle so memory stays O(N) in sparse boxes.
        let max_cells = (2 * n).max(1) as f64;
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
            // Coarsen the finest axis.
            let k = (0..D)
                .max_by(|&a, &b| counts[a].cmp(&counts[b]))
                .unwrap_or(0);
            let c = counts[k];
            let new = (c / 2).max(1);
            let new = if periodic[k] && new < 3 { 1 } else { new };
            total = total / c as f64 * new as f64;
            counts[k] = new;
            if new == c {
                break;
            }
        }
        for k in 0..D {
            widths[k] = bx.lengths[k] / counts[k] as f64;
        }
        let ncells = counts.iter().product();
        Self {
            counts,
            widths,
            periodic,
            head: vec![NONE; ncells],
            next: vec![NONE; n],
            prev: vec![NONE; n],
            coords: vec![[0; D]; n],
        }
    }

    /// Heap memory in bytes (cell heads, lists and coordinates).
    pub fn memory_bytes(&self) -> usize {
        (self.head.capacity() + self.next.capacity() + self.prev.capacity()) * 4
            + self.coords.capacity() * 4 * D
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

    #[inline(always)]
    fn flat(&self, c: &[u32; D]) -> usize {
        let mut idx = 0usize;
        for k in (0..D).rev() {
            idx = idx * self.counts[k] + c[k] as usize;
        }
        idx
    }

    /// Puts particle `i` into cell `c`.
    pub fn insert(&mut self, i: usize, c: [u32; D]) {
        let f = self.flat(&c);
        let h = self.head[f];
        self.next[i] = h;
        self.prev[i] = NONE;
        if h != NONE {
            self.prev[h as usize] = i as u32;
        }
        self.head[f] = i as u32;
        self.coords[i] = c;
    }

    /// Takes particle `i` out of its cell.
    pub fn remove(&mut self, i: usize) {
        let (p, n) = (self.prev[i], self.next[i]);
        if p != NONE {
            self.next[p as usize] = n;
        } else {
            let f = self.flat(&self.coords[i]);
            self.head[f] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
    }

    /// Moves particle `i` one cell along `axis` in direction `step` (+1 or -1), wrapping on
    /// periodic axes. Returns whether the particle wrapped around the box.
    pub fn shift(&mut self, i: usize, axis: usize, step: i32) -> bool {
        self.remove(i);
        let mut c = self.coords[i];
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
        self.insert(i, c);
        wrapped
    }

    /// Calls `f(j)` for every particle in the cells neighbouring (and including) cell `c`.
    #[inline(always)]
    pub fn for_each_neighbour(&self, c: &[u32; D], mut f: impl FnMut(usize)) {
        // Offsets per axis: -1, 0, +1, clipped at walls, wrapped on periodic axes; a
        // single-cell axis contributes only 0.
        let mut ranges = [[0i64; 3]; D];
        let mut lens = [0usize; D];
        for k in 0..D {
            let n = self.counts[k] as i64;
            let ck = c[k] as i64;
            let mut m = 0;
            for off in -1i64..=1 {
                if n == 1 && off != 0 {
                    continue;
                }
                let mut v = ck + off;
                if v < 0 || v >= n {
                    if !self.periodic[k] {
                        continue;
                    }
                    v = v.rem_euclid(n);
                }
                ranges[k][m] = v;
                m += 1;
            }
            lens[k] = m;
        }
        let mut idx = [0usize; D];
        loop {
            let mut flat = 0usize;
            for k in (0..D).rev() {
                flat = flat * self.counts[k] + ranges[k][idx[k]] as usize;
            }
            let mut j = self.head[flat];
            while j != NONE {
                f(j as usize);
                j = self.next[j as usize];
            }
            // Odometer increment.
            let mut k = 0;
            loop {
                if k == D {
                    return;
                }
                idx[k] += 1;
                if idx[k] < lens[k] {
                    break;
                }
                idx[k] = 0;
                k += 1;
            }
        }
    }
}
