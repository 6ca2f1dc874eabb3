//! The grains of a DSMC engine (or of one rank's slab): one record per grain, in storage
//! order (sorted by cell after every step, see `cells`).
//!
//! A record holds the grain's position, velocity and identity, and its last collision
//! time when the TC model is on. Everything outside the kernel (flight, sort, collisions)
//! goes through the accessors here, so that the storage layout can change without its
//! users: positions and velocities come out as [`Vector`]s in box coordinates, and a
//! record travels between ranks or into a checkpoint as a fixed number of 64-bit words
//! ([`Grains::pack`], [`Grains::push_packed`]) that restore it bit for bit.

use crate::vector::Vector;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// The grains' records in storage order.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Grains<const D: usize> {
    pub(super) pos: Vec<Vector<D>>,
    pub(super) vel: Vec<Vector<D>>,
    pub(super) ids: Vec<u32>,
    /// Time of each grain's last collision (the TC model only; empty otherwise).
    pub(super) last: Vec<f64>,
    /// Whether the records carry `last`.
    collision_times: bool,
}

impl<const D: usize> Grains<D> {
    /// No grains; `collision_times`: whether the records carry the TC model's last
    /// collision time.
    pub fn new(collision_times: bool) -> Self {
        Self {
            collision_times,
            ..Self::default()
        }
    }

    /// Room for `n` grains without reallocation.
    pub fn with_capacity(n: usize, collision_times: bool) -> Self {
        Self {
            pos: Vec::with_capacity(n),
            vel: Vec::with_capacity(n),
            ids: Vec::with_capacity(n),
            last: Vec::with_capacity(if collision_times { n } else { 0 }),
            collision_times,
        }
    }

    /// Grains `ids` at positions `pos` with velocities `vel` (equal lengths), no previous
    /// collision.
    pub fn from_parts(
        pos: Vec<Vector<D>>,
        vel: Vec<Vector<D>>,
        ids: Vec<u32>,
        collision_times: bool,
    ) -> Self {
        let n = pos.len();
        debug_assert!(vel.len() == n && ids.len() == n);
        Self {
            pos,
            vel,
            ids,
            last: if collision_times {
                vec![f64::NEG_INFINITY; n]
            } else {
                Vec::new()
            },
            collision_times,
        }
    }

    /// Number of grains.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// Whether there is no grain.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Whether the records carry last collision times (the TC model).
    pub fn has_collision_times(&self) -> bool {
        self.collision_times
    }

    /// Turns the last collision times on (every grain without a previous collision) or
    /// off (forgotten).
    pub fn set_collision_times(&mut self, on: bool) {
        if !on {
            self.last = Vec::new();
        } else if !self.collision_times {
            self.last = vec![f64::NEG_INFINITY; self.len()];
        }
        self.collision_times = on;
    }

    /// Position of grain `i` (box coordinates).
    #[inline]
    pub fn position(&self, i: usize) -> Vector<D> {
        self.pos[i]
    }

    /// Velocity of grain `i`.
    #[inline]
    pub fn velocity(&self, i: usize) -> Vector<D> {
        self.vel[i]
    }

    /// Sets the velocity of grain `i`.
    #[inline]
    pub fn set_velocity(&mut self, i: usize, v: Vector<D>) {
        self.vel[i] = v;
    }

    /// Identity of grain `i` (its index at construction).
    #[inline]
    pub fn id(&self, i: usize) -> u32 {
        self.ids[i]
    }

    /// Time of grain `i`'s last collision (TC model), `None` without collision times.
    #[inline]
    pub fn last_collision(&self, i: usize) -> Option<f64> {
        self.last.get(i).copied()
    }

    /// Every position, in storage order.
    pub fn positions(&self) -> Vec<Vector<D>> {
        (0..self.len()).map(|i| self.position(i)).collect()
    }

    /// Every velocity, in storage order.
    pub fn velocities(&self) -> Vec<Vector<D>> {
        (0..self.len()).map(|i| self.velocity(i)).collect()
    }

    /// Every identity, in storage order.
    pub fn ids(&self) -> Vec<u32> {
        (0..self.len()).map(|i| self.id(i)).collect()
    }

    /// Appends grain `id` at `x` with velocity `v` (no previous collision).
    pub fn push(&mut self, id: u32, x: Vector<D>, v: Vector<D>) {
        let tc = self.has_collision_times();
        self.pos.push(x);
        self.vel.push(v);
        self.ids.push(id);
        if tc {
            self.last.push(f64::NEG_INFINITY);
        }
    }

    /// 64-bit words per packed record ([`Self::pack`]).
    pub fn words(&self) -> usize {
        1 + 2 * D + usize::from(self.has_collision_times())
    }

    /// Appends grain `i`'s record to `out` as [`Self::words`] words (bit patterns; a
    /// record restored by [`Self::push_packed`] or [`Self::set_packed`] is the same bits).
    pub fn pack(&self, i: usize, out: &mut Vec<f64>) {
        out.push(f64::from_bits(u64::from(self.ids[i])));
        out.extend_from_slice(&self.pos[i].0);
        out.extend_from_slice(&self.vel[i].0);
        if let Some(&t) = self.last.get(i) {
            out.push(t);
        }
    }

    /// Appends the record packed in `words` (exactly [`Self::words`] of them).
    pub fn push_packed(&mut self, words: &[f64]) {
        let n = self.len();
        self.resize(n + 1);
        self.set_packed(n, words);
    }

    /// Overwrites grain `i` with the record packed in `words`.
    pub fn set_packed(&mut self, i: usize, words: &[f64]) {
        self.ids[i] = words[0].to_bits() as u32;
        self.pos[i] = Vector::from_slice(&words[1..1 + D]).unwrap_or_default();
        self.vel[i] = Vector::from_slice(&words[1 + D..1 + 2 * D]).unwrap_or_default();
        if let Some(t) = self.last.get_mut(i) {
            *t = words[1 + 2 * D];
        }
    }

    /// Copies the records `src` to `dest ..` (as `slice::copy_within`).
    pub fn copy_within(&mut self, src: Range<usize>, dest: usize) {
        self.pos.copy_within(src.clone(), dest);
        self.vel.copy_within(src.clone(), dest);
        self.ids.copy_within(src.clone(), dest);
        if self.collision_times {
            self.last.copy_within(src, dest);
        }
    }

    /// Copies record `from` over record `to`.
    #[inline]
    pub fn copy(&mut self, from: usize, to: usize) {
        self.pos[to] = self.pos[from];
        self.vel[to] = self.vel[from];
        self.ids[to] = self.ids[from];
        if self.collision_times {
            self.last[to] = self.last[from];
        }
    }

    /// Shortens or lengthens to `n` grains (new records: identity 0 at the origin, at
    /// rest; to be overwritten).
    pub fn resize(&mut self, n: usize) {
        let tc = self.has_collision_times();
        self.pos.resize(n, Vector::zero());
        self.vel.resize(n, Vector::zero());
        self.ids.resize(n, 0);
        if tc {
            self.last.resize(n, f64::NEG_INFINITY);
        }
    }

    /// Keeps the first `n` grains.
    pub fn truncate(&mut self, n: usize) {
        self.pos.truncate(n);
        self.vel.truncate(n);
        self.ids.truncate(n);
        self.last.truncate(n);
    }

    /// A copy of the records `r`.
    pub fn range(&self, r: Range<usize>) -> Grains<D> {
        let tc = self.has_collision_times();
        Grains {
            pos: self.pos[r.clone()].to_vec(),
            vel: self.vel[r.clone()].to_vec(),
            ids: self.ids[r.clone()].to_vec(),
            last: if tc {
                self.last[r].to_vec()
            } else {
                Vec::new()
            },
            collision_times: tc,
        }
    }

    /// Appends copies of `other`'s records `r` (both with or both without collision
    /// times).
    pub fn extend_from(&mut self, other: &Grains<D>, r: Range<usize>) {
        self.pos.extend_from_slice(&other.pos[r.clone()]);
        self.vel.extend_from_slice(&other.vel[r.clone()]);
        self.ids.extend_from_slice(&other.ids[r.clone()]);
        if self.has_collision_times() {
            self.last.extend_from_slice(&other.last[r]);
        }
    }

    /// Whether the arrays have one length (a store read from a file that fails this was
    /// not written by this engine).
    pub fn consistent(&self) -> bool {
        let n = self.ids.len();
        self.pos.len() == n
            && self.vel.len() == n
            && self.last.len() == if self.collision_times { n } else { 0 }
    }
}
