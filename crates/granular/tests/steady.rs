//! Steady states of a dilute granular gas with DSMC (`[driving]`, `granular::driving`):
//! the homogeneous cooling state sampled by velocity rescaling, the white-noise heated gas,
//! and the freely cooling gas's `a2(t)`, against the Sonine theory of van Noije and Ernst
//! (1998). Dilute DSMC without the Enskog factor solves the Boltzmann equation, so these
//! are the exact tests of the theory, up to its own truncation.
//!
//! Tolerances: 4 standard errors of the run's mean from 10 batch means (each batch of at
//! least 3.5 collisions per grain, several times the relaxation time of `a2` and `T`, which
//! is about one mean free time), plus, for `a2`, the truncation error of the linear Sonine
//! estimates (`SONINE_TRUNCATION`); both shared with the event-driven tests
//! (`crate::common`).

use crate::common::{
    SONINE_TRUNCATION, STANDARD_ERRORS, assert_within_errors, batch_estimate as estimate,
    scenario_text,
};
use granular::collision_law::CollisionLaw;
use granular::driving::{Driving, GasTheory};
use granular::dsmc::{DsmcConfig, DsmcEngine};
use granular::engine::Engine;
use granular::theory::{haff, sonine};
use granular::{AxisKind, SimulationBox, Vector};
use std::f64::consts::SQRT_2;

/// The time step in mean free times. DSMC's collisional loss per step has a bias below
/// `0.75 zeta tau` (`docs/dsmc.md`, the Haff test), 0.3 % here: below the Sonine
/// correction `3 a2/16` (1.4 % at `e = 0.5`) that the cooling rate resolves.
const STEP: f64 = 0.01;

/// The bound `0.75 zeta tau` on the relative bias of DSMC's loss rate (see [`STEP`]).
fn loss_bias(zeta: f64, eng: &DsmcEngine<2>) -> f64 {
    0.75 * zeta * eng.time_step()
}

/// Grains and radius of a unit periodic box of 2 mean free paths (no clustering).
fn dilute_gas<const D: usize>(n: usize, e: f64, seed: u64) -> DsmcEngine<D> {
    let sigma = 2.0 / (SQRT_2 * n as f64);
    let r = if D == 2 {
        sigma / 4.0
    } else {
        (sigma / std::f64::consts::PI).sqrt() / 2.0
    };
    let omega = haff::collision_frequency(D, n as f64, r, 1.0, 1.0, 1.0);
    let cfg = DsmcConfig {
        // STEP mean free times at T = 1, the steady temperature of both states here.
        time_step: Some(STEP / omega),
        cell_size: Some(0.25),
        law: CollisionLaw::uniform(e),
        ..DsmcConfig::default()
    };
    let bx = SimulationBox::uniform(Vector([1.0; D]), AxisKind::Periodic);
    DsmcEngine::<D>::new(cfg, bx, n, r, 1.0, 1.0, seed).expect("valid set-up")
}

/// The gas's kinetic theory (dilute: `chi = 1`).
fn theory<const D: usize>(e: &DsmcEngine<D>) -> GasTheory {
    GasTheory {
        dimension: D,
        restitution: e.config().law.restitution,
        number_density: e.number_density(),
        radius: e.radius(),
        mass: e.mass(),
        chi: 1.0,
        particles: e.particle_count(),
    }
}

/// Runs `relax` then `sample` collisions per grain, recording every tenth of a mean free time
/// (at `T = 1`) `a2`, `T` and the window's cooling rate `zeta = 2 (energy lost) / (D N T
/// dt)` (the energy lost from the driving's tally, `dissipated`); returns their blocking
/// series.
fn sample<const D: usize>(eng: &mut DsmcEngine<D>, relax: f64, sample: f64) -> [Vec<f64>; 3] {
    let n = eng.particle_count() as f64;
    let omega = haff::collision_frequency(D, eng.number_density(), eng.radius(), 1.0, 1.0, 1.0);
    let cpp = |e: &DsmcEngine<D>| 2.0 * e.collisions() as f64 / n;
    let lost = |e: &DsmcEngine<D>| {
        e.driving()
            .map_or(0.0, |s| s.dissipated(e.kinetic_energy()))
    };
    let mut out = [Vec::new(), Vec::new(), Vec::new()];
    let (mut t, dt) = (0.0, 0.1 / omega);
    loop {
        let before = lost(eng);
        t += dt;
        eng.advance(t, u64::MAX).expect("finite");
        let c = cpp(eng);
        if c >= relax + sample {
            return out;
        }
        if c >= relax {
            let temp = eng.temperature();
            out[0].push(eng.a2());
            out[1].push(temp);
            out[2].push(2.0 * (lost(eng) - before) / (D as f64 * n * temp * dt));
        }
    }
}

/// Velocity rescaling samples the homogeneous cooling state: `a2` follows van Noije and
/// Ernst's second estimate (2D, `e = 0.5`, where `a2 = 0.077` is well resolved), the
/// temperature stays at `T*` after every step, momentum stays zero, and the measured
/// cooling rate (energy put back per unit time) is the Sonine `zeta(T*)`.
#[test]
fn rescaled_dsmc_samples_the_homogeneous_cooling_state() {
    let e = 0.5;
    let mut eng = dilute_gas::<2>(20_000, e, 11);
    eng.set_driving(Some(Driving::Rescale { temperature: 1.0 }));
    let [a2, temp, zeta] = sample(&mut eng, 5.0, 40.0);
    let (a2, sd) = estimate(&a2);
    let second = sonine::cooling_a2_second(2, e);
    eprintln!("rescaled HCS: a2 = {a2} ± {sd}, second estimate {second}");
    assert_within_errors("a2 (second estimate)", (a2, sd), second, SONINE_TRUNCATION);
    // The temperature is the target after every step (its series has no variance).
    let t = temp.iter().sum::<f64>() / temp.len() as f64;
    assert!((t - 1.0).abs() < 1e-12, "T = {t}");
    assert!(eng.mean_velocity().norm() < 1e-12);
    // Energy bookkeeping: injected = dissipated (K is back at its value after every step).
    let s = eng.driving().expect("driven");
    let dissipated = s.dissipated(eng.kinetic_energy());
    assert!((dissipated - s.injected_energy).abs() < 1e-9 * s.injected_energy);
    // Cooling rate: the energy put back per unit time over (D/2) N T*, against
    // zeta0 (1 + 3 a2/16) with the second estimate (whose truncation moves it by
    // 3/16 SONINE_TRUNCATION relative), less the time-step bias.
    let (zeta, sd) = estimate(&zeta);
    let zeta_theory = theory(&eng).cooling_rate(1.0, second);
    eprintln!("rescaled HCS: zeta = {zeta} ± {sd}, theory {zeta_theory}");
    let model = (3.0 / 16.0 * SONINE_TRUNCATION + loss_bias(zeta_theory, &eng)) * zeta_theory;
    assert_within_errors("zeta", (zeta, sd), zeta_theory, model);
}

/// The white-noise heated gas: `a2` follows van Noije and Ernst's heated-gas estimate
/// (2D, `e = 0.5`: `a2 = 0.036`), momentum stays exactly zero, and the steady temperature
/// is that of the exact energy balance `(D/2) m xi0² (N - 1) = (D/2) N zeta(T) T` with the
/// Sonine loss rate (the strength is chosen for `T = 1`).
#[test]
fn white_noise_dsmc_reaches_the_heated_steady_state() {
    let e = 0.5;
    let mut eng = dilute_gas::<2>(20_000, e, 12);
    let th = theory(&eng);
    let wn = sonine::white_noise_a2(2, e);
    // xi0² for T = 1: m xi0² (1 - 1/N) = zeta(1) * 1.
    let strength = th.cooling_rate(1.0, wn) / (1.0 - 1.0 / 20_000.0);
    let driving = Driving::WhiteNoise { strength };
    eng.set_driving(Some(driving.clone()));
    let [a2, temp, zeta] = sample(&mut eng, 8.0, 40.0);
    let (a2, sd) = estimate(&a2);
    eprintln!("white noise: a2 = {a2} ± {sd}, estimate {wn}");
    assert_within_errors("a2 (heated-gas estimate)", (a2, sd), wn, SONINE_TRUNCATION);
    // Away from the HCS value: the two states are told apart.
    let hcs = sonine::cooling_a2_second(2, e);
    assert!(
        (a2 - hcs).abs() > STANDARD_ERRORS * sd + SONINE_TRUNCATION,
        "a2 = {a2} ± {sd}"
    );
    assert!(
        eng.mean_velocity().norm() < 1e-12,
        "{:?}",
        eng.mean_velocity()
    );
    let (t, sd_t) = estimate(&temp);
    let t_theory = th.white_noise_temperature(strength, th.a2(&driving));
    eprintln!("white noise: T = {t} ± {sd_t}, energy balance {t_theory}");
    // The Sonine truncation moves the loss rate by 3/16 SONINE_TRUNCATION and the time
    // step by up to `loss_bias`, so T by 2/3 of their sum (T^(3/2) ~ 1 / loss rate).
    let model =
        2.0 / 3.0 * (3.0 / 16.0 * SONINE_TRUNCATION + loss_bias(th.cooling_rate(1.0, wn), &eng));
    assert_within_errors("T (energy balance)", (t, sd_t), t_theory, model * t_theory);
    // Energy balance in the mean: the loss rate equals the heating power.
    let (zeta, sd_z) = estimate(&zeta);
    let heating = strength * (1.0 - 1.0 / 20_000.0);
    eprintln!(
        "white noise: zeta T = {} ± {}, heating {heating}",
        zeta * t,
        sd_z * t
    );
    assert!(
        (zeta * t - heating).abs() < STANDARD_ERRORS * (sd_z * t + sd_t * zeta),
        "zeta T = {}, heating {heating}",
        zeta * t
    );
}

/// A freely cooling dilute gas: after the transient (5 collisions per grain), `a2(t)`
/// stays at van Noije and Ernst's second HCS estimate for tens of collisions per grain
/// while the temperature drops a hundredfold (2D, `e = 0.5`; the time step follows the
/// mean free time).
#[test]
fn freely_cooling_dsmc_a2_follows_the_second_estimate() {
    let e = 0.5;
    let n = 20_000;
    let mut eng = dilute_gas::<2>(n, e, 13);
    let mut a2 = Vec::new();
    let cpp = |e: &DsmcEngine<2>| 2.0 * e.collisions() as f64 / n as f64;
    while cpp(&eng) < 40.0 {
        // A twentieth of the mean free time at the current temperature.
        let omega = haff::collision_frequency(
            2,
            eng.number_density(),
            eng.radius(),
            eng.temperature(),
            1.0,
            1.0,
        );
        eng.step(0.05 / omega);
        if cpp(&eng) >= 5.0 {
            a2.push(eng.a2());
        }
    }
    assert!(eng.temperature() < 0.01, "T = {}", eng.temperature());
    let (a2, sd) = estimate(&a2);
    let second = sonine::cooling_a2_second(2, e);
    eprintln!("free cooling: a2 = {a2} ± {sd}, second estimate {second}");
    assert_within_errors("a2 (second estimate)", (a2, sd), second, SONINE_TRUNCATION);
}

/// Runs `scenario` to its end in a fresh run directory named after `tag` and the process,
/// checks that the time series has every one of `columns`, removes the directory and
/// returns the summary.
pub(crate) fn run_with_columns(
    tag: &str,
    scenario: granular::scenario::Scenario,
    columns: &[&str],
) -> granular::run::Summary {
    let dir = std::env::temp_dir().join(format!("{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let summary = granular::run::Run::create(&dir, scenario)
        .unwrap()
        .run_to_end(&mut |_| {}, None)
        .unwrap();
    let header = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let header = header.lines().next().unwrap();
    for c in columns {
        assert!(header.split(',').any(|h| h == *c), "{c} in {header}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    summary
}

/// A bundled driven scenario, shrunk by `overrides`.
pub(crate) fn bundled(name: &str, overrides: &[&str]) -> granular::scenario::Scenario {
    let text = scenario_text(&format!("{name}.toml"));
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    granular::scenario::Scenario::from_toml(&text, &o).expect("valid")
}

/// Both drivings resume from a checkpoint in the middle of an output interval bit for bit
/// (the kick stream index and the energy tally are in the checkpoint). The step is 0.2,
/// 0.07 mean free times of the 3000 grains (the bundled 0.004 is 0.5 % of the 20 000
/// grains' one): 1 800 steps, each driven, per chunk of 200 000 events instead of 60 000.
#[test]
fn driven_dsmc_resumes_bit_identical() {
    for name in ["dsmc-hcs-rescaled", "dsmc-white-noise"] {
        let s = bundled(
            name,
            &[
                "species[0].count=3000",
                "dsmc.time_step=0.2",
                "output.interval=1e6",
                "output.checkpoint_seconds=1e-9",
                "stop.events=800000",
            ],
        );
        crate::spine::assert_resume_mid_interval(name, s);
    }
}

/// A white-noise run writes the driving's columns and the `steady_state` block, with the
/// heated gas's Sonine `a2` and the energy-balance temperature beside the measurements.
#[test]
fn white_noise_run_reports_its_steady_state() {
    let s = bundled(
        "dsmc-white-noise",
        &["species[0].count=4000", "stop.collisions_per_particle=30"],
    );
    let summary = run_with_columns(
        "granular-steady",
        s,
        &[
            "dissipated_energy",
            "injected_energy",
            "driving_power",
            "dissipation_rate",
            "cooling_rate",
        ],
    );
    let st = summary.steady_state.expect("steady_state block");
    assert_eq!(st.kind, "white_noise");
    assert_eq!(st.theory_a2, sonine::white_noise_a2(2, 0.5));
    assert_eq!(st.chi, 1.0);
    // The energy balance for the bundled strength (1) and radius with 4000 grains; the
    // physics is tested above, this is the plumbing: the block holds the run averages.
    let gas = GasTheory {
        dimension: 2,
        restitution: 0.5,
        number_density: 4000.0,
        radius: 1.7678e-5,
        mass: 1.0,
        chi: 1.0,
        particles: 4000,
    };
    let expected = gas.white_noise_temperature(1.0, st.theory_a2);
    assert!(
        (st.theory_temperature / expected - 1.0).abs() < 1e-12,
        "{} {expected}",
        st.theory_temperature
    );
    let averages = summary.averages.expect("averages");
    assert_eq!(
        st.temperature.as_ref(),
        averages.observables.get("temperature")
    );
    assert_eq!(st.a2.as_ref(), averages.observables.get("a2"));
    let zeta = st.cooling_rate.expect("cooling rate averaged");
    assert!(zeta.samples > 10 && zeta.mean > 0.0, "{zeta:?}");
}
