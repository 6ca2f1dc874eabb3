//! The figures of the opt-in observables (`output.impact_histograms`,
//! `output.structure_factor`, `output.density_map`): impact-parameter histograms between
//! observation times, `S(k)` and its peak, density maps. Shared by `granular plot` (one run)
//! and `granular compare` (several runs, times in units of the first run's `t0`).

use crate::plot::{HeatMaps, HeatPanel, LinePlot, Series};
use crate::run_files::{RunFiles, floats, get, haff_time, load, save, tag};
use granular::output::npz::read_npz;
use granular::run::{RunDir, RunFile};
use granular::theory::{equilibrium, haff};
use std::path::{Path, PathBuf};

/// The figures of the opt-in observables of one run (impact histograms, `S(k)`, density
/// maps; nothing when the run has none), for `granular plot`.
pub(crate) fn observables(dir: &Path, out: &Path) -> Result<Vec<PathBuf>, String> {
    let runs = [load(dir)?];
    let mut made = Vec::new();
    impact(&runs, out, &mut made)?;
    structure_factor(&runs, out, &mut made)?;
    density_maps(&runs, out, &mut made)?;
    Ok(made)
}

pub(crate) fn impact(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    for run in runs {
        let path = RunDir::new(&run.dir).file(RunFile::ImpactHistograms);
        if !path.is_file() {
            continue;
        }
        let a = read_npz(&path).map_err(|e| e.to_string())?;
        let edges = floats(&a, "edges", &path)?;
        let dens = floats(&a, "density", &path)?;
        let (ts, te) = (floats(&a, "t_start", &path)?, floats(&a, "t_end", &path)?);
        let bins = edges.len().saturating_sub(1);
        if bins == 0 || dens.len() != ts.len() * bins {
            continue;
        }
        let centres: Vec<f64> = edges.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
        let unit = t0.unwrap_or(1.0);
        let name = if t0.is_some() { "t/t₀" } else { "t/τ" };
        // From 0, so that a flat histogram looks flat next to one with a grazing excess.
        let top = dens
            .iter()
            .cloned()
            .filter(|v| v.is_finite())
            .fold(1.25, f64::max);
        let mut plot = LinePlot::new(format!("Impact parameters: {}", run.label))
            .x_label("reduced impact parameter b/σ")
            .y_label("probability density p(b/σ)")
            .y_range(0.0, 1.05 * top);
        for (i, row) in dens.chunks(bins).enumerate() {
            if row.iter().all(|v| !v.is_finite()) {
                continue;
            }
            plot = plot.series(Series::line_markers(
                format!("{name} = {:.2}-{:.2}", ts[i] / unit, te[i] / unit),
                centres.clone(),
                row.to_vec(),
            ));
        }
        let d = run.scenario.dimension;
        plot = plot.series(Series::theory_fn(
            "molecular chaos",
            (0.0, 1.0),
            50,
            false,
            move |x| haff::impact_parameter_density(d, x),
        ));
        save(&plot, out.join(format!("impact_{}", tag(run))), made)?;
    }
    Ok(())
}

/// `S(k)` per observation, restricted to complete shells (`|n| <= max_index`).
pub(crate) struct SkData {
    pub times: Vec<f64>,
    pub k_units: Vec<f64>,
    pub rows: Vec<Vec<f64>>,
}

pub(crate) fn read_sk(run: &RunFiles) -> Result<Option<SkData>, String> {
    let path = RunDir::new(&run.dir).file(RunFile::StructureFactor);
    if !path.is_file() {
        return Ok(None);
    }
    let a = read_npz(&path).map_err(|e| e.to_string())?;
    let times = floats(&a, "times", &path)?.to_vec();
    let k = floats(&a, "k", &path)?;
    let s = floats(&a, "s", &path)?;
    let l = run.scenario.lengths().iter().cloned().fold(0.0, f64::max);
    let max_index = run.scenario.output.structure_factor_max_index as f64;
    let k_units: Vec<f64> = k
        .iter()
        .map(|k| k * l / (2.0 * std::f64::consts::PI))
        .collect();
    let keep: Vec<usize> = (0..k.len())
        .filter(|&i| k_units[i] <= max_index + 0.5)
        .collect();
    if k.is_empty() || s.len() != times.len() * k.len() {
        return Ok(None);
    }
    let rows = s
        .chunks(k.len())
        .map(|r| keep.iter().map(|&i| r[i]).collect())
        .collect();
    Ok(Some(SkData {
        times,
        k_units: keep.iter().map(|&i| k_units[i]).collect(),
        rows,
    }))
}

/// The packing fraction of a run and the long-wavelength limit `S(0)` of the equilibrium
/// fluid at it, from the library's equation of state
/// (`theory::equilibrium::structure_factor_zero`).
fn eos_structure_factor_zero(scenario: &granular::scenario::Scenario) -> (f64, f64) {
    let phi = scenario
        .resolve()
        .grains
        .map_or(f64::NAN, |g| g.packing_fraction);
    (
        phi,
        equilibrium::structure_factor_zero(scenario.dimension, phi),
    )
}

pub(crate) fn structure_factor(
    runs: &[RunFiles],
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    let unit = t0.unwrap_or(1.0);
    let name = if t0.is_some() { "t/t₀" } else { "t/τ" };
    let mut peak = LinePlot::new("Largest S(k) against time")
        .x_label(if t0.is_some() {
            "time t/t₀"
        } else {
            "time t [τ]"
        })
        .y_label("largest structure factor max S(k) (dimensionless)")
        .log_x(true)
        .log_y(true);
    let mut any = false;
    for run in runs {
        let Some(sk) = read_sk(run)? else {
            continue;
        };
        let mut plot = LinePlot::new(format!("Structure factor: {}", run.label))
            .x_label("wave number k [2π/L]")
            .y_label("structure factor S(k) (dimensionless)")
            .log_x(true)
            .log_y(true);
        let mut px = Vec::new();
        let mut py = Vec::new();
        for (t, row) in sk.times.iter().zip(&sk.rows) {
            plot = plot.series(Series::line(
                format!("{name} = {:.3}", t / unit),
                sk.k_units.clone(),
                row.clone(),
            ));
            if *t > 0.0 {
                px.push(t / unit);
                py.push(row.iter().cloned().fold(0.0, f64::max));
            }
        }
        let k_range = vec![sk.k_units[0], *sk.k_units.last().unwrap_or(&1.0)];
        plot = plot.series(Series::theory(
            "ideal gas, S = 1",
            k_range.clone(),
            vec![1.0, 1.0],
        ));
        let s0 = eos_structure_factor_zero(&run.scenario);
        plot = plot.series(Series::theory(
            format!(
                "S(0) of the equation of state, φ = {:.3}: {:.3}",
                s0.0, s0.1
            ),
            k_range,
            vec![s0.1, s0.1],
        ));
        save(
            &plot,
            out.join(format!("structure_factor_{}", tag(run))),
            made,
        )?;
        if !px.is_empty() {
            peak = peak.series(Series::line_markers(run.label.clone(), px, py));
            any = true;
        }
    }
    if any {
        save(&peak, out.join("structure_factor_peak"), made)?;
    }
    Ok(())
}

pub(crate) fn density_maps(
    runs: &[RunFiles],
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    let unit = t0.unwrap_or(1.0);
    let name = if t0.is_some() { "t/t₀" } else { "t/τ" };
    let mut fig = HeatMaps::new("number density in bins / mean density", 3).log_scale(true);
    let mut any = false;
    for run in runs {
        let path = RunDir::new(&run.dir).file(RunFile::DensityMaps);
        if !path.is_file() || run.scenario.dimension != 2 {
            continue;
        }
        let a = read_npz(&path).map_err(|e| e.to_string())?;
        let times = floats(&a, "times", &path)?;
        let dens = get(&a, "density", &path)?;
        let values = dens
            .as_f64()
            .ok_or_else(|| format!("{}: `density` is not float64", path.display()))?;
        let (ny, nx) = match dens.shape.as_slice() {
            [_, ny, nx] => (*ny as usize, *nx as usize),
            _ => continue,
        };
        let volume: f64 = run.scenario.lengths().iter().product();
        let mean = run.scenario.particle_count() as f64 / volume;
        let picks = [0, times.len() / 2, times.len().saturating_sub(1)];
        for &i in &picks {
            let Some(t) = times.get(i) else { continue };
            let v = values[i * nx * ny..(i + 1) * nx * ny]
                .iter()
                .map(|x| x / mean)
                .collect();
            fig = fig.panel(HeatPanel {
                title: format!("{}: {name} = {:.1}", run.label, t / unit),
                nx,
                ny,
                values: v,
            });
            any = true;
        }
    }
    if any {
        let stem = out.join("density_maps");
        made.extend(
            fig.save_png_and_svg(&stem)
                .map_err(|e| format!("{}: {e}", stem.display()))?,
        );
    }
    Ok(())
}
