//! The engine's own cost of an `advance` call: one call to time `T` against `S` calls in
//! equal steps, in Rust (no Python), on the gas of the Python benchmark
//! (`crates/granular-py/benches/bench_python.py`: event-driven disks in the periodic unit
//! square, packing fraction 0.2, seed 1). Issue 23 asks that 10^4 small steps cost at most
//! 5 % more than one call; the difference per call here is what the library adds, the rest
//! of the Python figure is the binding's.
//!
//! `cargo bench -p granular --bench advance_steps -- [N] [S] [T] [REPEAT] [one|many]`
//! (defaults 1000 10000 5 5). Both ways end in the same state bit for bit (checked). With
//! `one` or `many` it only runs that way once, for counting instructions under valgrind.
//! Results and the machine: docs/performance.md.

use granular::prelude::*;
use std::time::Instant;

fn gas(n: usize) -> Simulation {
    let scenario =
        granular::bench::unit_square_gas("edmd", n, 0.2, "random").expect("benchmark scenario");
    Simulation::new(scenario).expect("benchmark state")
}

/// Advances a fresh gas to `total` in `steps` equal calls; the wall seconds and the
/// final positions.
fn run(n: usize, steps: usize, total: f64) -> (f64, Vec<f64>) {
    let mut sim = gas(n);
    let dt = total / steps as f64;
    let start = Instant::now();
    for k in 1..=steps {
        sim.advance(if k == steps { total } else { k as f64 * dt })
            .expect("advance");
    }
    let seconds = start.elapsed().as_secs_f64();
    let mut x = vec![0.0; n * 2];
    assert!(sim.positions_into(&mut x));
    (seconds, x)
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let steps: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let total: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(5.0);
    let repeat: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(5);
    match args.get(4).map(String::as_str) {
        Some("one") => {
            run(n, 1, total);
            return;
        }
        Some("many") => {
            run(n, steps, total);
            return;
        }
        _ => {}
    }
    let (mut one, mut many) = (Vec::new(), Vec::new());
    for _ in 0..repeat {
        let (a, xa) = run(n, 1, total);
        let (b, xb) = run(n, steps, total);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&xa), bits(&xb), "steps changed the trajectory");
        one.push(a);
        many.push(b);
    }
    one.sort_by(f64::total_cmp);
    many.sort_by(f64::total_cmp);
    let (a, b) = (one[0], many[0]);
    println!("advance_steps: {n} disks to t = {total}, best of {repeat}");
    println!("  one call        {:.4} s", a);
    println!(
        "  {steps} calls    {:.4} s  ->  {:+.2} %, {:.2} us per call",
        b,
        100.0 * (b / a - 1.0),
        1e6 * (b - a) / steps as f64
    );
}
