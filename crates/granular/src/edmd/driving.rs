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
//!
//! This module holds the driving's rule (the interval, the kicks); the engine applies it
//! (`engine/drive.rs`: the stops of the event loop, the new velocities, the predictions).

use crate::driving::{Driving, DrivingState, Kicks};
use crate::random::{RESTART, derive_key};
use serde::{Deserialize, Serialize};

/// The interval between two white-noise kicks, in mean free times at the state's
/// temperature: each grain collides with probability about 0.05 between two kicks, so the
/// kicks approximate the continuous noise closely, while the predictions recomputed at
/// every kick cost about as much as the collisions (`N` per kick). The bias this leaves on
/// `a2` and `T` is measured in `docs/edmd.md` (halving the interval).
pub(crate) const KICK_FRACTION: f64 = 0.05;

/// The interval between two rescalings, in mean free times at `T*`. A uniform scaling of
/// all peculiar velocities does not change the shape of the velocity distribution, and the
/// hard-core dynamics at another temperature is the same dynamics on another clock, so the
/// sampled state does not depend on this interval; it only bounds the temperature's
/// excursion between rescalings (`1 - exp(-zeta dt)`, 4 % at `e = 0.5`).
pub(crate) const RESCALE_FRACTION: f64 = 0.1;

/// A driving attached to the event-driven engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct EdmdDriving {
    /// The driving and its tally (the application count indexes the kick streams).
    pub state: DrivingState,
    /// Seed of the kick streams.
    pub seed: u64,
    /// Absolute time of the driving's attachment, `t_0`.
    pub start: f64,
    /// `dt_kick` (time units).
    pub interval: f64,
    /// Where the kick streams restarted after the grains were set from outside
    /// (`Edmd::restart`); `None` before any.
    #[serde(default)]
    pub restart: Option<DrivingRestart>,
}

/// The driving's state at a restart of the engine's grains (`Edmd::restart`): the kick
/// times start again from the restart time (`EdmdDriving::start`) and the kicks come from
/// the streams `(derive_key(seed, [RESTART, t]), [KICKS, k - applications, id])`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct DrivingRestart {
    /// The applications before the restart.
    pub applications: u64,
    /// The seed of the streams after it.
    pub seed: u64,
}

impl EdmdDriving {
    /// The driving attached at absolute time `start` to a gas of kinetic energy
    /// `kinetic_energy`, with kick streams under `seed`, applied every `interval` (a
    /// fraction of the mean free time at the state's temperature:
    /// [`crate::edmd::Edmd::kick_interval`]).
    pub(crate) fn new(
        driving: Driving,
        kinetic_energy: f64,
        seed: u64,
        start: f64,
        interval: f64,
    ) -> Self {
        Self {
            state: DrivingState::new(driving, kinetic_energy),
            seed,
            start,
            interval,
            restart: None,
        }
    }

    /// The driving carried over a restart of the grains at absolute time `time`: the
    /// same driving, interval and tally; kick times counted from `time` and kick streams
    /// keyed by `time` ([`crate::random::RESTART`]), whatever happened before.
    pub(crate) fn restarted(&self, time: f64) -> Self {
        Self {
            start: time,
            restart: Some(DrivingRestart {
                applications: self.state.applications,
                seed: derive_key(self.seed, &[RESTART, time.to_bits()]),
            }),
            ..self.clone()
        }
    }

    /// Applications since the start (or the last restart), and the seed of their streams.
    fn applications_and_seed(&self) -> (u64, u64) {
        match self.restart {
            Some(r) => (self.state.applications - r.applications, r.seed),
            None => (self.state.applications, self.seed),
        }
    }

    /// Absolute time of the next application.
    pub(crate) fn next_time(&self) -> f64 {
        let (k, _) = self.applications_and_seed();
        self.start + (k + 1) as f64 * self.interval
    }

    /// The white-noise kicks of the next application, for a noise of `strength`.
    pub(crate) fn kicks(&self, strength: f64) -> Kicks {
        let (k, seed) = self.applications_and_seed();
        Kicks::new(seed, k, strength, self.interval)
    }
}
