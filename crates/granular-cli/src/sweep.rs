//! `granular sweep` (the whole sweep, or one shard of it) and `granular merge`.

use crate::error::CliError;
use granular::run::sweep::{self, Shard, SweepRow};
use std::path::Path;

/// What `granular sweep` was given.
pub(crate) struct SweepArgs<'a> {
    pub scenario: &'a Path,
    pub text: &'a str,
    pub dir: &'a Path,
    pub set: &'a [String],
    pub threads: usize,
    pub shard: Option<Shard>,
    pub insist: bool,
    pub observable: String,
}

/// The ranks of `mpirun` a sweep is spread over: this rank, their number, and a collective
/// "did any rank fail".
pub(crate) struct SweepRanks<'a> {
    pub rank: usize,
    pub size: usize,
    pub any_failed: &'a dyn Fn(bool) -> bool,
}

/// Shard `shard` split further over `size` ranks: rank `r` takes the members of `shard`
/// whose turn in it is `r` (member `m` with `m mod (N K) = I - 1 + N r`).
fn rank_shard(shard: Shard, rank: usize, size: usize) -> Shard {
    Shard {
        index: shard.index + shard.count * rank,
        count: shard.count * size,
    }
}

/// Runs the sweep (or its shard: `--shard`, else the environment) and, for the whole
/// sweep, merges the table and prints the chosen observable as CSV.
pub(crate) fn sweep(a: &SweepArgs, ranks: Option<SweepRanks>) -> Result<(), CliError> {
    let outer = match a.shard {
        Some(s) => s,
        None => match Shard::from_env(|k| std::env::var(k).ok()) {
            Ok(Some((s, from))) => {
                eprintln!("shard {s} (from {from}; --shard overrides it)");
                s
            }
            Ok(None) => Shard::ALL,
            Err(e) => return Err(CliError::Message(e)),
        },
    };
    let shard = match &ranks {
        Some(r) => rank_shard(outer, r.rank, r.size),
        None => outer,
    };
    let start = std::time::Instant::now();
    let report = |name: &str, s: &granular::Summary| {
        eprintln!(
            "{name}: {} collisions in {:.2} s, stopped by {}",
            s.collisions, s.wall_seconds, s.stop_reason
        );
    };
    let fail = |e: sweep::SweepError| format!("{}: {e}", a.scenario.display());
    let options = sweep::SweepOptions {
        threads: a.threads,
        shard,
        insist: a.insist,
    };
    let done = sweep::run_shard_with(a.dir, a.text, a.set, &options, &report).map_err(fail);
    if let Some(r) = &ranks {
        // Every rank has finished its members (collective); rank 0 writes the table.
        let failed = (r.any_failed)(done.is_err());
        let done = done?;
        if failed {
            return Err(CliError::Message(format!(
                "{}: a rank failed (its message is above); rerun the same command to \
                 finish the missing members",
                a.dir.display()
            )));
        }
        if r.rank != 0 {
            return Ok(());
        }
        eprintln!(
            "{}: shard {outer} spread over {} ranks, all finished ({} members run now on \
             rank 0)",
            a.dir.display(),
            r.size,
            done.ran
        );
    } else if shard.count == 1 {
        done?;
    } else {
        let done = done?;
        eprintln!(
            "{}: shard {shard}: {} of {} members ({} run now) in {:.1} s; when every shard has \
             finished: granular merge {}",
            a.dir.display(),
            done.members.len(),
            done.total,
            done.ran,
            start.elapsed().as_secs_f64(),
            a.dir.display()
        );
        return Ok(());
    }
    if outer.count > 1 {
        eprintln!(
            "{}: shard {outer} done; when every shard has finished: granular merge {}",
            a.dir.display(),
            a.dir.display()
        );
        return Ok(());
    }
    let merged = sweep::merge(a.dir, false).map_err(fail)?;
    print_observable(&merged.meta.keys, &merged.rows, &a.observable);
    eprintln!(
        "{}: {} points in {:.1} s; table in {}",
        a.dir.display(),
        merged.rows.len(),
        start.elapsed().as_secs_f64(),
        a.dir.join("sweep.csv").display()
    );
    Ok(())
}

/// The chosen observable as CSV on standard output: the keys, mean, standard error.
fn print_observable(keys: &[sweep::table::KeyMeta], rows: &[SweepRow], observable: &str) {
    let names: Vec<&str> = keys.iter().map(|k| k.key.as_str()).collect();
    println!("{},{observable}_mean,{observable}_stderr", names.join(","));
    for r in rows {
        if let Some((m, e)) = r.observable(observable) {
            println!("{},{m},{e}", r.values.join(","));
        }
    }
}

/// `granular merge DIR [--allow-missing]`.
pub(crate) fn merge(dir: &Path, allow_missing: bool) -> Result<(), CliError> {
    let merged = sweep::merge(dir, allow_missing).map_err(|e| e.to_string())?;
    let missing = &merged.meta.missing;
    if !missing.is_empty() {
        eprintln!(
            "warning: {} members missing (listed in sweep.json):\n  {}",
            missing.len(),
            missing.join("\n  ")
        );
    }
    let members: u64 = merged.rows.iter().map(|r| r.members).sum();
    eprintln!(
        "{}: {} points, {members} members; table in {}",
        dir.display(),
        merged.rows.len(),
        dir.join("sweep.csv").display()
    );
    Ok(())
}
