//! The inelastic-collapse detector: a window of events that advances the time by far
//! less than those events would take at the typical collision rate. A collapse is
//! reported as typed data ([`Collapse`], with its [`CollapseRemedy`]); the scenario layer
//! words the advice in its keys.

use super::Edmd;
use crate::engine::{Collapse, CollapseRemedy, EngineError};
use serde::{Deserialize, Serialize};

/// Inelastic-collapse detector state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(super) struct CollapseWatch {
    pub(super) window_start_events: u64,
    pub(super) window_start_time: f64,
    /// Pair collisions and time since the start of the run at the starts of the last two
    /// windows (the earlier one first), for the mean free time before a collapse: the
    /// collapse's own collisions, in the window that detects it and perhaps the one before,
    /// would shrink it by orders of magnitude. Only for the report of a collapse, so not in
    /// checkpoints: the first windows after a resume fall back to the run's mean free time.
    #[serde(skip)]
    pub(super) starts: [Option<(u64, f64)>; 2],
}

/// Events per collapse-detector window in systems of up to 2^14 grains; larger ones
/// watch over 4 events per grain ([`Edmd::collapse_window`]).
pub(super) const COLLAPSE_WINDOW: u64 = 1 << 16;

impl<const D: usize> Edmd<D> {
    /// Events per collapse-detector window: at least 4 per grain, because each check
    /// reads every grain (the kinetic energy and the total mass). With a fixed 2^16, 10^6
    /// inelastic disks spent 14 % of their time on those reads and the cache misses after
    /// them.
    pub(super) fn collapse_window(&self) -> u64 {
        COLLAPSE_WINDOW.max(4 * self.len() as u64)
    }

    pub(super) fn check_collapse(&mut self) -> Result<(), EngineError> {
        let events = self.totals.events - self.collapse.window_start_events;
        if events < self.collapse_window() {
            return Ok(());
        }
        let elapsed = self.now - self.collapse.window_start_time;
        self.collapse.window_start_events = self.totals.events;
        self.collapse.window_start_time = self.now;
        let before = self.collapse.starts[0];
        self.collapse.starts = [
            self.collapse.starts[1],
            Some((self.totals.pair_collisions, self.origin + self.now)),
        ];
        if self.law.is_elastic() || self.growth != 0.0 {
            return Ok(());
        }
        let total_mass: f64 = (0..self.len()).map(|s| self.mass(s)).sum();
        let v_typ = (2.0 * self.kinetic_energy_now() / total_mass).sqrt();
        // Grains all at rest have no time scale, unless their events took no time at all
        // (a grain stopped on a perfectly inelastic floor under gravity).
        if v_typ == 0.0 && elapsed > 0.0 {
            return Ok(());
        }
        // Time those events take at one collision per grain per time a grain needs to
        // cross its own diameter at the typical speed: a generous upper bound on rates.
        let natural = events as f64 / self.len() as f64 * 2.0 * self.min_radius / v_typ;
        if elapsed < self.options.collapse_ratio * natural {
            // The mean free time up to two windows ago, before the collapse began.
            let tau = match before {
                Some((c, t)) if c > 0 => self.len() as f64 * t / (2.0 * c as f64),
                _ => self.mean_free_time_so_far(),
            };
            let tau = if tau.is_finite() {
                tau
            } else {
                2.0 * self.min_radius / v_typ
            };
            return Err(EngineError::Collapse(Box::new(Collapse {
                time: self.origin + self.now,
                events,
                elapsed,
                restitution: self.law.restitution,
                mean_free_time: tau,
                remedy: self.collapse_remedy(tau),
                advice: None,
            })));
        }
        Ok(())
    }

    /// What would stop a collapse, given the mean free time `tau` before it
    /// ([`CollapseRemedy`]): without the TC model `t_c` = 10^-3 `tau` for a freely cooling
    /// gas, and 0.1 `tau` under gravity; with the model on, ten times its `t_c`; under
    /// gravity towards a wall of restitution 0, a wall restitution above 0.
    pub(super) fn collapse_remedy(&self, tau: f64) -> CollapseRemedy {
        let t_c = self.law.contact_duration;
        let falls_on_a_wall = (0..D).any(|k| self.gravity[k] != 0.0 && !self.bx.is_periodic(k));
        if falls_on_a_wall && self.law.wall_restitution == 0.0 {
            // A grain that lands keeps no normal velocity, gravity presses it into the wall
            // again at once, and an elastic reflection of nothing is nothing: no t_c helps.
            CollapseRemedy::WallRestitutionAboveZero
        } else if t_c > 0.0 {
            CollapseRemedy::LongerContactDuration {
                contact_duration: t_c,
                advised: 10.0 * t_c,
            }
        } else if self.has_gravity {
            CollapseRemedy::EnableContactDuration {
                advised: 0.1 * tau,
                under_gravity: true,
            }
        } else {
            CollapseRemedy::EnableContactDuration {
                advised: 1e-3 * tau,
                under_gravity: false,
            }
        }
    }
}
