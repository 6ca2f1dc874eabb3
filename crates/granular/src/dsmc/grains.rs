//! The grains of a DSMC engine (or of one rank's slab): one record per grain, in storage
//! order (sorted by cell after every step, see `cells`).
//!
//! # The record
//!
//! A grain is `D` lattice words (its position as integer lattice coordinates, whose low
//! bits also hold its identity: see [`Lattice`]) and `D` velocity components (`f64`), and,
//! with the TC model only, its last collision time (`f64`): `16 D` bytes, 32 in 2D and
//! 48 in 3D; rough grains add their angular velocity, `d_r` columns (`ω_z` of a disk, the
//! three components of a sphere's), 8 bytes in 2D and 24 in 3D, which smooth grains do
//! not have. Each quantity is one column (a structure of arrays), so that the free flight
//! streams through whole columns and an optional per-grain quantity (the TC model's
//! collision times; rotational velocities) is one more column that costs nothing when
//! absent. Sorting by cell moves one column at a time through one shared scratch column
//! (`Grains::reorder`), so the sort needs `8 + 4` bytes per grain (the scratch and each
//! grain's destination), not a second copy of the record.
//!
//! Everything outside the kernel (flight, sort, collisions) goes through the accessors
//! here: positions and velocities come out as [`Vector`]s in box coordinates, and a record
//! travels between ranks or into a checkpoint as [`Grains::words`] 64-bit words
//! ([`Grains::pack`], [`Grains::push_packed`]) that restore it bit for bit.

use super::lattice::Lattice;
use crate::collision_law::rough::{Spin, rotational_dof};
use crate::vector::Vector;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// The grains' records in storage order.
#[derive(Debug, Serialize, Deserialize)]
pub(crate) struct Grains<const D: usize> {
    /// The mapping between positions and lattice words (and the identity bits).
    lattice: Lattice<D>,
    /// Lattice words, one column per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub(super) pos: [Vec<u64>; D],
    /// Velocity components, one column per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub(super) vel: [Vec<f64>; D],
    /// Time of each grain's last collision (the TC model only; empty otherwise).
    pub(super) last: Vec<f64>,
    /// Whether the records carry `last`.
    collision_times: bool,
    /// Angular velocities of rough grains, one column per rotational degree of freedom
    /// (`ω_z` in 2D; `ω_x`, `ω_y`, `ω_z` in 3D); no column for smooth grains.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) spin: Vec<Vec<f64>>,
    /// The sort's scratch column (see [`Grains::reorder`]); not part of the state.
    #[serde(skip)]
    scratch: Vec<u64>,
}

impl<const D: usize> Clone for Grains<D> {
    /// The records, without the scratch column.
    fn clone(&self) -> Self {
        Self {
            lattice: self.lattice,
            pos: self.pos.clone(),
            vel: self.vel.clone(),
            last: self.last.clone(),
            collision_times: self.collision_times,
            spin: self.spin.clone(),
            scratch: Vec::new(),
        }
    }
}

impl<const D: usize> Grains<D> {
    /// No grains on `lattice`; `collision_times`: whether the records carry the TC
    /// model's last collision time.
    pub(crate) fn new(lattice: Lattice<D>, collision_times: bool) -> Self {
        Self::with_capacity(lattice, 0, collision_times)
    }

    /// Room for `n` grains without reallocation.
    pub(crate) fn with_capacity(lattice: Lattice<D>, n: usize, collision_times: bool) -> Self {
        Self {
            lattice,
            pos: std::array::from_fn(|_| Vec::with_capacity(n)),
            vel: std::array::from_fn(|_| Vec::with_capacity(n)),
            last: Vec::with_capacity(if collision_times { n } else { 0 }),
            collision_times,
            spin: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// Grains `ids` at positions `pos` (in the box) with velocities `vel` (equal
    /// lengths), no previous collision.
    pub(crate) fn from_parts(
        lattice: Lattice<D>,
        pos: &[Vector<D>],
        vel: &[Vector<D>],
        ids: &[u32],
        collision_times: bool,
    ) -> Self {
        let mut g = Self::with_capacity(lattice, pos.len(), collision_times);
        for ((x, v), &id) in pos.iter().zip(vel).zip(ids) {
            g.push(id, *x, *v);
        }
        g
    }

    /// `n` grains whose records are all zero (no previous collision; `spin_columns`
    /// angular-velocity columns, none for smooth grains), to be written by
    /// [`Self::set_packed`].
    pub(crate) fn zeroed(
        lattice: Lattice<D>,
        n: usize,
        collision_times: bool,
        spin_columns: usize,
    ) -> Self {
        Self {
            lattice,
            pos: std::array::from_fn(|_| vec![0; n]),
            vel: std::array::from_fn(|_| vec![0.0; n]),
            last: vec![f64::NEG_INFINITY; if collision_times { n } else { 0 }],
            collision_times,
            spin: (0..spin_columns).map(|_| vec![0.0; n]).collect(),
            scratch: Vec::new(),
        }
    }

    /// The lattice of the positions.
    pub(crate) fn lattice(&self) -> &Lattice<D> {
        &self.lattice
    }

    /// Number of grains.
    pub fn len(&self) -> usize {
        self.vel[0].len()
    }

    /// Whether the records carry last collision times (the TC model).
    pub(crate) fn has_collision_times(&self) -> bool {
        self.collision_times
    }

    /// Turns the last collision times on (every grain without a previous collision) or
    /// off (forgotten).
    pub(crate) fn set_collision_times(&mut self, on: bool) {
        if !on {
            self.last = Vec::new();
        } else if !self.collision_times {
            self.last = vec![f64::NEG_INFINITY; self.len()];
        }
        self.collision_times = on;
    }

    /// Whether the grains are rough (the records carry angular velocities).
    pub(crate) fn is_rough(&self) -> bool {
        !self.spin.is_empty()
    }

    /// Gives the records angular velocities (rough grains): `flat` holds `d_r` values per
    /// grain in storage order (`ω_z` in 2D; `ω_x, ω_y, ω_z` in 3D); `None` takes them
    /// away (smooth grains).
    pub(crate) fn set_spins(&mut self, flat: Option<&[f64]>) {
        self.spin = match flat {
            None => Vec::new(),
            Some(flat) => {
                let r = rotational_dof(D);
                (0..r)
                    .map(|c| flat.iter().skip(c).step_by(r).copied().collect())
                    .collect()
            }
        };
    }

    /// The angular velocity of grain `i` (`[0, 0, ω_z]` for a disk); zero for smooth
    /// grains.
    #[inline]
    pub(crate) fn spin(&self, i: usize) -> Spin {
        match self.spin.len() {
            0 => [0.0; 3],
            1 => [0.0, 0.0, self.spin[0][i]],
            _ => [self.spin[0][i], self.spin[1][i], self.spin[2][i]],
        }
    }

    /// Multiplies every angular velocity by `factor` (in parallel; nothing for smooth
    /// grains).
    pub(crate) fn scale_spins(&mut self, factor: f64) {
        use rayon::prelude::*;
        for col in &mut self.spin {
            col.par_chunks_mut(4096)
                .for_each(|c| c.iter_mut().for_each(|w| *w *= factor));
        }
    }

    /// Bytes held per grain: the record's columns and the sort's scratch column, from
    /// their capacities (the destination cells of a step are the engine's).
    pub(crate) fn bytes(&self) -> usize {
        let words: usize = self.pos.iter().map(Vec::capacity).sum::<usize>()
            + self.vel.iter().map(Vec::capacity).sum::<usize>()
            + self.last.capacity()
            + self.spin.iter().map(Vec::capacity).sum::<usize>()
            + self.scratch.capacity();
        8 * words
    }

    /// The lattice words of grain `i`.
    #[inline]
    pub(crate) fn words_of(&self, i: usize) -> [u64; D] {
        std::array::from_fn(|k| self.pos[k][i])
    }

    /// Position of grain `i` (box coordinates: the nearest `f64` to its lattice point).
    #[inline]
    pub(crate) fn position(&self, i: usize) -> Vector<D> {
        self.lattice.position(&self.words_of(i))
    }

    /// Velocity of grain `i`.
    #[inline]
    pub(crate) fn velocity(&self, i: usize) -> Vector<D> {
        Vector(std::array::from_fn(|k| self.vel[k][i]))
    }

    /// Identity of grain `i` (its index at construction).
    #[inline]
    pub(crate) fn id(&self, i: usize) -> u32 {
        self.lattice.id(&self.words_of(i))
    }

    /// Every position, in storage order.
    pub(crate) fn positions(&self) -> Vec<Vector<D>> {
        (0..self.len()).map(|i| self.position(i)).collect()
    }

    /// Every velocity, in storage order.
    pub(crate) fn velocities(&self) -> Vec<Vector<D>> {
        (0..self.len()).map(|i| self.velocity(i)).collect()
    }

    /// Every identity, in storage order.
    pub(crate) fn ids(&self) -> Vec<u32> {
        (0..self.len()).map(|i| self.id(i)).collect()
    }

    /// Replaces every velocity `v` (of the grain with identity `id`) by `f(id, v)`, in
    /// parallel.
    pub(crate) fn update_velocities(&mut self, f: impl Fn(u32, Vector<D>) -> Vector<D> + Sync) {
        use rayon::prelude::*;
        let lattice = self.lattice;
        let n = self.len();
        const CHUNK: usize = 4096;
        let mut cols = self.columns();
        let mut jobs = Vec::with_capacity(n.div_ceil(CHUNK));
        while cols.len() > 0 {
            let mid = CHUNK.min(cols.len());
            let (a, b) = cols.split_at(mid);
            jobs.push(a);
            cols = b;
        }
        jobs.into_par_iter().for_each(|c| {
            for i in 0..c.len() {
                let w: [u64; D] = std::array::from_fn(|k| c.pos[k][i]);
                let v = f(lattice.id(&w), Vector(std::array::from_fn(|k| c.vel[k][i])));
                for k in 0..D {
                    c.vel[k][i] = v[k];
                }
            }
        });
    }

    /// Velocity components along axis `k` of every grain, in storage order.
    pub(crate) fn velocity_column(&self, k: usize) -> &[f64] {
        &self.vel[k]
    }

    /// Appends grain `id` at `x` (in the box) with velocity `v` (no previous collision).
    pub(crate) fn push(&mut self, id: u32, x: Vector<D>, v: Vector<D>) {
        let w = self.lattice.words(&x, id);
        for k in 0..D {
            self.pos[k].push(w[k]);
            self.vel[k].push(v[k]);
        }
        if self.collision_times {
            self.last.push(f64::NEG_INFINITY);
        }
        for col in &mut self.spin {
            col.push(0.0);
        }
    }

    /// 64-bit words per packed record ([`Self::pack`]).
    pub(crate) fn words(&self) -> usize {
        2 * D + usize::from(self.collision_times) + self.spin.len()
    }

    /// Where the angular velocity starts in a packed record.
    fn spin_word(&self) -> usize {
        2 * D + usize::from(self.collision_times)
    }

    /// Appends grain `i`'s record to `out` as [`Self::words`] words (bit patterns: the
    /// lattice words, the velocity, the last collision time, the angular velocity; a
    /// record restored by
    /// [`Self::push_packed`] or [`Self::set_packed`] is the same bits).
    pub(crate) fn pack(&self, i: usize, out: &mut Vec<f64>) {
        for k in 0..D {
            out.push(f64::from_bits(self.pos[k][i]));
        }
        for k in 0..D {
            out.push(self.vel[k][i]);
        }
        if let Some(&t) = self.last.get(i) {
            out.push(t);
        }
        for col in &self.spin {
            out.push(col[i]);
        }
    }

    /// Appends the record packed in `words` (exactly [`Self::words`] of them).
    pub(crate) fn push_packed(&mut self, words: &[f64]) {
        for k in 0..D {
            self.pos[k].push(words[k].to_bits());
            self.vel[k].push(words[D + k]);
        }
        if self.collision_times {
            self.last.push(words[2 * D]);
        }
        let at = self.spin_word();
        for (c, col) in self.spin.iter_mut().enumerate() {
            col.push(words[at + c]);
        }
    }

    /// Overwrites record `i` with the record packed in `words` (exactly [`Self::words`]
    /// of them).
    pub(crate) fn set_packed(&mut self, i: usize, words: &[f64]) {
        for k in 0..D {
            self.pos[k][i] = words[k].to_bits();
            self.vel[k][i] = words[D + k];
        }
        if self.collision_times {
            self.last[i] = words[2 * D];
        }
        let at = self.spin_word();
        for (c, col) in self.spin.iter_mut().enumerate() {
            col[i] = words[at + c];
        }
    }

    /// A copy of the records `r`.
    pub(crate) fn range(&self, r: Range<usize>) -> Grains<D> {
        let mut g = Self::with_capacity(self.lattice, r.len(), self.collision_times);
        g.spin = vec![Vec::with_capacity(r.len()); self.spin.len()];
        g.extend_from(self, r);
        g
    }

    /// Appends copies of `other`'s records `r` (both with or both without collision
    /// times, both rough or both smooth, on the same lattice).
    pub(crate) fn extend_from(&mut self, other: &Grains<D>, r: Range<usize>) {
        for k in 0..D {
            self.pos[k].extend_from_slice(&other.pos[k][r.clone()]);
            self.vel[k].extend_from_slice(&other.vel[k][r.clone()]);
        }
        if self.collision_times {
            self.last.extend_from_slice(&other.last[r.clone()]);
        }
        for (col, o) in self.spin.iter_mut().zip(&other.spin) {
            col.extend_from_slice(&o[r.clone()]);
        }
    }

    /// Whether the columns have one length and the lattice is `lattice` (a store read from
    /// a file that fails this was not written by this engine).
    pub(crate) fn consistent(&self, lattice: &Lattice<D>) -> bool {
        let n = self.len();
        self.lattice == *lattice
            && self.pos.iter().all(|c| c.len() == n)
            && self.vel.iter().all(|c| c.len() == n)
            && self.last.len() == if self.collision_times { n } else { 0 }
            && (self.spin.is_empty() || self.spin.len() == rotational_dof(D))
            && self.spin.iter().all(|c| c.len() == n)
    }

    /// The kernel's mutable view of every column.
    pub(super) fn columns(&mut self) -> Columns<'_, D> {
        Columns {
            pos: self.pos.each_mut().map(|c| &mut c[..]),
            vel: self.vel.each_mut().map(|c| &mut c[..]),
            last: &mut self.last[..],
            spin: Spins::of(&mut self.spin),
        }
    }

    /// Reorders the records: record `i` goes to slot `dest[i]` of `n` slots (`dest[i] ==
    /// n`: it leaves), and the packed records `arrivals` (each [`Self::words`] words) go
    /// to the slots `arrival_slots`; every slot `0 .. n` must be taken exactly once. One
    /// column at a time is scattered into the scratch column, which then takes the
    /// column's place (the column's old storage becomes the scratch).
    pub(super) fn reorder(
        &mut self,
        dest: &[u32],
        n: usize,
        arrivals: &[f64],
        arrival_slots: &[u32],
    ) {
        let w = self.words();
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut scatter = |col: &mut Vec<u64>, at: usize| {
            fit(&mut scratch, n + 1);
            let out = &mut scratch[..n + 1];
            // Four at a time (fewer loop instructions per grain).
            let (d4, dr) = dest.as_chunks::<4>();
            let (x4, xr) = col[..dest.len()].as_chunks::<4>();
            for (s, x) in d4.iter().zip(x4) {
                out[s[0] as usize] = x[0];
                out[s[1] as usize] = x[1];
                out[s[2] as usize] = x[2];
                out[s[3] as usize] = x[3];
            }
            for (&s, &x) in dr.iter().zip(xr) {
                out[s as usize] = x;
            }
            for (r, &s) in arrivals.chunks_exact(w).zip(arrival_slots) {
                out[s as usize] = r[at].to_bits();
            }
            scratch.truncate(n);
            std::mem::swap(col, &mut scratch);
        };
        for k in 0..D {
            scatter(&mut self.pos[k], k);
        }
        for k in 0..D {
            with_bits(&mut self.vel[k], |c| scatter(c, D + k));
        }
        if self.collision_times {
            with_bits(&mut self.last, |c| scatter(c, 2 * D));
        }
        let at = 2 * D + usize::from(self.collision_times);
        for (c, col) in self.spin.iter_mut().enumerate() {
            with_bits(col, |b| scatter(b, at + c));
        }
        self.scratch = scratch;
    }
}

/// Makes `v` `len` long without writing its old contents anew (they are overwritten by
/// the caller) and without growing its allocation by doubling: a column that needs more
/// room gets a fresh allocation with a little headroom (`len / 256 + 16`), so a rank whose
/// grain count drifts up reallocates rarely and no buffer ever holds twice its grains.
fn fit(v: &mut Vec<u64>, len: usize) {
    if v.capacity() < len {
        *v = Vec::new();
        *v = Vec::with_capacity(len + len / 256 + 16);
    }
    if v.len() < len {
        v.resize(len, 0);
    } else {
        v.truncate(len);
    }
}

/// Runs `f` on the bits of an `f64` column (the same allocation, no copy).
fn with_bits(col: &mut Vec<f64>, f: impl FnOnce(&mut Vec<u64>)) {
    let mut bits: Vec<u64> = bytemuck::allocation::cast_vec(std::mem::take(col));
    f(&mut bits);
    *col = bytemuck::allocation::cast_vec(bits);
}

/// Mutable slices of every column of a range of grains (the kernel's view).
pub(super) struct Columns<'a, const D: usize> {
    pub(super) pos: [&'a mut [u64]; D],
    pub(super) vel: [&'a mut [f64]; D],
    /// Empty without the TC model.
    pub(super) last: &'a mut [f64],
    /// The angular velocities of rough grains (`None` for smooth grains).
    pub(super) spin: Option<Spins<'a>>,
}

/// Mutable slices of the angular-velocity columns of a range of rough grains: one column
/// (`ω_z`) in 2D, three in 3D.
pub(super) struct Spins<'a> {
    pub(super) cols: [&'a mut [f64]; 3],
    /// Columns in use (1 or 3).
    pub(super) len: usize,
}

impl<'a> Spins<'a> {
    /// The view of `spin` (`None` when it has no column: smooth grains).
    fn of(spin: &'a mut [Vec<f64>]) -> Option<Self> {
        let len = spin.len();
        if len == 0 {
            return None;
        }
        let mut cols: [&'a mut [f64]; 3] = Default::default();
        for (c, col) in spin.iter_mut().enumerate() {
            cols[c] = &mut col[..];
        }
        Some(Self { cols, len })
    }

    /// The first `mid` grains and the rest.
    fn split_at(self, mid: usize) -> (Spins<'a>, Spins<'a>) {
        let mut lo: [&'a mut [f64]; 3] = Default::default();
        let mut hi: [&'a mut [f64]; 3] = Default::default();
        for (c, col) in self.cols.into_iter().enumerate().take(self.len) {
            let (a, b) = col.split_at_mut(mid);
            lo[c] = a;
            hi[c] = b;
        }
        (
            Spins {
                cols: lo,
                len: self.len,
            },
            Spins {
                cols: hi,
                len: self.len,
            },
        )
    }

    /// The angular velocity of grain `i` (`[0, 0, ω_z]` for a disk).
    #[inline(always)]
    pub(super) fn get(&self, i: usize) -> Spin {
        if self.len == 1 {
            [0.0, 0.0, self.cols[0][i]]
        } else {
            [self.cols[0][i], self.cols[1][i], self.cols[2][i]]
        }
    }

    /// Sets the angular velocity of grain `i`.
    #[inline(always)]
    pub(super) fn set(&mut self, i: usize, w: &Spin) {
        if self.len == 1 {
            self.cols[0][i] = w[2];
        } else {
            for (col, &x) in self.cols.iter_mut().zip(w) {
                col[i] = x;
            }
        }
    }
}

impl<'a, const D: usize> Columns<'a, D> {
    /// The first `mid` grains and the rest.
    pub(super) fn split_at(self, mid: usize) -> (Columns<'a, D>, Columns<'a, D>) {
        let mut lo_pos: [&'a mut [u64]; D] = std::array::from_fn(|_| Default::default());
        let mut hi_pos: [&'a mut [u64]; D] = std::array::from_fn(|_| Default::default());
        for (k, c) in self.pos.into_iter().enumerate() {
            let (a, b) = c.split_at_mut(mid);
            lo_pos[k] = a;
            hi_pos[k] = b;
        }
        let mut lo_vel: [&'a mut [f64]; D] = std::array::from_fn(|_| Default::default());
        let mut hi_vel: [&'a mut [f64]; D] = std::array::from_fn(|_| Default::default());
        for (k, c) in self.vel.into_iter().enumerate() {
            let (a, b) = c.split_at_mut(mid);
            lo_vel[k] = a;
            hi_vel[k] = b;
        }
        let (la, lb) = if self.last.is_empty() {
            (&mut [][..], &mut [][..])
        } else {
            self.last.split_at_mut(mid)
        };
        let (sa, sb) = match self.spin {
            Some(s) => {
                let (a, b) = s.split_at(mid);
                (Some(a), Some(b))
            }
            None => (None, None),
        };
        (
            Columns {
                pos: lo_pos,
                vel: lo_vel,
                last: la,
                spin: sa,
            },
            Columns {
                pos: hi_pos,
                vel: hi_vel,
                last: lb,
                spin: sb,
            },
        )
    }

    /// Number of grains.
    pub(super) fn len(&self) -> usize {
        self.vel[0].len()
    }
}
