//! `initial_state.npz`: the per-grain arrays of a run's scenario that did not come as
//! scenario text (NumPy arrays given through the Python package, members of an `.npz` file
//! elsewhere), kept in the run directory so that it is complete and its `scenario.toml`
//! runs again, bit for bit, from any working directory.

use super::{RunDir, RunFile};
use crate::output::npz::{NpzArray, write_npz};
use crate::run::RunError;
use crate::scenario::{GrainVectors, Scenario, VectorSource};

impl RunDir {
    /// Writes the arrays of `scenario` that were given by a program or read from an `.npz`
    /// file to `initial_state.npz` (members named by their keys, e.g.
    /// `species[0].positions`), and returns the scenario that names them there; arrays
    /// written inline in the scenario stay inline, and a scenario without such arrays is
    /// returned unchanged (and no file is written).
    pub(crate) fn store_initial_state(&self, scenario: Scenario) -> Result<Scenario, RunError> {
        let (mut bare, arrays) = scenario.without_arrays();
        let elsewhere = |v: &GrainVectors| !matches!(v.source(), VectorSource::Inline);
        if !arrays.iter().any(|(_, v)| elsewhere(v)) {
            return Ok(scenario);
        }
        let name = RunFile::InitialState.name();
        let mut members = Vec::new();
        for (key, v) in arrays.iter().filter(|(_, v)| elsewhere(v)) {
            members.push((
                key.as_str(),
                NpzArray::f64_2d(v.values().to_vec(), v.len(), v.width())?,
            ));
        }
        write_npz(self.file(RunFile::InitialState), &members)?;
        for (key, v) in &arrays {
            let kept = if elsewhere(v) {
                v.stored_in(name, key)
            } else {
                v.clone()
            };
            bare.put_array(key, kept)
                .map_err(|e| RunError::Build(crate::build::BuildError::Scenario(e)))?;
        }
        Ok(bare)
    }
}
