//! Parameter sweeps and ensembles: the same scenario for each value of one key, each
//! value with several seeds, members run in parallel on all cores.
//!
//! Member `(point p, seed s)` runs in `DIR/point_PPP/seed_SSS` with the seed
//! `derive_key(scenario.seed, [MEMBER, s])`: the same seed index uses the same random
//! stream at every point (common random numbers, which makes differences between points
//! less noisy), and no result depends on the number of threads or the order in which
//! members finish. A member whose `summary.json` exists is not run again, so an
//! interrupted sweep resumes where it stopped.

use super::{Run, RunError, Summary};
use crate::random::{MEMBER, derive_key};
use crate::scenario::{Scenario, ScenarioError, SweepSpec};
use crate::stats::RunningStats;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One row of the aggregated table: a value of the swept key and, for each observable,
/// the mean and standard error over seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The value of the swept key, as TOML text.
    pub value: String,
    /// The value as a number (the norm of an array, e.g. a speed).
    pub number: f64,
    /// `(observable, mean, standard error, members)`.
    pub observables: Vec<(String, f64, f64, u64)>,
}

/// Why a sweep failed.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The scenario has no `[sweep]` table.
    #[error(
        "the scenario has no [sweep] table: add one with key, values and seeds (docs/scenario.md)"
    )]
    NoSweep,
    /// A member's scenario is invalid.
    #[error("{0}")]
    Scenario(#[from] ScenarioError),
    /// A member failed.
    #[error("member {member}: {source}")]
    Member {
        /// Member directory.
        member: String,
        /// What went wrong.
        source: RunError,
    },
    /// The table could not be written.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Error.
        source: std::io::Error,
    },
}

/// Number of a TOML value: the value itself, or the Euclidean norm of an array (a
/// velocity vector gives the speed).
fn numeric(v: &toml::Value) -> f64 {
    match v {
        toml::Value::Integer(i) => *i as f64,
        toml::Value::Float(f) => *f,
        toml::Value::Array(a) => a.iter().map(|x| numeric(x).powi(2)).sum::<f64>().sqrt(),
        _ => f64::NAN,
    }
}

fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The scalar observables of a member summary (final observables, crater size); all of
/// them deterministic, so the table does not depend on timing or threads.
fn observables(summary: &Summary) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = summary
        .final_observables
        .iter()
        .filter(|(_, v)| v.is_finite())
        .map(|(k, v)| (k.clone(), *v))
        .collect();
    if let Some(d) = summary.observable("crater_size") {
        out.push(("crater_size".into(), d));
    }
    out
}

/// Runs the sweep of `scenario_text` in `dir` with `threads` worker threads (0: all
/// cores). `on_member` is called (from worker threads) as members finish.
pub fn run_sweep(
    dir: &Path,
    scenario_text: &str,
    overrides: &[String],
    threads: usize,
    on_member: &(dyn Fn(&str, &Summary) + Sync),
) -> Result<Vec<SweepRow>, SweepError> {
    let base = Scenario::from_toml(scenario_text, overrides)?;
    let spec: SweepSpec = base.sweep.clone().ok_or(SweepError::NoSweep)?;
    std::fs::create_dir_all(dir).map_err(|source| SweepError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let members: Vec<(usize, usize)> = (0..spec.values.len())
        .flat_map(|p| (0..spec.seeds).map(move |s| (p, s)))
        .collect();
    let run_member = |&(p, s): &(usize, usize)| -> Result<Summary, SweepError> {
        let member_dir = dir
            .join(format!("point_{p:03}"))
            .join(format!("seed_{s:03}"));
        let name = member_dir.display().to_string();
        let summary_path = member_dir.join("summary.json");
        if let Ok(text) = std::fs::read_to_string(&summary_path)
            && let Ok(done) = serde_json::from_str::<Summary>(&text)
        {
            return Ok(done);
        }
        let mut o = overrides.to_vec();
        o.push(format!("{}={}", spec.key, spec.values[p]));
        o.push(format!(
            "seed={}",
            derive_key(base.seed, &[MEMBER, s as u64]) >> 1
        ));
        let scenario = Scenario::from_toml(scenario_text, &o)?;
        let summary = Run::create(&member_dir, scenario)
            .and_then(|r| r.run_to_end(&mut |_| {}, None))
            .map_err(|source| SweepError::Member {
                member: name.clone(),
                source,
            })?;
        on_member(&name, &summary);
        Ok(summary)
    };
    let run_all = || members.par_iter().map(run_member).collect::<Vec<_>>();
    let results = if threads == 0 {
        run_all()
    } else {
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(run_all),
            Err(_) => run_all(),
        }
    };
    let mut summaries = Vec::with_capacity(results.len());
    for r in results {
        summaries.push(r?);
    }
    // Aggregate in index order (never a parallel float reduction).
    let mut rows = Vec::new();
    for (p, value) in spec.values.iter().enumerate() {
        let mut names: Vec<String> = Vec::new();
        let mut stats: Vec<RunningStats> = Vec::new();
        for s in 0..spec.seeds {
            for (k, x) in observables(&summaries[p * spec.seeds + s]) {
                let idx = match names.iter().position(|n| *n == k) {
                    Some(i) => i,
                    None => {
                        names.push(k);
                        stats.push(RunningStats::new());
                        names.len() - 1
                    }
                };
                stats[idx].push(x);
            }
        }
        rows.push(SweepRow {
            value: value_text(value),
            number: numeric(value),
            observables: names
                .into_iter()
                .zip(stats)
                .map(|(n, st)| {
                    let err = if st.count > 1 {
                        st.standard_error()
                    } else {
                        f64::NAN
                    };
                    (n, st.mean(), err, st.count)
                })
                .collect(),
        });
    }
    write_table(&dir.join("sweep.csv"), &spec.key, &rows)?;
    Ok(rows)
}

/// Writes the aggregated table: `value, parameter, <obs>_mean, <obs>_stderr, ...`.
fn write_table(path: &Path, key: &str, rows: &[SweepRow]) -> Result<(), SweepError> {
    let mut columns: Vec<String> = Vec::new();
    for r in rows {
        for (n, ..) in &r.observables {
            if !columns.contains(n) {
                columns.push(n.clone());
            }
        }
    }
    let mut out = format!("# sweep of {key}\nvalue,parameter,members");
    for c in &columns {
        out.push_str(&format!(",{c}_mean,{c}_stderr"));
    }
    out.push('\n');
    for r in rows {
        let members = r.observables.first().map_or(0, |o| o.3);
        out.push_str(&format!(
            "\"{}\",{:e},{}",
            r.value.replace('"', "'"),
            r.number,
            members
        ));
        for c in &columns {
            match r.observables.iter().find(|o| &o.0 == c) {
                Some((_, m, e, _)) => out.push_str(&format!(",{m:e},{e:e}")),
                None => out.push_str(",nan,nan"),
            }
        }
        out.push('\n');
    }
    std::fs::write(path, out).map_err(|source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    })
}
