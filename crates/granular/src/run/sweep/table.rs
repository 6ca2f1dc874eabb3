//! `sweep.csv` (one row per point: the point number, each swept key's value in a column
//! named by the key, the members, and the mean and standard error over seeds of every
//! scalar observable) and its sidecar `sweep.json` (what the columns are: scenario, keys
//! and values, seeds, units, version, members found and missing). The CSV has one header
//! row and nothing else, so `pandas.read_csv` and `numpy.genfromtxt(names=True)` read it
//! as it is. Both files depend only on the set of finished members, never on how the
//! sweep was run (threads, shards, order).

use super::SweepError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The sweep's table, `sweep.csv`.
pub const SWEEP_TABLE: &str = "sweep.csv";

/// The table's sidecar, `sweep.json`.
pub const SWEEP_META: &str = "sweep.json";

/// One row of `sweep.csv`: a point of the scan.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// Point number (the member directories `point_PPP`).
    pub point: usize,
    /// Each swept key's value as written in the table: a number as TOML writes it, an
    /// array (a velocity) as its Euclidean norm, a string as it is.
    pub values: Vec<String>,
    /// Each swept key's value as a number (the norm of an array; NaN for a string).
    pub numbers: Vec<f64>,
    /// Finished members of this point.
    pub members: u64,
    /// `(observable, mean, standard error)` over the members where it is finite (the
    /// error NaN with fewer than two).
    pub observables: Vec<(String, f64, f64)>,
}

impl SweepRow {
    /// Mean and standard error of `observable` at this point.
    pub fn observable(&self, name: &str) -> Option<(f64, f64)> {
        self.observables
            .iter()
            .find(|o| o.0 == name)
            .map(|o| (o.1, o.2))
    }
}

/// `sweep.csv` read back with its sidecar: the typed table that `granular plot` and the
/// tests use.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepTable {
    /// The swept keys, in column order (`collisions.restitution`, ...).
    pub keys: Vec<String>,
    /// The observables, in column order (each has `_mean` and `_stderr` columns).
    pub observables: Vec<String>,
    /// One row per point, in point order.
    pub rows: Vec<SweepRow>,
    /// `sweep.json`.
    pub meta: SweepMeta,
}

/// One swept key in `sweep.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeyMeta {
    /// Dotted scenario key, also the column name.
    pub key: String,
    /// Its values, in order (JSON of the TOML values).
    pub values: Vec<serde_json::Value>,
    /// How the column holds them: `number`, `norm` (of an array) or `text`.
    pub cell: String,
    /// Its physical dimension in the scenario's units, when known (`length`, `energy`, ...).
    pub dimension: Option<String>,
}

/// One observable in `sweep.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObservableMeta {
    /// Name (columns `<name>_mean`, `<name>_stderr`).
    pub name: String,
    /// Dimension in the scenario's units, when known.
    pub dimension: Option<String>,
}

/// One point in `sweep.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMeta {
    /// Point number.
    pub point: usize,
    /// Value of each key (JSON of the TOML values).
    pub values: Vec<serde_json::Value>,
    /// Member directories, relative to the sweep directory (`point_000/seed_001`).
    pub members: Vec<String>,
}

/// `sweep.json`: what `sweep.csv` holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepMeta {
    /// Version of this file's layout.
    pub format: u32,
    /// Version of granular that merged the table.
    pub granular_version: String,
    /// The sweep's resolved scenario, relative to the sweep directory.
    pub scenario: String,
    /// Its description.
    pub description: String,
    /// Its engine.
    pub engine: String,
    /// Its seed (members derive theirs from it).
    pub seed: u64,
    /// `grid` or `zip`.
    pub mode: String,
    /// Seeds per point.
    pub seeds: usize,
    /// The seed of member `s` at every point.
    pub member_seeds: Vec<u64>,
    /// The observable `granular sweep` prints.
    pub observable: String,
    /// What the units are.
    pub units: String,
    /// The swept keys.
    pub keys: Vec<KeyMeta>,
    /// The observables of the table.
    pub observables: Vec<ObservableMeta>,
    /// Every point with its members.
    pub points: Vec<PointMeta>,
    /// Members without a finished run (`point_001/seed_002`); empty for a complete sweep.
    pub missing: Vec<String>,
}

/// The sentence on units in `sweep.json`.
pub(super) const UNITS: &str = "the scenario's own consistent units (docs/scenario.md; \
    k_B = 1, so a temperature is an energy); `dimension` names each column's dimension \
    in them, null where none is recorded";

/// A TOML value as a table cell and as a number.
pub(super) fn cell(v: &toml::Value) -> (String, f64, &'static str) {
    match v {
        toml::Value::Integer(i) => (i.to_string(), *i as f64, "number"),
        toml::Value::Float(f) => (format!("{f:?}"), *f, "number"),
        toml::Value::Array(_) => {
            let n = norm(v);
            (format!("{n:?}"), n, "norm")
        }
        toml::Value::String(s) => (s.clone(), f64::NAN, "text"),
        other => (other.to_string(), f64::NAN, "text"),
    }
}

/// Euclidean norm of a TOML number or array of numbers (a velocity gives the speed).
fn norm(v: &toml::Value) -> f64 {
    match v {
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(f) => *f,
        toml::Value::Array(a) => a.iter().map(|x| norm(x).powi(2)).sum::<f64>().sqrt(),
        _ => f64::NAN,
    }
}

/// The dimension of a swept key or an observable, by its last name part, in the
/// scenario's units; `None` where none is recorded.
pub(super) fn dimension(name: &str) -> Option<String> {
    let last = name.rsplit('.').next().unwrap_or(name);
    let last = last.split('[').next().unwrap_or(last);
    let first = name.split('.').next().unwrap_or(name);
    let d = match (first, last) {
        (_, "restitution" | "wall_restitution" | "packing_fraction" | "fraction") => "1",
        (_, "count" | "collisions_per_particle" | "pair_collisions" | "wall_collisions") => "1",
        (_, "steps" | "crater_size" | "a2" | "collisions" | "samples" | "kurtosis") => "1",
        (_, "mass") => "mass",
        (_, "radius" | "lengths" | "displacement" | "cell_size") => "length",
        ("kinetic_energy_per_grain" | "temperature", _) => "energy",
        (_, "temperature" | "kinetic_energy" | "dissipated_energy") => "energy",
        (_, "velocity" | "speed" | "velocity_x" | "velocity_y") => "length/time",
        (_, "time" | "interval" | "contact_duration" | "time_step" | "mean_free_time") => "time",
        (_, "collision_frequency") => "1/time",
        (_, "gravity") => "length/time^2",
        (_, "pressure" | "wall_pressure") => "energy/length^D",
        (_, n) if n.ends_with("_ratio") => "1",
        _ => return None,
    };
    Some(d.to_string())
}

/// Writes `sweep.csv` and `sweep.json` (each to a temporary file, then renamed).
pub(super) fn write(dir: &Path, rows: &[SweepRow], meta: &SweepMeta) -> Result<(), SweepError> {
    let observables: Vec<&str> = meta.observables.iter().map(|o| o.name.as_str()).collect();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["point".to_string()];
    header.extend(meta.keys.iter().map(|k| k.key.clone()));
    header.push("members".into());
    for o in &observables {
        header.push(format!("{o}_mean"));
        header.push(format!("{o}_stderr"));
    }
    let csv_err = |e: csv::Error| SweepError::Table {
        path: dir.join(SWEEP_TABLE),
        message: e.to_string(),
    };
    w.write_record(&header).map_err(csv_err)?;
    for r in rows {
        let mut rec = vec![r.point.to_string()];
        rec.extend(r.values.iter().cloned());
        rec.push(r.members.to_string());
        for o in &observables {
            let (m, e) = r.observable(o).unwrap_or((f64::NAN, f64::NAN));
            rec.push(format!("{m:e}"));
            rec.push(format!("{e:e}"));
        }
        w.write_record(&rec).map_err(csv_err)?;
    }
    let bytes = w.into_inner().map_err(|e| SweepError::Table {
        path: dir.join(SWEEP_TABLE),
        message: e.to_string(),
    })?;
    let json = serde_json::to_string_pretty(meta).map_err(|e| SweepError::Table {
        path: dir.join(SWEEP_META),
        message: e.to_string(),
    })? + "\n";
    super::write_atomically(&dir.join(SWEEP_META), json.as_bytes())?;
    super::write_atomically(&dir.join(SWEEP_TABLE), &bytes)
}

impl SweepTable {
    /// Reads `DIR/sweep.csv` with `DIR/sweep.json` (the csv crate; the columns by name).
    pub fn read(dir: &Path) -> Result<SweepTable, SweepError> {
        let meta_path = dir.join(SWEEP_META);
        let table_err = |path: &Path, message: String| SweepError::Table {
            path: path.to_path_buf(),
            message,
        };
        let text = std::fs::read_to_string(&meta_path).map_err(|e| {
            table_err(
                &meta_path,
                format!(
                    "{e}; a sweep directory has sweep.json next to sweep.csv (a sweep written \
                     by an older granular: run `granular sweep` again, finished members are kept)"
                ),
            )
        })?;
        let meta: SweepMeta =
            serde_json::from_str(&text).map_err(|e| table_err(&meta_path, e.to_string()))?;
        let csv_path = dir.join(SWEEP_TABLE);
        let mut reader =
            csv::Reader::from_path(&csv_path).map_err(|e| table_err(&csv_path, e.to_string()))?;
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| table_err(&csv_path, e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let at = |name: &str| {
            header
                .iter()
                .position(|h| h == name)
                .ok_or_else(|| table_err(&csv_path, format!("no column `{name}`")))
        };
        let keys: Vec<String> = meta.keys.iter().map(|k| k.key.clone()).collect();
        let observables: Vec<String> = meta.observables.iter().map(|o| o.name.clone()).collect();
        let key_cols = keys.iter().map(|k| at(k)).collect::<Result<Vec<_>, _>>()?;
        let obs_cols = observables
            .iter()
            .map(|o| Ok((at(&format!("{o}_mean"))?, at(&format!("{o}_stderr"))?)))
            .collect::<Result<Vec<_>, SweepError>>()?;
        let (point_col, members_col) = (at("point")?, at("members")?);
        let mut rows = Vec::new();
        for rec in reader.records() {
            let rec = rec.map_err(|e| table_err(&csv_path, e.to_string()))?;
            let get = |i: usize| rec.get(i).unwrap_or_default();
            let num = |i: usize| get(i).parse::<f64>().unwrap_or(f64::NAN);
            let values: Vec<String> = key_cols.iter().map(|&i| get(i).to_string()).collect();
            rows.push(SweepRow {
                point: get(point_col).parse().unwrap_or(rows.len()),
                numbers: key_cols.iter().map(|&i| num(i)).collect(),
                values,
                members: get(members_col).parse().unwrap_or(0),
                observables: observables
                    .iter()
                    .zip(&obs_cols)
                    .map(|(o, &(m, e))| (o.clone(), num(m), num(e)))
                    .collect(),
            });
        }
        Ok(SweepTable {
            keys,
            observables,
            rows,
            meta,
        })
    }

    /// Column `observable`: means and standard errors in point order.
    pub fn observable(&self, name: &str) -> Option<(Vec<f64>, Vec<f64>)> {
        if !self.observables.iter().any(|o| o == name) {
            return None;
        }
        Some(
            self.rows
                .iter()
                .map(|r| r.observable(name).unwrap_or((f64::NAN, f64::NAN)))
                .unzip(),
        )
    }
}
