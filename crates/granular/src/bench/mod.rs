//! The benchmarks of the engines, in one place: every mode of `granular bench`, the
//! criterion and instruction-count benchmarks (`benches/`) and the speed tests call this
//! module, and the command line only formats what it returns.
//!
//! * [`edmd`]: the event-driven engine's equilibrated fluids ([`edmd::FluidCase`]) and
//!   their collisions per CPU second ([`edmd::measure`]);
//! * [`dsmc`]: DSMC particle-steps per second on threads ([`dsmc::measure`]) and split
//!   over ranks ([`dsmc::measure_decomposed`]);
//! * [`intruder`]: the Gillespie engines' collisions per second
//!   ([`intruder::measure_collision_rate`]);
//! * [`unit_square_gas`]: the periodic unit square of disks that `benches/` and the
//!   Python benchmark time through [`Simulation`](crate::Simulation).
//!
//! Hidden from the documentation: the cases and result types follow the benchmarks, not
//! a stable API. Results and the machines they were measured on: `docs/performance.md`.

pub mod dsmc;
pub mod edmd;
pub mod intruder;

use crate::scenario::Scenario;

/// Fewest grains of a bench case: fewer give too few collisions to measure (one grain
/// in a periodic box never collides).
pub const MIN_GRAINS: usize = 16;

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// Unsupported dimension.
    #[error("dimension {0} is not supported (2 or 3)")]
    Dimension(usize),
    /// Placing the grains failed.
    #[error(transparent)]
    Init(#[from] crate::setup::InitError),
    /// An engine stopped.
    #[error(transparent)]
    Engine(#[from] crate::engine::EngineError),
    /// The DSMC engine could not be built.
    #[error(transparent)]
    Dsmc(#[from] crate::dsmc::DsmcError),
    /// The DSMC engine could not be split over the ranks.
    #[error(transparent)]
    Domain(#[from] crate::dsmc::DomainError),
    /// The thread pool could not be built.
    #[error(transparent)]
    Pool(#[from] rayon::ThreadPoolBuildError),
    /// An intruder case that does not exist or could not be built.
    #[error("{0}")]
    Case(String),
}

/// A case too large for the memory this machine can give (see [`check_memory`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryShortfall {
    /// Bytes the case would need.
    pub need: f64,
    /// Bytes available (`MemAvailable`).
    pub available: f64,
    /// The most grains that fit.
    pub max_grains: f64,
}

/// Refuses `n` grains at `bytes_per_grain` bytes each when they would take more than 80 %
/// of the memory the system can give without swapping (accepted where it does not say).
pub fn check_memory(n: usize, bytes_per_grain: f64) -> Result<(), MemoryShortfall> {
    let need = n as f64 * bytes_per_grain;
    match crate::host::available_memory() {
        Some(have) if need > 0.8 * have => Err(MemoryShortfall {
            need,
            available: have,
            max_grains: (0.8 * have / bytes_per_grain).floor(),
        }),
        _ => Ok(()),
    }
}

/// Resident memory of this process now and at its peak, bytes (`VmRSS`, `VmHWM`; NaN
/// where the system does not say).
pub fn resident_memory() -> (f64, f64) {
    crate::host::resident_memory()
}

/// CPU time of the calling thread, in seconds (NaN where the system does not say):
/// benchmarks report rates per CPU second, so that other processes on a shared machine do
/// not count against the engine.
pub fn thread_cpu_seconds() -> f64 {
    cpu_time::ThreadTime::try_now()
        .map(|t| t.as_duration().as_secs_f64())
        .unwrap_or(f64::NAN)
}

/// `n` grains of `engine` ("edmd" or "dsmc") at packing fraction `phi` in the periodic
/// unit square, Maxwell-Boltzmann at `T = 1`, seed 1, placed by `placement` ("random" or
/// "lattice"); no stop rule that a benchmark reaches, so the cost limits are waived. The
/// gas of `benches/advance_steps.rs`, `benches/state_copy.rs` and the Python benchmark
/// (`crates/granular-py/benches/bench_python.py`).
pub fn unit_square_gas(
    engine: &str,
    n: usize,
    phi: f64,
    placement: &str,
) -> Result<Scenario, crate::scenario::ScenarioError> {
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
    Scenario::from_toml_insisting(&text, &[])
}
