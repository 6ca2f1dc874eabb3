//! The intruder engines behind one type: building them from `[intruder]`, and the theory
//! value of their temperature ratio. Equation numbers refer to the Gillespie intruder
//! paper (`docs/intruder.md`); the files of an intruder run are written by
//! `run::outputs::IntruderStatistics`.

use serde::{Deserialize, Serialize};

use crate::engine::{Engine, EngineError, Progress};
use crate::intruder::ball::{Ball, BallDsmcTwin, BallError};
use crate::intruder::dsmc_twin::DsmcTwin;
use crate::intruder::theory::{martin_piasecki_ratio, power_law_exact_case};
use crate::intruder::{Intruder1d, Needle};
use crate::observation::Observation;
use crate::scenario::{BathTable, IntruderSpec, Scenario};

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
    /// `model = "disk"`.
    Disk(Ball<2>),
    /// `model = "sphere"`.
    Sphere(Ball<3>),
    /// `model = "disk"`, `method = "dsmc-twin"`.
    DiskTwin(BallDsmcTwin<2>),
    /// `model = "sphere"`, `method = "dsmc-twin"`.
    SphereTwin(BallDsmcTwin<3>),
}

macro_rules! each_model {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            IntruderEngine::OneD($e) => $body,
            IntruderEngine::Needle($e) => $body,
            IntruderEngine::DsmcTwin($e) => $body,
            IntruderEngine::Disk($e) => $body,
            IntruderEngine::Sphere($e) => $body,
            IntruderEngine::DiskTwin($e) => $body,
            IntruderEngine::SphereTwin($e) => $body,
        }
    };
}

/// A disk or sphere engine error in the words of the scenario (`intruder.<key>`).
fn ball_error(e: BallError) -> String {
    format!("`intruder.{}` {}", e.key, e.message)
}

/// Builds the engine of `[intruder]`; its random stream is `stream(seed, [DYNAMICS])` (and
/// `[INITIAL_STATE]` for the DSMC twin's bath sample).
pub fn build(scenario: &Scenario) -> Result<IntruderEngine, String> {
    let seed = scenario.seed;
    match &scenario.intruder() {
        Some(IntruderSpec::OneD(c)) => c
            .config()
            .and_then(|c| Intruder1d::new(&c, seed))
            .map(IntruderEngine::OneD)
            .map_err(|e| e.to_string()),
        Some(IntruderSpec::Needle(c)) => Needle::new(&c.config(), seed)
            .map(IntruderEngine::Needle)
            .map_err(|e| e.to_string()),
        Some(IntruderSpec::DsmcTwin(c)) => c
            .config()
            .and_then(|c| DsmcTwin::new(&c, seed))
            .map(IntruderEngine::DsmcTwin)
            .map_err(|e| e.to_string()),
        Some(IntruderSpec::Disk(c)) if c.is_twin() => c
            .twin_config(2)
            .and_then(|c| BallDsmcTwin::new(&c, seed))
            .map(IntruderEngine::DiskTwin)
            .map_err(ball_error),
        Some(IntruderSpec::Disk(c)) => c
            .config(2)
            .and_then(|c| Ball::new(&c, seed))
            .map(IntruderEngine::Disk)
            .map_err(ball_error),
        Some(IntruderSpec::Sphere(c)) if c.is_twin() => c
            .twin_config(3)
            .and_then(|c| BallDsmcTwin::new(&c, seed))
            .map(IntruderEngine::SphereTwin)
            .map_err(ball_error),
        Some(IntruderSpec::Sphere(c)) => c
            .config(3)
            .and_then(|c| Ball::new(&c, seed))
            .map(IntruderEngine::Sphere)
            .map_err(ball_error),
        None => Err("engine = \"intruder\" needs an [intruder] table".into()),
    }
}

impl IntruderEngine {
    /// Time the model discards before its own averages (the resolved `transient`).
    pub fn transient(&self) -> f64 {
        each_model!(self, e => e.transient())
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
    /// The model's observation; the needle's temperatures also as ratios to `T_B`.
    fn observe(&self) -> Observation {
        match self {
            IntruderEngine::Needle(n) => {
                let mut out = n.observe();
                let s = n.summary();
                out.engine_specific.extend([
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
            other => each_model!(other, e => e.observe()),
        }
    }
    fn kinetic_energy(&self) -> f64 {
        each_model!(self, e => e.kinetic_energy())
    }
}

/// The theory value of `T/T_B` when one exists: G-18 (generalised to `m`) for the
/// Gaussian bath, `alpha` in the exact power-law case `M/m = alpha` (1D); G-40 for a disk
/// or sphere in a Gaussian bath.
pub fn theory_ratio(spec: &IntruderSpec) -> Option<(f64, &'static str)> {
    if let Some((c, _)) = spec.ball() {
        return matches!(c.bath, BathTable::Gaussian { .. }).then(|| {
            (
                martin_piasecki_ratio(c.restitution, c.mass, c.bath_mass),
                "Martin-Piasecki in d dimensions, G-40: (1 + alpha) M/(2M + (1 - alpha) m)",
            )
        });
    }
    let c = spec.one_d()?;
    match c.bath {
        BathTable::Gaussian { .. } => Some((
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

/// The values `[intruder]` leaves to the engine (`sample_interval`, `transient`,
/// `histogram_max`), as the engine resolved them, each with its key; only those the
/// scenario does not set. `granular check` prints them.
pub fn automatic_values(scenario: &Scenario) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let mut add = |given: Option<f64>, key: &str, value: f64| {
        if given.is_none() {
            out.push((format!("intruder.{key}"), value));
        }
    };
    match &scenario.intruder() {
        Some(IntruderSpec::Needle(c)) => {
            if let Ok(n) = Needle::new(&c.config(), scenario.seed) {
                add(c.sample_interval, "sample_interval", n.sample_interval());
                add(c.transient, "transient", n.transient());
            }
        }
        Some(spec @ (IntruderSpec::Disk(_) | IntruderSpec::Sphere(_))) => {
            if let Ok(e) = build(scenario) {
                let c = spec.ball().map(|(c, _)| c);
                let (dt, t0, h) = match &e {
                    IntruderEngine::Disk(b) => {
                        (b.sample_interval(), b.transient(), b.histogram_max())
                    }
                    IntruderEngine::Sphere(b) => {
                        (b.sample_interval(), b.transient(), b.histogram_max())
                    }
                    IntruderEngine::DiskTwin(b) => {
                        (b.sample_interval(), b.transient(), b.histogram_max())
                    }
                    IntruderEngine::SphereTwin(b) => {
                        (b.sample_interval(), b.transient(), b.histogram_max())
                    }
                    _ => return out,
                };
                if let Some(c) = c {
                    add(c.sample_interval, "sample_interval", dt);
                    add(c.transient, "transient", t0);
                    add(c.histogram_max, "histogram_max", h);
                }
            }
        }
        Some(spec) => {
            // The twin resolves its defaults as the 1D engine of the same table does.
            if let Some(c) = spec.one_d()
                && let Ok(e) = c.config().and_then(|c| Intruder1d::new(&c, scenario.seed))
            {
                add(c.sample_interval, "sample_interval", e.sample_interval());
                add(c.transient, "transient", e.transient());
                add(c.histogram_max, "histogram_max", e.histogram_max());
            }
        }
        None => {}
    }
    out
}
