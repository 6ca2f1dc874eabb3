//! The engine under a steady-state driving (`edmd/driving.rs`): the event loop stops at
//! every application time, the driving changes every velocity there (positions do not
//! move), and every prediction is redone (`velocities.rs`): no overlap is created and no
//! event is skipped.

use super::Edmd;
use crate::driving::{Driving, DrivingState, GasTheory, rescale_factor};
use crate::edmd::driving::{EdmdDriving, KICK_FRACTION, RESCALE_FRACTION};
use crate::engine::{Engine, EngineError, Progress};
use crate::theory::haff;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Attaches a steady-state driving from now on (replacing any earlier one), with kick
    /// streams under `seed` and `dt_kick` = `KICK_FRACTION` (white noise) or
    /// `RESCALE_FRACTION` (rescale) of the Enskog mean free time at the state's
    /// temperature ([`Edmd::gas_theory`]). Requires a gas without gravity.
    pub fn set_driving(&mut self, driving: Option<Driving>, seed: u64) {
        let fraction = match driving {
            Some(Driving::WhiteNoise { .. }) => KICK_FRACTION,
            _ => RESCALE_FRACTION,
        };
        self.set_driving_every(driving, seed, fraction);
    }

    /// [`Edmd::set_driving`] with `dt_kick = fraction` mean free times at the state's
    /// temperature.
    pub(crate) fn set_driving_every(&mut self, driving: Option<Driving>, seed: u64, fraction: f64) {
        let Some(driving) = driving else {
            self.driving = None;
            return;
        };
        let energy = self.kinetic_energy_now() + self.rotational_energy_now().unwrap_or(0.0);
        let interval = self.kick_interval(&driving, fraction);
        let attached = EdmdDriving::new(driving, energy, seed, self.time(), interval);
        self.driving = Some(attached);
    }

    /// `dt_kick = fraction` mean free times of the Enskog theory at the driven state's
    /// temperature: rescaling's `T*`, or the white-noise energy balance of the smooth gas
    /// (KT-13) or, for rough grains, of the translational loss at the steady temperature
    /// ratio (RS-6).
    pub(crate) fn kick_interval(&self, driving: &Driving, fraction: f64) -> f64 {
        let theory = self.gas_theory();
        let nu = |t: f64| theory.collision_frequency(t);
        let temperature = match *driving {
            Driving::Rescale { temperature } => temperature,
            Driving::WhiteNoise { strength } if self.is_rough() => {
                let law = self.collision_law();
                let gas = crate::theory::rough::RoughGas {
                    dimension: D,
                    normal_restitution: law.restitution,
                    tangential_restitution: law.tangential_restitution,
                    inertia: self.species_inertia()[0],
                };
                gas.white_noise_temperature(strength, theory.mass, theory.particles, nu(1.0))
            }
            Driving::WhiteNoise { strength } => {
                theory.white_noise_temperature(strength, theory.a2(driving))
            }
        };
        fraction / nu(temperature)
    }

    /// The driving and its tally, if any.
    pub fn driving(&self) -> Option<&DrivingState> {
        self.driving.as_ref().map(|d| &d.state)
    }

    /// The interval `dt_kick` between applications of the driving (time units).
    pub fn driving_interval(&self) -> Option<f64> {
        self.driving.as_ref().map(|d| d.interval)
    }

    /// The kinetic theory of the gas: grain 0's radius and mass (one species), the number
    /// density `N / V` and the Enskog contact value `chi(phi)` ([`haff::contact_value`]).
    pub fn gas_theory(&self) -> GasTheory {
        let n = self.particle_count();
        let radius = self.radii().first().copied().unwrap_or(0.0);
        let volume = self.simulation_box().volume();
        let phi = crate::theory::kinetic::mixture_packing_fraction(D, [(n, radius)], volume);
        GasTheory {
            dimension: D,
            restitution: self.collision_law().restitution,
            number_density: n as f64 / volume,
            radius,
            mass: if n > 0 { self.mass_of(0) } else { 1.0 },
            chi: haff::contact_value(D, phi),
            particles: n,
        }
    }

    /// Events up to `until`, stopping at every application time of the driving on the way
    /// to apply it (at most `max_events` events in all).
    pub(super) fn advance_driven(
        &mut self,
        until: f64,
        max_events: u64,
    ) -> Result<Progress, EngineError> {
        let first = self.events();
        loop {
            let Some(d) = self.driving.as_ref() else {
                return self.advance_events(until, max_events);
            };
            let next = d.next_time();
            let target = next.min(until);
            let left = max_events.saturating_sub(self.events() - first);
            if let Progress::BudgetExhausted = self.advance_events(target, left)? {
                return Ok(Progress::BudgetExhausted);
            }
            if next > until {
                return Ok(Progress::Reached);
            }
            self.drive();
            if next == until {
                return Ok(Progress::Reached);
            }
        }
    }

    /// Applies the driving once, at the current time.
    fn drive(&mut self) {
        let Some(d) = self.driving.clone() else {
            return;
        };
        let before = self.kinetic_energy_now();
        let spin_before = self.rotational_energy_now();
        let n = self.particle_count();
        let total_mass: f64 = (0..n).map(|i| self.mass_of(i)).sum();
        let u = self.momentum() * (1.0 / total_mass);
        match d.state.driving {
            Driving::Rescale { temperature } => {
                // Peculiar temperature, `sum m (v - u)² / (D N)`.
                let peculiar = before - 0.5 * total_mass * u.norm_squared();
                let t = 2.0 * peculiar / (D as f64 * n as f64);
                let lambda = rescale_factor(temperature, t);
                self.change_velocities(|_, v| u + (v - u) * lambda);
                // Rough grains: the spins by the same factor, so the temperature ratio
                // is left to the collisions.
                self.scale_spins(lambda);
            }
            Driving::WhiteNoise { strength } => {
                let kicks = d.kicks(strength);
                let kick = |id: u32| kicks.of::<D>(id);
                // The mean over ids in id order (independent of the storage order).
                let mean = (0..n as u32).fold(Vector::<D>::zero(), |a, id| a + kick(id))
                    * (1.0 / n as f64);
                self.change_velocities(|id, v| v + kick(id) - mean);
            }
        }
        let after = self.kinetic_energy_now();
        let injected = match (spin_before, self.rotational_energy_now()) {
            (Some(b), Some(a)) => (after + a) - (before + b),
            _ => after - before,
        };
        if let Some(d) = self.driving.as_mut() {
            d.state.applications += 1;
            d.state.injected_energy += injected;
        }
    }
}
