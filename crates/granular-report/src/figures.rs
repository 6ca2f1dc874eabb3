//! `granular plot DIR`: the figures of a finished run or sweep, redrawn from its files
//! (never by rerunning). Written to `DIR/figures/` as PNG and SVG.

use crate::plot::{
    Animation, ColourBy, HistogramPlot, LinePlot, PictureStyle, PlotError, Series, SnapshotPicture,
};
use crate::table::{Table, column, read_csv};
use granular::boundary::AxisKind;
use granular::run::sweep::SweepTable;
use granular::scenario::Scenario;
use granular::theory::equilibrium;
use granular::theory::haff;
use std::path::{Path, PathBuf};

fn save_both(
    stem: &Path,
    r: Result<[PathBuf; 2], PlotError>,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let files = r.map_err(|e| format!("{}: {e}", stem.display()))?;
    made.extend(files);
    Ok(())
}

/// Draws the figures of a run or a sweep directory; returns the files written.
pub(crate) fn plot(dir: &Path, animate: bool) -> Result<Vec<PathBuf>, String> {
    if dir.join("sweep.csv").is_file() {
        plot_sweep(dir)
    } else if dir.join("timeseries.csv").is_file() {
        plot_run(dir, animate)
    } else {
        Err(format!(
            "{}: neither a run directory (timeseries.csv) nor a sweep directory (sweep.csv)",
            dir.display()
        ))
    }
}

fn snapshots(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("snapshots"))
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "npz"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

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

fn plot_run(dir: &Path, animate: bool) -> Result<Vec<PathBuf>, String> {
    let text = std::fs::read_to_string(dir.join("scenario.toml"))
        .map_err(|e| format!("{}: {e}", dir.join("scenario.toml").display()))?;
    let scenario = Scenario::from_resolved_toml(&text).map_err(|e| e.to_string())?;
    if scenario.intruder.is_some() {
        return crate::intruder_plots::plot_run(dir);
    }
    let out = dir.join("figures");
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    let d = scenario.dimension;
    let names: Vec<String> = scenario.species.iter().map(|s| s.name.clone()).collect();

    // Kinetic energy against time (per grain and species when there are several).
    let ts = read_csv(&dir.join("timeseries.csv"))?;
    let time = column(&ts, "time").unwrap_or_default();
    let mut energy = LinePlot::new("Kinetic energy")
        .x_label("time t")
        .y_label("kinetic energy per grain E / N");
    let n_total = scenario.particle_count() as f64;
    if let Some(k) = column(&ts, "kinetic_energy") {
        let per_grain: Vec<f64> = k.iter().map(|x| x / n_total).collect();
        let decays = per_grain
            .first()
            .zip(per_grain.last())
            .is_some_and(|(a, b)| *b < 0.1 * a && *b > 0.0);
        energy = energy
            .log_y(decays)
            .series(Series::line("all grains", time.clone(), per_grain));
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
        &mut made,
    )?;

    // Speed histograms: initial and pooled equilibrium, with Maxwell-Boltzmann (HD-12).
    if let Ok(h) = read_csv(&dir.join("speed_histograms.csv")) {
        let sp_col = h.0.iter().position(|c| c == "species").unwrap_or(0);
        for (s, name) in names.iter().enumerate() {
            let rows: Vec<&Vec<String>> =
                h.1.iter().filter(|r| r.get(sp_col) == Some(name)).collect();
            if rows.is_empty() {
                continue;
            }
            let get = |c: &str| -> Vec<f64> {
                let i = h.0.iter().position(|x| x == c).unwrap_or(0);
                rows.iter()
                    .map(|r| r.get(i).and_then(|x| x.parse().ok()).unwrap_or(f64::NAN))
                    .collect()
            };
            let (lo, hi) = (get("speed_low"), get("speed_high"));
            let mut edges = lo.clone();
            edges.push(*hi.last().unwrap_or(&0.0));
            let initial = get("initial_density");
            let stem = out.join(format!("speed_initial_{name}"));
            let p = HistogramPlot::new(format!("Initial speeds: {name}"), edges.clone(), initial)
                .x_label("speed v")
                .y_label("probability density p(v)");
            save_both(&stem, p.save_png_and_svg(&stem), &mut made)?;
            let eq = get("equilibrium_density");
            let counts = get("equilibrium_count");
            let total: f64 = counts.iter().filter(|c| c.is_finite()).sum();
            if total > 0.0 {
                let width = hi[0] - lo[0];
                let errors: Vec<f64> = counts
                    .iter()
                    .map(|c| c.max(0.0).sqrt() / (total * width))
                    .collect();
                let mass = scenario.species[s].mass;
                // Temperature of the pooled samples from the mean of m v^2 over the density.
                let mv2: f64 = lo
                    .iter()
                    .zip(&hi)
                    .zip(&eq)
                    .map(|((a, b), p)| mass * (0.5 * (a + b)).powi(2) * p * width)
                    .sum();
                let temperature = equilibrium::kinetic_temperature(d, mv2);
                let stem = out.join(format!("speed_equilibrium_{name}"));
                let p =
                    HistogramPlot::new(format!("Equilibrium speeds: {name}"), edges.clone(), eq)
                        .with_errors(errors)
                        .data_label(format!("simulation ({} speeds)", total as u64))
                        .x_label("speed v")
                        .y_label("probability density p(v)")
                        .theory(
                            format!("Maxwell-Boltzmann, T = {temperature:.4}"),
                            move |v| equilibrium::speed_density(d, v, mass, temperature),
                        );
                save_both(&stem, p.save_png_and_svg(&stem), &mut made)?;
            }
        }
    }

    // Impact parameters of pair collisions against molecular chaos (uniform in 2D, 2x in 3D).
    if let Ok(h) = read_csv(&dir.join("impact_parameter.csv"))
        && let (Some(lo), Some(hi), Some(dens)) = (
            column(&h, "b_over_sigma_low"),
            column(&h, "b_over_sigma_high"),
            column(&h, "density"),
        )
        && dens.iter().any(|x| *x > 0.0)
    {
        let mut edges = lo.clone();
        edges.push(*hi.last().unwrap_or(&1.0));
        let stem = out.join("impact_parameter");
        let p = HistogramPlot::new("Impact parameters of collisions", edges, dens)
            .x_label("impact parameter b / sigma")
            .y_label("probability density")
            .theory("molecular chaos", move |x| {
                haff::impact_parameter_density(d, x)
            });
        save_both(&stem, p.save_png_and_svg(&stem), &mut made)?;
    }

    // Snapshots: first and last, grains as true-size disks.
    let files = snapshots(dir);
    if d == 2 {
        for (label, file) in [("first", files.first()), ("last", files.last())] {
            if let Some(f) = file {
                let snap = granular::run::read_snapshot(f).map_err(|e| e.to_string())?;
                let stem = out.join(format!("snapshot_{label}"));
                let style = picture_style(&scenario, names.len());
                save_both(
                    &stem,
                    SnapshotPicture::new(&snap, style).save_png_and_svg(&stem),
                    &mut made,
                )?;
            }
        }
        if animate && files.len() > 1 {
            let snaps = files
                .iter()
                .map(|f| granular::run::read_snapshot(f).map_err(|e| e.to_string()))
                .collect::<Result<Vec<_>, String>>()?;
            let path = out.join("animation.gif");
            let anim = Animation::new(
                &snaps,
                picture_style(&scenario, names.len()).show_time(true),
            );
            anim.save_gif(&path)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            made.push(path.clone());
            let mp4 = out.join("animation.mp4");
            if anim.save_mp4(&mp4).map_err(|e| e.to_string())? {
                made.push(mp4);
            }
        }
    }
    // Impact histograms at several times, S(k), density maps (opt-in [output] keys).
    made.extend(crate::observable_plots::observables(dir, &out)?);
    Ok(made)
}

fn plot_sweep(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let table = SweepTable::read(dir).map_err(|e| e.to_string())?;
    let key = table
        .keys
        .first()
        .cloned()
        .unwrap_or_else(|| "point".into());
    let out = dir.join("figures");
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    // The first key on the x axis (the point number for a key whose values are text);
    // one curve per combination of the other keys.
    let x: Vec<f64> = table
        .rows
        .iter()
        .map(|r| match r.numbers.first() {
            Some(x) if x.is_finite() => *x,
            _ => r.point as f64,
        })
        .collect();
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, r) in table.rows.iter().enumerate() {
        let label: Vec<String> = table
            .keys
            .iter()
            .zip(&r.values)
            .skip(1)
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        let label = label.join(", ");
        match groups.iter_mut().find(|g| g.0 == label) {
            Some(g) => g.1.push(i),
            None => groups.push((label, vec![i])),
        }
    }
    // One figure per observable with error bars over seeds.
    for name in &table.observables {
        let Some((y, e)) = table.observable(name) else {
            continue;
        };
        if y.iter().all(|v| !v.is_finite()) {
            continue;
        }
        let stem = out.join(format!("sweep_{}", name.replace(['.', '/'], "_")));
        let mut p = LinePlot::new(format!("{name} against {key}"))
            .x_label(key.clone())
            .y_label(format!("{name} (mean ± standard error)"));
        for (label, rows) in &groups {
            let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<f64>>();
            let err: Vec<f64> = pick(&e)
                .into_iter()
                .map(|v| if v.is_finite() { v } else { 0.0 })
                .collect();
            let label = if label.is_empty() {
                name.clone()
            } else {
                label.clone()
            };
            p = p.series(Series::line_markers(label, pick(&x), pick(&y)).with_errors(err));
        }
        save_both(&stem, p.save_png_and_svg(&stem), &mut made)?;
    }
    // Time series of every point (mean over seeds), per species energy when present.
    let points: Vec<(String, Vec<PathBuf>)> = table
        .meta
        .points
        .iter()
        .zip(&table.rows)
        .map(|(p, r)| {
            let label: Vec<String> = table
                .keys
                .iter()
                .zip(&r.values)
                .map(|(k, v)| format!("{k} = {v}"))
                .collect();
            (
                label.join(", "),
                p.members.iter().map(|m| dir.join(m)).collect(),
            )
        })
        .collect();
    let mut energy = LinePlot::new(format!("Kinetic energy per grain, by {key}"))
        .x_label("time t")
        .y_label("kinetic energy per grain");
    let mut any = false;
    for (label, seeds) in &points {
        let tables: Vec<Table> = seeds
            .iter()
            .filter_map(|s| read_csv(&s.join("timeseries.csv")).ok())
            .collect();
        let Some(first) = tables.first() else {
            continue;
        };
        let time = column(first, "time").unwrap_or_default();
        let species_cols: Vec<String> = first
            .0
            .iter()
            .filter(|c| c.starts_with("kinetic_energy_per_grain."))
            .cloned()
            .collect();
        let cols: Vec<String> = if species_cols.is_empty() {
            vec!["kinetic_energy".into()]
        } else {
            species_cols
        };
        for c in cols {
            let mut mean = vec![0.0; time.len()];
            let mut used = 0.0;
            for t in &tables {
                if let Some(v) = column(t, &c)
                    && v.len() >= time.len()
                {
                    mean.iter_mut().zip(&v).for_each(|(m, x)| *m += x);
                    used += 1.0;
                }
            }
            if used > 0.0 {
                mean.iter_mut().for_each(|m| *m /= used);
                let species = c.strip_prefix("kinetic_energy_per_grain.").unwrap_or("all");
                energy = energy.series(Series::line(
                    format!("{label}: {species}"),
                    time.clone(),
                    mean,
                ));
                any = true;
            }
        }
    }
    if any {
        let stem = out.join("sweep_energy_time");
        save_both(&stem, energy.save_png_and_svg(&stem), &mut made)?;
    }
    Ok(made)
}
