//! The CSV tables of a run directory (`timeseries.csv`, `speed_histograms.csv`, ...) read
//! back as text: a header and rows, with `#` lines as comments.

use std::path::Path;

/// A CSV table: the header and the rows, as text.
pub(crate) type Table = (Vec<String>, Vec<Vec<String>>);

/// Reads a CSV file (lines starting with `#` are comments) into header and rows.
pub(crate) fn read_csv(path: &Path) -> Result<Table, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(str::to_string)
        .collect();
    let rows = reader
        .records()
        .map(|r| {
            r.map(|r| r.iter().map(str::to_string).collect())
                .map_err(|e| e.to_string())
        })
        .collect::<Result<Vec<Vec<String>>, String>>()?;
    Ok((header, rows))
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
