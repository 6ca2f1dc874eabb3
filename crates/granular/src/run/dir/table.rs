//! The CSV tables of a run directory (`timeseries.csv`, the histograms, the correlations,
//! a sweep's `sweep.csv`) read back: a header and rows of text, `#` lines as comments.

use crate::run::RunError;
use std::path::Path;

/// A CSV table as written: the header and the rows, as text.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each with one entry per column.
    pub rows: Vec<Vec<String>>,
}

/// One column of a [`Table`], typed.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    /// Every entry is a number (`NaN` and `inf` included).
    Numbers(Vec<f64>),
    /// Some entry is not a number: the column as text (e.g. `species`).
    Text(Vec<String>),
}

impl Table {
    /// Reads the CSV file at `path` (lines starting with `#` are comments; the first other
    /// line is the header).
    pub fn read(path: &Path) -> Result<Table, RunError> {
        let text = std::fs::read_to_string(path).map_err(crate::run::io_err(path))?;
        Table::parse(&text).map_err(|message| RunError::Read {
            path: path.to_path_buf(),
            message,
        })
    }

    /// Reads CSV text (as [`Table::read`]).
    pub fn parse(text: &str) -> Result<Table, String> {
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
        Ok(Table { header, rows })
    }

    /// The index of the column `name`.
    pub fn position(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// The column `name` as numbers (`NaN` where an entry is not one); `None` without such
    /// a column.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.position(name)?;
        Some(
            self.rows
                .iter()
                .map(|r| r.get(i).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN))
                .collect(),
        )
    }

    /// Every column, typed: numbers where every entry reads as one, text otherwise.
    pub fn columns(&self) -> Vec<(String, Column)> {
        self.header
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let cells = || self.rows.iter().map(move |r| r.get(i).map_or("", |s| s));
                let numbers: Option<Vec<f64>> = cells().map(|c| c.parse().ok()).collect();
                let column = match numbers {
                    Some(v) => Column::Numbers(v),
                    None => Column::Text(cells().map(str::to_string).collect()),
                };
                (name.clone(), column)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::{Column, Table};

    #[test]
    fn reads_header_rows_and_typed_columns() {
        let t = Table::parse("# a comment\nspecies,x,y\nsmall,1.5,nan\nbig,-2e3,inf\n").unwrap();
        assert_eq!(t.header, ["species", "x", "y"]);
        assert_eq!(t.rows.len(), 2);
        assert_eq!(t.column("x"), Some(vec![1.5, -2e3]));
        assert_eq!(t.column("z"), None);
        let cols = t.columns();
        assert_eq!(cols[0].1, Column::Text(vec!["small".into(), "big".into()]));
        assert_eq!(cols[1].1, Column::Numbers(vec![1.5, -2000.0]));
        match &cols[2].1 {
            Column::Numbers(v) => assert!(v[0].is_nan() && v[1] == f64::INFINITY),
            other => panic!("{other:?}"),
        }
    }
}
