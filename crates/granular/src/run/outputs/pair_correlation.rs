//! `pair_correlation.csv`: the radial pair correlation `g(r)` per species pair, averaged
//! over the observation times, and its contact value in the summary (`final.contact_value`
//! and `final.contact_value_error`; per pair `contact_value.<a>.<b>` in a mixture). The
//! binning, the box's exact normalisation and the contact fit are in
//! [`crate::structure`].

use super::{Output, spatial::observation_due, write_table};
use crate::observation::Observation;
use crate::run::{RunError, Summary};
use crate::simulation::Simulation;
use crate::structure::{PairCorrelation, PairGeometry};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// `g(r)` accumulated over the observation times (part of the checkpoint).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct PairCorrelationOutput {
    #[serde(skip)]
    dir: PathBuf,
    /// Index of the next entry of `output.observable_times` to wait for.
    next_time: usize,
    /// The accumulator (built at the first observation).
    accumulator: Option<PairCorrelation>,
    /// Species names.
    names: Vec<String>,
}

impl PairCorrelationOutput {
    /// `g(r)` written into `dir`.
    pub(crate) fn new(dir: &Path) -> PairCorrelationOutput {
        PairCorrelationOutput {
            dir: dir.to_path_buf(),
            ..PairCorrelationOutput::default()
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.to_path_buf();
    }

    /// Column suffix of species pair `p`.
    fn pair_name(&self, a: usize, b: usize) -> String {
        format!("{}.{}", self.names[a], self.names[b])
    }

    fn write(&self, g: &PairCorrelation) -> Result<(), RunError> {
        let pairs = g.geometry.pairs();
        let mut header = vec!["r".to_string()];
        header.extend(
            pairs
                .iter()
                .map(|&(a, b)| format!("g.{}", self.pair_name(a, b))),
        );
        let values = g.g();
        let rows: Vec<Vec<f64>> = g
            .centres()
            .iter()
            .enumerate()
            .map(|(k, &r)| {
                std::iter::once(r)
                    .chain(values.iter().map(|v| v[k]))
                    .collect()
            })
            .collect();
        write_table(
            &self.dir.join(crate::run::RunFile::PairCorrelation.name()),
            &header,
            &rows,
        )
    }
}

impl Output for PairCorrelationOutput {
    fn observe(&mut self, simulation: &Simulation, _: &Observation) -> Result<(), RunError> {
        let first = simulation.outputs_done() == 0;
        let out = &simulation.scenario().output;
        if !observation_due(&mut self.next_time, out, simulation.time(), first) {
            return Ok(());
        }
        // With listed times after t = 0, the initial placement (not an equilibrium state)
        // is left out.
        if first && out.observable_times.first().is_some_and(|&t| t > 0.0) {
            return Ok(());
        }
        let Some(snap) = simulation.snapshot() else {
            return Ok(());
        };
        if self.accumulator.is_none() {
            let species = snap.species_names.len();
            let mut radii = vec![0.0; species];
            let mut counts = vec![0usize; species];
            for (&s, &r) in snap.species.iter().zip(&snap.radii) {
                radii[s as usize] = r;
                counts[s as usize] += 1;
            }
            let scenario = simulation.scenario();
            let geometry = PairGeometry {
                lengths: scenario.lengths(),
                periodic: scenario
                    .axes()
                    .iter()
                    .map(|a| *a == crate::boundary::AxisKind::Periodic)
                    .collect(),
                radii: radii.clone(),
                counts,
            };
            let r_max =
                out.pair_correlation_range * 2.0 * radii.iter().fold(0.0f64, |a, &b| a.max(b));
            let acc = PairCorrelation::new(geometry, out.pair_correlation_bins, r_max).map_err(
                |message| RunError::Output {
                    key: "output.pair_correlation_range".into(),
                    message: format!(
                        "is {}: g(r) {message}; lower it",
                        out.pair_correlation_range
                    ),
                },
            )?;
            self.accumulator = Some(acc);
            self.names = snap.species_names.clone();
        }
        if let Some(acc) = &mut self.accumulator {
            acc.add(&snap.positions, &snap.species);
        }
        if let Some(acc) = &self.accumulator {
            self.write(acc)?;
        }
        Ok(())
    }

    fn finish(&mut self, _: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let Some(acc) = &self.accumulator else {
            return Ok(());
        };
        let pairs = acc.geometry.pairs();
        for (p, &(a, b)) in pairs.iter().enumerate() {
            let (value, error) = acc.contact_value(p).unwrap_or((f64::NAN, f64::NAN));
            let key = if pairs.len() == 1 {
                "contact_value".to_string()
            } else {
                format!("contact_value.{}", self.pair_name(a, b))
            };
            summary
                .final_observables
                .insert(format!("{key}_error"), error);
            summary.final_observables.insert(key, value);
        }
        Ok(())
    }
}
