//! A run: a [`Simulation`] run to its stop rule with the standard outputs of its scenario
//! attached (`outputs`), a log, checkpoints and the summary, recorded into a run
//! directory. The directory's files, their names and their readers are [`dir`]'s
//! ([`RunDir`]).

pub mod checkpoint;
pub mod dir;
pub(crate) mod grains;
mod lock;
pub(crate) mod outputs;
pub(crate) mod parts;
mod recorder;
pub mod summary;
pub mod sweep;

pub(crate) use crate::build::build_on;
/// The intruder engines behind one type (moved to [`crate::build::intruder`]).
pub use crate::build::{AnyEngine, BuildError, MemoryBudget, build, initial_particles, intruder};
pub use crate::output::npz::write_snapshot;
pub use dir::{DirectoryState, RunDir, RunFile, Table, read_snapshot};
pub use outputs::Output;
pub(crate) use outputs::StandardOutputs;
pub use summary::{AverageValue, AveragesSummary, ResolvedSummary, Summary};

use crate::engine::EngineError;
use crate::output::format_number;
use crate::scenario::Scenario;
use crate::simulation::{RunHooks, Simulation, SimulationState};
use recorder::Recorder;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Version of the checkpoint format; bumped when the state layout changes (3: the event
/// codes of cell crossings carry the partner bound of the cheap crossing; 4: the event
/// queue's bucket lists end at an index instead of a sentinel; 5: the event queue is a
/// tournament tree or a calendar, by the number of grains; 6: the cell grid keeps a few
/// large grains out of its lists; 7: the run's outputs as typed states, the time series'
/// rate window out of the event-driven engine; 8: a header with the payload's length and
/// CRC-32 before the MessagePack payload, [`checkpoint`]; 9: the blocking accumulators of
/// the summary's `averages`; 10: the engines' driving state; 11: the DSMC engine's species
/// table instead of one species name; 12: the DSMC record's positions as lattice words
/// carrying the identities; 13: the initial temperature the scenario's derived values are
/// resolved at; 14: the parameters changed in flight and the random streams of a state set
/// from outside; 15: the `[[schedule]]` entries applied, and the scenario as it started
/// rather than as changed in flight).
pub const CHECKPOINT_FORMAT: u32 = 15;

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The engine stopped (collapse, numerical breakdown).
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// Building the engine failed.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A NumPy file could not be written or read.
    #[error(transparent)]
    Npz(#[from] crate::output::npz::NpzError),
    /// A file of the run directory could not be read as what it should be.
    #[error("{path}: {message}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A trajectory file could not be written.
    #[error(transparent)]
    Trajectory(#[from] crate::trajectory::TrajectoryError),
    /// A checkpoint could not be read.
    #[error("checkpoint {path}: {message}")]
    Checkpoint {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A checkpoint could not be written (a full disk).
    #[error("could not write the checkpoint {path}: {message}")]
    CheckpointWrite {
        /// The file.
        path: PathBuf,
        /// What went wrong and what to do.
        message: String,
    },
    /// Another process is running in the run directory.
    #[error("run directory {dir} is in use: {message}")]
    Locked {
        /// The run directory.
        dir: PathBuf,
        /// Who holds it and what to do.
        message: String,
    },
    /// The directory cannot be used for this (not a run directory, a finished run, an
    /// edited scenario).
    #[error("{dir}: {message}")]
    Directory {
        /// The directory.
        dir: PathBuf,
        /// What is wrong and what to do.
        message: String,
    },
    /// An output cannot record this run as configured (checked when the output starts).
    #[error("`{key}` {message}")]
    Output {
        /// The scenario key to change.
        key: String,
        /// Its value, what is wrong and the fix.
        message: String,
    },
    /// The run was interrupted on request (Ctrl-C, SIGTERM); a checkpoint was written.
    #[error(
        "interrupted at t = {time}; state saved in {}. Continue with `granular resume {}`",
        checkpoint::path(dir).display(),
        dir.display()
    )]
    Interrupted {
        /// The run directory.
        dir: PathBuf,
        /// Simulation time of the checkpoint, formatted.
        time: String,
    },
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// What the caller sees while a run progresses.
#[derive(Clone, Debug)]
pub struct ProgressReport {
    /// Fraction of the run done, in [0, 1], from the nearest stop rule.
    pub fraction: f64,
    /// Simulation time.
    pub time: f64,
    /// Events so far.
    pub events: u64,
    /// Events per wall-clock second in this session.
    pub events_per_second: f64,
}

/// Everything a checkpoint holds ([`RunDir::checkpoint`] reads it).
#[derive(Serialize, Deserialize)]
pub(crate) struct Checkpoint {
    format: u32,
    scenario: String,
    simulation: SimulationState,
    outputs: StandardOutputs,
    /// A run decomposed over ranks: the engine above has no particles; they are in
    /// these parts ([`parts`]). Absent from the threaded run's checkpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    parts: Option<parts::Manifest>,
}

/// A run in progress in a run directory.
pub struct Run {
    simulation: Simulation,
    recorder: Recorder,
    interrupt: Option<Box<dyn FnMut() -> bool + Send>>,
    /// Makes the ranks of a decomposed run take the same decision (see [`Run::agree_with`]).
    agree: Option<Agree>,
}

/// A collective "does any rank say yes" (a decomposed run's ranks agree on when to
/// checkpoint and on an interruption, which each sees at its own time).
pub type Agree = Box<dyn FnMut(bool) -> bool + Send>;

/// Warnings about the set-up, for the log and the summary's `warnings`: DSMC's validity
/// conditions violated by the initial state (computed when the engine was built, and
/// carried by checkpoints) and the pre-flight estimate's warning on the scenario.
fn set_up_warnings(simulation: &Simulation) -> Vec<String> {
    let mut warnings = Vec::new();
    if let AnyEngine::Dsmc2(e) = simulation.engine() {
        warnings.extend(e.validity_warnings().iter().map(|w| w.message.clone()));
    }
    if let AnyEngine::Dsmc3(e) = simulation.engine() {
        warnings.extend(e.validity_warnings().iter().map(|w| w.message.clone()));
    }
    warnings.extend(simulation.scenario().cost().warning(simulation.scenario()));
    warnings
}

impl Run {
    /// Starts a new run of `scenario` in `dir`: created if missing; an empty directory or
    /// an earlier run directory (whose files are replaced) is used; a directory with other
    /// files is refused, and so is one in which another process runs.
    pub fn create(dir: &Path, scenario: Scenario) -> Result<Run, RunError> {
        let start = Instant::now();
        let (log, lock, scenario) = Recorder::prepare(dir, scenario)?;
        let simulation = Simulation::new(scenario)?;
        let mut run = Run::with_log(dir, simulation, log, lock);
        run.recorder.log(
            start.elapsed().as_secs_f64(),
            &format!(
                "built {} engine: {} grains, dimension {}, seed {} ({:.3} s)",
                run.simulation.engine_name(),
                run.simulation.particle_count(),
                run.simulation.scenario().dimension,
                run.simulation.scenario().seed,
                start.elapsed().as_secs_f64()
            ),
        );
        Ok(run)
    }

    /// [`Run::create`], split over the ranks of `comm` when it is given (collective):
    /// every rank creates only its own grains (`build_on`); `dir` is this rank's
    /// directory, `shared` the run directory every rank sees (rank 0's `dir`), where each
    /// rank writes its checkpoint parts and its blocks of the snapshots. With `memory`, a
    /// DSMC run whose most loaded rank would not fit in its share of the node is refused
    /// before the grains go to their slabs ([`crate::build::MemoryBudget::check`]; `None`:
    /// no check, as `--insist`).
    pub fn create_on(
        dir: &Path,
        scenario: Scenario,
        comm: Option<std::sync::Arc<dyn crate::dsmc::Communicator>>,
        shared: &Path,
        memory: Option<crate::build::MemoryBudget>,
    ) -> Result<Run, RunError> {
        let start = Instant::now();
        let (log, lock, scenario) = Recorder::prepare(dir, scenario)?;
        let (engine, resolved) = build_on(&scenario, comm.clone(), memory)?;
        let simulation = Simulation::from_parts(scenario, engine, resolved);
        let mut run = Run::with_log(dir, simulation, log, lock);
        if let Some(comm) = comm {
            run.decompose(comm, shared)
                .map_err(|e| RunError::Build(BuildError::Dsmc(e.to_string())))?;
        }
        let over = match run.simulation.engine().domain() {
            Some(d) => format!(" over {} ranks", d.size()),
            None => String::new(),
        };
        run.recorder.log(
            start.elapsed().as_secs_f64(),
            &format!(
                "built {} engine{over}: {} grains, dimension {}, seed {} ({:.3} s)",
                run.simulation.engine_name(),
                run.simulation.particle_count(),
                run.simulation.scenario().dimension,
                run.simulation.scenario().seed,
                start.elapsed().as_secs_f64()
            ),
        );
        Ok(run)
    }

    /// Records `simulation` (built in memory, perhaps advanced) into `dir`; the outputs
    /// start at its current time. `scenario.toml` is the scenario as the simulation
    /// started (as in its checkpoints); the changes made in flight so far go to `log.txt`
    /// and the summary.
    pub fn from_simulation(dir: &Path, mut simulation: Simulation) -> Result<Run, RunError> {
        let (log, lock, stored) = Recorder::prepare(dir, simulation.initial_scenario().clone())?;
        simulation.keep_initial_scenario(stored);
        Ok(Run::with_log(dir, simulation, log, lock))
    }

    fn with_log(
        dir: &Path,
        simulation: Simulation,
        log: std::fs::File,
        (lock, note): (lock::Lock, Option<String>),
    ) -> Run {
        let warnings = set_up_warnings(&simulation);
        let mut recorder = Recorder {
            dir: dir.to_path_buf(),
            outputs: StandardOutputs::for_simulation(dir, &simulation),
            attached: Vec::new(),
            log,
            _lock: lock,
            started: false,
            warnings,
            shared: None,
            generation: 0,
            logged_changes: 0,
        };
        if let Some(note) = note {
            recorder.log(0.0, &note);
        }
        for w in recorder.warnings.clone() {
            recorder.log(0.0, &format!("warning: {w}"));
        }
        Run {
            simulation,
            recorder,
            interrupt: None,
            agree: None,
        }
    }

    /// Reopens an interrupted run from its checkpoint. Refused when the directory is
    /// missing, holds a finished run, has no checkpoint, is in use by another process, when
    /// the checkpoint is damaged (its CRC-32, length and format are checked) or when
    /// `scenario.toml` was edited after the run started.
    pub fn resume(dir: &Path) -> Result<Run, RunError> {
        Run::resume_with(dir, None)
    }

    /// The simulation of the last checkpoint of the run directory `dir`, in memory, as
    /// [`Run::resume`] restores it (the same state, bit for bit: run on, it continues as
    /// `granular resume` does), without taking the directory over: nothing in `dir` is
    /// written or locked. Refused as [`Run::resume`] refuses (no directory, a finished run,
    /// no checkpoint, a damaged checkpoint).
    pub fn checkpointed(dir: &Path) -> Result<Simulation, RunError> {
        let run_dir = RunDir::new(dir);
        let path = run_dir.file(RunFile::Checkpoint);
        let refuse = |message: String| {
            Err(RunError::Directory {
                dir: dir.to_path_buf(),
                message,
            })
        };
        match run_dir.state() {
            DirectoryState::Missing => {
                return refuse("no such directory: give a run directory".into());
            }
            DirectoryState::Run { finished: true } => {
                return refuse(format!(
                    "the run is finished (summary.json is present and no checkpoint): nothing \
                     to continue. Its results are in {}; read them with granular.load_run",
                    run_dir.file(RunFile::Summary).display()
                ));
            }
            _ if !path.is_file() => {
                return refuse(format!(
                    "no checkpoint ({} is missing): the run stopped before its first \
                     checkpoint, or this is not a run directory",
                    path.display()
                ));
            }
            _ => {}
        }
        let cp = run_dir.checkpoint()?;
        let scenario = stored_scenario(&cp.scenario, dir).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: e.to_string(),
        })?;
        parts::restore(dir, scenario, cp.simulation, cp.parts.as_ref(), None)
    }

    /// [`Run::resume`] on the ranks of `comm` (collective): `dir` is this rank's copy of
    /// the run directory (its files), `shared` the run directory every rank sees. The
    /// checkpoint of a run over several ranks is read in parts, each rank only the parts
    /// that overlap its slab; the single-file checkpoint of a threaded run is read whole
    /// by every rank, then split. The run is decomposed afterwards.
    pub fn resume_decomposed(
        dir: &Path,
        shared: &Path,
        comm: std::sync::Arc<dyn crate::dsmc::Communicator>,
    ) -> Result<Run, RunError> {
        Run::resume_with(dir, Some((shared, comm)))
    }

    fn resume_with(
        dir: &Path,
        ranks: Option<(&Path, std::sync::Arc<dyn crate::dsmc::Communicator>)>,
    ) -> Result<Run, RunError> {
        let path = checkpoint::path(dir);
        let nothing = |message: String| RunError::Directory {
            dir: dir.to_path_buf(),
            message,
        };
        let run_dir = RunDir::new(dir);
        match run_dir.state() {
            DirectoryState::Missing => {
                return Err(nothing(
                    "no such directory: give the run directory \
                    (the --out of `granular run`)"
                        .into(),
                ));
            }
            DirectoryState::Run { finished: true } => {
                return Err(nothing(format!(
                    "the run is finished (summary.json is present and no checkpoint): nothing \
                     to resume. Its results are in {}; to run it again: `granular run {} --out {} --replace`",
                    run_dir.file(RunFile::Summary).display(),
                    run_dir.file(RunFile::Scenario).display(),
                    dir.display()
                )));
            }
            _ if !path.is_file() => {
                return Err(nothing(format!(
                    "no checkpoint ({} is missing): the run stopped before its first \
                     checkpoint, or this is not a run directory. Start it again: `granular run {} --out {} --replace`",
                    path.display(),
                    run_dir.file(RunFile::Scenario).display(),
                    dir.display()
                )));
            }
            _ => {}
        }
        let lock = lock::Lock::acquire(dir)?;
        let cp = run_dir.checkpoint()?;
        let scenario = stored_scenario(&cp.scenario, dir).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: e.to_string(),
        })?;
        check_scenario_file(dir, &cp.scenario, &scenario)?;
        let mut outputs = cp.outputs;
        outputs.relocate(dir);
        // Drop rows written after the checkpoint, so the series continues seamlessly.
        outputs.rewind(ranks.as_ref().is_none_or(|(_, c)| c.rank() == 0))?;
        let log_path = run_dir.file(RunFile::Log);
        let log = std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(&log_path)
            .map_err(io_err(&log_path))?;
        let shared = ranks.as_ref().map_or(dir, |(s, _)| *s).to_path_buf();
        let simulation = parts::restore(dir, scenario, cp.simulation, cp.parts.as_ref(), ranks)?;
        parts::restore_rows(&mut outputs, &simulation, cp.parts.as_ref(), &shared)?;
        if simulation.engine().domain().is_some() {
            outputs.share(&shared);
        }
        let mut recorder = Recorder {
            dir: dir.to_path_buf(),
            outputs,
            attached: Vec::new(),
            log,
            _lock: lock.0,
            started: true,
            // The same as the uninterrupted run's: DSMC's validity warnings are those of
            // the initial state, kept in the checkpoint; the pre-flight warning is the
            // scenario's.
            warnings: set_up_warnings(&simulation),
            shared: simulation.engine().domain().is_some().then_some(shared),
            generation: cp.parts.as_ref().map_or(0, |m| m.generation),
            // The changes before the checkpoint are in the log already.
            logged_changes: simulation.changes().len(),
        };
        if let Some(note) = lock.1 {
            recorder.log(simulation.wall_seconds(), &note);
        }
        recorder.log(
            simulation.wall_seconds(),
            &format!(
                "resumed at t = {} after {} outputs",
                format_number(simulation.time()),
                simulation.outputs_done()
            ),
        );
        Ok(Run {
            simulation,
            recorder,
            interrupt: None,
            agree: None,
        })
    }

    /// Makes the run stop between two chunks of events when `requested` returns true
    /// (a signal handler's flag): it writes a checkpoint and returns
    /// [`RunError::Interrupted`]; `granular resume` continues it bit for bit.
    pub fn interrupt_when(&mut self, requested: impl FnMut() -> bool + Send + 'static) {
        self.interrupt = Some(Box::new(requested));
    }

    /// Splits a DSMC run over the ranks of `comm` (collective; see
    /// [`Simulation::decompose`]). Every rank runs the same loop: give each the same
    /// scenario, and to ranks other than 0 a directory of their own to throw away (all
    /// outputs hold whole-system values, so rank 0's directory is the run's). `shared` is
    /// the run directory (rank 0's), which every rank must see: each writes its part of
    /// the checkpoints and its block of the snapshots there, so that no rank gathers all
    /// particles (`parts`).
    pub fn decompose(
        &mut self,
        comm: std::sync::Arc<dyn crate::dsmc::Communicator>,
        shared: &Path,
    ) -> Result<(), crate::dsmc::DomainError> {
        self.simulation.decompose(comm)?;
        if self.simulation.engine().domain().is_some() {
            self.recorder.shared = Some(shared.to_path_buf());
            self.recorder.outputs.share(shared);
        }
        Ok(())
    }

    /// Makes every rank of a decomposed run stop on `stop.wall_seconds` at the same step
    /// (see [`Simulation::decide_wall_clock_with`]).
    pub fn decide_wall_clock_with(&mut self, decide: crate::simulation::WallClock) {
        self.simulation.decide_wall_clock_with(decide);
    }

    /// `agree(local)` is called on every rank between chunks, once for an interruption
    /// request and once for a due time-based checkpoint, and must return the same answer
    /// on every rank (e.g. whether any rank says yes): the decisions that depend on the
    /// wall clock or on signals are then the same on every rank of a decomposed run.
    pub fn agree_with(&mut self, agree: Agree) {
        self.agree = Some(agree);
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        self.simulation.scenario()
    }

    /// The simulation being recorded.
    pub fn simulation(&self) -> &Simulation {
        &self.simulation
    }

    /// Warnings about the set-up (DSMC's validity conditions), also in `log.txt` and the
    /// summary's `warnings`.
    pub fn warnings(&self) -> &[String] {
        &self.recorder.warnings
    }

    /// Attaches an output of the caller's own besides the standard ones. It is called
    /// after them at every output time, but it is not part of checkpoints: a resumed run
    /// has only the standard outputs.
    pub fn attach(&mut self, output: Box<dyn Output + Send>) {
        self.recorder.attached.push(output);
    }

    /// Saves the full state atomically (write to a temporary file, then rename).
    pub fn checkpoint(&mut self) -> Result<(), RunError> {
        self.recorder.checkpoint(&self.simulation)
    }

    /// Runs to the end. `on_progress` is called every few hundred thousand events; if
    /// `interrupt_after_outputs` is set the run stops (as if killed) after that many
    /// outputs, leaving its checkpoint (used to test resume).
    pub fn run_to_end(
        mut self,
        on_progress: &mut dyn FnMut(&ProgressReport),
        interrupt_after_outputs: Option<u64>,
    ) -> Result<Summary, RunError> {
        self.recorder.start(&self.simulation)?;
        let checkpoint_seconds = self.simulation.scenario().output.checkpoint_seconds;
        let mut hooks = DirectoryHooks {
            recorder: &mut self.recorder,
            on_progress,
            interrupt_after_outputs,
            interrupt: self.interrupt.take(),
            agree: self.agree.take(),
            checkpoint_seconds,
            last_checkpoint: Instant::now(),
        };
        let reason = self.simulation.run_with(&mut hooks)?;
        self.recorder.finish(&self.simulation, reason)
    }
}

/// The run loop's hooks for a run directory: outputs at output times, progress and
/// checkpoints between chunks, a checkpoint when the engine fails.
struct DirectoryHooks<'a> {
    recorder: &'a mut Recorder,
    on_progress: &'a mut dyn FnMut(&ProgressReport),
    interrupt_after_outputs: Option<u64>,
    interrupt: Option<Box<dyn FnMut() -> bool + Send>>,
    agree: Option<Agree>,
    checkpoint_seconds: f64,
    last_checkpoint: Instant,
}

impl RunHooks for DirectoryHooks<'_> {
    type Error = RunError;

    fn after_chunk(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        self.recorder.log_changes(simulation);
        (self.on_progress)(&ProgressReport {
            fraction: simulation.fraction_done(),
            time: simulation.time(),
            events: simulation.events(),
            events_per_second: simulation.events_per_second(),
        });
        let mut interrupted = self.interrupt.as_mut().is_some_and(|requested| requested());
        let mut due = self.last_checkpoint.elapsed().as_secs_f64() >= self.checkpoint_seconds;
        if let Some(agree) = self.agree.as_mut() {
            interrupted = agree(interrupted);
            due = agree(due);
        }
        if interrupted {
            let time = format_number(simulation.time());
            self.recorder.log(
                simulation.wall_seconds(),
                &format!("interrupted at t = {time}"),
            );
            self.recorder.checkpoint(simulation)?;
            return Err(RunError::Interrupted {
                dir: self.recorder.dir.clone(),
                time,
            });
        }
        // Between chunks, not only at outputs: a dense bed under gravity can spend hours
        // of events on one output interval. The state between two chunks is as complete
        // as at an output (resume continues the interval).
        if due {
            self.recorder.checkpoint(simulation)?;
            self.last_checkpoint = Instant::now();
        }
        Ok(())
    }

    fn at_output(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        self.recorder.observe(simulation)
    }

    fn after_output(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if self
            .interrupt_after_outputs
            .is_some_and(|k| simulation.outputs_done() >= k)
        {
            self.recorder.checkpoint(simulation)?;
            return Err(RunError::Checkpoint {
                path: self.recorder.dir.clone(),
                message: "interrupted on request".into(),
            });
        }
        Ok(())
    }

    fn on_engine_error(&mut self, simulation: &Simulation, error: &EngineError) {
        self.recorder.log(
            simulation.wall_seconds(),
            &format!("engine stopped: {error}"),
        );
        let _ = self.recorder.checkpoint(simulation);
    }
}

/// The scenario a checkpoint stores, its `.npz` arrays read from the run directory `dir`
/// (its `initial_state.npz`).
fn stored_scenario(text: &str, dir: &Path) -> Result<Scenario, crate::scenario::ScenarioError> {
    crate::scenario::ScenarioInput {
        text,
        base: Some(dir),
        ..Default::default()
    }
    .read()
}

/// Refuses a resume when `DIR/scenario.toml` says something else than the scenario the
/// run started with (`stored`, from the checkpoint). Layout and comments may differ: the
/// file is compared after reading it.
fn check_scenario_file(dir: &Path, stored: &str, scenario: &Scenario) -> Result<(), RunError> {
    let path = RunDir::new(dir).file(RunFile::Scenario);
    let Ok(text) = std::fs::read_to_string(&path) else {
        // Missing: the checkpoint has the scenario; write it back.
        return std::fs::write(&path, stored).map_err(io_err(&path));
    };
    if text == stored {
        return Ok(());
    }
    let same = Scenario::from_resolved_toml(&text, Some(dir))
        .is_ok_and(|s| s.to_toml() == scenario.to_toml());
    if same {
        return Ok(());
    }
    let first = text
        .lines()
        .zip(stored.lines().chain(std::iter::repeat("")))
        .position(|(a, b)| a != b)
        .unwrap_or(stored.lines().count());
    Err(RunError::Directory {
        dir: dir.to_path_buf(),
        message: format!(
            "{} was edited after the run started (line {} differs from the scenario stored \
             in the checkpoint): a resumed run continues the scenario it started with. Undo \
             the edit to resume, or start the edited scenario as a new run: \
             `granular run {} --out NEW_DIR`",
            path.display(),
            first + 1,
            path.display()
        ),
    })
}
