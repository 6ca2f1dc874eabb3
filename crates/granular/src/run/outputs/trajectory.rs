//! `trajectory/`: the snapshots, as the run goes, in the viewer formats of
//! `output.trajectory` ([`crate::trajectory`]), written at the same output times as
//! `snapshots/snapshot_NNNNNN.npz`.

use super::Output;
use crate::observation::Observation;
use crate::run::{RunError, Summary};
use crate::simulation::Simulation;
use crate::trajectory::{Cell, Format, Frame, Writer};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Trajectories in one or more formats (extended XYZ, LAMMPS dump, GSD, VTK).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Trajectory {
    #[serde(skip)]
    dir: PathBuf,
    formats: Vec<Format>,
    every: u64,
    cell: Option<Cell>,
    writers: Vec<Writer>,
}

impl Trajectory {
    /// Trajectories in `formats` into `dir/trajectory/`, a frame every `every` outputs (0:
    /// only the first and the last), as for the snapshots.
    pub fn new(dir: &Path, formats: &[Format], every: u64) -> Trajectory {
        Trajectory {
            dir: dir.join("trajectory"),
            formats: formats.to_vec(),
            every,
            cell: None,
            writers: Vec::new(),
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.join("trajectory");
        for w in &mut self.writers {
            w.relocate(&self.dir);
        }
    }

    /// Cuts the files back to the frames written before the checkpoint.
    pub(crate) fn rewind(&self) -> Result<(), RunError> {
        self.writers
            .iter()
            .try_for_each(|w| w.rewind().map_err(RunError::from))
    }

    /// The files a viewer opens, one per format.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.writers.iter().map(Writer::path).collect()
    }

    fn write(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        let (Some(snapshot), Some(cell)) = (simulation.snapshot(), &self.cell) else {
            return Ok(());
        };
        let frame = Frame {
            step: simulation.outputs_done(),
            snapshot: &snapshot,
            cell,
        };
        for w in &mut self.writers {
            w.append(&frame)?;
        }
        Ok(())
    }
}

impl Output for Trajectory {
    /// Opens the files; refuses a run over ranks above
    /// `GATHER_LIMIT` (10^6) grains (every rank gathers each frame).
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        crate::run::grains::refuse_whole_gather(simulation, "output.trajectory")?;
        self.cell = Some(Cell::from_scenario(simulation.scenario()));
        self.writers = self
            .formats
            .iter()
            .map(|f| Writer::create(*f, &self.dir))
            .collect::<Result<_, _>>()?;
        Ok(())
    }

    fn observe(&mut self, simulation: &Simulation, _: &Observation) -> Result<(), RunError> {
        let k = simulation.outputs_done();
        if k == 0 || (self.every > 0 && k.is_multiple_of(self.every)) {
            self.write(simulation)?;
        }
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, _: &mut Summary) -> Result<(), RunError> {
        let k = simulation.outputs_done();
        if self.every == 0 || !k.is_multiple_of(self.every) {
            self.write(simulation)?;
        }
        Ok(())
    }
}
