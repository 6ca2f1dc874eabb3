//! `granular bench`: collisions per second on standard cases, from equilibrated states.
//! The measurements are the library's (`granular::bench`); this module checks the flags
//! and formats the results (a line per case, or `--json` one object per case).

#[cfg(feature = "mpi")]
mod ranks;

use clap::Subcommand;
use granular::bench::edmd::FluidCase;
use granular::bench::{self as lib, MemoryShortfall};

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Gillespie intruder engine: collisions per second on one core.
    Intruder {
        /// Only this case (1d-gaussian, 1d-power-law, needle, 1d-gaussian-direct, needle-paper).
        #[arg(long)]
        case: Option<String>,
        /// Collisions per case (1 or more; `1e6` is read as 1000000).
        #[arg(long, default_value_t = 5_000_000, allow_hyphen_values = true, value_parser = crate::args::count)]
        collisions: u64,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
    /// DSMC engine: 2D and 3D at N = 10^5, 10^6, 10^7, with 1 and 2 threads.
    Dsmc {
        /// Only this dimension (2 or 3).
        #[arg(long, allow_hyphen_values = true, value_parser = crate::args::dimension)]
        dimension: Option<usize>,
        /// Only this number of particles (at least 16; `1e6` is read as 1000000).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
        n: Option<usize>,
        /// Only this number of threads (1 to four times the cores).
        #[arg(long, allow_hyphen_values = true, value_parser = crate::args::threads)]
        threads: Option<usize>,
        /// Tangential restitution of pair collisions, in [-1, 1]: above -1 the grains are
        /// rough and spin (docs/rough.md); -1 smooth.
        #[arg(long, default_value_t = -1.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        tangential_restitution: f64,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
    /// DSMC split over the ranks of `mpirun` (the `mpi` build): strong scaling (fixed N,
    /// by default the case of Fig. 1 of Müller & Herrmann's DSMC paper: 2D, N = 500 000, packing fraction 0.1,
    /// periodic, about 10 grains per cell) or weak scaling (`--n-per-rank`), with every
    /// rank's particle-steps per second, compute and communication time, bytes and calls
    /// per step.
    #[cfg(feature = "mpi")]
    DsmcRanks(ranks::DsmcRanksArgs),
    /// Event-driven engine: elastic grains in a periodic box (or walls, inelastic
    /// collisions, two kinds of grains), collisions per CPU second.
    Edmd {
        /// Only this dimension (2 or 3).
        #[arg(long, allow_hyphen_values = true, value_parser = crate::args::dimension)]
        dimension: Option<usize>,
        /// Only this number of grains (at least 16; `1e6` is read as 1000000).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
        n: Option<usize>,
        /// Only this packing fraction (above 0; at most 0.78 in 2D, 0.52 in 3D).
        #[arg(long, allow_hyphen_values = true, value_parser = crate::args::number)]
        packing_fraction: Option<f64>,
        /// Collisions per grain to measure over (after equilibration; above 0).
        #[arg(long, default_value_t = 50.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        collisions_per_particle: f64,
        /// Hard walls on every face instead of a periodic box.
        #[arg(long)]
        walls: bool,
        /// Restitution of pair and wall collisions, in [0, 1]; below 1 with the TC model
        /// (contact duration 10^-3 mean free times).
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        restitution: f64,
        /// Radius of half of the grains over the other half's (a 50:50 size mixture; above 0).
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        size_ratio: f64,
        /// Mass of half of the grains over the other half's (a 50:50 mass mixture; above 0).
        #[arg(long, default_value_t = 1.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        mass_ratio: f64,
        /// Gravity along the last axis (needs --walls): positive pulls the grains down the
        /// axis, towards its wall at 0, negative up, towards the other.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        gravity: f64,
        /// Tangential restitution of pair collisions, in [-1, 1]: above -1 the grains are
        /// rough and spin (docs/rough.md); -1 smooth.
        #[arg(long, default_value_t = -1.0, allow_hyphen_values = true, value_parser = crate::args::number)]
        tangential_restitution: f64,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
}

/// `--n`: a whole number, also written as `1e6`.
pub(crate) fn parse_count(s: &str) -> Result<usize, String> {
    if let Ok(n) = s.trim().parse::<usize>() {
        return Ok(n);
    }
    match s.trim().parse::<f64>() {
        Ok(x) if x >= 0.0 && x.fract() == 0.0 && x < usize::MAX as f64 => Ok(x as usize),
        _ => Err(format!(
            "a number of grains is a whole number, e.g. 10000 or 1e6 (got `{s}`)"
        )),
    }
}

/// Refuses `--n n` when `n` grains at `bytes_per` bytes each would not fit in memory.
fn check_memory(n: usize, bytes_per: f64) -> Result<(), String> {
    lib::check_memory(n, bytes_per).map_err(
        |MemoryShortfall {
             need,
             available,
             max_grains,
         }| {
            format!(
                "--n {n}: the case would need about {:.3} GB of memory and {:.3} GB are \
                 available; give a smaller --n (at most about {max_grains:.0})",
                need / 1e9,
                available / 1e9,
            )
        },
    )
}

/// The flags of `bench edmd` checked before anything is allocated: the accepted ranges are
/// named in the errors.
fn check_edmd_flags(
    dimension: Option<usize>,
    n: Option<usize>,
    packing_fraction: Option<f64>,
    collisions_per_particle: f64,
) -> Result<(), String> {
    if let Some(d) = dimension
        && d != 2
        && d != 3
    {
        return Err(format!("--dimension {d}: use 2 or 3"));
    }
    if let Some(n) = n {
        if n < lib::MIN_GRAINS {
            return Err(format!(
                "--n {n}: give at least {} grains (fewer collide too rarely to measure)",
                lib::MIN_GRAINS
            ));
        }
        check_memory(n, lib::edmd::BYTES_PER_GRAIN)?;
    }
    if let Some(phi) = packing_fraction {
        // Below the densest lattice the set-up places grains on (square: pi/4; simple
        // cubic: pi/6); denser states would need a compression that may never end.
        let max = match dimension {
            Some(3) => 0.52,
            _ => 0.78,
        };
        if !(phi > 0.0 && phi <= max) {
            return Err(format!(
                "--packing-fraction {phi}: give a packing fraction in (0, {max}] for {}D \
                 (0.52 in 3D, 0.78 in 2D)",
                dimension.unwrap_or(2)
            ));
        }
    }
    if !(collisions_per_particle.is_finite() && collisions_per_particle > 0.0) {
        return Err(format!(
            "--collisions-per-particle {collisions_per_particle}: give a positive number, e.g. 50"
        ));
    }
    Ok(())
}

pub fn run(cmd: BenchCommand) -> Result<(), String> {
    match cmd {
        BenchCommand::Intruder {
            case,
            collisions,
            json,
        } => {
            let cases: Vec<String> = match case {
                Some(c) => vec![c],
                None => lib::intruder::CASES.iter().map(|c| c.to_string()).collect(),
            };
            for c in cases {
                let r = lib::intruder::measure_collision_rate(&c, collisions, 1)
                    .map_err(|e| e.to_string())?;
                if json {
                    println!("{}", serde_json::to_string(&r).unwrap_or_default());
                } else {
                    println!(
                        "intruder {:<20} {:.3e} collisions/s ({} collisions in {:.2} s)",
                        r.case, r.collisions_per_second, r.collisions, r.seconds
                    );
                }
            }
            Ok(())
        }
        BenchCommand::Dsmc {
            dimension,
            n,
            threads,
            tangential_restitution,
            json,
        } => {
            if !(-1.0..=1.0).contains(&tangential_restitution) {
                return Err(format!(
                    "--tangential-restitution {tangential_restitution}: give β in [-1, 1] (-1: smooth grains)"
                ));
            }
            if let Some(d) = dimension
                && d != 2
                && d != 3
            {
                return Err(format!("--dimension {d}: use 2 or 3"));
            }
            if let Some(n) = n {
                if n < lib::MIN_GRAINS {
                    return Err(format!(
                        "--n {n}: give at least {} particles",
                        lib::MIN_GRAINS
                    ));
                }
                check_memory(n, lib::dsmc::BYTES_PER_PARTICLE)?;
            }
            let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
            if let Some(t) = threads
                && (t == 0 || t > 4 * cores)
            {
                return Err(format!(
                    "--threads {t}: give 1 to {} worker threads (this machine has {cores} cores)",
                    4 * cores
                ));
            }
            for (d, n, t) in lib::dsmc::cases(dimension, n, threads) {
                let r = lib::dsmc::measure_rough(d, n, t, tangential_restitution)
                    .map_err(|e| e.to_string())?;
                if json {
                    println!("{}", serde_json::to_string(&r).unwrap_or_default());
                } else {
                    println!(
                        "dsmc {}D N = {:>9} threads = {}: {:.3e} particle-steps/s, {:.3e} collisions/s ({:.3} collisions per particle-step)",
                        r.dimension,
                        r.n,
                        r.threads,
                        r.particle_steps_per_second,
                        r.collisions_per_second,
                        r.collisions_per_particle_step
                    );
                }
            }
            Ok(())
        }
        #[cfg(feature = "mpi")]
        BenchCommand::DsmcRanks(args) => ranks::run(args),
        BenchCommand::Edmd {
            dimension,
            n,
            packing_fraction,
            collisions_per_particle,
            walls,
            restitution,
            size_ratio,
            mass_ratio,
            gravity,
            tangential_restitution,
            json,
        } => {
            check_edmd_flags(dimension, n, packing_fraction, collisions_per_particle)?;
            if !(0.0..=1.0).contains(&restitution) {
                return Err(format!(
                    "--restitution {restitution}: the restitution must lie in [0, 1] (1: elastic)"
                ));
            }
            if !(-1.0..=1.0).contains(&tangential_restitution) {
                return Err(format!(
                    "--tangential-restitution {tangential_restitution}: it must lie in [-1, 1] (-1: smooth grains, 1: perfectly rough)"
                ));
            }
            if !gravity.is_finite() {
                return Err(format!(
                    "--gravity {gravity}: give a finite acceleration (positive: down the last axis; negative: up)"
                ));
            }
            if gravity != 0.0 && !walls {
                return Err(format!(
                    "--gravity {gravity} needs --walls: in a periodic box the grains would fall forever"
                ));
            }
            for (flag, value) in [("--size-ratio", size_ratio), ("--mass-ratio", mass_ratio)] {
                if !(value.is_finite() && value > 0.0) {
                    return Err(format!(
                        "{flag} {value}: give a positive ratio (1: one kind of grain)"
                    ));
                }
            }
            for case in lib::edmd::select_cases(dimension, n, packing_fraction) {
                let fluid_case = FluidCase {
                    walls,
                    restitution,
                    size_ratio,
                    mass_ratio,
                    gravity,
                    tangential_restitution,
                    ..FluidCase::standard(case.n, case.packing_fraction)
                };
                let r = lib::edmd::measure(
                    case.dimension,
                    &fluid_case,
                    collisions_per_particle,
                    case.reference,
                )
                .map_err(|e| e.to_string())?;
                if json {
                    // Through a JSON value: one object with its keys in order, as always.
                    let value = serde_json::to_value(&r).unwrap_or_default();
                    println!("{}", serde_json::to_string(&value).unwrap_or_default());
                } else {
                    println!(
                        "edmd {}D N = {} phi = {:.2}{}: {:.3e} collisions/s, {:.3e} events/s (per CPU second), {:.0} bytes/particle{} (setup {:.1} s)",
                        r.dimension,
                        r.n,
                        r.packing_fraction,
                        describe(&fluid_case),
                        r.collisions_per_second,
                        r.events_per_second,
                        r.bytes_per_particle,
                        match r.reference_collisions_per_second {
                            Some(reference) => format!(", reference {reference:.1e}"),
                            None => String::new(),
                        },
                        r.setup_seconds
                    );
                }
            }
            Ok(())
        }
    }
}

/// What sets a case apart from the standard one, for the text output (empty for it).
fn describe(c: &FluidCase) -> String {
    let mut out = String::new();
    if c.walls {
        out.push_str(", walls");
    }
    if c.restitution != 1.0 {
        out.push_str(&format!(", restitution {} (TC)", c.restitution));
    }
    if c.size_ratio != 1.0 {
        out.push_str(&format!(", size ratio {}", c.size_ratio));
    }
    if c.mass_ratio != 1.0 {
        out.push_str(&format!(", mass ratio {}", c.mass_ratio));
    }
    if c.gravity != 0.0 {
        out.push_str(&format!(", gravity {}", c.gravity));
    }
    if c.tangential_restitution != -1.0 {
        out.push_str(&format!(", rough β = {}", c.tangential_restitution));
    }
    out
}
