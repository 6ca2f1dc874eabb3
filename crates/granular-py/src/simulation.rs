//! `granular.Simulation`: the library's in-memory [`Simulation`], advanced with the
//! interpreter lock released and Ctrl-C checked between chunks of events.

use crate::convert::json_to_python;
use crate::errors::{
    SimulationError, build_error, engine_error, guard, scenario_error, simulation_error,
    state_error, value_error,
};
use crate::scenario::PyScenario;
use crate::state::{matrix, snapshot_arrays, spins};
use granular::engine::{EngineError, Progress};
use granular::grain_state::{GrainState, StateError};
use granular::run::{Run, RunError};
use granular::simulation::{RunHooks, Simulation};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Events per chunk of `advance`: between chunks the interpreter lock is taken back
/// briefly to check for Ctrl-C (a chunk is a few milliseconds of work).
const CHUNK_EVENTS: u64 = 20_000;

/// A simulation of any engine (edmd, dsmc, intruder) held in memory.
///
/// Simulation(scenario, seed=None): `scenario` is a granular.Scenario or the path of a
/// scenario file; `seed` overrides the scenario's seed (as `granular run --seed`). The
/// initial state is built at once (SimulationError when it cannot be, e.g. grains that do
/// not fit). The same scenario and seed give the same trajectory as `granular run`, bit for
/// bit. Long calls (advance, run) release the interpreter lock, so other Python threads
/// run meanwhile, and raise KeyboardInterrupt within milliseconds of Ctrl-C, leaving the
/// simulation at a consistent state (the time it reached).
#[pyclass(name = "Simulation", module = "granular")]
pub struct PySimulation {
    simulation: Option<Simulation>,
    scenario: PyScenario,
    /// Where `run(out=...)` wrote the run, once it has (the simulation then lives there).
    recorded: Option<PathBuf>,
    /// The run directory `Simulation.resume` read, with the events of its checkpoint:
    /// `run(out=that directory)` continues it as `granular resume` while the simulation
    /// has not moved since.
    resumed: Option<(PathBuf, u64)>,
}

/// Errors of the interruptible run loop: the engine's, or a Python exception (Ctrl-C).
enum LoopError {
    Engine(EngineError),
    Python(PyErr),
}

impl From<EngineError> for LoopError {
    fn from(e: EngineError) -> Self {
        LoopError::Engine(e)
    }
}

/// Hooks of `Simulation::run_with` that take the interpreter lock after each chunk to
/// check for signals.
struct SignalHooks;

impl RunHooks for SignalHooks {
    type Error = LoopError;

    fn after_chunk(&mut self, _simulation: &Simulation) -> Result<(), LoopError> {
        Python::attach(|py| py.check_signals()).map_err(LoopError::Python)
    }
}

/// Payload of the unwind that stops `Run::run_to_end` when Ctrl-C arrives (its progress
/// callback cannot return an error).
struct Interrupted(PyErr);

/// The error of a simulation that `run(out=...)` took over.
fn gone(recorded: &Option<PathBuf>) -> PyErr {
    SimulationError::new_err(format!(
        "this simulation was handed to run(out={:?}), which ran it to its end and wrote it \
there; read it with granular.load_run(...), or build a new Simulation",
        recorded.as_deref().unwrap_or(std::path::Path::new("?"))
    ))
}

/// The scenario argument of `Simulation(...)` and `Simulation.from_snapshot(...)`: a
/// `granular.Scenario` or the path of a scenario file, with `seed` overriding its seed and
/// the pre-flight cost limits checked unless `insist`.
fn scenario_argument(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    seed: Option<u64>,
    insist: bool,
) -> PyResult<PyScenario> {
    let base: PyScenario = match scenario.cast::<PyScenario>() {
        Ok(s) => s.borrow().clone(),
        Err(_) => {
            let path: PathBuf = scenario.extract().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(
                    "scenario must be a granular.Scenario or the path of a scenario file",
                )
            })?;
            let text = std::fs::read_to_string(&path).map_err(|e| {
                pyo3::exceptions::PyOSError::new_err(format!("{}: {e}", path.display()))
            })?;
            PyScenario::build(py, text, Vec::new(), Some(path.display().to_string()))?
        }
    };
    let scenario = match seed {
        Some(s) => base.with_overrides(py, &[format!("seed={s}")])?,
        None => base,
    };
    scenario.within_limits(py, insist)?;
    Ok(scenario)
}

/// Whether two paths name the same directory (compared canonically when both exist).
fn same_directory(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

impl PySimulation {
    fn sim(&self) -> PyResult<&Simulation> {
        self.simulation.as_ref().ok_or_else(|| gone(&self.recorded))
    }

    fn sim_mut(&mut self) -> PyResult<&mut Simulation> {
        self.simulation.as_mut().ok_or_else(|| gone(&self.recorded))
    }

    /// The snapshot, or a SimulationError for the intruder engine.
    fn snapshot_or_error(&self) -> PyResult<granular::engine::Snapshot> {
        let sim = self.sim()?;
        guard("snapshot", || {
            sim.snapshot().ok_or_else(|| {
                simulation_error(
                    "the intruder engine has no grain state (no positions or velocities); use \
observe() for the intruder's velocity and statistics",
                )
            })
        })
    }

    /// Positions or velocities alone, without the rest of a snapshot.
    fn one_array<'py>(
        &self,
        py: Python<'py>,
        what: crate::state::Quantity,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let sim = self.sim()?;
        if let Some(array) = crate::state::by_id(py, sim, what)? {
            return Ok(array);
        }
        let s = self.snapshot_or_error()?;
        let n = s.radii.len();
        let values = match what {
            crate::state::Quantity::Positions => s.positions,
            crate::state::Quantity::Velocities => s.velocities,
        };
        matrix(py, values, n, s.dimension.max(1))
    }

    fn run_in_memory(&mut self, py: Python<'_>) -> PyResult<String> {
        let sim = self.sim_mut()?;
        let result = py.detach(|| {
            guard("run", || {
                Ok(sim
                    .run_with(&mut SignalHooks)
                    .map(|r| r.as_str().to_string()))
            })
        })?;
        match result {
            Ok(reason) => Ok(reason),
            Err(LoopError::Engine(e)) => Err(engine_error(e)),
            Err(LoopError::Python(e)) => Err(e),
        }
    }

    fn run_to_directory<'py>(
        &mut self,
        py: Python<'py>,
        out: PathBuf,
    ) -> PyResult<Bound<'py, PyAny>> {
        let continues = match &self.resumed {
            Some((dir, events)) if same_directory(dir, &out) => {
                if self.sim()?.events() != *events {
                    return Err(SimulationError::new_err(format!(
                        "this simulation was resumed from {} and advanced since: run(out=...) \
into that directory would not continue its files; give another directory (a new run from the \
present state) or resume again",
                        dir.display()
                    )));
                }
                true
            }
            _ => false,
        };
        let sim = self.simulation.take().ok_or_else(|| gone(&self.recorded))?;
        self.recorded = Some(out.clone());
        let dir = out.clone();
        let outcome = py.detach(move || {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || {
                let run = if continues {
                    // The directory's own run, reopened as `granular resume` does (its
                    // outputs, log and lock); the in-memory copy is the same state.
                    drop(sim);
                    Run::resume(&dir)?
                } else {
                    Run::from_simulation(&dir, sim)?
                };
                run.run_to_end(
                    &mut |_| {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            std::panic::resume_unwind(Box::new(Interrupted(e)));
                        }
                    },
                    None,
                )
            }))
        });
        let summary = match outcome {
            Ok(Ok(summary)) => summary,
            Ok(Err(RunError::Engine(e))) => {
                return Err(simulation_error(format!(
                    "{e}\n(state saved in {}; fix the scenario and rerun)",
                    out.display()
                )));
            }
            Ok(Err(e)) => return Err(simulation_error(e)),
            Err(payload) => {
                return Err(match payload.downcast::<Interrupted>() {
                    Ok(i) => i.0,
                    Err(p) => {
                        let detail = p
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| p.downcast_ref::<String>().cloned())
                            .unwrap_or_default();
                        simulation_error(format!(
                            "internal error in run: {detail} (a bug in granular: please report it with the scenario)"
                        ))
                    }
                });
            }
        };
        let value = serde_json::to_value(&summary).map_err(simulation_error)?;
        json_to_python(py, &value)
    }
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (scenario, seed = None, insist = false))]
    fn new(
        py: Python<'_>,
        scenario: &Bound<'_, PyAny>,
        seed: Option<u64>,
        insist: bool,
    ) -> PyResult<Self> {
        let scenario = scenario_argument(py, scenario, seed, insist)?;
        let resolved = scenario.resolved.clone();
        let origin = scenario.origin.clone();
        let built = py.detach(|| guard("Simulation()", || Ok(Simulation::new(resolved))))?;
        let simulation = built.map_err(|e| build_error(py, e, origin.as_deref()))?;
        Ok(Self {
            simulation: Some(simulation),
            scenario,
            recorded: None,
            resumed: None,
        })
    }

    /// Simulation.from_snapshot(scenario, snapshot, seed=None, insist=False) -> Simulation
    ///
    /// A simulation of `scenario` that starts from the grains of `snapshot` at its time
    /// instead of the scenario's initial state: `snapshot` is the path of a snapshot
    /// `.npz` (a run directory's `snapshot_NNNNNN.npz`), a `granular.Snapshot`
    /// (`granular.load_run(...).snapshot(k)`) or the dict of `Simulation.snapshot()`;
    /// its `positions` and `velocities` (float64 (N, D), input order) and `time` are used,
    /// and the `angular_velocities` of a rough run's snapshot where it has them (rough
    /// grains of a snapshot without them start from the scenario's drawn spins).
    /// The run goes on exactly, bit for bit, as a simulation of the same scenario whose
    /// state was set to the same arrays at the same time (`set_state`). Raises ValueError
    /// or TypeError for arrays that do not fit the scenario (shape, dtype, NaN, a grain
    /// outside the box, overlapping grains), ScenarioError, SimulationError (e.g. the
    /// intruder engine, which has no grains).
    #[staticmethod]
    #[pyo3(signature = (scenario, snapshot, seed = None, insist = false))]
    fn from_snapshot(
        py: Python<'_>,
        scenario: &Bound<'_, PyAny>,
        snapshot: &Bound<'_, PyAny>,
        seed: Option<u64>,
        insist: bool,
    ) -> PyResult<Self> {
        let scenario = scenario_argument(py, scenario, seed, insist)?;
        let resolved = scenario.resolved.clone();
        let origin = scenario.origin.clone();
        let a = snapshot_arrays(py, snapshot, &resolved)?;
        let built = py.detach(|| {
            guard("Simulation.from_snapshot()", || {
                Ok(Simulation::from_grain_state(
                    resolved,
                    a.time,
                    GrainState {
                        positions: Some(&a.positions),
                        velocities: Some(&a.velocities),
                        angular_velocities: a.angular_velocities.as_deref(),
                    },
                ))
            })
        })?;
        let simulation = built.map_err(|e| match e {
            StateError::Build(b) => build_error(py, b, origin.as_deref()),
            other => state_error(other),
        })?;
        Ok(Self {
            simulation: Some(simulation),
            scenario,
            recorded: None,
            resumed: None,
        })
    }

    /// Simulation.resume(run_dir) -> Simulation
    ///
    /// The simulation of the last checkpoint of a run directory (written by `granular run`,
    /// `granular resume`, a cluster run or `Simulation.run(out=...)`), in memory: advanced
    /// or run on, it continues bit for bit as `granular resume run_dir` does. The
    /// directory is only read; `run(out=run_dir)` (before any other advance) continues it
    /// there, writing the same files as `granular resume run_dir`. Raises SimulationError
    /// when there is nothing to resume (no directory, a finished run, no checkpoint, a
    /// damaged checkpoint), with the command line's message.
    #[staticmethod]
    fn resume(py: Python<'_>, run_dir: PathBuf) -> PyResult<Self> {
        let dir = run_dir.clone();
        let simulation = py
            .detach(|| guard("Simulation.resume()", || Ok(Run::checkpointed(&dir))))?
            .map_err(simulation_error)?;
        let scenario = PyScenario::of(
            py,
            simulation.scenario(),
            Some(run_dir.join("scenario.toml").display().to_string()),
        )?;
        let events = simulation.events();
        Ok(Self {
            simulation: Some(simulation),
            scenario,
            recorded: None,
            resumed: Some((run_dir, events)),
        })
    }

    /// set(key, value) -> dict
    ///
    /// Changes a parameter from the current time on, between two advance() calls:
    /// "collisions.restitution", "collisions.tangential_restitution" and
    /// "collisions.friction" (rough grains; -1 makes them smooth, smooth grains cannot
    /// become rough), "collisions.wall_restitution",
    /// "collisions.wall_tangential_restitution", "collisions.contact_duration" (the TC
    /// model), "driving.strength" (white noise), "driving.temperature" (rescaling),
    /// "gravity" (a list of D numbers). Validated as the same key in a scenario; other keys
    /// (counts, dimension, box, species, seed, engine) and every key of the intruder engine
    /// raise ScenarioError saying so, and a refused call changes nothing. Returns the change
    /// as a dict (time, key, old, new); the changes are kept (`changes`) and written to
    /// log.txt and summary.json (`changes`) by run(out=...).
    fn set<'py>(
        &mut self,
        py: Python<'py>,
        key: &str,
        value: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let text = crate::convert::to_toml(value, key)?.to_string();
        let sim = self.sim_mut()?;
        let change = guard("set", || Ok(sim.set(key, &text).cloned()))?
            .map_err(|e| scenario_error(py, &e, None))?;
        self.scenario = match self.scenario.with_overrides(py, &[format!("{key}={text}")]) {
            Ok(s) => s,
            // Rough grains made smooth: the changed scenario drops the species' rough keys
            // (`scenario::changed`), which the overrides alone cannot say.
            Err(_) => {
                let changed = self.sim()?.scenario().clone();
                PyScenario::of(py, &changed, self.scenario.origin.clone())?
            }
        };
        let value = serde_json::to_value(&change).map_err(simulation_error)?;
        json_to_python(py, &value)
    }

    /// The parameters changed in flight so far (set), in order: a list of dicts with
    /// time, key, old and new value.
    #[getter]
    fn changes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let value = serde_json::to_value(self.sim()?.changes()).map_err(simulation_error)?;
        json_to_python(py, &value)
    }

    /// set_state(positions=None, velocities=None, angular_velocities=None) -> None
    ///
    /// Sets the positions, velocities and/or (rough grains) angular velocities of every
    /// grain at the current time (positions and velocities float64 (N, D), angular
    /// velocities float64 (N,) in 2D and (N, 3) in 3D, as `angular_velocities` returns
    /// them; input order: grain i is the i-th grain of the scenario's species list; an
    /// array left out keeps its present values). Checked before anything changes:
    /// shape and dtype (TypeError, ValueError), finite values, every centre inside the box
    /// (for edmd at least a radius from a wall) and, for edmd, no two grains overlapping
    /// (ValueError naming the first overlapping pair and their distance), angular
    /// velocities only for rough grains (ValueError for smooth ones); a refused call
    /// leaves the simulation unchanged. The engine then rebuilds what depends on the state
    /// (edmd: every grain synchronised to the current time and every event predicted
    /// again; dsmc: the cell sort) and keys its random streams by the current time, so the
    /// run goes on exactly as `Simulation.from_snapshot` of the same arrays at this time.
    /// Time, counters and initial_kinetic_energy go on. SimulationError for the intruder
    /// engine (no grains).
    #[pyo3(signature = (positions = None, velocities = None, angular_velocities = None))]
    fn set_state(
        &mut self,
        py: Python<'_>,
        positions: Option<&Bound<'_, PyAny>>,
        velocities: Option<&Bound<'_, PyAny>>,
        angular_velocities: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let sim = self.sim_mut()?;
        if sim.engine_name() == "intruder" {
            return Err(state_error(StateError::NoGrains {
                engine: sim.engine_name(),
            }));
        }
        if positions.is_none() && velocities.is_none() && angular_velocities.is_none() {
            return Err(pyo3::exceptions::PyTypeError::new_err(
                "set_state() needs positions=..., velocities=..., angular_velocities=... or \
several of them",
            ));
        }
        if angular_velocities.is_some() && !sim.engine().is_rough() {
            return Err(state_error(StateError::Smooth));
        }
        let (n, d) = (sim.particle_count(), sim.dimension());
        let positions = positions
            .map(|p| crate::state::grain_array(py, "positions", p, n, d))
            .transpose()?;
        let velocities = velocities
            .map(|v| crate::state::grain_array(py, "velocities", v, n, d))
            .transpose()?;
        let spins = angular_velocities
            .map(|w| crate::state::spin_array(py, w, n, d))
            .transpose()?;
        let state = GrainState {
            positions: positions.as_deref(),
            velocities: velocities.as_deref(),
            angular_velocities: spins.as_deref(),
        };
        py.detach(|| guard("set_state", || Ok(sim.set_state(state))))?
            .map_err(state_error)
    }

    /// advance(until) -> None
    ///
    /// Advances to exactly the time `until` (not before the current time). The interpreter
    /// lock is released while the engine works; Ctrl-C raises KeyboardInterrupt between two
    /// chunks of events, with the simulation at the (earlier) time it reached. Raises
    /// SimulationError when the engine cannot go on (e.g. inelastic collapse).
    fn advance(&mut self, py: Python<'_>, until: f64) -> PyResult<()> {
        let sim = self.sim_mut()?;
        let now = sim.time();
        if !(until.is_finite() && until >= now) {
            return Err(value_error(format!(
                "until is {until}; give a finite time not before the current time {now}"
            )));
        }
        loop {
            let progress = py.detach(|| {
                guard("advance", || {
                    sim.advance_chunk(until, CHUNK_EVENTS).map_err(engine_error)
                })
            })?;
            if progress == Progress::Reached {
                return Ok(());
            }
            py.check_signals()?;
        }
    }

    /// run(out=None) -> str | dict
    ///
    /// Runs until the scenario's stop rule ([stop]), on the scenario's output grid: the same
    /// trajectory as `granular run`. Without `out`, in memory: returns the stop reason
    /// ("time", "collisions_per_particle", "collisions", "events", "energy_fraction",
    /// "wall_seconds") and the simulation stays usable. With `out` (a directory), writes the
    /// run directory of `granular run` (summary.json, timeseries.csv, snapshots, histograms;
    /// the same files bit for bit for the same scenario and seed) and returns the summary as
    /// a dict; the simulation is then handed over to the run and this object can no longer
    /// be advanced (read the results with granular.load_run(out)). Ctrl-C raises
    /// KeyboardInterrupt (a run directory is left as a killed run: `granular resume` continues it).
    #[pyo3(signature = (out = None))]
    fn run<'py>(&mut self, py: Python<'py>, out: Option<PathBuf>) -> PyResult<Bound<'py, PyAny>> {
        match out {
            None => Ok(self.run_in_memory(py)?.into_pyobject(py)?.into_any()),
            Some(dir) => self.run_to_directory(py, dir),
        }
    }

    /// observe() -> dict
    ///
    /// The typed observation at the current time as a dict (the library's Observation:
    /// engine, dimension, particles, time, events, collisions, collisions_per_particle,
    /// kinetic_energy, temperature, species (list of dicts), and the engine's optional
    /// counters, None where an engine does not measure one). No side effect.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sim = self.sim()?;
        let obs = guard("observe", || Ok(sim.observe()))?;
        let value = serde_json::to_value(&obs).map_err(simulation_error)?;
        json_to_python(py, &value)
    }

    /// resolved -> dict
    ///
    /// Every quantity the simulation derived from its scenario, resolved once at the
    /// temperature of the drawn initial state (the library's `scenario::Resolved`, the record
    /// `summary.json`'s `resolved` block, `granular check` and the report read): `dimension`
    /// and, for the many-grain engines, `grains` (None for the intruder): `species` (name,
    /// count, radius, mass, grain_volume, temperature), `volume`, `particles`,
    /// `number_density`, `packing_fraction`, `restitution`, `hcs_a2`, `radius`, `mass`,
    /// `contact_value`, `enskog`, `chi`, `temperature`, `collision_frequency`,
    /// `mean_free_time`, `mean_free_path`, `dilute_collision_frequency`, `cooling` (Haff's
    /// time and Sonine factor; None for an elastic gas), `dsmc` (time step and cells; None
    /// for the event-driven engine) and `driving` (the steady state; None without
    /// `[driving]`). Units are the scenario's.
    #[getter]
    fn resolved<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sim = self.sim()?;
        let value = serde_json::to_value(sim.resolved()).map_err(simulation_error)?;
        json_to_python(py, &value)
    }

    /// columns() -> dict[str, float]
    ///
    /// The observation as the named values of a `timeseries.csv` row (same names, same
    /// order; the rates over an output interval are not included).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let sim = self.sim()?;
        let cols = guard("columns", || Ok(sim.observe().columns(None)))?;
        let d = PyDict::new(py);
        for (k, v) in cols {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// snapshot() -> dict
    ///
    /// The state of every grain, copied into new NumPy arrays, in input order (grain i is the
    /// i-th grain of the scenario's species list): "positions" and "velocities" float64
    /// (N, D), "radii" and "masses" float64 (N,), "species" uint32 (N,) indices into
    /// "species_names" (list of str), and "time" (float). Raises SimulationError for the
    /// intruder engine (no grains; use observe()).
    fn snapshot<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.snapshot_or_error()?;
        let d = PyDict::new(py);
        let dim = s.dimension.max(1);
        let n = s.radii.len();
        d.set_item("time", s.time)?;
        d.set_item("positions", matrix(py, s.positions, n, dim)?)?;
        d.set_item("velocities", matrix(py, s.velocities, n, dim)?)?;
        d.set_item("radii", PyArray1::from_vec(py, s.radii))?;
        d.set_item("masses", PyArray1::from_vec(py, s.masses))?;
        d.set_item("species", PyArray1::from_vec(py, s.species))?;
        d.set_item("species_names", s.species_names)?;
        if !s.angular_velocities.is_empty() {
            d.set_item(
                "angular_velocities",
                spins(py, s.angular_velocities, n, dim)?,
            )?;
        }
        Ok(d)
    }

    /// Angular velocities of rough grains (radians per time unit), input order: float64
    /// (N,) in 2D (the spin ω_z about the axis normal to the plane), (N, 3) in 3D; None for
    /// smooth grains (collisions.tangential_restitution = -1), which carry no rotation. A
    /// new copy at every access.
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let s = self.snapshot_or_error()?;
        if s.angular_velocities.is_empty() {
            return Ok(None);
        }
        let n = s.radii.len();
        spins(py, s.angular_velocities, n, s.dimension).map(Some)
    }

    /// Positions, float64 (N, D), input order; a new copy at every access (use
    /// snapshot() to get several arrays of one instant).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.one_array(py, crate::state::Quantity::Positions)
    }

    /// Velocities, float64 (N, D), input order; a new copy at every access.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.one_array(py, crate::state::Quantity::Velocities)
    }

    /// Radii, float64 (N,), input order; a new copy at every access.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_vec(py, self.snapshot_or_error()?.radii))
    }

    /// Masses, float64 (N,), input order; a new copy at every access.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_vec(py, self.snapshot_or_error()?.masses))
    }

    /// Species indices, uint32 (N,), into species_names; a new copy at every access.
    #[getter]
    fn species<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        Ok(PyArray1::from_vec(py, self.snapshot_or_error()?.species))
    }

    /// The box as a dict that freud (`freud.box.Box.from_box(sim.box)`) and HOOMD-blue
    /// take: "Lx", "Ly", "Lz" (0 in 2D), "xy", "xz", "yz" (0), "dimensions". granular's box
    /// runs from 0 to L along each axis, freud's from -L/2 to L/2 (shift the positions by
    /// L/2); freud treats every axis as periodic (set its `periodic` for walled axes).
    /// SimulationError for the intruder engine.
    #[getter(r#box)]
    fn simulation_box<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::state::box_dict(py, self.sim()?.scenario())
    }

    /// Species names, in the scenario's order.
    #[getter]
    fn species_names(&self) -> Vec<String> {
        self.scenario
            .resolved
            .species()
            .iter()
            .map(|s| s.name.clone())
            .collect()
    }

    /// impact_histogram() -> dict | None
    ///
    /// Histogram of the normalised impact parameter b/sigma of all pair collisions so far
    /// (edmd, dsmc): "edges" float64 (B+1,), "counts" uint64 (B,), "underflow", "overflow";
    /// None for the intruder engine.
    fn impact_histogram<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let sim = self.sim()?;
        let Some(h) = guard("impact_histogram", || Ok(sim.impact_histogram()))? else {
            return Ok(None);
        };
        let bins = h.counts.len();
        let edges: Vec<f64> = (0..=bins)
            .map(|i| h.min + (h.max - h.min) * i as f64 / bins as f64)
            .collect();
        let d = PyDict::new(py);
        d.set_item("edges", PyArray1::from_vec(py, edges))?;
        d.set_item("counts", PyArray1::from_vec(py, h.counts))?;
        d.set_item("underflow", h.underflow)?;
        d.set_item("overflow", h.overflow)?;
        Ok(Some(d))
    }

    /// Current simulation time (the scenario's time unit).
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.sim()?.time())
    }

    /// Events processed since t = 0 (collisions and bookkeeping events).
    #[getter]
    fn events(&self) -> PyResult<u64> {
        Ok(self.sim()?.events())
    }

    /// Collisions since t = 0 (pair collisions; intruder-bath collisions for the intruder).
    #[getter]
    fn collisions(&self) -> PyResult<u64> {
        Ok(self.sim()?.collisions())
    }

    /// Number of grains N (1 for an intruder).
    #[getter]
    fn particle_count(&self) -> PyResult<usize> {
        Ok(self.sim()?.particle_count())
    }

    /// Spatial dimension D of the state (intruder models: 1 for 1d and dsmc-twin, 2 for the
    /// needle and the disk, 3 for the sphere).
    #[getter]
    fn dimension(&self) -> PyResult<usize> {
        Ok(self.sim()?.dimension())
    }

    /// The engine: "edmd", "dsmc" or "intruder".
    #[getter]
    fn engine(&self) -> PyResult<String> {
        Ok(self.sim()?.engine_name().to_string())
    }

    /// Kinetic energy at t = 0.
    #[getter]
    fn initial_kinetic_energy(&self) -> PyResult<f64> {
        Ok(self.sim()?.initial_kinetic_energy())
    }

    /// Fraction of the scenario's run done, in [0, 1], from the stop rule nearest its end.
    #[getter]
    fn fraction_done(&self) -> PyResult<f64> {
        Ok(self.sim()?.fraction_done())
    }

    /// Computing seconds spent on this simulation since it was built.
    #[getter]
    fn wall_seconds(&self) -> PyResult<f64> {
        Ok(self.sim()?.wall_seconds())
    }

    /// The scenario (a copy; changing it does not change this simulation).
    #[getter]
    fn scenario(&self) -> PyScenario {
        self.scenario.clone()
    }

    fn __repr__(&self) -> String {
        match &self.simulation {
            Some(s) => format!(
                "<granular.Simulation engine={:?} N={} D={} t={} events={} collisions={}>",
                s.engine_name(),
                s.particle_count(),
                s.dimension(),
                s.time(),
                s.events(),
                s.collisions()
            ),
            None => format!(
                "<granular.Simulation run to its end into {:?}>",
                self.recorded
                    .as_deref()
                    .unwrap_or(std::path::Path::new("?"))
            ),
        }
    }
}
