//! # granular
//!
//! Simulation of granular gases — many hard grains that collide and lose energy — with
//! three engines that share one set of physics modules:
//!
//! * [`edmd`]: event-driven molecular dynamics of hard disks (2D) and spheres (3D),
//!   after the hard-disk seed (`event-driven-hard-disk-gas.txt`);
//!
//! Conventions, written once: lengths in units of the box (or of the scenario's length
//! unit), masses in units of the scenario's mass unit, Boltzmann's constant `k_B = 1`, so
//! a temperature is an energy, `T = m <|v|^2> / D` in `D` dimensions.

pub mod boundary;
pub mod collision_law;
pub mod dsmc;
pub mod edmd;
pub mod engine;
pub mod intruder;
pub mod observables;
pub mod observation;
pub mod output;
pub mod quadrature;
pub mod random;
pub mod run;
pub mod scenario;
pub mod simulation;
pub mod stats;
pub mod theory;
pub mod vector;

pub use boundary::{AxisKind, SimulationBox};
pub use observation::{Observation, Rates, SpeciesObservation};
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
