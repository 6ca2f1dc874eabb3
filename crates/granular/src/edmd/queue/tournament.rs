//! A tournament tree (a complete binary tree of winners) over particle indices `0..n`,
//! ordered by `(key, index)`.
//!
//! The tree has `L` leaves, `n` rounded up to a power of two, all at one depth: leaf
//! node `L + i` is particle `i` (a sentinel at `+inf` beyond the last particle), and inner
//! node `k` of `1..L` holds the winner of its subtree, the particle with the least key
//! below it, ties to the lower index. The minimum is the root's winner (node 1); an
//! update replays the `log2 L` matches on the path from the particle's leaf to the root,
//! each an integer comparison and two selects without a branch, and the two grains of a
//! pair collision climb side by side up to the node where their paths meet
//! ([`TournamentQueue::update_pair`]).
//!
//! While the tree stays in cache this is cheaper than the calendar
//! ([`super::CalendarQueue`]): no bucket lists to unlink and link with their dependent
//! loads, and no small heap to sift, whose comparisons are coin tosses for the branch
//! predictor (the largest source of mispredictions in the calendar). It needs 8 bytes
//! per particle for the key and 4-8 for the winners, where the calendar needs 17-18.
//!
//! Hand-written for the same reason as the calendar: it is the core of the engine's
//! speed, and it needs decrease/increase-key on particle indices.

use serde::{Deserialize, Serialize};

/// Tournament tree over particle indices `0..n`, ordered by `(key, index)`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct TournamentQueue {
    /// Event time of each particle as an [`ordered`] integer (`+inf`: none), and at index
    /// `n` a sentinel at `+inf` that fills the leaves beyond the last particle.
    keys: Vec<u64>,
    /// `winner[k]` for node `k` in `1..leaves`: the particle of least `(key, index)`
    /// below node `k` (`winner[0]` is unused).
    winner: Vec<u32>,
    /// Number of leaves: `n` rounded up to a power of two. Leaf `leaves + i` is particle
    /// `i` (the sentinel `n` for `i >= n`).
    leaves: usize,
}

impl TournamentQueue {
    /// A queue of `n` particles, all with key `+inf`.
    pub(crate) fn new(n: usize) -> Self {
        let leaves = n.next_power_of_two();
        let mut q = Self {
            keys: vec![ordered(f64::INFINITY); n + 1],
            winner: vec![0; leaves],
            leaves,
        };
        q.replay_all();
        q
    }

    /// Number of particles.
    pub(crate) fn len(&self) -> usize {
        self.keys.len() - 1
    }

    /// Whether the queue holds no particles.
    pub(crate) fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The winner of node `k` (`1 <= k < 2 leaves`).
    #[inline(always)]
    fn winner_of(&self, k: usize) -> u32 {
        if k >= self.leaves {
            (k - self.leaves).min(self.len()) as u32
        } else {
            self.winner[k]
        }
    }

    /// The better of two particles: the lesser key, ties to the lower index.
    #[inline(always)]
    fn better(&self, a: u32, b: u32) -> u32 {
        play(a, self.keys[a as usize], b, self.keys[b as usize]).0
    }

    /// Recomputes every node's winner from the leaves up.
    fn replay_all(&mut self) {
        for k in (1..self.leaves).rev() {
            self.winner[k] = self.better(self.winner_of(2 * k), self.winner_of(2 * k + 1));
        }
    }

    /// The particle with the earliest finite event and its time (`None`: none is finite).
    #[inline(always)]
    pub(crate) fn min(&self) -> Option<(usize, f64)> {
        if self.is_empty() {
            return None;
        }
        let w = self.winner_of(1) as usize;
        let k = from_ordered(self.keys[w]);
        k.is_finite().then_some((w, k))
    }

    /// The key of particle `i` (tests compare the queues through it).
    #[cfg(test)]
    pub(crate) fn key(&self, i: usize) -> f64 {
        from_ordered(self.keys[i])
    }

    /// Sets the key of particle `i` and replays the matches on its path to the root.
    #[inline]
    pub(crate) fn update(&mut self, i: usize, key: f64) {
        let n = self.len();
        assert!(i < n, "particle {i} beyond the queue's {n}");
        let rank = ordered(key);
        self.keys[i] = rank;
        if self.leaves >= 2 {
            let (w, rw) = self.leaf_match(i, rank);
            self.climb((self.leaves + i) >> 1, w, rw);
        }
    }

    /// Sets the keys of two particles `i != j` (the grains of a pair collision) and
    /// replays the matches on both paths: side by side up to the node where they meet,
    /// so that the two chains of matches overlap in the processor, then once.
    #[inline]
    pub(crate) fn update_pair(&mut self, i: usize, key_i: f64, j: usize, key_j: f64) {
        let n = self.len();
        assert!(
            i < n && j < n && i != j,
            "pair ({i}, {j}) in a queue of {n}"
        );
        let (rank_i, rank_j) = (ordered(key_i), ordered(key_j));
        self.keys[i] = rank_i;
        self.keys[j] = rank_j;
        // Both keys are stored before the first matches, so that each sees the other's
        // new key when they are neighbours.
        let (mut wi, mut ri) = self.leaf_match(i, rank_i);
        let (mut wj, mut rj) = self.leaf_match(j, rank_j);
        let mask = self.leaves - 1;
        let winner = &mut self.winner[..=mask];
        let (mut ni, mut nj) = ((self.leaves + i) >> 1, (self.leaves + j) >> 1);
        // All leaves are at one depth, so the two paths climb in step and meet at their
        // lowest common ancestor; below it each node is on one path only.
        while ni != nj {
            winner[ni & mask] = wi;
            winner[nj & mask] = wj;
            // A sibling on the other path was stored just above.
            let (si, sj) = (winner[(ni ^ 1) & mask], winner[(nj ^ 1) & mask]);
            let (rsi, rsj) = (self.keys[si as usize], self.keys[sj as usize]);
            (wi, ri) = play(wi, ri, si, rsi);
            (wj, rj) = play(wj, rj, sj, rsj);
            ni >>= 1;
            nj >>= 1;
        }
        debug_assert_eq!(wi, wj);
        self.climb(ni, wi, ri);
    }

    /// The first match of particle `i` (of rank `rank`): against its neighbouring leaf,
    /// the sentinel beyond the last particle included. Returns the winner and its rank.
    #[inline(always)]
    fn leaf_match(&self, i: usize, rank: u64) -> (u32, u64) {
        let s = (i ^ 1).min(self.len()) as u32;
        play(i as u32, rank, s, self.keys[s as usize])
    }

    /// Stores `w` (of rank `rw`) as the winner of inner node `node` and replays the
    /// matches above it, up to the root.
    #[inline(always)]
    fn climb(&mut self, mut node: usize, mut w: u32, mut rw: u64) {
        let mask = self.leaves - 1;
        // Indices masked by `leaves - 1` need no bounds check in this slice.
        let winner = &mut self.winner[..=mask];
        winner[node & mask] = w;
        while node > 1 {
            let s = winner[(node ^ 1) & mask];
            (w, rw) = play(w, rw, s, self.keys[s as usize]);
            node >>= 1;
            winner[node & mask] = w;
        }
    }

    /// Subtracts `dt` from every key (time-origin shift). The order by `(key, index)` is
    /// recomputed, as two keys may round to the same value.
    pub(crate) fn shift(&mut self, dt: f64) {
        let n = self.len();
        for k in &mut self.keys[..n] {
            *k = ordered(from_ordered(*k) - dt);
        }
        self.replay_all();
    }

    /// Relabels the particles: particle `i` becomes `new_of_old[i]`.
    pub(crate) fn relabel(&mut self, new_of_old: &[u32]) {
        let n = self.len();
        // Copied back into the same buffer: a fresh vector of `n` with the sentinel
        // pushed would double its capacity (8 bytes per particle more).
        let keys = super::permuted(&self.keys[..n], new_of_old);
        self.keys[..n].copy_from_slice(&keys);
        self.replay_all();
    }

    /// Heap memory in bytes.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.keys.capacity() * 8 + self.winner.capacity() * 4
    }
}

/// The bits of `key` as an unsigned integer of the same order (negative keys reversed
/// and below the positive ones; `-0` counts as `+0`, as in floating-point comparison), so
/// that a match compares integers: the compiler turns a floating-point comparison with
/// ties into branches, and these are coin tosses for the branch predictor.
#[inline(always)]
fn ordered(key: f64) -> u64 {
    let bits = (key + 0.0).to_bits();
    bits ^ (((bits as i64 >> 63) as u64) | (1 << 63))
}

/// The inverse of [`ordered`].
#[inline(always)]
fn from_ordered(rank: u64) -> f64 {
    f64::from_bits(rank ^ ((((!rank) as i64 >> 63) as u64) | (1 << 63)))
}

/// One match: the winner of particle `w` (of rank `rw`) against `s` (of rank `rs`), and
/// its rank, by selects (no branch).
#[inline(always)]
fn play(w: u32, rw: u64, s: u32, rs: u64) -> (u32, u64) {
    let s_first = first(rs, s, rw, w);
    (
        std::hint::select_unpredictable(s_first, s, w),
        std::hint::select_unpredictable(s_first, rs, rw),
    )
}

/// Whether `(ka, a)` comes before `(kb, b)`, without a branch.
#[inline(always)]
fn first(ka: u64, a: u32, kb: u64, b: u32) -> bool {
    // `ka < kb || (ka == kb && a < b)` in a shorter chain of dependent instructions: an
    // add with carry and a comparison (which would wrap only at `kb == u64::MAX`, the
    // rank of a NaN with every bit set, which no event time is).
    ka < kb.wrapping_add((a < b) as u64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    /// The earliest `(key, index)` by brute force.
    fn brute_min(keys: &[f64]) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, &k) in keys.iter().enumerate() {
            if k.is_finite() && best.is_none_or(|(_, b)| k < b) {
                best = Some((i, k));
            }
        }
        best
    }

    /// A key on a coarse grid (ties are frequent), or `+inf`.
    fn draw(rng: &mut impl RngExt) -> f64 {
        match rng.random_range(0..8) {
            0 => f64::INFINITY,
            _ => rng.random_range(0..16) as f64 * 0.25,
        }
    }

    #[test]
    fn ordered_keys_keep_the_order_of_times() {
        let times = [
            f64::NEG_INFINITY,
            -1e300,
            -2.5,
            -1e-300,
            0.0,
            1e-310,
            1e-300,
            0.5,
            1.0,
            3.0,
            1e300,
            f64::INFINITY,
        ];
        for (a, &ta) in times.iter().enumerate() {
            assert_eq!(from_ordered(ordered(ta)), ta);
            for &tb in &times[a + 1..] {
                assert!(ordered(ta) < ordered(tb), "{ta} < {tb}");
            }
        }
        assert_eq!(ordered(-0.0), ordered(0.0));
        for (a, b) in [(1u32, 2u32), (2, 1), (7, 300)] {
            for (ka, kb) in [(1.0, 2.0), (2.0, 1.0), (1.5, 1.5)] {
                let expected = ka < kb || (ka == kb && a < b);
                assert_eq!(first(ordered(ka), a, ordered(kb), b), expected);
            }
        }
    }

    /// Random updates of one or two particles (with many equal keys, so that ties to
    /// the lower index are exercised), shifts and relabellings, checked against a
    /// brute-force minimum, for sizes with and without a sentinel leaf.
    #[test]
    fn always_returns_the_earliest_and_lowest() {
        let mut rng = stream(5, &[0]);
        for n in [1, 2, 3, 5, 8, 100, 257] {
            let mut q = TournamentQueue::new(n);
            let mut keys = vec![f64::INFINITY; n];
            assert_eq!(q.min(), None);
            for step in 0..20_000 {
                let i = rng.random_range(0..n);
                if n > 1 && step % 2 == 0 {
                    let j = (i + rng.random_range(1..n)) % n;
                    let (ki, kj) = (draw(&mut rng), draw(&mut rng));
                    q.update_pair(i, ki, j, kj);
                    keys[i] = ki;
                    keys[j] = kj;
                } else {
                    let k = draw(&mut rng);
                    q.update(i, k);
                    keys[i] = k;
                }
                if step % 1000 == 999 {
                    q.shift(0.25);
                    keys.iter_mut().for_each(|k| *k -= 0.25);
                    let mut new_of_old: Vec<u32> = (0..n as u32).collect();
                    new_of_old.rotate_left(n / 3);
                    q.relabel(&new_of_old);
                    let mut relabelled = keys.clone();
                    for (i, &j) in new_of_old.iter().enumerate() {
                        relabelled[j as usize] = keys[i];
                    }
                    keys = relabelled;
                }
                assert_eq!(q.min(), brute_min(&keys), "n = {n}, step {step}");
            }
            for (i, &k) in keys.iter().enumerate() {
                assert_eq!(q.key(i), k);
            }
        }
    }
}
