//! The intruder engines' statistics: `intruder_histograms.csv` and `.npz` (velocity
//! histograms on the time grid with their reference densities) and the `intruder` block
//! of the summary (stationary averages with errors, and the theory value: G-18 for the
//! Gaussian bath, the exact power-law case, equipartition for the elastic needle; for a
//! disk or sphere G-40 to G-42 in a Gaussian bath).

use super::Output;
use crate::build::intruder::{IntruderEngine, theory_ratio};
use crate::intruder::ball::{BallParams, BallSummary};
use crate::observation::Observation;
use crate::output::npz::{NpzArray, write_npz};
use crate::run::summary::IntruderSummary;
use crate::run::{AnyEngine, RunError, Summary, io_err};
use crate::scenario::BathTable;
use crate::scenario::IntruderSpec;
use crate::simulation::Simulation;
use crate::stats::Histogram;
use crate::theory::equilibrium::speed_cdf;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The intruder's histograms and averages, written at the end of the run (the engine
/// keeps the statistics, so this output holds nothing that grows with the run).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct IntruderStatistics {
    #[serde(skip)]
    dir: PathBuf,
}

impl IntruderStatistics {
    /// Files written into `dir`.
    pub(crate) fn new(dir: &Path) -> IntruderStatistics {
        IntruderStatistics {
            dir: dir.to_path_buf(),
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.to_path_buf();
    }
}

impl Output for IntruderStatistics {
    fn observe(&mut self, _: &Simulation, _: &Observation) -> Result<(), RunError> {
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        if let (AnyEngine::Intruder(engine), Some(spec)) =
            (simulation.engine(), &simulation.scenario().intruder())
        {
            summary.intruder = Some(write_statistics(engine, spec, &self.dir)?);
        }
        Ok(())
    }
}

fn histogram_rows(
    name: &str,
    h: &Histogram,
    theory: &dyn Fn(f64, f64) -> f64,
    out: &mut String,
    arrays: &mut Vec<(String, Vec<f64>)>,
) {
    let w = h.bin_width();
    let total = h.total();
    let dens = h.density();
    let (mut lo_v, mut count_v, mut dens_v, mut th_v) = (vec![], vec![], vec![], vec![]);
    for (b, &c) in h.counts.iter().enumerate() {
        let lo = h.min + b as f64 * w;
        let d = if total > 0 { dens[b] } else { f64::NAN };
        let th = theory(lo, lo + w);
        out.push_str(&format!("{name},{lo:e},{:e},{c},{d:e},{th:e}\n", lo + w));
        lo_v.push(lo);
        count_v.push(c as f64);
        dens_v.push(d);
        th_v.push(th);
    }
    lo_v.push(h.max);
    arrays.push((format!("{name}_edges"), lo_v));
    arrays.push((format!("{name}_count"), count_v));
    arrays.push((format!("{name}_density"), dens_v));
    arrays.push((format!("{name}_theory_density"), th_v));
}

/// Mean density of a zero-mean Gaussian of standard deviation `sd` over `[a, b]`.
fn gaussian_bin(sd: f64) -> impl Fn(f64, f64) -> f64 {
    move |a: f64, b: f64| {
        if sd > 0.0 && sd.is_finite() {
            let cdf = |v: f64| 0.5 * libm::erfc(-v / (sd * std::f64::consts::SQRT_2));
            (cdf(b) - cdf(a)) / (b - a)
        } else {
            f64::NAN
        }
    }
}

/// Writes `intruder_histograms.csv` and `intruder_histograms.npz` (velocity histograms on
/// the time grid with their reference densities) and returns the `intruder` block of
/// `summary.json`.
fn write_statistics(
    engine: &IntruderEngine,
    spec: &IntruderSpec,
    dir: &Path,
) -> Result<IntruderSummary, RunError> {
    let mut csv = String::from("variable,low,high,count,density,theory_density\n");
    let mut arrays: Vec<(String, Vec<f64>)> = Vec::new();
    let mut block = IntruderSummary {
        model: spec.model().into(),
        ..IntruderSummary::default()
    };
    match engine {
        IntruderEngine::OneD(_) | IntruderEngine::DsmcTwin(_) => {
            let s = match engine {
                IntruderEngine::OneD(e) => e.summary(),
                IntruderEngine::DsmcTwin(e) => e.summary(),
                _ => unreachable!("handled below"),
            };
            let cfg = spec.one_d();
            let bath_temperature = s.temperature.mean / s.temperature_ratio.mean;
            let mass = cfg.map_or(1.0, |c| c.mass);
            // Reference density: the Gaussian at the theory temperature when G-18 holds,
            // else the best-fit (maximum-likelihood zero-mean) Gaussian.
            let theory = theory_ratio(spec);
            let (sd, reference) = match theory {
                Some((r, _))
                    if matches!(cfg.map(|c| &c.bath), Some(BathTable::Gaussian { .. })) =>
                {
                    ((r * bath_temperature / mass).sqrt(), "gaussian_eq18")
                }
                _ => ((s.temperature.mean / mass).sqrt(), "gaussian_best_fit"),
            };
            histogram_rows(
                "velocity",
                &s.histogram,
                &gaussian_bin(sd),
                &mut csv,
                &mut arrays,
            );
            block.histogram_reference = reference.into();
            block.samples = s.samples;
            for (k, e) in [
                ("temperature", s.temperature),
                ("temperature_ratio", s.temperature_ratio),
                ("kurtosis", s.kurtosis),
                ("mean_velocity", s.mean_velocity),
            ] {
                block.averages.insert(k.into(), Some(e.mean));
                block.averages.insert(format!("{k}_error"), Some(e.error));
            }
            block.bath_temperature = Some(bath_temperature);
            if let Some((r, source)) = theory {
                block.theory_temperature_ratio = Some(r);
                block.theory = Some(source.into());
                block.temperature_ratio_z = Some(s.temperature_ratio.z_score(r));
            }
            if let IntruderEngine::DsmcTwin(t) = engine {
                block.bound_raises = Some(t.bound_raises());
                block.trials_per_collision = Some(t.trials_per_collision());
            }
        }
        IntruderEngine::Disk(e) => ball_statistics(
            &e.summary(),
            &e.params,
            spec,
            &mut block,
            &mut csv,
            &mut arrays,
        ),
        IntruderEngine::Sphere(e) => ball_statistics(
            &e.summary(),
            &e.params,
            spec,
            &mut block,
            &mut csv,
            &mut arrays,
        ),
        IntruderEngine::DiskTwin(t) => {
            ball_statistics(
                &t.summary(),
                t.params(),
                spec,
                &mut block,
                &mut csv,
                &mut arrays,
            );
            block.bound_raises = Some(t.bound_raises());
            block.trials_per_collision = Some(t.trials_per_collision());
        }
        IntruderEngine::SphereTwin(t) => {
            ball_statistics(
                &t.summary(),
                t.params(),
                spec,
                &mut block,
                &mut csv,
                &mut arrays,
            );
            block.bound_raises = Some(t.bound_raises());
            block.trials_per_collision = Some(t.trials_per_collision());
        }
        IntruderEngine::Needle(n) => {
            let s = n.summary();
            histogram_rows(
                "velocity_component",
                &s.component_histogram,
                &gaussian_bin(s.component_sigma),
                &mut csv,
                &mut arrays,
            );
            histogram_rows(
                "angular_velocity",
                &s.omega_histogram,
                &gaussian_bin(s.omega_sigma),
                &mut csv,
                &mut arrays,
            );
            block.histogram_reference = "gaussian_best_fit".into();
            block.samples = s.samples;
            for (k, e) in [
                ("translational_temperature", s.translational_temperature),
                ("rotational_temperature", s.rotational_temperature),
                ("translational_temperature_ratio", s.translational_ratio),
                ("rotational_temperature_ratio", s.rotational_ratio),
                ("correlation_r", s.correlation),
            ] {
                block.averages.insert(k.into(), Some(e.mean));
                block.averages.insert(format!("{k}_error"), Some(e.error));
            }
            block.velocity_component_sigma = Some(s.component_sigma);
            block.angular_velocity_sigma = Some(s.omega_sigma);
            if matches!(spec, IntruderSpec::Needle(c) if c.restitution == 1.0) {
                block.theory =
                    Some("equipartition (alpha = 1): T_tr/T_B = T_rot/T_B = 1, R = 1".into());
            }
        }
    }
    let path = dir.join(crate::run::RunFile::IntruderHistograms.name());
    std::fs::write(&path, csv).map_err(io_err(&path))?;
    let npz: Vec<(&str, NpzArray)> = arrays
        .iter()
        .map(|(k, v)| (k.as_str(), NpzArray::f64_1d(v.clone())))
        .collect();
    write_npz(dir.join(crate::run::RunFile::IntruderArrays.name()), &npz)?;
    Ok(block)
}

/// The disk's or sphere's histograms (`velocity_x`, `velocity_y` (, `velocity_z`) and
/// `speed`) against the Maxwellian at the G-40 temperature in a Gaussian bath, else at the
/// measured temperature; its averages, and the theory values G-40 to G-42 (Gaussian bath).
fn ball_statistics(
    s: &BallSummary,
    params: &BallParams,
    spec: &IntruderSpec,
    block: &mut IntruderSummary,
    csv: &mut String,
    arrays: &mut Vec<(String, Vec<f64>)>,
) {
    let d = s.dimension;
    let theory = theory_ratio(spec);
    let (temperature, reference) = match theory {
        Some((r, _)) => (r * params.bath_temperature, "maxwellian_g40"),
        None => (s.temperature.mean, "maxwellian_best_fit"),
    };
    let sd = (temperature / params.mass).sqrt();
    for (h, name) in s
        .component_histograms
        .iter()
        .zip(["velocity_x", "velocity_y", "velocity_z"])
    {
        histogram_rows(name, h, &gaussian_bin(sd), csv, arrays);
    }
    let speed_bin = |a: f64, b: f64| {
        if temperature > 0.0 && temperature.is_finite() {
            (speed_cdf(d, b, params.mass, temperature) - speed_cdf(d, a, params.mass, temperature))
                / (b - a)
        } else {
            f64::NAN
        }
    };
    histogram_rows("speed", &s.speed_histogram, &speed_bin, csv, arrays);
    block.histogram_reference = reference.into();
    block.samples = s.samples;
    for (k, e) in [
        ("temperature", s.temperature),
        ("temperature_ratio", s.temperature_ratio),
        ("kurtosis", s.kurtosis),
        ("collision_rate", s.collision_rate),
        ("truncated_temperature", s.truncated_temperature),
    ] {
        block.averages.insert(k.into(), Some(e.mean));
        block.averages.insert(format!("{k}_error"), Some(e.error));
    }
    block.bath_temperature = Some(params.bath_temperature);
    if let Some((r, source)) = theory {
        block.theory_temperature_ratio = Some(r);
        block.theory = Some(source.into());
        block.temperature_ratio_z = Some(s.temperature_ratio.z_score(r));
        block.theory_kurtosis = Some(s.maxwellian_kurtosis);
        block.theory_collision_rate = Some(s.theory_collision_rate);
    }
}
