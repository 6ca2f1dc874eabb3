//! `granular plot DIR`: what the directory is — a sweep (`sweep.csv`), a run of the
//! intruder engine, or a run of the edmd or dsmc engine (`timeseries.csv`) — and the
//! figures of each, drawn by [`crate::sweep_plots`], [`crate::intruder_plots`] and
//! [`crate::figures`].

use granular::run::RunDir;
use granular::run::sweep::SWEEP_TABLE;
use std::path::{Path, PathBuf};

/// Draws the figures of a run or a sweep directory; returns the files written.
pub(crate) fn plot(dir: &Path, animate: bool) -> Result<Vec<PathBuf>, String> {
    let run = RunDir::new(dir);
    if dir.join(SWEEP_TABLE).is_file() {
        crate::sweep_plots::plot_sweep(dir)
    } else if run.has_time_series() {
        let scenario = run.scenario().map_err(|e| e.to_string())?;
        if scenario.intruder().is_some() {
            crate::intruder_plots::plot_run(dir)
        } else {
            crate::figures::plot_run(dir, &scenario, animate)
        }
    } else {
        Err(format!(
            "{}: neither a run directory (timeseries.csv) nor a sweep directory (sweep.csv)",
            dir.display()
        ))
    }
}
