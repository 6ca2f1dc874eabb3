//! `granular plot SWEEP_DIR`: the figures of a sweep that mean something physically: each
//! observable of `sweep.csv` against the swept value (mean ± standard error over seeds),
//! and the kinetic energy against time of every point (one colour per swept value, one
//! line style per species). Bookkeeping columns (`time`, collision counters, DSMC's step
//! counters) are not drawn. Axes are labelled from the meaning of the swept key
//! ([`key_label`]), not the raw key.

use crate::plot::{LinePlot, PALETTE, Series};
use crate::run_files::save_both;
use crate::table::{Table, column, read_run_csv};
use granular::run::sweep::SweepTable as LibSweepTable;
use granular::run::{RunDir, RunFile};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A sweep's table as the figures use it: the library's typed [`LibSweepTable`] (the one
/// reader of `sweep.csv` and `sweep.json`), with the first swept key on the x axis and the
/// points grouped by the values of the other keys (one curve per group).
pub(crate) struct SweepTable {
    /// The first swept scenario key, e.g. `collisions.restitution` (the x axis).
    pub key: String,
    /// Each point's label: every key's symbol and value (`ξ = 0.6, m₁ = 2`).
    pub labels: Vec<String>,
    /// The first key's value of every point as a number (the point number where it is
    /// not one).
    pub numbers: Vec<f64>,
    /// Points with equal values of the other keys: `(label, rows)`, in row order.
    pub groups: Vec<(String, Vec<usize>)>,
    /// The table.
    pub table: LibSweepTable,
}

/// Reads `DIR/sweep.csv` and `DIR/sweep.json`.
pub(crate) fn read_sweep(dir: &Path) -> Result<SweepTable, String> {
    let table = LibSweepTable::read(dir).map_err(|e| e.to_string())?;
    let key = table
        .keys
        .first()
        .cloned()
        .unwrap_or_else(|| "point".into());
    let symbols: Vec<String> = table.keys.iter().map(|k| key_label(k).0).collect();
    let label = |r: &granular::run::sweep::SweepRow, skip: usize| {
        symbols
            .iter()
            .zip(&r.values)
            .skip(skip)
            .map(|(k, v)| format!("{k} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let labels = table.rows.iter().map(|r| label(r, 0)).collect();
    let numbers = table
        .rows
        .iter()
        .map(|r| match r.numbers.first() {
            Some(x) if x.is_finite() => *x,
            _ => r.point as f64,
        })
        .collect();
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (i, r) in table.rows.iter().enumerate() {
        let l = label(r, 1);
        match groups.iter_mut().find(|g| g.0 == l) {
            Some(g) => g.1.push(i),
            None => groups.push((l, vec![i])),
        }
    }
    Ok(SweepTable {
        key,
        labels,
        numbers,
        groups,
        table,
    })
}

/// Subscript digits: `0` -> `₀`.
fn subscript(i: &str) -> String {
    i.chars()
        .map(|c| match c.to_digit(10) {
            Some(d) => char::from_u32(0x2080 + d).unwrap_or(c),
            None => c,
        })
        .collect()
}

/// The symbol and the axis label (with unit) of a swept scenario key; units are those of
/// the simulation: length `L`, mass `m`, time `τ`. Unknown keys are shown as they are.
///
/// `collisions.restitution` -> (`ξ`, `restitution ξ`); `species[0].mass` -> (`m₀`,
/// `mass m₀ [m]`).
pub(crate) fn key_label(key: &str) -> (String, String) {
    if let Some(rest) = key.strip_prefix("species[")
        && let Some((index, field)) = rest.split_once("].")
    {
        let i = subscript(index);
        let (symbol, label) = match field {
            "mass" => (format!("m{i}"), format!("mass m{i} [m]")),
            "radius" => (format!("r{i}"), format!("radius r{i} [L]")),
            "count" => (format!("N{i}"), format!("number of grains N{i}")),
            "packing_fraction" => (
                format!("φ{i}"),
                format!("packing fraction φ{i} (dimensionless)"),
            ),
            "velocity.speed" => (format!("v{i}"), format!("initial speed v{i} [L/τ]")),
            "velocity.temperature" => (
                format!("T{i}"),
                format!("initial temperature T{i} [m L²/τ²]"),
            ),
            _ => return (key.to_string(), key.to_string()),
        };
        return (symbol, label);
    }
    let known: &[(&str, &str, &str)] = &[
        (
            "collisions.restitution",
            "ξ",
            "restitution ξ (dimensionless)",
        ),
        (
            "collisions.wall_restitution",
            "ξ_w",
            "wall restitution ξ_w (dimensionless)",
        ),
        (
            "collisions.wall_tangential_restitution",
            "β_w",
            "tangential wall restitution β_w (dimensionless)",
        ),
        ("collisions.tc", "t_c", "TC time t_c [τ]"),
        ("box.lengths[0]", "L_x", "box length L_x [L]"),
        ("box.lengths[1]", "L_y", "box length L_y [L]"),
        ("box.lengths[2]", "L_z", "box length L_z [L]"),
        ("seed", "seed", "seed"),
        ("dsmc.time_step", "Δt", "DSMC time step Δt [τ]"),
        ("dsmc.cell_size", "Δx", "DSMC cell size Δx [L]"),
        ("intruder.alpha", "α", "restitution α (dimensionless)"),
        ("intruder.restitution", "α", "restitution α (dimensionless)"),
        ("intruder.mass", "M", "intruder mass M [m]"),
        ("intruder.mass_ratio", "M/m", "mass ratio M/m"),
        ("stop.time", "t_end", "run time t_end [τ]"),
        (
            "stop.collisions_per_particle",
            "C/N",
            "collisions per grain",
        ),
    ];
    known.iter().find(|(k, ..)| *k == key).map_or_else(
        || (key.to_string(), key.to_string()),
        |(_, symbol, label)| (symbol.to_string(), label.to_string()),
    )
}

/// Columns of `sweep.csv` that are bookkeeping, not physics: no figure against the swept
/// value.
const BOOKKEEPING: [&str; 9] = [
    "time",
    "collisions",
    "pair_collisions",
    "wall_collisions",
    "collisions_per_particle",
    "tc_elastic_collisions",
    "steps",
    "vmax_exceeded",
    "events",
];

/// The axis label (with unit) of a sweep observable, or `None` for bookkeeping columns.
pub(crate) fn observable_label(name: &str, dimension_hint: Option<usize>) -> Option<String> {
    if BOOKKEEPING.contains(&name) {
        return None;
    }
    let pressure_unit = match dimension_hint {
        Some(3) => "m/(L τ²)",
        _ => "m/τ²",
    };
    let energy = "[m L²/τ²]";
    Some(match name {
        "kinetic_energy" => format!("final kinetic energy E {energy}"),
        "temperature" => format!("final temperature T {energy}"),
        "dissipated_energy" => format!("dissipated energy {energy}"),
        "collision_frequency" => "collision frequency ν [1/τ]".into(),
        "mean_free_time" => "mean free time [τ]".into(),
        "pressure" => format!("pressure P [{pressure_unit}]"),
        "wall_pressure" => format!("wall pressure [{pressure_unit}]"),
        "a2" => "Sonine coefficient a₂".into(),
        "crater_size" => "crater size (bed grains moved > one diameter)".into(),
        "temperature_ratio" => "temperature ratio T/T_B".into(),
        _ => match name.split_once('.') {
            Some(("kinetic_energy_per_grain", species)) => {
                format!("final kinetic energy per grain, {species} {energy}")
            }
            Some(("temperature", species)) => format!("final temperature, {species} {energy}"),
            _ => name.replace('_', " "),
        },
    })
}

/// Draws the figures of a sweep directory; returns the files written.
pub(crate) fn plot_sweep(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let sweep = read_sweep(dir)?;
    let (symbol, key_text) = key_label(&sweep.key);
    let out = RunDir::new(dir).figure_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut made = Vec::new();
    let points = point_dirs(dir)?;
    let dimension = points
        .values()
        .flat_map(|seeds| seeds.first())
        .next()
        .and_then(|s| RunDir::new(s).summary().ok())
        .map(|s| s.dimension);
    // One figure per observable with error bars over seeds: one curve per combination of
    // the other keys' values (one colour each).
    for name in &sweep.table.observables {
        let Some(y_label) = observable_label(name, dimension) else {
            continue;
        };
        let Some((y, e)) = sweep.table.observable(name) else {
            continue;
        };
        if y.iter().all(|v| !v.is_finite()) {
            continue;
        }
        let stem = out.join(format!("sweep_{}", name.replace(['.', '/'], "_")));
        let title = format!(
            "{} against {}",
            first_words(&y_label),
            first_words(&key_text)
        );
        let mut p = LinePlot::new(title)
            .x_label(key_text.clone())
            .y_label(y_label.clone());
        for (g, (label, rows)) in sweep.groups.iter().enumerate() {
            let pick = |v: &[f64]| rows.iter().map(|&i| v[i]).collect::<Vec<f64>>();
            let errors = pick(&e)
                .into_iter()
                .map(|v| if v.is_finite() { v } else { 0.0 })
                .collect();
            let name = if label.is_empty() {
                "mean ± standard error over seeds".to_string()
            } else {
                format!("{label} (mean ± s.e. over seeds)")
            };
            p = p.series(
                Series::line_markers(name, pick(&sweep.numbers), pick(&y))
                    .with_errors(errors)
                    .with_colour(PALETTE[g % PALETTE.len()]),
            );
        }
        save_both(&stem, p.save_png_and_svg(&stem), &mut made)?;
    }
    energy_against_time(&sweep, &symbol, &points, &out, &mut made)?;
    Ok(made)
}

/// The label up to its unit or remark: `final temperature T [m L²/τ²]` -> `final
/// temperature T`.
fn first_words(label: &str) -> &str {
    let end = [label.find(" ["), label.find(" (")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(label.len());
    &label[..end]
}

/// The member directories of every point: `point_NNN/seed_MMM`, sorted.
fn point_dirs(dir: &Path) -> Result<BTreeMap<String, Vec<PathBuf>>, String> {
    let mut points: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for p in std::fs::read_dir(dir).map_err(|e| e.to_string())?.flatten() {
        let name = p.file_name().to_string_lossy().to_string();
        if name.starts_with("point_") {
            let mut seeds: Vec<PathBuf> = std::fs::read_dir(p.path())
                .map_err(|e| e.to_string())?
                .flatten()
                .map(|s| s.path())
                .collect();
            seeds.sort();
            points.insert(name, seeds);
        }
    }
    Ok(points)
}

/// Kinetic energy per grain against time, mean over seeds: one colour per point, one line
/// style per species.
fn energy_against_time(
    sweep: &SweepTable,
    symbol: &str,
    points: &BTreeMap<String, Vec<PathBuf>>,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let mut energy = LinePlot::new(format!("Kinetic energy per grain, by {symbol}"))
        .x_label("time t [τ]")
        .y_label("kinetic energy per grain E/N [m L²/τ²]");
    let mut any = false;
    for (i, seeds) in points.values().enumerate() {
        let tables: Vec<Table> = seeds
            .iter()
            .filter_map(|s| read_run_csv(s, RunFile::TimeSeries).ok())
            .collect();
        let Some(head) = tables.first() else {
            continue;
        };
        let time = column(head, "time").unwrap_or_default();
        let point = sweep.labels.get(i).cloned().unwrap_or_default();
        let species_cols: Vec<String> = head
            .0
            .iter()
            .filter(|c| c.starts_with("kinetic_energy_per_grain."))
            .cloned()
            .collect();
        let per_species = !species_cols.is_empty();
        let cols = if per_species {
            species_cols
        } else {
            vec!["kinetic_energy".into()]
        };
        for (k, c) in cols.iter().enumerate() {
            let mut mean = vec![0.0; time.len()];
            let mut used = 0.0;
            for t in &tables {
                if let Some(v) = column(t, c)
                    && v.len() >= time.len()
                {
                    mean.iter_mut().zip(&v).for_each(|(m, x)| *m += x);
                    used += 1.0;
                }
            }
            if used == 0.0 {
                continue;
            }
            mean.iter_mut().for_each(|m| *m /= used);
            let name = match c.strip_prefix("kinetic_energy_per_grain.") {
                Some(species) => format!("{point}: {species}"),
                None => {
                    // Total energy: per grain with the grain count of the member.
                    let n = RunDir::new(&seeds[0])
                        .summary()
                        .map_or(1.0, |s| s.n.max(1) as f64);
                    mean.iter_mut().for_each(|m| *m /= n);
                    point.clone()
                }
            };
            energy = energy.series(
                Series::line(name, time.clone(), mean)
                    .with_colour(PALETTE[i % PALETTE.len()])
                    .with_pattern(if per_species { k } else { 0 }),
            );
            any = true;
        }
    }
    if any {
        let stem = out.join("sweep_energy_time");
        save_both(&stem, energy.save_png_and_svg(&stem), made)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_labelled_by_meaning() {
        assert_eq!(
            key_label("collisions.restitution"),
            ("ξ".into(), "restitution ξ (dimensionless)".into())
        );
        assert_eq!(
            key_label("species[0].mass"),
            ("m₀".into(), "mass m₀ [m]".into())
        );
        assert_eq!(key_label("species[12].radius").1, "radius r₁₂ [L]");
        assert_eq!(key_label("something.else").1, "something.else");
        assert_eq!(observable_label("wall_collisions", Some(2)), None);
        assert_eq!(observable_label("time", Some(2)), None);
        assert_eq!(
            observable_label("pressure", Some(3)).as_deref(),
            Some("pressure P [m/(L τ²)]")
        );
    }
}
