//! Disk (2D) and sphere (3D) intruders against exact results: the Martin-Piasecki
//! temperature G-40, the Maxwellian kurtosis G-41 and mean collision rate G-42, the
//! Maxwellian histograms; the direct (G-36) and thinning (G-38) samplers against each
//! other; the DSMC twin (G-45) against the Gillespie engine, also in a power-law bath.
//!
//! Tolerances: `Z` batch-means standard errors (fixed seeds). Run lengths from the measured
//! variance: 4 x 10^5 collisions give a standard error of about 0.4 % on `T/T_B` (the
//! autocorrelation of `|V|^2` spans a few relaxation times), well below the differences
//! between the cases tested.

use granular::intruder::ball::{
    Ball, BallConfig, BallDsmcTwin, BallDsmcTwinConfig, BallMethod, BallSummary,
    IsotropicBathConfig,
};
use granular::intruder::observables::Estimate;
use granular::intruder::theory::martin_piasecki_ratio;
use granular::stats::chi_square_test;
use granular::theory::equilibrium::speed_cdf;
use granular::theory::intruder::{maxwellian_kurtosis, maxwellian_mean_collision_rate};

const Z: f64 = 4.0;
const P_MIN: f64 = 1e-4;

fn assert_within(e: Estimate, want: f64, what: &str) {
    assert!(
        e.error.is_finite() && e.error > 0.0,
        "{what}: no error bar {e:?}"
    );
    assert!(
        (e.mean - want).abs() <= Z * e.error,
        "{what}: {} +- {} vs {want} (z = {:.2})",
        e.mean,
        e.error,
        e.z_score(want)
    );
}

/// Two estimates agree within `Z` combined errors.
fn assert_agree(a: Estimate, b: Estimate, what: &str) {
    let err = a.error.hypot(b.error);
    assert!(err.is_finite() && err > 0.0, "{what}: no error bars");
    assert!(
        (a.mean - b.mean).abs() <= Z * err,
        "{what}: {} +- {} vs {} +- {} (z = {:.2})",
        a.mean,
        a.error,
        b.mean,
        b.error,
        (a.mean - b.mean) / err
    );
}

fn run(dimension: usize, cfg: &BallConfig, seed: u64, collisions: u64) -> BallSummary {
    if dimension == 2 {
        let mut e = Ball::<2>::new(cfg, seed).unwrap();
        e.run_collisions(collisions).unwrap();
        e.summary()
    } else {
        let mut e = Ball::<3>::new(cfg, seed).unwrap();
        e.run_collisions(collisions).unwrap();
        e.summary()
    }
}

fn run_twin(dimension: usize, cfg: &BallDsmcTwinConfig, seed: u64, collisions: u64) -> BallSummary {
    if dimension == 2 {
        let mut e = BallDsmcTwin::<2>::new(cfg, seed).unwrap();
        e.run_collisions(collisions);
        e.summary()
    } else {
        let mut e = BallDsmcTwin::<3>::new(cfg, seed).unwrap();
        e.run_collisions(collisions);
        e.summary()
    }
}

/// The theory checks of a Gaussian-bath run: G-40, G-41, G-42.
fn check_maxwellian(s: &BallSummary, cfg: &BallConfig, what: &str) {
    let d = s.dimension;
    let t_b = match cfg.bath {
        IsotropicBathConfig::Gaussian { temperature } => temperature,
        _ => unreachable!(),
    };
    let ratio = martin_piasecki_ratio(cfg.restitution, cfg.mass, cfg.bath_mass);
    assert_within(s.temperature_ratio, ratio, &format!("{what}: T/T_B"));
    assert_within(
        s.kurtosis,
        maxwellian_kurtosis(d),
        &format!("{what}: kurtosis"),
    );
    let rate = maxwellian_mean_collision_rate(
        d,
        cfg.radius,
        cfg.bath_density,
        t_b,
        cfg.bath_mass,
        ratio * t_b,
        cfg.mass,
    );
    assert!((s.theory_collision_rate - rate).abs() <= 1e-12 * rate);
    assert_within(s.collision_rate, rate, &format!("{what}: collision rate"));
}

/// G-40 for M/m in {0.5, 1, 2} and alpha in {0.2, 0.5, 0.8}, in 2D and 3D, with the
/// kurtosis G-41 and the mean collision rate G-42 of each run.
#[test]
fn martin_piasecki_ratio_kurtosis_and_rate_in_two_and_three_dimensions() {
    let mut seed = 100;
    for dimension in [2usize, 3] {
        for mass in [0.5, 1.0, 2.0] {
            for alpha in [0.2, 0.5, 0.8] {
                let cfg = BallConfig {
                    radius: 0.7,
                    mass,
                    bath_mass: 1.0,
                    restitution: alpha,
                    bath_density: 1.3,
                    bath: IsotropicBathConfig::Gaussian { temperature: 0.8 },
                    initial_velocity: vec![1.5; dimension],
                    ..Default::default()
                };
                seed += 1;
                let s = run(dimension, &cfg, seed, 400_000);
                check_maxwellian(
                    &s,
                    &cfg,
                    &format!("d = {dimension}, M = {mass}, alpha = {alpha}"),
                );
            }
        }
    }
}

/// The paper's direct sampler (closed-form rate G-33, impact normal G-36, normal velocity
/// G-12) gives the same stationary state.
#[test]
fn direct_method_gives_the_same_stationary_state() {
    for (i, dimension) in [2usize, 3].into_iter().enumerate() {
        let cfg = BallConfig {
            mass: 0.5,
            restitution: 0.3,
            method: BallMethod::Direct,
            bath: IsotropicBathConfig::Gaussian { temperature: 1.1 },
            ..Default::default()
        };
        let s = run(dimension, &cfg, 7 + i as u64, 300_000);
        check_maxwellian(&s, &cfg, &format!("direct, d = {dimension}"));
    }
}

/// The component and speed histograms are those of the Maxwellian at the G-40 temperature
/// (Pearson's test; grid spacing of 20 relaxation times, so the samples are independent).
#[test]
fn histograms_are_the_maxwellian_of_the_theory() {
    for (i, dimension) in [2usize, 3].into_iter().enumerate() {
        let base = BallConfig {
            mass: 2.0,
            restitution: 0.4,
            bath: IsotropicBathConfig::Gaussian { temperature: 1.0 },
            histogram_bins: 40,
            ..Default::default()
        };
        // Relaxation time d (m + M)/((1 + alpha) m rho sigma <c>), here about 10.
        let cfg = BallConfig {
            sample_interval: Some(200.0),
            ..base
        };
        let s = run(dimension, &cfg, 31 + i as u64, 1_500_000);
        let t = martin_piasecki_ratio(cfg.restitution, cfg.mass, cfg.bath_mass);
        let sd = (t / cfg.mass).sqrt();
        for (k, h) in s.component_histograms.iter().enumerate() {
            let c = chi_square_test(h, |x| {
                0.5 * libm::erfc(-x / (sd * std::f64::consts::SQRT_2))
            });
            assert!(c.p_value > P_MIN, "d = {dimension}, component {k}: {c:?}");
        }
        let c = chi_square_test(&s.speed_histogram, |c| speed_cdf(dimension, c, cfg.mass, t));
        assert!(c.p_value > P_MIN, "d = {dimension}, speed: {c:?}");
        assert!(s.samples > 5_000, "{} samples", s.samples);
    }
}

/// A tabulated speed distribution (the Maxwell speed law at 600 points) behaves as the
/// Gaussian bath (G-40 within the errors; the table's interpolation error is ~1e-5).
#[test]
fn tabulated_maxwell_speeds_follow_martin_piasecki() {
    for (i, dimension) in [2usize, 3].into_iter().enumerate() {
        let t_b: f64 = 0.5;
        let hi = 8.0 * t_b.sqrt();
        let points: Vec<(f64, f64)> = (0..=600)
            .map(|k| {
                let c = hi * k as f64 / 600.0;
                (
                    c,
                    granular::theory::equilibrium::speed_density(dimension, c, 1.0, t_b),
                )
            })
            .collect();
        let cfg = BallConfig {
            restitution: 0.5,
            bath: IsotropicBathConfig::Tabulated { points },
            ..Default::default()
        };
        let s = run(dimension, &cfg, 51 + i as u64, 400_000);
        assert_within(
            s.temperature_ratio,
            martin_piasecki_ratio(0.5, 1.0, 1.0),
            &format!("tabulated, d = {dimension}"),
        );
        assert_within(
            s.kurtosis,
            maxwellian_kurtosis(dimension),
            "tabulated kurtosis",
        );
    }
}

/// The DSMC twin (G-45) reaches the Martin-Piasecki state of the Gaussian bath.
#[test]
fn dsmc_twin_follows_martin_piasecki() {
    for (i, dimension) in [2usize, 3].into_iter().enumerate() {
        let cfg = BallDsmcTwinConfig {
            ball: BallConfig {
                mass: 2.0,
                restitution: 0.2,
                bath: IsotropicBathConfig::Gaussian { temperature: 0.5 },
                ..Default::default()
            },
            bath_particles: 5_000,
        };
        let s = run_twin(dimension, &cfg, 61 + i as u64, 200_000);
        check_maxwellian(&s, &cfg.ball, &format!("twin, d = {dimension}"));
    }
}

/// Power-law bath (G-43): no theory, the Gillespie engine against its DSMC twin. The
/// intruder inherits the `|V|^-4` tail, so `<|V|^4>` diverges and the batch-means error of
/// the temperature is not valid; compared are the collision rate and the truncated
/// temperature `M <min(|V|^2, h^2)>/d` (bounded), both with valid errors.
#[test]
fn power_law_bath_gillespie_agrees_with_dsmc_twin() {
    for (i, dimension) in [2usize, 3].into_iter().enumerate() {
        let ball = BallConfig {
            mass: 1.0,
            restitution: 0.5,
            bath: IsotropicBathConfig::PowerLaw { temperature: 0.5 },
            ..Default::default()
        };
        let g = run(dimension, &ball, 71 + i as u64, 400_000);
        let twin = BallDsmcTwinConfig {
            ball: ball.clone(),
            bath_particles: 5_000,
        };
        let t = run_twin(dimension, &twin, 81 + i as u64, 150_000);
        let what = format!("power law, d = {dimension}");
        assert_agree(g.collision_rate, t.collision_rate, &format!("{what}: rate"));
        assert_agree(
            g.truncated_temperature,
            t.truncated_temperature,
            &format!("{what}: truncated temperature"),
        );
        // And the power-law bath heats the intruder more than the Gaussian bath would.
        let gaussian = martin_piasecki_ratio(0.5, 1.0, 1.0);
        assert!(g.temperature_ratio.mean > gaussian + 0.05, "{what}: {g:?}");
    }
}
