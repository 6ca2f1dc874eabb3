//! The species of a DSMC engine's grains: their names and the id range of each (species
//! are contiguous in id order, as the set-up numbers the grains, `setup`).

use serde::{Deserialize, Serialize};

/// The species of an engine's grains: names, and the id ranges (species are contiguous
/// in id order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct SpeciesTable {
    /// Names, in id order.
    pub names: Vec<String>,
    /// One past the last id of each species.
    pub ends: Vec<u32>,
}

impl SpeciesTable {
    /// One species of `n` grains called `name`.
    pub(crate) fn one(name: &str, n: usize) -> SpeciesTable {
        SpeciesTable {
            names: vec![name.to_string()],
            ends: vec![n as u32],
        }
    }

    /// The species of grain `id`.
    #[inline]
    pub(crate) fn of(&self, id: u32) -> u32 {
        (self.ends.partition_point(|&e| e <= id) as u32).min(self.names.len() as u32 - 1)
    }
}
