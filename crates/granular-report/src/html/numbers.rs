//! The summary numbers of a run next to their theory, with the deviation in standard errors
//! where both an error and a theory exist. Every theory value comes from the library
//! (`granular::theory`, `granular::intruder::theory`) or from `summary.json`, which the
//! library wrote with the same functions; nothing here is a formula of its own.

use super::page::{escape, number, table};
use crate::run_files::RunFiles;
use crate::table::{Table, column};
use granular::Summary;
use granular::intruder::theory::GAUSSIAN_KURTOSIS;
use granular::scenario::{EngineKind, Scenario};
use granular::stats::batch_means;
use granular::theory::{equilibrium, haff};

/// One measured number, its standard error, its theory value and where that comes from
/// (`NaN` where there is none).
pub(crate) struct Comparison {
    pub quantity: String,
    pub measured: f64,
    pub error: f64,
    pub theory: f64,
    pub source: String,
    /// Whether `measured / theory - 1` means something (not for a chi-square).
    pub relative: bool,
}

impl Comparison {
    fn new(quantity: impl Into<String>, measured: f64, error: f64, theory: f64) -> Self {
        Self {
            quantity: quantity.into(),
            measured,
            error,
            theory,
            source: String::new(),
            relative: true,
        }
    }

    fn absolute(mut self) -> Self {
        self.relative = false;
        self
    }

    fn source(mut self, source: impl Into<String>) -> Self {
        self.source = source.into();
        self
    }

    /// `(measured - theory) / error`, `NaN` when any of them is missing.
    pub(crate) fn deviation(&self) -> f64 {
        if self.error > 0.0 {
            (self.measured - self.theory) / self.error
        } else {
            f64::NAN
        }
    }
}

/// The comparisons of a many-grain (`edmd`, `dsmc`) run.
pub(crate) fn grains(
    scenario: &Scenario,
    summary: &Summary,
    ts: &Table,
    run: Option<&RunFiles>,
) -> Vec<Comparison> {
    let d = scenario.dimension;
    let mut rows = Vec::new();
    for (name, fit) in &summary.maxwell_boltzmann_fit {
        let dof = fit.degrees_of_freedom as f64;
        rows.push(
            Comparison::new(
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
            )),
        );
        if let Some(s) = summary.species.get(name) {
            rows.push(
                Comparison::new(
                    format!("mean speed of {name}"),
                    s.mean_speed,
                    s.mean_speed_error,
                    s.maxwell_boltzmann_mean_speed,
                )
                .source("Maxwell-Boltzmann mean speed at the pooled temperature"),
            );
        }
    }
    let e = scenario.collisions.restitution;
    for (name, s) in &summary.scaled_speeds {
        rows.push(
            Comparison::new(
                format!("a2 of the scaled speeds of {name}"),
                s.a2,
                f64::NAN,
                haff::sonine_a2(d, e),
            )
            .source(format!(
                "first Sonine correction of the homogeneous cooling state at restitution {}; temperatures {} to {}",
                number(e),
                number(s.temperature_min),
                number(s.temperature_max)
            )),
        );
    }
    let simple = scenario.species.len() == 1 && scenario.gravity.iter().all(|g| *g == 0.0);
    if simple
        && e < 1.0
        && let Some(c) = run.and_then(|r| haff_comparison(r, summary))
    {
        rows.push(c);
    }
    if simple && e == 1.0 {
        rows.extend(equation_of_state(scenario, summary, ts));
    }
    rows
}

/// Haff's time from kinetic theory for the engine of the run (`haff_time` with the first
/// Sonine correction): the event-driven gas with the Enskog contact value at its packing
/// fraction (`enskog_haff_time`), DSMC with the contact value its Enskog factor used, or
/// `chi = 1` (the Boltzmann gas DSMC simulates without `dsmc.enskog`).
fn theory_haff_time(run: &RunFiles, summary: &Summary) -> Option<(f64, f64)> {
    let sc = &run.scenario;
    let d = sc.dimension;
    let radius = sc.radius(0);
    let volume: f64 = sc.lengths().iter().product();
    let n = sc.particle_count() as f64 / volume;
    let t0 = *run.temperature.first()?;
    let (e, m) = (sc.collisions.restitution, sc.species[0].mass);
    if !(t0 > 0.0 && e < 1.0) {
        return None;
    }
    Some(match sc.engine {
        EngineKind::Dsmc => {
            let chi = summary
                .resolved
                .as_ref()
                .and_then(|r| r.contact_value)
                .unwrap_or(1.0);
            (haff::haff_time(d, n, radius, t0, m, e, chi, true), chi)
        }
        _ => {
            let phi = haff::packing_fraction(d, n, radius);
            (
                haff::enskog_haff_time(d, n, radius, t0, m, e),
                haff::contact_value(d, phi),
            )
        }
    })
}

/// Haff's time `t0` fitted to the kinetic energy (least squares in `ln K` with the library's
/// `haff_energy`, DSMC-3) while `K > K(0)/10`, against kinetic theory
/// ([`theory_haff_time`]).
fn haff_comparison(run: &RunFiles, summary: &Summary) -> Option<Comparison> {
    let (theory, chi) = theory_haff_time(run, summary)?;
    let k0 = *run.energy.first()?;
    let points: Vec<(f64, f64)> = run
        .time
        .iter()
        .zip(&run.energy)
        .skip(1)
        .take_while(|(_, k)| **k > 0.1 * k0)
        .map(|(t, k)| (*t, k.ln()))
        .collect();
    if points.len() < 3 {
        return None;
    }
    let residuals = |t0: f64| -> f64 {
        points
            .iter()
            .map(|(t, lk)| (lk - haff::haff_energy(k0, *t, t0).ln()).powi(2))
            .sum()
    };
    // Golden-section search in ln t0 over six decades around the theory value.
    let (mut a, mut b) = ((theory * 1e-3).ln(), (theory * 1e3).ln());
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if residuals(c.exp()) < residuals(d.exp()) {
            b = d;
        } else {
            a = c;
        }
    }
    let t0 = (0.5 * (a + b)).exp();
    let n = points.len() as f64;
    let sigma2 = residuals(t0) / (n - 1.0);
    let h = 1e-6 * t0;
    let jj: f64 = points
        .iter()
        .map(|(t, _)| {
            let up = haff::haff_energy(k0, *t, t0 + h).ln();
            let down = haff::haff_energy(k0, *t, t0 - h).ln();
            ((up - down) / (2.0 * h)).powi(2)
        })
        .sum();
    let error = (sigma2 / jj).sqrt();
    Some(
        Comparison::new("Haff's time t0 (fit of the kinetic energy)", t0, error, theory).source(
            format!(
                "DSMC-3 with t0 from kinetic theory (contact value chi = {}, first Sonine correction); \
                 fitted over {} rows while K > K(0)/10; the error is the fit's, rows are correlated, so it is a lower bound",
                number(chi),
                points.len()
            ),
        ),
    )
}

/// The compressibility factor `Z = P / (n T)` of an elastic one-species run, averaged over
/// the rows after equilibration (batch means), against the hard-disk or hard-sphere
/// equation of state at the resolved packing fraction.
fn equation_of_state(scenario: &Scenario, summary: &Summary, ts: &Table) -> Vec<Comparison> {
    let eta = match &summary.resolved {
        Some(r) => r.packing_fraction,
        None => return Vec::new(),
    };
    let (Some(cpp), Some(temperature)) = (
        column(ts, "collisions_per_particle"),
        column(ts, "temperature"),
    ) else {
        return Vec::new();
    };
    let volume: f64 = scenario.lengths().iter().product();
    let density = scenario.particle_count() as f64 / volume;
    let after = scenario.output.equilibration_collisions_per_particle;
    let theory = equilibrium::compressibility(scenario.dimension, eta);
    let law = if scenario.dimension == 2 {
        "hard-disk equation of state (Liu 2020, fitted to Kolafa and Rottner)"
    } else {
        "Carnahan-Starling"
    };
    let mut rows = Vec::new();
    for (col, what) in [
        ("pressure", "from the collisional virial"),
        ("wall_pressure", "from the momentum given to the walls"),
    ] {
        let Some(p) = column(ts, col) else {
            continue;
        };
        let z: Vec<f64> = p
            .iter()
            .zip(&temperature)
            .zip(&cpp)
            .filter(|((p, _), c)| **c >= after && p.is_finite())
            .map(|((p, t), _)| p / (density * t))
            .collect();
        if z.len() < 20 {
            continue;
        }
        let (mean, error) = batch_means(&z, 10);
        rows.push(
            Comparison::new(format!("compressibility factor Z = P/(nT), {what}"), mean, error, theory)
                .source(format!(
                    "{law} at packing fraction {} (stated accuracy a few 10^-3 relative, not in the error); \
                     {} rows after {} collisions per grain, error by 10 batch means",
                    number(eta),
                    z.len(),
                    number(after)
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
        let source = b
            .theory
            .clone()
            .unwrap_or_else(|| "no exact theory for an inelastic needle (alpha < 1)".into());
        for (key, what) in [
            ("translational_temperature_ratio", "T_tr / T_B"),
            ("rotational_temperature_ratio", "T_rot / T_B"),
            ("correlation_r", "correlation R (Eq. 30)"),
        ] {
            rows.push(
                Comparison::new(what, v(key), v(&format!("{key}_error")), theory)
                    .source(source.clone()),
            );
        }
    } else {
        rows.push(
            Comparison::new(
                "temperature ratio T / T_B",
                v("temperature_ratio"),
                v("temperature_ratio_error"),
                b.theory_temperature_ratio.unwrap_or(f64::NAN),
            )
            .source(
                b.theory
                    .clone()
                    .unwrap_or_else(|| "no exact theory for this bath and mass ratio".into()),
            ),
        );
        let gaussian = b.histogram_reference == "gaussian_eq18";
        // Disk and sphere: the summary carries G-41 and G-42 (Gaussian bath).
        let (kurtosis_theory, kurtosis_source) = match b.theory_kurtosis {
            Some(k) => (k, "Maxwellian in d dimensions, (d + 2)/d (G-41)"),
            None if gaussian => (
                GAUSSIAN_KURTOSIS,
                "Gaussian (Martin-Piasecki: the stationary intruder is Gaussian)",
            ),
            None => (f64::NAN, ""),
        };
        rows.push(
            Comparison::new(
                "kurtosis <v⁴>/<v²>²",
                v("kurtosis"),
                v("kurtosis_error"),
                kurtosis_theory,
            )
            .source(kurtosis_source),
        );
        if let Some(rate) = b.theory_collision_rate {
            rows.push(
                Comparison::new(
                    "collision rate [1/τ]",
                    v("collision_rate"),
                    v("collision_rate_error"),
                    rate,
                )
                .source("mean rate of the Maxwellian intruder at the G-40 temperature (G-42)"),
            );
        }
    }
    rows
}

/// The comparison table, the deviation coloured by its size (`ok` below 2, `warn` below 3).
pub(crate) fn render(rows: &[Comparison]) -> String {
    if rows.is_empty() {
        return "<p>This run has no quantity with an exact theory to compare with \
                (see the final observables below).</p>"
            .into();
    }
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|c| {
            let z = c.deviation();
            let class = if !z.is_finite() {
                "none"
            } else if z.abs() < 2.0 {
                "ok"
            } else if z.abs() < 3.0 {
                "warn"
            } else {
                "bad"
            };
            let measured = if c.error.is_finite() {
                format!("{} ± {}", number(c.measured), number(c.error))
            } else {
                number(c.measured)
            };
            let deviation = if z.is_finite() {
                format!("{z:+.2} σ")
            } else {
                "—".into()
            };
            let relative = c.measured / c.theory - 1.0;
            let relative = if c.relative && relative.is_finite() && c.theory != 0.0 {
                format!("{:+.2} %", 100.0 * relative)
            } else {
                "—".into()
            };
            vec![
                escape(&c.quantity),
                measured,
                number(c.theory),
                format!("<span class=\"z {class}\">{deviation}</span>"),
                relative,
                escape(&c.source),
            ]
        })
        .collect();
    table(
        "numbers",
        &[
            "quantity",
            "measured ± standard error",
            "theory",
            "deviation",
            "relative",
            "theory and notes",
        ],
        &body,
    )
}
