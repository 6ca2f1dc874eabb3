//! The event queue: one entry per particle (the earliest event predicted for it), keyed
//! by event time, ordered by `(time, particle index)` so that the order of events never
//! depends on the queue's history or kind.
//!
//! Two structures, chosen by the number of particles ([`EventQueue::new`]), give the
//! same order and hence the same trajectory:
//! * [`CalendarQueue`] (Paul, J. Comput. Phys. 221, 615 (2007)): O(1) insertion and
//!   removal in buckets of time, about two cache misses per update at any N;
//! * [`TournamentQueue`]: a binary tree of winners, `log2 N` branch-free matches per
//!   update and the minimum at its root; faster while the tree stays in cache.

mod calendar;
mod tournament;

pub(crate) use calendar::CalendarQueue;
use serde::{Deserialize, Serialize};
pub(crate) use tournament::TournamentQueue;

/// Grains from which the engine uses the calendar queue. Below, the tournament tree (at
/// most 800 kB) stays in the second-level cache of the machine we measured on, and in one
/// process it ran faster than the calendar by 8-18 % at 2D 10^3-6 x 10^4 grains (φ = 0.2
/// and 0.7), 4 % at 2D 8 x 10^4 and 2 % at 3D 10^4-3 x 10^4; at 2D 10^5 it was level or
/// up to 3.5 % slower, at 3D 6 x 10^4 1 % and at 3D 10^5 6 % slower (there the calendar's
/// look-ahead pays).
pub const TOURNAMENT_MAX_GRAINS: usize = 1 << 16;

/// Grains from which the calendar queue (and the engine) look ahead at the events to
/// come and prefetch what they will read (`EventQueue::ahead`). Below it everything
/// fits in the processor's second-level cache and the look-ahead measured 3 % slower
/// (2D, 10^4 grains); above it, 8-29 % faster (2D and 3D, 10^5 and 10^6 grains).
pub const LOOK_AHEAD_MIN_GRAINS: usize = 1 << 15;

/// `values` relabelled: the value of particle `i` goes to `new_of_old[i]`.
fn permuted<T: Copy + Default>(values: &[T], new_of_old: &[u32]) -> Vec<T> {
    let mut out = vec![T::default(); values.len()];
    for (&v, &j) in values.iter().zip(new_of_old) {
        out[j as usize] = v;
    }
    out
}

/// The engine's event queue: a tournament tree below [`TOURNAMENT_MAX_GRAINS`]
/// particles, a calendar queue from there on. Both order events by `(time, particle)`,
/// so the choice never changes a trajectory.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) enum EventQueue {
    /// From [`TOURNAMENT_MAX_GRAINS`] particles on.
    Calendar(CalendarQueue),
    /// Below [`TOURNAMENT_MAX_GRAINS`] particles.
    Tournament(TournamentQueue),
}

impl EventQueue {
    /// A queue of `n` particles, all with key `+inf`.
    pub(crate) fn new(n: usize) -> Self {
        if n < TOURNAMENT_MAX_GRAINS {
            Self::Tournament(TournamentQueue::new(n))
        } else {
            Self::Calendar(CalendarQueue::new(n))
        }
    }

    /// The particle with the earliest finite event and its time (`None`: none is finite).
    #[inline(always)]
    pub(crate) fn min(&mut self) -> Option<(usize, f64)> {
        match self {
            Self::Calendar(q) => q.min(),
            Self::Tournament(q) => q.min(),
        }
    }

    /// The key of particle `i` (tests compare the queues through it).
    #[cfg(test)]
    pub(crate) fn key(&self, i: usize) -> f64 {
        match self {
            Self::Calendar(q) => q.key(i),
            Self::Tournament(q) => q.key(i),
        }
    }

    /// Sets the key of particle `i`.
    #[inline(always)]
    pub(crate) fn update(&mut self, i: usize, key: f64) {
        match self {
            Self::Calendar(q) => q.update(i, key),
            Self::Tournament(q) => q.update(i, key),
        }
    }

    /// Sets the keys of two particles `i != j` (the grains of a pair collision).
    #[inline(always)]
    pub(crate) fn update_pair(&mut self, i: usize, key_i: f64, j: usize, key_j: f64) {
        match self {
            Self::Calendar(q) => {
                q.update(i, key_i);
                q.update(j, key_j);
            }
            Self::Tournament(q) => q.update_pair(i, key_i, j, key_j),
        }
    }

    /// Whether [`EventQueue::ahead`] looks ahead (a calendar of at least
    /// [`LOOK_AHEAD_MIN_GRAINS`] particles).
    pub(crate) fn looks_ahead(&self) -> bool {
        matches!(self, Self::Calendar(q) if q.len() >= LOOK_AHEAD_MIN_GRAINS)
    }

    /// A particle whose event comes up soon, whose records the engine may start loading
    /// (calendar only; a hint).
    #[inline(always)]
    pub(crate) fn ahead(&self) -> Option<usize> {
        match self {
            Self::Calendar(q) => q.ahead(),
            Self::Tournament(_) => None,
        }
    }

    /// Starts loading what the next update of particle `i` reads (a hint).
    #[inline(always)]
    pub(crate) fn prefetch_links(&self, i: u32) {
        if let Self::Calendar(q) = self {
            q.prefetch_links(i);
        }
    }

    /// Subtracts `dt` from every key (time-origin shift); `now` is the shifted current
    /// time.
    pub(crate) fn shift(&mut self, dt: f64, now: f64) {
        match self {
            Self::Calendar(q) => q.shift(dt, now),
            Self::Tournament(q) => q.shift(dt),
        }
    }

    /// Adapts the queue to the pending events after keys were set in bulk (the calendar's
    /// bucket width; the tournament tree is always up to date).
    pub(crate) fn rebuild(&mut self, now: f64) {
        if let Self::Calendar(q) = self {
            q.rebuild(now);
        }
    }

    /// Relabels the particles: particle `i` becomes `new_of_old[i]`; `now` is the
    /// current time.
    pub(crate) fn relabel(&mut self, new_of_old: &[u32], now: f64) {
        match self {
            Self::Calendar(q) => q.relabel(new_of_old, now),
            Self::Tournament(q) => q.relabel(new_of_old),
        }
    }

    /// Heap memory in bytes.
    pub(crate) fn memory_bytes(&self) -> usize {
        match self {
            Self::Calendar(q) => q.memory_bytes(),
            Self::Tournament(q) => q.memory_bytes(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    /// The calendar and the tournament tree give the same earliest event, ties to the
    /// lower index, under the engine's pattern of use (process the minimum, move time
    /// forward, shift the origin): the choice between them never changes a trajectory.
    #[test]
    fn calendar_and_tournament_agree() {
        let mut rng = stream(7, &[0]);
        let n = 300;
        let mut calendar = CalendarQueue::new(n);
        let mut tournament = TournamentQueue::new(n);
        let mut now = 0.0;
        for step in 0..50_000 {
            let i = rng.random_range(0..n);
            // Times on a grid of 1/64 (ties), some far ahead (the calendar's overflow).
            let key = match step % 13 {
                0 => f64::INFINITY,
                1 => now + rng.random_range(0..100_000) as f64 / 64.0,
                _ => now + rng.random_range(0..64) as f64 / 64.0,
            };
            calendar.update(i, key);
            tournament.update(i, key);
            if step % 2 == 0
                && let Some((m, t)) = tournament.min()
            {
                now = t;
                let j = (m + 1 + rng.random_range(0..n - 1)) % n;
                let (km, kj) = (
                    now + rng.random_range(0..64) as f64 / 64.0,
                    now + rng.random_range(0..64) as f64 / 64.0,
                );
                calendar.update(m, km);
                calendar.update(j, kj);
                tournament.update_pair(m, km, j, kj);
            }
            if step % 5000 == 4999 {
                calendar.shift(now, 0.0);
                tournament.shift(now);
                now = 0.0;
            }
            assert_eq!(calendar.min(), tournament.min(), "step {step}");
        }
    }
}
