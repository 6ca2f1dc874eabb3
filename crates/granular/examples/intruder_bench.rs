//! Measures intruder collision rates: `cargo run --release -p granular --example intruder_bench [collisions]`.
fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_000_000);
    for case in granular::intruder::bench::CASES {
        let n = if case == "needle-paper" { n / 20 } else { n };
        match granular::intruder::bench::measure_collision_rate(case, n, 1) {
            Ok(r) => println!(
                "{:20} {:>12} collisions {:8.3} s {:10.3e} collisions/s",
                r.case, r.collisions, r.seconds, r.collisions_per_second
            ),
            Err(e) => eprintln!("{case}: {e}"),
        }
    }
}
