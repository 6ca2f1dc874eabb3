//! The run directory ([`RunDir`]): the one place that names its files ([`RunFile`] and the
//! folders) and reads them back, typed: the scenario, the summary, the CSV tables
//! ([`Table`]), the NumPy arrays, the snapshots in output order, the checkpoint and the
//! trajectories. The outputs write through these names; the command line, the report, the
//! trajectory export and the Python package read through these readers.
//!
//! | file | content |
//! |---|---|
//! | `scenario.toml` | the fully resolved scenario |
//! | `timeseries.csv` | one row of scalar observables per output time |
//! | `snapshots/snapshot_NNNNNN.npz` | positions, velocities, radii, masses, species (NumPy) |
//! | `speed_histograms.csv`, `velocity_histograms.csv`, `scaled_speed_histograms.csv`, `impact_parameter.csv`, `intruder_histograms.csv` | histograms ([`FileGroup::Histograms`]) |
//! | `pair_correlation.csv`, `mean_square_displacement.csv`, `velocity_autocorrelation.csv` | opt-in correlations ([`FileGroup::Correlations`]) |
//! | `impact_histograms.npz`, `structure_factor.npz`, `density_maps.npz`, `intruder_histograms.npz` | arrays ([`FileGroup::Arrays`]) |
//! | `trajectory/` | trajectories for the viewers ([`crate::trajectory::Format`]) |
//! | `summary.json` | engine, version, seed, timings, final observables, goodness of fit |
//! | `checkpoint.msgpack`, `checkpoint.parts/` | the state at the last checkpoint (removed when the run ends) |
//! | `.lock` | the process id of the run writing the directory |
//! | `log.txt` | what happened, with wall-clock times |
//! | `figures/`, `report.html` | the figures of `granular plot` and the page of `granular report` |
//! | `initial_state.npz` | per-grain arrays that came from NumPy or another `.npz` file, named by `scenario.toml` |

mod export;
mod initial_state;
mod table;

pub use table::{Column, Table};

use super::{RunError, Summary};
use crate::engine::Snapshot;
use crate::output::npz::NpzArray;
use crate::scenario::Scenario;
use crate::trajectory::Format;
use std::path::{Path, PathBuf};

/// A file of a run directory, by what it holds; [`RunFile::name`] is its name in the
/// directory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RunFile {
    /// `scenario.toml`: the fully resolved scenario.
    Scenario,
    /// `summary.json`: written when the run ends.
    Summary,
    /// `timeseries.csv`: one row of observables per output time.
    TimeSeries,
    /// `log.txt`: what happened, with wall-clock times.
    Log,
    /// `checkpoint.msgpack`: the state at the last checkpoint.
    Checkpoint,
    /// `.lock`: the process id of the run writing the directory.
    Lock,
    /// `speed_histograms.csv`.
    SpeedHistograms,
    /// `velocity_histograms.csv`.
    VelocityHistograms,
    /// `scaled_speed_histograms.csv`: a cooling gas's speeds in units of the thermal speed.
    ScaledSpeedHistograms,
    /// `impact_parameter.csv`.
    ImpactParameter,
    /// `intruder_histograms.csv`.
    IntruderHistograms,
    /// `pair_correlation.csv`.
    PairCorrelation,
    /// `mean_square_displacement.csv`.
    MeanSquareDisplacement,
    /// `velocity_autocorrelation.csv`.
    VelocityAutocorrelation,
    /// `impact_histograms.npz`.
    ImpactHistograms,
    /// `structure_factor.npz`.
    StructureFactor,
    /// `density_maps.npz`.
    DensityMaps,
    /// `intruder_histograms.npz`.
    IntruderArrays,
    /// `report.html`: the page of `granular report`.
    Report,
    /// `initial_state.npz`: the per-grain arrays of the scenario that were given as NumPy
    /// arrays or read from an `.npz` file; `scenario.toml` names its members.
    InitialState,
}

/// The kinds of result file beside the time series, as the Python package groups them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileGroup {
    /// CSV histograms.
    Histograms,
    /// CSV correlation functions (opt-in outputs).
    Correlations,
    /// NumPy `.npz` arrays.
    Arrays,
}

impl RunFile {
    /// Every file, in the order of the table above.
    pub const ALL: [RunFile; 20] = [
        RunFile::Scenario,
        RunFile::Summary,
        RunFile::TimeSeries,
        RunFile::Log,
        RunFile::Checkpoint,
        RunFile::Lock,
        RunFile::SpeedHistograms,
        RunFile::VelocityHistograms,
        RunFile::ScaledSpeedHistograms,
        RunFile::ImpactParameter,
        RunFile::IntruderHistograms,
        RunFile::PairCorrelation,
        RunFile::MeanSquareDisplacement,
        RunFile::VelocityAutocorrelation,
        RunFile::ImpactHistograms,
        RunFile::StructureFactor,
        RunFile::DensityMaps,
        RunFile::IntruderArrays,
        RunFile::Report,
        RunFile::InitialState,
    ];

    /// The file's name in the run directory.
    pub const fn name(self) -> &'static str {
        match self {
            RunFile::Scenario => "scenario.toml",
            RunFile::Summary => "summary.json",
            RunFile::TimeSeries => "timeseries.csv",
            RunFile::Log => "log.txt",
            RunFile::Checkpoint => "checkpoint.msgpack",
            RunFile::Lock => ".lock",
            RunFile::SpeedHistograms => "speed_histograms.csv",
            RunFile::VelocityHistograms => "velocity_histograms.csv",
            RunFile::ScaledSpeedHistograms => "scaled_speed_histograms.csv",
            RunFile::ImpactParameter => "impact_parameter.csv",
            RunFile::IntruderHistograms => "intruder_histograms.csv",
            RunFile::PairCorrelation => "pair_correlation.csv",
            RunFile::MeanSquareDisplacement => "mean_square_displacement.csv",
            RunFile::VelocityAutocorrelation => "velocity_autocorrelation.csv",
            RunFile::ImpactHistograms => "impact_histograms.npz",
            RunFile::StructureFactor => "structure_factor.npz",
            RunFile::DensityMaps => "density_maps.npz",
            RunFile::IntruderArrays => "intruder_histograms.npz",
            RunFile::Report => "report.html",
            RunFile::InitialState => "initial_state.npz",
        }
    }

    /// The group of a result file beside the time series and its short name in the group
    /// (`speed`, `pair_correlation`, `structure_factor`, ...: the keys of the Python
    /// package's `RunData.histograms`, `.correlations` and `.arrays`); `None` for the
    /// other files.
    pub const fn group(self) -> Option<(FileGroup, &'static str)> {
        use FileGroup::{Arrays, Correlations, Histograms};
        Some(match self {
            RunFile::SpeedHistograms => (Histograms, "speed"),
            RunFile::VelocityHistograms => (Histograms, "velocity"),
            RunFile::ScaledSpeedHistograms => (Histograms, "scaled_speed"),
            RunFile::ImpactParameter => (Histograms, "impact_parameter"),
            RunFile::IntruderHistograms => (Histograms, "intruder"),
            RunFile::PairCorrelation => (Correlations, "pair_correlation"),
            RunFile::MeanSquareDisplacement => (Correlations, "mean_square_displacement"),
            RunFile::VelocityAutocorrelation => (Correlations, "velocity_autocorrelation"),
            RunFile::ImpactHistograms => (Arrays, "impact_histograms"),
            RunFile::StructureFactor => (Arrays, "structure_factor"),
            RunFile::DensityMaps => (Arrays, "density_maps"),
            RunFile::IntruderArrays => (Arrays, "intruder_histograms"),
            _ => return None,
        })
    }
}

/// The folder of the snapshots, `snapshots/`.
pub const SNAPSHOTS: &str = "snapshots";
/// The folder of the trajectories, `trajectory/`.
pub const TRAJECTORY: &str = "trajectory";
/// The folder of a checkpoint written in parts by the ranks of a decomposed run.
pub const CHECKPOINT_PARTS: &str = "checkpoint.parts";
/// The folder of the figures of `granular plot`, `figures/`.
pub const FIGURES: &str = "figures";

/// What a directory holds, for deciding whether a run may be written into it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectoryState {
    /// It does not exist.
    Missing,
    /// An empty directory.
    Empty,
    /// A run directory: `scenario.toml` with `log.txt`, `summary.json` or a checkpoint.
    Run {
        /// `summary.json` is present and no checkpoint: the run finished.
        finished: bool,
    },
    /// Something else: a file, or a directory with other files.
    Other,
}

/// One snapshot file: its output index (`NNNNNN` of `snapshot_NNNNNN.npz`) and path.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct SnapshotFile {
    /// The output index.
    pub index: u64,
    /// The file.
    pub path: PathBuf,
}

/// A run directory: the files of `granular run` (or [`crate::Run`]) under one path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunDir {
    path: PathBuf,
}

impl RunDir {
    /// The run directory at `path` (nothing is read until asked).
    pub fn new(path: impl Into<PathBuf>) -> RunDir {
        RunDir { path: path.into() }
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The path of `file` in it.
    pub fn file(&self, file: RunFile) -> PathBuf {
        self.path.join(file.name())
    }

    /// Whether `file` is present.
    pub fn has(&self, file: RunFile) -> bool {
        self.file(file).is_file()
    }

    /// The snapshot folder.
    pub fn snapshot_dir(&self) -> PathBuf {
        self.path.join(SNAPSHOTS)
    }

    /// The snapshot of output `index`: `snapshots/snapshot_NNNNNN.npz`.
    pub fn snapshot_file(&self, index: u64) -> PathBuf {
        self.snapshot_dir().join(snapshot_name(index))
    }

    /// The trajectory folder.
    pub fn trajectory_dir(&self) -> PathBuf {
        self.path.join(TRAJECTORY)
    }

    /// The folder of a checkpoint in parts.
    pub fn parts_dir(&self) -> PathBuf {
        self.path.join(CHECKPOINT_PARTS)
    }

    /// The folder of the figures.
    pub fn figure_dir(&self) -> PathBuf {
        self.path.join(FIGURES)
    }

    /// What the directory holds.
    pub fn state(&self) -> DirectoryState {
        let dir = &self.path;
        if !dir.exists() {
            return DirectoryState::Missing;
        }
        let Ok(mut entries) = std::fs::read_dir(dir) else {
            return DirectoryState::Other;
        };
        if entries.next().is_none() {
            return DirectoryState::Empty;
        }
        if self.has(RunFile::Scenario)
            && (self.has(RunFile::Log)
                || self.has(RunFile::Summary)
                || self.has(RunFile::Checkpoint))
        {
            DirectoryState::Run {
                finished: self.has(RunFile::Summary) && !self.has(RunFile::Checkpoint),
            }
        } else {
            DirectoryState::Other
        }
    }

    /// Whether the run has a time series: a run directory to plot or report (a sweep
    /// directory has `sweep.csv` instead).
    pub fn has_time_series(&self) -> bool {
        self.has(RunFile::TimeSeries)
    }

    /// `scenario.toml` as written.
    pub fn scenario_text(&self) -> Result<String, RunError> {
        read_text(&self.file(RunFile::Scenario))
    }

    /// The run's resolved scenario, read from `scenario.toml`.
    pub fn scenario(&self) -> Result<Scenario, RunError> {
        let path = self.file(RunFile::Scenario);
        let text = read_text(&path)?;
        Scenario::from_resolved_toml(&text, Some(&self.path)).map_err(|e| read_error(&path, e))
    }

    /// `summary.json` (present once the run has finished).
    pub fn summary(&self) -> Result<Summary, RunError> {
        let path = self.file(RunFile::Summary);
        let text = std::fs::read_to_string(&path).map_err(super::io_err(&path))?;
        serde_json::from_str(&text).map_err(|e| RunError::Checkpoint {
            path,
            message: format!("not a summary of this version of granular: {e}"),
        })
    }

    /// `timeseries.csv`.
    pub fn timeseries(&self) -> Result<Table, RunError> {
        Table::read(&self.file(RunFile::TimeSeries))
    }

    /// A CSV file of the directory (a histogram or correlation table).
    pub fn table(&self, file: RunFile) -> Result<Table, RunError> {
        Table::read(&self.file(file))
    }

    /// The arrays of a NumPy file of the directory, in file order.
    pub fn arrays(&self, file: RunFile) -> Result<Vec<(String, NpzArray)>, RunError> {
        read_arrays(self.file(file))
    }

    /// The result files present beside the time series, in the order of [`RunFile::ALL`],
    /// with their group and short name.
    pub fn result_files(&self) -> Vec<(FileGroup, &'static str, PathBuf)> {
        RunFile::ALL
            .into_iter()
            .filter_map(|f| f.group().map(|(group, key)| (group, key, self.file(f))))
            .filter(|(_, _, path)| path.is_file())
            .collect()
    }

    /// The snapshot files (`snapshots/snapshot_NNNNNN.npz`) in output order; none when
    /// there is no snapshot folder (an intruder run).
    pub fn snapshots(&self) -> Result<Vec<SnapshotFile>, RunError> {
        let dir = self.snapshot_dir();
        if !dir.is_dir() {
            return Ok(Vec::new());
        }
        let mut files = Vec::new();
        for entry in std::fs::read_dir(&dir).map_err(super::io_err(&dir))? {
            let path = entry.map_err(super::io_err(&dir))?.path();
            let index = path
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(|n| n.strip_prefix("snapshot_"))
                .and_then(|n| n.strip_suffix(".npz"))
                .and_then(|n| n.parse::<u64>().ok());
            if let Some(index) = index {
                files.push(SnapshotFile { index, path });
            }
        }
        files.sort();
        Ok(files)
    }

    /// The snapshot of output `index`.
    pub fn snapshot(&self, index: u64) -> Result<Snapshot, RunError> {
        read_snapshot(self.snapshot_file(index))
    }

    /// The trajectory files present (the file a viewer opens), in the order of
    /// [`Format::ALL`].
    pub fn trajectories(&self) -> Vec<(Format, PathBuf)> {
        let dir = self.trajectory_dir();
        Format::ALL
            .into_iter()
            .map(|f| (f, dir.join(f.file_name())))
            .filter(|(_, p)| p.is_file())
            .collect()
    }

    /// The checkpoint (`checkpoint.msgpack`), checked against its header (length, CRC-32,
    /// format; [`super::checkpoint`]) and read. Without the directory's lock: the caller
    /// holds it.
    pub(crate) fn checkpoint(&self) -> Result<super::Checkpoint, RunError> {
        let path = self.file(RunFile::Checkpoint);
        let bytes = std::fs::read(&path).map_err(super::io_err(&path))?;
        let payload = super::checkpoint::decode(&path, &bytes)?;
        rmp_serde::from_slice(payload).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: format!(
                "{e}: its checksum is right but its state does not read; it was written by \
                 another build of granular. Rerun the scenario with --replace"
            ),
        })
    }

    /// Writes the snapshots as trajectories in each of `formats` into `trajectory/`
    /// (`granular export`); see [`export`](Self::export_trajectories).
    pub fn export_trajectories(
        &self,
        formats: &[Format],
    ) -> Result<Vec<PathBuf>, crate::trajectory::TrajectoryError> {
        export::export(self, formats)
    }

    /// Removes what an earlier run left that a new one would not overwrite: snapshots,
    /// checkpoint (whole or in parts) and summary.
    pub(crate) fn clear_earlier_run(&self) {
        let _ = std::fs::remove_dir_all(self.snapshot_dir());
        let _ = std::fs::remove_file(self.file(RunFile::Checkpoint));
        let _ = std::fs::remove_dir_all(self.parts_dir());
        let _ = std::fs::remove_file(self.file(RunFile::Summary));
        // Written again from memory when the new run's scenario has such arrays (they are
        // read before the directory is cleared, even from this very file).
        let _ = std::fs::remove_file(self.file(RunFile::InitialState));
    }

    /// Removes the checkpoint of a run that has ended.
    pub(crate) fn remove_checkpoint(&self) {
        let _ = std::fs::remove_file(self.file(RunFile::Checkpoint));
        let _ = std::fs::remove_dir_all(self.parts_dir());
    }
}

/// `snapshot_NNNNNN.npz`.
pub(crate) fn snapshot_name(index: u64) -> String {
    format!("snapshot_{index:06}.npz")
}

fn read_error(path: &Path, e: impl std::fmt::Display) -> RunError {
    RunError::Read {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

fn read_text(path: &Path) -> Result<String, RunError> {
    std::fs::read_to_string(path).map_err(super::io_err(path))
}

/// A snapshot file, read and checked ([`crate::output::npz::read_snapshot`]); the error
/// names the file.
pub fn read_snapshot(path: impl AsRef<Path>) -> Result<Snapshot, RunError> {
    let path = path.as_ref();
    crate::output::npz::read_snapshot(path).map_err(|e| read_error(path, e))
}

/// The arrays of a NumPy `.npz` file, in file order; the error names the file.
pub fn read_arrays(path: impl AsRef<Path>) -> Result<Vec<(String, NpzArray)>, RunError> {
    let path = path.as_ref();
    crate::output::npz::read_npz(path).map_err(|e| read_error(path, e))
}
