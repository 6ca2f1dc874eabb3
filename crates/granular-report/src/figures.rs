//! The figures of a finished run of the edmd or dsmc engine, redrawn from its files
//! (never by rerunning), for `granular plot DIR` (see `directory`). Written to
//! `DIR/figures/` as PNG and SVG.

use crate::plot::{
    Animation, ColourBy, HistogramPlot, LinePlot, PictureStyle, Series, SnapshotPicture,
};
use crate::run_files::save_both;
use crate::table::{column, column_of, read_run_csv, snapshot_files};
use granular::boundary::AxisKind;
use granular::run::{RunDir, RunFile, Summary};
use granular::scenario::Scenario;
use granular::stats::{ChiSquare, Histogram, chi_square_test};
use granular::theory::equilibrium;
use granular::theory::haff;
use std::path::{Path, PathBuf};

fn picture_style(scenario: &Scenario, species: usize) -> PictureStyle {
    let l = scenario.lengths();
    let axes = scenario.axes();
    let style = PictureStyle::new(l[0], l[1])
        .periodic(axes[0] == AxisKind::Periodic, axes[1] == AxisKind::Periodic);
    if species > 1 {
        style.colour_by(ColourBy::Species)
    } else {
        style.colour_by(ColourBy::Speed { max: None })
    }
}

/// Draws the figures of a run of the edmd or dsmc engine (`scenario`, read from `dir`).
pub(crate) fn plot_run(
    dir: &Path,
    scenario: &Scenario,
    animate: bool,
) -> Result<Vec<PathBuf>, String> {
    let run = RunDir::new(dir);
    let out = run.figure_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    let summary = run.summary().ok();
    energy(dir, scenario, &out, &mut made)?;
    speed_histograms(dir, scenario, summary.as_ref(), &out, &mut made)?;
    impact_parameters(dir, scenario, &out, &mut made)?;
    crate::rough_plots::rough_temperatures(dir, scenario, summary.as_ref(), &out, &mut made)?;
    snapshot_figures(dir, scenario, animate, &out, &mut made)?;
    // Impact histograms at several times, S(k), density maps (opt-in [output] keys).
    made.extend(crate::observable_plots::observables(dir, &out)?);
    Ok(made)
}

/// Kinetic energy per grain against time (and per species when there are several); a
/// cooling gas (restitution below 1) on log-log axes with Haff's law (DSMC-3) at the
/// kinetic-theory `t0` (Enskog contact value and first Sonine correction,
/// `theory::haff::enskog_haff_time`).
fn energy(
    dir: &Path,
    scenario: &Scenario,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let names: Vec<String> = scenario.species().iter().map(|s| s.name.clone()).collect();
    let ts = read_run_csv(dir, RunFile::TimeSeries)?;
    let time = column(&ts, "time").unwrap_or_default();
    let run = crate::run_files::load(dir).ok();
    let t0 = run.as_ref().and_then(crate::run_files::haff_time);
    let model = run.as_ref().map_or("", crate::run_files::haff_model);
    let mut energy = LinePlot::new(if t0.is_some() {
        "Kinetic energy of the cooling gas"
    } else {
        "Kinetic energy"
    })
    .x_label("time t [τ]")
    .y_label("kinetic energy per grain E/N [m L²/τ²]");
    let n_total = scenario.particle_count() as f64;
    if let Some(k) = column(&ts, "kinetic_energy") {
        let per_grain: Vec<f64> = k.iter().map(|x| x / n_total).collect();
        let decays = per_grain
            .first()
            .zip(per_grain.last())
            .is_some_and(|(a, b)| *b < 0.1 * a && *b > 0.0);
        if let (Some(t0), Some(&k0)) = (t0, per_grain.first()) {
            let t_end = time.iter().copied().fold(0.0, f64::max);
            let t_start = time.iter().copied().find(|t| *t > 0.0).unwrap_or(t0 * 1e-2);
            energy = energy
                .log_x(true)
                .log_y(true)
                .series(Series::line("all grains", time.clone(), per_grain))
                .series(Series::theory_fn(
                    format!("Haff's law, t₀ = {t0:.4} τ ({model})"),
                    (t_start, t_end.max(t_start * 10.0)),
                    200,
                    true,
                    move |t| haff::haff_energy(k0, t, t0),
                ));
        } else if let Some(drift) = conserved_to_round_off(&per_grain).filter(|_| names.len() < 2) {
            // Constant to round-off: drawn as its relative change, with the constancy in
            // the title, not zoomed onto the noise of the last digits.
            let k0 = per_grain[0];
            let change: Vec<f64> = per_grain.iter().map(|k| k / k0 - 1.0).collect();
            energy = LinePlot::new(format!(
                "Kinetic energy, conserved to round-off (largest |E/E(0) − 1| = {})",
                crate::plot::format_tick(drift)
            ))
            .x_label("time t [τ]")
            .y_label("relative change of the kinetic energy E/E(0) − 1")
            .series(Series::line("all grains", time.clone(), change));
        } else {
            energy =
                energy
                    .log_y(decays)
                    .series(Series::line("all grains", time.clone(), per_grain));
        }
    }
    if names.len() > 1 {
        for name in &names {
            if let Some(k) = column(&ts, &format!("kinetic_energy_per_grain.{name}")) {
                energy = energy.series(Series::line(name.to_string(), time.clone(), k));
            }
        }
    }
    save_both(
        &out.join("energy"),
        energy.save_png_and_svg(out.join("energy")),
        made,
    )
}

/// The largest `|E/E(0) - 1|` of a series that stays constant to round-off (below 10⁻⁹,
/// the elastic event-driven gas); `None` otherwise.
fn conserved_to_round_off(values: &[f64]) -> Option<f64> {
    let first = *values.first()?;
    let drift = values
        .iter()
        .map(|v| (v / first - 1.0).abs())
        .fold(0.0, f64::max);
    (first != 0.0 && values.len() > 1 && drift < 1e-9).then_some(drift)
}

/// Speed histograms per species: initial, and the pooled equilibrium ones with
/// Maxwell-Boltzmann (HD-12) and the run's Pearson test printed on the figure.
fn speed_histograms(
    dir: &Path,
    scenario: &Scenario,
    summary: Option<&Summary>,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let Ok(h) = read_run_csv(dir, RunFile::SpeedHistograms) else {
        return Ok(());
    };
    let d = scenario.dimension;
    let sp_col = h.0.iter().position(|c| c == "species").unwrap_or(0);
    for (s, species) in scenario.species().iter().enumerate() {
        let name = &species.name;
        let rows: Vec<&Vec<String>> = h.1.iter().filter(|r| r.get(sp_col) == Some(name)).collect();
        if rows.is_empty() {
            continue;
        }
        let get = |c: &str| column_of(&h, c, &rows);
        let (lo, hi) = (get("speed_low"), get("speed_high"));
        let mut edges = lo.clone();
        edges.push(*hi.last().unwrap_or(&0.0));
        let initial = get("initial_density");
        let stem = out.join(format!("speed_initial_{name}"));
        let p = HistogramPlot::new(format!("Initial speeds: {name}"), edges.clone(), initial)
            .x_label("speed v [L/τ]")
            .y_label("probability density p(v) [τ/L]");
        save_both(&stem, p.save_png_and_svg(&stem), made)?;
        if let Some(scaled) = summary.and_then(|sm| sm.scaled_speeds.get(name)) {
            // Not a steady state: no single temperature describes the pooled speeds; the
            // scaled speeds c = v / v_T(t) instead.
            scaled_speed_histogram(dir, name, scaled.a2, out, made)?;
            continue;
        }
        let eq = get("equilibrium_density");
        let counts = get("equilibrium_count");
        let total: f64 = counts.iter().filter(|c| c.is_finite()).sum();
        if total <= 0.0 {
            continue;
        }
        let width = hi[0] - lo[0];
        let errors: Vec<f64> = counts
            .iter()
            .map(|c| c.max(0.0).sqrt() / (total * width))
            .collect();
        let mass = scenario.species()[s].mass;
        let fit = summary.and_then(|sm| sm.maxwell_boltzmann_fit.get(name));
        // The fit's temperature; without one, that of the pooled density.
        let temperature = fit.map_or_else(
            || {
                let mv2: f64 = lo
                    .iter()
                    .zip(&hi)
                    .zip(&eq)
                    .map(|((a, b), p)| mass * (0.5 * (a + b)).powi(2) * p * width)
                    .sum();
                equilibrium::kinetic_temperature(d, mv2)
            },
            |f| f.temperature,
        );
        let stem = out.join(format!("speed_equilibrium_{name}"));
        let mut p = HistogramPlot::new(format!("Equilibrium speeds: {name}"), edges.clone(), eq)
            .with_errors(errors)
            .data_label(format!("simulation ({} speeds)", total as u64))
            .x_label("speed v [L/τ]")
            .y_label("probability density p(v) [τ/L]")
            .theory(
                format!("Maxwell-Boltzmann, T = {temperature:.4} [m L²/τ²]"),
                move |v| equilibrium::speed_density(d, v, mass, temperature),
            );
        if let Some(f) = fit {
            p = p.goodness_of_fit(f.chi_square, f.degrees_of_freedom, f.p_value);
        }
        save_both(&stem, p.save_png_and_svg(&stem), made)?;
    }
    Ok(())
}

/// The pooled scaled speeds `c = v / v_T(t)` of a species that was not in a steady state
/// (`scaled_speed_histograms.csv`) against the Maxwell-Boltzmann density of `c`, with
/// Pearson's test and the pooled `a2`.
fn scaled_speed_histogram(
    dir: &Path,
    name: &str,
    a2: f64,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let Ok(h) = read_run_csv(dir, RunFile::ScaledSpeedHistograms) else {
        return Ok(());
    };
    let sp_col = h.0.iter().position(|c| c == "species").unwrap_or(0);
    let rows: Vec<&Vec<String>> =
        h.1.iter()
            .filter(|r| r.get(sp_col).map(String::as_str) == Some(name))
            .collect();
    let get = |c: &str| column_of(&h, c, &rows);
    let (lo, hi, dens, counts, mb) = (
        get("c_low"),
        get("c_high"),
        get("density"),
        get("count"),
        get("maxwell_boltzmann_density"),
    );
    if lo.is_empty() || hi.len() != lo.len() {
        return Ok(());
    }
    let mut edges = lo.clone();
    edges.push(*hi.last().unwrap_or(&0.0));
    let centres: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
    let total: f64 = counts.iter().filter(|c| c.is_finite()).sum();
    let stem = out.join(format!("speed_scaled_{name}"));
    let mut p = HistogramPlot::new(
        format!("Scaled speeds of the cooling gas: {name}"),
        edges.clone(),
        dens,
    )
    .data_label(format!(
        "simulation ({} speeds), a₂ = {a2:.4}",
        total as u64
    ))
    .x_label("scaled speed c = v/v_T(t)")
    .y_label("probability density p(c) (dimensionless)")
    .theory_points("Maxwell-Boltzmann", centres, mb.clone());
    if let Some(fit) = chi_square_of_bins(&edges, &counts, binned_cdf(&edges, &mb)) {
        p = p.goodness_of_fit(fit.statistic, fit.degrees_of_freedom, fit.p_value);
    }
    save_both(&stem, p.save_png_and_svg(&stem), made)
}

/// Pearson's test of binned counts (`counts[i]` in `[edges[i], edges[i+1])`) against a
/// model's cumulative distribution over the binned range, pooling bins to five expected
/// counts (`granular::stats::chi_square_test`).
pub(crate) fn chi_square_of_bins(
    edges: &[f64],
    counts: &[f64],
    cdf: impl Fn(f64) -> f64,
) -> Option<ChiSquare> {
    let (&min, &max) = (edges.first()?, edges.last()?);
    let bins = counts.len();
    if bins == 0 || edges.len() != bins + 1 || counts.iter().any(|c| !c.is_finite() || *c < 0.0) {
        return None;
    }
    // Equal bins are what `Histogram` holds; the run files write equal bins.
    let width = (max - min) / bins as f64;
    if edges
        .windows(2)
        .any(|w| ((w[1] - w[0]) - width).abs() > 1e-9 * width.abs().max(1e-300))
    {
        return None;
    }
    let mut hist = Histogram::new(min, max, bins);
    hist.counts = counts.iter().map(|c| c.round() as u64).collect();
    (hist.total() > 0).then(|| chi_square_test(&hist, cdf))
}

/// Impact parameters of pair collisions against molecular chaos (uniform in 2D, 2x in 3D),
/// with Pearson's test.
fn impact_parameters(
    dir: &Path,
    scenario: &Scenario,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let d = scenario.dimension;
    let Ok(h) = read_run_csv(dir, RunFile::ImpactParameter) else {
        return Ok(());
    };
    let (Some(lo), Some(hi), Some(dens)) = (
        column(&h, "b_over_sigma_low"),
        column(&h, "b_over_sigma_high"),
        column(&h, "density"),
    ) else {
        return Ok(());
    };
    if !dens.iter().any(|x| *x > 0.0) {
        return Ok(());
    }
    let mut edges = lo.clone();
    edges.push(*hi.last().unwrap_or(&1.0));
    let stem = out.join("impact_parameter");
    let mut p = HistogramPlot::new("Impact parameters of collisions", edges.clone(), dens)
        .x_label("reduced impact parameter b/σ")
        .y_label("probability density p(b/σ)")
        .theory("molecular chaos", move |x| {
            haff::impact_parameter_density(d, x)
        });
    if let Some(counts) = column(&h, "count")
        && let Some(fit) = chi_square_of_bins(&edges, &counts, |x| haff::impact_parameter_cdf(d, x))
    {
        p = p.goodness_of_fit(fit.statistic, fit.degrees_of_freedom, fit.p_value);
    }
    save_both(&stem, p.save_png_and_svg(&stem), made)
}

/// Fewer snapshots than this make a short animation: its title says how to get more.
const FEW_FRAMES: usize = 10;

/// Snapshots, first and last: 2D runs as they are; 3D runs as the x-y projection of all
/// grains (nearer grains on top) and as a central slice `Lz/2 ± w` (`w` two grain
/// diameters or `Lz/20`, whichever is larger). With `animate`, a GIF (and MP4) of all
/// snapshots (2D: the box; 3D: the projection).
fn snapshot_figures(
    dir: &Path,
    scenario: &Scenario,
    animate: bool,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let files = snapshot_files(dir);
    let species = scenario.species().len();
    let l = scenario.lengths();
    for (label, file) in [("first", files.first()), ("last", files.last())] {
        let Some(f) = file else { continue };
        let snap = granular::run::read_snapshot(f).map_err(|e| e.to_string())?;
        let stem = out.join(format!("snapshot_{label}"));
        let style = picture_style(scenario, species);
        if scenario.dimension == 2 {
            let r = SnapshotPicture::new(&snap, style).save_png_and_svg(&stem);
            save_both(&stem, r, made)?;
            continue;
        }
        let lz = l.get(2).copied().unwrap_or(1.0);
        let r_max = snap.radii.iter().copied().fold(0.0, f64::max);
        let w = (4.0 * r_max).max(lz / 20.0);
        let projection = style.clone().title("x-y projection of all grains");
        let r = SnapshotPicture::new(&snap, projection).save_png_and_svg(&stem);
        save_both(&stem, r, made)?;
        let stem = out.join(format!("snapshot_{label}_slice"));
        let slice = style
            .title(format!(
                "slice {:.4} ≤ z < {:.4} [L] (centres)",
                0.5 * lz - w,
                0.5 * lz + w
            ))
            .slab(0.5 * lz - w, 0.5 * lz + w);
        let r = SnapshotPicture::new(&snap, slice).save_png_and_svg(&stem);
        save_both(&stem, r, made)?;
    }
    if animate && files.len() > 1 {
        let snaps = files
            .iter()
            .map(|f| granular::run::read_snapshot(f).map_err(|e| e.to_string()))
            .collect::<Result<Vec<_>, String>>()?;
        let mut style = picture_style(scenario, species).show_time(true);
        if snaps.len() < FEW_FRAMES {
            style = style.title(few_frames_note(snaps.len()));
        }
        let path = out.join("animation.gif");
        let anim = Animation::new(&snaps, style);
        anim.save_gif(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        made.push(path.clone());
        let mp4 = out.join("animation.mp4");
        if anim.save_mp4(&mp4).map_err(|e| e.to_string())? {
            made.push(mp4);
        }
    }
    Ok(())
}

/// The title of an animation with few frames: how to get more.
pub(crate) fn few_frames_note(frames: usize) -> String {
    format!(
        "only {frames} snapshots: for more frames, rerun with --set output.snapshot_every=1 \
         (and a smaller output.interval)"
    )
}

/// The cumulative distribution over the binned range of a density given as bin averages
/// (`density[i]` over `[edges[i], edges[i+1])`), normalised to 1 over the range (samples
/// outside it are not counted), linear inside each bin.
pub(crate) fn binned_cdf(edges: &[f64], density: &[f64]) -> impl Fn(f64) -> f64 + use<> {
    let mut cumulative = vec![0.0];
    for (w, d) in edges.windows(2).zip(density) {
        let mass = if d.is_finite() {
            d.max(0.0) * (w[1] - w[0])
        } else {
            0.0
        };
        cumulative.push(cumulative.last().copied().unwrap_or(0.0) + mass);
    }
    let total = cumulative.last().copied().unwrap_or(0.0);
    let edges = edges.to_vec();
    move |x: f64| {
        if total <= 0.0 || edges.len() < 2 {
            return f64::NAN;
        }
        let i = edges.partition_point(|e| *e <= x);
        if i == 0 {
            return 0.0;
        }
        if i >= edges.len() {
            return 1.0;
        }
        let (a, b) = (edges[i - 1], edges[i]);
        let f = cumulative[i - 1] + (cumulative[i] - cumulative[i - 1]) * (x - a) / (b - a);
        f / total
    }
}

#[cfg(test)]
mod tests {
    use super::binned_cdf;

    #[test]
    fn binned_cdf_is_piecewise_linear_and_normalised() {
        let cdf = binned_cdf(&[0.0, 1.0, 2.0], &[0.25, 0.75]);
        assert_eq!(cdf(-1.0), 0.0);
        assert_eq!(cdf(0.0), 0.0);
        assert!((cdf(0.5) - 0.125).abs() < 1e-15);
        assert!((cdf(1.0) - 0.25).abs() < 1e-15);
        assert!((cdf(1.5) - 0.625).abs() < 1e-15);
        assert_eq!(cdf(2.0), 1.0);
        assert_eq!(cdf(3.0), 1.0);
    }
}
