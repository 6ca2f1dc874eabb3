//! The grains of a simulation as plain arrays, in input order: what every engine is
//! built from and what it can hand back.

use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// Everything that defines the grains at the start of a run.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ParticleSet<const D: usize> {
    /// Centre positions, inside the box.
    pub positions: Vec<Vector<D>>,
    /// Velocities.
    pub velocities: Vec<Vector<D>>,
    /// Radii (> 0).
    pub radii: Vec<f64>,
    /// Masses (> 0).
    pub masses: Vec<f64>,
    /// Species index of each grain into `species_names`.
    pub species: Vec<u32>,
    /// Species names.
    pub species_names: Vec<String>,
    /// Angular velocities of rough grains (radians per time unit), `d_r` values per grain
    /// (`ω_z` of a disk; `ω_x, ω_y, ω_z` of a sphere; `collision_law::rough::spin_at`);
    /// empty for smooth grains, and zero spins for rough grains when empty.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub angular_velocities: Vec<f64>,
    /// Reduced moment of inertia `κ = 4I/(mσ²)` of each species (by species index) of
    /// rough grains; empty: uniform grains (`collision_law::rough::uniform_inertia`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inertia: Vec<f64>,
}

impl<const D: usize> ParticleSet<D> {
    /// Number of grains.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

/// Writes `value(s)`, the `D` values of the grain in storage slot `s`, into row `ids[s]`
/// of `out` (row-major, `D` values per row): from an engine's storage order (sorted in
/// space) back to input order.
///
/// `ids` must be a permutation of `0..ids.len()` (every engine keeps one) and `out` exactly
/// `ids.len() × D` long; rows that no slot names are left as they were.
///
/// Written by hand because it is the whole cost of handing 10^6 positions to NumPy: the
/// storage is read in order, and the writes land at random rows, a cache miss each. Large
/// systems are split into row ranges, one per worker of rayon's pool (at most four): each
/// worker scans every slot and writes only its own rows, so the writes are disjoint without
/// `unsafe`, at the price of reading the slot order once per worker (sequential, cheap
/// beside the random writes).
pub(crate) fn scatter_by_id<const D: usize>(
    ids: &[u32],
    out: &mut [f64],
    value: impl Fn(usize) -> [f64; D] + Sync,
) {
    use rayon::prelude::*;
    /// Below this many grains one thread is faster than waking the pool.
    const PARALLEL_FROM: usize = 100_000;
    debug_assert_eq!(out.len(), ids.len() * D);
    let n = ids.len();
    let workers = if n < PARALLEL_FROM {
        1
    } else {
        rayon::current_num_threads().clamp(1, 4)
    };
    let rows = n.div_ceil(workers).max(1);
    out.par_chunks_mut(rows * D)
        .enumerate()
        .for_each(|(k, chunk)| {
            let first = k * rows;
            let range = first..first + chunk.len() / D;
            for (s, &id) in ids.iter().enumerate() {
                let id = id as usize;
                if range.contains(&id) {
                    let at = (id - first) * D;
                    chunk[at..at + D].copy_from_slice(&value(s));
                }
            }
        });
}

/// Writes `value(slots[i])`, the `D` values of the grain that lies in storage slot
/// `slots[i]`, into row `i` of `out` (row-major, `D` values per row): the gather that
/// undoes an engine's storage order when it keeps the slot of every grain id.
///
/// `out` must be `slots.len() × D` long. Every row is written exactly once, in order, so
/// the rows split into blocks that rayon's workers fill independently (safe Rust, no
/// scan of the whole order per worker), and the writes stream sequentially into the
/// caller's buffer; the reads go through `slots`. `ahead(slots)` is called with the
/// slots a few rows ahead of the current one, so that the engine can prefetch their
/// storage and the cache misses of a scrambled order overlap. This costs about as much as
/// a sequential copy of the storage when the order is nearly the input order, and stays
/// within a small factor of it for a random one (docs/performance.md).
pub(crate) fn gather_by_slot<const D: usize>(
    slots: &[u32],
    out: &mut [f64],
    ahead: impl Fn(&[u32]) + Sync,
    value: impl Fn(usize) -> [f64; D] + Sync,
) {
    use rayon::prelude::*;
    /// Rows per task: 64 KiB of output in 2D, small enough for rayon to balance the
    /// blocks over its workers and large enough that a task's start is negligible.
    const BLOCK: usize = 4096;
    /// Below this many grains one thread is faster than waking the pool.
    const PARALLEL_FROM: usize = 100_000;
    /// Rows between a prefetch and the read it prepares.
    const AHEAD: usize = 16;
    debug_assert_eq!(out.len(), slots.len() * D);
    let fill = |first: usize, rows: &mut [f64]| {
        let block = &slots[first..first + rows.len() / D];
        for (r, row) in rows.chunks_exact_mut(D).enumerate() {
            if let Some(next) = block.get(r + AHEAD..r + AHEAD + 1) {
                ahead(next);
            }
            row.copy_from_slice(&value(block[r] as usize));
        }
    };
    if slots.len() < PARALLEL_FROM {
        fill(0, out);
    } else {
        out.par_chunks_mut(BLOCK * D)
            .enumerate()
            .for_each(|(k, rows)| fill(k * BLOCK, rows));
    }
}

#[cfg(test)]
mod tests {
    use super::{gather_by_slot, scatter_by_id};

    /// The gather by slot puts the same values in the same rows as the scatter by id,
    /// for the inverse permutation, small (one thread) and large (blocks over the pool).
    #[test]
    fn gather_by_slot_is_the_scatter_by_id_of_the_inverse_order() {
        for n in [0, 1, 7, 1000, 250_001] {
            let a = (1..)
                .map(|k| 7919 * k + 1)
                .find(|&a| gcd(a, n.max(1)) == 1)
                .unwrap_or(1);
            let ids: Vec<u32> = (0..n).map(|i| ((a * i + 13) % n.max(1)) as u32).collect();
            let mut slots = vec![0u32; n];
            for (s, &id) in ids.iter().enumerate() {
                slots[id as usize] = s as u32;
            }
            let value = |s: usize| [s as f64, -(s as f64)];
            let mut scattered = vec![f64::NAN; 2 * n];
            scatter_by_id::<2>(&ids, &mut scattered, value);
            let mut gathered = vec![f64::NAN; 2 * n];
            let asked = std::sync::atomic::AtomicUsize::new(0);
            gather_by_slot::<2>(
                &slots,
                &mut gathered,
                |next| {
                    assert!(next.iter().all(|&s| (s as usize) < n));
                    asked.fetch_add(next.len(), std::sync::atomic::Ordering::Relaxed);
                },
                value,
            );
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&gathered), bits(&scattered), "n = {n}");
            // Every row but the last AHEAD of each block is announced ahead.
            if n >= 100 {
                assert!(asked.into_inner() > n / 2, "n = {n}: prefetch hints");
            }
        }
    }

    /// The split into row ranges (large systems) and the single pass (small ones) both
    /// put every slot's values in the row its id names, for a scrambled permutation.
    #[test]
    fn scatter_puts_every_slot_in_its_row() {
        for n in [0, 1, 7, 1000, 250_001] {
            // A scrambled permutation: i -> (a i + b) mod n with a coprime to n.
            let a = (1..)
                .map(|k| 7919 * k + 1)
                .find(|&a| gcd(a, n.max(1)) == 1)
                .unwrap_or(1);
            let ids: Vec<u32> = (0..n).map(|i| ((a * i + 13) % n.max(1)) as u32).collect();
            let mut out = vec![f64::NAN; 2 * n];
            scatter_by_id::<2>(&ids, &mut out, |s| [s as f64, -(s as f64)]);
            for (s, &id) in ids.iter().enumerate() {
                let row = 2 * id as usize;
                assert_eq!(
                    out[row..row + 2],
                    [s as f64, -(s as f64)],
                    "n = {n}, slot {s}"
                );
            }
        }
    }

    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 { a } else { gcd(b, a % b) }
    }
}
