//! `granular`: the command line over the granular library, as a library: the binary
//! (`src/main.rs`) and the Python package (`python -m granular`) call [`main_with_args`].
//!
//! A thin layer: it parses arguments, turns scenario files into runs, shows progress on a
//! terminal, and reports errors (through `miette`). All physics and file formats live in
//! the library, the figures in `granular-report`.

mod bench;
mod error;
mod interrupt;
mod intruder_summary;

use clap::{Parser, Subcommand};
use error::CliError;
use granular::output::format_number;
use granular::run::{DirectoryState, ProgressReport, Run, RunError};
use granular::scenario::Scenario;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Simulate granular gases: event-driven molecular dynamics and DSMC of hard disks and spheres.
#[derive(Parser)]
#[command(name = "granular", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario and write its run directory.
    Run {
        /// Scenario file (TOML; see docs/scenario.md).
        scenario: PathBuf,
        /// Run directory (default: `runs/<scenario name>`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Seed of all random streams, 0 to 18446744073709551615 (overrides the scenario's `seed`).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_seed)]
        seed: Option<u64>,
        /// Override a scenario key, e.g. --set collisions.restitution=0.9 (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
        /// Replace an earlier run in the --out directory (finished or interrupted).
        #[arg(long)]
        replace: bool,
    },
    /// Validate a scenario and print it fully resolved.
    Check {
        /// Scenario file.
        scenario: PathBuf,
        /// Override a scenario key (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Run a scenario's `[sweep]`: every value of a key, several seeds each, in parallel.
    Sweep {
        /// Scenario file with a `[sweep]` table.
        scenario: PathBuf,
        /// Sweep directory (default: `runs/<scenario name>`); finished members are kept.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads, 1 to the number of cores (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Override a scenario key for every member (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Draw the figures of a finished run or sweep (from its files, without rerunning).
    Plot {
        /// Run or sweep directory.
        dir: PathBuf,
        /// Also write an animation of the snapshots (GIF; MP4 too when ffmpeg is present).
        #[arg(long)]
        animate: bool,
    },
    /// Write a self-contained HTML page of a finished run or sweep (DIR/report.html):
    /// scenario, summary against theory, figures and a snapshot player.
    Report {
        /// Run or sweep directory.
        dir: PathBuf,
    },
    /// Overlay finished runs (e.g. EDMD and DSMC of one scenario): energy with Haff's law,
    /// impact-parameter histograms, S(k), density maps.
    Compare {
        /// Run directories (the first one sets Haff's t0).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Directory for the figures (PNG and SVG).
        #[arg(long)]
        out: PathBuf,
    },
    /// Continue an interrupted run from its last checkpoint.
    Resume {
        /// Run directory.
        dir: PathBuf,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Reproduce the figures of the Gillespie intruder paper (PNG, SVG and CSV).
    Reproduce(ReproduceArgs),
    /// Measure the speed of an engine on standard cases.
    Bench {
        #[command(subcommand)]
        engine: bench::BenchCommand,
    },
}

/// Arguments of `granular reproduce`.
#[derive(clap::Args, Debug)]
struct ReproduceArgs {
    /// Figures to make: fig1 fig2 fig3 fig4 fig5 fig7 fig8, or all.
    #[arg(required = true, value_name = "FIGURE")]
    figures: Vec<String>,
    /// Output directory (created).
    #[arg(long, default_value = "figures/intruder")]
    out: PathBuf,
    /// Ten times fewer collisions than the paper (for tests and previews).
    #[arg(long)]
    quick: bool,
    /// Worker threads, 1 to the number of cores (default: all cores); results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Seed of all random streams, 0 to 18446744073709551615.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = parse_seed)]
    seed: u64,
}

/// Runs the command line with `args` (the program name first, as `std::env::args`) and
/// returns the process exit status: 0 on success, 2 on an error (reported through
/// `miette` on stderr) or a usage error (clap's message), 130 or 143 for a run stopped by
/// SIGINT or SIGTERM after its final checkpoint. The `granular` binary and the
/// Python package's `python -m granular` both call this.
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version are "errors" that print to stdout and exit 0.
            let _ = e.print();
            return e.exit_code();
        }
    };
    error::install_handler();
    match dispatch(cli) {
        Ok(()) => 0,
        Err(e) => {
            let status = e.exit_status();
            error::report(e);
            i32::from(status)
        }
    }
}

/// `--seed`: a whole number in the range of `u64` (clap's own parser would read `-1` as a
/// flag and give no range).
fn parse_seed(s: &str) -> Result<u64, String> {
    s.trim()
        .parse::<u64>()
        .map_err(|_| format!("a seed is a whole number in 0..={} (got `{s}`)", u64::MAX))
}

/// `--threads`: at least 1, at most the number of cores (more is capped, with a note).
fn worker_threads(threads: Option<usize>) -> Result<usize, CliError> {
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

/// `runs/<scenario file stem>`.
fn default_dir(scenario: &Path) -> PathBuf {
    PathBuf::from("runs").join(
        scenario
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().to_string()),
    )
}

fn load(path: &Path, seed: Option<u64>, set: &[String]) -> Result<Scenario, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut overrides = set.to_vec();
    if let Some(s) = seed {
        // A string: TOML integers stop at i64::MAX, seeds at u64::MAX.
        overrides.push(format!("seed=\"{s}\""));
    }
    let mut sc = Scenario::from_toml(&text, &overrides)
        .map_err(|e| CliError::scenario(path, &text, &overrides, e))?;
    if let Some(o) = bath_file_override(path, &sc) {
        overrides.push(o);
        sc = Scenario::from_toml(&text, &overrides)
            .map_err(|e| CliError::scenario(path, &text, &overrides, e))?;
    }
    Ok(sc)
}

/// A tabulated intruder bath `file` is relative to the scenario file: the override that
/// makes it absolute (so that validation reads it, and run directories, sweeps and
/// resumes find it from any working directory), if there is one to make.
fn bath_file_override(path: &Path, sc: &Scenario) -> Option<String> {
    use granular::intruder::BathConfig;
    let cfg = sc.intruder.as_ref()?.one_d()?;
    let BathConfig::Tabulated { file: Some(f), .. } = &cfg.bath else {
        return None;
    };
    if Path::new(f).is_absolute() {
        return None;
    }
    let base = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let base = std::path::absolute(base).unwrap_or_else(|_| base.to_path_buf());
    let full = base.join(f).to_string_lossy().into_owned();
    Some(format!("intruder.bath.file={}", toml::Value::String(full)))
}

fn dispatch(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Run {
            scenario,
            out,
            seed,
            set,
            quiet,
            replace,
        } => {
            let sc = load(&scenario, seed, &set)?;
            let dir = out.unwrap_or_else(|| default_dir(&scenario));
            if let DirectoryState::Run { finished } = DirectoryState::of(&dir)
                && !replace
            {
                let what = if finished {
                    "a finished run (summary.json)".to_string()
                } else {
                    format!(
                        "an earlier run (to continue it: `granular resume {}`)",
                        dir.display()
                    )
                };
                return Err(CliError::Message(format!(
                    "{} holds {what}; pass --replace to overwrite it, or choose another --out",
                    dir.display()
                )));
            }
            let run = Run::create(&dir, sc).map_err(|e| e.to_string())?;
            finish(run, &dir, quiet)
        }
        Command::Check { scenario, set } => {
            let sc = load(&scenario, None, &set)?;
            print!("{}", sc.to_toml());
            match &sc.intruder {
                Some(i) => eprintln!(
                    "{}: valid (intruder engine, model {})",
                    scenario.display(),
                    i.model()
                ),
                None => eprintln!(
                    "{}: valid ({} grains, {} species)",
                    scenario.display(),
                    sc.particle_count(),
                    sc.species.len()
                ),
            }
            Ok(())
        }
        Command::Resume { dir, quiet } => {
            let run = Run::resume(&dir).map_err(|e| e.to_string())?;
            finish(run, &dir, quiet)
        }
        Command::Bench { engine } => Ok(bench::run(engine)?),
        Command::Compare { dirs, out } => {
            let files = granular_report::compare(&dirs, &out)?;
            for f in &files {
                println!("{}", f.display());
            }
            eprintln!("{}: {} figure files", out.display(), files.len());
            Ok(())
        }
        Command::Reproduce(args) => {
            let options = granular_report::reproduce::Options {
                out: args.out,
                quick: args.quick,
                threads: worker_threads(args.threads)?,
                seed: args.seed,
            };
            let quick = if args.quick { " (--quick)" } else { "" };
            granular_report::reproduce::run(&args.figures, &options, &|done| {
                for f in &done.files {
                    println!("{}", f.display());
                }
                eprintln!("{}: {:.1} s{quick}", done.name, done.seconds);
            })?;
            Ok(())
        }
        Command::Report { dir } => {
            let pages = granular_report::report(&dir)?;
            for p in &pages {
                println!("{}", p.display());
            }
            eprintln!("{}: {} report pages", dir.display(), pages.len());
            Ok(())
        }
        Command::Plot { dir, animate } => {
            let files = granular_report::plot_dir(&dir, animate)?;
            for f in &files {
                println!("{}", f.display());
            }
            eprintln!("{}: {} figure files", dir.display(), files.len());
            Ok(())
        }
        Command::Sweep {
            scenario,
            out,
            threads,
            set,
        } => {
            let threads = worker_threads(threads)?;
            let text = std::fs::read_to_string(&scenario)
                .map_err(|e| format!("{}: {e}", scenario.display()))?;
            let dir = out.unwrap_or_else(|| default_dir(&scenario));
            let mut set = set;
            if let Some(o) = bath_file_override(&scenario, &load(&scenario, None, &set)?) {
                set.push(o);
            }
            let start = std::time::Instant::now();
            let rows = granular::run::sweep::run_sweep(&dir, &text, &set, threads, &|name, s| {
                eprintln!(
                    "{name}: {} collisions in {:.2} s, stopped by {}",
                    s.collisions, s.wall_seconds, s.stop_reason
                );
            })
            .map_err(|e| format!("{}: {e}", scenario.display()))?;
            let observable = load(&scenario, None, &set)?
                .sweep
                .map(|s| s.observable)
                .unwrap_or_default();
            println!("value,{observable}_mean,{observable}_stderr");
            for r in &rows {
                if let Some((_, m, e, _)) = r.observables.iter().find(|o| o.0 == observable) {
                    println!("{},{m},{e}", r.value);
                }
            }
            eprintln!(
                "{}: {} points in {:.1} s; table in {}",
                dir.display(),
                rows.len(),
                start.elapsed().as_secs_f64(),
                dir.join("sweep.csv").display()
            );
            Ok(())
        }
    }
}

fn finish(mut run: Run, dir: &Path, quiet: bool) -> Result<(), CliError> {
    let interrupt = interrupt::Interrupt::install();
    run.interrupt_when(interrupt.check());
    let elastic = run.scenario().collisions.law().is_elastic();
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
    let result = run.run_to_end(&mut on_progress, None);
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
