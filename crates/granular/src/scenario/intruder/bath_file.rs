//! The file of a tabulated bath (`[intruder.bath] kind = "tabulated"`, `file = "..."`):
//! two columns `v f` per line, read and checked here, so that the engine receives the
//! points ([`crate::intruder::BathConfig::Tabulated`]) and reads no file.

use std::path::Path;

use crate::intruder::{BathError, Tabulated};

/// Reads the two-column text/CSV file at `path` (see `parse`); a path that is not a
/// regular file, or one too large for a table, is refused before it is read
/// ([`crate::scenario::read_text_file`]).
pub fn read(path: &Path) -> Result<Vec<(f64, f64)>, BathError> {
    parse(&read_text(path)?, &path.display().to_string())
}

/// Reads the two columns of the file at `path` (see [`parse_columns`]) without checking
/// them as a 1D velocity density: a disk or sphere intruder's table is a speed
/// distribution, checked by its engine (G-44).
pub(crate) fn read_columns(path: &Path) -> Result<Vec<(f64, f64)>, BathError> {
    parse_columns(&read_text(path)?, &path.display().to_string())
}

/// The text of the file at `path`; a path that is not a regular file, or one too large for
/// a table, is refused before it is read ([`crate::scenario::read_text_file`]).
fn read_text(path: &Path) -> Result<String, BathError> {
    crate::scenario::read_text_file(path).map_err(|source| BathError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Parses a two-column table (see [`parse_columns`]) and checks that the points make a
/// bath density ([`Tabulated::new`]); errors name `origin` (the file).
pub(crate) fn parse(text: &str, origin: &str) -> Result<Vec<(f64, f64)>, BathError> {
    let points = parse_columns(text, origin)?;
    Tabulated::new(&points).map_err(|e| match e {
        BathError::Invalid(m) => BathError::Invalid(format!("{origin}: {m}")),
        other => other,
    })?;
    Ok(points)
}

/// Parses a two-column table (`v f` per line, separated by whitespace, comma or semicolon;
/// `#` starts a comment; a non-numeric first line is taken as a header); errors name
/// `origin` (the file), the line and the column (counted in characters from 1).
pub(crate) fn parse_columns(text: &str, origin: &str) -> Result<Vec<(f64, f64)>, BathError> {
    let mut points = Vec::new();
    let mut header_seen = false;
    for (i, raw) in text.lines().enumerate() {
        let content = raw.split('#').next().unwrap_or("");
        if content.trim().is_empty() {
            continue;
        }
        // Each field with the column (1-based, in characters) where it starts.
        let mut fields: Vec<(usize, &str)> = Vec::new();
        let mut start = None;
        for (c, (b, ch)) in content.char_indices().enumerate() {
            let separator = ch == ',' || ch == ';' || ch.is_whitespace();
            match (separator, start) {
                (false, None) => start = Some((c + 1, b)),
                (true, Some((col, s))) => {
                    fields.push((col, &content[s..b]));
                    start = None;
                }
                _ => {}
            }
        }
        if let Some((col, s)) = start {
            fields.push((col, &content[s..]));
        }
        let bad = fields.iter().find(|(_, f)| f.parse::<f64>().is_err());
        if points.is_empty() && !header_seen && bad.is_some() {
            header_seen = true;
            continue; // header
        }
        let parse_error = |column: usize, message: String| BathError::Parse {
            path: origin.into(),
            line: i + 1,
            message: format!("column {column}: {message}"),
        };
        if let Some((col, field)) = bad {
            return Err(parse_error(
                *col,
                format!("`{field}` is not a number; give two numbers per line, v and f(v)"),
            ));
        }
        if fields.len() != 2 {
            let col = fields.get(2).map_or(1, |f| f.0);
            return Err(parse_error(
                col,
                format!(
                    "expected two columns (v, f), found {}; give two numbers per line",
                    fields.len()
                ),
            ));
        }
        let value = |k: usize| fields[k].1.parse::<f64>().unwrap_or(f64::NAN);
        points.push((value(0), value(1)));
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A text that is not a table (a README given as a bath) fails at its second line,
    /// naming the column; a header line and comments are skipped.
    #[test]
    fn errors_name_line_and_column() {
        let e = parse("# Title\n\nSome words here\nand more words\n", "README.md").unwrap_err();
        let shown = e.to_string();
        assert!(
            shown.contains("README.md, line 4: column 1: `and` is not a number"),
            "{shown}"
        );
        let e = parse("v f\n0 1\n1 x\n", "bath.dat")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3: column 3: `x`"), "{e}");
        let e = parse("0, 1, 2\n", "bath.dat").unwrap_err().to_string();
        assert!(e.contains("line 1: column 7: expected two columns"), "{e}");
        assert_eq!(
            parse("v f\n0 1\n1 0 # end\n", "b").unwrap(),
            vec![(0.0, 1.0), (1.0, 0.0)]
        );
    }
}
