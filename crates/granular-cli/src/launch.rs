//! Running a run to its end: worker threads, MPI ranks (the DSMC engine split over them, with
//! the `mpi` feature), the progress bar, and the report of a finished or failed run.

use crate::error::CliError;
#[cfg(feature = "mpi")]
use crate::ranks;
use crate::{interrupt, intruder_summary, sweep};
use granular::output::format_number;
use granular::run::{ProgressReport, Run, RunError};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;

/// Sizes the worker threads of a run (`granular run`/`resume --threads`): the given number
/// (capped at the cores), or the cores shared among the `ranks_on_node` MPI ranks of this
/// node (at least 1 each). An explicit `RAYON_NUM_THREADS` is kept when `--threads` is not
/// given. The result never depends on it (docs/cluster.md, "Ranks and threads").
fn use_threads(threads: Option<usize>, ranks_on_node: usize) -> Result<(), CliError> {
    let n = match threads {
        Some(_) => worker_threads(threads)?,
        None if std::env::var_os("RAYON_NUM_THREADS").is_some() => return Ok(()),
        None => (worker_threads(None)? / ranks_on_node.max(1)).max(1),
    };
    // Fails only if the pool already exists (a second run in one process): keep it.
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global();
    Ok(())
}

/// `--threads`: at least 1, at most the number of cores (more is capped, with a note).
pub(crate) fn worker_threads(threads: Option<usize>) -> Result<usize, CliError> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    match threads {
        None => Ok(cores),
        Some(0) => Err(CliError::Message(format!(
            "--threads 0: give at least 1 worker thread, or leave the flag out to use all {cores} cores"
        ))),
        Some(t) if t > cores => {
            eprintln!("note: --threads {t} capped at {cores}, the number of cores of this machine");
            Ok(cores)
        }
        Some(t) => Ok(t),
    }
}

/// Opens the run with `open(directory of this rank, rank, communicator, ranks of the run
/// on this node)` and runs it to the end: as it
/// is without the `mpi` feature; with it, on every rank of `mpirun` (one rank without),
/// the DSMC engine split over the ranks (see `ranks`).
#[cfg(not(feature = "mpi"))]
pub(crate) fn launch(
    dir: &Path,
    quiet: bool,
    threads: Option<usize>,
    open: impl FnOnce(&Path, usize, Ranks, usize) -> Result<Run, String>,
) -> Result<(), CliError> {
    use_threads(threads, 1)?;
    let run = open(dir, 0, None, 1)?;
    finish_after(run, dir, quiet, None)
}

/// `granular sweep`; under `mpirun` with several ranks (the `mpi` feature) the members are
/// spread over the ranks and rank 0 writes the table once all have finished.
#[cfg(not(feature = "mpi"))]
pub(crate) fn sweep_on_ranks(args: &sweep::SweepArgs) -> Result<(), CliError> {
    sweep::sweep(args, None)
}

#[cfg(feature = "mpi")]
pub(crate) fn sweep_on_ranks(args: &sweep::SweepArgs) -> Result<(), CliError> {
    let ranks = ranks::Ranks::start();
    if ranks.size() == 1 {
        return sweep::sweep(args, None);
    }
    sweep::sweep(
        args,
        Some(sweep::SweepRanks {
            rank: ranks.rank(),
            size: ranks.size(),
            any_failed: &ranks::any_rank,
        }),
    )
}

/// The communicator of a run over several ranks, for opening it (`None`: one rank).
pub(crate) type Ranks = Option<std::sync::Arc<dyn granular::dsmc::Communicator>>;

#[cfg(not(feature = "mpi"))]
pub(crate) fn ranks_copy(_dir: &Path, _mine: &Path) -> Result<(), String> {
    Ok(())
}

#[cfg(feature = "mpi")]
pub(crate) fn ranks_copy(dir: &Path, mine: &Path) -> Result<(), String> {
    ranks::copy_run_files(dir, mine)
}

#[cfg(feature = "mpi")]
pub(crate) fn launch(
    dir: &Path,
    quiet: bool,
    threads: Option<usize>,
    open: impl FnOnce(&Path, usize, Ranks, usize) -> Result<Run, String>,
) -> Result<(), CliError> {
    let ranks = ranks::Ranks::start();
    use_threads(threads, ranks.on_node())?;
    let mine = ranks.directory(dir);
    let rank = ranks.rank();
    let result = (|| {
        let comm = (ranks.size() > 1).then(|| ranks.communicator());
        let mut run = ranks.agree(open(&mine, rank, comm, ranks.on_node()))?;
        if ranks.size() > 1 {
            // One rank (also without mpirun) runs the threaded engine as it is.
            ranks.agree(
                run.decompose(ranks.communicator(), dir)
                    .map_err(|e| e.to_string()),
            )?;
            run.agree_with(Box::new(ranks::any_rank));
            // stop.wall_seconds: rank 0's clock decides, at the same step on every rank.
            run.decide_wall_clock_with(Box::new(ranks::rank0_decides));
        }
        // A test hook (scripts/test-mpi): stop as if killed after this many outputs,
        // leaving the checkpoint, to resume it on another number of ranks.
        let stop_after = std::env::var("GRANULAR_TEST_STOP_AFTER_OUTPUTS")
            .ok()
            .and_then(|s| s.parse().ok());
        if rank != 0 {
            // The same run as rank 0's: its warnings and report once, from rank 0.
            return run_silently(run, stop_after);
        }
        finish_after(run, dir, quiet, stop_after)
    })();
    ranks.clean(dir);
    result
}

/// Runs `run` to the end without a word (ranks other than 0); errors are rank 0's to
/// report, this rank's exit status follows them.
#[cfg(feature = "mpi")]
fn run_silently(run: Run, stop_after: Option<u64>) -> Result<(), CliError> {
    let interrupt = interrupt::Interrupt::install();
    let mut run = run;
    run.interrupt_when(interrupt.check());
    match run.run_to_end(&mut |_| {}, stop_after) {
        Ok(_) => Ok(()),
        Err(RunError::Interrupted { .. }) => Err(CliError::Interrupted {
            status: interrupt.exit_status(),
            message: String::new(),
        }),
        Err(e) => Err(CliError::Message(e.to_string())),
    }
}

/// Runs `run` to the end with a progress bar and reports; stops as if killed after
/// `stop_after` outputs when given (a test hook).
fn finish_after(
    mut run: Run,
    dir: &Path,
    quiet: bool,
    stop_after: Option<u64>,
) -> Result<(), CliError> {
    let interrupt = interrupt::Interrupt::install();
    run.interrupt_when(interrupt.check());
    let elastic = run.scenario().collisions().law().is_elastic();
    for w in run.warnings() {
        eprintln!("warning: {w}");
    }
    let bar = if !quiet && std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40} {percent:>3}% t = {msg} [{elapsed_precise} < {eta_precise}]",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Some(bar)
    } else {
        None
    };
    let mut on_progress = |p: &ProgressReport| {
        if let Some(bar) = &bar {
            bar.set_position((p.fraction * 1000.0) as u64);
            bar.set_message(format!(
                "{}, {} events/s",
                format_number(p.time),
                format_number(p.events_per_second)
            ));
        }
    };
    let result = run.run_to_end(&mut on_progress, stop_after);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    match result {
        Ok(summary) => {
            eprintln!(
                "{}: {} grains, t = {}, {} collisions in {:.2} s ({} collisions/s), stopped by {}",
                dir.display(),
                summary.n,
                summary
                    .final_observables
                    .get("time")
                    .map_or(String::from("?"), |&v| format_number(v)),
                summary.collisions,
                summary.wall_seconds,
                format_number(summary.collisions_per_second),
                summary.stop_reason
            );
            intruder_summary::print(&summary);
            if let Some(c) = &summary.crater {
                eprintln!(
                    "  crater: {} of {} `{}` grains moved more than {}",
                    c.displaced, c.grains, c.species, c.displacement
                );
            }
            let fits = if elastic {
                summary.maxwell_boltzmann_fit.clone()
            } else {
                Default::default()
            };
            for (species, fit) in &fits {
                eprintln!(
                    "  Maxwell-Boltzmann fit of `{species}`: chi2 = {:.1} for {} degrees of freedom, p = {:.3} ({} speeds pooled)",
                    fit.chi_square, fit.degrees_of_freedom, fit.p_value, fit.samples
                );
            }
            Ok(())
        }
        Err(RunError::Engine(e)) => Err(CliError::Message(format!(
            "{e}\n(state saved in {}; fix the scenario and rerun)",
            dir.display()
        ))),
        Err(e @ RunError::Interrupted { .. }) => Err(CliError::Interrupted {
            status: interrupt.exit_status(),
            message: e.to_string(),
        }),
        Err(e) => Err(CliError::Message(e.to_string())),
    }
}
