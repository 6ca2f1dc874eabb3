//! `granular plot` for intruder run directories
//! (`engine = "intruder"`): the running temperature ratio (or the needle's temperatures and
//! `R`) against time, and the velocity histograms on the time grid with their reference
//! densities (`intruder_histograms.csv`, see `docs/output.md`).

use std::path::{Path, PathBuf};

use granular::run::{RunDir, RunFile};

use crate::figures::{binned_cdf, chi_square_of_bins};
use crate::plot::{HistogramPlot, LinePlot, PlotError, Series};
use crate::table::{column_of as column, read_run_csv};

fn save(
    stem: &Path,
    r: Result<[PathBuf; 2], PlotError>,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    made.extend(r.map_err(|e| format!("{}: {e}", stem.display()))?);
    Ok(())
}

/// Draws the figures of an intruder run directory into `DIR/figures/`.
pub(crate) fn plot_run(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let run = RunDir::new(dir);
    let out = run.figure_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    let summary = run.summary().ok();
    let block = summary.as_ref().and_then(|s| s.intruder.clone());
    let theory = block.as_ref().and_then(|b| b.theory_temperature_ratio);

    // Running averages against time (after the transient; NaN rows are skipped).
    let ts = read_run_csv(dir, RunFile::TimeSeries)?;
    let rows: Vec<&Vec<String>> = ts.1.iter().collect();
    let time = column(&ts, "time", &rows);
    let pairs: &[(&str, &str)] = if ts.0.iter().any(|c| c == "temperature_ratio") {
        &[("temperature_ratio", "T/T_B")]
    } else {
        &[
            ("translational_temperature_ratio", "T_tr/T_B"),
            ("rotational_temperature_ratio", "T_rot/T_B"),
            ("correlation_r", "R (Eq. 30)"),
        ]
    };
    let mut p = LinePlot::new("Intruder: running averages on the time grid")
        .x_label("time t [τ]")
        .y_label("running average (dimensionless) ± batch-means error");
    for (key, label) in pairs {
        let y = column(&ts, key, &rows);
        let e = column(&ts, &format!("{key}_error"), &rows);
        let e: Vec<f64> = e
            .iter()
            .map(|v| if v.is_finite() { *v } else { 0.0 })
            .collect();
        p = p.series(Series::line(*label, time.clone(), y).with_errors(e));
    }
    if let Some(r) = theory {
        let (t0, t1) = (
            time.first().copied().unwrap_or(0.0),
            time.last().copied().unwrap_or(1.0),
        );
        p = p.series(Series::theory(
            format!("theory {r:.4}"),
            vec![t0, t1],
            vec![r, r],
        ));
    }
    let stem = out.join("running_averages");
    save(&stem, p.save_png_and_svg(&stem), &mut made)?;

    // Histograms with their reference densities.
    let h = read_run_csv(dir, RunFile::IntruderHistograms)?;
    let reference = match block.as_ref().map(|b| b.histogram_reference.as_str()) {
        Some("gaussian_eq18") => "Gaussian at the temperature of Eq. 18".to_string(),
        Some("gaussian_best_fit") => "best-fit zero-mean Gaussian".to_string(),
        Some("maxwellian_g40") => "Maxwellian at the temperature of G-40".to_string(),
        Some("maxwellian_best_fit") => "Maxwellian at the measured temperature".to_string(),
        Some(other) => other.replace('_', " "),
        None => "reference".into(),
    };
    let var = h.0.iter().position(|c| c == "variable").unwrap_or(0);
    let mut names: Vec<String> = Vec::new();
    for r in &h.1 {
        if let Some(n) = r.get(var)
            && !names.contains(n)
        {
            names.push(n.clone());
        }
    }
    for name in names {
        let rows: Vec<&Vec<String>> = h.1.iter().filter(|r| r.get(var) == Some(&name)).collect();
        let (lo, hi) = (column(&h, "low", &rows), column(&h, "high", &rows));
        let dens = column(&h, "density", &rows);
        let th = column(&h, "theory_density", &rows);
        let counts = column(&h, "count", &rows);
        let mut edges = lo.clone();
        edges.push(hi.last().copied().unwrap_or(0.0));
        let centres: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
        let fit = chi_square_of_bins(&edges, &counts, binned_cdf(&edges, &th));
        let (x_label, y_label) = match name.as_str() {
            "velocity" => (
                "intruder velocity v [L/τ]",
                "probability density p(v) [τ/L]",
            ),
            "velocity_component" => (
                "intruder velocity component vₓ, v_y [L/τ]",
                "probability density [τ/L]",
            ),
            "angular_velocity" => ("angular velocity ω [1/τ]", "probability density p(ω) [τ]"),
            "velocity_x" | "velocity_y" | "velocity_z" => (
                "intruder velocity component [L/τ]",
                "probability density [τ/L]",
            ),
            "speed" => (
                "intruder speed |V| [L/τ]",
                "probability density p(|V|) [τ/L]",
            ),
            _ => (
                name.as_str(),
                "probability density [1/unit of the abscissa]",
            ),
        };
        for log in [false, true] {
            let stem = out.join(format!("histogram_{name}{}", if log { "_log" } else { "" }));
            let mut p = HistogramPlot::new(
                format!("Intruder {} on the time grid", name.replace('_', " ")),
                edges.clone(),
                dens.clone(),
            )
            .x_label(x_label)
            .y_label(y_label)
            .log_y(log)
            .theory_points_over_data(reference.clone(), centres.clone(), th.clone());
            if let Some(f) = &fit {
                p = p.goodness_of_fit(f.statistic, f.degrees_of_freedom, f.p_value);
            }
            save(&stem, p.save_png_and_svg(&stem), &mut made)?;
        }
    }
    Ok(made)
}
