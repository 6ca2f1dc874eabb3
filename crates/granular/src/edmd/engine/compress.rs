//! The end of Lubachevsky-Stillinger compression (growing radii).

use super::Edmd;

impl<const D: usize> Edmd<D> {
    /// Ends Lubachevsky-Stillinger growth: radii are frozen at their current values.
    pub(crate) fn freeze_growth(&mut self) {
        if self.growth == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
        }
        let scale = 1.0 + self.growth * self.now;
        for r in &mut self.kind_radius {
            *r *= scale;
        }
        self.growth = 0.0;
        self.max_radius = self.kind_radius.iter().cloned().fold(0.0, f64::max);
        self.min_radius = self
            .kind_radius
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        for i in 0..self.len() {
            self.predict(i);
        }
        self.queue.rebuild(self.now);
    }
}
