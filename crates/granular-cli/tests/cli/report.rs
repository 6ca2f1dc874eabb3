//! `granular report`: the HTML page of a run and of a sweep, read back as text (the browser
//! test of the player is in the Python suite, `tests/test_report.py`).

use super::{granular, scenarios, tmp};
use std::path::Path;

fn report(dir: &Path) -> (String, Vec<String>) {
    let out = granular().arg("report").arg(dir).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let pages = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect();
    (
        std::fs::read_to_string(dir.join("report.html")).unwrap(),
        pages,
    )
}

/// The page loads nothing: no `src` or `href` to another file or the network, no CSS `url()`,
/// no `@import` (an SVG namespace is not a request).
fn assert_self_contained(html: &str) {
    for bad in [
        " src=",
        "href=\"http",
        "url(",
        "@import",
        "<link",
        "<iframe",
    ] {
        assert!(!html.contains(bad), "the page contains `{bad}`");
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn report_of_an_elastic_run_has_its_theory_and_the_player_data() {
    let dir = tmp("report-mb");
    let out = granular()
        .arg("run")
        .arg(scenarios().join("maxwell-boltzmann.toml"))
        .arg("--out")
        .arg(&dir)
        .args(["--quiet", "--set", "species.0.count=1000"])
        .args(["--set", "stop.collisions_per_particle=60"])
        .args(["--set", "output.snapshot_every=20"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (html, pages) = report(&dir);
    assert_eq!(pages, vec![dir.join("report.html").display().to_string()]);
    assert_self_contained(&html);
    assert!(html.contains("χ² of the speeds of disk against Maxwell-Boltzmann"));
    assert!(html.contains("compressibility factor Z = P/(nT)"));
    assert!(html.contains("<svg class=\"figure\""));
    assert!(
        html.contains("engine = &quot;edmd&quot;"),
        "the resolved scenario, escaped"
    );
    // The player's data: every snapshot, every grain, histograms over all grains.
    let start = html.find("id=\"granular-data\">").unwrap() + "id=\"granular-data\">".len();
    let end = start + html[start..].find("</script>").unwrap();
    let data: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
    let snapshots = std::fs::read_dir(dir.join("snapshots")).unwrap().count();
    assert_eq!(
        summary(&dir)["snapshots"].as_u64().unwrap() as usize,
        snapshots
    );
    assert_eq!(data["frames"].as_array().unwrap().len(), snapshots);
    assert_eq!(data["grains_total"], 1000);
    for f in data["frames"].as_array().unwrap() {
        let total: u64 = f["histogram"]["counts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap())
            .sum();
        assert_eq!(total, 1000);
    }
    assert!(!html.contains("id=\"subsample-notice\""));
}

#[test]
fn report_of_an_intruder_sweep_links_every_member() {
    let dir = tmp("report-sweep");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scenarios().join("intruder-1d.toml")).unwrap()
        + "\n[sweep]\nkey = \"intruder.restitution\"\nvalues = [0.2, 0.8]\nseeds = 2\nobservable = \"temperature_ratio\"\n";
    std::fs::write(dir.join("sweep.toml"), text).unwrap();
    let out = granular()
        .args(["sweep", "--out"])
        .arg(dir.join("out"))
        .arg(dir.join("sweep.toml"))
        .args(["--set", "stop.collisions=50000"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sweep = dir.join("out");
    let (html, pages) = report(&sweep);
    assert_eq!(pages.len(), 5, "{pages:?}");
    assert_self_contained(&html);
    assert!(html.contains("<th>temperature_ratio_mean</th>"));
    assert!(html.contains("<svg class=\"figure\""), "the sweep's figure");
    // The figures plot each observable's mean over the seeds with its standard error as bars,
    // and the table has both columns.
    assert!(html.contains("mean ± standard error over seeds"));
    assert!(html.contains("<th>temperature_ratio_stderr</th>"));
    for p in 0..2 {
        for s in 0..2 {
            let member = format!("point_{p:03}/seed_{s:03}");
            assert!(html.contains(&format!("href=\"{member}/report.html\"")));
            let page = std::fs::read_to_string(sweep.join(&member).join("report.html")).unwrap();
            assert_self_contained(&page);
            // The deviation shown is the one the library wrote into summary.json.
            let z = summary(&sweep.join(&member))["intruder"]["temperature_ratio_z"]
                .as_f64()
                .unwrap();
            assert!(page.contains(&format!("{z:+.2} σ")), "{member}: z = {z}");
            assert!(page.contains("Martin-Piasecki"));
            assert!(
                !page.contains("granular-data"),
                "no player without snapshots"
            );
        }
    }
}

#[test]
fn report_of_a_directory_that_is_no_run_says_what_to_give() {
    let dir = tmp("report-empty");
    std::fs::create_dir_all(&dir).unwrap();
    let out = granular().arg("report").arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("neither a run directory"), "{err}");
    assert!(err.contains("granular run --out"), "{err}");
}
