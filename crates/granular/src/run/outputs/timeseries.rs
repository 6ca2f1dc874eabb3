//! `timeseries.csv`: one row of the observation per output time, with the rates of the
//! window since the previous row; the last row is the `final` block of the summary.

use super::Output;
use crate::observation::Observation;
use crate::run::{RunError, Summary, io_err};
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The time series of a run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct TimeSeries {
    #[serde(skip)]
    path: PathBuf,
    /// Column names, fixed by the first row.
    columns: Vec<String>,
    /// The observation of the previous row: the start of the next rate window.
    previous: Option<Observation>,
    /// The last row, by column.
    last: Vec<(String, f64)>,
    /// Bytes of the file written so far (a resumed run cuts the file back to this).
    bytes: u64,
}

impl TimeSeries {
    /// A time series written to `dir/timeseries.csv`.
    pub(crate) fn new(dir: &Path) -> TimeSeries {
        TimeSeries {
            path: dir.join(crate::run::RunFile::TimeSeries.name()),
            columns: Vec::new(),
            previous: None,
            last: Vec::new(),
            bytes: 0,
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.path = dir.join(crate::run::RunFile::TimeSeries.name());
    }

    /// Cuts the file back to the rows written before the checkpoint.
    pub(crate) fn rewind(&self) -> Result<(), RunError> {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(&self.path)
            .map_err(io_err(&self.path))?;
        file.set_len(self.bytes).map_err(io_err(&self.path))
    }

    fn write_record(&mut self, fields: &[String], create: bool) -> Result<(), RunError> {
        let file = if create {
            std::fs::File::create(&self.path)
        } else {
            std::fs::OpenOptions::new().append(true).open(&self.path)
        }
        .map_err(io_err(&self.path))?;
        let mut writer = csv::Writer::from_writer(file);
        let csv_err = |e: csv::Error| RunError::Io {
            path: self.path.clone(),
            source: std::io::Error::other(e),
        };
        writer.write_record(fields).map_err(csv_err)?;
        writer.flush().map_err(io_err(&self.path))?;
        self.bytes = std::fs::metadata(&self.path)
            .map_err(io_err(&self.path))?
            .len();
        Ok(())
    }
}

impl Output for TimeSeries {
    fn observe(&mut self, _: &Simulation, observation: &Observation) -> Result<(), RunError> {
        let rates = self
            .previous
            .as_ref()
            .map(|earlier| observation.rates_since(earlier));
        let values = observation.columns(rates.as_ref());
        if self.columns.is_empty() {
            self.columns = values.iter().map(|(k, _)| k.clone()).collect();
            let header = self.columns.clone();
            self.write_record(&header, true)?;
        }
        // Every row has the columns of the first (a species' value absent: `nan`).
        let row: Vec<String> = self
            .columns
            .iter()
            .map(|c| {
                values
                    .iter()
                    .find(|(k, _)| k == c)
                    .map_or(String::from("nan"), |(_, v)| format!("{v:e}"))
            })
            .collect();
        self.write_record(&row, false)?;
        self.previous = Some(observation.clone());
        self.last = values;
        Ok(())
    }

    fn finish(&mut self, _: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        summary.final_observables = self.last.iter().cloned().collect();
        Ok(())
    }
}
