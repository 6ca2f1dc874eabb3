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
pub(crate) struct Trajectory {
    #[serde(skip)]
    dir: PathBuf,
    formats: Vec<Format>,
    every: u64,
    cell: Option<Cell>,
    writers: Vec<Writer>,
    /// Over ranks: the trajectory folder of the run directory every rank sees, where the
    /// ranks put their blocks of grains for rank 0.
    #[serde(skip)]
    shared: Option<PathBuf>,
    /// Rough grains: κ of each species ([`crate::trajectory::species_inertia`]); empty for
    /// smooth grains (and absent from their checkpoints).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    inertia: Vec<f64>,
}

impl Trajectory {
    /// Trajectories in `formats` into `dir/trajectory/`, a frame every `every` outputs (0:
    /// only the first and the last), as for the snapshots.
    pub(crate) fn new(dir: &Path, formats: &[Format], every: u64) -> Trajectory {
        Trajectory {
            dir: dir.join(crate::run::dir::TRAJECTORY),
            formats: formats.to_vec(),
            every,
            cell: None,
            writers: Vec::new(),
            shared: None,
            inertia: Vec::new(),
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.join(crate::run::dir::TRAJECTORY);
        for w in &mut self.writers {
            w.relocate(&self.dir);
        }
    }

    /// Makes a decomposed run's ranks put their blocks of grains into `dir`'s trajectory
    /// folder (the run directory every rank sees).
    pub(crate) fn share(&mut self, dir: &Path) {
        self.shared = Some(crate::run::RunDir::new(dir).trajectory_dir());
    }

    /// Cuts the files back to the frames written before the checkpoint.
    pub(crate) fn rewind(&self) -> Result<(), RunError> {
        self.writers
            .iter()
            .try_for_each(|w| w.rewind().map_err(RunError::from))
    }

    fn write(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        let Some(cell) = &self.cell else {
            return Ok(());
        };
        if simulation.engine().domain().is_some() {
            // Over ranks: rank 0 writes every format from the ranks' blocks of ids, a
            // piece at a time; the other ranks write nothing.
            let folder = self.shared.as_ref().unwrap_or(&self.dir);
            let base = folder.join(format!("frame_{:06}", simulation.outputs_done()));
            let writers = &mut self.writers;
            let inertia = &self.inertia;
            return crate::run::parts::with_blocks(simulation.engine(), &base, |blocks| {
                let rows = crate::trajectory::Rows {
                    step: simulation.outputs_done(),
                    time: blocks.time,
                    dimension: blocks.dimension,
                    n: blocks.n,
                    species_names: &blocks.species.names,
                    max_radius: blocks.radius,
                    cell,
                    inertia,
                    grains: blocks,
                };
                for w in writers.iter_mut() {
                    w.append_rows(&rows)?;
                }
                Ok(())
            });
        }
        let Some(snapshot) = simulation.snapshot() else {
            return Ok(());
        };
        let frame = Frame {
            step: simulation.outputs_done(),
            snapshot: &snapshot,
            cell,
            inertia: &self.inertia,
        };
        for w in &mut self.writers {
            w.append(&frame)?;
        }
        Ok(())
    }
}

impl Output for Trajectory {
    /// Opens the files. Over ranks, only rank 0 writes them, from the ranks' blocks of
    /// grain ids (no rank gathers a frame).
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        self.cell = Some(Cell::from_scenario(simulation.scenario()));
        self.inertia = crate::trajectory::species_inertia(simulation.scenario());
        let rough = !self.inertia.is_empty();
        self.writers = self
            .formats
            .iter()
            .map(|f| Writer::create(*f, &self.dir, rough))
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
