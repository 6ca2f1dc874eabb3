//! Particle trajectories in the formats the standard viewers read: extended XYZ
//! ([`xyz`], OVITO, ASE), the LAMMPS text dump ([`lammps`], OVITO, ASE), GSD with the HOOMD
//! schema ([`gsd`], OVITO, HOOMD-blue, `gsd` on PyPI) and VTK PolyData with a `.pvd` time
//! index ([`vtk`], ParaView).
//!
//! Every frame carries the time, the box and its periodicity, and per grain its id,
//! species, position, velocity, radius and mass; a run of rough grains adds each grain's
//! angular velocity (and, in GSD, its moment of inertia: [`gsd`]), a smooth run writes
//! nothing about spin. The run directory's box is
//! `[0, L_0] x ... x [0, L_{D-1}]`; the formats keep that origin except GSD, whose HOOMD
//! schema centres the box on the origin (positions are shifted by `-L/2`). A 2D run is
//! written with `z = 0` (see each module for how the format marks it as two-dimensional).
//!
//! [`Writer`] appends frames to one file (or series) as a run goes, and can be cut back to
//! a checkpoint; `RunDir::export_trajectories` (in `run`) converts the `.npz` snapshots of an
//! existing run directory.

pub mod gsd;
pub mod lammps;
pub mod vtk;
mod writer;
pub mod xyz;

pub use writer::Writer;

use crate::engine::Snapshot;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

pub use crate::output::TrajectoryFormat as Format;

/// The simulation box as the trajectory formats see it: `[0, L_k]` along each axis, periodic
/// or walled.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// Edge lengths `L_k`, length units; one per dimension (2 or 3).
    pub lengths: Vec<f64>,
    /// Whether each axis is periodic (otherwise: hard walls).
    pub periodic: Vec<bool>,
}

impl Cell {
    /// The box of a many-grain scenario.
    pub fn from_scenario(scenario: &crate::Scenario) -> Cell {
        Cell {
            lengths: scenario.lengths(),
            periodic: scenario
                .axes()
                .iter()
                .map(|a| *a == crate::AxisKind::Periodic)
                .collect(),
        }
    }
}

/// The reduced moments of inertia `κ = 4I/(mσ²)` of a scenario's species, in the order of
/// `[[species]]`, when its grains are rough (`species[i].inertia` or the uniform grain's);
/// empty for smooth grains: what tells the trajectory formats to write angular velocities.
/// A rough run made smooth by its schedule keeps its spins in the snapshots, and its
/// trajectories keep writing them.
pub fn species_inertia(scenario: &crate::Scenario) -> Vec<f64> {
    if !scenario.collisions().law().is_rough() {
        return Vec::new();
    }
    let d = scenario.dimension;
    scenario
        .species()
        .iter()
        .map(|sp| {
            sp.inertia
                .unwrap_or(crate::collision_law::rough::uniform_inertia(d))
        })
        .collect()
}

/// One frame: a snapshot, its output index (the step) and the box.
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    /// Output index of the snapshot (`NNNNNN` of `snapshot_NNNNNN.npz`), written as the
    /// step or timestep where the format has one.
    pub step: u64,
    /// The state.
    pub snapshot: &'a Snapshot,
    /// The box.
    pub cell: &'a Cell,
    /// Rough grains: the reduced moment of inertia κ of each species
    /// ([`species_inertia`]); empty for smooth grains, whose frames carry no spin.
    pub inertia: &'a [f64],
}

impl Frame<'_> {
    /// Number of grains.
    pub fn len(&self) -> usize {
        self.snapshot.radii.len()
    }

    /// Whether there are no grains.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Spatial dimension of the run (2 or 3).
    pub fn dimension(&self) -> usize {
        self.snapshot.dimension
    }

    /// Position of grain `i` with three components (`z = 0` in 2D).
    pub fn position(&self, i: usize) -> [f64; 3] {
        pad(&self.snapshot.positions, self.dimension(), i)
    }

    /// Velocity of grain `i` with three components (`v_z = 0` in 2D).
    pub fn velocity(&self, i: usize) -> [f64; 3] {
        pad(&self.snapshot.velocities, self.dimension(), i)
    }

    /// Species name of grain `i`.
    pub fn species_name(&self, i: usize) -> &str {
        let s = self.snapshot.species[i] as usize;
        self.snapshot
            .species_names
            .get(s)
            .map_or("grain", String::as_str)
    }

    /// Edge lengths with three components; a 2D box gets the slab thickness
    /// [`Frame::slab`] along z.
    pub fn lengths3(&self) -> [f64; 3] {
        let l = &self.cell.lengths;
        [
            l[0],
            l.get(1).copied().unwrap_or(1.0),
            l.get(2).copied().unwrap_or_else(|| self.slab()),
        ]
    }

    /// Periodicity with three components (z of a 2D run: not periodic).
    pub fn periodic3(&self) -> [bool; 3] {
        let p = &self.cell.periodic;
        [
            p[0],
            p.get(1).copied().unwrap_or(false),
            p.get(2).copied().unwrap_or(false),
        ]
    }

    /// Thickness of the thin z range a 2D run is drawn in by the formats that need a 3D
    /// box: the largest grain diameter (1 without grains).
    pub fn slab(&self) -> f64 {
        let d = 2.0 * self.snapshot.radii.iter().copied().fold(0.0, f64::max);
        if d > 0.0 { d } else { 1.0 }
    }
}

/// Consecutive grains of a frame, in id order: the grains `first .. first + len()`.
#[derive(Clone, Copy, Debug)]
pub struct Piece<'a> {
    /// The id of the piece's first grain.
    pub first: usize,
    /// Spatial dimension.
    pub dimension: usize,
    /// Positions, `dimension` values per grain.
    pub positions: &'a [f64],
    /// Velocities, as the positions.
    pub velocities: &'a [f64],
    /// Radii.
    pub radii: &'a [f64],
    /// Masses.
    pub masses: &'a [f64],
    /// Species indices.
    pub species: &'a [u32],
    /// Angular velocities of rough grains, `d_r` values per grain (`ω_z` in 2D, three
    /// components in 3D); empty for smooth grains.
    pub angular_velocities: &'a [f64],
}

impl Piece<'_> {
    /// Grains in the piece.
    pub fn len(&self) -> usize {
        self.radii.len()
    }

    /// Whether the piece holds no grain.
    pub fn is_empty(&self) -> bool {
        self.radii.is_empty()
    }

    /// Position of the piece's grain `i` with three components (`z = 0` in 2D).
    pub fn position(&self, i: usize) -> [f64; 3] {
        pad(self.positions, self.dimension, i)
    }

    /// Velocity of the piece's grain `i` with three components.
    pub fn velocity(&self, i: usize) -> [f64; 3] {
        pad(self.velocities, self.dimension, i)
    }

    /// Angular velocity of the piece's grain `i` with three components (`(0, 0, ω_z)` in
    /// 2D); zero when the piece carries no angular velocities.
    pub fn angular_velocity(&self, i: usize) -> [f64; 3] {
        let w = self.angular_velocities;
        if self.dimension == 2 {
            [0.0, 0.0, w.get(i).copied().unwrap_or(0.0)]
        } else {
            let mut out = [0.0; 3];
            if let Some(s) = w.get(3 * i..3 * i + 3) {
                out.copy_from_slice(s);
            }
            out
        }
    }
}

/// The grains of a frame produced piece by piece, in id order (every call from the first
/// grain): a whole snapshot is one piece; a decomposed run's rank 0 reads the ranks'
/// blocks of ids a piece at a time, so that a frame is written in memory independent of
/// the number of grains.
pub trait Pieces {
    /// Calls `f` with consecutive pieces covering every grain once, in id order.
    fn each(&self, f: &mut dyn FnMut(&Piece<'_>) -> std::io::Result<()>) -> std::io::Result<()>;
}

impl Pieces for Snapshot {
    fn each(&self, f: &mut dyn FnMut(&Piece<'_>) -> std::io::Result<()>) -> std::io::Result<()> {
        f(&Piece {
            first: 0,
            dimension: self.dimension,
            positions: &self.positions,
            velocities: &self.velocities,
            radii: &self.radii,
            masses: &self.masses,
            species: &self.species,
            angular_velocities: &self.angular_velocities,
        })
    }
}

/// A frame whose grains are read piece by piece ([`Pieces`]): what every format writer
/// writes. [`Frame::rows`] gives the rows of a whole snapshot.
#[derive(Clone, Copy)]
pub struct Rows<'a> {
    /// Output index (the step).
    pub step: u64,
    /// Simulation time.
    pub time: f64,
    /// Spatial dimension.
    pub dimension: usize,
    /// Number of grains.
    pub n: usize,
    /// Species names.
    pub species_names: &'a [String],
    /// The largest grain radius (the slab thickness of a 2D frame is its diameter).
    pub max_radius: f64,
    /// The box.
    pub cell: &'a Cell,
    /// Rough grains: κ of each species ([`species_inertia`]); empty for smooth grains.
    pub inertia: &'a [f64],
    /// The grains.
    pub grains: &'a dyn Pieces,
}

impl Rows<'_> {
    /// Edge lengths with three components; a 2D box gets the slab thickness
    /// [`Rows::slab`] along z.
    pub fn lengths3(&self) -> [f64; 3] {
        let l = &self.cell.lengths;
        [
            l[0],
            l.get(1).copied().unwrap_or(1.0),
            l.get(2).copied().unwrap_or_else(|| self.slab()),
        ]
    }

    /// Periodicity with three components (z of a 2D run: not periodic).
    pub fn periodic3(&self) -> [bool; 3] {
        let p = &self.cell.periodic;
        [
            p[0],
            p.get(1).copied().unwrap_or(false),
            p.get(2).copied().unwrap_or(false),
        ]
    }

    /// Thickness of the thin z range a 2D run is drawn in: the largest grain diameter (1
    /// without grains).
    pub fn slab(&self) -> f64 {
        let d = 2.0 * self.max_radius;
        if d > 0.0 { d } else { 1.0 }
    }

    /// Name of species `s`.
    pub fn species_name(&self, s: u32) -> &str {
        self.species_names
            .get(s as usize)
            .map_or("grain", String::as_str)
    }

    /// Whether the grains are rough: the frame carries their angular velocities.
    pub fn is_rough(&self) -> bool {
        !self.inertia.is_empty()
    }

    /// The principal moment of inertia `I = κ m R²` of a grain of species `s`, mass `m`
    /// and radius `R` (0 for smooth grains).
    pub fn moment_of_inertia(&self, s: u32, mass: f64, radius: f64) -> f64 {
        let kappa = self.inertia.get(s as usize).copied().unwrap_or(0.0);
        crate::collision_law::rough::Body {
            mass,
            radius,
            inertia: kappa,
        }
        .moment_of_inertia()
    }
}

impl Frame<'_> {
    /// The frame as rows read in one piece.
    pub fn rows(&self) -> Rows<'_> {
        Rows {
            step: self.step,
            time: self.snapshot.time,
            dimension: self.dimension(),
            n: self.len(),
            species_names: &self.snapshot.species_names,
            max_radius: self.snapshot.radii.iter().copied().fold(0.0, f64::max),
            cell: self.cell,
            inertia: self.inertia,
            grains: self.snapshot,
        }
    }
}

fn pad(values: &[f64], dimension: usize, i: usize) -> [f64; 3] {
    let mut out = [0.0; 3];
    out[..dimension].copy_from_slice(&values[i * dimension..(i + 1) * dimension]);
    out
}

/// Why a trajectory could not be written or exported.
#[derive(Debug, thiserror::Error)]
pub enum TrajectoryError {
    /// The file system failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A snapshot could not be read.
    #[error(transparent)]
    Npz(#[from] crate::output::npz::NpzError),
    /// The run directory cannot be exported (intruder engine, no snapshots, no scenario).
    #[error("{0}")]
    Export(String),
}

pub(crate) fn io_err(
    path: &std::path::Path,
) -> impl FnOnce(std::io::Error) -> TrajectoryError + '_ {
    move |source| TrajectoryError::Io {
        path: path.to_path_buf(),
        source,
    }
}

#[cfg(test)]
pub(crate) mod test_frame {
    use super::*;

    /// Two grains of two species in a 2D box periodic along x, walled along y.
    pub fn snapshot_2d() -> (Snapshot, Cell) {
        let snap = Snapshot {
            time: 0.25,
            dimension: 2,
            positions: vec![0.1, 0.2, 0.7, 0.4],
            velocities: vec![1.0, -0.5, 0.125, 2.0],
            radii: vec![0.01, 0.02],
            masses: vec![1.0, 4.0],
            species: vec![0, 1],
            species_names: vec!["bath".into(), "intruder".into()],
            ..Default::default()
        };
        let cell = Cell {
            lengths: vec![1.0, 0.5],
            periodic: vec![true, false],
        };
        (snap, cell)
    }

    /// [`snapshot_2d`] with rough grains: their `ω_z` and κ of the two species.
    pub fn rough_2d() -> (Snapshot, Cell, Vec<f64>) {
        let (mut snap, cell) = snapshot_2d();
        snap.angular_velocities = vec![3.5, -0.25];
        (snap, cell, vec![0.5, 0.25])
    }

    /// Two rough spheres of two species in a 3D box, spinning about every axis.
    pub fn rough_3d() -> (Snapshot, Cell, Vec<f64>) {
        let snap = Snapshot {
            time: 0.5,
            dimension: 3,
            positions: vec![0.1, 0.2, 0.3, 0.7, 0.4, 0.1],
            velocities: vec![1.0, -0.5, 0.25, 0.125, 2.0, -1.0],
            radii: vec![0.01, 0.02],
            masses: vec![1.0, 4.0],
            species: vec![0, 1],
            species_names: vec!["bath".into(), "intruder".into()],
            angular_velocities: vec![1.5, -2.0, 0.75, 0.0, 10.0, -4.0],
        };
        let cell = Cell {
            lengths: vec![1.0, 0.5, 0.5],
            periodic: vec![true, false, true],
        };
        (snap, cell, vec![0.4, 2.0 / 3.0])
    }
}
