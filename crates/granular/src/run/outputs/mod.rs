//! Outputs: what is attached to a simulation to record it. Each output is set up at the
//! start, observes the simulation at every output time and adds its block to the summary
//! at the end ([`Output`], in the spirit of lumol's `Output` and ripgrep's `Sink`). The run
//! directory is the set of standard outputs that the scenario's `[output]` table attaches
//! ([`StandardOutputs`]); a library user attaches their own with
//! [`Run::attach`](super::Run::attach).
//!
//! | output | file(s) |
//! |---|---|
//! | [`TimeSeries`] | `timeseries.csv` (written with the `csv` crate) |
//! | [`Snapshots`] | `snapshots/snapshot_NNNNNN.npz` |
//! | [`SpeedStatistics`] | `speed_histograms.csv`, `velocity_histograms.csv`; the Maxwell-Boltzmann fit and per-species averages of the summary |
//! | [`ImpactParameter`] | `impact_parameter.csv` |
//! | [`SpatialObservables`] | `impact_histograms.npz`, `structure_factor.npz`, `density_maps.npz` |
//! | [`Averages`] | the `averages` block of the summary (means and blocking errors) |
//! | [`Crater`] | the `crater` block of the summary |
//! | [`IntruderStatistics`] | `intruder_histograms.csv`, `.npz`; the `intruder` block |
//! | [`Trajectory`] | `trajectory/` (opt-in, `output.trajectory`): `trajectory.xyz`, `.lammpstrj`, `.gsd`, `.pvd` + `vtp/` |
//! | [`PairCorrelationOutput`] | `pair_correlation.csv`; `final.contact_value` |
//! | [`TransportOutput`] | `mean_square_displacement.csv`, `velocity_autocorrelation.csv`; `final.diffusion_coefficient` |

mod averages;
mod crater;
mod impact;
mod intruder;
mod pair_correlation;
mod rough;
mod scaled_speeds;
mod snapshots;
mod spatial;
mod speeds;
mod steady;
mod timeseries;
mod trajectory;
mod transport;

pub(crate) use averages::Averages;
pub(crate) use crater::Crater;
pub(crate) use impact::ImpactParameter;
pub(crate) use intruder::IntruderStatistics;
pub(crate) use pair_correlation::PairCorrelationOutput;
pub(crate) use snapshots::Snapshots;
pub(crate) use spatial::SpatialObservables;
pub(crate) use speeds::SpeedStatistics;
pub(crate) use timeseries::TimeSeries;
pub(crate) use trajectory::Trajectory;
pub(crate) use transport::TransportOutput;

use super::{RunError, Summary};
use crate::observation::Observation;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Something that records a simulation: set up at the start, called at every output time,
/// finished at the end.
pub trait Output {
    /// Once, before the observation at the start of the run.
    fn setup(&mut self, _simulation: &Simulation) -> Result<(), RunError> {
        Ok(())
    }

    /// At every output time, with the observation of that time (the same for every output).
    fn observe(
        &mut self,
        simulation: &Simulation,
        observation: &Observation,
    ) -> Result<(), RunError>;

    /// Once, at the end of the run: write what is left and fill the output's block of the
    /// summary.
    fn finish(&mut self, _simulation: &Simulation, _summary: &mut Summary) -> Result<(), RunError> {
        Ok(())
    }
}

/// The outputs of a run directory, as the scenario's `[output]` table attaches them. They
/// are part of a checkpoint (outputs attached by the user are not).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct StandardOutputs {
    timeseries: TimeSeries,
    snapshots: Snapshots,
    speeds: Option<SpeedStatistics>,
    spatial: Option<SpatialObservables>,
    impact: ImpactParameter,
    crater: Option<Crater>,
    intruder: Option<IntruderStatistics>,
    #[serde(default)]
    trajectory: Option<Trajectory>,
    averages: Averages,
    pair_correlation: Option<PairCorrelationOutput>,
    #[serde(default)]
    transport: Option<TransportOutput>,
}

impl StandardOutputs {
    /// The outputs a simulation's scenario asks for, writing into `dir`.
    pub(crate) fn for_simulation(dir: &Path, simulation: &Simulation) -> StandardOutputs {
        let scenario = simulation.scenario();
        // Every engine but the intruder models has grains (asked of the scenario, not of a
        // snapshot: that would gather a decomposed run).
        let grains = scenario.intruder().is_none();
        let o = &scenario.output;
        let spatial = o.impact_histograms || o.structure_factor || !o.density_map.is_empty();
        StandardOutputs {
            timeseries: TimeSeries::new(dir),
            snapshots: Snapshots::new(dir, o.snapshot_every),
            speeds: grains.then(|| SpeedStatistics::new(dir)),
            spatial: (grains && spatial).then(|| SpatialObservables::new(dir)),
            impact: ImpactParameter::new(dir),
            crater: scenario.crater().cloned().map(Crater::new),
            intruder: scenario
                .intruder()
                .is_some()
                .then(|| IntruderStatistics::new(dir)),
            trajectory: (grains && !o.trajectory.is_empty())
                .then(|| Trajectory::new(dir, &o.trajectory, o.snapshot_every)),
            averages: Averages::new(),
            pair_correlation: (grains && o.pair_correlation)
                .then(|| PairCorrelationOutput::new(dir)),
            transport: (grains && o.msd).then(|| TransportOutput::new(dir)),
        }
    }

    /// Points every file output at `dir` (after a checkpoint is read back: the directory
    /// may have moved).
    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.timeseries.relocate(dir);
        self.snapshots.relocate(dir);
        if let Some(s) = &mut self.speeds {
            s.relocate(dir);
        }
        if let Some(s) = &mut self.spatial {
            s.relocate(dir);
        }
        self.impact.relocate(dir);
        if let Some(i) = &mut self.intruder {
            i.relocate(dir);
        }
        if let Some(t) = &mut self.trajectory {
            t.relocate(dir);
        }
        if let Some(g) = &mut self.pair_correlation {
            g.relocate(dir);
        }
        if let Some(t) = &mut self.transport {
            t.relocate(dir);
        }
    }

    /// Makes the snapshots of a decomposed run go to `dir`, the run directory every rank
    /// sees (each rank writes its block there; see [`crate::run::parts`]).
    pub(crate) fn share(&mut self, dir: &Path) {
        self.snapshots.share(dir);
        if let Some(t) = &mut self.trajectory {
            t.share(dir);
        }
    }

    /// Moves the per-grain state of the outputs that keep one (the MSD's unwrapped
    /// positions and samples) out: `None` when there is none.
    pub(crate) fn take_rows(&mut self) -> Option<crate::transport::GrainRows> {
        self.transport.as_mut().and_then(TransportOutput::take_rows)
    }

    /// Puts per-grain state back ([`StandardOutputs::take_rows`]).
    pub(crate) fn put_rows(&mut self, rows: crate::transport::GrainRows) {
        if let Some(t) = &mut self.transport {
            t.put_rows(rows);
        }
    }

    /// Cuts files that are appended to back to where the checkpoint left them; the
    /// trajectory files only where this process writes them (`trajectories`: not on the
    /// ranks other than 0 of a decomposed run, whose directory has none).
    pub(crate) fn rewind(&self, trajectories: bool) -> Result<(), RunError> {
        self.timeseries.rewind()?;
        match &self.trajectory {
            Some(t) if trajectories => t.rewind(),
            _ => Ok(()),
        }
    }

    /// The outputs in the order they are called (the time series first: the others read
    /// nothing from it, but a failure there is the most useful to report first).
    fn each(&mut self) -> Vec<&mut dyn Output> {
        let mut out: Vec<&mut dyn Output> = vec![&mut self.timeseries];
        if let Some(s) = &mut self.spatial {
            out.push(s);
        }
        out.push(&mut self.snapshots);
        if let Some(t) = &mut self.trajectory {
            out.push(t);
        }
        if let Some(s) = &mut self.speeds {
            out.push(s);
        }
        out.push(&mut self.impact);
        if let Some(c) = &mut self.crater {
            out.push(c);
        }
        if let Some(i) = &mut self.intruder {
            out.push(i);
        }
        out.push(&mut self.averages);
        if let Some(g) = &mut self.pair_correlation {
            out.push(g);
        }
        if let Some(t) = &mut self.transport {
            out.push(t);
        }
        out
    }
}

impl Output for StandardOutputs {
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        self.each()
            .into_iter()
            .try_for_each(|o| o.setup(simulation))
    }

    fn observe(
        &mut self,
        simulation: &Simulation,
        observation: &Observation,
    ) -> Result<(), RunError> {
        self.each()
            .into_iter()
            .try_for_each(|o| o.observe(simulation, observation))
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        self.each()
            .into_iter()
            .try_for_each(|o| o.finish(simulation, summary))
    }
}

/// Writes a CSV table with a header row (numbers in full precision, NaN as `NaN`), as
/// NumPy's `genfromtxt(names=True, delimiter=",")` and pandas read it.
pub(super) fn write_table(
    path: &Path,
    header: &[String],
    rows: &[Vec<f64>],
) -> Result<(), RunError> {
    let csv_err = |e: csv::Error| RunError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    };
    let mut writer = csv::Writer::from_path(path).map_err(csv_err)?;
    writer.write_record(header).map_err(csv_err)?;
    for row in rows {
        writer
            .write_record(row.iter().map(|x| format!("{x}")))
            .map_err(csv_err)?;
    }
    writer.flush().map_err(super::io_err(path))
}
