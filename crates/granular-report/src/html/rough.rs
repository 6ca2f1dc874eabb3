//! Rough grains (`summary.json`'s `rough` block, `docs/rough.md`): the measured temperature
//! ratio `θ = T_r/T_t` and reduced cooling rate `ζ/ν` against the kinetic theory of rough
//! grains in its Maxwellian (RS-4..RS-6) and first Sonine (RS-8, RS-9) approximations, each
//! theory value with its stated accuracy.
//!
//! Stated accuracies: the Maxwellian approximation's error is the size of the Sonine
//! correction, `|Maxwell - Sonine|`; the Sonine approximation's is that of the products of
//! cumulants it drops, the largest cumulant squared times the value. Where a cumulant
//! exceeds 0.5 the expansion has broken down (docs/rough.md, the quasi-smooth cooling
//! state) and neither is compared.

use super::comparison::Comparison;
use super::page::{number, short};
use granular::Summary;
use granular::boundary::AxisKind;
use granular::run::summary::{AverageValue, RoughSummary};
use granular::scenario::Scenario;

/// Largest Sonine cumulant the comparison trusts (the summary's note uses the same bound).
const LARGEST_CUMULANT: f64 = 0.5;

fn measured(v: &Option<AverageValue>) -> (f64, f64, String) {
    v.as_ref().map_or((f64::NAN, f64::NAN, String::new()), |a| {
        (
            a.mean,
            a.error.unwrap_or(f64::NAN),
            a.error_note
                .as_ref()
                .map_or(String::new(), |n| format!("; no error: {n}")),
        )
    })
}

/// Why the homogeneous one-species theory does not describe this run (`None`: it does).
fn set_up_excludes(scenario: &Scenario, rough: &RoughSummary) -> Option<String> {
    if scenario.species().len() != 1 {
        Some("a mixture: the theory is that of one species".into())
    } else if scenario.gravity().iter().any(|g| *g != 0.0) {
        Some("gravity makes the gas inhomogeneous".into())
    } else if scenario.axes().contains(&AxisKind::Wall) {
        Some("the box has walls; the theory is that of a homogeneous gas in a periodic box".into())
    } else if scenario.collisions().friction.is_some() {
        Some("Walton's Coulomb rule (collisions.friction): no theory of constant β applies".into())
    } else if rough.theory_temperature_ratio.is_none() {
        Some("no theory value in summary.json".into())
    } else {
        None
    }
}

/// The rows of a run of rough grains: θ and ζ/ν against each approximation.
pub(crate) fn rows(scenario: &Scenario, summary: &Summary) -> Vec<Comparison> {
    let Some(r) = &summary.rough else {
        return Vec::new();
    };
    let state = match r.state.as_str() {
        "white_noise" => "white-noise driven state",
        "rescale" => "homogeneous cooling state (rescaled)",
        _ => "homogeneous cooling state",
    };
    let (white_noise, eq_ratio, eq_rate) = if r.state == "white_noise" {
        (true, "RS-6", "RS-2 at RS-6")
    } else {
        (false, "RS-4", "RS-5")
    };
    let eq_sonine = if white_noise { "RS-9" } else { "RS-8" };
    let excluded = set_up_excludes(scenario, r);
    let largest = r
        .theory_cumulants_sonine
        .map(|a| a.iter().fold(0.0f64, |m, x| m.max(x.abs())));
    let broken = match largest {
        None => Some("the first Sonine approximation has no solution here".to_string()),
        Some(a) if a > LARGEST_CUMULANT => Some(format!(
            "the Sonine expansion has broken down (largest cumulant {} > {}: a rotational \
             distribution far from Gaussian), so neither approximation can be trusted to \
             better than tens of per cent (docs/rough.md)",
            short(a, 2),
            LARGEST_CUMULANT
        )),
        Some(_) => None,
    };
    let params = format!(
        "α = {}, β = {}, κ = {}",
        number(r.normal_restitution),
        number(r.tangential_restitution),
        number(r.inertia)
    );
    let mut rows = Vec::new();
    for (what, value, maxwell, sonine, eq_m) in [
        (
            "temperature ratio θ = T_r/T_t",
            &r.temperature_ratio,
            r.theory_temperature_ratio,
            r.theory_temperature_ratio_sonine,
            eq_ratio,
        ),
        (
            "reduced cooling rate ζ/ν (total energy, per collision of a grain)",
            &r.reduced_cooling_rate,
            r.theory_reduced_cooling_rate,
            r.theory_reduced_cooling_rate_sonine,
            eq_rate,
        ),
    ] {
        let (m, err, note) = measured(value);
        let maxwell = maxwell.unwrap_or(f64::NAN);
        let sonine = sonine.unwrap_or(f64::NAN);
        let mut row = Comparison::new(format!("{what}, {state}, Maxwellian"), m, err, maxwell)
            .accuracy((maxwell - sonine).abs())
            .source(format!(
                "{eq_m} at {params}; stated accuracy: the size of the Sonine correction \
             (Sonine value {}){note}",
                number(sonine)
            ));
        if let Some(why) = excluded.as_ref().or(broken.as_ref()) {
            row = row.not_applicable(why.clone());
        }
        rows.push(row);
        let a = largest.unwrap_or(f64::NAN);
        let mut row = Comparison::new(format!("{what}, {state}, Sonine"), m, err, sonine)
            .accuracy(a * a * sonine.abs())
            .source(format!(
                "{eq_sonine} (the first Sonine approximation, linear in the cumulants) at \
                 {params}; stated accuracy: the dropped products of cumulants, the largest \
                 cumulant ({}) squared times the value{note}",
                short(a, 2)
            ));
        if let Some(why) = excluded.as_ref().or(broken.as_ref()) {
            row = row.not_applicable(why.clone());
        }
        rows.push(row);
    }
    rows
}
