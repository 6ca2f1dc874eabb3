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

/// Rough grains: the cooling rate of the total energy, the Maxwellian `ζ/ν` at the state's
/// temperature ratio (RS-4 held by rescaling, RS-6 under white noise) times `ν(T)` at the
/// run's mean temperature, in place of the smooth gas's (`docs/rough.md`). The state's
/// `a2` and temperature are already the rough gas's ([`crate::scenario::DrivingResolved`]).
fn rough(gas: &RoughGas, theory: &GasTheory, driving: &Driving, block: &mut SteadyStateSummary) {
    let theta = match driving {
        Driving::Rescale { .. } => gas.cooling_temperature_ratio(),
        Driving::WhiteNoise { .. } => Some(gas.white_noise_temperature_ratio()),
    };
    block.theory_cooling_rate = match (&block.temperature, theta) {
        (Some(t), Some(theta)) => {
            Some(gas.total_cooling_rate(theta) * theory.collision_frequency(t.mean))
        }
        _ => None,
    };
}
