//! The steady-state driving of the DSMC engine ([`crate::driving`]): applied after every
//! step, outside the move and collision kernels. Rescaling uses the engine's chunked
//! reductions; the white-noise kicks come from per-grain streams named by the grain's
//! identity, and their mean is an ordered chunked sum over the storage order, so both are
//! bit-identical for any number of threads or ranks.

use super::engine::DsmcEngine;
use crate::driving::{Driving, DrivingState, Kicks, rescale_factor};
use crate::vector::Vector;

impl<const D: usize> DsmcEngine<D> {
    /// Attaches a steady-state driving from now on (replacing any earlier one); its energy
    /// tally starts at the current kinetic energy.
    pub fn set_driving(&mut self, driving: Option<Driving>) {
        let k = self.kinetic_energy_now() + self.rotational_energy_now().unwrap_or(0.0);
        self.driving = driving.map(|d| DrivingState::new(d, k));
    }

    /// Replaces the driving's rule (a new white-noise strength or rescaling temperature)
    /// from the next step on, keeping its tally and its kick streams' count. Without a
    /// driving, nothing (the caller checks that there is one).
    pub(crate) fn change_driving(&mut self, driving: Driving) {
        if let Some(state) = self.driving.as_mut() {
            state.driving = driving;
        }
    }

    /// The driving and its tally, if any.
    pub fn driving(&self) -> Option<&DrivingState> {
        self.driving.as_ref()
    }

    /// Applies the driving once, after a step of length `dt` (time units). Rough grains:
    /// `rescale` multiplies the angular velocities by the factor of the peculiar
    /// velocities (the translational temperature is held, the ratio `T_r / T_t` is the
    /// collisions'), white noise kicks the translational velocities only (as RS-6 and
    /// RS-9 assume); the injected energy counts both kinds.
    pub(super) fn drive(&mut self, dt: f64) {
        let Some(state) = self.driving.as_ref() else {
            return;
        };
        let total = |e: &Self| e.kinetic_energy_now() + e.rotational_energy_now().unwrap_or(0.0);
        let before = total(self);
        match state.driving {
            Driving::Rescale { temperature } => {
                let u = self.mean_velocity();
                let lambda = rescale_factor(temperature, self.temperature());
                self.grains.update_velocities(|_, v| u + (v - u) * lambda);
                self.grains.scale_spins(lambda);
            }
            Driving::WhiteNoise { strength } => {
                let (seed, k) = self.kick_seed_and_application();
                let kicks = Kicks::new(seed, k, strength, dt);
                // Each grain's kick comes from its own stream, drawn twice (for the mean,
                // then to apply it) rather than stored: no per-grain buffer.
                let kick = |id: u32| kicks.of::<D>(id);
                let g = &self.grains;
                let add = |a: &mut [f64; D], x: &[f64; D]| {
                    for (a, x) in a.iter_mut().zip(x) {
                        *a += x;
                    }
                };
                let sum = self.ordered_fold::<D, D>(|i| kick(g.id(i)).0, add, add);
                let mean = Vector(sum) * (1.0 / self.n_global() as f64);
                self.grains.update_velocities(|id, v| v + kick(id) - mean);
            }
        }
        let after = total(self);
        if let Some(s) = self.driving.as_mut() {
            s.applications += 1;
            s.injected_energy += after - before;
        }
    }
}
