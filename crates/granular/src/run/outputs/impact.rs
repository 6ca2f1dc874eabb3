//! `impact_parameter.csv`: the histogram of `b / σ` of all pair collisions of the run
//! (DSMC section 3.2, Fig. 2b).

use super::Output;
use crate::observation::Observation;
use crate::run::{RunError, Summary, io_err};
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The impact-parameter histogram of the whole run, written at the end.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct ImpactParameter {
    #[serde(skip)]
    path: PathBuf,
}

impl ImpactParameter {
    /// Written to `dir/impact_parameter.csv`.
    pub(crate) fn new(dir: &Path) -> ImpactParameter {
        ImpactParameter {
            path: dir.join(crate::run::RunFile::ImpactParameter.name()),
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.path = dir.join(crate::run::RunFile::ImpactParameter.name());
    }
}

impl Output for ImpactParameter {
    fn observe(&mut self, _: &Simulation, _: &Observation) -> Result<(), RunError> {
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, _: &mut Summary) -> Result<(), RunError> {
        let Some(h) = simulation.impact_histogram() else {
            return Ok(());
        };
        let mut out = String::from("b_over_sigma_low,b_over_sigma_high,count,density\n");
        let dens = h.density();
        for (b, c) in h.counts.iter().enumerate() {
            let lo = h.min + b as f64 * h.bin_width();
            out.push_str(&format!(
                "{:e},{:e},{},{:e}\n",
                lo,
                lo + h.bin_width(),
                c,
                dens[b]
            ));
        }
        std::fs::write(&self.path, out).map_err(io_err(&self.path))
    }
}
