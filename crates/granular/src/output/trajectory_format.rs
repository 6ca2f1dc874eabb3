//! The trajectory formats by name: what `[output] trajectory` and `granular export
//! --format` accept. The writers are in the `trajectory` module (which re-exports this type as
//! `trajectory::Format`); the name list lives here, below both the scenario format and
//! the writers.

use serde::{Deserialize, Serialize};

/// A trajectory format (`[output] trajectory`, `granular export --format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrajectoryFormat {
    /// Extended XYZ, `trajectory/trajectory.xyz`.
    Xyz,
    /// LAMMPS text dump, `trajectory/trajectory.lammpstrj`.
    Lammps,
    /// GSD (HOOMD schema), `trajectory/trajectory.gsd`.
    Gsd,
    /// VTK PolyData, `trajectory/vtp/snapshot_NNNNNN.vtp` indexed by `trajectory/trajectory.pvd`.
    Vtk,
}

impl TrajectoryFormat {
    /// Every format, in the order of the documentation.
    pub const ALL: [TrajectoryFormat; 4] = [
        TrajectoryFormat::Xyz,
        TrajectoryFormat::Lammps,
        TrajectoryFormat::Gsd,
        TrajectoryFormat::Vtk,
    ];

    /// The name in scenario files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            TrajectoryFormat::Xyz => "xyz",
            TrajectoryFormat::Lammps => "lammps",
            TrajectoryFormat::Gsd => "gsd",
            TrajectoryFormat::Vtk => "vtk",
        }
    }

    /// The format named `s` (`"xyz"`, `"lammps"`, `"gsd"`, `"vtk"`).
    pub fn parse(s: &str) -> Result<TrajectoryFormat, String> {
        TrajectoryFormat::ALL
            .into_iter()
            .find(|f| f.name() == s.trim())
            .ok_or_else(|| format!("unknown trajectory format `{s}`; use xyz, lammps, gsd or vtk"))
    }

    /// The file (relative to the trajectory folder) a viewer opens.
    pub(crate) fn file_name(self) -> &'static str {
        match self {
            TrajectoryFormat::Xyz => "trajectory.xyz",
            TrajectoryFormat::Lammps => "trajectory.lammpstrj",
            TrajectoryFormat::Gsd => "trajectory.gsd",
            TrajectoryFormat::Vtk => "trajectory.pvd",
        }
    }
}
