//! `granular compare DIR... --out OUT`: overlays finished runs (typically the event-driven
//! and the DSMC run of one scenario, section 3.2 of the DSMC seed, Figs. 2-3), from their
//! files:
//!
//! | figure | content |
//! |---|---|
//! | `energy` | kinetic energy per grain against time, log-log, every run, with Haff's law (seed Eq. 3) `K(t) = K(0)/(1 + t/t0)^2`, `t0` from kinetic theory with the Enskog and Sonine corrections (`theory::haff::haff_time`), `t0` marked |
//! | `energy_ratio` | `K(t) / K_Haff(t)` and the ratio of the runs to the first run |
//! | `impact_<run>` | impact-parameter densities of the collisions between observation times (Fig. 2b), with the molecular-chaos density |
//! | `structure_factor_<run>` | `S(k)` at every observation time (Fig. 3), `k` in units of `2 pi / L` |
//! | `structure_factor_peak` | largest `S(k)` against time, every run |
//! | `density_maps` | density / mean density at `t = 0`, a middle and the last observation, one row per run |
//!
//! `granular plot DIR` draws the same figures for one run.

use crate::plot::{HeatMaps, HeatPanel, LegendPosition, LinePlot, Series};
use granular::output::npz::{NpzArray, read_npz};
use granular::scenario::{EngineKind, Scenario};
use granular::theory::haff;
use std::path::{Path, PathBuf};

/// One finished run, as read back from its directory.
struct RunFiles {
    dir: PathBuf,
    label: String,
    scenario: Scenario,
    time: Vec<f64>,
    energy: Vec<f64>,
    temperature: Vec<f64>,
}

type Arrays = Vec<(String, NpzArray)>;

fn get<'a>(arrays: &'a Arrays, name: &str, file: &Path) -> Result<&'a NpzArray, String> {
    arrays
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, a)| a)
        .ok_or_else(|| format!("{}: no array `{name}`", file.display()))
}

fn floats<'a>(arrays: &'a Arrays, name: &str, file: &Path) -> Result<&'a [f64], String> {
    get(arrays, name, file)?
        .as_f64()
        .ok_or_else(|| format!("{}: array `{name}` is not float64", file.display()))
}

fn load(dir: &Path) -> Result<RunFiles, String> {
    let path = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let scenario =
        Scenario::from_toml(&text, &[]).map_err(|e| format!("{}: {e}", path.display()))?;
    let ts = crate::figures::read_csv(&dir.join("timeseries.csv"))?;
    let col = |name: &str| {
        crate::figures::column(&ts, name).ok_or_else(|| {
            format!(
                "{}: no column `{name}`",
                dir.join("timeseries.csv").display()
            )
        })
    };
    let engine = match scenario.engine {
        EngineKind::Edmd => "EDMD",
        EngineKind::Dsmc => "DSMC",
        EngineKind::Intruder => {
            return Err(format!(
                "{}: `granular compare` overlays cooling runs of the edmd and dsmc engines; \
                 this is an intruder run (use `granular plot` for it)",
                dir.display()
            ));
        }
    };
    let name = dir
        .file_name()
        .map_or(String::new(), |s| s.to_string_lossy().to_string());
    Ok(RunFiles {
        dir: dir.to_path_buf(),
        label: format!("{engine} ({name})"),
        time: col("time")?,
        energy: col("kinetic_energy")?,
        temperature: col("temperature")?,
        scenario,
    })
}

/// Haff's time of a run from kinetic theory: Enskog contact value at the run's packing
/// fraction, first Sonine correction, initial temperature from `timeseries.csv`.
fn haff_time(run: &RunFiles) -> Option<f64> {
    let sc = &run.scenario;
    let d = sc.dimension;
    let radius = sc.radius(0);
    let volume: f64 = sc.lengths().iter().product();
    let n = sc.particle_count() as f64 / volume;
    let phi = haff::packing_fraction(d, n, radius);
    let chi = haff::contact_value(d, phi);
    let t0 = *run.temperature.first()?;
    let e = sc.collisions.restitution;
    (e < 1.0 && t0 > 0.0)
        .then(|| haff::haff_time(d, n, radius, t0, sc.species[0].mass, e, chi, true))
}

fn save(plot: &LinePlot, stem: PathBuf, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let files = plot
        .save_png_and_svg(&stem)
        .map_err(|e| format!("{}: {e}", stem.display()))?;
    made.extend(files);
    Ok(())
}

/// A file-name-safe tag of a run.
fn tag(run: &RunFiles) -> String {
    run.dir
        .file_name()
        .map_or("run".into(), |s| s.to_string_lossy().to_string())
        .replace(
            |c: char| !c.is_ascii_alphanumeric() && c != '-' && c != '_',
            "_",
        )
}

/// Draws the comparison figures of `dirs` into `out`; returns the files written.
pub fn compare(dirs: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>, String> {
    if dirs.is_empty() {
        return Err("compare: give at least one run directory".into());
    }
    let runs = dirs
        .iter()
        .map(|d| load(d))
        .collect::<Result<Vec<_>, String>>()?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    energy(&runs, out, &mut made)?;
    impact(&runs, out, &mut made)?;
    structure_factor(&runs, out, &mut made)?;
    density_maps(&runs, out, &mut made)?;
    let path = out.join("comparison.json");
    let text = serde_json::to_string_pretty(&numbers(&runs)?).unwrap_or_default();
    std::fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    made.push(path);
    Ok(made)
}

/// First time (in units of `t0`) at which `|ratio - 1|` exceeds `threshold`.
fn first_departure(t: &[f64], ratio: &[f64], threshold: f64, t0: f64) -> serde_json::Value {
    t.iter()
        .zip(ratio)
        .find(|(_, r)| (*r - 1.0).abs() > threshold)
        .map_or(serde_json::Value::Null, |(t, _)| serde_json::json!(t / t0))
}

/// The numbers quoted in docs/dsmc.md: `t0`, when each run leaves Haff's law, when the
/// runs part, and the `S(k)` peak at every observation.
fn numbers(runs: &[RunFiles]) -> Result<serde_json::Value, String> {
    let t0 = haff_time(&runs[0]).unwrap_or(f64::NAN);
    let mut per_run = serde_json::Map::new();
    for run in runs {
        let k0 = run.energy.first().copied().unwrap_or(f64::NAN);
        let ratio: Vec<f64> = run
            .time
            .iter()
            .zip(&run.energy)
            .map(|(t, k)| k / haff::haff_energy(k0, *t, t0))
            .collect();
        let mut entry = serde_json::json!({
            "final_time_over_t0": run.time.last().map(|t| t / t0),
            "final_energy_over_initial": run.energy.last().map(|k| k / k0),
            "final_energy_over_haff": ratio.last(),
            "leaves_haff_by_10_percent_at_t_over_t0": first_departure(&run.time, &ratio, 0.1, t0),
            "leaves_haff_by_factor_2_at_t_over_t0": first_departure(&run.time, &ratio, 1.0, t0),
        });
        if let Some(sk) = read_sk(run)? {
            let peaks: Vec<serde_json::Value> = sk
                .times
                .iter()
                .zip(&sk.rows)
                .map(|(t, row)| {
                    let (i, s) = row
                        .iter()
                        .enumerate()
                        .fold((0, f64::NEG_INFINITY), |a, (i, &s)| if s > a.1 { (i, s) } else { a });
                    serde_json::json!({"t_over_t0": t / t0, "s_max": s, "k_l_over_2pi": sk.k_units.get(i)})
                })
                .collect();
            entry["structure_factor_peaks"] = serde_json::Value::Array(peaks);
        }
        per_run.insert(run.label.clone(), entry);
    }
    let mut pairs = serde_json::Map::new();
    let first = &runs[0];
    for other in runs.iter().skip(1) {
        let (t, r): (Vec<f64>, Vec<f64>) = first
            .time
            .iter()
            .zip(&first.energy)
            .zip(other.time.iter().zip(&other.energy))
            .filter(|((ta, _), (tb, _))| (*ta - *tb).abs() <= 1e-9 * ta.abs().max(1.0))
            .map(|((t, a), (_, b))| (*t, b / a))
            .unzip();
        pairs.insert(
            format!("{} / {}", other.label, first.label),
            serde_json::json!({
                "parts_by_5_percent_at_t_over_t0": first_departure(&t, &r, 0.05, t0),
                "parts_by_10_percent_at_t_over_t0": first_departure(&t, &r, 0.1, t0),
                "final_ratio": r.last(),
            }),
        );
    }
    Ok(serde_json::json!({"t0": t0, "runs": per_run, "energy_ratios": pairs}))
}

/// The figures of the opt-in observables of one run (impact histograms, `S(k)`, density
/// maps; nothing when the run has none), for `granular plot`.
pub fn observables(dir: &Path, out: &Path) -> Result<Vec<PathBuf>, String> {
    let runs = [load(dir)?];
    let mut made = Vec::new();
    impact(&runs, out, &mut made)?;
    structure_factor(&runs, out, &mut made)?;
    density_maps(&runs, out, &mut made)?;
    Ok(made)
}

fn energy(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let first = &runs[0];
    let t0 = haff_time(first);
    let mut plot = LinePlot::new("Kinetic energy per grain")
        .x_label("time t")
        .y_label("kinetic energy per grain K / N")
        .log_x(true)
        .log_y(true)
        .legend(LegendPosition::Auto);
    let mut ratio = LinePlot::new("Kinetic energy relative to Haff's law")
        .x_label(if t0.is_some() { "t / t0" } else { "time t" })
        .y_label("K(t) / K_Haff(t); ratio of runs")
        .log_x(true)
        .log_y(true);
    for run in runs {
        let n = run.scenario.particle_count().max(1) as f64;
        let per: Vec<f64> = run.energy.iter().map(|k| k / n).collect();
        plot = plot.series(Series::line(
            run.label.clone(),
            run.time.clone(),
            per.clone(),
        ));
        if let Some(t0) = t0 {
            let k0 = per.first().copied().unwrap_or(f64::NAN);
            let x: Vec<f64> = run.time.iter().map(|t| t / t0).collect();
            let y = run
                .time
                .iter()
                .zip(&per)
                .map(|(t, k)| k / haff::haff_energy(k0, *t, t0))
                .collect();
            ratio = ratio.series(Series::line(run.label.clone(), x, y));
        }
    }
    if let Some(t0) = t0 {
        let n = first.scenario.particle_count().max(1) as f64;
        let k0 = first.energy.first().copied().unwrap_or(f64::NAN) / n;
        let t_end = first.time.iter().cloned().fold(0.0, f64::max);
        let t_start = first
            .time
            .iter()
            .cloned()
            .find(|t| *t > 0.0)
            .unwrap_or(t0 * 1e-2);
        plot = plot
            .series(Series::theory_fn(
                format!("Haff, Eq. 3: t0 = {t0:.4} (Enskog + Sonine)"),
                (t_start, t_end.max(t_start * 10.0)),
                200,
                true,
                move |t| haff::haff_energy(k0, t, t0),
            ))
            .series(Series::theory(
                "t = t0".to_string(),
                vec![t0, t0],
                vec![k0 * 1e-6, k0 * 1.2],
            ));
        // The first run against the others, where their output times coincide.
        if runs.len() > 1 {
            for other in &runs[1..] {
                let (x, y): (Vec<f64>, Vec<f64>) = first
                    .time
                    .iter()
                    .zip(&first.energy)
                    .zip(other.time.iter().zip(&other.energy))
                    .filter(|((ta, _), (tb, _))| (*ta - *tb).abs() <= 1e-9 * ta.abs().max(1.0))
                    .map(|((t, a), (_, b))| (t / t0, b / a))
                    .unzip();
                ratio = ratio.series(Series::theory(
                    format!("{} / {}", other.label, first.label),
                    x,
                    y,
                ));
            }
        }
        save(&ratio, out.join("energy_ratio"), made)?;
    }
    // The Haff curve sets the lower end of the axis; keep the data in view.
    save(&plot, out.join("energy"), made)
}

fn impact(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    for run in runs {
        let path = run.dir.join("impact_histograms.npz");
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
        let name = if t0.is_some() { "t/t0" } else { "t" };
        // From 0, so that a flat histogram looks flat next to one with a grazing excess.
        let top = dens
            .iter()
            .cloned()
            .filter(|v| v.is_finite())
            .fold(1.25, f64::max);
        let mut plot = LinePlot::new(format!("Impact parameters: {}", run.label))
            .x_label("impact parameter b / sigma")
            .y_label("probability density")
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
            move |x| if d == 2 { 1.0 } else { 2.0 * x },
        ));
        save(&plot, out.join(format!("impact_{}", tag(run))), made)?;
    }
    Ok(())
}

/// `S(k)` per observation, restricted to complete shells (`|n| <= max_index`).
struct SkData {
    times: Vec<f64>,
    k_units: Vec<f64>,
    rows: Vec<Vec<f64>>,
}

fn read_sk(run: &RunFiles) -> Result<Option<SkData>, String> {
    let path = run.dir.join("structure_factor.npz");
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

fn structure_factor(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    let unit = t0.unwrap_or(1.0);
    let name = if t0.is_some() { "t/t0" } else { "t" };
    let mut peak = LinePlot::new("Largest S(k) against time")
        .x_label(if t0.is_some() { "t / t0" } else { "time t" })
        .y_label("max_k S(k)")
        .log_x(true)
        .log_y(true);
    let mut any = false;
    for run in runs {
        let Some(sk) = read_sk(run)? else {
            continue;
        };
        let mut plot = LinePlot::new(format!("Structure factor: {}", run.label))
            .x_label("k L / (2 pi)")
            .y_label("S(k)")
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
        plot = plot.series(Series::theory(
            "ideal gas S = 1",
            vec![sk.k_units[0], *sk.k_units.last().unwrap_or(&1.0)],
            vec![1.0, 1.0],
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

fn density_maps(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let t0 = haff_time(&runs[0]);
    let unit = t0.unwrap_or(1.0);
    let name = if t0.is_some() { "t/t0" } else { "t" };
    let mut fig = HeatMaps::new("number density / mean density", 3);
    let mut any = false;
    for run in runs {
        let path = run.dir.join("density_maps.npz");
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
