//! The recorder of a run directory: its files, log, outputs and checkpoints, apart from the
//! simulation they record ([`super::Run`] drives both).

/// The files and log of a run directory, apart from the simulation they record.
pub(super) struct Recorder {
    pub(super) dir: PathBuf,
    pub(super) outputs: StandardOutputs,
    pub(super) attached: Vec<Box<dyn Output + Send>>,
    pub(super) log: std::fs::File,
    /// The directory's lock, held while the run lives.
    pub(super) _lock: lock::Lock,
    /// Whether the outputs have been set up and have seen the start.
    pub(super) started: bool,
    pub(super) warnings: Vec<String>,
    /// The run directory every rank of a decomposed run writes its checkpoint parts and
    /// snapshot blocks into (rank 0's `dir`).
    pub(super) shared: Option<PathBuf>,
    /// The number of the last checkpoint written in parts.
    pub(super) generation: u64,
    /// Changes in flight written to `log.txt` so far.
    pub(super) logged_changes: usize,
}

use super::{
    CHECKPOINT_FORMAT, Checkpoint, DirectoryState, Output, ResolvedSummary, RunDir, RunError,
    RunFile, StandardOutputs, Summary, checkpoint, io_err, lock, summary,
};
use crate::build::AnyEngine;
use crate::output::format_number;
use crate::scenario::Scenario;
use crate::simulation::{Simulation, StopReason};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

impl Recorder {
    /// Prepares `dir` for a new run: refuses a directory that is neither empty nor a run
    /// directory, takes its lock, removes the files of an earlier run that a new run would
    /// not overwrite, writes `scenario.toml` (and `initial_state.npz`, with the arrays that
    /// came from NumPy or another `.npz` file), and opens `log.txt`; returns the scenario as
    /// stored (naming `initial_state.npz`).
    #[allow(clippy::type_complexity)]
    pub(super) fn prepare(
        dir: &Path,
        scenario: Scenario,
    ) -> Result<(std::fs::File, (lock::Lock, Option<String>), Scenario), RunError> {
        let run_dir = RunDir::new(dir);
        if run_dir.state() == DirectoryState::Other {
            return Err(RunError::Directory {
                dir: dir.to_path_buf(),
                message: "is neither empty nor a run directory; granular writes runs only \
                          into a new or empty directory or over an earlier run. Choose \
                          another --out (e.g. a new subdirectory)"
                    .into(),
            });
        }
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        let lock = lock::Lock::acquire(dir)?;
        run_dir.clear_earlier_run();
        let scenario = run_dir.store_initial_state(scenario)?;
        let path = run_dir.file(RunFile::Scenario);
        std::fs::write(&path, scenario.to_toml()).map_err(io_err(&path))?;
        let log_path = run_dir.file(RunFile::Log);
        let log = std::fs::File::create(&log_path).map_err(io_err(&log_path))?;
        Ok((log, lock, scenario))
    }

    pub(super) fn log(&mut self, wall_seconds: f64, msg: &str) {
        let _ = writeln!(self.log, "[{wall_seconds:9.3} s] {msg}");
    }

    /// Writes the changes in flight made since the last call (by `Simulation::set` or the
    /// scenario's `[[schedule]]`) to `log.txt`.
    pub(super) fn log_changes(&mut self, simulation: &Simulation) {
        let new = simulation
            .changes()
            .get(self.logged_changes..)
            .unwrap_or(&[]);
        let lines: Vec<String> = new
            .iter()
            .map(|c| {
                format!(
                    "set {} from {} to {} at t = {}",
                    c.key,
                    c.old,
                    c.new,
                    format_number(c.time)
                )
            })
            .collect();
        self.logged_changes += lines.len();
        for line in lines {
            self.log(simulation.wall_seconds(), &line);
        }
    }

    /// Sets the outputs up and records the start, once.
    pub(super) fn start(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if self.started {
            return Ok(());
        }
        self.started = true;
        // Parameters changed in flight before the run was recorded.
        self.log_changes(simulation);
        self.outputs.setup(simulation)?;
        for o in &mut self.attached {
            o.setup(simulation)?;
        }
        self.observe(simulation)
    }

    pub(super) fn observe(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if let Some(domain) = simulation.engine().domain() {
            // How the ranks share the work (log.txt): grains per rank and the time spent
            // waiting in communication, since the last output.
            let own = match simulation.engine() {
                AnyEngine::Dsmc2(e) => e.local_len(),
                AnyEngine::Dsmc3(e) => e.local_len(),
                _ => 0,
            };
            let (balance, lo, hi, recuts) = domain.load_report(own);
            self.log(
                simulation.wall_seconds(),
                &format!(
                    "ranks: grains per rank max/mean {balance:.3}; time in communication \
                     (waiting included) {:.1} to {:.1} % per rank; cuts moved {recuts} times",
                    100.0 * lo,
                    100.0 * hi
                ),
            );
        }
        let observation = simulation.observe();
        self.outputs.observe(simulation, &observation)?;
        for o in &mut self.attached {
            o.observe(simulation, &observation)?;
        }
        Ok(())
    }

    pub(super) fn checkpoint(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if let Some(domain) = simulation.engine().domain() {
            return self.checkpoint_in_parts(simulation, domain.rank());
        }
        let cp = Checkpoint {
            format: CHECKPOINT_FORMAT,
            scenario: simulation.initial_scenario().to_toml(),
            simulation: simulation.state(),
            outputs: self.outputs.clone(),
            parts: None,
        };
        self.write_checkpoint(simulation, &cp)
    }

    pub(super) fn write_checkpoint(
        &mut self,
        simulation: &Simulation,
        cp: &Checkpoint,
    ) -> Result<(), RunError> {
        let path = checkpoint::path(&self.dir);
        let bytes = rmp_serde::to_vec_named(cp).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: e.to_string(),
        })?;
        if let Err(e) = checkpoint::write_atomic(&path, &checkpoint::encode(&bytes)) {
            self.log(simulation.wall_seconds(), &e.to_string());
            return Err(e);
        }
        self.log(
            simulation.wall_seconds(),
            &format!("checkpoint at t = {}", format_number(simulation.time())),
        );
        Ok(())
    }

    pub(super) fn finish(
        mut self,
        simulation: &Simulation,
        reason: StopReason,
    ) -> Result<Summary, RunError> {
        let wall = simulation.wall_seconds();
        let events = simulation.events();
        let collisions = simulation.collisions();
        let mut summary = Summary {
            engine: simulation.engine_name().to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            seed: simulation.scenario().seed,
            dimension: simulation.dimension(),
            n: simulation.particle_count(),
            wall_seconds: wall,
            events,
            events_per_second: events as f64 / wall.max(1e-9),
            collisions,
            collisions_per_second: collisions as f64 / wall.max(1e-9),
            stop_reason: reason.as_str().to_string(),
            initial_kinetic_energy: simulation.initial_kinetic_energy(),
            final_observables: BTreeMap::new(),
            maxwell_boltzmann_fit: BTreeMap::new(),
            species: BTreeMap::new(),
            scaled_speeds: BTreeMap::new(),
            crater: None,
            intruder: None,
            averages: None,
            steady_state: None,
            rough: None,
            resolved: ResolvedSummary::of(simulation.resolved()),
            ranks: None,
            warnings: self.warnings.clone(),
            changes: simulation.changes().to_vec(),
            outputs: simulation.outputs_done(),
            snapshots: 0,
        };
        self.outputs.finish(simulation, &mut summary)?;
        for o in &mut self.attached {
            o.finish(simulation, &mut summary)?;
        }
        // After the outputs, which may read the grains by blocks (and so hold more).
        summary.ranks = ranks_summary(simulation);
        let run_dir = RunDir::new(&self.dir);
        let path = run_dir.file(RunFile::Summary);
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        std::fs::write(&path, text + "\n").map_err(io_err(&path))?;
        run_dir.remove_checkpoint();
        self.log(
            wall,
            &format!("finished ({reason}): {events} events, {collisions} collisions, {wall:.3} s"),
        );
        Ok(summary)
    }
}

/// How the ranks of a decomposed DSMC run shared the grains (collective; `None` for a run
/// in one process).
fn ranks_summary(simulation: &Simulation) -> Option<summary::RanksSummary> {
    let domain = simulation.engine().domain()?;
    let own = match simulation.engine() {
        AnyEngine::Dsmc2(e) => e.local_len(),
        AnyEngine::Dsmc3(e) => e.local_len(),
        _ => 0,
    };
    let peaks = domain.peaks(own);
    let ranks = peaks.len();
    let n = simulation.particle_count().max(1) as f64;
    let most = peaks.iter().map(|p| p.0).max().unwrap_or(0);
    Some(summary::RanksSummary {
        ranks,
        peak_grains: peaks.iter().map(|p| p.0).collect(),
        peak_over_even_share: most as f64 * ranks as f64 / n,
        final_grains: peaks.iter().map(|p| p.1).collect(),
        cuts_moved: domain.recuts(),
    })
}
