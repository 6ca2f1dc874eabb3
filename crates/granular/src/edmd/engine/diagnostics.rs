//! Diagnostics: the largest overlap, the mean free time so far, the memory held.

use super::Edmd;
use crate::edmd::candidates::Grain;

impl<const D: usize> Edmd<D> {
    /// The largest overlap `σ_ij - |x_i - x_j|` over all touching pairs at the current time
    /// (zero or round-off for a correct run), and the largest wall penetration.
    pub fn max_overlap(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..self.len() {
            let xi = self.position_raw(i);
            let ri = self.radius_now(i);
            for k in 0..D {
                if !self.bx.is_periodic(k) {
                    worst = worst.max(ri - xi[k]).max(xi[k] + ri - self.bx.lengths[k]);
                }
            }
            self.cells.for_each_candidate(i, |j| {
                if j > i {
                    let d = self.bx.separation(&xi, &self.position_raw(j)).norm();
                    worst = worst.max(ri + self.radius_now(j) - d);
                }
            });
        }
        worst
    }

    /// Mean time between collisions of one grain over the whole run so far.
    pub(crate) fn mean_free_time_so_far(&self) -> f64 {
        let t = self.origin + self.now;
        if self.totals.pair_collisions == 0 {
            f64::INFINITY
        } else {
            self.len() as f64 * t / (2.0 * self.totals.pair_collisions as f64)
        }
    }

    /// Heap memory held by the engine's per-particle and per-cell arrays, in bytes
    /// (grain records, events, partners, TC times, id maps, kinds, queue and cell lists):
    /// what `granular bench edmd` reports per particle.
    pub fn memory_bytes(&self) -> usize {
        fn bytes<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        self.grains.capacity() * std::mem::size_of::<Grain<D>>()
            + bytes(&self.event)
            + bytes(&self.last_partner)
            + bytes(&self.last_collision)
            + bytes(&self.id)
            + self.slot.get().map_or(0, bytes)
            + bytes(&self.kind_radius)
            + bytes(&self.kind_mass)
            + bytes(&self.kind_species)
            + self.queue.memory_bytes()
            + self.cells.memory_bytes()
    }
}
