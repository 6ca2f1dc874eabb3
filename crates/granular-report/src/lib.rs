//! Figures over finished granular runs, drawn from their files (never by rerunning):
//!
//! * [`plot_dir`]: the figures of a run or sweep directory (`granular plot`);
//! * [`compare`]: several `edmd` / `dsmc` runs overlaid, with Haff's law
//!   (`granular compare`);
//! * [`reproduce`]: the figures of the Gillespie intruder paper (`granular reproduce`);
//! * [`report`]: one self-contained HTML page per run or sweep (`granular report`), with
//!   the summary against theory, the figures and a snapshot player;
//! * [`scaling`]: the measured and modelled speed-up of decomposed DSMC (`granular
//!   scaling`);
//! * [`plot`]: the plotting types underneath (line plots, histograms, heat maps, snapshot
//!   pictures, animations), which take numbers and know nothing of runs.
//!
//! Every theory curve comes from the library (`granular::theory`,
//! `granular::intruder::theory`); this crate reads files and draws.

mod compare;
mod directory;
mod figures;
pub mod html;
mod intruder_plots;
mod observable_plots;
pub mod plot;
pub mod reproduce;
mod rough_plots;
mod run_files;
pub mod scaling;
mod sweep_plots;
mod table;

use std::path::{Path, PathBuf};

/// Why figures could not be made: names the file or the argument and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReportError {
    message: String,
}

impl ReportError {
    fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
        }
    }
}

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ReportError {}

impl From<String> for ReportError {
    fn from(message: String) -> Self {
        Self::new(message)
    }
}

/// Draws the figures of a run or sweep directory into `DIR/figures/` (PNG and SVG; with
/// `animate`, an animation of the snapshots too); returns the files written.
pub fn plot_dir(dir: &Path, animate: bool) -> Result<Vec<PathBuf>, ReportError> {
    Ok(directory::plot(dir, animate)?)
}

/// Overlays the finished `edmd` / `dsmc` runs `dirs` into `out` (the first run sets Haff's
/// `t0`); returns the files written, `comparison.json` last.
pub fn compare(dirs: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>, ReportError> {
    Ok(compare::compare(dirs, out)?)
}

/// Writes the self-contained HTML report of a run (`DIR/report.html`) or of a sweep (the
/// sweep's page and one per member); draws the figures of [`plot_dir`] first. Returns the
/// pages written (a sweep's own page last).
pub fn report(dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    Ok(html::report(dir)?)
}
