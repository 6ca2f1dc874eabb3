//! The report of a sweep directory: the table of `sweep.csv`, the figures `granular plot`
//! draws of it (each observable against the swept value with error bars, as inline SVG),
//! and a link to the report of every member, which is written too.

use super::page::{Page, escape, figures, table};
use granular::run::{RunDir, RunFile};
use rayon::prelude::*;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The table of a sweep as the report shows it.
pub(crate) struct SweepTable {
    /// The swept keys (the columns between `point` and `members`).
    pub keys: Vec<String>,
    /// The header of `sweep.csv`.
    pub header: Vec<String>,
    /// Its rows, as written.
    pub rows: Vec<Vec<String>>,
}

/// Reads `sweep.csv` as it is: one header row, `point`, a column per swept key, then
/// `members` and the observables (`granular::run::sweep::table`).
pub(crate) fn read_sweep_table(dir: &Path) -> Result<SweepTable, String> {
    let (header, rows) = crate::table::read_csv(&dir.join(granular::run::sweep::SWEEP_TABLE))?;
    let keys = header
        .iter()
        .skip(1)
        .take_while(|c| c.as_str() != "members")
        .cloned()
        .collect();
    Ok(SweepTable { keys, header, rows })
}

/// The member run directories `DIR/point_*/seed_*`, sorted.
fn members(dir: &Path) -> Vec<PathBuf> {
    let sorted = |d: &Path, prefix: &str| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(d)
            .map(|rd| {
                rd.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| {
                        p.is_dir()
                            && p.file_name()
                                .is_some_and(|n| n.to_string_lossy().starts_with(prefix))
                    })
                    .collect()
            })
            .unwrap_or_default();
        v.sort();
        v
    };
    sorted(dir, "point_")
        .iter()
        .flat_map(|p| sorted(p, "seed_"))
        .filter(|m| RunDir::new(m).has(RunFile::Summary))
        .collect()
}

/// Writes the members' reports and `DIR/report.html`; returns the pages written.
pub(crate) fn report(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let sweep = read_sweep_table(dir)?;
    crate::directory::plot(dir, false)?;
    let members = members(dir);
    let mut written = members
        .par_iter()
        .map(|m| super::report_run(m))
        .collect::<Result<Vec<_>, String>>()?;
    let name = dir
        .file_name()
        .map_or("sweep".into(), |s| s.to_string_lossy().to_string());
    let keys = if sweep.keys.is_empty() {
        "parameter".to_string()
    } else {
        sweep.keys.join(", ")
    };
    let mut page = Page::new(
        &format!("granular report: sweep {name}"),
        &format!("sweep of {keys} · {} members", members.len()),
    );
    let header: Vec<String> = sweep.header.iter().map(|h| escape(h)).collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = sweep
        .rows
        .iter()
        .map(|r| r.iter().map(|c| escape(c)).collect())
        .collect();
    page.section(
        "table",
        "sweep.csv",
        &format!(
            "<p>Each observable's mean over the seeds of a point, with its standard error.</p>{}",
            table("sweep", &header, &rows)
        ),
    );
    page.section(
        "figures",
        "Observables against the swept value",
        &figures(dir, &[]),
    );
    let mut links = String::from("<ul class=\"members\">");
    for m in &members {
        let rel = m.strip_prefix(dir).unwrap_or(m);
        let rel = rel.to_string_lossy().replace('\\', "/");
        let _ = write!(
            links,
            "<li><a href=\"{0}/report.html\">{0}</a></li>",
            escape(&rel)
        );
    }
    links.push_str("</ul>");
    page.section("members", "Members", &links);
    let path = RunDir::new(dir).file(RunFile::Report);
    std::fs::write(&path, page.finish("")).map_err(|e| format!("{}: {e}", path.display()))?;
    written.push(path);
    Ok(written)
}
