//! The copy of every grain's position into a caller's buffer in input order
//! (`Simulation::positions_into`, what `Simulation.positions` of the Python package
//! calls): the number issue 23 asks to be "a few milliseconds" for 10^6 disks.
//!
//! `cargo bench -p granular --bench state_copy -- [N] [lattice|random] [REPEAT] [edmd|dsmc]`
//! (defaults 1000000 lattice 15 edmd). It builds the event-driven gas of the Python benchmark
//! (`crates/granular-py/benches/bench_python.py`: periodic unit square, packing fraction
//! 0.1, seed 1), advances it to t = 0.001, and prints the best and median of REPEAT calls
//! into one reused buffer and, for scale, of a `copy_from_slice` of the result. `random`
//! places the grains at random, so that the storage order (sorted in space) is a random
//! permutation of the input order, as in any gas that has run for a while. With REPEAT
//! up to 3 it only makes REPEAT calls, for counting instructions and cache misses under
//! valgrind: the counts of REPEAT = 3 less those of REPEAT = 1 are two calls.
//! Results and the machine: docs/performance.md.

use granular::prelude::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let n: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let placement = args.get(1).map_or("lattice", String::as_str);
    let repeat: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(15);
    let engine = args.get(3).map_or("edmd", String::as_str);
    let scenario =
        granular::bench::unit_square_gas(engine, n, 0.1, placement).expect("benchmark scenario");
    let start = Instant::now();
    let mut sim = Simulation::new(scenario).expect("benchmark state");
    sim.advance(0.001).expect("advance");
    let built = start.elapsed().as_secs_f64();
    let mut out = vec![0.0; n * 2];
    if repeat <= 3 {
        for _ in 0..repeat {
            assert!(sim.positions_into(&mut out));
        }
        return;
    }
    // The first call builds the engine's slot table (kept until its next reordering).
    let start = Instant::now();
    assert!(sim.positions_into(&mut out));
    let first = start.elapsed().as_secs_f64();
    println!(
        "state_copy: {n} disks, {placement} placement (built and advanced in {built:.1} s), \
         {} rayon threads; first call {:.2} ms",
        rayon::current_num_threads(),
        1e3 * first
    );
    let mut copy = vec![0.0; n * 2];
    let (mut ours, mut plain) = (Vec::new(), Vec::new());
    for _ in 0..repeat {
        let start = Instant::now();
        sim.positions_into(&mut out);
        ours.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        copy.copy_from_slice(std::hint::black_box(&out));
        plain.push(start.elapsed().as_secs_f64());
    }
    for (what, t) in [
        ("positions_into", &mut ours),
        ("copy_from_slice", &mut plain),
    ] {
        t.sort_by(f64::total_cmp);
        println!(
            "  {what:16} best {:.2} ms, median {:.2} ms ({repeat} calls)",
            1e3 * t[0],
            1e3 * t[t.len() / 2]
        );
    }
}
