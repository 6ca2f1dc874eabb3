//! The `steady_state` block of the summary: a driven gas's run averages (`a2`, temperature,
//! cooling rate) beside the Sonine theory of its state ([`crate::driving`]).

use crate::driving::{Driving, GasTheory};
use crate::run::AnyEngine;
use crate::run::summary::{AveragesSummary, SteadyStateSummary};
use crate::simulation::Simulation;
use crate::theory::sonine;

/// The block, for a DSMC or event-driven run with a driving; `None` otherwise.
pub(super) fn summary(
    simulation: &Simulation,
    averages: &AveragesSummary,
) -> Option<SteadyStateSummary> {
    let (driving, theory) = match simulation.engine() {
        AnyEngine::Dsmc2(e) => (e.driving()?.driving.clone(), gas(e)),
        AnyEngine::Dsmc3(e) => (e.driving()?.driving.clone(), gas(e)),
        AnyEngine::Edmd2(e) => (e.driving()?.driving.clone(), e.gas_theory()),
        AnyEngine::Edmd3(e) => (e.driving()?.driving.clone(), e.gas_theory()),
        _ => return None,
    };
    let get = |k: &str| averages.observables.get(k).cloned();
    let a2 = theory.a2(&driving);
    let temperature = get("temperature");
    let theory_cooling_rate = temperature
        .as_ref()
        .map(|t| theory.cooling_rate(t.mean, a2));
    let (kind, theory_temperature, first) = match driving {
        Driving::Rescale { temperature } => (
            "rescale",
            temperature,
            Some(sonine::cooling_a2_first(
                theory.dimension,
                theory.restitution,
            )),
        ),
        Driving::WhiteNoise { strength } => (
            "white_noise",
            theory.white_noise_temperature(strength, a2),
            None,
        ),
    };
    Some(SteadyStateSummary {
        kind: kind.into(),
        a2: get("a2"),
        theory_a2: a2,
        theory_a2_first: first,
        temperature,
        theory_temperature,
        cooling_rate: get("cooling_rate"),
        theory_cooling_rate,
        chi: theory.chi,
    })
}

/// The kinetic-theory description of a DSMC engine's gas.
fn gas<const D: usize>(e: &crate::dsmc::DsmcEngine<D>) -> GasTheory {
    GasTheory {
        dimension: D,
        restitution: e.config().law.restitution,
        number_density: e.number_density(),
        radius: e.radius(),
        mass: e.mass(),
        chi: e.enskog_factor(),
        particles: crate::engine::Engine::particle_count(e),
    }
}
