//! The file of a tabulated bath (`[intruder.bath] kind = "tabulated"`, `file = "..."`):
//! two columns `v f` per line, read and checked here, so that the engine receives the
//! points ([`crate::intruder::BathConfig::Tabulated`]) and reads no file.

use std::path::Path;

use crate::intruder::{BathError, Tabulated};

/// Reads the two-column text/CSV file at `path` (see [`parse`]).
pub fn read(path: &Path) -> Result<Vec<(f64, f64)>, BathError> {
    parse(&read_text(path)?, &path.display().to_string())
}

/// Reads the two columns of the file at `path` (see [`parse_columns`]) without checking
/// them as a 1D velocity density: a disk or sphere intruder's table is a speed
/// distribution, checked by its engine (G-44).
pub fn read_columns(path: &Path) -> Result<Vec<(f64, f64)>, BathError> {
    parse_columns(&read_text(path)?, &path.display().to_string())
}

fn read_text(path: &Path) -> Result<String, BathError> {
    std::fs::read_to_string(path).map_err(|source| BathError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Parses a two-column table (see [`parse_columns`]) and checks that the points make a
/// bath density ([`Tabulated::new`]); errors name `origin` (the file).
pub fn parse(text: &str, origin: &str) -> Result<Vec<(f64, f64)>, BathError> {
    let points = parse_columns(text, origin)?;
    Tabulated::new(&points).map_err(|e| match e {
        BathError::Invalid(m) => BathError::Invalid(format!("{origin}: {m}")),
        other => other,
    })?;
    Ok(points)
}

/// Parses a two-column table (`v f` per line, separated by whitespace, comma or semicolon;
/// `#` starts a comment; a non-numeric first line is taken as a header); errors name
/// `origin` (the file) and the line.
pub fn parse_columns(text: &str, origin: &str) -> Result<Vec<(f64, f64)>, BathError> {
    let mut points = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        let parsed: Vec<Result<f64, _>> = fields.iter().map(|s| s.parse::<f64>()).collect();
        if points.is_empty() && parsed.iter().any(|p| p.is_err()) {
            continue; // header
        }
        if fields.len() != 2 {
            return Err(BathError::Parse {
                path: origin.into(),
                line: i + 1,
                message: format!("expected two columns (v, f), found {}", fields.len()),
            });
        }
        match (&parsed[0], &parsed[1]) {
            (Ok(v), Ok(f)) => points.push((*v, *f)),
            _ => {
                return Err(BathError::Parse {
                    path: origin.into(),
                    line: i + 1,
                    message: format!("not a number in {line:?}"),
                });
            }
        }
    }
    Ok(points)
}
