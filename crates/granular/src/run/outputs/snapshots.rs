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
pub(crate) struct Snapshots {
    #[serde(skip)]
    dir: PathBuf,
    every: u64,
    written: u64,
    /// The snapshots folder every rank of a decomposed run writes into.
    #[serde(skip)]
    shared: Option<PathBuf>,
}

impl Snapshots {
    /// Snapshots into `dir/snapshots/`, one every `every` outputs (0: only the first and
    /// the last).
    pub(crate) fn new(dir: &Path, every: u64) -> Snapshots {
        Snapshots {
            dir: dir.join(crate::run::dir::SNAPSHOTS),
            every,
            written: 0,
            shared: None,
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.join(crate::run::dir::SNAPSHOTS);
    }

    pub(crate) fn share(&mut self, dir: &Path) {
        self.shared = Some(dir.join(crate::run::dir::SNAPSHOTS));
    }

    fn write(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        let name = crate::run::dir::snapshot_name(simulation.outputs_done());
        if simulation.engine().domain().is_some() {
            // Every rank its block of grain ids, into the one file (collective).
            let dir = self.shared.as_ref().unwrap_or(&self.dir);
            crate::run::parts::write_snapshot(simulation.engine(), &dir.join(name))?;
            self.written += 1;
        } else if let Some(snap) = simulation.snapshot() {
            write_snapshot(self.dir.join(name), &snap)?;
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
