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
pub struct TransportOutput {
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
    names: Vec<String>,
}

impl TransportOutput {
    /// MSD and VACF written into `dir`.
    pub fn new(dir: &Path) -> TransportOutput {
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
            ("mean_square_displacement.csv", "msd"),
            ("velocity_autocorrelation.csv", "vacf"),
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

/// The `output.interval` error of the unwrapping guard.
fn interval_error(interval: f64, message: String) -> RunError {
    RunError::Output {
        key: "output.interval".into(),
        message: format!(
            "is {interval}: for the mean-square displacement {message}; give a shorter output interval"
        ),
    }
}

impl Output for TransportOutput {
    /// Refuses an output interval in which a grain could cross half a periodic edge
    /// (before the run starts), and a run over ranks above
    /// `GATHER_LIMIT` (10^6) grains (every rank gathers the whole system).
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        crate::run::grains::refuse_whole_gather(simulation, "output.msd")?;
        let Some(snap) = simulation.snapshot() else {
            return Ok(());
        };
        let scenario = simulation.scenario();
        let m_min = snap.masses.iter().fold(f64::INFINITY, |a, &b| a.min(b));
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
                    "a grain as fast as the kinetic energy allows could cross half a periodic edge in {allowed}, so its periodic images would be ambiguous (minimum-image unwrapping)"
                ),
            ));
        }
        Ok(())
    }

    fn observe(
        &mut self,
        simulation: &Simulation,
        observation: &Observation,
    ) -> Result<(), RunError> {
        let Some(snap) = simulation.snapshot() else {
            return Ok(());
        };
        let now = simulation.time();
        let interval = simulation.scenario().output.interval;
        let k = observation.kinetic_energy;
        let (Some(u), Some(c)) = (&mut self.unwrapper, &mut self.correlator) else {
            let scenario = simulation.scenario();
            let periodic = scenario
                .axes()
                .iter()
                .map(|a| *a == crate::boundary::AxisKind::Periodic)
                .collect();
            self.m_min = snap.masses.iter().fold(f64::INFINITY, |a, &b| a.min(b));
            let u = Unwrapper::new(scenario.lengths(), periodic, &snap.positions, now, k);
            let mut c =
                LogLagCorrelator::new(snap.dimension, &snap.species, snap.species_names.len());
            c.add(&u.unwrapped, &snap.velocities);
            self.unwrapper = Some(u);
            self.correlator = Some(c);
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
            c.add(x, &snap.velocities);
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
