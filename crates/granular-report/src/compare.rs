//! `granular compare DIR... --out OUT`: overlays finished runs (typically the event-driven
//! and the DSMC run of one scenario, section 3.2 of Müller & Herrmann's DSMC paper, Figs. 2-3), from their
//! files:
//!
//! | figure | content |
//! |---|---|
//! | `energy` | kinetic energy per grain against time, log-log, every run, with Haff's law (DSMC-3) `K(t) = K(0)/(1 + t/t0)^2`, `t0` from kinetic theory with the Enskog and Sonine corrections (`theory::haff::haff_time`), `t0` marked |
//! | `energy_ratio` | `K(t) / K_Haff(t)` and the ratio of the runs to the first run |
//! | `impact_<run>` | impact-parameter densities of the collisions between observation times (Fig. 2b), with the molecular-chaos density |
//! | `structure_factor_<run>` | `S(k)` at every observation time (Fig. 3), `k` in units of `2 pi / L` |
//! | `structure_factor_peak` | largest `S(k)` against time, every run |
//! | `density_maps` | density / mean density at `t = 0`, a middle and the last observation, one row per run |
//!
//! `granular plot DIR` draws the same figures for one run.

use crate::observable_plots::{density_maps, impact, read_sk, structure_factor};
use crate::plot::{LegendPosition, LinePlot, Series};
use crate::run_files::{RunFiles, haff_time, load, save};
use granular::theory::haff;
use std::path::{Path, PathBuf};

/// Draws the comparison figures of `dirs` into `out`; returns the files written.
pub(crate) fn compare(dirs: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>, String> {
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

/// The critical size `L_c` of the homogeneous cooling state of a run's gas (HCS-2,
/// `theory::stability::critical_length`: Haff's law holds only in a box smaller than it)
/// and the longest edge of its box.
fn critical_size(run: &RunFiles) -> (f64, f64) {
    let sc = &run.scenario;
    let longest = sc.lengths().iter().cloned().fold(0.0, f64::max);
    (
        crate::run_files::critical_length(sc).unwrap_or(f64::NAN),
        longest,
    )
}

/// The numbers quoted in docs/dsmc.md: `t0`, the critical size of the homogeneous cooling
/// state against the box (above 1 Haff's law cannot hold for long), when each run leaves
/// Haff's law, when the runs part, and the `S(k)` peak at every observation.
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
        let (critical, longest) = critical_size(run);
        let mut entry = serde_json::json!({
            "critical_size": critical,
            "box_over_critical_size": longest / critical,
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
    let mut all = serde_json::json!({"t0": t0, "runs": per_run, "energy_ratios": pairs});
    if let Some(why) = crate::run_files::haff_excluded(&runs[0].scenario) {
        // No Haff's law for this set-up: `t0` is null and nothing is measured against it.
        all["haff_not_applicable"] = serde_json::Value::String(why);
    }
    Ok(all)
}

fn energy(runs: &[RunFiles], out: &Path, made: &mut Vec<PathBuf>) -> Result<(), String> {
    let first = &runs[0];
    let t0 = haff_time(first);
    let mut plot = LinePlot::new("Kinetic energy per grain")
        .x_label("time t [τ]")
        .y_label("kinetic energy per grain E/N [m L²/τ²]")
        .log_x(true)
        .log_y(true)
        .legend(LegendPosition::Auto);
    let mut ratio = LinePlot::new("Kinetic energy relative to Haff's law")
        .x_label(if t0.is_some() {
            "time t/t₀"
        } else {
            "time t [τ]"
        })
        .y_label("energy ratio E/E_Haff; ratio of runs")
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
        // The t0 marker spans the data (and the Haff curve), not beyond.
        let lowest = runs
            .iter()
            .flat_map(|r| {
                let n = r.scenario.particle_count().max(1) as f64;
                r.energy.iter().map(move |k| k / n)
            })
            .chain(std::iter::once(haff::haff_energy(k0, t_end, t0)))
            .filter(|k| *k > 0.0)
            .fold(k0, f64::min);
        plot = plot
            .series(Series::theory_fn(
                format!(
                    "Haff, DSMC-3: t₀ = {t0:.4} τ ({})",
                    crate::run_files::haff_model(first)
                ),
                (t_start, t_end.max(t_start * 10.0)),
                200,
                true,
                move |t| haff::haff_energy(k0, t, t0),
            ))
            .series(Series::theory(
                "t = t₀".to_string(),
                vec![t0, t0],
                vec![0.8 * lowest, k0 * 1.2],
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
