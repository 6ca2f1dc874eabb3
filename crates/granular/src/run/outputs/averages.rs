//! The `averages` block of the summary: the mean and standard error of every time-series
//! observable that means something as an average, over the outputs after the
//! equilibration time, from the observations in memory. Errors come from online blocking
//! ([`crate::averaging`]), whose state is a few numbers per observable and level, so a
//! checkpoint restores it bit for bit.

use super::Output;
use crate::averaging::Blocking;
use crate::observation::{Observation, Rates};
use crate::run::summary::{AverageValue, AveragesSummary};
use crate::run::{AnyEngine, RunError, Summary};
use crate::scenario::BathTable;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};

/// How errors are estimated, as the summary states it.
const METHOD: &str = "blocking (Flyvbjerg and Petersen, J. Chem. Phys. 91, 461 (1989)); block \
     length: the smallest 2^k with B^3 > 2 N (s_k/s_0)^4 (Lee, Drummond and Needs, Phys. Rev. B \
     83, 245114 (2011)), at least 8 blocks, on a plateau";

/// Why the power-law bath's errors are not given.
const POWER_LAW_NOTE: &str = "the power-law bath's v^2 has infinite variance: no error estimate \
     from one run is valid (batch means come out 1.4-4.8 times smaller than the seed-to-seed \
     scatter); use the spread over independent seeds";

/// Columns of the many-grain engines averaged (and `temperature.*`, `a2.*`), besides the
/// rates of the window. Counters and `mean_free_time` (the mean of `1/ν` is not `1/⟨ν⟩`)
/// are left out.
const COLUMNS: [&str; 7] = [
    "kinetic_energy",
    "temperature",
    "a2",
    // Rough grains only (`docs/rough.md`).
    "rotational_temperature",
    "temperature_ratio",
    "reduced_cooling_rate",
    "rotational_energy",
];
/// The rate columns of a driven gas ([`crate::driving`]); NaN (skipped) outside the
/// equilibrated windows.
const DRIVEN: [&str; 3] = ["driving_power", "dissipation_rate", "cooling_rate"];

/// The run averages.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct Averages {
    /// Time of the first sample averaged.
    start_time: Option<f64>,
    /// The previous observation: the start of the next rate window.
    previous: Option<Observation>,
    /// Whether it was past the equilibration time (a rate window enters only when it lies
    /// wholly after it).
    previous_in: bool,
    /// Observable names, in the order first seen.
    names: Vec<String>,
    /// Blocking accumulators, in the order of `names`.
    blocks: Vec<Blocking>,
}

/// Where the averages start: a time, or a number of collisions per grain.
enum Rule {
    Time(f64),
    CollisionsPerParticle(f64),
}

/// The equilibration rule of a simulation, and its description in the summary.
fn rule(simulation: &Simulation) -> (Rule, String) {
    let output = &simulation.scenario().output;
    if let Some(t) = output.equilibration_time {
        return (Rule::Time(t), format!("output.equilibration_time = {t}"));
    }
    if let AnyEngine::Intruder(e) = simulation.engine() {
        let t = e.transient();
        return (Rule::Time(t), format!("intruder.transient = {t} (default)"));
    }
    let c = output.equilibration_collisions_per_particle;
    (
        Rule::CollisionsPerParticle(c),
        format!("output.equilibration_collisions_per_particle = {c} (default)"),
    )
}

/// The samples of one observation: `(name, value)` of the averaged quantities.
fn samples(obs: &Observation, rates: Option<&Rates>) -> Vec<(String, f64)> {
    let columns = obs.columns(rates);
    if obs.engine == "intruder" {
        return columns
            .into_iter()
            .filter(|(k, _)| k == "velocity" || k == "kinetic_energy")
            .collect();
    }
    let mut out: Vec<(String, f64)> = columns
        .into_iter()
        .filter(|(k, _)| {
            COLUMNS.contains(&k.as_str())
                || DRIVEN.contains(&k.as_str())
                || k.starts_with("temperature.")
                || k.starts_with("a2.")
        })
        .collect();
    if let Some(r) = rates {
        // Z = P / (n T), n = N / V; NaN (skipped) where the engine has no pressure.
        let n = obs.particles as f64 / obs.volume;
        out.extend([
            ("collision_frequency".into(), r.collision_frequency),
            ("pressure".into(), r.pressure),
            ("wall_pressure".into(), r.wall_pressure),
            (
                "compressibility_factor".into(),
                r.pressure / (n * obs.temperature),
            ),
        ]);
    }
    out
}

impl Averages {
    /// No samples yet.
    pub(crate) fn new() -> Averages {
        Averages::default()
    }

    fn push(&mut self, name: &str, x: f64) {
        if !x.is_finite() {
            return;
        }
        let i = match self.names.iter().position(|n| n == name) {
            Some(i) => i,
            None => {
                self.names.push(name.to_string());
                self.blocks.push(Blocking::new());
                self.names.len() - 1
            }
        };
        self.blocks[i].push(x);
    }
}

impl Output for Averages {
    fn observe(&mut self, simulation: &Simulation, obs: &Observation) -> Result<(), RunError> {
        let now_in = match rule(simulation).0 {
            Rule::Time(t) => obs.time >= t,
            Rule::CollisionsPerParticle(c) => obs.collisions_per_particle >= c,
        };
        // The window's rates only when it starts after the equilibration time.
        let rates = match (&self.previous, self.previous_in) {
            (Some(p), true) => Some(obs.rates_since(p)),
            _ => None,
        };
        self.previous = Some(obs.clone());
        self.previous_in = now_in;
        if !now_in {
            return Ok(());
        }
        if self.start_time.is_none() {
            self.start_time = Some(obs.time);
        }
        for (name, x) in samples(obs, rates.as_ref()) {
            self.push(&name, x);
        }
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let power_law = simulation
            .scenario()
            .intruder()
            .and_then(|s| s.one_d())
            .is_some_and(|c| matches!(c.bath, BathTable::PowerLaw { .. }));
        let equilibration = rule(simulation).1;
        let observables = self
            .names
            .iter()
            .zip(&self.blocks)
            .map(|(name, b)| {
                let e = b.estimate();
                let invalid = power_law && name == "kinetic_energy";
                let value = AverageValue {
                    mean: e.mean,
                    error: if invalid { None } else { e.error },
                    error_note: if invalid {
                        Some(POWER_LAW_NOTE.to_string())
                    } else {
                        e.note
                    },
                    samples: e.samples,
                    block_length: if invalid { 0 } else { e.block_length },
                    blocks: if invalid { 0 } else { e.blocks },
                };
                (name.clone(), value)
            })
            .collect();
        let averages = AveragesSummary {
            start_time: self.start_time.unwrap_or(f64::NAN),
            equilibration,
            method: METHOD.to_string(),
            observables,
        };
        summary.steady_state = super::steady::summary(simulation, &averages);
        summary.rough = super::rough::summary(simulation, &averages);
        summary.averages = Some(averages);
        Ok(())
    }
}
