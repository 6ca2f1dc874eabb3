//! Prints the intruder figure tables as CSV:
//! `cargo run --release -p granular --example intruder_figures -- [collisions] [seed]`.
use granular::intruder::figures;

fn main() {
    let mut args = std::env::args().skip(1);
    let n: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(500_000);
    let seed: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let alphas = figures::alpha_grid();
    let tables = [
        figures::fig1_flux(61, n / 10, seed),
        figures::fig2_colliding_velocities(n, seed),
        figures::fig3_temperature_ratio(&alphas, n, seed),
        figures::fig4_power_law_ratio(&alphas, n, seed),
        figures::fig5_power_law_distributions(n, seed),
        figures::fig7_correlation(&alphas, n, seed),
        figures::fig8_angular_distribution(10 * n, seed),
    ];
    for t in &tables {
        println!("# {}", t.title);
        println!("{}", t.to_csv());
    }
}
