//! The data of the paper's figures, as tables of named columns, with the theory overlaid
//! where it exists. Every simulated point `i` of a sweep uses the stream
//! `stream(seed, [MEMBER, i])`, and sweeps run in parallel with rayon, so the tables do not
//! depend on the number of threads. `collisions` is the number of collisions simulated per
//! point (the transient included); the paper uses 5e5 (Fig. 3) to 5e6 (Fig. 8).

use rayon::prelude::*;

use super::bath::{Bath, BathConfig, BathDistribution, Gaussian, Side};
use super::needle::{Needle, NeedleConfig, NeedleSummary};
use super::observables::Table;
use super::one_d::{Intruder1d, Intruder1dConfig, Intruder1dParams, Intruder1dSummary};
use super::theory::martin_piasecki_ratio;
use crate::random::{MEMBER, RngExt, stream};
use crate::stats::Histogram;

/// `n` evenly spaced values from `lo` to `hi` inclusive.
pub fn linspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if n < 2 {
        return vec![lo];
    }
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The restitution values of the paper's sweeps: 0, 0.1, ..., 1.
pub fn alpha_grid() -> Vec<f64> {
    (0..=10).map(|i| i as f64 / 10.0).collect()
}

fn run_1d(cfg: &Intruder1dConfig, collisions: u64, seed: u64, index: u64) -> Intruder1dSummary {
    let params = match Intruder1dParams::new(cfg) {
        Ok(p) => p,
        Err(e) => panic!("figure configuration is invalid: {e}"),
    };
    let mut e = Intruder1d::with_params(
        params,
        cfg,
        stream(seed, &[MEMBER, index]),
        cfg.initial_velocity,
    );
    e.run_collisions(collisions);
    e.summary()
}

fn run_needle(cfg: &NeedleConfig, collisions: u64, seed: u64, index: u64) -> NeedleSummary {
    let mut n = match Needle::new(cfg, crate::random::derive_key(seed, &[MEMBER, index])) {
        Ok(n) => n,
        Err(e) => panic!("figure configuration is invalid: {e}"),
    };
    if let Err(e) = n.run_collisions(collisions) {
        panic!("needle run failed: {e}");
    }
    n.summary()
}

/// Fig. 1: total collision rate `phi(v1)/rho` (G-16) for `a = 0.5, 1, 2, 4` on
/// `v1 in [-3, 3]`, with a Monte Carlo estimate of each value: `collisions` candidate events
/// of the thinning sampler at fixed `v1`, `phi = rho (|v1| + <|v|>) * acceptance`.
pub fn fig1_flux(points: usize, collisions: u64, seed: u64) -> Table {
    let v1s = linspace(-3.0, 3.0, points);
    let mut t = Table::new("Fig. 1: collision rate phi(v1)/rho of a Gaussian bath (Eq. 16)");
    t.push("v1", v1s.clone());
    for (ia, &a) in [0.5, 1.0, 2.0, 4.0].iter().enumerate() {
        let g = Gaussian::new(a).unwrap_or_else(|e| panic!("{e}"));
        t.push(
            format!("phi_a{a}"),
            v1s.iter().map(|&v| g.flux(v)).collect(),
        );
        t.push(
            format!("phi_plus_a{a}"),
            v1s.iter().map(|&v| g.flux_plus(v)).collect(),
        );
        let mc: Vec<f64> = v1s
            .par_iter()
            .enumerate()
            .map(|(i, &v1)| {
                let mut rng = stream(seed, &[MEMBER, ia as u64, i as u64]);
                let mut acc = 0u64;
                for _ in 0..collisions {
                    let bound = v1.abs() + g.mean_speed();
                    let v = if rng.random::<f64>() * bound < v1.abs() {
                        g.sample(&mut rng)
                    } else {
                        g.sample_speed_weighted(&mut rng)
                    };
                    if rng.random::<f64>() * (v1.abs() + v.abs()) < (v - v1).abs() {
                        acc += 1;
                    }
                }
                (v1.abs() + g.mean_speed()) * acc as f64 / collisions.max(1) as f64
            })
            .collect();
        t.push(format!("phi_mc_a{a}"), mc);
    }
    t
}

/// Fig. 2: density `g_+(v, v1)` of the bath velocities colliding with the right side
/// (G-12), `a = 1`, `v1 = -2, -1, 0, 1, 2`: theory and a histogram of `collisions` draws
/// of the exact sampler, on 100 bins of `[-5, 3]`.
pub fn fig2_colliding_velocities(collisions: u64, seed: u64) -> Table {
    let g = Bath::Gaussian(Gaussian::new(1.0).unwrap_or_else(|e| panic!("{e}")));
    let bins = 100;
    let proto = Histogram::new(-5.0, 3.0, bins);
    let centres: Vec<f64> = (0..bins).map(|i| proto.bin_center(i)).collect();
    let mut t = Table::new("Fig. 2: colliding bath velocity density g_+(v, v1), Eq. 12");
    t.push("v", centres.clone());
    let v1s = [-2.0, -1.0, 0.0, 1.0, 2.0];
    let hists: Vec<Vec<f64>> = v1s
        .par_iter()
        .enumerate()
        .map(|(i, &v1)| {
            let mut rng = stream(seed, &[MEMBER, i as u64]);
            let mut h = proto.clone();
            for _ in 0..collisions {
                h.push(g.sample_colliding(Side::Right, v1, &mut rng));
            }
            h.density()
        })
        .collect();
    for (k, &v1) in v1s.iter().enumerate() {
        t.push(
            format!("g_theory_v1={v1}"),
            centres
                .iter()
                .map(|&v| g.colliding_density(Side::Right, v1, v))
                .collect(),
        );
        t.push(format!("g_sampled_v1={v1}"), hists[k].clone());
    }
    t
}

/// `T/T_B` of the 1D intruder at each `alpha` (the other fields from `base`); point `i` uses
/// the stream `stream(seed, [MEMBER, offset + i])`.
pub(crate) fn ratio_sweep(
    base: &Intruder1dConfig,
    alphas: &[f64],
    collisions: u64,
    seed: u64,
    offset: u64,
) -> Vec<Intruder1dSummary> {
    alphas
        .par_iter()
        .enumerate()
        .map(|(i, &alpha)| {
            let cfg = Intruder1dConfig {
                restitution: alpha,
                ..base.clone()
            };
            run_1d(&cfg, collisions, seed, offset + i as u64)
        })
        .collect()
}

/// Fig. 3: `T/T_B` versus `alpha` for `M = m = 1`, Gaussian bath `a = 1`, with G-18.
pub fn fig3_temperature_ratio(alphas: &[f64], collisions: u64, seed: u64) -> Table {
    let base = Intruder1dConfig {
        mass: 1.0,
        ..Default::default()
    };
    let res = ratio_sweep(&base, alphas, collisions, seed, 0);
    let mut t = Table::new("Fig. 3: T/T_B vs alpha, M = m = 1, Gaussian bath (Eq. 18)");
    t.push("alpha", alphas.to_vec());
    t.push(
        "T_over_TB",
        res.iter().map(|r| r.temperature_ratio.mean).collect(),
    );
    t.push(
        "T_over_TB_error",
        res.iter().map(|r| r.temperature_ratio.error).collect(),
    );
    t.push(
        "eq18",
        alphas
            .iter()
            .map(|&a| martin_piasecki_ratio(a, 1.0, 1.0))
            .collect(),
    );
    t.push("kurtosis", res.iter().map(|r| r.kurtosis.mean).collect());
    t.push(
        "kurtosis_error",
        res.iter().map(|r| r.kurtosis.error).collect(),
    );
    t
}

/// Fig. 4: `T/T_B` versus `alpha` in the power-law bath (G-19, `T_B = 1`) for `M = 1`
/// and `M = 0.5`, with the Gaussian-bath result (G-18) and the exact value `alpha` at
/// `M/m = alpha` (NaN elsewhere).
pub fn fig4_power_law_ratio(alphas: &[f64], collisions: u64, seed: u64) -> Table {
    let mut t = Table::new("Fig. 4: T/T_B vs alpha, power-law bath (Eq. 19), M = 1 and 0.5");
    t.push("alpha", alphas.to_vec());
    for (k, &mass) in [1.0, 0.5].iter().enumerate() {
        let base = Intruder1dConfig {
            mass,
            bath: BathConfig::PowerLaw { temperature: 1.0 },
            ..Default::default()
        };
        let res = ratio_sweep(&base, alphas, collisions, seed, 1000 * k as u64);
        t.push(
            format!("T_over_TB_M{mass}"),
            res.iter().map(|r| r.temperature_ratio.mean).collect(),
        );
        t.push(
            format!("T_over_TB_M{mass}_error"),
            res.iter().map(|r| r.temperature_ratio.error).collect(),
        );
        t.push(
            format!("gaussian_eq18_M{mass}"),
            alphas
                .iter()
                .map(|&a| martin_piasecki_ratio(a, mass, 1.0))
                .collect(),
        );
        t.push(
            format!("exact_M{mass}"),
            alphas
                .iter()
                .map(|&a| {
                    if (a - mass).abs() < 1e-12 {
                        a
                    } else {
                        f64::NAN
                    }
                })
                .collect(),
        );
    }
    t
}

/// Fig. 5: intruder velocity distributions for `alpha = 0, 0.1, ..., 1` at `M = 1/2` in the
/// power-law bath (`T_B = 1`, so `a = 1`), on `[-8, 8]` (120 bins), with the exact
/// solution at `alpha = 0.5` (G-19 with the bath's `a`) and its `v^-4` tail
/// `sqrt(2)/(pi a^(3/2) v^4)`.
pub fn fig5_power_law_distributions(collisions: u64, seed: u64) -> Table {
    let alphas = alpha_grid();
    let base = Intruder1dConfig {
        mass: 0.5,
        bath: BathConfig::PowerLaw { temperature: 1.0 },
        histogram_max: Some(8.0),
        histogram_bins: 120,
        ..Default::default()
    };
    let res = ratio_sweep(&base, &alphas, collisions, seed, 0);
    let proto = &res[0].histogram;
    let centres: Vec<f64> = (0..proto.counts.len())
        .map(|i| proto.bin_center(i))
        .collect();
    let mut t = Table::new("Fig. 5: intruder velocity distributions, power-law bath, M = 1/2");
    t.push("v", centres.clone());
    for (a, r) in alphas.iter().zip(&res) {
        t.push(format!("F_alpha{a}"), r.histogram.density());
    }
    // The raw counts where Eq. 19 is exact (`alpha = M/m`), for Pearson's test.
    if let Some(r) = alphas
        .iter()
        .zip(&res)
        .find(|(a, _)| **a == 0.5)
        .map(|(_, r)| r)
    {
        t.push(
            "count_alpha0.5",
            r.histogram.counts.iter().map(|&c| c as f64).collect(),
        );
    }
    let exact = Bath::PowerLaw(super::bath::PowerLaw::new(1.0).unwrap_or_else(|e| panic!("{e}")));
    t.push(
        "eq19_exact_alpha0.5",
        centres.iter().map(|&v| exact.density(v)).collect(),
    );
    t.push(
        "tail_v^-4",
        centres
            .iter()
            .map(|&v| std::f64::consts::SQRT_2 / (std::f64::consts::PI * v.powi(4)))
            .collect(),
    );
    t
}

/// Fig. 7: `R = <v^2 w^2>/(<v^2><w^2>)` (G-30) versus `alpha` for needles of
/// `M/m = 0.1, 0.5, 1` (`L = 1`, `I = M L^2/12`, `a = 1`, `rho = 1`).
pub fn fig7_correlation(alphas: &[f64], collisions: u64, seed: u64) -> Table {
    let masses = [0.1, 0.5, 1.0];
    let jobs: Vec<(usize, usize)> = (0..masses.len())
        .flat_map(|m| (0..alphas.len()).map(move |a| (m, a)))
        .collect();
    let res: Vec<NeedleSummary> = jobs
        .par_iter()
        .map(|&(im, ia)| {
            let cfg = NeedleConfig {
                mass: masses[im],
                restitution: alphas[ia],
                ..Default::default()
            };
            run_needle(&cfg, collisions, seed, (im * alphas.len() + ia) as u64)
        })
        .collect();
    let mut t = Table::new("Fig. 7: needle correlation R (Eq. 30) vs alpha, M = 0.1, 0.5, 1");
    t.push("alpha", alphas.to_vec());
    for (im, &m) in masses.iter().enumerate() {
        let rows = &res[im * alphas.len()..(im + 1) * alphas.len()];
        t.push(
            format!("R_M{m}"),
            rows.iter().map(|r| r.correlation.mean).collect(),
        );
        t.push(
            format!("R_M{m}_error"),
            rows.iter().map(|r| r.correlation.error).collect(),
        );
        t.push(
            format!("Ttr_over_TB_M{m}"),
            rows.iter().map(|r| r.translational_ratio.mean).collect(),
        );
        t.push(
            format!("Trot_over_TB_M{m}"),
            rows.iter().map(|r| r.rotational_ratio.mean).collect(),
        );
    }
    t.push("equilibrium_R", vec![1.0; alphas.len()]);
    t
}

/// Fig. 8: angular-velocity distribution of a needle with `M/m = 0.1`, `alpha = 0.1`
/// (the paper: 5e6 collisions), with the best-fit (maximum-likelihood zero-mean) Gaussian
/// of variance `<w^2>`; also the velocity-component distribution and its Gaussian.
pub fn fig8_angular_distribution(collisions: u64, seed: u64) -> Table {
    let cfg = NeedleConfig {
        mass: 0.1,
        restitution: 0.1,
        // The inelastic needle is much colder than the bath: +-2 equipartition widths
        // (about 8 standard deviations of omega) keep the 120 bins on the data.
        histogram_width: 2.0,
        ..Default::default()
    };
    let r = run_needle(&cfg, collisions, seed, 0);
    let gauss =
        |x: f64, s: f64| (-0.5 * x * x / (s * s)).exp() / (s * (2.0 * std::f64::consts::PI).sqrt());
    let h = &r.omega_histogram;
    let w: Vec<f64> = (0..h.counts.len()).map(|i| h.bin_center(i)).collect();
    let hv = &r.component_histogram;
    let v: Vec<f64> = (0..hv.counts.len()).map(|i| hv.bin_center(i)).collect();
    let mut t = Table::new("Fig. 8: needle angular velocity distribution, M/m = 0.1, alpha = 0.1");
    t.push("omega", w.clone());
    t.push("P_omega", h.density());
    t.push("count_omega", h.counts.iter().map(|&c| c as f64).collect());
    t.push(
        "gaussian_fit_omega",
        w.iter().map(|&x| gauss(x, r.omega_sigma)).collect(),
    );
    t.push("v_component", v.clone());
    t.push("P_v_component", hv.density());
    t.push(
        "gaussian_fit_v",
        v.iter().map(|&x| gauss(x, r.component_sigma)).collect(),
    );
    t
}
