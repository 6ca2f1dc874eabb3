//! Steady states of a granular gas of smooth hard grains (constant restitution `e`):
//!
//! * **rescale**: the homogeneous cooling state (HCS) sampled in scaled variables. After
//!   every DSMC step the peculiar velocities are multiplied by `lambda = sqrt(T* / T)`, so
//!   the temperature stays at `T*` while the shape of the velocity distribution relaxes to
//!   that of the HCS. Time then runs in units where the temperature is fixed ("scaled
//!   time"), and the energy the rescaling puts back per unit time is the energy the
//!   collisions remove: `P = (D/2) N zeta T*`, so `zeta = 2 P / (D N T*)` is the cooling
//!   rate of the HCS (Brey, Ruiz-Montero and Cubero, Phys. Rev. E 54, 3664 (1996);
//!   Montanero and Santos, Granular Matter 2, 53 (2000)).
//! * **white_noise**: the stochastically heated gas (T. P. C. van Noije and M. H. Ernst,
//!   Granular Matter 1, 57 (1998); D. R. M. Williams and F. C. MacKintosh, Phys. Rev. E 54,
//!   R9 (1996)): `m dv_i/dt = F_i + m xi_i(t)` with Gaussian white noise
//!   `<xi_ia(t) xi_jb(t')> = xi0² delta_ij delta_ab delta(t - t')`. After every DSMC step of
//!   length `dt` each velocity component receives a Gaussian kick of variance
//!   `xi0² dt` (`strength = xi0²`, units length²/time³); the mean kick is subtracted, so
//!   the total momentum stays exactly what it was (zero) and the injected power is
//!   `(D/2) m xi0² (N - 1)` on average. The gas reaches the temperature at which this
//!   balances the collisional loss `(D/2) N zeta(T) T`, [`GasTheory::white_noise_temperature`].
//!
//! Random kicks come from the stream `(seed, [KICKS, application, id])` of the engine's
//! dynamics seed: one per grain and application, named by the grain's identity, so the
//! kicks are the same for any thread count, storage order or number of ranks.

use crate::random::{derive_key, extend_key, std_normal, stream_from_key};
use crate::theory::{haff, sonine};
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// Path prefix of the kick streams under the engine's seed (the DSMC collision streams are
/// `[DYNAMICS, step, cell]`, prefix 1).
pub(crate) const KICKS: u64 = 3;

/// Which steady state is maintained, and its parameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Driving {
    /// Rescale the peculiar velocities to `temperature` (energy units) after every step.
    Rescale {
        /// The fixed temperature `T*` (energy units).
        temperature: f64,
    },
    /// Gaussian velocity kicks of variance `strength * dt` per component after every step.
    WhiteNoise {
        /// `xi0²`, the velocity variance per component and unit time (length² / time³).
        strength: f64,
    },
}

/// The driving of a running engine: what it does and what it has done (kept in
/// checkpoints, so a resumed run continues the same kick streams and energy tally).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DrivingState {
    /// What is applied.
    pub driving: Driving,
    /// Applications so far (the index of the next kick stream).
    pub applications: u64,
    /// Kinetic energy put into the gas by the driving since `t = 0` (energy units;
    /// negative where a rescaling removed energy).
    pub injected_energy: f64,
    /// Kinetic energy when the driving was attached (for the dissipated energy
    /// `K(0) + injected - K(t)` of an engine without walls or gravity).
    pub initial_kinetic_energy: f64,
}

impl DrivingState {
    /// A driving attached to a gas of kinetic energy `kinetic_energy`.
    pub(crate) fn new(driving: Driving, kinetic_energy: f64) -> DrivingState {
        DrivingState {
            driving,
            applications: 0,
            injected_energy: 0.0,
            initial_kinetic_energy: kinetic_energy,
        }
    }

    /// The energy lost in collisions since `t = 0`, `K(0) + injected - K(t)`, for a gas
    /// of kinetic energy `kinetic_energy` now (exact without walls or gravity).
    pub fn dissipated(&self, kinetic_energy: f64) -> f64 {
        self.initial_kinetic_energy + self.injected_energy - kinetic_energy
    }
}

/// The white-noise kicks of one application: grain `id`'s kick is `width` times `D`
/// standard normal deviates from the stream `(seed, [KICKS, application, id])`, the same
/// for any storage order, thread count or number of ranks. The stream's prefix is hashed
/// once per application and each grain's generator seeded without `seed_from_u64`'s
/// byte-wise fill ([`stream_from_key`]): the same bits as `stream(seed, &[KICKS,
/// application, id])` at about a third of the cost, which matters as every grain is
/// kicked twice per step (for the mean, then to apply it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kicks {
    /// `derive_key(seed, [KICKS, application])`.
    prefix: u64,
    /// `sqrt(xi0² dt)`, the standard deviation of each component (velocity units).
    width: f64,
}

impl Kicks {
    /// The kicks of application number `application` under `seed`, for a noise of
    /// `strength` (`xi0²`, length²/time³) over an interval `dt` (time units).
    pub(crate) fn new(seed: u64, application: u64, strength: f64, dt: f64) -> Kicks {
        Kicks {
            prefix: derive_key(seed, &[KICKS, application]),
            width: (strength * dt).sqrt(),
        }
    }

    /// The kick of grain `id` (velocity units), before the mean kick is taken off.
    #[inline]
    pub(crate) fn of<const D: usize>(&self, id: u32) -> Vector<D> {
        let mut rng = stream_from_key(extend_key(self.prefix, u64::from(id)));
        let mut v = Vector::<D>::zero();
        for c in 0..D {
            v[c] = self.width * std_normal(&mut rng);
        }
        v
    }
}

/// The factor `lambda = sqrt(T* / T)` that brings the temperature `T` to `T*` (1 for a
/// gas at rest, which cannot be rescaled).
pub(crate) fn rescale_factor(target: f64, temperature: f64) -> f64 {
    if temperature > 0.0 && temperature.is_finite() {
        (target / temperature).sqrt()
    } else {
        1.0
    }
}

/// The kinetic theory of the driven gas: one species of radius `radius`, mass `mass`, at
/// number density `number_density` in `dimension` dimensions, with restitution
/// `restitution` and contact value `chi` (1: Boltzmann, dilute DSMC).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GasTheory {
    /// `D`.
    pub dimension: usize,
    /// `e`.
    pub restitution: f64,
    /// Number density `n` (1 / length^D).
    pub number_density: f64,
    /// Grain radius (length).
    pub radius: f64,
    /// Grain mass.
    pub mass: f64,
    /// Enskog factor `chi` of the collision frequency.
    pub chi: f64,
    /// Number of grains `N` (the momentum-conserving kicks heat `N - 1` degrees per axis).
    pub particles: usize,
}

impl GasTheory {
    /// The Sonine `a2` of the state (van Noije and Ernst 1998): the HCS's second estimate
    /// for `rescale` (KT-11, the one DSMC follows), the heated gas's for `white_noise`
    /// (KT-12).
    pub fn a2(&self, driving: &Driving) -> f64 {
        match driving {
            Driving::Rescale { .. } => sonine::cooling_a2_second(self.dimension, self.restitution),
            Driving::WhiteNoise { .. } => sonine::white_noise_a2(self.dimension, self.restitution),
        }
    }

    /// Cooling rate `zeta(T) = (1 - e²)/D omega(T) (1 + 3 a2/16)` (per unit time, KT-8:
    /// [`haff::sonine_cooling_rate`]), with `omega` the Enskog-Boltzmann collision
    /// frequency (KT-5).
    pub fn cooling_rate(&self, temperature: f64, a2: f64) -> f64 {
        let omega = self.collision_frequency(temperature);
        haff::sonine_cooling_rate(self.dimension, self.restitution, omega, a2)
    }

    /// The Enskog-Boltzmann collision frequency `omega(T)` of one grain of this gas (KT-5,
    /// [`haff::collision_frequency`]), per unit time.
    pub(crate) fn collision_frequency(&self, temperature: f64) -> f64 {
        haff::collision_frequency(
            self.dimension,
            self.number_density,
            self.radius,
            temperature,
            self.mass,
            self.chi,
        )
    }

    /// The steady temperature of the white-noise driven gas, KT-13, from the exact energy balance
    /// `(D/2) m xi0² (N - 1) = (D/2) N zeta(T) T` with the Sonine loss rate
    /// [`Self::cooling_rate`] at `a2`: since `zeta ~ sqrt(T)`,
    /// `T = (m xi0² (1 - 1/N) / zeta(T = 1))^(2/3)`.
    pub fn white_noise_temperature(&self, strength: f64, a2: f64) -> f64 {
        let n = self.particles as f64;
        let heating = self.mass * strength * (1.0 - 1.0 / n);
        (heating / self.cooling_rate(1.0, a2)).powf(2.0 / 3.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steady temperature balances heating and loss exactly.
    #[test]
    fn white_noise_temperature_balances() {
        let g = GasTheory {
            dimension: 2,
            restitution: 0.6,
            number_density: 0.01,
            radius: 0.5,
            mass: 2.0,
            chi: 1.0,
            particles: 1000,
        };
        let a2 = g.a2(&Driving::WhiteNoise { strength: 1.0 });
        let t = g.white_noise_temperature(3.0, a2);
        let loss = g.cooling_rate(t, a2) * t;
        let gain = 2.0 * 3.0 * (1.0 - 1e-3);
        assert!((loss - gain).abs() < 1e-12 * gain, "{loss} {gain}");
        assert_eq!(rescale_factor(4.0, 1.0), 2.0);
        assert_eq!(rescale_factor(4.0, 0.0), 1.0);
    }
}
