//! The `steady_state` block of the summary: a driven gas's run averages (`a2`, temperature,
//! cooling rate) beside the Sonine theory of its state, as the scenario resolved it
//! ([`crate::scenario::DrivingResolved`]).

use crate::driving::Driving;
use crate::run::summary::{AveragesSummary, SteadyStateSummary};
use crate::simulation::Simulation;

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
    Some(SteadyStateSummary {
        kind: kind.into(),
        a2: get("a2"),
        theory_a2: state.a2,
        theory_a2_first: state.a2_first,
        temperature,
        theory_temperature: state.temperature,
        cooling_rate: get("cooling_rate"),
        theory_cooling_rate,
        chi: theory.chi,
    })
}
