use granular::intruder::one_d::{Intruder1d, Intruder1dConfig};
use std::time::Instant;
fn main() {
    let cfg = Intruder1dConfig {
        transient: Some(0.0),
        ..Default::default()
    };
    let mut e = Intruder1d::new(&cfg, 1).unwrap();
    let t0 = Instant::now();
    e.evolve_to(2.0e7);
    let s = t0.elapsed().as_secs_f64();
    use granular::engine::Engine;
    println!(
        "no grid: {} collisions {} events, {:.3e}/s collisions, {:.3e}/s events",
        e.collisions(),
        e.events(),
        e.collisions() as f64 / s,
        e.events() as f64 / s
    );
}
