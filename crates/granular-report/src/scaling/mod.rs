//! `granular scaling`: the speed-up of decomposed DSMC, measured (`granular bench
//! dsmc-ranks --csv`) and modelled ([`model`]) up to 1024 ranks, as a figure like the DSMC
//! Fig. 1 of Müller & Herrmann's DSMC paper and as tables.

pub mod model;

use crate::plot::{LegendPosition, LinePlot, Series};
use model::{Inputs, Network, Variant};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One row of the benchmark's CSV (one rank of one measurement).
#[derive(Clone, Debug)]
struct Row {
    scaling: String,
    values: BTreeMap<String, f64>,
}

impl Row {
    fn get(&self, key: &str) -> f64 {
        self.values.get(key).copied().unwrap_or(f64::NAN)
    }
}

fn read_rows(path: &Path) -> Result<Vec<Row>, String> {
    let mut r = csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let headers = r
        .headers()
        .map_err(|e| format!("{}: {e}", path.display()))?
        .clone();
    let mut rows = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| format!("{}: {e}", path.display()))?;
        let mut row = Row {
            scaling: String::new(),
            values: BTreeMap::new(),
        };
        for (h, v) in headers.iter().zip(rec.iter()) {
            if h == "scaling" {
                row.scaling = v.to_string();
            } else if let Ok(x) = v.parse::<f64>() {
                row.values.insert(h.to_string(), x);
            }
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The best (highest) whole-run particle-steps per second per rank count, for one kind of
/// scaling (and, given, one N): `(ranks, n, particle-steps/s)`.
fn best_by_ranks(rows: &[Row], scaling: &str, n: Option<f64>) -> Vec<(usize, f64, f64)> {
    let mut best: BTreeMap<usize, (f64, f64)> = BTreeMap::new();
    for r in rows
        .iter()
        .filter(|r| r.scaling == scaling && n.is_none_or(|n| r.get("n") == n))
    {
        let k = r.get("ranks") as usize;
        let e = best.entry(k).or_insert((r.get("n"), 0.0));
        if r.get("particle_steps_per_second") > e.1 {
            *e = (r.get("n"), r.get("particle_steps_per_second"));
        }
    }
    best.into_iter().map(|(k, (n, p))| (k, n, p)).collect()
}

/// The model's inputs from the strong-scaling rows: compute cost on one rank, traffic
/// on two.
fn inputs(rows: &[Row]) -> Result<Inputs, String> {
    let strong: Vec<&Row> = rows.iter().filter(|r| r.scaling == "strong").collect();
    // The N of the first one-rank row; the other rows at that N.
    let n0 = strong
        .iter()
        .find(|r| r.get("ranks") == 1.0)
        .map_or(f64::NAN, |r| r.get("n"));
    let one: Vec<&&Row> = strong
        .iter()
        .filter(|r| r.get("ranks") == 1.0 && r.get("n") == n0)
        .collect();
    let two: Vec<&&Row> = strong
        .iter()
        .filter(|r| r.get("ranks") == 2.0 && r.get("n") == n0)
        .collect();
    if one.is_empty() || two.is_empty() {
        return Err(
            "the benchmark file needs strong-scaling rows on 1 and 2 ranks (run \
             `granular bench dsmc-ranks --csv FILE` under `mpirun -n 1` and `-n 2`)"
                .into(),
        );
    }
    let compute = one
        .iter()
        .map(|r| r.get("compute_seconds_per_step") / r.get("particles"))
        .fold(f64::INFINITY, f64::min);
    let mean = |key: &str| two.iter().map(|r| r.get(key)).sum::<f64>() / two.len() as f64;
    Ok(Inputs {
        dimension: one[0].get("dimension") as usize,
        n0: one[0].get("n"),
        planes0: one[0].get("cell_planes"),
        compute_per_particle_step: compute,
        // On 2 periodic ranks each rank's two faces both lead to the other rank.
        migrants_per_face: mean("migrants_per_step") / 2.0,
        migration_calls: mean("migration_calls_per_step"),
        reduction_calls: mean("reduction_calls_per_step"),
    })
}

/// Rank counts of the tables: powers of two to 1024.
fn rank_counts() -> Vec<usize> {
    (0..=10).map(|p| 1usize << p).collect()
}

fn fmt_opt(x: Option<f64>) -> String {
    x.map_or(String::from(""), |v| format!("{v:.6}"))
}

/// Reads the benchmark CSV `bench`, writes into `out`: `scaling_model.csv` (speed-up and
/// time per step by variant, N and rank count), `scaling_model.json` (the inputs, the
/// network, the 50 % thresholds) and the figure `dsmc_speedup.png` / `.svg`. Returns the
/// files written and a text summary. `compute`: seconds per particle-step to use instead
/// of the measured one (a prediction for an idle machine or another processor).
pub fn scaling(
    bench: &Path,
    out: &Path,
    net: Network,
    compute: Option<f64>,
) -> Result<(Vec<PathBuf>, String), String> {
    let rows = read_rows(bench)?;
    let mut m = inputs(&rows)?;
    if let Some(c) = compute {
        m.compute_per_particle_step = c;
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let sizes = [m.n0, 1e7, 1e8, 1e9];
    let mut table = String::from(
        "variant,n,ranks,particles_per_rank,speedup,efficiency,compute_seconds,migration_seconds,reduction_seconds\n",
    );
    for v in Variant::ALL {
        for &n in &sizes {
            for k in rank_counts() {
                if let Some(t) = m.step_time(v, n, k, &net) {
                    let s = m.speedup(v, n, k, &net);
                    table.push_str(&format!(
                        "{},{n},{k},{},{},{},{},{},{}\n",
                        v.name(),
                        n / k as f64,
                        fmt_opt(s),
                        fmt_opt(s.map(|s| s / k as f64)),
                        t[0],
                        t[1],
                        t[2]
                    ));
                }
            }
        }
    }
    let table_path = out.join("scaling_model.csv");
    std::fs::write(&table_path, table).map_err(|e| format!("{}: {e}", table_path.display()))?;

    let mut summary = format!(
        "inputs: {}D, N0 = {}, {} cell planes, compute {:.3e} s per particle-step, {:.1} \
         migrants per slab face per step, {} migration and {} reduction calls per step; \
         network: latency {:.2e} s, {:.2e} bytes/s per rank\n",
        m.dimension,
        m.n0,
        m.planes0,
        m.compute_per_particle_step,
        m.migrants_per_face,
        m.migration_calls,
        m.reduction_calls,
        net.latency,
        net.bandwidth
    );
    let mut thresholds = Vec::new();
    for v in Variant::ALL {
        for &n in &sizes {
            let k_max = (m.max_ranks(v, n) as usize).min(1024);
            let t = m.falls_below(v, n, k_max, 0.5, &net);
            let s_max = m.speedup(v, n, k_max, &net).unwrap_or(f64::NAN);
            summary.push_str(&format!(
                "{:<18} N = {:.0e}: rank limit {}, {}; speed-up on {k_max} ranks {s_max:.1}\n",
                v.name(),
                n,
                m.max_ranks(v, n),
                match t {
                    Some((k, per)) =>
                        format!("efficiency < 50 % from {k} ranks ({per:.0} per rank)"),
                    None => format!("efficiency >= 50 % up to {k_max} ranks"),
                }
            ));
            thresholds.push(serde_json::json!({
                "variant": v.name(), "n": n, "rank_limit": m.max_ranks(v, n),
                "ranks_below_half": t.map(|t| t.0), "particles_per_rank_below_half": t.map(|t| t.1),
                "speedup_at_limit": s_max, "limit_considered": k_max,
            }));
        }
    }
    let measured = best_by_ranks(&rows, "strong", Some(m.n0));
    let weak = best_by_ranks(&rows, "weak", None);
    let json = serde_json::json!({
        "inputs": {
            "dimension": m.dimension, "n0": m.n0, "cell_planes": m.planes0,
            "compute_seconds_per_particle_step": m.compute_per_particle_step,
            "migrants_per_face_per_step": m.migrants_per_face,
            "migration_calls_per_step": m.migration_calls,
            "reduction_calls_per_step": m.reduction_calls,
        },
        "network": { "latency_seconds": net.latency, "bandwidth_bytes_per_second": net.bandwidth },
        "measured_strong": measured.iter().map(|&(k, n, p)| serde_json::json!({"ranks": k, "n": n, "particle_steps_per_second": p})).collect::<Vec<_>>(),
        "measured_weak": weak.iter().map(|&(k, n, p)| serde_json::json!({"ranks": k, "n": n, "particle_steps_per_second": p})).collect::<Vec<_>>(),
        "efficiency_below_half": thresholds,
    });
    let json_path = out.join("scaling_model.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&json).unwrap_or_default(),
    )
    .map_err(|e| format!("{}: {e}", json_path.display()))?;
    let mut files = vec![table_path, json_path];
    files.extend(figure(&m, &measured, &weak, &net, out)?);
    Ok((files, summary))
}

/// `5×10^5`: a particle number for a legend.
fn sci(n: f64) -> String {
    let e = n.log10().floor();
    let m = n / 10f64.powf(e);
    if (m - 1.0).abs() < 1e-9 {
        format!("10^{e:.0}")
    } else {
        format!("{}×10^{e:.0}", (m * 100.0).round() / 100.0)
    }
}

/// Speed-up against ranks: ideal, measured (strong; weak as scaled speed-up), and the
/// model's variants for the measured N, and the slabs for 10^8.
fn figure(
    m: &Inputs,
    measured: &[(usize, f64, f64)],
    weak: &[(usize, f64, f64)],
    net: &Network,
    out: &Path,
) -> Result<Vec<PathBuf>, String> {
    // 16 rank counts per factor of 2 (the exact chunk layout makes the raw-values model
    // jump between neighbouring rank counts; these points show its trend).
    let mut ks: Vec<usize> = (0..=160)
        .map(|j| 2f64.powf(j as f64 / 16.0).round() as usize)
        .collect();
    ks.dedup();
    let curve = |v: Variant, n: f64| -> (Vec<f64>, Vec<f64>) {
        ks.iter()
            .filter_map(|&k| m.speedup(v, n, k, net).map(|s| (k as f64, s)))
            .unzip()
    };
    let mut plot = LinePlot::new(format!(
        "DSMC speed-up, {}D, packing fraction 0.1 (model: {:.0} ns per particle-step, latency {:.1} µs, {:.1} GB/s per rank)",
        m.dimension,
        m.compute_per_particle_step * 1e9,
        net.latency * 1e6,
        net.bandwidth / 1e9
    ))
    .x_label("number of processors (MPI ranks) K")
    .y_label("speed-up S(K) = T(1) / T(K)")
    .log_x(true)
    .log_y(true)
    .x_range(0.8, 1300.0)
    // Three decades below S = 1 leave the lower right corner to the legend, off the data.
    .y_range(1e-3, 2000.0)
    .legend(LegendPosition::LowerRight)
    .series(Series::theory("ideal S = K", vec![1.0, 1024.0], vec![1.0, 1024.0]).dashed(true));
    let n0 = m.n0;
    let n0_text = sci(n0);
    for (v, label) in [
        (
            Variant::Slabs,
            "model, slabs, chained sums (as implemented)",
        ),
        (
            Variant::SlabsRawValues,
            "model, slabs, raw values gathered (earlier)",
        ),
        (Variant::BisectionChained, "model, bisection, chained sums"),
    ] {
        let (x, y) = curve(v, n0);
        plot = plot.series(Series::theory(format!("{label}, N = {n0_text}"), x, y).dashed(false));
    }
    let (x, y) = curve(Variant::Slabs, 1e8);
    plot = plot.series(Series::theory(
        "model, slabs as implemented, N = 10^8",
        x,
        y,
    ));
    if let Some(&(_, _, p1)) = measured.iter().find(|r| r.0 == 1) {
        let (x, y): (Vec<f64>, Vec<f64>) =
            measured.iter().map(|&(k, _, p)| (k as f64, p / p1)).unzip();
        plot = plot.series(Series::markers(format!("measured, N = {n0_text}"), x, y));
    }
    if let Some(&(_, _, p1)) = weak.iter().find(|r| r.0 == 1) {
        let (x, y): (Vec<f64>, Vec<f64>) = weak.iter().map(|&(k, _, p)| (k as f64, p / p1)).unzip();
        plot = plot.series(Series::markers("measured, weak (N per rank fixed)", x, y));
    }
    let stem = out.join("dsmc_speedup");
    let files = plot.save_png_and_svg(&stem).map_err(|e| e.to_string())?;
    Ok(files.to_vec())
}
