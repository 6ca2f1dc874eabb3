//! The summary numbers of a run next to their theory. Each row says what is measured and
//! what it is compared with; the deviation is counted in the combined uncertainty
//! `sqrt(error² + accuracy²)` of the run's standard error and the theory's stated accuracy,
//! and a theory whose conditions the run does not meet is not compared: the row says why,
//! in a neutral colour. Every theory value comes from the library (`granular::theory`,
//! `granular::intruder::theory`) or from `summary.json`, which the library wrote with the
//! same functions; nothing here is a formula of its own.

use super::comparison::Comparison;
use super::page::{number, short};
use crate::run_files::RunFiles;
use granular::Summary;
use granular::boundary::AxisKind;
use granular::intruder::theory::GAUSSIAN_KURTOSIS;
use granular::scenario::Scenario;
use granular::theory::{equilibrium, hard_wall};

/// Why the Maxwell-Boltzmann distribution does not describe the run (`None`: it does).
fn not_in_equilibrium(scenario: &Scenario) -> Option<String> {
    let c = scenario.collisions();
    let wall = c.wall_restitution.unwrap_or(c.restitution);
    if scenario.driving().is_some() {
        Some(
            "a driven gas is not Maxwell-Boltzmann: its distribution departs from it by a2 \
             (the steady-state rows)"
                .into(),
        )
    } else if c.restitution < 1.0 || (wall < 1.0 && scenario.axes().contains(&AxisKind::Wall)) {
        Some(format!(
            "inelastic collisions (restitution {}, walls {}) keep the gas out of equilibrium",
            number(c.restitution),
            number(wall)
        ))
    } else {
        None
    }
}

/// The comparisons of a many-grain (`edmd`, `dsmc`) run.
pub(crate) fn grains(
    scenario: &Scenario,
    summary: &Summary,
    run: Option<&RunFiles>,
) -> Vec<Comparison> {
    let mut rows = Vec::new();
    let equilibrium_excluded = not_in_equilibrium(scenario);
    for (name, fit) in &summary.maxwell_boltzmann_fit {
        let dof = fit.degrees_of_freedom as f64;
        let mut row = Comparison::new(
            format!("χ² of the speeds of {name} against Maxwell-Boltzmann"),
            fit.chi_square,
            (2.0 * dof).sqrt(),
            dof,
        )
        .absolute()
        .source(format!(
            "HD-12 at T = {}; expected χ² = degrees of freedom ({}), spread √(2·dof); p = {}, {} speeds from {} snapshots",
            number(fit.temperature),
            fit.degrees_of_freedom,
            number(fit.p_value),
            fit.samples,
            fit.snapshots
        ));
        if let Some(why) = &equilibrium_excluded {
            row = row.not_applicable(why.clone());
        }
        rows.push(row);
        if let Some(s) = summary.species.get(name) {
            let mut row = Comparison::new(
                format!("mean speed of {name}"),
                s.mean_speed,
                s.mean_speed_error,
                s.maxwell_boltzmann_mean_speed,
            )
            .source("Maxwell-Boltzmann mean speed at the pooled temperature");
            if let Some(why) = &equilibrium_excluded {
                row = row.not_applicable(why.clone());
            }
            rows.push(row);
        }
    }
    for (name, s) in &summary.scaled_speeds {
        let range = format!(
            "pooled over the snapshots at temperatures {} to {}; no error (one number per run)",
            number(s.temperature_min),
            number(s.temperature_max)
        );
        let row = match s.theory_a2 {
            Some(_) if summary.rough.is_some() => Comparison::new(
                format!("a2 of the scaled speeds of {name}"),
                s.a2,
                f64::NAN,
                f64::NAN,
            )
            .not_applicable(
                "rough grains: van Noije and Ernst's a2 is that of smooth grains (the rough \
                 theory's a20 is in summary.json's rough block, theory_cumulants_sonine)",
            )
            .source(range),
            Some([first, second]) => Comparison::new(
                format!("a2 of the scaled speeds of {name}"),
                s.a2,
                f64::NAN,
                second,
            )
            .accuracy((first - second).abs())
            .source(format!(
                "van Noije and Ernst's second estimate of the homogeneous cooling state's a2 \
                 (first {}), at restitution {}; {range}",
                number(first),
                number(scenario.collisions().restitution)
            )),
            None => Comparison::new(
                format!("a2 of the scaled speeds of {name}"),
                s.a2,
                f64::NAN,
                f64::NAN,
            )
            .not_applicable(
                "the cooling state's a2 is the theory of one species in a periodic box \
                 without gravity",
            )
            .source(range),
        };
        rows.push(row);
    }
    if let Some(row) = run.and_then(super::cooling::haff_row) {
        rows.push(row);
    }
    rows.extend(equation_of_state(scenario, summary));
    rows.extend(super::steady::rows(scenario, summary));
    rows.extend(super::rough::rows(scenario, summary));
    rows
}

/// The compressibility factor `Z = P / (n T)`, `n = N / V`, of an elastic one-species run
/// (the run averages after equilibration, `summary.json`'s `averages`), against the
/// hard-disk or hard-sphere equation of state at the bulk density of the box, with the
/// walls' shift of the measured pressures (`theory::hard_wall`, W-1 to W-4).
fn equation_of_state(scenario: &Scenario, summary: &Summary) -> Vec<Comparison> {
    let simple = scenario.species().len() == 1 && scenario.gravity().iter().all(|g| *g == 0.0);
    if !simple || not_in_equilibrium(scenario).is_some() {
        return Vec::new();
    }
    let Some(averages) = &summary.averages else {
        return Vec::new();
    };
    let d = scenario.dimension;
    let lengths = scenario.lengths();
    let walls: Vec<bool> = scenario
        .axes()
        .iter()
        .map(|a| *a == AxisKind::Wall)
        .collect();
    let n = scenario.particle_count();
    let theory = hard_wall::walled_box(&lengths, &walls, n, scenario.radius(0));
    let eta = theory.bulk_packing_fraction;
    let law = if d == 2 {
        "hard-disk equation of state (Liu 2020, fitted to Kolafa and Rottner)"
    } else {
        "Carnahan-Starling"
    };
    let walled = walls.iter().any(|w| *w);
    let density = n as f64 / lengths.iter().product::<f64>();
    let temperature = averages
        .observables
        .get("temperature")
        .map_or(f64::NAN, |t| t.mean);
    let mut rows = Vec::new();
    for (key, what, z, wall) in [
        (
            "compressibility_factor",
            "from the collisional virial",
            theory.virial_compressibility,
            theory.virial_accuracy,
        ),
        (
            "wall_pressure",
            "from the momentum given to the walls",
            theory.wall_compressibility,
            theory.wall_accuracy,
        ),
    ] {
        let Some(a) = averages.observables.get(key) else {
            continue;
        };
        let Some(error) = a.error else { continue };
        let scale = if key == "wall_pressure" {
            1.0 / (density * temperature)
        } else {
            1.0
        };
        if !z.is_finite() || !(a.mean * scale).is_finite() {
            continue;
        }
        let eos = equilibrium::compressibility_accuracy(d, eta) * z;
        let correction = if walled {
            format!(
                "at the bulk packing fraction {} of the box (W-3), with the walls' shift of the \
                 measured pressure, {} % (W-4, scaled particle theory)",
                short(eta, 4),
                short(100.0 * (z / theory.uncorrected - 1.0), 2)
            )
        } else {
            format!("at packing fraction {}", number(eta))
        };
        let mut parts = format!(
            "equation of state {} %",
            short(100.0 * equilibrium::compressibility_accuracy(d, eta), 2)
        );
        if walled {
            parts.push_str(&format!(
                ", wall correction {} %",
                short(100.0 * wall / z, 2)
            ));
        }
        rows.push(
            Comparison::new(
                format!("compressibility factor Z = P/(nT), n = N/V, {what}"),
                a.mean * scale,
                error * scale,
                z,
            )
            .accuracy((eos * eos + wall * wall).sqrt())
            .source(format!(
                "{law} {correction}; stated accuracy: {parts}; {} samples after equilibration, \
                 error by blocking",
                a.samples
            )),
        );
    }
    rows
}

/// The comparisons of an intruder run, from its `summary.json` block.
pub(crate) fn intruder(summary: &Summary) -> Vec<Comparison> {
    let Some(b) = &summary.intruder else {
        return Vec::new();
    };
    let v = |k: &str| b.value(k).unwrap_or(f64::NAN);
    let mut rows = Vec::new();
    if b.model == "needle" {
        // Equipartition holds only for the elastic needle; the summary names it then.
        let theory = if b.theory.is_some() { 1.0 } else { f64::NAN };
        for (key, what) in [
            ("translational_temperature_ratio", "T_tr / T_B"),
            ("rotational_temperature_ratio", "T_rot / T_B"),
            ("correlation_r", "correlation R (Eq. 30)"),
        ] {
            let row = Comparison::new(what, v(key), v(&format!("{key}_error")), theory);
            rows.push(match &b.theory {
                Some(source) => row.source(format!("{source} (exact)")),
                None => row
                    .not_applicable("there is no exact theory for an inelastic needle (alpha < 1)"),
            });
        }
    } else {
        let row = Comparison::new(
            "temperature ratio T / T_B",
            v("temperature_ratio"),
            v("temperature_ratio_error"),
            b.theory_temperature_ratio.unwrap_or(f64::NAN),
        );
        rows.push(match &b.theory {
            Some(source) => row.source(format!("{source} (exact)")),
            None => row.not_applicable("there is no exact theory for this bath and mass ratio"),
        });
        let gaussian = b.histogram_reference == "gaussian_eq18";
        // Disk and sphere: the summary carries G-41 and G-42 (Gaussian bath).
        let row = |theory: f64| {
            Comparison::new(
                "kurtosis <v⁴>/<v²>²",
                v("kurtosis"),
                v("kurtosis_error"),
                theory,
            )
        };
        rows.push(match b.theory_kurtosis {
            Some(k) => row(k).source("Maxwellian in d dimensions, (d + 2)/d (G-41, exact)"),
            None if gaussian => row(GAUSSIAN_KURTOSIS).source(
                "Gaussian (Martin-Piasecki: the stationary intruder in a Gaussian bath is Gaussian, exact)",
            ),
            None => row(f64::NAN)
                .not_applicable("the intruder is Gaussian only in a Gaussian bath"),
        });
        if let Some(rate) = b.theory_collision_rate {
            rows.push(
                Comparison::new(
                    "collision rate [1/τ]",
                    v("collision_rate"),
                    v("collision_rate_error"),
                    rate,
                )
                .source(
                    "mean rate of the Maxwellian intruder at the G-40 temperature (G-42, exact)",
                ),
            );
        }
    }
    rows
}
