//! The `rough` block of the summary: a rough gas's measured temperature ratio and reduced
//! cooling rate beside the kinetic theory of rough grains ([`crate::theory::rough`]).

use crate::driving::Driving;
use crate::run::AnyEngine;
use crate::run::summary::{AveragesSummary, RoughSummary};
use crate::simulation::Simulation;
use crate::theory::rough::{Approximation, RoughGas, RoughState};

/// The block, for a run of rough grains (EDMD or DSMC); `None` otherwise.
pub(super) fn summary(simulation: &Simulation, averages: &AveragesSummary) -> Option<RoughSummary> {
    let scenario = simulation.scenario();
    let law = scenario.collisions().law();
    let resolved = simulation.resolved().grains.as_ref()?.rough.as_ref()?;
    let driving = match simulation.engine() {
        AnyEngine::Edmd2(e) => e.driving().map(|d| d.driving.clone()),
        AnyEngine::Edmd3(e) => e.driving().map(|d| d.driving.clone()),
        AnyEngine::Dsmc2(e) => e.driving().map(|d| d.driving.clone()),
        AnyEngine::Dsmc3(e) => e.driving().map(|d| d.driving.clone()),
        AnyEngine::Intruder(_) => return None,
    };
    let d = scenario.dimension;
    let gas: RoughGas = resolved.gas(d, law.restitution);
    let (state, kind) = match driving {
        None => ("cooling", RoughState::Cooling),
        Some(Driving::Rescale { .. }) => ("rescale", RoughState::Cooling),
        Some(Driving::WhiteNoise { .. }) => ("white_noise", RoughState::WhiteNoise),
    };
    let get = |k: &str| averages.observables.get(k).cloned();
    // Walton's rule has no theory of constant β.
    let theory = law.friction.is_none();
    let maxwell_ratio = gas.temperature_ratio(kind, Approximation::Maxwell);
    let maxwell_rate = gas.reduced_cooling_rate(kind, Approximation::Maxwell);
    let sonine = gas.sonine_state(kind);
    let mut notes = vec![
        "theory for one species of rough grains in a homogeneous dilute gas (Boltzmann); ζ/ν with ν the measured collision frequency".to_string(),
    ];
    if scenario.species().len() > 1 {
        notes.push("this run has several species: the theory is that of the first alone".into());
    }
    if !theory {
        notes.push(
            "Walton's Coulomb rule (collisions.friction): no theory of constant β applies".into(),
        );
    }
    let cumulants = sonine.map(|s| [s.a20, s.a02, s.a11]);
    if cumulants.is_some_and(|a| a.iter().any(|x| x.abs() > 0.5)) {
        notes.push(
            "the Sonine cumulants are large (|a| > 0.5): both approximations are unreliable here (docs/rough.md)".into(),
        );
    }
    Some(RoughSummary {
        state: state.into(),
        normal_restitution: gas.normal_restitution,
        tangential_restitution: gas.tangential_restitution,
        inertia: gas.inertia,
        temperature_ratio: get("temperature_ratio"),
        theory_temperature_ratio: maxwell_ratio.filter(|_| theory),
        theory_temperature_ratio_sonine: sonine.map(|s| s.temperature_ratio).filter(|_| theory),
        reduced_cooling_rate: get("reduced_cooling_rate"),
        theory_reduced_cooling_rate: maxwell_rate.filter(|_| theory),
        theory_reduced_cooling_rate_sonine: gas
            .reduced_cooling_rate(kind, Approximation::Sonine)
            .filter(|_| theory),
        theory_cumulants_sonine: cumulants.filter(|_| theory),
        note: notes.join("; "),
    })
}
