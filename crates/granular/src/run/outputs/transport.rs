//! `mean_square_displacement.csv` and `velocity_autocorrelation.csv`: the MSD and the
//! VACF per species on log-spaced lags (multiples of `output.interval`), and the
//! self-diffusion coefficient in the summary (`final.diffusion_coefficient` from the MSD's
//! slope, `final.diffusion_coefficient_green_kubo` from the VACF's integral, each with its
//! `_error`; `.<species>` appended in a mixture). The log-lag correlator, the unwrapping
//! and the fits are in [`crate::transport`].

use super::{Output, write_table};
use crate::observation::Observation;
use crate::run::{RunError, Summary};
use crate::simulation::Simulation;
use crate::transport::{LogLagCorrelator, Unwrapper};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The correlator and the unwrapped positions (part of the checkpoint).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct TransportOutput {
    #[serde(skip)]
    dir: PathBuf,
    unwrapper: Option<Unwrapper>,
    correlator: Option<LogLagCorrelator>,
    /// Time of the first sample.
    start: f64,
    /// Time of the last sample fed to the correlator.
    last: f64,
    /// Lightest grain mass (the unwrapping guard).
    m_min: f64,
    /// The first grain id of the grains this process correlates (over ranks its block of
    /// ids; 0 otherwise).
    #[serde(default)]
    first: usize,
    names: Vec<String>,
}

impl TransportOutput {
    /// MSD and VACF written into `dir`.
    pub(crate) fn new(dir: &Path) -> TransportOutput {
        TransportOutput {
            dir: dir.to_path_buf(),
            ..TransportOutput::default()
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.to_path_buf();
    }

    fn write(&self, c: &LogLagCorrelator, interval: f64) -> Result<(), RunError> {
        for (file, quantity) in [
            (crate::run::RunFile::MeanSquareDisplacement.name(), "msd"),
            (crate::run::RunFile::VelocityAutocorrelation.name(), "vacf"),
        ] {
            let mut header = vec!["lag".to_string(), "origins".to_string()];
            for n in &self.names {
                header.push(format!("{quantity}.{n}"));
                header.push(format!("{quantity}_error.{n}"));
            }
            let rows: Vec<Vec<f64>> = c
                .filled()
                .into_iter()
                .map(|i| {
                    let mut row = vec![c.lags[i] as f64 * interval, c.origins[i] as f64];
                    for s in 0..self.names.len() {
                        let (v, e) = if quantity == "msd" {
                            c.msd(s, i)
                        } else {
                            c.vacf(s, i)
                        };
                        row.extend([v, e]);
                    }
                    row
                })
                .collect();
            write_table(&self.dir.join(file), &header, &rows)?;
        }
        Ok(())
    }
}

impl TransportOutput {
    /// Moves the per-grain state out (`None` before the first sample): a decomposed run
    /// writes each rank's into its checkpoint part and keeps it out of the manifest.
    pub(crate) fn take_rows(&mut self) -> Option<crate::transport::GrainRows> {
        let (Some(u), Some(c)) = (&mut self.unwrapper, &mut self.correlator) else {
            return None;
        };
        Some(c.take_rows(u, self.first))
    }

    /// Puts back the per-grain state of the grains `first ..` (cut from the parts of a
    /// checkpoint).
    pub(crate) fn put_rows(&mut self, rows: crate::transport::GrainRows) {
        if let (Some(u), Some(c)) = (&mut self.unwrapper, &mut self.correlator) {
            self.first = rows.first;
            c.put_rows(u, rows);
        }
    }
}

/// The `output.interval` error of the unwrapping guard.
fn interval_error(interval: f64, message: String) -> RunError {
    RunError::Output {
        key: "output.interval".into(),
        message: format!(
            "is {}: for the mean-square displacement {message}; give a shorter output interval",
            crate::output::format_number(interval)
        ),
    }
}

/// The lightest grain mass of the scenario (the unwrapping guard); the same on every
/// rank without a reduction.
fn lightest(simulation: &Simulation) -> f64 {
    simulation
        .scenario()
        .species()
        .iter()
        .map(|s| s.mass)
        .fold(f64::INFINITY, f64::min)
}

impl Output for TransportOutput {
    /// Refuses an output interval in which a grain could cross half a periodic edge
    /// (before the run starts).
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if simulation.scenario().intruder().is_some() {
            return Ok(());
        }
        let scenario = simulation.scenario();
        let m_min = lightest(simulation);
        let periodic = scenario
            .axes()
            .iter()
            .map(|a| *a == crate::boundary::AxisKind::Periodic)
            .collect();
        let u = Unwrapper::new(scenario.lengths(), periodic, &[], 0.0, 0.0);
        let allowed = u.max_interval(simulation.observe().kinetic_energy, m_min);
        let interval = scenario.output.interval;
        if interval >= allowed {
            return Err(interval_error(
                interval,
                format!(
                    "a grain as fast as the kinetic energy allows could cross half a periodic edge in {}, so its periodic images would be ambiguous (minimum-image unwrapping)",
                    crate::output::format_number(allowed)
                ),
            ));
        }
        Ok(())
    }

    /// Over ranks each rank unwraps and correlates its block of grain ids; the sums are
    /// chained from rank to rank in id order (the threaded run's additions).
    fn observe(
        &mut self,
        simulation: &Simulation,
        observation: &Observation,
    ) -> Result<(), RunError> {
        let Some(grains) = crate::run::grains::Grains::of(simulation) else {
            return Ok(());
        };
        let snap = &grains.snap;
        let now = simulation.time();
        let interval = simulation.scenario().output.interval;
        let k = observation.kinetic_energy;
        let mut chain =
            |acc: Vec<f64>, fold: &mut dyn FnMut(Vec<f64>) -> Vec<f64>| grains.chain(acc, fold);
        let (Some(u), Some(c)) = (&mut self.unwrapper, &mut self.correlator) else {
            let scenario = simulation.scenario();
            let periodic = scenario
                .axes()
                .iter()
                .map(|a| *a == crate::boundary::AxisKind::Periodic)
                .collect();
            self.m_min = lightest(simulation);
            let species_count = snap.species_names.len();
            let mut mine = vec![0u64; species_count];
            for &s in &snap.species {
                mine[s as usize] += 1;
            }
            // Grains of each species before this block (the chained counts' prefix), and
            // in the whole system.
            let mut before = vec![0usize; species_count];
            let counts: Vec<f64> = mine.iter().map(|&c| c as f64).collect();
            let totals = grains.chain(vec![0.0; species_count], |acc| {
                before = acc.iter().map(|&x| x as usize).collect();
                acc.iter().zip(&counts).map(|(a, b)| a + b).collect()
            });
            let totals: Vec<usize> = totals.iter().map(|&x| x as usize).collect();
            let u = Unwrapper::new(scenario.lengths(), periodic, &snap.positions, now, k);
            let mut c =
                LogLagCorrelator::for_block(snap.dimension, &snap.species, &before, &totals);
            c.add_chained(&u.unwrapped, &snap.velocities, &mut chain);
            self.unwrapper = Some(u);
            self.correlator = Some(c);
            self.first = grains.first;
            self.names = snap.species_names.clone();
            self.start = now;
            self.last = now;
            return Ok(());
        };
        let x = u
            .update(&snap.positions, now, k, self.m_min)
            .map_err(|m| interval_error(interval, m))?;
        // Only samples on the grid `start + j interval` enter the correlator (a last
        // output at a stop rule between output times does not).
        let expected = self.start + c.samples as f64 * interval;
        if (now - expected).abs() <= 1e-6 * interval {
            c.add_chained(x, &snap.velocities, &mut chain);
            self.last = now;
        }
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let Some(c) = &self.correlator else {
            return Ok(());
        };
        let out = &simulation.scenario().output;
        let interval = out.interval;
        self.write(c, interval)?;
        let span = self.last - self.start;
        let (from, to) = match out.msd_fit.as_slice() {
            [a, b] => (*a, *b),
            _ => (0.1 * span, 0.5 * span),
        };
        let single = self.names.len() == 1;
        let nan = (f64::NAN, f64::NAN);
        for (s, name) in self.names.iter().enumerate() {
            let suffix = if single {
                String::new()
            } else {
                format!(".{name}")
            };
            let einstein = c.einstein(s, interval, from, to).unwrap_or(nan);
            let green_kubo = c.green_kubo(s, interval, from).unwrap_or(nan);
            let f = &mut summary.final_observables;
            f.insert(format!("diffusion_coefficient{suffix}"), einstein.0);
            f.insert(format!("diffusion_coefficient_error{suffix}"), einstein.1);
            f.insert(
                format!("diffusion_coefficient_green_kubo{suffix}"),
                green_kubo.0,
            );
            f.insert(
                format!("diffusion_coefficient_green_kubo_error{suffix}"),
                green_kubo.1,
            );
        }
        summary
            .final_observables
            .insert("diffusion_fit_from".into(), from);
        summary
            .final_observables
            .insert("diffusion_fit_to".into(), to);
        Ok(())
    }
}
