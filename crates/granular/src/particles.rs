//! The grains of a simulation as plain arrays, in input order: what every engine is
//! built from and what it can hand back.

use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// Everything that defines the grains at the start of a run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ParticleSet<const D: usize> {
    /// Centre positions, inside the box.
    pub positions: Vec<Vector<D>>,
    /// Velocities.
    pub velocities: Vec<Vector<D>>,
    /// Radii (> 0).
    pub radii: Vec<f64>,
    /// Masses (> 0).
    pub masses: Vec<f64>,
    /// Species index of each grain into `species_names`.
    pub species: Vec<u32>,
    /// Species names.
    pub species_names: Vec<String>,
}

impl<const D: usize> ParticleSet<D> {
    /// Number of grains.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}
