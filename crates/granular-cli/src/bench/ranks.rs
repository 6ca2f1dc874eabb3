//! `mpirun -n K granular bench dsmc-ranks` (the `mpi` build): DSMC split over the ranks,
//! strong scaling (fixed total N, by default the case of Fig. 1 of Müller & Herrmann's DSMC paper) or weak scaling
//! (fixed N per rank), with every rank's compute and communication time and traffic. A
//! readable table on standard output, `--json` one object, `--csv FILE` one row per rank
//! appended to FILE (what `granular scaling` reads).

use granular::bench as lib;
use granular::bench::dsmc::{DecomposedResult, RankResult};
use std::io::Write;
use std::path::PathBuf;

/// Flags of `bench dsmc-ranks`.
#[derive(clap::Args, Debug)]
pub struct DsmcRanksArgs {
    /// Dimension (2 or 3).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true, value_parser = crate::args::dimension)]
    pub dimension: usize,
    /// Number of particles on all ranks together: strong scaling (`1e6` is read as
    /// 1000000).
    #[arg(long, value_parser = super::parse_count, default_value = "500000",
          conflicts_with = "n_per_rank", allow_hyphen_values = true)]
    pub n: usize,
    /// Number of particles per rank instead: weak scaling (N = this x the number of ranks).
    #[arg(long, value_parser = super::parse_count, allow_hyphen_values = true)]
    pub n_per_rank: Option<usize>,
    /// Packing fraction (above 0).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true, value_parser = crate::args::number)]
    pub packing_fraction: f64,
    /// Steps per timed segment (after 2 warm-up steps; 1 or more).
    #[arg(long, default_value_t = 20, allow_hyphen_values = true, value_parser = crate::args::count)]
    pub steps: u64,
    /// Timed segments; the fastest (by its slowest rank) is reported (1 or more).
    #[arg(long, default_value_t = 3, allow_hyphen_values = true, value_parser = crate::args::count)]
    pub segments: u64,
    /// One JSON object on standard output instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Append one row per rank to this CSV file (the header when the file is new or empty).
    #[arg(long)]
    pub csv: Option<PathBuf>,
}

/// Columns of the CSV, in order.
const COLUMNS: &[&str] = &[
    "scaling",
    "dimension",
    "n",
    "packing_fraction",
    "ranks",
    "threads",
    "cell_planes",
    "steps",
    "segments",
    "seconds",
    "particle_steps_per_second",
    "rank",
    "particles",
    "seconds_per_step",
    "compute_seconds_per_step",
    "migration_seconds_per_step",
    "reduction_seconds_per_step",
    "compute_particle_steps_per_second",
    "migration_bytes_per_step",
    "reduction_bytes_per_step",
    "bytes_received_per_step",
    "migrants_per_step",
    "migration_calls_per_step",
    "reduction_calls_per_step",
    "resident_bytes",
    "peak_resident_bytes",
];

fn csv_row(scaling: &str, r: &DecomposedResult, k: &RankResult) -> String {
    let cells: Vec<String> = vec![
        scaling.to_string(),
        r.dimension.to_string(),
        r.n.to_string(),
        r.packing_fraction.to_string(),
        r.ranks.to_string(),
        r.threads.to_string(),
        r.cell_planes.to_string(),
        r.steps.to_string(),
        r.segments.to_string(),
        r.seconds.to_string(),
        r.particle_steps_per_second.to_string(),
        k.rank.to_string(),
        k.particles.to_string(),
        k.seconds_per_step.to_string(),
        k.compute_seconds_per_step.to_string(),
        k.migration_seconds_per_step.to_string(),
        k.reduction_seconds_per_step.to_string(),
        k.compute_particle_steps_per_second.to_string(),
        k.migration_bytes_per_step.to_string(),
        k.reduction_bytes_per_step.to_string(),
        k.bytes_received_per_step.to_string(),
        k.migrants_per_step.to_string(),
        k.migration_calls_per_step.to_string(),
        k.reduction_calls_per_step.to_string(),
        k.resident_bytes.to_string(),
        k.peak_resident_bytes.to_string(),
    ];
    cells.join(",")
}

fn append_csv(path: &PathBuf, scaling: &str, r: &DecomposedResult) -> Result<(), String> {
    let fresh = std::fs::metadata(path).map_or(true, |m| m.len() == 0);
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| format!("--csv {}: {e}", path.display()))?;
    let mut text = String::new();
    if fresh {
        text.push_str(&COLUMNS.join(","));
        text.push('\n');
    }
    for k in &r.per_rank {
        text.push_str(&csv_row(scaling, r, k));
        text.push('\n');
    }
    f.write_all(text.as_bytes())
        .map_err(|e| format!("--csv {}: {e}", path.display()))
}

fn print_table(scaling: &str, r: &DecomposedResult) {
    println!(
        "dsmc {}D {scaling} scaling: N = {} phi = {} ranks = {} threads/rank = {} cell planes = {}: \
         {:.3e} particle-steps/s (fastest of {} segments of {} steps, slowest rank)",
        r.dimension,
        r.n,
        r.packing_fraction,
        r.ranks,
        r.threads,
        r.cell_planes,
        r.particle_steps_per_second,
        r.segments,
        r.steps
    );
    println!(
        "{:>4} {:>10} {:>10} {:>10} {:>10} {:>10} {:>11} {:>9} {:>10} {:>9} {:>7} {:>7} {:>8}",
        "rank",
        "particles",
        "step ms",
        "compute ms",
        "migrate ms",
        "reduce ms",
        "compute p/s",
        "migrants",
        "mig B",
        "red B",
        "mig c",
        "red c",
        "RSS MB"
    );
    for k in &r.per_rank {
        println!(
            "{:>4} {:>10} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>11.3e} {:>9.1} {:>10.0} {:>9.0} {:>7.1} {:>7.1} {:>8.1}",
            k.rank,
            k.particles,
            1e3 * k.seconds_per_step,
            1e3 * k.compute_seconds_per_step,
            1e3 * k.migration_seconds_per_step,
            1e3 * k.reduction_seconds_per_step,
            k.compute_particle_steps_per_second,
            k.migrants_per_step,
            k.migration_bytes_per_step,
            k.reduction_bytes_per_step,
            k.migration_calls_per_step,
            k.reduction_calls_per_step,
            k.resident_bytes / 1e6
        );
    }
    println!(
        "(per step; mig/red B: bytes sent to other ranks by migration/reductions; mig/red c: \
         calls, each two MPI collectives)"
    );
}

/// Runs the benchmark on every rank; rank 0 prints and writes.
pub fn run(a: DsmcRanksArgs) -> Result<(), String> {
    if !(a.dimension == 2 || a.dimension == 3) {
        return Err(format!("--dimension {}: use 2 or 3", a.dimension));
    }
    if !(a.packing_fraction > 0.0 && a.packing_fraction < 0.5) {
        return Err(format!(
            "--packing-fraction {}: give a value in (0, 0.5)",
            a.packing_fraction
        ));
    }
    if a.steps == 0 || a.segments == 0 {
        return Err(format!(
            "--steps {} --segments {}: give at least 1 of each",
            a.steps, a.segments
        ));
    }
    let ranks = crate::ranks::Ranks::start();
    let (scaling, n) = match a.n_per_rank {
        Some(m) => ("weak", m.saturating_mul(ranks.size())),
        None => ("strong", a.n),
    };
    if n < lib::MIN_GRAINS {
        return Err(format!(
            "--n {n}: give at least {} particles",
            lib::MIN_GRAINS
        ));
    }
    // Each rank creates and holds only its slab: the ranks on this machine hold N together.
    super::check_memory(n, lib::dsmc::decomposed_bytes_per_particle(a.dimension))?;
    let r = lib::dsmc::measure_decomposed(
        a.dimension,
        n,
        a.packing_fraction,
        a.steps,
        a.segments,
        ranks.communicator(),
    )
    .map_err(|e| e.to_string())?;
    if ranks.rank() != 0 {
        return Ok(());
    }
    if let Some(path) = &a.csv {
        append_csv(path, scaling, &r)?;
    }
    if a.json {
        let mut v = serde_json::to_value(&r).map_err(|e| e.to_string())?;
        v["scaling"] = scaling.into();
        println!("{v}");
    } else {
        print_table(scaling, &r);
    }
    Ok(())
}
