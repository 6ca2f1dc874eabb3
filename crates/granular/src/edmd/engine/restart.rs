//! Grains set from outside the event loop (`Simulation::set_state`, a run started from a
//! snapshot): the engine is rebuilt around the new positions and velocities at a given
//! time, so that what follows depends only on that state and time, not on the history
//! before it.

use super::Edmd;
use crate::engine::Engine;
use crate::particles::ParticleSet;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Puts every grain at `positions` with `velocities` (row-major `n × D` by grain id,
    /// lengths and length / time) and, rough grains, `angular_velocities` (`d_r` values per
    /// grain by id; empty for smooth grains) at absolute time `time`, and rebuilds everything that
    /// depends on them: every grain's clock is set to `time`, the cells, the storage order
    /// and every prediction are made again, as when the engine was built. The collision
    /// law, the options, the totals and the impact histogram are kept; the TC model's
    /// memory of the last collisions and the collapse detector start afresh; a driving
    /// keeps its interval and tally and counts its kicks from `time`
    /// (`EdmdDriving::restarted`). Two engines of the same grains restarted with the same
    /// arrays at the same time therefore continue with the same bits, whatever they did
    /// before.
    ///
    /// The caller validates the arrays (lengths `n × D` and `n × d_r`, finite, inside the
    /// box or the walls, no overlap: `Simulation::set_state`); compression must be over.
    pub(crate) fn restart(
        &mut self,
        time: f64,
        positions: &[f64],
        velocities: &[f64],
        angular_velocities: &[f64],
    ) {
        let n = self.len();
        debug_assert_eq!(positions.len(), n * D);
        debug_assert_eq!(velocities.len(), n * D);
        debug_assert_eq!(angular_velocities.len(), self.angular_velocities().len());
        debug_assert_eq!(self.growth, 0.0);
        let rows = |a: &[f64]| -> Vec<Vector<D>> {
            a.chunks_exact(D)
                .map(|c| Vector::from_slice(c).unwrap_or_default())
                .collect()
        };
        let particles = ParticleSet {
            positions: rows(positions),
            velocities: rows(velocities),
            radii: self.radii(),
            masses: self.masses(),
            species: self.species(),
            species_names: self.species_names.clone(),
            // Rough grains keep their κ.
            angular_velocities: angular_velocities.to_vec(),
            inertia: self.species_inertia(),
        };
        let mut fresh = Self::new(
            self.bx.clone(),
            particles,
            self.law.clone(),
            self.options.clone(),
        );
        // The fresh engine's clock reads 0 on its grains: its origin is `time`.
        fresh.origin = time;
        fresh.totals = std::mem::take(&mut self.totals);
        fresh.impact = self.impact.clone();
        fresh.log = self.log.take();
        fresh.driving = self.driving.as_ref().map(|d| d.restarted(time));
        *self = fresh;
        debug_assert_eq!(self.time(), time);
    }
}
