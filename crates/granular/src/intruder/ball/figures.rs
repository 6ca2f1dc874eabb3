//! The data of the two disk-and-sphere figures of `granular reproduce` (the paper's Figs. 3
//! and 4 carried to `d` dimensions), as tables of named columns. Every simulated point `i`
//! uses the seed `derive_key(seed, [MEMBER, i])`, and the points run in parallel with
//! rayon, so the tables do not depend on the number of threads. `collisions` is the number
//! of collisions simulated per point (the transient included).

use rayon::prelude::*;

use super::{Ball, BallConfig, BallDsmcTwin, BallDsmcTwinConfig, BallSummary, IsotropicBathConfig};
use crate::intruder::figures::ratio_sweep;
use crate::intruder::observables::Table;
use crate::intruder::one_d::Intruder1dConfig;
use crate::intruder::theory::martin_piasecki_ratio;
use crate::random::{MEMBER, derive_key};

fn seed_of(seed: u64, index: u64) -> u64 {
    derive_key(seed, &[MEMBER, index])
}

/// A disk (`dimension = 2`) or sphere run of `collisions` collisions.
fn run_ball(dimension: usize, cfg: &BallConfig, collisions: u64, seed: u64) -> BallSummary {
    fn go<const D: usize>(cfg: &BallConfig, collisions: u64, seed: u64) -> BallSummary {
        let mut e = Ball::<D>::new(cfg, seed)
            .unwrap_or_else(|e| panic!("figure configuration is invalid: {e}"));
        if let Err(e) = e.run_collisions(collisions) {
            panic!("disk/sphere run failed: {e}");
        }
        e.summary()
    }
    if dimension == 2 {
        go::<2>(cfg, collisions, seed)
    } else {
        go::<3>(cfg, collisions, seed)
    }
}

/// The DSMC twin of [`run_ball`].
fn run_twin(dimension: usize, cfg: &BallDsmcTwinConfig, collisions: u64, seed: u64) -> BallSummary {
    fn go<const D: usize>(cfg: &BallDsmcTwinConfig, collisions: u64, seed: u64) -> BallSummary {
        let mut e = BallDsmcTwin::<D>::new(cfg, seed)
            .unwrap_or_else(|e| panic!("figure configuration is invalid: {e}"));
        e.run_collisions(collisions);
        e.summary()
    }
    if dimension == 2 {
        go::<2>(cfg, collisions, seed)
    } else {
        go::<3>(cfg, collisions, seed)
    }
}

/// `T/T_B` versus `alpha` at `M = m = 1` in a Gaussian bath (`T_B = 1/2`) for the 1D
/// intruder, the disk and the sphere (radius 1/2, `rho = 1`), with their batch-means errors
/// and Martin-Piasecki's G-18/G-40, the same curve in every dimension; also the kurtosis
/// against `(d + 2)/d` (G-41). Columns `alpha`, `T_over_TB_d{1,2,3}` (and `_error`),
/// `kurtosis_d{1,2,3}` (and `_error`), `martin_piasecki`.
pub fn temperature_ratio_by_dimension(alphas: &[f64], collisions: u64, seed: u64) -> Table {
    let mut t = Table::new(
        "T/T_B vs alpha, M = m, Gaussian bath, d = 1, 2, 3 (G-18, G-40: Martin-Piasecki)",
    );
    t.push("alpha", alphas.to_vec());
    let one_d = ratio_sweep(&Intruder1dConfig::default(), alphas, collisions, seed, 0);
    t.push(
        "T_over_TB_d1",
        one_d.iter().map(|r| r.temperature_ratio.mean).collect(),
    );
    t.push(
        "T_over_TB_d1_error",
        one_d.iter().map(|r| r.temperature_ratio.error).collect(),
    );
    t.push(
        "kurtosis_d1",
        one_d.iter().map(|r| r.kurtosis.mean).collect(),
    );
    t.push(
        "kurtosis_d1_error",
        one_d.iter().map(|r| r.kurtosis.error).collect(),
    );
    for d in [2usize, 3] {
        let res: Vec<BallSummary> = alphas
            .par_iter()
            .enumerate()
            .map(|(i, &alpha)| {
                let cfg = BallConfig {
                    restitution: alpha,
                    ..Default::default()
                };
                run_ball(
                    d,
                    &cfg,
                    collisions,
                    seed_of(seed, 1000 * d as u64 + i as u64),
                )
            })
            .collect();
        t.push(
            format!("T_over_TB_d{d}"),
            res.iter().map(|r| r.temperature_ratio.mean).collect(),
        );
        t.push(
            format!("T_over_TB_d{d}_error"),
            res.iter().map(|r| r.temperature_ratio.error).collect(),
        );
        t.push(
            format!("kurtosis_d{d}"),
            res.iter().map(|r| r.kurtosis.mean).collect(),
        );
        t.push(
            format!("kurtosis_d{d}_error"),
            res.iter().map(|r| r.kurtosis.error).collect(),
        );
    }
    t.push(
        "martin_piasecki",
        alphas
            .iter()
            .map(|&a| martin_piasecki_ratio(a, 1.0, 1.0))
            .collect(),
    );
    t
}

/// `T/T_B` versus `alpha` of a disk and a sphere (`M = m = 1`, radius 1/2, `rho = 1`) in
/// the isotropic power-law bath G-43 (`T_B = 1/2`), from the Gillespie engine (thinning,
/// G-38) and from its DSMC twin (G-45, `bath_particles` stored velocities): no exact
/// result, the two methods against each other. Also the truncated temperature ratio
/// `M <min(|V|^2, h^2)>/(d T_B)` (`h = 6 sqrt(T_B/M)`), whose batch-means error stays valid
/// in this heavy-tailed state. Columns `alpha`, `{gillespie,twin}_T_over_TB_d{2,3}` (and
/// `_error`), `{gillespie,twin}_truncated_d{2,3}` (and `_error`), `martin_piasecki`
/// (G-40 of the Gaussian bath at the same `T_B`, for reference).
pub fn power_law_by_dimension(
    alphas: &[f64],
    collisions: u64,
    bath_particles: usize,
    seed: u64,
) -> Table {
    let mut t = Table::new(
        "T/T_B vs alpha, disk and sphere in the power-law bath (G-43): Gillespie vs DSMC twin",
    );
    t.push("alpha", alphas.to_vec());
    for d in [2usize, 3] {
        for twin in [false, true] {
            let res: Vec<BallSummary> = alphas
                .par_iter()
                .enumerate()
                .map(|(i, &alpha)| {
                    let ball = BallConfig {
                        restitution: alpha,
                        bath: IsotropicBathConfig::PowerLaw { temperature: 0.5 },
                        ..Default::default()
                    };
                    let s = seed_of(seed, 1000 * d as u64 + 100 * twin as u64 + i as u64);
                    if twin {
                        let cfg = BallDsmcTwinConfig {
                            ball,
                            bath_particles,
                        };
                        run_twin(d, &cfg, collisions, s)
                    } else {
                        run_ball(d, &ball, collisions, s)
                    }
                })
                .collect();
            let name = if twin { "twin" } else { "gillespie" };
            let t_b = 0.5;
            t.push(
                format!("{name}_T_over_TB_d{d}"),
                res.iter().map(|r| r.temperature_ratio.mean).collect(),
            );
            t.push(
                format!("{name}_T_over_TB_d{d}_error"),
                res.iter().map(|r| r.temperature_ratio.error).collect(),
            );
            t.push(
                format!("{name}_truncated_d{d}"),
                res.iter()
                    .map(|r| r.truncated_temperature.mean / t_b)
                    .collect(),
            );
            t.push(
                format!("{name}_truncated_d{d}_error"),
                res.iter()
                    .map(|r| r.truncated_temperature.error / t_b)
                    .collect(),
            );
        }
    }
    t.push(
        "martin_piasecki",
        alphas
            .iter()
            .map(|&a| martin_piasecki_ratio(a, 1.0, 1.0))
            .collect(),
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_have_every_column_and_do_not_depend_on_threads() {
        let alphas = [0.0, 1.0];
        let a = temperature_ratio_by_dimension(&alphas, 20_000, 3);
        for c in [
            "T_over_TB_d1",
            "T_over_TB_d2_error",
            "kurtosis_d3",
            "martin_piasecki",
        ] {
            assert_eq!(a.column(c).map(<[f64]>::len), Some(2), "{c}");
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let b = pool.install(|| temperature_ratio_by_dimension(&alphas, 20_000, 3));
        assert_eq!(a.to_csv(), b.to_csv());
        let p = power_law_by_dimension(&[0.5], 20_000, 500, 4);
        for c in ["gillespie_T_over_TB_d2", "twin_truncated_d3_error"] {
            assert!(p.column(c).unwrap()[0].is_finite(), "{c}");
        }
    }
}
