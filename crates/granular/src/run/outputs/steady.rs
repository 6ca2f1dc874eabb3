//! The `steady_state` block of the summary: a driven gas's run averages (`a2`, temperature,
//! cooling rate) beside the Sonine theory of its state, as the scenario resolved it
//! ([`crate::scenario::DrivingResolved`]).

use crate::driving::{Driving, GasTheory};
use crate::run::summary::{AveragesSummary, SteadyStateSummary};
use crate::simulation::Simulation;
use crate::theory::rough::RoughGas;

/// The block, for a DSMC or event-driven run with a driving; `None` otherwise.
pub(super) fn summary(
    simulation: &Simulation,
    averages: &AveragesSummary,
) -> Option<SteadyStateSummary> {
    let state = simulation.resolved().grains.as_ref()?.driving.as_ref()?;
    let theory = &state.gas;
    let get = |k: &str| averages.observables.get(k).cloned();
    let temperature = get("temperature");
    let theory_cooling_rate = temperature
        .as_ref()
        .map(|t| theory.cooling_rate(t.mean, state.a2));
    let kind = match state.driving {
        Driving::Rescale { .. } => "rescale",
        Driving::WhiteNoise { .. } => "white_noise",
    };
    let mut block = SteadyStateSummary {
        kind: kind.into(),
        a2: get("a2"),
        theory_a2: state.a2,
        theory_a2_first: state.a2_first,
        temperature,
        theory_temperature: state.temperature,
        cooling_rate: get("cooling_rate"),
        theory_cooling_rate,
        chi: theory.chi,
    };
    if let Some(rough_grains) = simulation.resolved().grains.as_ref()?.rough.as_ref() {
        let gas = rough_grains.gas(theory.dimension, theory.restitution);
        rough(&gas, theory, &state.driving, &mut block);
    }
    Some(block)
}

/// Rough grains: the theory of the rough gas in place of the smooth one (`docs/rough.md`):
/// `a2` is the Sonine `a20` (RS-8, RS-9; NaN where it has no solution), the white-noise
/// temperature the Maxwellian balance of `RoughGas::white_noise_temperature`, and the
/// cooling rate of the total energy the Maxwellian `ζ/ν` times `ν(T)` at the run's mean
/// temperature.
fn rough(gas: &RoughGas, theory: &GasTheory, driving: &Driving, block: &mut SteadyStateSummary) {
    let nu = |t: f64| {
        crate::theory::kinetic::collision_frequency(
            theory.dimension,
            theory.number_density,
            theory.radius,
            t,
            theory.mass,
            theory.chi,
        )
    };
    let (sonine, theta) = match driving {
        Driving::Rescale { .. } => (gas.sonine_cooling_state(), gas.cooling_temperature_ratio()),
        Driving::WhiteNoise { strength } => {
            block.theory_temperature =
                gas.white_noise_temperature(*strength, theory.mass, theory.particles, nu(1.0));
            (
                gas.sonine_white_noise_state(),
                Some(gas.white_noise_temperature_ratio()),
            )
        }
    };
    block.theory_a2 = sonine.map_or(f64::NAN, |s| s.a20);
    block.theory_a2_first = None;
    block.theory_cooling_rate = match (&block.temperature, theta) {
        (Some(t), Some(theta)) => Some(gas.total_cooling_rate(theta) * nu(t.mean)),
        _ => None,
    };
}
