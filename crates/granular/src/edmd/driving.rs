//! The steady-state driving of the event-driven engine ([`crate::driving`]). The event
//! loop stops at fixed times `t_k = t_0 + k dt_kick`, the driving changes every velocity
//! there (positions do not move), and the event calendar is predicted again from scratch
//! (`Edmd::change_velocities`): no overlap is created and no event is skipped.
//!
//! * `rescale`: the peculiar velocities are multiplied by `sqrt(T* / T)` at every `t_k`.
//! * `white_noise`: every velocity component receives a Gaussian kick of variance
//!   `xi0² dt_kick` at every `t_k`, less the mean kick (momentum stays zero). Between kicks
//!   the grains fly ballistically and collide, so the kicks approximate the continuous
//!   noise with an error of order `dt_kick / t_mf` in the shape of the distribution; the
//!   injected power is exact on average.
//!
//! `dt_kick` is [`KICK_FRACTION`] (white noise) or [`RESCALE_FRACTION`] (rescale) of the
//! mean free time of the Enskog theory at the state's temperature (`T*`, or the white-noise
//! energy-balance temperature), fixed when the driving is attached. Each kick costs a recalculation of all `N` event predictions, about as much
//! as `N` collisions, so a run takes about `1 / KICK_FRACTION` times longer than a free one.
//! The kick of grain `id` at application `k` comes from the stream
//! `(seed, [KICKS, k, id])`, as in DSMC: reproducible and independent of storage order.

use super::engine::Edmd;
use crate::driving::{Driving, DrivingState, GasTheory, KICKS, rescale_factor};
use crate::engine::{Engine, EngineError, Progress};
use crate::random::{std_normal, stream};
use crate::theory::haff;
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// The interval between two white-noise kicks, in mean free times at the state's
/// temperature: each grain collides with probability about 0.05 between two kicks, so the
/// kicks approximate the continuous noise closely, while the predictions recomputed at
/// every kick cost about as much as the collisions (`N` per kick). The bias this leaves on
/// `a2` and `T` is measured in `docs/edmd.md` (halving the interval).
pub const KICK_FRACTION: f64 = 0.05;

/// The interval between two rescalings, in mean free times at `T*`. A uniform scaling of
/// all peculiar velocities does not change the shape of the velocity distribution, and the
/// hard-core dynamics at another temperature is the same dynamics on another clock, so the
/// sampled state does not depend on this interval; it only bounds the temperature's
/// excursion between rescalings (`1 - exp(-zeta dt)`, 4 % at `e = 0.5`).
pub const RESCALE_FRACTION: f64 = 0.1;

/// A driving attached to the event-driven engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EdmdDriving {
    /// The driving and its tally (the application count indexes the kick streams).
    pub state: DrivingState,
    /// Seed of the kick streams.
    pub seed: u64,
    /// Absolute time of the driving's attachment, `t_0`.
    pub start: f64,
    /// `dt_kick` (time units).
    pub interval: f64,
}

impl<const D: usize> Edmd<D> {
    /// Attaches a steady-state driving from now on (replacing any earlier one), with kick
    /// streams under `seed` and `dt_kick` = [`KICK_FRACTION`] (white noise) or
    /// [`RESCALE_FRACTION`] (rescale) of the Enskog mean free time at the state's
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
    pub fn set_driving_every(&mut self, driving: Option<Driving>, seed: u64, fraction: f64) {
        let Some(driving) = driving else {
            self.driving = None;
            return;
        };
        let theory = self.gas_theory();
        let temperature = match driving {
            Driving::Rescale { temperature } => temperature,
            Driving::WhiteNoise { strength } => {
                theory.white_noise_temperature(strength, theory.a2(&driving))
            }
        };
        let omega = haff::collision_frequency(
            D,
            theory.number_density,
            theory.radius,
            temperature,
            theory.mass,
            theory.chi,
        );
        let k = self.kinetic_energy_now();
        self.driving = Some(EdmdDriving {
            state: DrivingState::new(driving, k),
            seed,
            start: self.time(),
            interval: fraction / omega,
        });
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
        let grain = if D == 2 {
            std::f64::consts::PI * radius * radius
        } else {
            4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
        };
        let phi = n as f64 * grain / volume;
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
            let next = d.start + (d.state.applications + 1) as f64 * d.interval;
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
        let Some(d) = self.driving.as_ref() else {
            return;
        };
        let before = self.kinetic_energy_now();
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
            }
            Driving::WhiteNoise { strength } => {
                let width = (strength * d.interval).sqrt();
                let (seed, k) = (d.seed, d.state.applications);
                let kick = |id: u32| {
                    let mut rng = stream(seed, &[KICKS, k, u64::from(id)]);
                    let mut v = Vector::<D>::zero();
                    for c in 0..D {
                        v[c] = width * std_normal(&mut rng);
                    }
                    v
                };
                // The mean over ids in id order (independent of the storage order).
                let mean = (0..n as u32).fold(Vector::<D>::zero(), |a, id| a + kick(id))
                    * (1.0 / n as f64);
                self.change_velocities(|id, v| v + kick(id) - mean);
            }
        }
        let after = self.kinetic_energy_now();
        if let Some(d) = self.driving.as_mut() {
            d.state.applications += 1;
            d.state.injected_energy += after - before;
        }
    }
}
