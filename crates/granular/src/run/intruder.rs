//! The intruder engine in the runner: building it from `[intruder]`, and the files of an
//! intruder run directory (`intruder_histograms.csv`/`.npz`, the `intruder` block of
//! `summary.json`). Equation numbers refer to the Gillespie intruder paper
//! (`docs/intruder.md`).

use serde::{Deserialize, Serialize};
use std::path::Path;

use super::{RunError, io_err, json_number};
use crate::engine::{Engine, EngineError, Progress, Scalar};
use crate::intruder::dsmc_twin::DsmcTwin;
use crate::intruder::theory::{martin_piasecki_ratio, power_law_exact_case};
use crate::intruder::{BathConfig, Intruder1d, Needle};
use crate::output::npz::{NpzArray, write_npz};
use crate::scenario::{IntruderSpec, Scenario};
use crate::stats::Histogram;

/// One of the intruder engines (the `model` of `[intruder]`).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[allow(clippy::large_enum_variant)]
pub enum IntruderEngine {
    /// `model = "1d"`.
    OneD(Intruder1d),
    /// `model = "needle"`.
    Needle(Needle),
    /// `model = "dsmc-twin"`.
    DsmcTwin(DsmcTwin),
}

macro_rules! each_model {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            IntruderEngine::OneD($e) => $body,
            IntruderEngine::Needle($e) => $body,
            IntruderEngine::DsmcTwin($e) => $body,
        }
    };
}

/// Builds the engine of `[intruder]`; its random stream is `stream(seed, [DYNAMICS])` (and
/// `[INITIAL_STATE]` for the DSMC twin's bath sample).
pub fn build(scenario: &Scenario) -> Result<IntruderEngine, String> {
    let seed = scenario.seed;
    match &scenario.intruder {
        Some(IntruderSpec::OneD(c)) => Intruder1d::new(c, seed)
            .map(IntruderEngine::OneD)
            .map_err(|e| e.to_string()),
        Some(IntruderSpec::Needle(c)) => Needle::new(c, seed)
            .map(IntruderEngine::Needle)
            .map_err(|e| e.to_string()),
        Some(IntruderSpec::DsmcTwin(c)) => DsmcTwin::new(c, seed)
            .map(IntruderEngine::DsmcTwin)
            .map_err(|e| e.to_string()),
        None => Err("engine = \"intruder\" needs an [intruder] table".into()),
    }
}

impl Engine for IntruderEngine {
    fn name(&self) -> &'static str {
        "intruder"
    }
    fn time(&self) -> f64 {
        each_model!(self, e => e.time())
    }
    fn events(&self) -> u64 {
        each_model!(self, e => e.events())
    }
    fn collisions(&self) -> u64 {
        each_model!(self, e => e.collisions())
    }
    fn particle_count(&self) -> usize {
        1
    }
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        each_model!(self, e => e.advance(until, max_events))
    }
    /// The model's scalars; the needle's temperatures also as ratios to `T_B`.
    fn scalars(&mut self) -> Vec<Scalar> {
        match self {
            IntruderEngine::Needle(n) => {
                let mut out = n.scalars();
                let s = n.summary();
                out.extend([
                    (
                        "translational_temperature_ratio".into(),
                        s.translational_ratio.mean,
                    ),
                    (
                        "translational_temperature_ratio_error".into(),
                        s.translational_ratio.error,
                    ),
                    (
                        "rotational_temperature_ratio".into(),
                        s.rotational_ratio.mean,
                    ),
                    (
                        "rotational_temperature_ratio_error".into(),
                        s.rotational_ratio.error,
                    ),
                ]);
                out
            }
            other => each_model!(other, e => e.scalars()),
        }
    }
    fn kinetic_energy(&mut self) -> f64 {
        each_model!(self, e => e.kinetic_energy())
    }
}

/// The theory value of `T/T_B` for a 1D intruder, when one exists: G-18 (generalised
/// to `m`) for the Gaussian bath, `alpha` in the exact power-law case `M/m = alpha`.
pub fn theory_ratio(spec: &IntruderSpec) -> Option<(f64, &'static str)> {
    let c = spec.one_d()?;
    match c.bath {
        BathConfig::Gaussian { .. } => Some((
            martin_piasecki_ratio(c.restitution, c.mass, c.bath_mass),
            "Martin-Piasecki, Eq. 18: (1 + alpha)/(2 + (1 - alpha) m/M)",
        )),
        _ if power_law_exact_case(c.restitution, c.mass, c.bath_mass) => Some((
            c.restitution,
            "exact case M/m = alpha: the intruder takes the bath distribution, T/T_B = alpha",
        )),
        _ => None,
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
pub(super) fn finish(
    engine: &IntruderEngine,
    scenario: &Scenario,
    dir: &Path,
) -> Result<serde_json::Value, RunError> {
    let Some(spec) = &scenario.intruder else {
        return Ok(serde_json::Value::Null);
    };
    let mut csv = String::from("variable,low,high,count,density,theory_density\n");
    let mut arrays: Vec<(String, Vec<f64>)> = Vec::new();
    let mut block = serde_json::Map::new();
    block.insert("model".into(), spec.model().into());
    match engine {
        IntruderEngine::OneD(_) | IntruderEngine::DsmcTwin(_) => {
            let s = match engine {
                IntruderEngine::OneD(e) => e.summary(),
                IntruderEngine::DsmcTwin(e) => e.summary(),
                IntruderEngine::Needle(_) => unreachable!("handled below"),
            };
            let cfg = spec.one_d();
            let bath_temperature = s.temperature.mean / s.temperature_ratio.mean;
            let mass = cfg.map_or(1.0, |c| c.mass);
            // Reference density: the Gaussian at the theory temperature when G-18 holds,
            // else the best-fit (maximum-likelihood zero-mean) Gaussian.
            let theory = theory_ratio(spec);
            let (sd, reference) = match theory {
                Some((r, _))
                    if matches!(cfg.map(|c| &c.bath), Some(BathConfig::Gaussian { .. })) =>
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
            block.insert("histogram_reference".into(), reference.into());
            block.insert("samples".into(), s.samples.into());
            for (k, e) in [
                ("temperature", s.temperature),
                ("temperature_ratio", s.temperature_ratio),
                ("kurtosis", s.kurtosis),
                ("mean_velocity", s.mean_velocity),
            ] {
                block.insert(k.into(), json_number(e.mean));
                block.insert(format!("{k}_error"), json_number(e.error));
            }
            block.insert("bath_temperature".into(), json_number(bath_temperature));
            if let Some((r, source)) = theory {
                block.insert("theory_temperature_ratio".into(), json_number(r));
                block.insert("theory".into(), source.into());
                block.insert(
                    "temperature_ratio_z".into(),
                    json_number(s.temperature_ratio.z_score(r)),
                );
            }
            if let IntruderEngine::DsmcTwin(t) = engine {
                block.insert("bound_raises".into(), t.bound_raises().into());
                block.insert(
                    "trials_per_collision".into(),
                    json_number(t.trials_per_collision()),
                );
            }
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
            block.insert("histogram_reference".into(), "gaussian_best_fit".into());
            block.insert("samples".into(), s.samples.into());
            for (k, e) in [
                ("translational_temperature", s.translational_temperature),
                ("rotational_temperature", s.rotational_temperature),
                ("translational_temperature_ratio", s.translational_ratio),
                ("rotational_temperature_ratio", s.rotational_ratio),
                ("correlation_r", s.correlation),
            ] {
                block.insert(k.into(), json_number(e.mean));
                block.insert(format!("{k}_error"), json_number(e.error));
            }
            block.insert(
                "velocity_component_sigma".into(),
                json_number(s.component_sigma),
            );
            block.insert("angular_velocity_sigma".into(), json_number(s.omega_sigma));
            if matches!(spec, IntruderSpec::Needle(c) if c.restitution == 1.0) {
                block.insert(
                    "theory".into(),
                    "equipartition (alpha = 1): T_tr/T_B = T_rot/T_B = 1, R = 1".into(),
                );
            }
        }
    }
    let path = dir.join("intruder_histograms.csv");
    std::fs::write(&path, csv).map_err(io_err(&path))?;
    let npz: Vec<(&str, NpzArray)> = arrays
        .iter()
        .map(|(k, v)| (k.as_str(), NpzArray::f64_1d(v.clone())))
        .collect();
    write_npz(dir.join("intruder_histograms.npz"), &npz)?;
    Ok(serde_json::Value::Object(block))
}
