//! The event queue: an indexed binary min-heap holding exactly one entry per particle (the
//! earliest event predicted for it), keyed by event time.
//!
//! Hand-written rather than taken from a crate because it is the core of the engine's
//! speed: with one entry per particle the heap never grows, an update is a sift in place
//! (no allocation, no stale entries piling up), and the positions array gives O(log N)
//! decrease/increase-key, which `std::collections::BinaryHeap` cannot do.

use serde::{Deserialize, Serialize};

/// Indexed min-heap over particle indices `0..n`, ordered by `keys[i]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EventQueue {
    heap: Vec<u32>,
    slot: Vec<u32>,
    keys: Vec<f64>,
}

impl EventQueue {
    /// A queue of `n` particles, all with key `+inf`.
    pub fn new(n: usize) -> Self {
        Self {
            heap: (0..n as u32).collect(),
            slot: (0..n as u32).collect(),
            keys: vec![f64::INFINITY; n],
        }
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// Whether the queue is empty.
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }

    /// The particle with the earliest event and its time.
    #[inline(always)]
    pub fn min(&self) -> Option<(usize, f64)> {
        self.heap
            .first()
            .map(|&i| (i as usize, self.keys[i as usize]))
    }

    /// The key of particle `i`.
    #[inline(always)]
    pub fn key(&self, i: usize) -> f64 {
        self.keys[i]
    }

    /// Sets the key of particle `i` and restores the heap order.
    #[inline]
    pub fn update(&mut self, i: usize, key: f64) {
        let old = self.keys[i];
        self.keys[i] = key;
        let pos = self.slot[i] as usize;
        if key < old {
            self.sift_up(pos);
        } else {
            self.sift_down(pos);
        }
    }

    /// Subtracts `dt` from every key (time-origin shift; the order is preserved up to ties).
    pub fn shift(&mut self, dt: f64) {
        for k in &mut self.keys {
            *k -= dt;
        }
    }

    #[inline(always)]
    fn sift_up(&mut self, mut pos: usize) {
        let item = self.heap[pos];
        let key = self.keys[item as usize];
        while pos > 0 {
            let parent = (pos - 1) / 2;
            let p = self.heap[parent];
            if self.keys[p as usize] <= key {
                break;
            }
            self.heap[pos] = p;
            self.slot[p as usize] = pos as u32;
            pos = parent;
        }
        self.heap[pos] = item;
        self.slot[item as usize] = pos as u32;
    }

    #[inline(always)]
    fn sift_down(&mut self, mut pos: usize) {
        let n = self.heap.len();
        let item = self.heap[pos];
        let key = self.keys[item as usize];
        loop {
            let left = 2 * pos + 1;
            if left >= n {
                break;
            }
            let right = left + 1;
            let mut child = left;
            if right < n
                && self.keys[self.heap[right] as usize] < self.keys[self.heap[left] as usize]
            {
                child = right;
            }
            let c = self.heap[child];
            if self.keys[c as usize] >= key {
                break;
            }
            self.heap[pos] = c;
            self.slot[c as usize] = pos as u32;
            pos = child;
        }
        self.heap[pos] = item;
        self.slot[item as usize] = pos as u32;
    }

    /// Relabels the particles: particle `i` becomes `new_of_old[i]` (the heap order is
    /// unchanged, since the keys are).
    pub fn relabel(&mut self, new_of_old: &[u32]) {
        let n = self.keys.len();
        let mut keys = vec![0.0; n];
        let mut slot = vec![0u32; n];
        for (i, &j) in new_of_old.iter().enumerate() {
            keys[j as usize] = self.keys[i];
            slot[j as usize] = self.slot[i];
        }
        for h in &mut self.heap {
            *h = new_of_old[*h as usize];
        }
        self.keys = keys;
        self.slot = slot;
    }

    /// Heap memory in bytes.
    pub fn memory_bytes(&self) -> usize {
        self.heap.capacity() * 4 + self.slot.capacity() * 4 + self.keys.capacity() * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    #[test]
    fn always_returns_the_minimum() {
        let mut rng = stream(3, &[0]);
        let n = 257;
        let mut q = EventQueue::new(n);
        let mut keys = vec![f64::INFINITY; n];
        for step in 0..20_000 {
            let i = rng.random_range(0..n);
            let k = if step % 7 == 0 {
                f64::INFINITY
            } else {
                rng.random::<f64>()
            };
            q.update(i, k);
            keys[i] = k;
            let (m, km) = q.min().unwrap();
            let best = keys.iter().cloned().fold(f64::INFINITY, f64::min);
            assert_eq!(km, best);
            assert_eq!(keys[m], best);
        }
    }
}
