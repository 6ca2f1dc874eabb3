//! What the library's benchmarks share: the periodic unit square of 2D grains they time
//! (also the gas of the Python benchmark, `crates/granular-py/benches/bench_python.py`).

use granular::prelude::*;

/// `n` grains of `engine` ("edmd" or "dsmc") at packing fraction `phi` in the periodic
/// unit square, Maxwell-Boltzmann at `T = 1`, seed 1, placed by `placement` ("random" or
/// "lattice"); no stop rule that a benchmark reaches, so the cost limits are waived.
pub fn unit_square_gas(engine: &str, n: usize, phi: f64, placement: &str) -> Scenario {
    let text = format!(
        r#"
engine = "{engine}"
dimension = 2
seed = 1
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "disk"
count = {n}
packing_fraction = {phi}
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[initial]
placement = "{placement}"
[stop]
time = 1e9
wall_seconds = 86400.0
"#
    );
    Scenario::from_toml_insisting(&text, &[]).expect("benchmark scenario")
}
