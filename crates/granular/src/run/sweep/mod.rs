//! Parameter sweeps and ensembles: the same scenario at every point of a scan over one or
//! several keys (`[sweep]`: a grid of every combination, or zipped lists), each point with
//! several seeds, members run in parallel on all cores, or shared out over independent
//! processes ([`Shard`]) and merged afterwards ([`merge`]).
//!
//! Member `(point p, seed s)` is a complete run directory `DIR/point_PPP/seed_SSS` with
//! the seed `derive_key(scenario.seed, [MEMBER, s])`: the same seed index uses the same
//! random stream at every point (common random numbers, which makes differences between
//! points less noisy), and no result depends on the number of threads or shards or the
//! order in which members finish. A finished member (its `summary.json`) is not run again
//! and an interrupted one resumes from its checkpoint, so an interrupted sweep or shard
//! continues where it stopped. `DIR/scenario.toml` is the sweep's resolved scenario
//! (written by every shard, identical): [`merge`] reads the plan from it and builds
//! `sweep.csv` and `sweep.json` ([`table`]) from whatever members have finished.

mod shard;
pub mod table;

pub use shard::Shard;
pub(crate) use table::SweepMeta;
pub use table::{SWEEP_META, SWEEP_TABLE, SweepRow, SweepTable};

use super::{DirectoryState, Run, RunDir, RunError, RunFile, Summary};
use crate::random::{MEMBER, derive_key};
use crate::scenario::{Scenario, ScenarioError, SweepMode, SweepSpec};
use crate::stats::RunningStats;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

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
    /// A file could not be written or read.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Error.
        source: std::io::Error,
    },
    /// `sweep.csv` or `sweep.json` could not be written or read.
    #[error("{path}: {message}")]
    Table {
        /// File.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The directory holds another sweep.
    #[error(
        "{dir} holds another sweep: its scenario.toml differs from this scenario with these \
         --set options, and its members would be mixed with this one's; use another --out, \
         or remove the directory"
    )]
    OtherSweep {
        /// Sweep directory.
        dir: PathBuf,
    },
    /// Not a sweep directory.
    #[error(
        "{dir}: no scenario.toml, so not a sweep directory of `granular sweep` (a sweep begun \
         by an older granular: run `granular sweep SCENARIO --out {dir}` again; finished \
         members are kept)"
    )]
    NotASweep {
        /// Directory.
        dir: PathBuf,
    },
    /// Members have not finished.
    #[error(
        "{dir}: {} of {total} members have not finished, so no table was written; run the \
         shards that hold them (`granular sweep SCENARIO --out DIR --shard I/N`) or merge what \
         there is with --allow-missing. Missing:\n  {}",
        missing.len(),
        missing.join("\n  ")
    )]
    Missing {
        /// Sweep directory.
        dir: PathBuf,
        /// Members, e.g. `point_001/seed_002 (not started)`.
        missing: Vec<String>,
        /// Number of members of the sweep.
        total: usize,
    },
}

/// The members of a sweep: its points (the values of its keys) times its seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPlan {
    /// The swept keys (`--set` form).
    pub keys: Vec<String>,
    /// The values of the keys at each point.
    pub points: Vec<Vec<toml::Value>>,
    /// The `[sweep]` table.
    pub spec: SweepSpec,
    /// The scenario's seed.
    pub seed: u64,
}

impl SweepPlan {
    /// The plan of `scenario`'s `[sweep]`.
    pub(crate) fn new(scenario: &Scenario) -> Result<SweepPlan, SweepError> {
        let spec = scenario.sweep.clone().ok_or(SweepError::NoSweep)?;
        Ok(SweepPlan {
            keys: spec.axes().into_iter().map(|a| a.key).collect(),
            points: spec.points(),
            seed: scenario.seed,
            spec,
        })
    }

    /// Number of members: points times seeds.
    pub(crate) fn member_count(&self) -> usize {
        self.points.len() * self.spec.seeds
    }

    /// `(point, seed)` of member number `m` (point-major).
    pub(crate) fn member(&self, m: usize) -> (usize, usize) {
        (m / self.spec.seeds, m % self.spec.seeds)
    }

    /// The member's directory relative to the sweep's: `point_PPP/seed_SSS`.
    pub fn member_name(point: usize, seed: usize) -> String {
        format!("point_{point:03}/seed_{seed:03}")
    }

    /// The seed of member `s` (at every point).
    pub(crate) fn member_seed(&self, s: usize) -> u64 {
        derive_key(self.seed, &[MEMBER, s as u64]) >> 1
    }

    /// The `--set` options that make member `(point, seed)` of the base scenario.
    pub(crate) fn member_overrides(&self, point: usize, seed: usize) -> Vec<String> {
        let mut o: Vec<String> = self
            .keys
            .iter()
            .zip(&self.points[point])
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        o.push(format!("seed={}", self.member_seed(seed)));
        o
    }
}

/// What one shard did.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardRun {
    /// The shard.
    pub shard: Shard,
    /// Its members (`point_000/seed_001`, ...), in order.
    pub members: Vec<String>,
    /// Of those, how many ran now (the others had finished before).
    pub ran: usize,
    /// Members of the whole sweep.
    pub total: usize,
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename,
/// so that a reader (or another shard) never sees half a file.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), SweepError> {
    let io = |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    };
    let tmp = path.with_extension(format!("tmp.{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// How a sweep (or one shard of it) runs: [`run_shard_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOptions {
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// The share of the members to run ([`Shard::ALL`]: all of them).
    pub shard: Shard,
    /// Run even above the pre-flight cost limits (what `granular sweep --insist` asks
    /// for): the scenario and every point are read with
    /// [`Scenario::from_toml_insisting`] instead of [`Scenario::from_toml`]. Every other
    /// check stays.
    pub insist: bool,
}

impl Default for SweepOptions {
    /// All cores, all members, within the limits.
    fn default() -> Self {
        SweepOptions {
            threads: 0,
            shard: Shard::ALL,
            insist: false,
        }
    }
}

/// Runs the whole sweep of `scenario_text` in `dir` with `threads` worker threads (0: all
/// cores) and merges its table. `on_member` is called (from worker threads) as members
/// finish.
pub fn run_sweep(
    dir: &Path,
    scenario_text: &str,
    overrides: &[String],
    threads: usize,
    on_member: &(dyn Fn(&str, &Summary) + Sync),
) -> Result<Vec<SweepRow>, SweepError> {
    let options = SweepOptions {
        threads,
        ..SweepOptions::default()
    };
    run_shard_with(dir, scenario_text, overrides, &options, on_member)?;
    Ok(merge(dir, false)?.rows)
}

/// Runs the members of `shard` (see `Shard::owns`) into `dir` within the pre-flight
/// cost limits; the table is left to [`merge`]. [`run_shard_with`] with
/// `SweepOptions { threads, shard, insist: false }`.
pub fn run_shard(
    dir: &Path,
    scenario_text: &str,
    overrides: &[String],
    threads: usize,
    shard: Shard,
    on_member: &(dyn Fn(&str, &Summary) + Sync),
) -> Result<ShardRun, SweepError> {
    let options = SweepOptions {
        threads,
        shard,
        insist: false,
    };
    run_shard_with(dir, scenario_text, overrides, &options, on_member)
}

/// Runs the members of `options.shard` (see `Shard::owns`) into `dir` on
/// `options.threads` worker threads, above the cost limits when `options.insist`; the
/// table is left to [`merge`] (which reads the members whatever their cost).
pub fn run_shard_with(
    dir: &Path,
    scenario_text: &str,
    overrides: &[String],
    options: &SweepOptions,
    on_member: &(dyn Fn(&str, &Summary) + Sync),
) -> Result<ShardRun, SweepError> {
    let SweepOptions {
        threads,
        shard,
        insist,
    } = *options;
    let base = if insist {
        Scenario::from_toml_insisting(scenario_text, overrides)?
    } else {
        Scenario::from_toml(scenario_text, overrides)?
    };
    let plan = SweepPlan::new(&base)?;
    let io = |source| SweepError::Io {
        path: dir.to_path_buf(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let resolved = base.to_toml();
    let path = dir.join(RunFile::Scenario.name());
    match std::fs::read_to_string(&path) {
        Ok(old) if old != resolved => {
            return Err(SweepError::OtherSweep {
                dir: dir.to_path_buf(),
            });
        }
        Ok(_) => {}
        Err(_) => write_atomically(&path, resolved.as_bytes())?,
    }
    let mine: Vec<usize> = (0..plan.member_count())
        .filter(|&m| shard.owns(m))
        .collect();
    let run_one = |&m: &usize| -> Result<bool, SweepError> {
        let (p, s) = plan.member(m);
        run_member(dir, scenario_text, overrides, &plan, p, s, on_member)
    };
    let run_all = || mine.par_iter().map(run_one).collect::<Vec<_>>();
    let results = if threads == 0 {
        run_all()
    } else {
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(run_all),
            Err(_) => run_all(),
        }
    };
    let mut ran = 0;
    for r in results {
        ran += usize::from(r?);
    }
    Ok(ShardRun {
        shard,
        members: mine
            .iter()
            .map(|&m| {
                let (p, s) = plan.member(m);
                SweepPlan::member_name(p, s)
            })
            .collect(),
        ran,
        total: plan.member_count(),
    })
}

/// Runs member `(p, s)` unless it has finished (resuming it from a checkpoint when it
/// has one); whether it ran now.
fn run_member(
    dir: &Path,
    scenario_text: &str,
    overrides: &[String],
    plan: &SweepPlan,
    p: usize,
    s: usize,
    on_member: &(dyn Fn(&str, &Summary) + Sync),
) -> Result<bool, SweepError> {
    let member_dir = dir.join(SweepPlan::member_name(p, s));
    let name = member_dir.display().to_string();
    let failed = |source| SweepError::Member {
        member: name.clone(),
        source,
    };
    let member = RunDir::new(&member_dir);
    if member.state() == (DirectoryState::Run { finished: true }) {
        return Ok(false);
    }
    let resumed = member
        .has(RunFile::Checkpoint)
        .then(|| Run::resume(&member_dir).ok())
        .flatten();
    let run = match resumed {
        Some(run) => run,
        None => {
            let mut o = overrides.to_vec();
            o.extend(plan.member_overrides(p, s));
            let scenario = crate::scenario::sweep_member(scenario_text, &o)?;
            Run::create(&member_dir, scenario).map_err(failed)?
        }
    };
    let summary = run.run_to_end(&mut |_| {}, None).map_err(failed)?;
    on_member(&name, &summary);
    Ok(true)
}

/// A merged sweep: its rows, sidecar and missing members.
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    /// The rows of `sweep.csv`.
    pub rows: Vec<SweepRow>,
    /// `sweep.json`.
    pub meta: SweepMeta,
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

/// Builds `DIR/sweep.csv` and `DIR/sweep.json` from the finished members of the sweep in
/// `dir` (its plan from `DIR/scenario.toml`). Members that have not finished are an error
/// that lists them, unless `allow_missing` (then `sweep.json` lists them and `members`
/// counts the finished ones). The files depend only on the finished members.
pub fn merge(dir: &Path, allow_missing: bool) -> Result<Merged, SweepError> {
    let path = dir.join(RunFile::Scenario.name());
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Err(SweepError::NotASweep {
            dir: dir.to_path_buf(),
        });
    };
    let base = Scenario::from_resolved_toml(&text, Some(dir))?;
    let plan = SweepPlan::new(&base)?;
    let mut missing = Vec::new();
    let mut summaries: Vec<Vec<Option<Summary>>> = Vec::with_capacity(plan.points.len());
    for p in 0..plan.points.len() {
        let mut row = Vec::with_capacity(plan.spec.seeds);
        for s in 0..plan.spec.seeds {
            let name = SweepPlan::member_name(p, s);
            let member = RunDir::new(dir.join(&name));
            match member.state() {
                DirectoryState::Run { finished: true } => {
                    let summary = member.summary().map_err(|source| SweepError::Member {
                        member: member.path().display().to_string(),
                        source,
                    })?;
                    row.push(Some(summary));
                }
                DirectoryState::Run { finished: false } => {
                    missing.push(format!("{name} (unfinished)"));
                    row.push(None);
                }
                _ => {
                    missing.push(format!("{name} (not started)"));
                    row.push(None);
                }
            }
        }
        summaries.push(row);
    }
    if !missing.is_empty() && !allow_missing {
        return Err(SweepError::Missing {
            dir: dir.to_path_buf(),
            missing,
            total: plan.member_count(),
        });
    }
    let rows = aggregate(&plan, &summaries);
    let meta = sidecar(&base, &plan, &rows, &summaries, missing);
    table::write(dir, &rows, &meta)?;
    Ok(Merged { rows, meta })
}

/// Mean and standard error over seeds per point, in index order (never a parallel float
/// reduction).
fn aggregate(plan: &SweepPlan, summaries: &[Vec<Option<Summary>>]) -> Vec<SweepRow> {
    let mut rows = Vec::with_capacity(plan.points.len());
    for (p, point) in plan.points.iter().enumerate() {
        let mut names: Vec<String> = Vec::new();
        let mut stats: Vec<RunningStats> = Vec::new();
        let done: Vec<&Summary> = summaries[p].iter().flatten().collect();
        for summary in &done {
            for (k, x) in observables(summary) {
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
        let cells: Vec<(String, f64, &str)> = point.iter().map(table::cell).collect();
        rows.push(SweepRow {
            point: p,
            values: cells.iter().map(|c| c.0.clone()).collect(),
            numbers: cells.iter().map(|c| c.1).collect(),
            members: done.len() as u64,
            observables: names
                .into_iter()
                .zip(stats)
                .map(|(n, st)| {
                    let err = if st.count > 1 {
                        st.standard_error()
                    } else {
                        f64::NAN
                    };
                    (n, st.mean(), err)
                })
                .collect(),
        });
    }
    rows
}

/// `sweep.json` of a merge.
fn sidecar(
    base: &Scenario,
    plan: &SweepPlan,
    rows: &[SweepRow],
    summaries: &[Vec<Option<Summary>>],
    missing: Vec<String>,
) -> SweepMeta {
    let json = |v: &toml::Value| serde_json::to_value(v).unwrap_or(serde_json::Value::Null);
    let mut observables: Vec<String> = Vec::new();
    for r in rows {
        for (n, ..) in &r.observables {
            if !observables.contains(n) {
                observables.push(n.clone());
            }
        }
    }
    let axes = plan.spec.axes();
    SweepMeta {
        format: 1,
        granular_version: env!("CARGO_PKG_VERSION").to_string(),
        scenario: RunFile::Scenario.name().into(),
        description: base.description.clone(),
        engine: toml::Value::try_from(base.kind())
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default(),
        seed: plan.seed,
        mode: match plan.spec.mode {
            SweepMode::Grid => "grid",
            SweepMode::Zip => "zip",
        }
        .into(),
        seeds: plan.spec.seeds,
        member_seeds: (0..plan.spec.seeds).map(|s| plan.member_seed(s)).collect(),
        observable: plan.spec.observable.clone(),
        units: table::UNITS.into(),
        keys: axes
            .iter()
            .map(|a| table::KeyMeta {
                key: a.key.clone(),
                values: a.values.iter().map(json).collect(),
                cell: a
                    .values
                    .first()
                    .map_or("number", |v| table::cell(v).2)
                    .into(),
                dimension: table::dimension(&a.key),
            })
            .collect(),
        observables: observables
            .into_iter()
            .map(|name| table::ObservableMeta {
                dimension: table::dimension(&name),
                name,
            })
            .collect(),
        points: plan
            .points
            .iter()
            .enumerate()
            .map(|(p, values)| table::PointMeta {
                point: p,
                values: values.iter().map(json).collect(),
                members: (0..plan.spec.seeds)
                    .filter(|&s| summaries[p][s].is_some())
                    .map(|s| SweepPlan::member_name(p, s))
                    .collect(),
            })
            .collect(),
        missing,
    }
}
