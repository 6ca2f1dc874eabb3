//! `granular report DIR`: one self-contained HTML page per run (`DIR/report.html`) or
//! sweep (`DIR/report.html` with a report for each member): the resolved scenario, the
//! summary numbers next to their theory, the figures of `granular plot` as inline SVG and,
//! for runs with snapshots, an interactive player on a canvas. Style sheet and script are
//! written by hand and inlined; the page loads nothing from the network.

mod comparison;
mod cooling;
mod numbers;
mod page;
pub mod player;
mod rough;
mod steady;
mod sweep;

use crate::table::{column, read_run_csv};
use granular::Summary;
use granular::run::sweep::SWEEP_TABLE;
use granular::run::{RunDir, RunFile};
use page::{Page, escape, number, table};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The player's hand-written script, inlined.
const PLAYER_JS: &str = include_str!("player.js");

/// Writes the report of a run or sweep directory; returns the pages written (for a sweep,
/// the members' pages first and the sweep's own page last).
pub(crate) fn report(dir: &Path) -> Result<Vec<PathBuf>, String> {
    if dir.join(SWEEP_TABLE).is_file() {
        sweep::report(dir)
    } else if RunDir::new(dir).has_time_series() {
        report_run(dir).map(|p| vec![p])
    } else {
        Err(format!(
            "{}: neither a run directory (timeseries.csv) nor a sweep directory (sweep.csv); \
             give the directory that `granular run --out` or `granular sweep --out` wrote",
            dir.display()
        ))
    }
}

/// Writes `DIR/report.html` of one finished run (drawing its figures with `granular plot`
/// first); returns its path.
pub(crate) fn report_run(dir: &Path) -> Result<PathBuf, String> {
    let run = RunDir::new(dir);
    let scenario_text = run.scenario_text().map_err(|e| e.to_string())?;
    let scenario = run.scenario().map_err(|e| e.to_string())?;
    if !run.has(RunFile::Summary) {
        return Err(format!(
            "{}: no summary.json, the run has not finished; continue it with `granular resume {}`",
            dir.display(),
            dir.display()
        ));
    }
    let summary = run.summary().map_err(|e| e.to_string())?;
    crate::directory::plot(dir, false)?;
    let ts = read_run_csv(dir, RunFile::TimeSeries)?;
    let name = dir
        .file_name()
        .map_or("run".into(), |s| s.to_string_lossy().to_string());
    let subtitle = format!(
        "{} · engine {} · {} · seed {}",
        if scenario.description.is_empty() {
            "granular run"
        } else {
            &scenario.description
        },
        summary.engine,
        if scenario.intruder().is_some() {
            format!("dimension of the motion {}", summary.dimension)
        } else {
            format!("{} grains in {}D", summary.n, summary.dimension)
        },
        summary.seed
    );
    let mut page = Page::new(&format!("granular report: {name}"), &subtitle);

    let rows = if scenario.intruder().is_some() {
        numbers::intruder(&summary)
    } else {
        let run = crate::run_files::load(dir).ok();
        numbers::grains(&scenario, &summary, run.as_ref())
    };
    page.section(
        "theory",
        "Summary against theory",
        &comparison::render(&rows),
    );

    let mut script = String::new();
    let player = if scenario.intruder().is_none() {
        player::player_data(dir, &scenario, player::Limits::default())?
    } else {
        None
    };
    if let Some(p) = &player {
        page.section("player", "Snapshots", &player_html(p));
        let _ = write!(
            script,
            "<script type=\"application/json\" id=\"granular-data\">{}</script>\n<script>\n{PLAYER_JS}</script>\n",
            p.json.replace("</", "<\\/")
        );
    }
    page.section("run", "Run", &facts(&summary));
    // The snapshot pictures of `granular plot` are the player's first and last frames.
    let skip: &[&str] = if player.is_some() {
        &["snapshot_"]
    } else {
        &[]
    };
    page.section("figures", "Figures", &page::figures(dir, skip));
    page.section("final", "Final observables", &final_table(&summary, &ts));
    page.section(
        "scenario",
        "Scenario (resolved)",
        &format!(
            "<p>The run's <code>scenario.toml</code>: rerunning it reproduces the run bit for bit.</p><pre>{}</pre>",
            escape(&scenario_text)
        ),
    );
    let path = run.file(RunFile::Report);
    std::fs::write(&path, page.finish(&script)).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

fn facts(s: &Summary) -> String {
    let mut rows = vec![
        vec!["engine".into(), escape(&s.engine)],
        vec!["granular version".into(), escape(&s.version)],
        vec!["stop reason".into(), escape(&s.stop_reason)],
        vec!["events".into(), s.events.to_string()],
        vec!["collisions".into(), s.collisions.to_string()],
        vec!["wall-clock seconds".into(), number(s.wall_seconds)],
        vec!["events per second".into(), number(s.events_per_second)],
        vec![
            "outputs, snapshots".into(),
            format!("{}, {}", s.outputs, s.snapshots),
        ],
    ];
    if let Some(r) = &s.resolved {
        rows.push(vec!["packing fraction".into(), number(r.packing_fraction)]);
        for (sp, radius) in &r.radius {
            rows.push(vec![format!("radius of {}", escape(sp)), number(*radius)]);
        }
    }
    if let Some(c) = &s.crater {
        rows.push(vec![
            "crater".into(),
            format!(
                "{} of {} grains of {} displaced by more than {} (fraction {})",
                c.displaced,
                c.grains,
                escape(&c.species),
                number(c.displacement),
                number(c.fraction)
            ),
        ]);
    }
    let mut out = table("facts", &["", ""], &rows);
    if !s.warnings.is_empty() {
        out.push_str("<div class=\"warnings\"><h3>Warnings</h3><ul>");
        for w in &s.warnings {
            let _ = write!(out, "<li>{}</li>", escape(w));
        }
        out.push_str("</ul></div>");
    }
    out
}

fn final_table(s: &Summary, ts: &crate::table::Table) -> String {
    let time = column(ts, "time").unwrap_or_default();
    let mut rows: Vec<Vec<String>> = s
        .final_observables
        .iter()
        .map(|(k, v)| vec![format!("<code>{}</code>", escape(k)), number(*v)])
        .collect();
    if let Some(b) = &s.intruder {
        for (k, v) in &b.averages {
            rows.push(vec![
                format!("<code>intruder.{}</code>", escape(k)),
                number(v.unwrap_or(f64::NAN)),
            ]);
        }
    }
    format!(
        "<p>The last row of <code>timeseries.csv</code> ({} rows, t = {} to {}).</p>{}",
        time.len(),
        number(time.first().copied().unwrap_or(f64::NAN)),
        number(time.last().copied().unwrap_or(f64::NAN)),
        table("final", &["column", "value"], &rows)
    )
}

fn player_html(p: &player::PlayerData) -> String {
    let mut notice = String::new();
    if p.stride > 1 || p.frames_shown < p.frames_total {
        let _ = write!(
            notice,
            "<p class=\"notice\" id=\"subsample-notice\">Subsampled to stay responsive: drawing {} of {} grains \
             (one grain in {}, the same in every frame) and {} of {} snapshots (evenly spaced). \
             The report draws at most {} grains and holds at most {} frames \
             ({} numbers in all); the speed histograms count all grains of a frame.</p>",
            p.grains_shown,
            p.grains_total,
            p.stride,
            p.frames_shown,
            p.frames_total,
            player::MAX_GRAINS,
            player::MAX_FRAMES,
            player::MAX_VALUES
        );
    }
    format!(
        "{notice}<div class=\"player\">\
         <div class=\"controls\">\
         <button id=\"play\" type=\"button\">Play</button>\
         <input id=\"frame\" type=\"range\" min=\"0\" max=\"{max}\" value=\"0\" step=\"1\" aria-label=\"frame\">\
         <span id=\"frame-label\"></span>\
         <label>colour by <select id=\"colour\"><option value=\"species\">species</option>\
         <option value=\"speed\">speed</option></select></label>\
         </div>\
         <div class=\"views\"><div><canvas id=\"grains\"></canvas><div id=\"legend\"></div></div>\
         <div><canvas id=\"histogram\"></canvas><p class=\"caption\">Speeds of all grains of the frame \
         (bars) and the Maxwell-Boltzmann density at the frame's temperature of each species (line).</p></div></div>\
         <p class=\"caption\" id=\"player-caption\"></p></div>",
        max = p.frames_shown.saturating_sub(1),
    )
}
