//! # granular
//!
//! Simulation of granular gases — many hard grains that collide and lose energy — with
//! three engines that share one set of physics modules:
//!
//! * [`edmd`]: event-driven molecular dynamics of hard disks (2D) and spheres (3D),
//!   after the hard-disk assignment (`event-driven-hard-disk-gas.txt`, equations HD-n);
//! * [`dsmc`]: Direct Simulation Monte Carlo of inelastic disks and spheres, after the
//!   Müller & Herrmann's DSMC paper (`dsmc-granular-matter.txt`, DSMC-n);
//! * [`intruder`]: Gillespie engines of an intruder in a bath (1D, the needle, and a DSMC
//!   twin), after the intruder paper (`gillespie-granular-intruder.txt`, G-n).
//!
//! Every engine is driven the same way: a [`Scenario`] (a TOML file, a string or built in
//! code) becomes a [`Simulation`], which is advanced to a time or until the scenario's
//! stop rule, and observed through a typed [`Observation`] (the same names in every
//! engine, no side effect on reading) and its particle state ([`Simulation::snapshot`]).
//! A [`Run`] records a simulation into a run directory through [`Output`]s; a user
//! attaches their own. `docs/library.md` is the tour; `docs/equations.md` maps every
//! numbered equation of the three documents to the function that implements it.
//!
//! ```
//! use granular::prelude::*;
//!
//! // 400 elastic disks at packing fraction 0.3 in a periodic box, from a string ...
//! let mut scenario = Scenario::from_toml(
//!     r#"
//!     engine = "edmd"
//!     dimension = 2
//!     box = { boundary = "periodic" }
//!     [[species]]
//!     name = "disk"
//!     count = 400
//!     packing_fraction = 0.3
//!     velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
//!     [stop]
//!     collisions_per_particle = 50
//!     "#,
//!     &[],
//! )?;
//! // ... changed in code ...
//! scenario.seed = 42;
//! let mut simulation = Simulation::new(scenario)?;
//! let start = simulation.observe();
//! simulation.run()?;
//! let end = simulation.observe();
//! // ... and observed: the compressibility factor Z = P / (n T) of the run, against the
//! // Henderson equation of state of hard disks.
//! let rates = end.rates_since(&start);
//! let z = rates.pressure / (400.0 * end.temperature);
//! let henderson = granular::theory::equilibrium::hard_disk_compressibility(0.3);
//! // (An illustration; the equation-of-state tests with their error bars are in tests/.)
//! assert!((z - henderson).abs() < 0.05 * henderson, "Z = {z}, Henderson {henderson}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Conventions, written once: lengths in units of the box (or of the scenario's length
//! unit), masses in units of the scenario's mass unit, Boltzmann's constant `k_B = 1`, so
//! a temperature is an energy, `T = m <|v|^2> / D` in `D` dimensions.

pub(crate) mod averaging;
#[doc(hidden)]
pub mod bench;
pub mod boundary;
pub(crate) mod build;
pub mod collision_law;
pub mod driving;
pub mod dsmc;
pub mod edmd;
pub mod engine;
pub mod grain_state;
mod host;
pub(crate) mod in_flight;
pub mod intruder;
pub(crate) mod moments;
pub(crate) mod neighbours;
pub mod observables;
mod observation;
pub mod output;
pub(crate) mod particles;
pub(crate) mod prefetch;
pub mod quadrature;
pub mod random;
pub mod run;
pub mod scenario;
pub(crate) mod setup;
pub mod simulation;
pub mod stats;
pub(crate) mod structure;
pub mod theory;
pub mod trajectory;
pub(crate) mod transport;
pub mod vector;

pub use boundary::{AxisKind, SimulationBox};
pub use observation::{DsmcCounters, Observation, Rates, SpeciesObservation};
pub use run::{Output, Run, RunError, Summary};
pub use scenario::{Scenario, ScenarioError};
pub use simulation::{Simulation, StopReason};
pub use vector::Vector;

/// The types a user of the library needs, in one import: `use granular::prelude::*;`.
pub mod prelude {
    pub use crate::engine::{EngineError, Progress, Snapshot};
    pub use crate::observation::{Observation, Rates, SpeciesObservation};
    pub use crate::run::{BuildError, Output, Run, RunError, Summary};
    pub use crate::scenario::{Scenario, ScenarioError};
    pub use crate::simulation::{Simulation, StopReason};
}
