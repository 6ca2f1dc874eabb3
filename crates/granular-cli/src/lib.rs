//! `granular`: the command line over the granular library, as a library: the binary
//! (`src/main.rs`) and the Python package (`python -m granular`) call [`main_with_args`].
//!
//! A thin layer: it parses arguments, turns scenario files into runs, shows progress on a
//! terminal, and reports errors (through `miette`). All physics and file formats live in
//! the library, the figures in `granular-report`.

mod args;
mod bench;
mod error;
mod interrupt;
mod intruder_summary;
mod launch;
#[cfg(feature = "mpi")]
mod ranks;
mod sweep;

use clap::{Parser, Subcommand};
use error::CliError;
use granular::run::{DirectoryState, MemoryBudget, Run, RunDir};
use granular::scenario::Scenario;
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
        /// Run even above the pre-flight cost limits (outputs, collisions, bytes; see
        /// `granular check` and docs/scenario.md, "Limits").
        #[arg(long)]
        insist: bool,
        /// Worker threads of this process (default: the cores, shared among the MPI ranks
        /// on this node); results do not depend on it.
        #[arg(long, allow_hyphen_values = true, value_parser = args::threads)]
        threads: Option<usize>,
    },
    /// Validate a scenario, print it fully resolved and estimate what the run will cost.
    Check {
        /// Scenario file.
        scenario: PathBuf,
        /// Override a scenario key (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Accept a scenario above the pre-flight cost limits (as `run --insist` would).
        #[arg(long)]
        insist: bool,
    },
    /// Run a scenario's `[sweep]`: every value of a key, several seeds each, in parallel.
    Sweep {
        /// Scenario file with a `[sweep]` table.
        scenario: PathBuf,
        /// Sweep directory (default: `runs/<scenario name>`); finished members are kept.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads, 1 to the number of cores (default: all cores).
        #[arg(long, allow_hyphen_values = true, value_parser = args::threads)]
        threads: Option<usize>,
        /// Override a scenario key for every member (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Run only share I of N of the members (1 <= I <= N; default: GRANULAR_SHARD or
        /// a Slurm job array's SLURM_ARRAY_TASK_ID/COUNT, else all); then `granular merge DIR`.
        #[arg(long, value_name = "I/N", value_parser = parse_shard)]
        shard: Option<granular::run::sweep::Shard>,
        /// Run even when the scenario or a point of its sweep is above the pre-flight cost
        /// limits (as `run --insist`; docs/scenario.md, "Limits").
        #[arg(long)]
        insist: bool,
    },
    /// Build sweep.csv and sweep.json of a sweep directory from its finished members
    /// (after the shards of `granular sweep --shard I/N`).
    Merge {
        /// Sweep directory (the --out of `granular sweep`).
        dir: PathBuf,
        /// Write the table from the members that have finished, listing the others in
        /// sweep.json (default: refuse, listing them).
        #[arg(long)]
        allow_missing: bool,
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
    /// The speed-up of decomposed DSMC, measured (`mpirun -n K granular bench dsmc-ranks
    /// --csv FILE`) and modelled up to 1024 ranks: a figure like Fig. 1 of Müller & Herrmann's DSMC paper and
    /// the model's tables (see docs/performance.md).
    Scaling {
        /// The benchmark's CSV (strong-scaling rows on 1 and 2 ranks at least).
        bench: PathBuf,
        /// Directory for dsmc_speedup.png/.svg, scaling_model.csv and scaling_model.json.
        #[arg(long)]
        out: PathBuf,
        /// Assumed network latency per message, microseconds (0 or more).
        #[arg(long, default_value_t = 2.0, allow_hyphen_values = true, value_parser = args::number)]
        latency_us: f64,
        /// Assumed network bandwidth per rank, GB/s (10^9 bytes per second; above 0).
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = args::number)]
        bandwidth_gbs: f64,
        /// Compute nanoseconds per particle-step instead of the measured one (for a
        /// prediction on another machine; above 0).
        #[arg(long, allow_hyphen_values = true, value_parser = args::number)]
        compute_ns: Option<f64>,
    },
    /// Write the snapshots of a run directory as trajectories for OVITO, ParaView, ASE,
    /// LAMMPS and HOOMD tools (into RUN/trajectory/).
    Export {
        /// Run directory.
        run: PathBuf,
        /// Formats: xyz, lammps, gsd, vtk (repeatable, or a comma-separated list).
        #[arg(long, required = true, value_delimiter = ',', value_parser = parse_format)]
        format: Vec<granular::trajectory::Format>,
    },
    /// Continue an interrupted run from its last checkpoint.
    Resume {
        /// Run directory.
        dir: PathBuf,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
        /// Worker threads of this process (default: the cores, shared among the MPI ranks
        /// on this node); results do not depend on it.
        #[arg(long, allow_hyphen_values = true, value_parser = args::threads)]
        threads: Option<usize>,
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
    /// Figures to make: fig1 fig2 fig3 fig4 fig5 fig7 fig8 (the intruder paper), fig3d fig4d
    /// (its Figs. 3 and 4 for disks and spheres), or all.
    #[arg(required = true, value_name = "FIGURE")]
    figures: Vec<String>,
    /// Output directory (created).
    #[arg(long, default_value = "figures/intruder")]
    out: PathBuf,
    /// Ten times fewer collisions than the paper (for tests and previews).
    #[arg(long)]
    quick: bool,
    /// Worker threads, 1 to the number of cores (default: all cores); results do not depend on it.
    #[arg(long, allow_hyphen_values = true, value_parser = args::threads)]
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
        .map_err(|_| format!("{} (got `{s}`)", granular::scenario::SEED_HELP))
}

/// `--format`: a trajectory format name.
fn parse_format(s: &str) -> Result<granular::trajectory::Format, String> {
    granular::trajectory::Format::parse(s)
}

/// The values the scenario leaves to the engine, as the scenario resolves them (intruder
/// `sample_interval`, `transient`, `histogram_max`; DSMC `time_step` and `cell_size`; the
/// steady state of `[driving]`), at the initial temperature its velocities describe
/// (`Scenario::resolve`; no engine is built).
fn automatic_values(sc: &Scenario) -> Vec<(String, f64)> {
    use granular::driving::Driving;
    use granular::scenario::EngineKind;
    if sc.kind() == EngineKind::Intruder {
        return granular::run::intruder::automatic_values(sc);
    }
    let resolved = sc.resolve();
    let Some(g) = resolved.grains else {
        return Vec::new();
    };
    let mut out = Vec::new();
    if let Some(d) = &g.dsmc {
        if sc.dsmc().is_some_and(|s| s.time_step.is_none()) {
            out.push((
                "dsmc.time_step (initial; it follows the mean free time)".to_string(),
                d.time_step,
            ));
        }
        if sc.dsmc().is_some_and(|s| s.cell_size.is_none()) {
            out.push((
                "dsmc.cell_size (cell edge along x)".to_string(),
                d.cell_edges.first().copied().unwrap_or(d.cell_size),
            ));
        }
    }
    if let Some(state) = &g.driving {
        match state.driving {
            Driving::Rescale { temperature } => {
                if sc
                    .driving()
                    .as_ref()
                    .is_some_and(|d| d.temperature.is_none())
                {
                    out.push((
                        "driving.temperature (the initial temperature)".into(),
                        temperature,
                    ));
                }
                let what = if g.rough.is_some() {
                    "steady a2 (rough grains' Sonine a20, RS-8)"
                } else {
                    "steady a2 (Sonine, HCS second estimate)"
                };
                out.push((what.into(), state.a2));
            }
            Driving::WhiteNoise { .. } => {
                let (a2, temperature) = if g.rough.is_some() {
                    (
                        "steady a2 (rough grains' Sonine a20, RS-9)",
                        "steady translational temperature (rough grains' energy balance, RS-6)",
                    )
                } else {
                    (
                        "steady a2 (Sonine, heated gas)",
                        "steady temperature (energy balance, Sonine loss rate)",
                    )
                };
                out.push((a2.into(), state.a2));
                out.push((temperature.into(), state.temperature));
            }
        }
    }
    out
}

/// `runs/<scenario file stem>`.
fn default_dir(scenario: &Path) -> PathBuf {
    PathBuf::from("runs").join(
        scenario
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().to_string()),
    )
}

/// The text of the scenario file at `path` (a special file, a directory or a file of more
/// than `granular::scenario::MAX_FILE_BYTES` refused before reading).
fn read_scenario(path: &Path) -> Result<String, String> {
    granular::scenario::read_text_file(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::InvalidInput | std::io::ErrorKind::InvalidData => e.to_string(),
        _ => format!("{}: {e}", path.display()),
    })
}

/// The scenario at `path` with its overrides; `insist`: without the cost limits.
fn load_with(
    path: &Path,
    seed: Option<u64>,
    set: &[String],
    insist: bool,
) -> Result<Scenario, CliError> {
    let text = read_scenario(path)?;
    let mut overrides = set.to_vec();
    if let Some(s) = seed {
        // A string: TOML integers stop at i64::MAX, seeds at u64::MAX.
        overrides.push(format!("seed=\"{s}\""));
    }
    let base = path.parent();
    let read = |o: &[String]| {
        granular::scenario::ScenarioInput {
            text: &text,
            overrides: o,
            base,
            limits: !insist,
            ..Default::default()
        }
        .read()
    };
    let mut sc = read(&overrides).map_err(|e| CliError::scenario(path, &text, &overrides, e))?;
    let absolute = granular::scenario::file_overrides(path, &sc);
    if !absolute.is_empty() {
        overrides.extend(absolute);
        sc = read(&overrides).map_err(|e| CliError::scenario(path, &text, &overrides, e))?;
    }
    Ok(sc)
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
            insist,
            threads,
        } => {
            let sc = load_with(&scenario, seed, &set, insist)?;
            let dir = out.unwrap_or_else(|| default_dir(&scenario));
            if let DirectoryState::Run { finished } = RunDir::new(&dir).state()
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
            launch::launch(&dir, quiet, threads, |mine, _, comm, ranks_on_node| {
                // Each rank creates only its own grains; a DSMC run whose most loaded rank
                // would not fit in its share of this node's memory is refused (not with
                // --insist).
                let memory = (!insist).then(|| MemoryBudget::this_node(ranks_on_node));
                Run::create_on(mine, sc, comm, &dir, memory).map_err(|e| e.to_string())
            })
        }
        Command::Export { run, format } => {
            let mut formats = format;
            formats.dedup();
            let files = RunDir::new(&run)
                .export_trajectories(&formats)
                .map_err(|e| e.to_string())?;
            for f in files {
                println!("{}", f.display());
            }
            Ok(())
        }
        Command::Check {
            scenario,
            set,
            insist,
        } => {
            let sc = load_with(&scenario, None, &set, insist)?;
            print!("{}", sc.to_toml());
            let automatic = automatic_values(&sc);
            if !automatic.is_empty() {
                println!("\n# Values left to the engine, as the scenario resolves them:");
                for (key, value) in automatic {
                    println!("# {key} = {value}");
                }
            }
            let cost = sc.cost();
            for line in cost.lines() {
                eprintln!("estimate: {line}");
            }
            if let Some(w) = cost.warning(&sc) {
                eprintln!("warning: {w}");
            }
            if let Err(e) = cost.check_limits() {
                eprintln!("above the limits, accepted by --insist: {e}");
            }
            match &sc.intruder() {
                Some(i) => eprintln!(
                    "{}: valid (intruder engine, model {})",
                    scenario.display(),
                    i.model()
                ),
                None => eprintln!(
                    "{}: valid ({} grains, {} species)",
                    scenario.display(),
                    sc.particle_count(),
                    sc.species().len()
                ),
            }
            Ok(())
        }
        Command::Resume {
            dir,
            quiet,
            threads,
        } => launch::launch(&dir, quiet, threads, |mine, rank, comm, _| {
            if rank != 0 {
                launch::ranks_copy(&dir, mine)?;
            }
            match comm {
                // Each rank reads only the checkpoint parts of its slab.
                Some(comm) => Run::resume_decomposed(mine, &dir, comm),
                None => Run::resume(mine),
            }
            .map_err(|e| e.to_string())
        }),
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
                threads: launch::worker_threads(args.threads)?,
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
        Command::Scaling {
            bench,
            out,
            latency_us,
            bandwidth_gbs,
            compute_ns,
        } => {
            if let Some(c) = compute_ns
                && !(c.is_finite() && c > 0.0)
            {
                return Err(format!("--compute-ns {c}: give a number > 0, e.g. 30").into());
            }
            if !(latency_us.is_finite() && latency_us >= 0.0) {
                return Err(
                    format!("--latency-us {latency_us}: give a number >= 0, e.g. 2").into(),
                );
            }
            if !(bandwidth_gbs.is_finite() && bandwidth_gbs > 0.0) {
                return Err(
                    format!("--bandwidth-gbs {bandwidth_gbs}: give a number > 0, e.g. 1").into(),
                );
            }
            let net = granular_report::scaling::model::Network {
                latency: latency_us * 1e-6,
                bandwidth: bandwidth_gbs * 1e9,
            };
            let (files, summary) =
                granular_report::scaling::scaling(&bench, &out, net, compute_ns.map(|c| c * 1e-9))?;
            print!("{summary}");
            for f in &files {
                println!("{}", f.display());
            }
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
            shard,
            insist,
        } => {
            let threads = launch::worker_threads(threads)?;
            let text = read_scenario(&scenario)?;
            let dir = out.unwrap_or_else(|| default_dir(&scenario));
            let mut set = set;
            let base = load_with(&scenario, None, &set, insist)?;
            set.extend(granular::scenario::file_overrides(&scenario, &base));
            let args = sweep::SweepArgs {
                scenario: &scenario,
                text: &text,
                dir: &dir,
                set: &set,
                threads,
                shard,
                insist,
                observable: base.sweep.map(|s| s.observable).unwrap_or_default(),
            };
            launch::sweep_on_ranks(&args)
        }
        Command::Merge { dir, allow_missing } => sweep::merge(&dir, allow_missing),
    }
}

/// `--shard I/N`.
fn parse_shard(text: &str) -> Result<granular::run::sweep::Shard, String> {
    text.parse()
}
