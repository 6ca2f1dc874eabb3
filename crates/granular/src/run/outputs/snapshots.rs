//! `snapshots/snapshot_NNNNNN.npz`: the state at `t = 0`, every `output.snapshot_every`
//! outputs, and at the end; `NNNNNN` is the output index.

use super::Output;
use crate::observation::Observation;
use crate::output::npz::write_snapshot;
use crate::run::{RunError, Summary};
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Snapshots of positions, velocities, radii, masses and species (NumPy `.npz`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshots {
    #[serde(skip)]
    dir: PathBuf,
    every: u64,
    written: u64,
}

impl Snapshots {
    /// Snapshots into `dir/snapshots/`, one every `every` outputs (0: only the first and
    /// the last).
    pub fn new(dir: &Path, every: u64) -> Snapshots {
        Snapshots {
            dir: dir.join("snapshots"),
            every,
            written: 0,
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.join("snapshots");
    }

    /// Snapshots written so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    fn write(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if let Some(snap) = simulation.snapshot() {
            let index = simulation.outputs_done();
            write_snapshot(self.dir.join(format!("snapshot_{index:06}.npz")), &snap)?;
            self.written += 1;
        }
        Ok(())
    }
}

impl Output for Snapshots {
    fn setup(&mut self, _: &Simulation) -> Result<(), RunError> {
        std::fs::create_dir_all(&self.dir).map_err(crate::run::io_err(&self.dir))
    }

    fn observe(&mut self, simulation: &Simulation, _: &Observation) -> Result<(), RunError> {
        let k = simulation.outputs_done();
        if k == 0 || (self.every > 0 && k.is_multiple_of(self.every)) {
            self.write(simulation)?;
        }
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let k = simulation.outputs_done();
        if self.every == 0 || !k.is_multiple_of(self.every) {
            self.write(simulation)?;
        }
        summary.snapshots = self.written;
        Ok(())
    }
}
