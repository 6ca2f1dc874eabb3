//! A calendar queue (Paul, J. Comput. Phys. 221, 615 (2007)) holding
//! exactly one entry per particle (the earliest event predicted for it), keyed by event
//! time.
//!
//! Time is cut into buckets of equal width. Events of the current bucket sit in a small
//! binary heap (a few entries), events of the next `nb - 1` buckets in unsorted doubly
//! linked lists, one per bucket, and later events in an overflow list that is sorted
//! into buckets once per turn of the calendar. Insertion and removal are O(1); the
//! minimum is the top of the small heap. A binary heap over all N particles costs
//! `log2 N` cache misses per update at N = 10^6; this costs about two.
//!
//! Hand-written rather than taken from a crate because it is the core of the engine's
//! speed and needs decrease/increase-key on particle indices, which no general-purpose
//! priority queue offers.
//!
//! The bucket width adapts to the dynamics: [`CalendarQueue::rebuild`] (called by the engine
//! every few collisions per particle) sets it from the mean time to the pending events.

use super::LOOK_AHEAD_MIN_GRAINS;
use crate::prefetch::prefetch_all;
use serde::{Deserialize, Serialize};

/// `prev` of a particle whose entry is in the current-bucket heap (`next` then holds its
/// heap position).
const IN_HEAP: u32 = u32::MAX;
/// `prev` of a particle with no finite event (key `+inf`): it is in no list.
const PARKED: u32 = u32::MAX - 1;

/// Buckets per particle (rounded up to a power of two). The engine uses the calendar
/// from [`super::TOURNAMENT_MAX_GRAINS`] on, where more buckets than this measured 4-8 %
/// slower (2D 10^6, 3D 10^5); with everything in cache (10^4 grains) N/2 buckets had run
/// 3-5 % faster (`docs/performance.md`).
const BUCKETS_PER_PARTICLE: f64 = 0.25;

/// Calendar queue over particle indices `0..n`, ordered by `keys[i]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct CalendarQueue {
    /// Event time of each particle (`+inf`: none).
    keys: Vec<f64>,
    /// The lists' forward links: `next[i]` for particle `i < n`, then the first element
    /// of each bucket's list (`n..n + nb`) and of the overflow list (`n + nb`); `n` ends
    /// a list. A bucket costs these 4 bytes only (no sentinel with its own back link).
    next: Vec<u32>,
    /// The back links of particles `0..n`: the element before, or the index in `next`
    /// of the list's head; `prev[n]` is a scratch slot that the end of a list writes.
    prev: Vec<u32>,
    /// Particles of the current bucket, a binary min-heap by key.
    heap: Vec<u32>,
    n: usize,
    /// Number of buckets (a power of two: slots are taken by a mask, [`Self::slot_of`]).
    nb: usize,
    width: f64,
    inv_width: f64,
    /// Time of the start of bucket 0.
    origin: f64,
    /// Absolute index of the current bucket.
    current: i64,
    /// Particles in bucket lists or in the overflow list.
    linked: usize,
    /// Look-ahead cursor in the next bucket's list (a hint only: see [`CalendarQueue::min`]).
    #[serde(skip)]
    ahead: u32,
}

impl CalendarQueue {
    /// A queue of `n` particles, all with key `+inf`.
    pub(crate) fn new(n: usize) -> Self {
        let nb = ((n as f64 * BUCKETS_PER_PARTICLE) as usize)
            .next_power_of_two()
            .max(16);
        let mut q = Self {
            keys: vec![f64::INFINITY; n],
            next: vec![0; n + nb + 1],
            prev: vec![PARKED; n + 1],
            heap: Vec::new(),
            n,
            nb,
            width: 1.0,
            inv_width: 1.0,
            origin: 0.0,
            current: 0,
            linked: 0,
            ahead: u32::MAX,
        };
        q.reset_lists();
        q
    }

    /// The index that ends a list.
    #[inline(always)]
    fn end(&self) -> usize {
        self.n
    }

    fn reset_lists(&mut self) {
        let end = self.end() as u32;
        for h in self.n..self.n + self.nb + 1 {
            self.next[h] = end;
        }
        for i in 0..self.n {
            self.prev[i] = PARKED;
        }
        // The heap holds a few entries; drop any capacity left from a transient.
        self.heap = Vec::with_capacity(64);
        self.linked = 0;
    }

    /// Number of particles.
    pub(crate) fn len(&self) -> usize {
        self.n
    }

    /// The particle with the earliest finite event and its time (`None`: none is finite).
    #[inline]
    pub(crate) fn min(&mut self) -> Option<(usize, f64)> {
        let mut scanned = 0;
        loop {
            if let Some(&top) = self.heap.first() {
                if self.n >= LOOK_AHEAD_MIN_GRAINS {
                    self.look_ahead();
                }
                return Some((top as usize, self.keys[top as usize]));
            }
            if self.linked == 0 {
                return None;
            }
            if scanned >= self.nb {
                // A whole turn of empty buckets: every event is in the overflow list.
                // Jump to the earliest.
                let mut earliest = i64::MAX;
                let mut i = self.next[self.n + self.nb] as usize;
                while i != self.end() {
                    earliest = earliest.min(self.bucket_of(self.keys[i]));
                    i = self.next[i] as usize;
                }
                if earliest == i64::MAX {
                    // The overflow list is empty: the turn's last bucket was slot 0, whose
                    // sorting of the overflow moved its events into the buckets ahead.
                    scanned = 0;
                    continue;
                }
                self.current = earliest - 1;
                self.sort_overflow();
                scanned = 0;
                continue;
            }
            self.current += 1;
            scanned += 1;
            let slot = self.slot_of(self.current);
            if slot == 0 {
                self.sort_overflow();
            }
            let head = self.n + slot;
            let mut i = self.next[head] as usize;
            while i != self.end() {
                let after = self.next[i] as usize;
                self.linked -= 1;
                self.heap_push(i);
                i = after;
            }
            self.next[head] = self.end() as u32;
            if self.n >= LOOK_AHEAD_MIN_GRAINS {
                let following = self.n + self.slot_of(self.current + 1);
                self.ahead = self.next[following];
                self.prefetch_entry(self.ahead);
            }
        }
    }

    /// The particle the look-ahead cursor is at: one whose event comes up soon (its
    /// bucket is next), whose records the engine may start loading.
    #[inline(always)]
    pub(crate) fn ahead(&self) -> Option<usize> {
        let i = self.ahead as usize;
        (i < self.n).then_some(i)
    }

    /// One step of the look-ahead walk through the next bucket's list: the link prefetched
    /// at the previous step is followed and the next one prefetched, with the element's
    /// key. When the bucket becomes current, moving it into the heap then finds its links
    /// and keys in cache instead of meeting one dependent cache miss per element (at 10^6
    /// grains that walk was most of the queue's minimum). The cursor is only a hint: the
    /// list may change under it (an element removed or moved to the heap leads it astray),
    /// which costs a useless prefetch, never a wrong result.
    #[inline(always)]
    fn look_ahead(&mut self) {
        let i = self.ahead as usize;
        if i < self.n {
            let next = self.next[i];
            self.ahead = next;
            self.prefetch_entry(next);
        }
    }

    /// Starts loading both list links of particle `i` (a hint), which its next update
    /// reads to unlink it.
    #[inline(always)]
    pub(crate) fn prefetch_links(&self, i: u32) {
        prefetch_all(&self.next, &[i]);
        prefetch_all(&self.prev, &[i]);
    }

    /// Starts loading the list link and key of entry `i` (a hint; any index is harmless).
    #[inline(always)]
    fn prefetch_entry(&self, i: u32) {
        prefetch_all(&self.next, &[i]);
        prefetch_all(&self.keys, &[i]);
    }

    /// The key of particle `i` (tests compare the queues through it).
    #[cfg(test)]
    pub(crate) fn key(&self, i: usize) -> f64 {
        self.keys[i]
    }

    /// Sets the key of particle `i`.
    #[inline]
    pub(crate) fn update(&mut self, i: usize, key: f64) {
        self.remove(i);
        self.keys[i] = key;
        self.insert(i);
    }

    /// Subtracts `dt` from every key (time-origin shift) and rebuilds the calendar at the
    /// shifted current time `now`.
    pub(crate) fn shift(&mut self, dt: f64, now: f64) {
        for k in &mut self.keys {
            *k -= dt;
        }
        self.rebuild(now);
    }

    /// Re-sorts every particle with the bucket width adapted to the pending events: the
    /// calendar spans four times their mean distance from `now`, so that few fall in the
    /// overflow list.
    pub(crate) fn rebuild(&mut self, now: f64) {
        let (mut sum, mut count) = (0.0, 0usize);
        for &k in &self.keys {
            if k.is_finite() {
                sum += (k - now).max(0.0);
                count += 1;
            }
        }
        let mean = if count > 0 { sum / count as f64 } else { 0.0 };
        self.width = if mean > 0.0 && mean.is_finite() {
            4.0 * mean / self.nb as f64
        } else {
            1.0
        };
        self.inv_width = 1.0 / self.width;
        self.origin = now;
        self.current = 0;
        self.reset_lists();
        for i in 0..self.n {
            self.insert(i);
        }
    }

    /// Relabels the particles: particle `i` becomes `new_of_old[i]`; rebuilds the
    /// calendar at the current time `now`.
    pub(crate) fn relabel(&mut self, new_of_old: &[u32], now: f64) {
        self.keys = super::permuted(&self.keys, new_of_old);
        self.rebuild(now);
    }

    /// Heap memory in bytes.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.keys.capacity() * 8
            + (self.next.capacity() + self.prev.capacity() + self.heap.capacity()) * 4
    }

    #[inline(always)]
    fn bucket_of(&self, t: f64) -> i64 {
        let x = (t - self.origin) * self.inv_width;
        // `as` truncates towards zero (and saturates), which is the floor for x >= 0;
        // it avoids a libm call on targets without a rounding instruction.
        if x >= 0.0 { x as i64 } else { x.floor() as i64 }
    }

    /// The calendar slot of absolute bucket `b`: `b mod nb`, by a mask (`nb` is a power
    /// of two; a 64-bit division costs tens of cycles on every update).
    #[inline(always)]
    fn slot_of(&self, b: i64) -> usize {
        debug_assert!(self.nb.is_power_of_two());
        (b as u64 & (self.nb as u64 - 1)) as usize
    }

    #[inline(always)]
    fn insert(&mut self, i: usize) {
        let t = self.keys[i];
        if !t.is_finite() {
            self.prev[i] = PARKED;
            return;
        }
        let b = self.bucket_of(t);
        if b <= self.current {
            self.heap_push(i);
        } else if b < self.current + self.nb as i64 {
            self.linked += 1;
            self.link(self.n + self.slot_of(b), i);
        } else {
            self.linked += 1;
            self.link(self.n + self.nb, i);
        }
    }

    #[inline(always)]
    fn remove(&mut self, i: usize) {
        match self.prev[i] {
            PARKED => {}
            IN_HEAP => self.heap_remove(self.next[i] as usize),
            p => {
                let n = self.next[i];
                self.next[p as usize] = n;
                self.prev[n as usize] = p;
                self.linked -= 1;
                self.prev[i] = PARKED;
            }
        }
    }

    /// Moves the overflow events that now fall within the calendar into their buckets.
    fn sort_overflow(&mut self) {
        let head = self.n + self.nb;
        let mut i = self.next[head] as usize;
        self.next[head] = self.end() as u32;
        while i != self.end() {
            let after = self.next[i] as usize;
            self.linked -= 1;
            self.insert(i);
            i = after;
        }
    }

    /// Puts particle `i` first in the list whose head is `next[head]`.
    #[inline(always)]
    fn link(&mut self, head: usize, i: usize) {
        let first = self.next[head];
        self.next[i] = first;
        self.prev[i] = head as u32;
        // At the end of a list, `first` is `n`: the scratch slot.
        self.prev[first as usize] = i as u32;
        self.next[head] = i as u32;
    }

    #[inline(always)]
    fn heap_push(&mut self, i: usize) {
        self.prev[i] = IN_HEAP;
        self.heap.push(i as u32);
        self.sift_up(self.heap.len() - 1);
    }

    #[inline(always)]
    fn heap_remove(&mut self, pos: usize) {
        let item = self.heap[pos] as usize;
        self.prev[item] = PARKED;
        let last = self.heap.pop().unwrap_or(0);
        if pos < self.heap.len() {
            self.heap[pos] = last;
            self.next[last as usize] = pos as u32;
            let pos = self.sift_up(pos);
            self.sift_down(pos);
        }
    }

    #[inline(always)]
    fn less(&self, a: u32, b: u32) -> bool {
        // Ties broken by index, so that the order never depends on the heap's history.
        let (ka, kb) = (self.keys[a as usize], self.keys[b as usize]);
        ka < kb || (ka == kb && a < b)
    }

    #[inline(always)]
    fn sift_up(&mut self, mut pos: usize) -> usize {
        let item = self.heap[pos];
        while pos > 0 {
            let parent = (pos - 1) / 2;
            let p = self.heap[parent];
            if !self.less(item, p) {
                break;
            }
            self.heap[pos] = p;
            self.next[p as usize] = pos as u32;
            pos = parent;
        }
        self.heap[pos] = item;
        self.next[item as usize] = pos as u32;
        pos
    }

    #[inline(always)]
    fn sift_down(&mut self, mut pos: usize) {
        let n = self.heap.len();
        let item = self.heap[pos];
        loop {
            let left = 2 * pos + 1;
            if left >= n {
                break;
            }
            let right = left + 1;
            let mut child = left;
            if right < n && self.less(self.heap[right], self.heap[left]) {
                child = right;
            }
            let c = self.heap[child];
            if !self.less(c, item) {
                break;
            }
            self.heap[pos] = c;
            self.next[c as usize] = pos as u32;
            pos = child;
        }
        self.heap[pos] = item;
        self.next[item as usize] = pos as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    /// An event beyond the calendar, alone in the queue, is found, also when the turn
    /// that reaches it moves it from the overflow list into a bucket at its last step;
    /// and the calendar stays at its time, so that an earlier event added then comes
    /// first.
    #[test]
    fn finds_a_lone_event_beyond_the_calendar() {
        for n in [2, 64, 257] {
            let mut q = CalendarQueue::new(n);
            let span = q.nb as f64 * q.width;
            for key in [0.5 * span, 1.27 * span, 1.5 * span, 2.0 * span, 37.3 * span] {
                q.rebuild(0.0);
                q.update(0, key);
                assert_eq!(q.min(), Some((0, key)), "n = {n}, key = {key}");
                let earlier = key * 0.999;
                q.update(n - 1, earlier);
                assert_eq!(q.min(), Some((n - 1, earlier)), "n = {n}, key = {key}");
                q.update(0, f64::INFINITY);
                q.update(n - 1, f64::INFINITY);
                assert_eq!(q.min(), None);
            }
        }
    }

    /// Random updates (earlier, later, infinite keys) interleaved with processing the
    /// minimum and moving time forward, as the engine does, checked against a brute-force
    /// minimum.
    #[test]
    fn always_returns_the_minimum() {
        let mut rng = stream(3, &[0]);
        let n = 257;
        let mut q = CalendarQueue::new(n);
        let mut keys = vec![f64::INFINITY; n];
        let mut now = 0.0;
        for step in 0..50_000 {
            let i = rng.random_range(0..n);
            let k = match step % 11 {
                0 => f64::INFINITY,
                // Far future: overflow list.
                1 => now + 1e3 * rng.random::<f64>(),
                _ => now + rng.random::<f64>() * rng.random::<f64>() * 3.0,
            };
            q.update(i, k);
            keys[i] = k;
            if step % 3 == 0
                && let Some((m, km)) = q.min()
            {
                // Process the minimum: time moves to it, the particle gets a later event.
                now = km;
                let next = now + rng.random::<f64>();
                q.update(m, next);
                keys[m] = next;
            }
            if step % 5000 == 0 {
                q.rebuild(now);
            }
            let best = keys.iter().cloned().fold(f64::INFINITY, f64::min);
            match q.min() {
                Some((m, km)) => {
                    assert_eq!(km, best, "step {step}");
                    assert_eq!(keys[m], best);
                }
                None => assert!(best.is_infinite()),
            }
        }
    }
}
