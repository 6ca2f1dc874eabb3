//! The interface every engine (event-driven MD, DSMC, Gillespie intruder) offers to the
//! [`Simulation`](crate::Simulation). Engines know nothing of files, terminals, threads or
//! plots: they advance, and they are observed.

use serde::{Deserialize, Serialize};

/// Why an engine could not continue.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// Inelastic collapse: events pile up in a vanishing time interval.
    #[error("{0}")]
    Collapse(Box<Collapse>),
    /// The state became inconsistent (a bug or a numerical breakdown); the message says which.
    #[error("{0}")]
    Numerical(String),
}

/// An inelastic collapse, as the event-driven engine detects it: a window of `events`
/// events advanced the time by only `elapsed` (grains collide ever faster in a shrinking
/// cluster; `docs/edmd.md`, "Inelastic collapse").
#[derive(Clone, Debug, PartialEq)]
pub struct Collapse {
    /// Time of the detection (the engine's absolute time).
    pub time: f64,
    /// Events of the window that detected it.
    pub events: u64,
    /// Time those events advanced.
    pub elapsed: f64,
    /// Restitution of the pair collisions.
    pub restitution: f64,
    /// Mean free time of a grain before the collapse began (measured up to two windows
    /// before the one that detected it), time units.
    pub mean_free_time: f64,
    /// What would stop it.
    pub remedy: CollapseRemedy,
    /// The remedy in the words of the input that set the engine up (the scenario's keys),
    /// added by that layer ([`Simulation`](crate::Simulation)); `None` from the engine.
    pub advice: Option<String>,
}

/// What would stop an inelastic collapse. Collisions closer than the contact duration
/// `t_c` of the TC model are elastic (section 2.3 of the hard-disk assignment), so every remedy
/// but the first trades some dissipation for stability.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CollapseRemedy {
    /// Gravity presses grains onto a wall of restitution 0: a grain that lands keeps no
    /// normal velocity and hits the wall again at zero intervals, which no TC model can
    /// stop; a wall restitution above 0 does.
    WallRestitutionAboveZero,
    /// The TC model is on with `contact_duration` but too short: `advised` is ten times
    /// longer (one taken from the mean free time could be shorter than the one that
    /// failed, when the collapse has shrunk it).
    LongerContactDuration {
        /// The present `t_c`, time units.
        contact_duration: f64,
        /// Ten times `contact_duration`.
        advised: f64,
    },
    /// The TC model is off: it would stop the collapse with the contact duration
    /// `advised`, 10^-3 of the mean free time in a freely cooling gas and 0.1 of it under
    /// gravity, where the grains come to rest in a bed that rattles ever faster (there
    /// 10^-3 only delays the collapse until the bed forms; measured in `docs/edmd.md`).
    EnableContactDuration {
        /// The advised `t_c`, time units.
        advised: f64,
        /// Whether the grains are under gravity.
        under_gravity: bool,
    },
}

impl std::fmt::Display for Collapse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "inelastic collapse at t = {:.6e}: the last {} events advanced the time by only \
             {:.3e} (grains collide ever faster in a shrinking cluster; restitution {}).",
            self.time, self.events, self.elapsed, self.restitution
        )?;
        if let Some(advice) = &self.advice {
            write!(f, " {advice}")?;
        }
        Ok(())
    }
}

/// How far a call to [`Engine::advance`] got.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// The engine reached the requested time.
    Reached,
    /// The event budget ran out first; the engine stopped at an event before the requested time.
    BudgetExhausted,
}

pub use crate::observation::Observation;
use crate::stats::Histogram;

/// Position/velocity snapshot of all particles (row-major `n x dimension` arrays).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Snapshot {
    /// Simulation time of the snapshot.
    pub time: f64,
    /// Spatial dimension (columns of `positions` and `velocities`).
    pub dimension: usize,
    /// Positions, `n * dimension` values.
    pub positions: Vec<f64>,
    /// Velocities, `n * dimension` values.
    pub velocities: Vec<f64>,
    /// Radius of each particle.
    pub radii: Vec<f64>,
    /// Mass of each particle.
    pub masses: Vec<f64>,
    /// Species index of each particle.
    pub species: Vec<u32>,
    /// Species names, indexed by the values of `species`.
    pub species_names: Vec<String>,
    /// Angular velocities of rough grains, `n * d_r` values (`d_r` = 1 in 2D: `ω_z`; 3 in
    /// 3D), radians per time unit; empty for smooth grains.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub angular_velocities: Vec<f64>,
}

/// The common interface of all engines.
pub trait Engine {
    /// Short engine name as written in `summary.json` (`"edmd"`, `"dsmc"`, `"intruder"`).
    fn name(&self) -> &'static str;

    /// Current simulation time, in the scenario's time unit.
    fn time(&self) -> f64;

    /// Number of events processed so far (collisions and bookkeeping events).
    fn events(&self) -> u64;

    /// Number of collisions so far (pair collisions for many-particle engines; for the
    /// intruder, intruder-bath collisions).
    fn collisions(&self) -> u64;

    /// Number of particles (1 for a single intruder).
    fn particle_count(&self) -> usize;

    /// Advances the state to exactly `until` (an output time), processing at most
    /// `max_events` events; returns [`Progress::BudgetExhausted`] if it stopped early so the
    /// caller can check wall-clock limits and report progress, then call again.
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError>;

    /// What the engine observes at the current time: the same typed quantities in every
    /// engine. Reading it has no side effect (rates over a window come from two
    /// observations, [`Observation::rates_since`]).
    fn observe(&self) -> Observation;

    /// Total kinetic energy at the current time (used by the energy stopping rule).
    fn kinetic_energy(&self) -> f64;

    /// Histogram of the normalised impact parameter `b / σ` of all pair collisions so far
    /// (many-grain engines).
    fn impact_histogram(&self) -> Option<Histogram> {
        None
    }

    /// Positions (`velocities = false`) or velocities of every grain, row-major by grain
    /// id (input order) into `out` (`n × D` values); `false` when the engine has no grains.
    /// Faster than a snapshot for one array: the engines read their records in storage
    /// order and scatter them by id.
    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        match self.snapshot() {
            Some(s) => {
                let v = if velocities {
                    s.velocities
                } else {
                    s.positions
                };
                out.copy_from_slice(&v);
                true
            }
            None => false,
        }
    }

    /// Positions and velocities at the current time, when the engine has particles.
    fn snapshot(&self) -> Option<Snapshot> {
        None
    }
}
