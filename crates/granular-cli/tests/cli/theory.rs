//! What a user sees is right (issue 37): the reports of every bundled scenario (run short)
//! have no red row, a run compared against a deliberately wrong theory does show red, and
//! no figure of those runs and reports, nor of `granular reproduce`, has two equal adjacent
//! tick labels or an axis without its quantity and unit.

use super::{granular, scenarios, tmp};
use std::path::{Path, PathBuf};

/// Each bundled scenario with the overrides that make it a few seconds long.
const SHORT: [(&str, &[&str]); 17] = [
    (
        "maxwell-boltzmann",
        &["species.0.count=2000", "stop.collisions_per_particle=150"],
    ),
    (
        "problem2-mixture",
        &[
            "species.0.count=1000",
            "species.1.count=1000",
            "stop.collisions_per_particle=150",
        ],
    ),
    ("problem3-cooling", &[]),
    ("problem4-crater", &[]),
    ("dsmc-cooling", &["stop.collisions_per_particle=20"]),
    ("dsmc-hcs-rescaled", &["stop.collisions_per_particle=15"]),
    ("dsmc-white-noise", &["stop.collisions_per_particle=15"]),
    ("edmd-hcs-rescaled", &["stop.collisions_per_particle=40"]),
    ("edmd-white-noise", &["stop.collisions_per_particle=40"]),
    ("intruder-1d", &[]),
    ("intruder-needle", &["stop.collisions=500000"]),
    ("intruder-disk", &[]),
    ("intruder-sphere", &[]),
    ("rough-hcs-edmd", &[]),
    ("rough-hcs-dsmc", &[]),
    (
        "section32-edmd",
        &[
            "species.0.count=4000",
            "stop.time=0.05",
            "output.interval=0.002",
            "output.observable_times=[0.011,0.033]",
            "output.structure_factor_max_index=8",
            "output.density_map=[16,16]",
        ],
    ),
    (
        "section32-dsmc",
        &[
            "species.0.count=4000",
            "stop.time=0.05",
            "output.interval=0.002",
            "output.observable_times=[0.011,0.033]",
            "output.structure_factor_max_index=8",
            "output.density_map=[16,16]",
            "dsmc.cell_size=0.05",
        ],
    ),
];

fn run(scenario: &Path, dir: &Path, set: &[&str]) {
    let mut cmd = granular();
    cmd.arg("run")
        .arg(scenario)
        .arg("--out")
        .arg(dir)
        .args(["--quiet", "--insist"]);
    for s in set {
        cmd.args(["--set", s]);
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        scenario.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn report(dir: &Path) -> String {
    let out = granular().arg("report").arg(dir).output().unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read_to_string(dir.join("report.html")).unwrap()
}

/// The rows of the page's comparison table: (colour class, the row's text).
fn rows(html: &str) -> Vec<(String, String)> {
    let Some(start) = html.find("<table class=\"numbers\">") else {
        return Vec::new();
    };
    let end = start + html[start..].find("</table>").unwrap();
    html[start..end]
        .split("<tr>")
        .skip(1)
        .filter_map(|row| {
            let class = row.split("class=\"z ").nth(1)?.split('"').next()?;
            let mut text = String::new();
            let mut inside = false;
            for c in row.chars() {
                match c {
                    '<' => inside = true,
                    '>' => {
                        inside = false;
                        text.push(' ');
                    }
                    _ if !inside => text.push(c),
                    _ => {}
                }
            }
            let text = text
                .replace("&#39;", "'")
                .replace("&quot;", "\"")
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&");
            Some((
                class.to_string(),
                text.split_whitespace().collect::<Vec<_>>().join(" "),
            ))
        })
        .collect()
}

/// One `<text>` element of an SVG: position, anchor, whether rotated, content.
struct Text {
    x: f64,
    y: f64,
    dy: String,
    anchor: String,
    rotated: bool,
    content: String,
}

fn attribute(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    Some(tag[start..start + tag[start..].find('"')?].to_string())
}

fn texts(svg: &str) -> Vec<Text> {
    svg.split("<text")
        .skip(1)
        .filter_map(|part| {
            let close = part.find('>')?;
            let tag = &part[..close];
            let content = part[close + 1..part.find("</text>")?].trim();
            Some(Text {
                x: attribute(tag, "x")?.parse().ok()?,
                y: attribute(tag, "y")?.parse().ok()?,
                dy: attribute(tag, "dy").unwrap_or_default(),
                anchor: attribute(tag, "text-anchor").unwrap_or_default(),
                rotated: tag.contains("rotate("),
                content: content
                    .replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&amp;", "&"),
            })
        })
        .collect()
}

/// The problems of one SVG figure (or of the SVG figures inlined in a page): equal
/// adjacent tick labels on an axis (the labels of a y axis share their right edge, those of
/// an x axis their top line), and axis titles without a quantity and unit (a `[unit]`, a
/// ratio `a/b` of like quantities, the word "dimensionless", or a count, "number of").
fn figure_problems(name: &str, svg: &str) -> Vec<String> {
    let mut problems = Vec::new();
    for figure in svg.split("<svg").skip(1) {
        let texts = texts(figure);
        let mut axes: std::collections::BTreeMap<(char, i64), Vec<(f64, String)>> =
            Default::default();
        for t in &texts {
            if t.rotated {
                continue;
            }
            if t.anchor == "end" {
                axes.entry(('y', t.x.round() as i64))
                    .or_default()
                    .push((t.y, t.content.clone()));
            } else if t.anchor == "middle" && t.dy == "0.76em" {
                axes.entry(('x', t.y.round() as i64))
                    .or_default()
                    .push((t.x, t.content.clone()));
            }
        }
        for ((axis, _), mut labels) in axes {
            labels.sort_by(|a, b| a.0.total_cmp(&b.0));
            for w in labels.windows(2) {
                if w[0].1 == w[1].1 && !w[0].1.is_empty() {
                    problems.push(format!(
                        "{name}: equal adjacent {axis} tick labels `{}`",
                        w[0].1
                    ));
                }
            }
        }
        // Axis titles: the rotated text (y) and the text set above the bottom edge (x).
        for t in texts.iter().filter(|t| t.rotated || t.dy == "-0.5ex") {
            let title = &t.content;
            let has_unit = title.contains('[')
                || title.contains('/')
                || title.contains("dimensionless")
                || title.starts_with("number of");
            if title.trim().is_empty() || !has_unit {
                problems.push(format!("{name}: axis title without a unit: `{title}`"));
            }
        }
    }
    problems
}

fn svg_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = entry.path();
        if p.is_dir() {
            svg_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "svg" || e == "html") {
            out.push(p);
        }
    }
}

#[test]
fn bundled_scenarios_report_no_false_alarm_and_their_figures_read_right() {
    let base = tmp("theory-bundled");
    // Every bundled scenario is in the list.
    let mut bundled: Vec<String> = std::fs::read_dir(scenarios())
        .unwrap()
        .filter_map(|e| {
            let name = e.ok()?.file_name().to_string_lossy().to_string();
            Some(name.strip_suffix(".toml")?.to_string())
        })
        .collect();
    bundled.sort();
    let mut listed: Vec<String> = SHORT.iter().map(|(n, _)| n.to_string()).collect();
    listed.sort();
    assert_eq!(bundled, listed, "SHORT must list every bundled scenario");
    let mut failures = Vec::new();
    let mut compared = 0;
    for (name, set) in SHORT {
        let dir = base.join(name);
        run(&scenarios().join(format!("{name}.toml")), &dir, set);
        let html = report(&dir);
        let mut haff_set_up_excluded = false;
        for (class, text) in rows(&html) {
            if class == "bad" {
                failures.push(format!("{name}: red row: {text}"));
            }
            if class == "ok" || class == "warn" {
                compared += 1;
            }
            // The set-up itself rules Haff's law out (walls, a mixture, gravity): not the
            // instability of a periodic box, where the curve shows where the gas leaves it.
            haff_set_up_excluded |= class == "none"
                && text.starts_with("Haff's time")
                && ["walls", "a mixture", "gravity"].iter().any(|w| {
                    text.contains(&format!("Not compared: {w}"))
                        || text.contains(&format!("Not compared: the box has {w}"))
                });
        }
        // A theory the table does not compare for the run's set-up is not drawn in its
        // figures either (the energy figure's Haff curve, legend "Haff's law, t₀ = ...").
        if haff_set_up_excluded && html.contains("law, t₀ = ") {
            failures.push(format!(
                "{name}: Haff's law drawn although the set-up excludes it"
            ));
        }
    }
    // The two cooling runs of section 3.2 overlaid, as docs/dsmc.md does.
    let out = granular()
        .arg("compare")
        .arg(base.join("section32-edmd"))
        .arg(base.join("section32-dsmc"))
        .arg("--out")
        .arg(base.join("compare"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The intruder paper's figures as `granular reproduce` draws them (ten times fewer
    // collisions: the axes and ticks are those of the full runs).
    let out = granular()
        .args(["reproduce", "all", "--quick", "--out"])
        .arg(base.join("reproduce"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut files = Vec::new();
    svg_files(&base, &mut files);
    assert!(
        files
            .iter()
            .filter(|f| f.starts_with(base.join("reproduce")))
            .count()
            >= 7,
        "reproduce drew too few figures"
    );
    assert!(files.len() > 50, "{} figures and pages", files.len());
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        failures.extend(figure_problems(&f.display().to_string(), &text));
    }
    // Some rows are compared at all (the test would pass on a page of grey rows).
    assert!(compared >= 10, "{compared} rows compared");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The checks can fail: a theory made wrong on purpose (the run's resolved scenario edited
/// to another restitution, or to another packing fraction) turns its row red.
#[test]
fn a_run_against_the_wrong_theory_shows_red() {
    let base = tmp("theory-wrong");
    // Haff's law in a box below the critical size of the shear instability.
    let cooling = base.join("cooling");
    run(
        &scenarios().join("dsmc-cooling.toml"),
        &cooling,
        &[
            "species.0.count=4000",
            "species.0.packing_fraction=0.0005",
            "stop.collisions_per_particle=30",
        ],
    );
    let haff = |html: &str| {
        rows(html)
            .into_iter()
            .find(|(_, t)| t.starts_with("Haff's time"))
            .unwrap_or_else(|| panic!("no Haff row in {html}"))
    };
    let (class, text) = haff(&report(&cooling));
    assert!(class == "ok" || class == "warn", "{class}: {text}");
    let path = cooling.join("scenario.toml");
    let resolved = std::fs::read_to_string(&path).unwrap();
    assert!(resolved.contains("restitution = 0.9\n"));
    std::fs::write(
        &path,
        resolved.replace("restitution = 0.9\n", "restitution = 0.85\n"),
    )
    .unwrap();
    let (class, text) = haff(&report(&cooling));
    assert_eq!(class, "bad", "{text}");
    // The equation of state of the walled box, with grains 3 % larger than the run's
    // (6 % more of the box covered).
    let gas = base.join("gas");
    run(
        &scenarios().join("maxwell-boltzmann.toml"),
        &gas,
        &["species.0.count=2000", "stop.collisions_per_particle=150"],
    );
    let z = |html: &str| {
        rows(html)
            .into_iter()
            .find(|(_, t)| t.contains("from the collisional virial"))
            .unwrap_or_else(|| panic!("no Z row in {html}"))
    };
    let (class, text) = z(&report(&gas));
    assert!(class == "ok" || class == "warn", "{class}: {text}");
    let path = gas.join("scenario.toml");
    let resolved = std::fs::read_to_string(&path).unwrap();
    assert!(resolved.contains("packing_fraction = 0.2\n"));
    std::fs::write(
        &path,
        resolved.replace("packing_fraction = 0.2\n", "packing_fraction = 0.212\n"),
    )
    .unwrap();
    let (class, text) = z(&report(&gas));
    assert_eq!(class, "bad", "{text}");
}
