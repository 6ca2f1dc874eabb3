//! The steady state of a driven gas (`summary.json`'s `steady_state` block) against the
//! Sonine theory of van Noije and Ernst, each theory value with its stated accuracy.

use super::comparison::Comparison;
use super::cooling::{dsmc_cooling_per_step, rate_accuracy};
use super::page::number;
use granular::Summary;
use granular::run::summary::{AverageValue, SteadyStateSummary};
use granular::scenario::Scenario;
use granular::theory::sonine;

fn measured(v: &Option<AverageValue>) -> (f64, f64) {
    v.as_ref().map_or((f64::NAN, f64::NAN), |a| {
        (a.mean, a.error.unwrap_or(f64::NAN))
    })
}

/// Why a measured average has no error (`error_note`), for the notes.
fn error_note(v: &Option<AverageValue>) -> String {
    v.as_ref()
        .and_then(|a| a.error_note.clone())
        .map_or(String::new(), |n| format!("; no error: {n}"))
}

/// The rows of a driven run: `a2`, the cooling rate and (white noise) the temperature.
pub(crate) fn rows(scenario: &Scenario, summary: &Summary) -> Vec<Comparison> {
    let Some(s) = &summary.steady_state else {
        return Vec::new();
    };
    let (d, e) = (scenario.dimension, scenario.collisions().restitution);
    let white_noise = s.kind == "white_noise";
    let (a2_accuracy, estimate) = if white_noise {
        (
            sonine::white_noise_a2_accuracy(d, e),
            "van Noije and Ernst's heated-gas a2; stated accuracy: the dropped a2² terms, as large relative to a2² as the spread of the cooling state's two estimates",
        )
    } else {
        (
            sonine::cooling_a2_accuracy(d, e),
            "van Noije and Ernst's second estimate of the cooling state's a2; stated accuracy: its spread from the first",
        )
    };
    let mut rows = Vec::new();
    let (m, err) = measured(&s.a2);
    rows.push(
        Comparison::new("a2 of the steady state (time average)", m, err, s.theory_a2)
            .accuracy(a2_accuracy)
            .source(format!("{estimate}{}", error_note(&s.a2))),
    );
    // Without a temperature sample (a run shorter than its equilibration time) there is
    // no mean temperature to evaluate the cooling rate and its accuracy at.
    let Some(zeta) = s.theory_cooling_rate else {
        return rows;
    };
    let (relative, parts) = rate_accuracy(
        scenario,
        s.theory_a2,
        a2_accuracy,
        dsmc_cooling_per_step(scenario, s.theory_a2, zeta),
        s.chi,
    );
    let (m, err) = measured(&s.cooling_rate);
    rows.push(
        Comparison::new("cooling rate ζ = 2 (loss rate) / (D N T)", m, err, zeta)
            .accuracy(relative * zeta)
            .source(format!(
                "ζ = (1-e²)/D ω(T) (1 + 3 a2/16) at the measured mean temperature and the theory a2, \
                 contact value χ = {}; stated accuracy: {parts}{}",
                number(s.chi),
                error_note(&s.cooling_rate)
            )),
    );
    if white_noise {
        rows.push(temperature_row(s, relative));
    }
    if summary.rough.is_some() {
        let why = "rough grains: this row's wording and stated accuracy are those of smooth grains \
                   (van Noije and Ernst); the rough grains' rows compare θ and ζ/ν with RS-4..RS-9";
        rows = rows.into_iter().map(|r| r.not_applicable(why)).collect();
    }
    rows
}

/// The white-noise temperature: heating balances the loss, `T ∝ ζ^(-2/3)`, so its relative
/// accuracy is two thirds of the cooling rate's.
fn temperature_row(s: &SteadyStateSummary, rate_relative: f64) -> Comparison {
    let (m, err) = measured(&s.temperature);
    Comparison::new("temperature T (time average)", m, err, s.theory_temperature)
        .accuracy(2.0 / 3.0 * rate_relative * s.theory_temperature)
        .source(format!(
            "the energy balance of the heating with the loss (1-e²)/D ω(T) (1 + 3 a2/16) N D T/2; \
             stated accuracy: 2/3 of the cooling rate's{}",
            error_note(&s.temperature)
        ))
}
