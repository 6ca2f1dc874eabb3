//! The CSV tables of a run directory (`timeseries.csv`, `speed_histograms.csv`, ...) read
//! back as text: a header and rows, with `#` lines as comments.

use granular::run::{RunDir, RunFile};
use std::path::{Path, PathBuf};

/// The snapshot files of the run directory `dir` in output order (none when it has no
/// snapshot folder or it cannot be read).
pub(crate) fn snapshot_files(dir: &Path) -> Vec<PathBuf> {
    RunDir::new(dir)
        .snapshots()
        .map(|files| files.into_iter().map(|f| f.path).collect())
        .unwrap_or_default()
}

/// A CSV table: the header and the rows, as text.
pub(crate) type Table = (Vec<String>, Vec<Vec<String>>);

/// Reads a CSV file (lines starting with `#` are comments) into header and rows, with the
/// library's reader ([`granular::run::Table`]).
pub(crate) fn read_csv(path: &Path) -> Result<Table, String> {
    let t = granular::run::Table::read(path).map_err(|e| e.to_string())?;
    Ok((t.header, t.rows))
}

/// The CSV file `file` of the run directory `dir`.
pub(crate) fn read_run_csv(dir: &Path, file: RunFile) -> Result<Table, String> {
    read_csv(&RunDir::new(dir).file(file))
}

pub(crate) fn column(t: &Table, name: &str) -> Option<Vec<f64>> {
    let i = t.0.iter().position(|h| h == name)?;
    Some(
        t.1.iter()
            .map(|r| r.get(i).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN))
            .collect(),
    )
}

/// The column `name` of the rows `rows` of `t` as numbers (`NaN` where a cell is not one;
/// empty when there is no such column).
pub(crate) fn column_of(t: &Table, name: &str, rows: &[&Vec<String>]) -> Vec<f64> {
    let Some(i) = t.0.iter().position(|h| h == name) else {
        return Vec::new();
    };
    rows.iter()
        .map(|r| r.get(i).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN))
        .collect()
}
