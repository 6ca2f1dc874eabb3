//! Collision rates of the Gillespie intruder engines (`granular bench intruder`).

use super::BenchError;
use crate::intruder::ball::{Ball, BallConfig, IsotropicBathConfig};
use crate::intruder::bath::BathConfig;
use crate::intruder::needle::{Needle, NeedleConfig, NeedleMethod};
use crate::intruder::one_d::{Intruder1d, Intruder1dConfig, Method1d};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The benchmark cases.
pub const CASES: [&str; 9] = [
    "1d-gaussian",
    "1d-power-law",
    "needle",
    "1d-gaussian-direct",
    "needle-paper",
    "2d-gaussian",
    "3d-gaussian",
    "2d-power-law",
    "3d-power-law",
];

/// Result of one measurement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchResult {
    /// Case name.
    pub case: String,
    /// Collisions simulated (after a short warm-up).
    pub collisions: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Collisions per second on one core.
    pub collisions_per_second: f64,
}

/// Simulates `collisions` collisions of the named case on the calling thread and returns
/// the rate. Cases: `1d-gaussian`, `1d-power-law`, `needle` (default samplers, i.e.
/// thinning) and `1d-gaussian-direct`, `needle-paper` (the paper's G-10 to G-13 / G-23 to G-26);
/// `2d-gaussian`, `3d-gaussian`, `2d-power-law`, `3d-power-law`: a disk or sphere of radius
/// 1/2 (thinning, G-38) in the Gaussian or isotropic power-law bath (G-43).
/// Parameters: `M = m = 1`, `alpha = 0.5`, `rho = 1`, `a = 1` (`T_B = 1/2`), averaging grid on.
pub fn measure_collision_rate(
    case: &str,
    collisions: u64,
    seed: u64,
) -> Result<BenchResult, BenchError> {
    let warm = (collisions / 10).max(1);
    let seconds = match case {
        "1d-gaussian" | "1d-power-law" | "1d-gaussian-direct" => {
            let cfg = Intruder1dConfig {
                bath: if case == "1d-power-law" {
                    BathConfig::PowerLaw { temperature: 1.0 }
                } else {
                    BathConfig::default()
                },
                method: if case == "1d-gaussian-direct" {
                    Method1d::Direct
                } else {
                    Method1d::Thinning
                },
                transient: Some(0.0),
                ..Default::default()
            };
            let mut e = Intruder1d::new(&cfg, seed).map_err(|e| BenchError::Case(e.to_string()))?;
            e.run_collisions(warm);
            let t0 = Instant::now();
            e.run_collisions(collisions);
            let s = t0.elapsed().as_secs_f64();
            std::hint::black_box(e.velocity());
            s
        }
        "needle" | "needle-paper" => {
            let cfg = NeedleConfig {
                method: if case == "needle" {
                    NeedleMethod::Thinning
                } else {
                    NeedleMethod::Paper
                },
                transient: Some(0.0),
                ..Default::default()
            };
            let mut e = Needle::new(&cfg, seed).map_err(|e| BenchError::Case(e.to_string()))?;
            e.run_collisions(warm)?;
            let t0 = Instant::now();
            e.run_collisions(collisions)?;
            let s = t0.elapsed().as_secs_f64();
            std::hint::black_box(e.velocity());
            s
        }
        "2d-gaussian" | "3d-gaussian" | "2d-power-law" | "3d-power-law" => {
            let cfg = BallConfig {
                bath: if case.ends_with("power-law") {
                    IsotropicBathConfig::PowerLaw { temperature: 0.5 }
                } else {
                    IsotropicBathConfig::Gaussian { temperature: 0.5 }
                },
                transient: Some(0.0),
                ..Default::default()
            };
            if case.starts_with("2d") {
                time_ball::<2>(&cfg, warm, collisions, seed)?
            } else {
                time_ball::<3>(&cfg, warm, collisions, seed)?
            }
        }
        other => {
            return Err(BenchError::Case(format!(
                "unknown intruder benchmark case {other:?}; known: {}",
                CASES.join(", ")
            )));
        }
    };
    Ok(BenchResult {
        case: case.to_string(),
        collisions,
        seconds,
        collisions_per_second: collisions as f64 / seconds,
    })
}

/// Seconds for `collisions` collisions of a disk or sphere after `warm` ones.
fn time_ball<const D: usize>(
    cfg: &BallConfig,
    warm: u64,
    collisions: u64,
    seed: u64,
) -> Result<f64, BenchError> {
    let mut e = Ball::<D>::new(cfg, seed).map_err(|e| BenchError::Case(e.to_string()))?;
    e.run_collisions(warm)?;
    let t0 = Instant::now();
    e.run_collisions(collisions)?;
    let s = t0.elapsed().as_secs_f64();
    std::hint::black_box(e.velocity());
    Ok(s)
}
