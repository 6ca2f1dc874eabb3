//! Memory effects of the granular gas heated by white noise (DSMC, 2D): the Mpemba effect of
//! Lasanta, Vega Reyes, Prados and Santos (Phys. Rev. Lett. 119, 148001 (2017)) against the
//! first Sonine relaxation of KT-14 and KT-15 (`theory::relaxation`).
//!
//! Two samples of the same gas under the same noise start from velocities set from arrays
//! (`Simulation::from_state`): sample A 5 % hotter with `a2 = +0.3`, sample B with
//! `a2 = -0.3`. The noise holds the gas at a tenth of their temperature, so both cool; A,
//! whose larger `a2` makes it cool faster (KT-8), crosses B and stays colder. The theory
//! is integrated from each sample's measured initial `T` and `a2`.
//!
//! Tolerances: four independent pairs (their own grains, velocities and streams); each
//! measured quantity is the mean over the pairs, with the standard error of that mean;
//! allowed are [`STANDARD_ERRORS`] standard errors plus the first Sonine approximation's
//! own error, taken as 15 % of the theory's value: the spread of its two estimates of the
//! cooling state's `a2` at this restitution (KT-10 against KT-11, 15 % at α = 0.3 in 2D),
//! the size of the terms of order `a2²` the equations drop. The DSMC step (a fiftieth of the
//! mean free time at the initial temperature) biases the cooling rate by at most
//! `0.75 ζ τ` = 0.7 %, the same for both samples, so that it cancels in their difference to
//! first order.

use crate::common::STANDARD_ERRORS;
use granular::prelude::*;
use granular::theory::relaxation::{SonineRelaxation, SonineState};
use granular::theory::sonine;

/// Grains per sample.
const GRAINS: usize = 50_000;
/// Restitution.
const RESTITUTION: f64 = 0.3;
/// The DSMC step in mean free times at T = 1.
const STEP: f64 = 0.01;

/// The dilute periodic gas of `GRAINS` disks under white noise of `strength`, with a DSMC
/// step `step`.
fn scenario(strength: f64, step: f64, seed: u64) -> Scenario {
    let text = format!(
        r#"
engine = "dsmc"
dimension = 2
seed = {seed}
box = {{ boundary = "periodic" }}
[[species]]
name = "grain"
count = {GRAINS}
packing_fraction = 0.01
velocity = {{ distribution = "maxwell_boltzmann", temperature = 1.0 }}
[collisions]
restitution = {RESTITUTION}
[driving]
kind = "white_noise"
strength = {strength}
[dsmc]
time_step = {step}
cell_size = 0.02
[stop]
time = 1e6
[output]
interval = 1e5
"#
    );
    Scenario::from_toml_insisting(&text, &[]).expect("scenario")
}

/// KT-14 and KT-15 for the gas of `sc` (dilute: χ = 1; the kick fraction of its `N`).
fn theory(sc: &Scenario) -> SonineRelaxation {
    let n = sc.particle_count();
    SonineRelaxation::new(2, RESTITUTION, 1.0, n as f64, sc.radius(0), 1.0, Some(n))
}

/// Velocities of `n` grains in 2D at temperature `t` (m = 1) with Sonine coefficient
/// about `a2`: `a2 > 0` a mixture of two Maxwellians at `T (1 ± sqrt(a2))`; `a2 < 0` a
/// mixture of grains at one speed (a2 = -1/2 in 2D) and Maxwellian ones. Zero momentum,
/// exactly `t`.
fn velocities(n: usize, t: f64, a2: f64, seed: u64) -> Vec<f64> {
    use rand::{RngExt, SeedableRng};
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut v = Vec::with_capacity(2 * n);
    for _ in 0..n {
        let (gx, gy): (f64, f64) = (
            StandardNormal.sample(&mut rng),
            StandardNormal.sample(&mut rng),
        );
        let (x, y) = if a2 >= 0.0 {
            let s = if rng.random::<bool>() {
                1.0 + a2.sqrt()
            } else {
                1.0 - a2.sqrt()
            };
            (gx * s.sqrt(), gy * s.sqrt())
        } else if rng.random::<f64>() < -2.0 * a2 {
            // Speed sqrt(2) (<v²> = 2 T at T = 1 in 2D), random direction.
            let phi = rng.random::<f64>() * std::f64::consts::TAU;
            (2f64.sqrt() * phi.cos(), 2f64.sqrt() * phi.sin())
        } else {
            (gx, gy)
        };
        v.push(x);
        v.push(y);
    }
    let (mx, my) = (
        v.iter().step_by(2).sum::<f64>() / n as f64,
        v.iter().skip(1).step_by(2).sum::<f64>() / n as f64,
    );
    for (i, x) in v.iter_mut().enumerate() {
        *x -= if i % 2 == 0 { mx } else { my };
    }
    let now = v.iter().map(|x| x * x).sum::<f64>() / (2.0 * n as f64);
    let scale = (t / now).sqrt();
    v.iter_mut().for_each(|x| *x *= scale);
    v
}

fn positions(n: usize, seed: u64) -> Vec<f64> {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..2 * n).map(|_| rng.random::<f64>()).collect()
}

/// The first time at which `diff` (at `times`) changes sign, from a straight line fitted
/// to the points within `half` of `guess`.
fn crossing(times: &[f64], diff: &[f64], guess: f64, half: f64) -> f64 {
    let pts: Vec<(f64, f64)> = times
        .iter()
        .zip(diff)
        .filter(|(t, _)| (**t - guess).abs() <= half)
        .map(|(t, d)| (*t, *d))
        .collect();
    let n = pts.len() as f64;
    let (mt, md) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = pts.iter().map(|p| (p.0 - mt) * (p.1 - md)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    mt - md / slope
}

/// Mean and standard error of the mean of independent values.
fn mean_and_error(x: &[f64]) -> (f64, f64) {
    let mut stats = granular::stats::RunningStats::new();
    x.iter().for_each(|v| stats.push(*v));
    (stats.mean(), stats.standard_error())
}

/// The Mpemba effect: the hotter sample A, with the larger `a2`, crosses the colder B and
/// stays colder; the crossing time and the late difference against KT-14/KT-15.
#[test]
fn the_hotter_sample_cools_faster_and_crosses() {
    let probe = scenario(1.0, 1e-6, 1);
    let th = theory(&probe);
    let w1 = th.collision_frequency_at_unit_temperature;
    let strength = th.strength_for_temperature(0.1);
    let step = STEP / w1;
    // Output times, in units of the mean free time at T = 1.
    let times: Vec<f64> = (1..=40).map(|k| 0.1 * k as f64).collect();
    let late = |t: f64| (2.5..=4.0).contains(&t);
    let (mut crossings, mut lates, mut theory_crossings, mut theory_lates) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for pair in 0..4u64 {
        let sc = scenario(strength, step, 10 + pair);
        let x = positions(GRAINS, 100 + pair);
        let mut samples = Vec::new();
        for (temperature, a2, seed) in [(1.05, 0.3, 200 + pair), (1.0, -0.3, 300 + pair)] {
            let v = velocities(GRAINS, temperature, a2, seed);
            let sim = Simulation::from_state(sc.clone(), 0.0, &x, &v).expect("state");
            let o = sim.observe();
            let start = SonineState {
                temperature: o.temperature,
                a2: o.a2.expect("a2"),
            };
            samples.push((sim, start));
        }
        let mut diff = Vec::new();
        let mut theory_diff = Vec::new();
        for &t in &times {
            let mut temps = [0.0; 2];
            let mut theory_temps = [0.0; 2];
            for (k, (sim, start)) in samples.iter_mut().enumerate() {
                sim.advance(t / w1).expect("advance");
                temps[k] = sim.observe().temperature;
                theory_temps[k] = th.evolve(*start, strength, t / w1).temperature;
            }
            diff.push(temps[0] / temps[1] - 1.0);
            theory_diff.push(theory_temps[0] / theory_temps[1] - 1.0);
        }
        assert!(diff[0] > 0.03, "A starts hotter: {}", diff[0]);
        let t_cross = crossing(&times, &theory_diff, 1.2, 0.15);
        theory_crossings.push(t_cross);
        crossings.push(crossing(&times, &diff, t_cross, 0.6));
        let mean_late = |d: &[f64]| {
            let w: Vec<f64> = times
                .iter()
                .zip(d)
                .filter(|(t, _)| late(**t))
                .map(|(_, v)| *v)
                .collect();
            w.iter().sum::<f64>() / w.len() as f64
        };
        lates.push(mean_late(&diff));
        theory_lates.push(mean_late(&theory_diff));
    }
    let (late, late_se) = mean_and_error(&lates);
    let (cross, cross_se) = mean_and_error(&crossings);
    let theory_late = mean_and_error(&theory_lates).0;
    let theory_cross = mean_and_error(&theory_crossings).0;
    eprintln!(
        "Mpemba (2D, α = {RESTITUTION}): crossing at {cross:.3} ± {cross_se:.3} mean free \
         times (theory {theory_cross:.3}); late T_A/T_B - 1 = {late:.4} ± {late_se:.4} \
         (theory {theory_late:.4})"
    );
    // The effect itself: A ends colder than B, far beyond the noise.
    assert!(
        late < -5.0 * late_se && late < -0.01,
        "A stays colder: {late} ± {late_se}"
    );
    // Against the first Sonine relaxation (15 % its own accuracy here, see the module).
    let sonine_error = (sonine::cooling_a2_first(2, RESTITUTION)
        - sonine::cooling_a2_second(2, RESTITUTION))
    .abs()
        / sonine::cooling_a2_first(2, RESTITUTION);
    assert!(sonine_error < 0.16, "{sonine_error}");
    for (what, (m, se), th) in [
        ("crossing time", (cross, cross_se), theory_cross),
        ("late T_A/T_B - 1", (late, late_se), theory_late),
    ] {
        assert!(
            (m - th).abs() < STANDARD_ERRORS * se + sonine_error * th.abs(),
            "{what}: {m} ± {se}, theory {th} (allowed {STANDARD_ERRORS} se + {sonine_error:.3} of it)"
        );
    }
}
