//! `granular export`: the `.npz` snapshots of an existing run directory as trajectories.

use super::{RunDir, RunFile};
use crate::scenario::{EngineKind, Scenario};
use crate::trajectory::{Cell, Format, Frame, TrajectoryError, Writer, species_inertia};
use std::path::PathBuf;

/// Writes the snapshots `run/snapshots/snapshot_NNNNNN.npz`, in the order of `NNNNNN`, to
/// `run/trajectory/` in each of `formats` (an earlier trajectory of the same format is
/// replaced) and returns the files a viewer opens. The box comes from the run's resolved
/// `scenario.toml`. Fails, naming the fix, for a run of the intruder engine (it has no
/// grain positions) and for a directory without snapshots.
pub(super) fn export(run: &RunDir, formats: &[Format]) -> Result<Vec<PathBuf>, TrajectoryError> {
    let scenario_path = run.file(RunFile::Scenario);
    let text = std::fs::read_to_string(&scenario_path).map_err(|e| {
        TrajectoryError::Export(format!(
            "{}: {e}; give a run directory written by `granular run`",
            scenario_path.display()
        ))
    })?;
    let scenario = Scenario::from_resolved_toml(&text, Some(run.path()))
        .map_err(|e| TrajectoryError::Export(format!("{}: {e}", scenario_path.display())))?;
    if scenario.kind() == EngineKind::Intruder {
        return Err(TrajectoryError::Export(format!(
            "{} is a run of the intruder engine, which has no grain trajectories (one intruder in a bath that is not simulated grain by grain); export runs of the edmd or dsmc engine",
            run.path().display()
        )));
    }
    let snapshots = run.snapshots().map_err(|e| match e {
        crate::run::RunError::Io { path, source } => TrajectoryError::Io { path, source },
        other => TrajectoryError::Export(other.to_string()),
    })?;
    if snapshots.is_empty() {
        return Err(TrajectoryError::Export(format!(
            "{} has no snapshots/snapshot_NNNNNN.npz to export; run the scenario (to the end, or until a checkpoint) first",
            run.path().display()
        )));
    }
    let cell = Cell::from_scenario(&scenario);
    let inertia = species_inertia(&scenario);
    let dir = run.trajectory_dir();
    let mut writers = formats
        .iter()
        .map(|f| Writer::create(*f, &dir, !inertia.is_empty()))
        .collect::<Result<Vec<_>, _>>()?;
    for file in &snapshots {
        // The library's snapshot reader, its error as before (it names the file).
        let snapshot = crate::output::npz::read_snapshot(&file.path)?;
        if !inertia.is_empty() && snapshot.angular_velocities.is_empty() {
            return Err(TrajectoryError::Export(format!(
                "{} has no `angular_velocities`, but the run's scenario.toml has rough grains \
                 (collisions.tangential_restitution > -1), whose snapshots carry them; \
                 export the snapshots with the scenario.toml of the run that wrote them",
                file.path.display()
            )));
        }
        let frame = Frame {
            step: file.index,
            snapshot: &snapshot,
            cell: &cell,
            inertia: &inertia,
        };
        for w in &mut writers {
            w.append(&frame)?;
        }
    }
    Ok(writers.iter().map(Writer::path).collect())
}
