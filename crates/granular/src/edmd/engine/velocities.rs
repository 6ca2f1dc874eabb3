//! Velocities changed from outside the event loop (a driving's kicks, the compression's
//! thermostat): every prediction is redone.

use super::Edmd;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Multiplies all velocities by `factor` (thermostat used during compression).
    pub(crate) fn scale_velocities(&mut self, factor: f64) {
        self.change_velocities(|_, v| v * factor);
    }

    /// Multiplies every angular velocity of rough grains by `factor` (free flight does not
    /// change spins, so no prediction changes).
    pub(crate) fn scale_spins(&mut self, factor: f64) {
        for w in &mut self.spin {
            *w *= factor;
        }
    }

    /// Replaces every grain's velocity `v` by `f(id, v)` at the current time, then
    /// predicts every grain's next event again and rebuilds the calendar (no event is
    /// skipped: the positions do not move, only the future changes). Without gravity.
    ///
    /// New velocities can send two grains that were each other's last partners towards
    /// each other again (a white-noise kick right after their collision); the prediction
    /// releases such pairs ([`Edmd::release_if_approaching`]).
    pub(crate) fn change_velocities(&mut self, mut f: impl FnMut(u32, Vector<D>) -> Vector<D>) {
        for i in 0..self.len() {
            self.advance_particle(i);
            let id = self.id[i];
            let g = &mut self.grains[i];
            g.vel = f(id, g.vel);
            g.counter = g.counter.wrapping_add(1);
        }
        for i in 0..self.len() {
            self.predict(i);
        }
        self.queue.rebuild(self.now);
    }
}
