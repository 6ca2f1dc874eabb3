//! [`export()`]: the `.npz` snapshots of an existing run directory as trajectories.

use super::{Cell, Format, Frame, TrajectoryError, Writer, io_err};
use crate::output::npz::read_snapshot;
use crate::scenario::{EngineKind, Scenario};
use std::path::{Path, PathBuf};

/// Writes the snapshots `run/snapshots/snapshot_NNNNNN.npz`, in the order of `NNNNNN`, to
/// `run/trajectory/` in each of `formats` (an earlier trajectory of the same format is
/// replaced) and returns the files a viewer opens. The box comes from the run's resolved
/// `scenario.toml`. Fails, naming the fix, for a run of the intruder engine (it has no
/// grain positions) and for a directory without snapshots.
pub fn export(run: &Path, formats: &[Format]) -> Result<Vec<PathBuf>, TrajectoryError> {
    let scenario_path = run.join("scenario.toml");
    let text = std::fs::read_to_string(&scenario_path).map_err(|e| {
        TrajectoryError::Export(format!(
            "{}: {e}; give a run directory written by `granular run`",
            scenario_path.display()
        ))
    })?;
    let scenario = Scenario::from_toml(&text, &[])
        .map_err(|e| TrajectoryError::Export(format!("{}: {e}", scenario_path.display())))?;
    if scenario.engine == EngineKind::Intruder {
        return Err(TrajectoryError::Export(format!(
            "{} is a run of the intruder engine, which has no grain trajectories (one intruder in a bath that is not simulated grain by grain); export runs of the edmd or dsmc engine",
            run.display()
        )));
    }
    let snapshots = snapshot_files(&run.join("snapshots"))?;
    if snapshots.is_empty() {
        return Err(TrajectoryError::Export(format!(
            "{} has no snapshots/snapshot_NNNNNN.npz to export; run the scenario (to the end, or until a checkpoint) first",
            run.display()
        )));
    }
    let cell = Cell::from_scenario(&scenario);
    let dir = run.join("trajectory");
    let mut writers = formats
        .iter()
        .map(|f| Writer::create(*f, &dir))
        .collect::<Result<Vec<_>, _>>()?;
    for (step, path) in &snapshots {
        let snapshot = read_snapshot(path)?;
        let frame = Frame {
            step: *step,
            snapshot: &snapshot,
            cell: &cell,
        };
        for w in &mut writers {
            w.append(&frame)?;
        }
    }
    Ok(writers.iter().map(Writer::path).collect())
}

/// The snapshot files of `dir` with their output index, in increasing order.
fn snapshot_files(dir: &Path) -> Result<Vec<(u64, PathBuf)>, TrajectoryError> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io_err(dir))? {
        let path = entry.map_err(io_err(dir))?.path();
        let index = path
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_prefix("snapshot_"))
            .and_then(|n| n.strip_suffix(".npz"))
            .and_then(|n| n.parse::<u64>().ok());
        if let Some(i) = index {
            files.push((i, path));
        }
    }
    files.sort();
    Ok(files)
}
