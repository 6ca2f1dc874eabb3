//! `granular bench`: collisions per second on standard cases, from equilibrated states.

use clap::Subcommand;
use granular::edmd::bench::{FluidCase, advance_collisions, fluid};
use granular::engine::Engine;
use std::time::Instant;

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Gillespie intruder engine: collisions per second on one core.
    Intruder {
        /// Only this case (1d-gaussian, 1d-power-law, needle, 1d-gaussian-direct, needle-paper).
        #[arg(long)]
        case: Option<String>,
        /// Collisions per case.
        #[arg(long, default_value_t = 5_000_000)]
        collisions: u64,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
    /// DSMC engine: 2D and 3D at N = 10^5, 10^6, 10^7, with 1 and 2 threads.
    Dsmc {
        /// Only this dimension (2 or 3).
        #[arg(long)]
        dimension: Option<usize>,
        /// Only this number of particles (at least 16; `1e6` is read as 1000000).
        #[arg(long, value_parser = parse_count)]
        n: Option<usize>,
        /// Only this number of threads.
        #[arg(long)]
        threads: Option<usize>,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
    /// DSMC split over the ranks of `mpirun` (the `mpi` build): strong scaling (fixed N,
    /// by default the DSMC seed's Fig. 1 case: 2D, N = 500 000, packing fraction 0.1,
    /// periodic, about 10 grains per cell) or weak scaling (`--n-per-rank`), with every
    /// rank's particle-steps per second, compute and communication time, bytes and calls
    /// per step.
    #[cfg(feature = "mpi")]
    DsmcRanks(crate::bench_ranks::DsmcRanksArgs),
    /// Event-driven engine: elastic grains in a periodic box (or walls, inelastic
    /// collisions, two kinds of grains), collisions per CPU second.
    Edmd {
        /// Only this dimension (2 or 3).
        #[arg(long)]
        dimension: Option<usize>,
        /// Only this number of grains (at least 16; `1e6` is read as 1000000).
        #[arg(long, value_parser = parse_count)]
        n: Option<usize>,
        /// Only this packing fraction.
        #[arg(long)]
        packing_fraction: Option<f64>,
        /// Collisions per grain to measure over (after equilibration).
        #[arg(long, default_value_t = 50.0)]
        collisions_per_particle: f64,
        /// Hard walls on every face instead of a periodic box.
        #[arg(long)]
        walls: bool,
        /// Restitution of pair and wall collisions, in [0, 1]; below 1 with the TC model
        /// (contact duration 10^-3 mean free times).
        #[arg(long, default_value_t = 1.0)]
        restitution: f64,
        /// Radius of half of the grains over the other half's (a 50:50 size mixture).
        #[arg(long, default_value_t = 1.0)]
        size_ratio: f64,
        /// Mass of half of the grains over the other half's (a 50:50 mass mixture).
        #[arg(long, default_value_t = 1.0)]
        mass_ratio: f64,
        /// Gravity along the last axis, downwards (needs --walls).
        #[arg(long, default_value_t = 0.0)]
        gravity: f64,
        /// One JSON object per case on standard output.
        #[arg(long)]
        json: bool,
    },
}

/// The standard cases of the engine-performance issue: (dimension, N, packing fraction,
/// collisions per CPU second of the fastest public event-driven code on this machine kind,
/// Smallenburg, Eur. Phys. J. E 45, 22 (2022), and its 2D port).
const CASES: &[(usize, usize, f64, f64)] = &[
    (2, 10_000, 0.7, 1.3e6),
    (2, 100_000, 0.7, 5.0e5),
    (2, 1_000_000, 0.7, 3.5e5),
    (2, 10_000, 0.2, 5.2e5),
    (3, 100_000, 0.45, 2.6e5),
    (3, 1_000_000, 0.45, 1.8e5),
];

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

/// Fewest grains of a bench case: fewer give too few collisions to measure (one grain
/// in a periodic box never collides).
pub(crate) const MIN_GRAINS: usize = 16;

/// Peak bytes per grain of the event-driven bench (set-up included; about 300 measured
/// for 10^5 grains in 3D), for the memory check before allocating.
const EDMD_BYTES_PER_GRAIN: f64 = 400.0;

/// Peak bytes per particle of the DSMC bench (positions, velocities, cells, sort buffers).
const DSMC_BYTES_PER_PARTICLE: f64 = 300.0;

/// The memory the system can give without swapping (`MemAvailable`), where it says.
fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Refuses `--n n` when `n` grains at `bytes_per` bytes each would not fit in memory.
pub(crate) fn check_memory(n: usize, bytes_per: f64) -> Result<(), String> {
    let need = n as f64 * bytes_per;
    if let Some(have) = available_memory()
        && need > 0.8 * have
    {
        return Err(format!(
            "--n {n}: the case would need about {:.3} GB of memory and {:.3} GB are available; \
             give a smaller --n (at most about {:.0})",
            need / 1e9,
            have / 1e9,
            (0.8 * have / bytes_per).floor()
        ));
    }
    Ok(())
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
        if n < MIN_GRAINS {
            return Err(format!(
                "--n {n}: give at least {MIN_GRAINS} grains (fewer collide too rarely to measure)"
            ));
        }
        check_memory(n, EDMD_BYTES_PER_GRAIN)?;
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

/// CPU time of the calling thread, in seconds: benchmarks report rates per CPU second, so
/// that other processes on a shared machine do not count against the engine.
fn thread_cpu_seconds() -> f64 {
    cpu_time::ThreadTime::try_now()
        .map(|t| t.as_duration().as_secs_f64())
        .unwrap_or(f64::NAN)
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
                None => granular::intruder::bench::CASES
                    .iter()
                    .map(|c| c.to_string())
                    .collect(),
            };
            for c in cases {
                let r = granular::intruder::bench::measure_collision_rate(&c, collisions, 1)?;
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
            json,
        } => {
            if let Some(d) = dimension
                && d != 2
                && d != 3
            {
                return Err(format!("--dimension {d}: use 2 or 3"));
            }
            if let Some(n) = n {
                if n < MIN_GRAINS {
                    return Err(format!("--n {n}: give at least {MIN_GRAINS} particles"));
                }
                check_memory(n, DSMC_BYTES_PER_PARTICLE)?;
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
            let dims: Vec<usize> = dimension.map_or(vec![2, 3], |d| vec![d]);
            let ns: Vec<usize> = n.map_or(vec![100_000, 1_000_000, 10_000_000], |n| vec![n]);
            let ts: Vec<usize> = threads.map_or(vec![1, 2], |t| vec![t]);
            for &d in &dims {
                for &n in &ns {
                    for &t in &ts {
                        let r =
                            granular::dsmc::bench::measure(d, n, t).map_err(|e| e.to_string())?;
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
                }
            }
            Ok(())
        }
        #[cfg(feature = "mpi")]
        BenchCommand::DsmcRanks(args) => crate::bench_ranks::run(args),
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
            json,
        } => {
            check_edmd_flags(dimension, n, packing_fraction, collisions_per_particle)?;
            if !(0.0..=1.0).contains(&restitution) {
                return Err(format!(
                    "--restitution {restitution}: the restitution must lie in [0, 1] (1: elastic)"
                ));
            }
            if !(gravity.is_finite() && gravity >= 0.0) {
                return Err(format!(
                    "--gravity {gravity}: give the magnitude, a number >= 0 (it points down the last axis)"
                ));
            }
            if gravity > 0.0 && !walls {
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
            let mut cases: Vec<(usize, usize, f64, f64)> = CASES
                .iter()
                .copied()
                .filter(|c| dimension.is_none_or(|d| d == c.0))
                .filter(|c| n.is_none_or(|n| n == c.1))
                .filter(|c| packing_fraction.is_none_or(|p| (p - c.2).abs() < 1e-9))
                .collect();
            if cases.is_empty() {
                // A case outside the table: run exactly what was asked.
                cases.push((
                    dimension.unwrap_or(2),
                    n.unwrap_or(10_000),
                    packing_fraction.unwrap_or(0.5),
                    f64::NAN,
                ));
            }
            for (d, n, phi, reference) in cases {
                let fluid_case = FluidCase {
                    walls,
                    restitution,
                    size_ratio,
                    mass_ratio,
                    gravity,
                    ..FluidCase::standard(n, phi)
                };
                let mut r = match d {
                    2 => case::<2>(&fluid_case, collisions_per_particle),
                    3 => case::<3>(&fluid_case, collisions_per_particle),
                    _ => return Err(format!("--dimension {d}: use 2 or 3")),
                }?;
                // The reference figures are for the standard case only.
                let reference = if fluid_case.is_standard() {
                    reference
                } else {
                    f64::NAN
                };
                if reference.is_finite() {
                    r["reference_collisions_per_second"] = reference.into();
                }
                if json {
                    println!("{}", serde_json::to_string(&r).unwrap_or_default());
                } else {
                    println!(
                        "edmd {}D N = {:>8} phi = {:.2}{}: {:.3e} collisions/s, {:.3e} events/s (per CPU second), {:.0} bytes/particle{} (setup {:.1} s)",
                        r["dimension"],
                        r["n"],
                        r["packing_fraction"].as_f64().unwrap_or(0.0),
                        describe(&fluid_case),
                        r["collisions_per_second"].as_f64().unwrap_or(0.0),
                        r["events_per_second"].as_f64().unwrap_or(0.0),
                        r["bytes_per_particle"].as_f64().unwrap_or(0.0),
                        if reference.is_finite() {
                            format!(", reference {reference:.1e}")
                        } else {
                            String::new()
                        },
                        r["setup_seconds"].as_f64().unwrap_or(0.0)
                    );
                }
            }
            Ok(())
        }
    }
}

/// Times one case from the library's equilibrated fluid (`granular::edmd::bench`).
fn case<const D: usize>(c: &FluidCase, cpp: f64) -> Result<serde_json::Value, String> {
    let (n, phi) = (c.n, c.packing_fraction);
    let setup = Instant::now();
    let mut e = fluid::<D>(c, 2024).map_err(|e| e.to_string())?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let (c0, ev0) = (e.collisions(), e.events());
    let start = Instant::now();
    let cpu_start = thread_cpu_seconds();
    advance_collisions(&mut e, (cpp * n as f64 / 2.0) as u64).map_err(|e| e.to_string())?;
    let cpu = thread_cpu_seconds() - cpu_start;
    let wall = start.elapsed().as_secs_f64();
    // Rates per CPU second (per wall second where the CPU clock is unavailable).
    let secs = if cpu.is_finite() && cpu > 0.0 {
        cpu
    } else {
        wall
    };
    let collisions = e.collisions() - c0;
    let events = e.events() - ev0;
    Ok(serde_json::json!({
        "engine": "edmd",
        "dimension": D,
        "n": n,
        "packing_fraction": phi,
        "collisions": collisions,
        "seconds": wall,
        "cpu_seconds": cpu,
        "collisions_per_second": collisions as f64 / secs,
        "events_per_second": events as f64 / secs,
        "bytes_per_particle": e.memory_bytes() as f64 / n as f64,
        "walls": c.walls,
        "restitution": c.restitution,
        "size_ratio": c.size_ratio,
        "mass_ratio": c.mass_ratio,
        "gravity": c.gravity,
        "setup_seconds": setup_seconds,
        "threads": 1,
    }))
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
    out
}
