//! Haff's law (DSMC-3) against a freely cooling run, where it applies.
//!
//! Haff's law is the energy of the *homogeneous* cooling state. It holds in a periodic box
//! of one species without gravity or driving that is smaller than the critical size of the
//! shear instability (`theory::stability::critical_length`, HCS-2), and only while the gas
//! stays homogeneous: the fit window ends at the last observation whose `S(k)` at the
//! smallest wave numbers (from `structure_factor.npz`, else computed from the snapshots) is
//! within four of its standard errors of the homogeneous value. In that window
//! `T^(-1/2)` grows linearly, `T(t)^(-1/2) = T(0)^(-1/2) (1 + t/t0)`; the measured `t0`
//! comes from its slope, the error from ten batches of the window, and the theory `t0`
//! carries its stated accuracy (the Sonine truncation, DSMC's step bias, the contact value).

use super::comparison::Comparison;
use super::page::{number, short};
use crate::run_files::{RunFiles, floats, get};
use granular::observables::structure_factor_of;
use granular::output::npz::{read_npz, read_snapshot};
use granular::run::{RunDir, RunFile};
use granular::scenario::{EngineKind, Scenario};
use granular::theory::{equilibrium, haff, sonine};

/// Collisions per grain before the window opens: the velocity distribution relaxes to the
/// cooling state's (its `a2`) within a few.
const RELAXATION_COLLISIONS: f64 = 5.0;

/// Batches of the window for the error of the slope.
const BATCHES: usize = 10;

/// Standard errors above the homogeneous value at which `S(k)` says the gas has left the
/// homogeneous state.
const HOMOGENEITY_SIGMAS: f64 = 4.0;

/// Wave numbers (in units of `2π / L`) that count as the smallest.
const SMALLEST_K: f64 = 3.5;

/// `S(k)` at the smallest wave numbers at each observation time, with its homogeneous
/// value and the spread of a homogeneous gas's estimate.
struct Homogeneity {
    times: Vec<f64>,
    s_small: Vec<f64>,
    /// `S(0)` of the homogeneous gas (1 for DSMC's point grains).
    homogeneous: f64,
    /// Its standard error over the wave vectors averaged, `S(0) / sqrt(M)`.
    spread: f64,
    /// Where the numbers come from.
    source: &'static str,
}

impl Homogeneity {
    fn threshold(&self) -> f64 {
        self.homogeneous + HOMOGENEITY_SIGMAS * self.spread
    }

    /// The last observation time before the first one above the threshold (`None`: the
    /// first is above it already); `+∞` when none is.
    fn end(&self) -> Option<f64> {
        match self.s_small.iter().position(|s| *s > self.threshold()) {
            None => Some(f64::INFINITY),
            Some(0) => None,
            Some(i) => Some(self.times[i - 1]),
        }
    }
}

/// The homogeneous `S(0)` of the run's gas: 1 for DSMC (point grains placed uniformly),
/// the equation of state's for the event-driven engine.
fn homogeneous_structure_factor(scenario: &Scenario, packing_fraction: f64) -> f64 {
    if scenario.kind() == EngineKind::Dsmc {
        1.0
    } else {
        equilibrium::structure_factor_zero(scenario.dimension, packing_fraction)
    }
}

/// `(sum of S over the wave vectors of the smallest shells, number of wave vectors)`.
fn smallest_shells(k: &[f64], s: &[f64], count: &[f64], length: f64) -> (f64, f64) {
    let unit = 2.0 * std::f64::consts::PI / length;
    k.iter()
        .zip(s)
        .zip(count)
        .filter(|((k, s), _)| **k / unit <= SMALLEST_K && s.is_finite())
        .fold((0.0, 0.0), |(a, m), ((_, s), c)| (a + s * c, m + c))
}

fn homogeneity(run: &RunFiles, packing_fraction: f64) -> Option<Homogeneity> {
    let sc = &run.scenario;
    let length = sc.lengths().iter().cloned().fold(0.0, f64::max);
    let s0 = homogeneous_structure_factor(sc, packing_fraction);
    let mut times = Vec::new();
    let mut s_small = Vec::new();
    let mut modes = f64::NAN;
    let path = RunDir::new(&run.dir).file(RunFile::StructureFactor);
    let source;
    if path.is_file() {
        let a = read_npz(&path).ok()?;
        let t = floats(&a, "times", &path).ok()?;
        let k = floats(&a, "k", &path).ok()?;
        let s = floats(&a, "s", &path).ok()?;
        let m = get(&a, "modes", &path).ok()?;
        let m: Vec<f64> = m
            .as_f64()
            .map(<[f64]>::to_vec)
            .or_else(|| m.as_u64().map(|v| v.iter().map(|x| *x as f64).collect()))?;
        if k.is_empty() || s.len() != t.len() * k.len() || m.len() != k.len() {
            return None;
        }
        for (time, row) in t.iter().zip(s.chunks(k.len())) {
            let (sum, count) = smallest_shells(k, row, &m, length);
            times.push(*time);
            s_small.push(sum / count);
            modes = count;
        }
        source = "S(k) of structure_factor.npz";
    } else {
        for f in crate::table::snapshot_files(&run.dir) {
            let snap = read_snapshot(&f).ok()?;
            let sk = structure_factor_of(&snap, &sc.lengths(), SMALLEST_K as usize)?;
            let count: Vec<f64> = sk.count.iter().map(|c| *c as f64).collect();
            let (sum, m) = smallest_shells(&sk.k, &sk.s, &count, length);
            times.push(snap.time);
            s_small.push(sum / m);
            modes = m;
        }
        source = "S(k) of the snapshots";
    }
    (modes > 0.0 && times.len() > 1).then(|| Homogeneity {
        times,
        s_small,
        homogeneous: s0,
        spread: s0 / modes.sqrt(),
        source,
    })
}

/// The relative accuracy of a kinetic-theory cooling rate `zeta` (and so of `t0 = 2/zeta`)
/// and what it is made of: the Sonine truncation (`3/16` of the stated accuracy
/// `a2_accuracy` of `a2`), DSMC's step bias (`theory::haff::step_cooling_bias` at
/// `zeta_tau`, the cooling per step; `None` for the event-driven engine), and, with an
/// Enskog contact value `chi != 1`, its spread between Henderson's `χ` and the equation of
/// state's `(Z - 1) / (2^(D-1) φ)`.
pub(crate) fn rate_accuracy(
    sc: &Scenario,
    a2: f64,
    a2_accuracy: f64,
    zeta_tau: Option<f64>,
    chi: f64,
) -> (f64, String) {
    let d = sc.dimension;
    let mut parts = vec![(
        3.0 / 16.0 * a2_accuracy / (1.0 + 3.0 * a2 / 16.0),
        "Sonine truncation",
    )];
    if let Some(zeta_tau) = zeta_tau {
        parts.push((haff::step_cooling_bias(1.0, zeta_tau), "DSMC step bias"));
    }
    if chi != 1.0 {
        let phi = sc.resolve().grains.map_or(f64::NAN, |g| g.packing_fraction);
        let from_eos =
            (equilibrium::compressibility(d, phi) - 1.0) / (2f64.powi(d as i32 - 1) * phi);
        parts.push(((chi / from_eos - 1.0).abs(), "contact value"));
    }
    let total = parts.iter().map(|(p, _)| p * p).sum::<f64>().sqrt();
    let text = parts
        .iter()
        .map(|(p, what)| format!("{what} {} %", short(100.0 * p, 2)))
        .collect::<Vec<_>>()
        .join(", ");
    (total, text)
}

/// DSMC's cooling per step `zeta tau`: with the automatic step, `STEP_FRACTION` of the
/// mean free time (`zeta / omega = (1-e²)/D (1 + 3a2/16)`); with a fixed `time_step`, at
/// the cooling rate `zeta`. `None` for the event-driven engine.
pub(crate) fn dsmc_cooling_per_step(sc: &Scenario, a2: f64, zeta: f64) -> Option<f64> {
    if sc.kind() != EngineKind::Dsmc {
        return None;
    }
    let e = sc.collisions().restitution;
    Some(match sc.dsmc().and_then(|d| d.time_step) {
        Some(tau) => zeta * tau,
        // The step is `STEP_FRACTION / omega`, so `zeta tau` is KT-8 at `omega = 1` times it.
        None => {
            granular::dsmc::engine::STEP_FRACTION
                * granular::theory::haff::sonine_cooling_rate(sc.dimension, e, 1.0, a2)
        }
    })
}

/// The row of Haff's time `t0` for a freely cooling one-species run (`None` for an elastic
/// or a driven run, which have rows of their own).
pub(crate) fn haff_row(run: &RunFiles) -> Option<Comparison> {
    let sc = &run.scenario;
    let (d, e) = (sc.dimension, sc.collisions().restitution);
    if e >= 1.0 || sc.driving().is_some() {
        return None;
    }
    let quantity = "Haff's time t0 = 1/(s √T(0)), s the slope of T^(-1/2) against t";
    if let Some(why) = crate::run_files::haff_excluded(sc) {
        return Some(Comparison::unmeasured(quantity).not_applicable(why));
    }
    let (theory, chi) = crate::run_files::haff_theory(run)?;
    let phi = sc.resolve().grains?.packing_fraction;
    let length = sc.lengths().iter().cloned().fold(0.0, f64::max);
    let critical = crate::run_files::critical_length(sc)?;
    let homogeneity = homogeneity(run, phi);
    let s_text = |h: &Homogeneity| {
        let top = h.s_small.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let at = h
            .s_small
            .iter()
            .position(|s| *s == top)
            .map_or(f64::NAN, |i| h.times[i]);
        format!(
            "{} at |k| ≤ {} · 2π/L: homogeneous {} ± {}, largest {} at t = {}",
            h.source,
            SMALLEST_K,
            short(h.homogeneous, 3),
            short(h.spread, 2),
            short(top, 3),
            short(at, 3)
        )
    };
    if length > critical {
        let mut why = format!(
            "the homogeneous cooling state is unstable in this box: its edge L = {} exceeds the \
             critical size L_c = {} of the shear instability (HCS-2, restitution {}), so vortices \
             and clusters grow and the energy decays more slowly than Haff's law",
            short(length, 3),
            short(critical, 3),
            short(e, 3)
        );
        if let Some(h) = &homogeneity {
            why.push_str(&format!("; {}", s_text(h)));
        }
        // Measured for information up to the first observation that shows the
        // inhomogeneity (the whole run without a record of it).
        let end = homogeneity.as_ref().map_or(f64::INFINITY, |h| {
            match h.s_small.iter().position(|s| *s > h.threshold()) {
                Some(i) => h.times[i.max(1)],
                None => f64::INFINITY,
            }
        });
        let (t0, error) = match slope_fit(run, end) {
            Some(f) => {
                why.push_str(&format!(
                    "; measured over t = {} to {}",
                    short(f.3, 3),
                    short(f.4, 3)
                ));
                (f.0, f.1)
            }
            None => (f64::NAN, f64::NAN),
        };
        let mut row = Comparison::new(quantity, t0, error, theory).not_applicable(why);
        row.source = format!(
            "DSMC-3 with t0 from kinetic theory (contact value χ = {})",
            number(chi)
        );
        return Some(row);
    }
    let end = homogeneity
        .as_ref()
        .map_or(Some(f64::INFINITY), Homogeneity::end);
    let Some(end) = end else {
        let h = homogeneity.as_ref()?;
        return Some(Comparison::unmeasured(quantity).not_applicable(format!(
            "the gas is not homogeneous at the run's first observation after t = 0 ({})",
            s_text(h)
        )));
    };
    let (t0, error, rows, start, stop, start_temperature) = match slope_fit(run, end) {
        Some(f) => f,
        None => {
            return Some(Comparison::unmeasured(quantity).not_applicable(format!(
                "fewer than {} rows after {RELAXATION_COLLISIONS} collisions per grain \
                 in the homogeneous window",
                2 * BATCHES
            )));
        }
    };
    let a2 = sonine::cooling_a2_first(d, e);
    // The cooling rate at the start of the window, the largest in it.
    let zeta = 2.0 / theory * (start_temperature / run.temperature.first()?).sqrt();
    let (relative, parts) = rate_accuracy(
        sc,
        a2,
        sonine::cooling_a2_accuracy(d, e),
        dsmc_cooling_per_step(sc, a2, zeta),
        chi,
    );
    let window = match &homogeneity {
        Some(h) if end.is_finite() => format!(
            "the window ends at the last observation before S(k) left the homogeneous value ({})",
            s_text(h)
        ),
        Some(h) => format!("homogeneous throughout ({})", s_text(h)),
        None => "no S(k) or snapshots to check the homogeneity".into(),
    };
    Some(
        Comparison::new(quantity, t0, error, theory)
            .accuracy(relative * theory)
            .source(format!(
                "DSMC-3 with t0 from kinetic theory (contact value χ = {}, first Sonine correction); \
                 L = {} below the critical size {} (HCS-2); fitted over t = {} to {} ({rows} rows, \
                 error from {BATCHES} batches); {window}; stated accuracy of t0: {parts}",
                short(chi, 4),
                short(length, 3),
                short(critical, 3),
                short(start, 3),
                short(stop, 3),
            )),
    )
}

/// `(t0, error, rows, window start, window end, temperature at the start)` of the slope of
/// `T^(-1/2)` over the rows after [`RELAXATION_COLLISIONS`] up to time `end`.
fn slope_fit(run: &RunFiles, end: f64) -> Option<(f64, f64, usize, f64, f64, f64)> {
    let t_init = *run.temperature.first()?;
    let cpp = crate::table::read_run_csv(&run.dir, RunFile::TimeSeries)
        .ok()
        .and_then(|ts| crate::table::column(&ts, "collisions_per_particle"))?;
    let rows: Vec<(f64, f64, f64)> = run
        .time
        .iter()
        .zip(&run.temperature)
        .zip(&cpp)
        .filter(|((t, temp), c)| **c >= RELAXATION_COLLISIONS && **t <= end && **temp > 0.0)
        .map(|((t, temp), _)| (*t, temp.powf(-0.5), *temp))
        .collect();
    if rows.len() < 2 * BATCHES {
        return None;
    }
    // Each batch's slope over its rows (sharing the end points), weighted by its duration.
    let len = (rows.len() - 1) / BATCHES;
    let mut slopes = Vec::with_capacity(BATCHES);
    for b in 0..BATCHES {
        let (a, z) = (rows[b * len], rows[(b + 1) * len]);
        slopes.push(((z.1 - a.1) / (z.0 - a.0), z.0 - a.0));
    }
    let first = rows[0];
    let last = rows[BATCHES * len];
    let slope = (last.1 - first.1) / (last.0 - first.0);
    let weights: f64 = slopes.iter().map(|s| s.1).sum();
    let mean_weight = weights / BATCHES as f64;
    let variance = slopes
        .iter()
        .map(|(s, w)| (w / mean_weight * (s - slope)).powi(2))
        .sum::<f64>()
        / (BATCHES as f64 - 1.0);
    let slope_error = (variance / BATCHES as f64).sqrt();
    let t0 = 1.0 / (slope * t_init.sqrt());
    Some((
        t0,
        t0 * slope_error / slope,
        BATCHES * len + 1,
        first.0,
        last.0,
        first.2,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_ends_before_the_first_inhomogeneous_observation() {
        let h = Homogeneity {
            times: vec![0.0, 1.0, 2.0, 3.0],
            s_small: vec![1.0, 1.2, 3.0, 5.0],
            homogeneous: 1.0,
            spread: 0.25,
            source: "test",
        };
        assert_eq!(h.end(), Some(1.0));
        let calm = Homogeneity {
            s_small: vec![1.0, 1.2, 1.1, 0.9],
            ..h
        };
        assert_eq!(calm.end(), Some(f64::INFINITY));
        let early = Homogeneity {
            s_small: vec![2.5, 1.0, 1.0, 1.0],
            ..calm
        };
        assert_eq!(early.end(), None);
    }
}
