//! Throughput of the DSMC engine: `cargo run --release --example dsmc_bench -- [dim n threads]...`
//! With no arguments: 2D and 3D, 1e5 and 1e6 particles, 1 and 2 threads.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let cases: Vec<(usize, usize, usize)> = if args.len() >= 3 {
        args.chunks(3).map(|c| (c[0], c[1], c[2])).collect()
    } else {
        let mut v = Vec::new();
        for d in [2, 3] {
            for n in [100_000, 1_000_000] {
                for t in [1, 2] {
                    v.push((d, n, t));
                }
            }
        }
        v
    };
    for (d, n, t) in cases {
        let r = granular::dsmc::bench::measure(d, n, t)?;
        println!(
            "D={} N={} threads={} steps={} time={:.2}s particle-steps/s={:.3e} collisions/s={:.3e} coll/particle/step={:.3}",
            r.dimension,
            r.n,
            r.threads,
            r.steps,
            r.seconds,
            r.particle_steps_per_second,
            r.collisions_per_second,
            r.collisions_per_particle_step
        );
    }
    Ok(())
}
