//! Parameters changed between two calls to `advance` (`Simulation::set`): gravity and the
//! driving. (The collision law: `Edmd::set_collision_law`.) Every grain is brought to the
//! current time and every event predicted again, so no event is skipped and no overlap
//! is created.

use super::Edmd;
use crate::driving::Driving;
use crate::edmd::driving::{KICK_FRACTION, RESCALE_FRACTION};
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Sets the uniform acceleration (length / time², `D` components; empty or zero:
    /// none) from the current time on.
    pub(crate) fn set_gravity(&mut self, gravity: &[f64]) {
        for i in 0..self.len() {
            self.advance_particle(i);
            let g = &mut self.grains[i];
            g.counter = g.counter.wrapping_add(1);
        }
        let mut g = Vector::<D>::zero();
        for (k, x) in gravity.iter().enumerate().take(D) {
            g[k] = *x;
        }
        self.gravity = g;
        self.has_gravity = g.norm_squared() > 0.0;
        self.options.gravity = gravity.to_vec();
        for i in 0..self.len() {
            self.predict(i);
        }
        self.queue.rebuild(self.now);
    }

    /// Replaces the driving's rule (a new white-noise strength or rescaling temperature)
    /// from the current time on, keeping its tally: the interval between applications is
    /// that of the new rule at its temperature, the kick times are counted from now and
    /// the kick streams keyed by now (as after a restart, [`crate::random::RESTART`]).
    /// Without a driving, nothing (the caller checks that there is one).
    pub(crate) fn change_driving(&mut self, driving: Driving) {
        let Some(old) = self.driving.clone() else {
            return;
        };
        let fraction = match driving {
            Driving::WhiteNoise { .. } => KICK_FRACTION,
            Driving::Rescale { .. } => RESCALE_FRACTION,
        };
        let time = crate::engine::Engine::time(self);
        let interval = self.kick_interval(&driving, fraction);
        let mut next = old.restarted(time);
        next.state.driving = driving;
        next.interval = interval;
        self.driving = Some(next);
    }
}
