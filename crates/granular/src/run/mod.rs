//! The runner: drives any engine through a scenario's output times and stop rules, and
//! writes the run directory:
//!
//! | file | content |
//! |---|---|
//! | `scenario.toml` | the fully resolved scenario |
//! | `timeseries.csv` | one row of scalar observables per output time |
//! | `snapshots/snapshot_NNNNNN.npz` | positions, velocities, radii, masses, species (NumPy) |
//! | `speed_histograms.csv` | initial and pooled equilibrium speed histograms per species |
//! | `velocity_histograms.csv` | pooled equilibrium velocity-component histograms per species |
//! | `impact_parameter.csv` | histogram of `b / σ` of all pair collisions |
//! | `impact_histograms.npz`, `structure_factor.npz`, `density_maps.npz` | opt-in observables at output times ([`observers`]) |
//! | `intruder_histograms.csv`, `.npz` | intruder engine: velocity histograms on the time grid with reference densities |
//! | `summary.json` | engine, version, seed, timings, final observables, goodness of fit |
//! | `checkpoint.msgpack` | full state at the last checkpoint (removed when the run ends) |
//! | `log.txt` | what happened, with wall-clock times |

mod build;
pub mod intruder;
pub mod observers;
pub mod sweep;

pub use crate::output::npz::{read_snapshot, write_snapshot};
pub use build::{AnyEngine, BuildError, build, initial_particles};

use crate::engine::{Engine, EngineError, Progress, Scalar};
use crate::scenario::Scenario;
use crate::stats::{ChiSquare, Histogram, RunningStats, chi_square_test};
use crate::theory::equilibrium;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Version of the checkpoint format; bumped when the state layout changes (3: the event
/// codes of cell crossings carry the partner bound of the cheap crossing; 4: the event
/// queue's bucket lists end at an index instead of a sentinel; 5: the event queue is a
/// tournament tree or a calendar, by the number of grains; 6: the cell grid keeps a few
/// large grains out of its lists).
pub const CHECKPOINT_FORMAT: u32 = 6;

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
    /// A checkpoint could not be read.
    #[error("checkpoint {path}: {message}")]
    Checkpoint {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Speed histograms per species: at `t = 0` and pooled over equilibrium samples.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SpeedHistograms {
    /// Species names.
    pub species: Vec<String>,
    /// Mass per species (for the theory curve).
    pub masses: Vec<f64>,
    /// Initial histograms.
    pub initial: Vec<Histogram>,
    /// Pooled equilibrium histograms.
    pub equilibrium: Vec<Histogram>,
    /// Pooled equilibrium histograms of the velocity components (all axes together).
    pub velocity: Vec<Histogram>,
    /// Σ m v² / D per species over the pooled samples (temperature estimate).
    pub energy_sum: Vec<f64>,
    /// Speeds of the pooled samples, per species.
    pub speed_stats: Vec<RunningStats>,
    /// Kinetic energies `m v² / 2` of the pooled samples, per species.
    pub energy_stats: Vec<RunningStats>,
    /// Number of pooled snapshots.
    pub samples: u64,
    /// Collisions per grain at the last pooled snapshot.
    pub last_sample_cpp: f64,
}

/// Runner state saved in checkpoints with the engine.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunState {
    /// Outputs written so far (rows of `timeseries.csv`).
    pub outputs: u64,
    /// Snapshots written so far.
    pub snapshots: u64,
    /// Kinetic energy at `t = 0`.
    pub initial_energy: f64,
    /// Wall-clock seconds spent before the last resume.
    pub wall_seconds: f64,
    /// Column names of `timeseries.csv`.
    pub columns: Vec<String>,
    /// Speed histograms.
    pub histograms: Option<SpeedHistograms>,
    /// Last output's scalars.
    pub last_scalars: Vec<Scalar>,
    /// Opt-in observables recorded so far (impact histograms, `S(k)`, density maps).
    #[serde(default)]
    pub observables: observers::ObservablesState,
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

/// Result of a finished run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    /// Engine name.
    pub engine: String,
    /// granular version.
    pub version: String,
    /// Seed.
    pub seed: u64,
    /// Dimension.
    pub dimension: usize,
    /// Number of particles.
    pub n: usize,
    /// Wall-clock seconds (all sessions of a resumed run).
    pub wall_seconds: f64,
    /// Events processed.
    pub events: u64,
    /// Events per wall-clock second.
    pub events_per_second: f64,
    /// Pair collisions.
    pub collisions: u64,
    /// Pair collisions per wall-clock second.
    pub collisions_per_second: f64,
    /// Which stop rule ended the run.
    pub stop_reason: String,
    /// Kinetic energy at `t = 0`.
    pub initial_kinetic_energy: f64,
    /// Observables at the end (same keys as `timeseries.csv`).
    #[serde(rename = "final")]
    pub final_observables: serde_json::Map<String, serde_json::Value>,
    /// Pearson chi-square of the pooled equilibrium speeds per species against the
    /// Maxwell-Boltzmann law at the measured temperature.
    pub maxwell_boltzmann_fit: serde_json::Map<String, serde_json::Value>,
    /// Per species, over the pooled equilibrium samples: mean speed and mean kinetic
    /// energy per grain with standard errors, and the Maxwell-Boltzmann mean speed at the
    /// species' measured temperature.
    pub species: serde_json::Map<String, serde_json::Value>,
    /// Crater measure, when the scenario has a `[crater]` table.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crater: Option<serde_json::Value>,
    /// Intruder engine: stationary averages with errors and the theory value (see
    /// `docs/output.md`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub intruder: Option<serde_json::Value>,
    /// Outputs and snapshots written.
    pub outputs: u64,
    /// Snapshots written.
    pub snapshots: u64,
}

/// Everything a checkpoint holds.
#[derive(Serialize, Deserialize)]
struct Checkpoint {
    format: u32,
    scenario: String,
    engine: AnyEngine,
    state: RunState,
}

/// A run in progress in a run directory.
pub struct Run {
    dir: PathBuf,
    scenario: Scenario,
    engine: AnyEngine,
    state: RunState,
    log: std::fs::File,
    session_start: Instant,
    session_events_start: u64,
}

impl Run {
    /// Starts a new run of `scenario` in `dir` (created; existing run files are replaced).
    pub fn create(dir: &Path, scenario: Scenario) -> Result<Run, RunError> {
        let _ = std::fs::remove_dir_all(dir.join("snapshots"));
        let _ = std::fs::remove_file(dir.join("checkpoint.msgpack"));
        std::fs::create_dir_all(dir.join("snapshots")).map_err(io_err(dir))?;
        let path = dir.join("scenario.toml");
        std::fs::write(&path, scenario.to_toml()).map_err(io_err(&path))?;
        let log_path = dir.join("log.txt");
        let log = std::fs::File::create(&log_path).map_err(io_err(&log_path))?;
        let start = Instant::now();
        let mut engine = build(&scenario)?;
        let initial_energy = engine.kinetic_energy();
        let mut run = Run {
            dir: dir.to_path_buf(),
            state: RunState {
                outputs: 0,
                snapshots: 0,
                initial_energy,
                wall_seconds: 0.0,
                columns: Vec::new(),
                histograms: None,
                last_scalars: Vec::new(),
                observables: Default::default(),
            },
            scenario,
            engine,
            log,
            session_start: start,
            session_events_start: 0,
        };
        run.log(&format!(
            "built {} engine: {} grains, dimension {}, seed {} ({:.3} s)",
            run.engine.name(),
            run.engine.particle_count(),
            run.scenario.dimension,
            run.scenario.seed,
            start.elapsed().as_secs_f64()
        ));
        run.init_histograms();
        run.write_output(true)?;
        Ok(run)
    }

    /// Reopens an interrupted run from its checkpoint.
    pub fn resume(dir: &Path) -> Result<Run, RunError> {
        let path = dir.join("checkpoint.msgpack");
        let bytes = std::fs::read(&path).map_err(io_err(&path))?;
        // The format number first, so that a checkpoint of another version is named as
        // such rather than failing somewhere inside the engine's state.
        #[derive(Deserialize)]
        struct Header {
            format: u32,
        }
        if let Ok(Header { format }) = rmp_serde::from_slice::<Header>(&bytes)
            && format != CHECKPOINT_FORMAT
        {
            return Err(RunError::Checkpoint {
                path,
                message: format!(
                    "checkpoint format {format} was written by another version of granular; \
                     this one reads format {CHECKPOINT_FORMAT}. Resume with the version that \
                     wrote it, or rerun the scenario (DIR/scenario.toml)"
                ),
            });
        }
        let cp: Checkpoint = rmp_serde::from_slice(&bytes).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: e.to_string(),
        })?;
        let scenario =
            Scenario::from_toml(&cp.scenario, &[]).map_err(|e| RunError::Checkpoint {
                path: path.clone(),
                message: e.to_string(),
            })?;
        // Drop rows written after the checkpoint, so the series continues seamlessly.
        let csv_path = dir.join("timeseries.csv");
        let text = std::fs::read_to_string(&csv_path).map_err(io_err(&csv_path))?;
        // Header, the row at t = 0, and one row per output.
        let keep: Vec<&str> = text.lines().take(cp.state.outputs as usize + 2).collect();
        std::fs::write(&csv_path, keep.join("\n") + "\n").map_err(io_err(&csv_path))?;
        let log_path = dir.join("log.txt");
        let log = std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(&log_path)
            .map_err(io_err(&log_path))?;
        let events = cp.engine.events();
        let mut run = Run {
            dir: dir.to_path_buf(),
            scenario,
            engine: cp.engine,
            state: cp.state,
            log,
            session_start: Instant::now(),
            session_events_start: events,
        };
        run.log(&format!(
            "resumed at t = {} after {} outputs",
            run.engine.time(),
            run.state.outputs
        ));
        Ok(run)
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The engine.
    pub fn engine(&mut self) -> &mut AnyEngine {
        &mut self.engine
    }

    fn log(&mut self, msg: &str) {
        let _ = writeln!(
            self.log,
            "[{:9.3} s] {msg}",
            self.state.wall_seconds + self.session_start.elapsed().as_secs_f64()
        );
    }

    fn init_histograms(&mut self) {
        let Some(snap) = self.engine.snapshot() else {
            return;
        };
        let d = snap.dimension;
        let n = snap.masses.len();
        let mut mv2 = 0.0;
        let mut msum = 0.0;
        for i in 0..n {
            let v2: f64 = snap.velocities[i * d..(i + 1) * d]
                .iter()
                .map(|x| x * x)
                .sum();
            mv2 += snap.masses[i] * v2;
            msum += snap.masses[i];
        }
        let species = snap.species_names.clone();
        let ns = species.len();
        let mut masses = vec![1.0; ns];
        for i in 0..n {
            masses[snap.species[i] as usize] = snap.masses[i];
        }
        // Upper edge from the lightest species' thermal speed at the mean energy.
        let t = mv2 / (d as f64 * n as f64);
        let histograms: Vec<Histogram> = (0..ns)
            .map(|s| {
                let v_rms = if t > 0.0 {
                    (d as f64 * t / masses[s]).sqrt()
                } else {
                    (mv2 / msum.max(1e-300)).sqrt().max(1.0)
                };
                let max = self.scenario.output.histogram_max_speed
                    * if v_rms > 0.0 { v_rms } else { 1.0 };
                Histogram::new(0.0, max, self.scenario.output.histogram_bins)
            })
            .collect();
        let mut initial = histograms.clone();
        for i in 0..n {
            let v: f64 = snap.velocities[i * d..(i + 1) * d]
                .iter()
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt();
            initial[snap.species[i] as usize].push(v);
        }
        let velocity = histograms
            .iter()
            .map(|h| Histogram::new(-h.max, h.max, 2 * h.counts.len()))
            .collect();
        self.state.histograms = Some(SpeedHistograms {
            species,
            masses,
            initial,
            equilibrium: histograms,
            velocity,
            energy_sum: vec![0.0; ns],
            speed_stats: vec![RunningStats::new(); ns],
            energy_stats: vec![RunningStats::new(); ns],
            samples: 0,
            last_sample_cpp: f64::NEG_INFINITY,
        });
    }

    /// Writes one output row (and a snapshot, and a histogram sample when due).
    fn write_output(&mut self, first: bool) -> Result<(), RunError> {
        if !first {
            self.state.outputs += 1;
        }
        let mut scalars = self.engine.scalars();
        if !scalars.iter().any(|s| s.0 == "time") {
            scalars.insert(0, ("time".into(), self.engine.time()));
        }
        let csv_path = self.dir.join("timeseries.csv");
        let mut file = if first {
            self.state.columns = scalars.iter().map(|s| s.0.clone()).collect();
            let mut f = std::fs::File::create(&csv_path).map_err(io_err(&csv_path))?;
            writeln!(f, "{}", self.state.columns.join(",")).map_err(io_err(&csv_path))?;
            f
        } else {
            std::fs::OpenOptions::new()
                .append(true)
                .open(&csv_path)
                .map_err(io_err(&csv_path))?
        };
        let row: Vec<String> = self
            .state
            .columns
            .iter()
            .map(|c| {
                scalars
                    .iter()
                    .find(|s| &s.0 == c)
                    .map_or(String::from("nan"), |s| format!("{:e}", s.1))
            })
            .collect();
        writeln!(file, "{}", row.join(",")).map_err(io_err(&csv_path))?;
        let cpp = scalars
            .iter()
            .find(|s| s.0 == "collisions_per_particle")
            .map_or(0.0, |s| s.1);
        self.state.last_scalars = scalars;
        self.record_observables(first)?;
        let every = self.scenario.output.snapshot_every;
        if first || (every > 0 && self.state.outputs.is_multiple_of(every)) {
            self.write_snapshot()?;
        }
        // Pool equilibrium speeds, samples far enough apart (appendix C.2).
        if let Some(h) = &self.state.histograms
            && cpp >= self.scenario.output.equilibration_collisions_per_particle
            && cpp - h.last_sample_cpp >= self.scenario.output.histogram_sample_spacing
            && let Some(snap) = self.engine.snapshot()
            && let Some(h) = &mut self.state.histograms
        {
            let d = snap.dimension;
            for i in 0..snap.masses.len() {
                let v2: f64 = snap.velocities[i * d..(i + 1) * d]
                    .iter()
                    .map(|x| x * x)
                    .sum();
                let s = snap.species[i] as usize;
                h.equilibrium[s].push(v2.sqrt());
                for &c in &snap.velocities[i * d..(i + 1) * d] {
                    h.velocity[s].push(c);
                }
                h.energy_sum[s] += snap.masses[i] * v2 / d as f64;
                h.speed_stats[s].push(v2.sqrt());
                h.energy_stats[s].push(0.5 * snap.masses[i] * v2);
            }
            h.samples += 1;
            h.last_sample_cpp = cpp;
        }
        Ok(())
    }

    fn write_snapshot(&mut self) -> Result<(), RunError> {
        if let Some(snap) = self.engine.snapshot() {
            let path = self
                .dir
                .join("snapshots")
                .join(format!("snapshot_{:06}.npz", self.state.outputs));
            write_snapshot(&path, &snap)?;
            self.state.snapshots += 1;
        }
        Ok(())
    }

    /// Saves the full state atomically (write to a temporary file, then rename).
    pub fn checkpoint(&mut self) -> Result<(), RunError> {
        let path = self.dir.join("checkpoint.msgpack");
        let tmp = self.dir.join("checkpoint.msgpack.tmp");
        let mut state = self.state.clone();
        state.wall_seconds += self.session_start.elapsed().as_secs_f64();
        let cp = Checkpoint {
            format: CHECKPOINT_FORMAT,
            scenario: self.scenario.to_toml(),
            engine: self.engine.clone(),
            state,
        };
        let bytes = rmp_serde::to_vec_named(&cp).map_err(|e| RunError::Checkpoint {
            path: path.clone(),
            message: e.to_string(),
        })?;
        std::fs::write(&tmp, bytes).map_err(io_err(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io_err(&path))?;
        self.log(&format!("checkpoint at t = {}", self.engine.time()));
        Ok(())
    }

    fn fraction_done(&mut self, energy: Option<f64>) -> f64 {
        let stop = &self.scenario.stop;
        let n = self.engine.particle_count().max(1) as f64;
        let mut f: f64 = 0.0;
        if let Some(t) = stop.time {
            f = f.max(self.engine.time() / t);
        }
        if let Some(c) = stop.collisions_per_particle {
            f = f.max(2.0 * self.engine.collisions() as f64 / n / c);
        }
        if let Some(c) = stop.collisions {
            f = f.max(self.engine.collisions() as f64 / c.max(1) as f64);
        }
        if let Some(e) = stop.events {
            f = f.max(self.engine.events() as f64 / e as f64);
        }
        if let (Some(frac), Some(k)) = (stop.energy_fraction, energy)
            && self.state.initial_energy > 0.0
            && k > 0.0
        {
            f = f.max((self.state.initial_energy / k).ln() / (1.0 / frac).ln());
        }
        if let Some(w) = stop.wall_seconds {
            f = f.max(self.wall_seconds() / w);
        }
        f.clamp(0.0, 1.0)
    }

    fn wall_seconds(&self) -> f64 {
        self.state.wall_seconds + self.session_start.elapsed().as_secs_f64()
    }

    /// Runs to the end. `on_progress` is called every few hundred thousand events; if
    /// `interrupt_after_outputs` is set the run stops (as if killed) after that many
    /// outputs, leaving its checkpoint (used to test resume).
    pub fn run_to_end(
        mut self,
        on_progress: &mut dyn FnMut(&ProgressReport),
        interrupt_after_outputs: Option<u64>,
    ) -> Result<Summary, RunError> {
        let interval = self.scenario.output.interval;
        let stop = self.scenario.stop.clone();
        let n = self.engine.particle_count().max(1) as f64;
        let chunk: u64 = 200_000;
        let mut last_checkpoint = Instant::now();
        let stop_reason;
        'outer: loop {
            let mut next = (self.state.outputs + 1) as f64 * interval;
            if let Some(t) = stop.time {
                next = next.min(t);
            }
            loop {
                let budget = match stop.events {
                    Some(e) => chunk.min(e.saturating_sub(self.engine.events())).max(1),
                    None => chunk,
                };
                let progress = self.engine.advance(next, budget);
                let progress = match progress {
                    Ok(p) => p,
                    Err(e) => {
                        self.log(&format!("engine stopped: {e}"));
                        let _ = self.checkpoint();
                        return Err(e.into());
                    }
                };
                let events = self.engine.events();
                let rate = (events - self.session_events_start) as f64
                    / self.session_start.elapsed().as_secs_f64().max(1e-9);
                let fraction = self.fraction_done(None);
                on_progress(&ProgressReport {
                    fraction,
                    time: self.engine.time(),
                    events,
                    events_per_second: rate,
                });
                // Between chunks, not only at outputs: a dense bed under gravity can spend
                // hours of events on one output interval. The engine's state between two
                // chunks is as complete as at an output (resume continues the interval).
                if last_checkpoint.elapsed().as_secs_f64()
                    >= self.scenario.output.checkpoint_seconds
                {
                    self.checkpoint()?;
                    last_checkpoint = Instant::now();
                }
                if progress == Progress::Reached {
                    break;
                }
                if stop.events.is_some_and(|e| events >= e) {
                    self.write_output(false)?;
                    stop_reason = "events";
                    break 'outer;
                }
                if stop.wall_seconds.is_some_and(|w| self.wall_seconds() >= w) {
                    self.write_output(false)?;
                    stop_reason = "wall_seconds";
                    break 'outer;
                }
            }
            self.write_output(false)?;
            let energy = self.engine.kinetic_energy();
            if stop.time.is_some_and(|t| self.engine.time() >= t) {
                stop_reason = "time";
                break;
            }
            if stop
                .collisions_per_particle
                .is_some_and(|c| 2.0 * self.engine.collisions() as f64 / n >= c)
            {
                stop_reason = "collisions_per_particle";
                break;
            }
            if stop
                .collisions
                .is_some_and(|c| self.engine.collisions() >= c)
            {
                stop_reason = "collisions";
                break;
            }
            if stop.events.is_some_and(|e| self.engine.events() >= e) {
                stop_reason = "events";
                break;
            }
            if stop
                .energy_fraction
                .is_some_and(|f| energy <= f * self.state.initial_energy)
            {
                stop_reason = "energy_fraction";
                break;
            }
            if stop.wall_seconds.is_some_and(|w| self.wall_seconds() >= w) {
                stop_reason = "wall_seconds";
                break;
            }
            if interrupt_after_outputs.is_some_and(|k| self.state.outputs >= k) {
                self.checkpoint()?;
                return Err(RunError::Checkpoint {
                    path: self.dir.clone(),
                    message: "interrupted on request".into(),
                });
            }
        }
        self.finish(stop_reason)
    }

    fn finish(mut self, stop_reason: &str) -> Result<Summary, RunError> {
        // Final snapshot (unless the last output already wrote one).
        let every = self.scenario.output.snapshot_every;
        if every == 0 || !self.state.outputs.is_multiple_of(every) {
            self.write_snapshot()?;
        }
        let fits = self.write_histograms()?;
        self.write_impact()?;
        let species = self.species_statistics();
        let crater = self.crater()?;
        let intruder = match &self.engine {
            AnyEngine::Intruder(e) => Some(intruder::finish(e, &self.scenario, &self.dir)?),
            _ => None,
        };
        let wall = self.wall_seconds();
        let events = self.engine.events();
        let collisions = self.engine.collisions();
        let mut final_observables = serde_json::Map::new();
        for (k, v) in &self.state.last_scalars {
            final_observables.insert(k.clone(), json_number(*v));
        }
        let summary = Summary {
            engine: self.engine.name().to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            seed: self.scenario.seed,
            dimension: self
                .scenario
                .intruder
                .as_ref()
                .map_or(self.scenario.dimension, |i| i.dimension()),
            n: self.engine.particle_count(),
            wall_seconds: wall,
            events,
            events_per_second: events as f64 / wall.max(1e-9),
            collisions,
            collisions_per_second: collisions as f64 / wall.max(1e-9),
            stop_reason: stop_reason.to_string(),
            initial_kinetic_energy: self.state.initial_energy,
            final_observables,
            maxwell_boltzmann_fit: fits,
            species,
            crater,
            intruder,
            outputs: self.state.outputs,
            snapshots: self.state.snapshots,
        };
        let path = self.dir.join("summary.json");
        let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
        std::fs::write(&path, text + "\n").map_err(io_err(&path))?;
        let _ = std::fs::remove_file(self.dir.join("checkpoint.msgpack"));
        self.log(&format!(
            "finished ({stop_reason}): {events} events, {collisions} collisions, {wall:.3} s"
        ));
        Ok(summary)
    }

    fn write_histograms(&mut self) -> Result<serde_json::Map<String, serde_json::Value>, RunError> {
        let mut fits = serde_json::Map::new();
        let Some(h) = &self.state.histograms else {
            return Ok(fits);
        };
        let d = self.scenario.dimension;
        let path = self.dir.join("speed_histograms.csv");
        let mut out = String::from(
            "species,speed_low,speed_high,initial_density,equilibrium_density,equilibrium_count,maxwell_boltzmann_density\n",
        );
        for s in 0..h.species.len() {
            let eq = &h.equilibrium[s];
            let count = eq.total();
            let temperature = if count > 0 {
                h.energy_sum[s] / count as f64
            } else {
                f64::NAN
            };
            let init_density = h.initial[s].density();
            let eq_density = eq.density();
            let w = eq.bin_width();
            for b in 0..eq.counts.len() {
                let lo = eq.min + b as f64 * w;
                let theory = if temperature > 0.0 {
                    (equilibrium::speed_cdf(d, lo + w, h.masses[s], temperature)
                        - equilibrium::speed_cdf(d, lo, h.masses[s], temperature))
                        / w
                } else {
                    f64::NAN
                };
                out.push_str(&format!(
                    "{},{:e},{:e},{:e},{:e},{},{:e}\n",
                    h.species[s],
                    lo,
                    lo + w,
                    init_density[b],
                    if count > 0 { eq_density[b] } else { f64::NAN },
                    eq.counts[b],
                    theory
                ));
            }
            if count > 0 && temperature > 0.0 {
                let fit: ChiSquare = chi_square_test(eq, |v| {
                    equilibrium::speed_cdf(d, v, h.masses[s], temperature)
                });
                fits.insert(
                    h.species[s].clone(),
                    serde_json::json!({
                        "temperature": temperature,
                        "samples": count,
                        "snapshots": h.samples,
                        "chi_square": fit.statistic,
                        "degrees_of_freedom": fit.degrees_of_freedom,
                        "p_value": fit.p_value,
                    }),
                );
            }
        }
        std::fs::write(&path, out).map_err(io_err(&path))?;
        // Velocity components against the Gaussian of variance T / m.
        let path = self.dir.join("velocity_histograms.csv");
        let mut out = String::from(
            "species,velocity_low,velocity_high,equilibrium_density,equilibrium_count,gaussian_density\n",
        );
        for s in 0..h.species.len() {
            let vh = &h.velocity[s];
            let count = h.equilibrium[s].total();
            let temperature = if count > 0 {
                h.energy_sum[s] / count as f64
            } else {
                f64::NAN
            };
            let sd = (temperature / h.masses[s]).sqrt();
            let cdf = |v: f64| 0.5 * libm::erfc(-v / (sd * std::f64::consts::SQRT_2));
            let dens = vh.density();
            let w = vh.bin_width();
            for (b, &count_b) in vh.counts.iter().enumerate() {
                let lo = vh.min + b as f64 * w;
                let theory = if sd > 0.0 {
                    (cdf(lo + w) - cdf(lo)) / w
                } else {
                    f64::NAN
                };
                let observed = if vh.total() > 0 { dens[b] } else { f64::NAN };
                out.push_str(&format!(
                    "{},{:e},{:e},{:e},{},{:e}\n",
                    h.species[s],
                    lo,
                    lo + w,
                    observed,
                    count_b,
                    theory
                ));
            }
        }
        std::fs::write(&path, out).map_err(io_err(&path))?;
        Ok(fits)
    }

    fn species_statistics(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut out = serde_json::Map::new();
        let Some(h) = &self.state.histograms else {
            return out;
        };
        let d = self.scenario.dimension;
        for s in 0..h.species.len() {
            let (sp, en) = (&h.speed_stats[s], &h.energy_stats[s]);
            if sp.count == 0 {
                continue;
            }
            let temperature = 2.0 * en.mean() / d as f64;
            out.insert(
                h.species[s].clone(),
                serde_json::json!({
                    "mass": h.masses[s],
                    "samples": sp.count,
                    "mean_speed": json_number(sp.mean()),
                    "mean_speed_error": json_number(sp.standard_error()),
                    "mean_kinetic_energy": json_number(en.mean()),
                    "mean_kinetic_energy_error": json_number(en.standard_error()),
                    "temperature": json_number(temperature),
                    "maxwell_boltzmann_mean_speed": json_number(equilibrium::mean_speed(d, h.masses[s], temperature)),
                }),
            );
        }
        out
    }

    /// Number of bed grains displaced by more than the threshold since `t = 0`.
    fn crater(&mut self) -> Result<Option<serde_json::Value>, RunError> {
        let Some(spec) = self.scenario.crater.clone() else {
            return Ok(None);
        };
        let path = self.dir.join("snapshots").join("snapshot_000000.npz");
        let initial = read_snapshot(&path)?;
        let Some(now) = self.engine.snapshot() else {
            return Ok(None);
        };
        let Some(index) = now.species_names.iter().position(|n| *n == spec.species) else {
            return Ok(None);
        };
        let d = now.dimension;
        let (mut total, mut displaced) = (0usize, 0usize);
        for i in 0..now.radii.len() {
            if now.species[i] as usize != index {
                continue;
            }
            total += 1;
            let r2: f64 = (0..d)
                .map(|k| (now.positions[i * d + k] - initial.positions[i * d + k]).powi(2))
                .sum();
            if r2 > spec.displacement * spec.displacement {
                displaced += 1;
            }
        }
        Ok(Some(serde_json::json!({
            "species": spec.species,
            "displacement": spec.displacement,
            "grains": total,
            "displaced": displaced,
            "fraction": displaced as f64 / total.max(1) as f64,
        })))
    }

    fn write_impact(&mut self) -> Result<(), RunError> {
        let Some(h) = self.engine.impact_histogram() else {
            return Ok(());
        };
        let path = self.dir.join("impact_parameter.csv");
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
        std::fs::write(&path, out).map_err(io_err(&path))?;
        Ok(())
    }
}

fn json_number(v: f64) -> serde_json::Value {
    serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, serde_json::Value::Number)
}
