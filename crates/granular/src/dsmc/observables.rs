//! Spatial observables of the DSMC engine. They are shared with the event-driven engine
//! and live in [`crate::observables`]; this module re-exports them for the DSMC API.

pub(crate) use crate::observables::{DensityMap, StructureFactor, density_map, structure_factor};
