//! The figure of a run of rough grains (`docs/rough.md`): the translational and rotational
//! temperatures against the collisions per grain `s`, and their ratio `θ = T_r/T_t`, beside
//! the kinetic theory that `summary.json`'s `rough` block holds (RS-4..RS-9, computed by the
//! library; nothing here is a formula of its own).
//!
//! With `s` as the clock a homogeneous cooling state decays as a straight line on a log
//! axis, `d ln T / ds = -ζ/ν` (the definition of the reduced cooling rate), so the theory
//! lines start at the measured temperatures where the averages start (the end of the
//! transient) and fall at the theory's `ζ/ν`; the ratio is a constant.

use crate::plot::{LinePlot, Panels, Series};
use crate::run_files::save_both;
use crate::table::{column, read_run_csv};
use granular::run::{RunFile, Summary};
use granular::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Draws `rough_temperatures` (nothing for smooth grains or without the columns).
pub(crate) fn rough_temperatures(
    dir: &Path,
    scenario: &Scenario,
    summary: Option<&Summary>,
    out: &Path,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    if !scenario.collisions().law().is_rough() {
        return Ok(());
    }
    let ts = read_run_csv(dir, RunFile::TimeSeries)?;
    let (Some(s), Some(tt), Some(tr)) = (
        column(&ts, "collisions_per_particle"),
        column(&ts, "translational_temperature"),
        column(&ts, "rotational_temperature"),
    ) else {
        return Ok(());
    };
    // Positive values only on the log axis (a run may start without spin).
    let positive = |y: &[f64]| -> (Vec<f64>, Vec<f64>) {
        s.iter()
            .zip(y)
            .filter(|(x, v)| **v > 0.0 && v.is_finite() && x.is_finite())
            .map(|(x, v)| (*x, *v))
            .unzip()
    };
    let (s_t, t_t) = positive(&tt);
    let (s_r, t_r) = positive(&tr);
    if s_t.len() < 2 {
        return Ok(());
    }
    let ratio: Vec<f64> = tt.iter().zip(&tr).map(|(a, b)| b / a).collect();
    let rough = summary.and_then(|s| s.rough.as_ref());
    let state = rough.map_or("cooling", |r| r.state.as_str());
    let title = match state {
        "white_noise" => "Rough grains heated by white noise",
        "rescale" => "Rough grains, homogeneous cooling state (rescaled)",
        _ => "Rough grains cooling freely",
    };
    let mut temperatures = LinePlot::new(title)
        .x_label("collisions per grain s (dimensionless)")
        .y_label("temperature T [m L²/τ²]")
        .log_y(true)
        .series(Series::line("translational T_t", s_t.clone(), t_t.clone()))
        .series(Series::line("rotational T_r", s_r, t_r));
    let mut ratios = LinePlot::new("Temperature ratio")
        .x_label("collisions per grain s (dimensionless)")
        .y_label("temperature ratio θ = T_r/T_t (dimensionless)")
        .series(Series::line("measured θ", s.clone(), ratio));
    let s_end = s_t.last().copied().unwrap_or(0.0);
    // Where the summary's averages start: the end of the transient.
    let s0 = scenario.output.equilibration_collisions_per_particle;
    let start = s_t.iter().position(|x| *x >= s0);
    for (approximation, ratio, rate, pattern) in rough.map_or(Vec::new(), |r| {
        vec![
            (
                "Maxwellian",
                r.theory_temperature_ratio,
                r.theory_reduced_cooling_rate,
                0,
            ),
            (
                "Sonine",
                r.theory_temperature_ratio_sonine,
                r.theory_reduced_cooling_rate_sonine,
                1,
            ),
        ]
    }) {
        let (eq_ratio, eq_rate) = match (state, approximation) {
            ("white_noise", "Maxwellian") => ("RS-6", "RS-2 at RS-6"),
            ("white_noise", _) => ("RS-9", "RS-9"),
            (_, "Maxwellian") => ("RS-4", "RS-5"),
            _ => ("RS-8", "RS-8"),
        };
        if let Some(theta) = ratio {
            ratios = ratios.series(
                Series::theory(
                    format!("{approximation} θ = {theta:.4} ({eq_ratio})"),
                    vec![s[0], s_end],
                    vec![theta, theta],
                )
                .with_pattern(pattern),
            );
        }
        // Free cooling: both temperatures fall at ζ/ν from the end of the transient.
        if let (Some(rate), Some(k), "cooling") = (rate, start, state)
            && s_end > s_t[k]
        {
            let from = s_t[k];
            for (name, t0) in [("T_t", t_t[k]), ("T_r", tr_at(&s, &tr, from))] {
                if t0.is_nan() || t0 <= 0.0 {
                    continue;
                }
                temperatures = temperatures.series(
                    Series::theory_fn(
                        format!("{name}, {approximation} ζ/ν = {rate:.4} ({eq_rate})"),
                        (from, s_end),
                        60,
                        false,
                        move |x| t0 * (-rate * (x - from)).exp(),
                    )
                    .with_pattern(pattern),
                );
            }
        }
    }
    let stem = out.join("rough_temperatures");
    save_both(
        &stem,
        Panels::new(temperatures, ratios).save_png_and_svg(&stem),
        made,
    )
}

/// The rotational temperature at collisions per grain `at` (the first row at or after it).
fn tr_at(s: &[f64], tr: &[f64], at: f64) -> f64 {
    s.iter().position(|x| *x >= at).map_or(f64::NAN, |i| tr[i])
}
