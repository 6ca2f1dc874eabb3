//! A simulation held in memory: built from a [`Scenario`], advanced to a time or until the
//! scenario's stop rule, read through typed observations and its particle state. The
//! command line, the Python package and the run directory (`run::Run`) all drive
//! this one type; nothing here touches a file.

use crate::build::{AnyEngine, BuildError, build_resolved};
use crate::engine::{Engine, EngineError, Progress, Snapshot};
use crate::grain_state::{self, GrainState, StateError};
pub use crate::in_flight::Change;
use crate::observation::Observation;
use crate::scenario::{Resolved, Scenario, ScenarioError, ScheduledChange, StopSpec};
use crate::stats::Histogram;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Events per chunk of [`Simulation::run_with`]: between two chunks the hooks report
/// progress, take checkpoints and may interrupt (a dense bed can spend hours of events in
/// one output interval).
pub const CHUNK_EVENTS: u64 = 200_000;

/// Which stop rule of `[stop]` ended a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// `stop.time` was reached.
    Time,
    /// `stop.collisions_per_particle` was reached.
    CollisionsPerParticle,
    /// `stop.collisions` was reached.
    Collisions,
    /// `stop.events` was reached.
    Events,
    /// The kinetic energy fell to `stop.energy_fraction` of its initial value.
    EnergyFraction,
    /// `stop.wall_seconds` of computing time were spent.
    WallSeconds,
}

impl StopReason {
    /// The name written in `summary.json` (`stop_reason`), the same as the `[stop]` key.
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::Time => "time",
            StopReason::CollisionsPerParticle => "collisions_per_particle",
            StopReason::Collisions => "collisions",
            StopReason::Events => "events",
            StopReason::EnergyFraction => "energy_fraction",
            StopReason::WallSeconds => "wall_seconds",
        }
    }
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the run loop of [`Simulation::run_with`] calls on the way: outputs, progress,
/// checkpoints and interruption hang here. Every method has a default that does nothing.
pub trait RunHooks {
    /// The error the hooks may return (it must hold an engine error too).
    type Error: From<EngineError>;

    /// After each chunk of at most [`CHUNK_EVENTS`] events.
    fn after_chunk(&mut self, _simulation: &Simulation) -> Result<(), Self::Error> {
        Ok(())
    }

    /// At each output time of the scenario's grid (`output.interval`), and at the end
    /// of a run that a stop rule ends between two output times.
    fn at_output(&mut self, _simulation: &Simulation) -> Result<(), Self::Error> {
        Ok(())
    }

    /// After an output at which no stop rule was reached (a test interrupts a run here).
    fn after_output(&mut self, _simulation: &Simulation) -> Result<(), Self::Error> {
        Ok(())
    }

    /// When the engine fails, before the error is returned.
    fn on_engine_error(&mut self, _simulation: &Simulation, _error: &EngineError) {}
}

/// Hooks that do nothing: [`Simulation::run`].
struct NoHooks;

impl RunHooks for NoHooks {
    type Error = EngineError;
}

/// The part of a simulation that a checkpoint holds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct SimulationState {
    pub engine: AnyEngine,
    pub initial_kinetic_energy: f64,
    /// The temperature of the initial state, at which the scenario was resolved (`None`
    /// for the intruder engine).
    pub initial_temperature: Option<f64>,
    pub outputs_done: u64,
    pub wall_seconds: f64,
    /// Parameters changed in flight so far ([`Simulation::set`] and `[[schedule]]`).
    #[serde(default)]
    pub changes: Vec<Change>,
    /// Entries of the scenario's `[[schedule]]` applied so far.
    #[serde(default)]
    pub schedule_done: usize,
}

/// A simulation of any engine, in memory.
///
/// ```
/// use granular::prelude::*;
///
/// let scenario = Scenario::from_toml(
///     r#"
///     engine = "edmd"
///     dimension = 2
///     seed = 7
///     [[species]]
///     name = "disk"
///     count = 200
///     packing_fraction = 0.2
///     velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
///     [stop]
///     collisions_per_particle = 5
///     [output]
///     interval = 1.0
///     "#,
///     &[],
/// )?;
/// let mut simulation = Simulation::new(scenario)?;
/// let reason = simulation.run()?;
/// let observation = simulation.observe();
/// assert_eq!(reason, StopReason::CollisionsPerParticle);
/// assert!(observation.collisions_per_particle >= 5.0);
/// // Elastic disks keep their energy to round-off.
/// let k0 = simulation.initial_kinetic_energy();
/// assert!((observation.kinetic_energy - k0).abs() < 1e-10 * k0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Simulation {
    scenario: Scenario,
    /// Every derived quantity of the scenario, at the drawn initial state.
    resolved: Resolved,
    engine: AnyEngine,
    initial_kinetic_energy: f64,
    outputs_done: u64,
    wall_seconds_before: f64,
    session_start: Instant,
    session_events_start: u64,
    /// Turns this process's `stop.wall_seconds` verdict into the one every rank of a
    /// decomposed run takes ([`Simulation::decide_wall_clock_with`]).
    wall_clock: Option<WallClock>,
    /// Parameters changed in flight so far, in order ([`Simulation::set`] and the
    /// scenario's `[[schedule]]`).
    changes: Vec<Change>,
    /// The scenario as it was before the first change in flight (`None` while there was
    /// none): checkpoints hold it, and restoring one makes the changes again.
    started_as: Option<Box<Scenario>>,
    /// Entries of the scenario's `[[schedule]]` applied so far.
    schedule_done: usize,
}

/// `decide(local)`: the `stop.wall_seconds` verdict of all ranks from this rank's own
/// (`local`), the same on every rank (for example rank 0's, broadcast). Collective.
pub type WallClock = Box<dyn Fn(bool) -> bool + Send + Sync>;

/// `scenario` resolved at the initial temperature `temperature` of its simulation (the
/// drawn state's; `None` for the intruder engine): a restored checkpoint and a change in
/// flight ([`Simulation::set`]) resolve the scenario as it now stands at the same
/// temperature as the run's start.
fn resolve_at(scenario: &Scenario, temperature: Option<f64>) -> Resolved {
    let nominal = scenario.resolve();
    match temperature {
        Some(t) => nominal.at_temperature(scenario, t),
        None => nominal,
    }
}

impl Simulation {
    /// Builds the engine of `scenario` (validated first) with its initial state.
    pub fn new(scenario: Scenario) -> Result<Simulation, BuildError> {
        let (engine, resolved) = build_resolved(&scenario)?;
        Ok(Simulation::from_parts(scenario, engine, resolved))
    }

    /// A simulation of `scenario` from an engine built from it and the scenario resolved
    /// at that engine's initial state (`build::build_resolved`, `build::build_on`).
    pub(crate) fn from_parts(
        scenario: Scenario,
        engine: AnyEngine,
        resolved: Resolved,
    ) -> Simulation {
        let initial_kinetic_energy = engine.kinetic_energy();
        Simulation {
            scenario,
            resolved,
            engine,
            initial_kinetic_energy,
            outputs_done: 0,
            wall_seconds_before: 0.0,
            session_start: Instant::now(),
            session_events_start: 0,
            wall_clock: None,
            changes: Vec::new(),
            started_as: None,
            schedule_done: 0,
        }
    }

    /// A simulation of `scenario` that starts from given grains at time `time` instead of
    /// the scenario's initial state: the engine is built from the scenario, then its
    /// grains are set as by [`Simulation::set_state`] at `time` (both arrays row-major
    /// `n × D` in input order; rough grains keep the angular velocities the scenario
    /// draws, see [`Simulation::from_grain_state`] to give them too). The continuation is
    /// the same, bit for bit, as that of any simulation of the same scenario whose state
    /// was set to the same arrays at the same time, for instance one that ran up to `time`
    /// and took a snapshot there: the engines rebuild everything from the arrays and key
    /// their random streams by `time` (see `crate::random::RESTART`).
    pub fn from_state(
        scenario: Scenario,
        time: f64,
        positions: &[f64],
        velocities: &[f64],
    ) -> Result<Simulation, StateError> {
        Simulation::from_grain_state(
            scenario,
            time,
            GrainState {
                positions: Some(positions),
                velocities: Some(velocities),
                angular_velocities: None,
            },
        )
    }

    /// [`Simulation::from_state`] from any of the per-grain arrays of a [`GrainState`]:
    /// those it leaves out are the scenario's drawn ones. A snapshot of a rough run
    /// (its positions, velocities and angular velocities) restarts it exactly.
    pub fn from_grain_state(
        scenario: Scenario,
        time: f64,
        state: GrainState<'_>,
    ) -> Result<Simulation, StateError> {
        if !(time.is_finite() && time >= 0.0) {
            return Err(StateError::Time(time));
        }
        let mut simulation = Simulation::new(scenario)?;
        let a = grain_state::checked(&simulation.engine, state)?;
        simulation
            .engine
            .restart(time, &a.positions, &a.velocities, &a.angular_velocities)
            .map_err(StateError::Engine)?;
        simulation.initial_kinetic_energy = simulation.engine.kinetic_energy();
        Ok(simulation)
    }

    /// Sets the positions, velocities and/or (rough grains) angular velocities of every
    /// grain (row-major `n × D`, and `n` values in 2D or `n × 3` in 3D for the angular
    /// velocities, in input order; `None` keeps the present ones) at the current time, and
    /// lets the engine rebuild what depends on them: the event-driven engine synchronises
    /// every grain to the current time and predicts every event again, DSMC sorts its
    /// cells again, and both key their random streams by the current time
    /// (`crate::random::RESTART`), so that the run goes on exactly as
    /// [`Simulation::from_grain_state`] of the same arrays at this time. Checked before
    /// anything changes: the lengths, finite values, centres inside the box (and, for the
    /// event-driven engine, at least a radius from a wall and no two grains overlapping),
    /// angular velocities only for rough grains. Refused for the intruder engines and for
    /// a DSMC run split over ranks. The clock, the counters and `initial_kinetic_energy`
    /// go on.
    pub fn set_state(&mut self, state: GrainState<'_>) -> Result<(), StateError> {
        let a = grain_state::checked(&self.engine, state)?;
        let time = self.time();
        self.engine
            .restart(time, &a.positions, &a.velocities, &a.angular_velocities)
            .map_err(StateError::Engine)
    }

    /// Changes the parameter `key` to `value` (the right side of `key = value` in TOML, as
    /// `granular run --set` takes it) from the current time on: the collision law
    /// (`collisions.restitution`, `collisions.tangential_restitution` and
    /// `collisions.friction` of rough grains, `collisions.wall_restitution`,
    /// `collisions.wall_tangential_restitution`, `collisions.contact_duration`), the
    /// driving's `driving.strength` or `driving.temperature`, and `gravity` (the keys of
    /// `scenario::schedule::IN_FLIGHT_KEYS`). Validated as the same key in a scenario (the scenario
    /// with the new value is checked whole); other keys, and every key of the intruder
    /// engines, are refused saying so. The change is kept ([`Simulation::changes`]) for
    /// `log.txt`, `summary.json` and checkpoints, and [`Simulation::resolved`] is resolved
    /// again from the changed scenario at the same initial temperature (Haff's time and the
    /// driving's steady state follow the new values). Rough grains may become smooth
    /// (β = -1: their angular velocities stay as they are); smooth grains carry none and
    /// cannot become rough. A refused change changes nothing.
    pub fn set(&mut self, key: &str, value: &str) -> Result<&Change, ScenarioError> {
        self.change(&[(key.to_string(), value.to_string())])?;
        Ok(&self.changes[self.changes.len() - 1])
    }

    /// Makes the changes `assignments` together at the current time (see
    /// [`Simulation::set`]).
    fn change(&mut self, assignments: &[(String, String)]) -> Result<(), ScenarioError> {
        let time = self.time();
        let (scenario, changes) =
            crate::in_flight::apply(&self.scenario, &mut self.engine, time, assignments)?;
        self.resolved = resolve_at(&scenario, self.initial_temperature());
        let before = std::mem::replace(&mut self.scenario, scenario);
        self.started_as.get_or_insert_with(|| Box::new(before));
        self.changes.extend(changes);
        Ok(())
    }

    /// The scenario's `[[schedule]]`.
    fn schedule(&self) -> &[ScheduledChange] {
        self.scenario.grains().map_or(&[], |g| &g.schedule)
    }

    /// The time of the next entry of the scenario's `[[schedule]]` not applied yet.
    pub fn next_scheduled_time(&self) -> Option<f64> {
        self.schedule().get(self.schedule_done).map(|e| e.time)
    }

    /// Applies the entries of the scenario's `[[schedule]]` whose time has come (at the
    /// current time; a simulation started from a state at a later time applies those it
    /// skipped at its start).
    fn apply_due_schedule(&mut self) -> Result<(), EngineError> {
        while let Some(entry) = self.schedule().get(self.schedule_done) {
            if entry.time > self.time() {
                break;
            }
            let assignments = entry.assignments();
            self.change(&assignments).map_err(|e| {
                EngineError::Numerical(format!(
                    "schedule[{}] could not be applied at t = {}: {e}",
                    self.schedule_done,
                    self.time()
                ))
            })?;
            self.schedule_done += 1;
        }
        Ok(())
    }

    /// The parameters changed in flight so far, in order.
    pub fn changes(&self) -> &[Change] {
        &self.changes
    }

    /// A simulation restored from a checkpoint's state.
    pub(crate) fn restore(scenario: Scenario, state: SimulationState) -> Simulation {
        let events = state.engine.events();
        // The checkpoint holds the scenario the run started with: the changes made in
        // flight since are made to it again (the engine has them already), and the
        // scenario so changed is resolved at the initial temperature (as `set` does).
        let started_as = (!state.changes.is_empty()).then(|| Box::new(scenario.clone()));
        let mut scenario = scenario;
        for change in &state.changes {
            let set = [(change.key.clone(), change.new.clone())];
            if let Ok(s) = crate::scenario::changed(&scenario, &set) {
                scenario = s;
            }
        }
        let resolved = resolve_at(&scenario, state.initial_temperature);
        Simulation {
            started_as,
            schedule_done: state.schedule_done,
            scenario,
            resolved,
            engine: state.engine,
            initial_kinetic_energy: state.initial_kinetic_energy,
            outputs_done: state.outputs_done,
            wall_seconds_before: state.wall_seconds,
            session_start: Instant::now(),
            session_events_start: events,
            wall_clock: None,
            changes: state.changes,
        }
    }

    /// Splits the run over the ranks of `comm` (collective): every rank builds or restores
    /// the same simulation, then keeps its slab of a DSMC engine. The trajectory, the
    /// observations and the checkpoints stay bit-identical to the undecomposed run's
    /// (see [`crate::dsmc::domain`]). Other engines are refused under several ranks.
    pub fn decompose(
        &mut self,
        comm: std::sync::Arc<dyn crate::dsmc::Communicator>,
    ) -> Result<(), crate::dsmc::DomainError> {
        self.engine.decompose(comm)?;
        if let Some(spec) = self.scenario.dsmc() {
            self.engine.set_balance(spec.balance());
        }
        Ok(())
    }

    /// Makes the ranks of a decomposed run stop on `stop.wall_seconds` at the same step:
    /// the rule is checked at the same points on every rank (between chunks of events and
    /// at output times, which do not depend on the clock), and `decide` turns each rank's
    /// own verdict into the common one (collective).
    pub fn decide_wall_clock_with(&mut self, decide: WallClock) {
        self.wall_clock = Some(decide);
    }

    /// Whether `limit` seconds of computing time are spent (by the common verdict of the
    /// ranks when there is one).
    fn wall_time_up(&self, limit: f64) -> bool {
        let local = self.wall_seconds() >= limit;
        match &self.wall_clock {
            Some(decide) => decide(local),
            None => local,
        }
    }

    /// The state a checkpoint holds (the engine is cloned; a decomposed engine is
    /// gathered whole, collectively).
    pub(crate) fn state(&self) -> SimulationState {
        SimulationState {
            engine: self.engine.whole(),
            initial_kinetic_energy: self.initial_kinetic_energy,
            initial_temperature: self.initial_temperature(),
            outputs_done: self.outputs_done,
            wall_seconds: self.wall_seconds(),
            changes: self.changes.clone(),
            schedule_done: self.schedule_done,
        }
    }

    /// The state a decomposed run's checkpoint manifest holds: as [`Simulation::state`]
    /// but the engine without its particles (they are in the ranks' parts). Local.
    pub(crate) fn shell_state(&self) -> SimulationState {
        SimulationState {
            engine: self.engine.shell(),
            initial_kinetic_energy: self.initial_kinetic_energy,
            initial_temperature: self.initial_temperature(),
            outputs_done: self.outputs_done,
            wall_seconds: self.wall_seconds(),
            changes: self.changes.clone(),
            schedule_done: self.schedule_done,
        }
    }

    /// The scenario (validated, with every default filled in), with the changes made in
    /// flight so far.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The scenario as the simulation started, before any change in flight (what a
    /// checkpoint stores).
    pub fn initial_scenario(&self) -> &Scenario {
        self.started_as.as_deref().unwrap_or(&self.scenario)
    }

    /// Replaces the scenario as the simulation started by `stored`, the same scenario with
    /// its per-grain arrays named where a run directory keeps them (`initial_state.npz`), so
    /// that checkpoints name them too instead of holding them as text.
    pub(crate) fn keep_initial_scenario(&mut self, stored: Scenario) {
        debug_assert!(stored == *self.initial_scenario());
        match &mut self.started_as {
            Some(s) => **s = stored,
            None => self.scenario = stored,
        }
    }

    /// Every quantity derived from the scenario (radii, packing fraction, contact value,
    /// collision frequency, mean free time and path, Haff's time, the DSMC step and cells,
    /// the driving's state), resolved once at the temperature of the drawn initial state.
    pub fn resolved(&self) -> &Resolved {
        &self.resolved
    }

    /// The temperature of the initial state (the many-grain engines).
    fn initial_temperature(&self) -> Option<f64> {
        self.resolved.grains.as_ref().map(|g| g.temperature)
    }

    /// The engine.
    pub fn engine(&self) -> &AnyEngine {
        &self.engine
    }

    /// Engine name (`"edmd"`, `"dsmc"`, `"intruder"`).
    pub fn engine_name(&self) -> &'static str {
        self.engine.name()
    }

    /// Spatial dimension of the state (the intruder models: 1 or 2).
    pub fn dimension(&self) -> usize {
        self.resolved.dimension
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        self.engine.time()
    }

    /// Events processed since `t = 0`.
    pub fn events(&self) -> u64 {
        self.engine.events()
    }

    /// Collisions since `t = 0` (see [`Observation::collisions`]).
    pub fn collisions(&self) -> u64 {
        self.engine.collisions()
    }

    /// Number of grains (1 for an intruder).
    pub fn particle_count(&self) -> usize {
        self.engine.particle_count()
    }

    /// Kinetic energy at `t = 0`.
    pub fn initial_kinetic_energy(&self) -> f64 {
        self.initial_kinetic_energy
    }

    /// Output intervals of the scenario's grid completed so far.
    pub fn outputs_done(&self) -> u64 {
        self.outputs_done
    }

    /// Computing seconds spent on this simulation, over all sessions of a resumed run.
    pub fn wall_seconds(&self) -> f64 {
        self.wall_seconds_before + self.session_start.elapsed().as_secs_f64()
    }

    /// Events per wall-clock second since this simulation was built or resumed.
    pub fn events_per_second(&self) -> f64 {
        (self.engine.events() - self.session_events_start) as f64
            / self.session_start.elapsed().as_secs_f64().max(1e-9)
    }

    /// The typed observation at the current time (no side effect).
    pub fn observe(&self) -> Observation {
        self.engine.observe()
    }

    /// Positions, velocities, radii, masses and species of every grain, in the order of
    /// the scenario's species and grains (`None` for the intruder engines).
    pub fn snapshot(&self) -> Option<Snapshot> {
        self.engine.snapshot()
    }

    /// Positions of every grain, wrapped into the box, row-major by grain (input order):
    /// `n × D` values, without building a whole snapshot (`None` for the intruder engines).
    pub fn positions(&self) -> Option<Vec<f64>> {
        self.state_array(false)
    }

    /// Velocities of every grain, row-major by grain (input order), as
    /// [`Simulation::positions`].
    pub fn velocities(&self) -> Option<Vec<f64>> {
        self.state_array(true)
    }

    /// Writes the positions of every grain, as [`Simulation::positions`], into `out`, a
    /// buffer the caller owns (for example a NumPy array's): `false`, with `out`
    /// untouched, for the intruder engines or when `out` is not `n × D` long. Filling a
    /// buffer that already exists spares the page faults of a fresh allocation, which
    /// cost as much as the copy itself for 10^6 grains.
    pub fn positions_into(&self, out: &mut [f64]) -> bool {
        self.state_into(false, out)
    }

    /// Writes the velocities of every grain into `out`, as
    /// [`Simulation::positions_into`].
    pub fn velocities_into(&self, out: &mut [f64]) -> bool {
        self.state_into(true, out)
    }

    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        self.engine_name() != "intruder"
            && out.len() == self.particle_count() * self.dimension()
            && self.engine.state_into(velocities, out)
    }

    fn state_array(&self, velocities: bool) -> Option<Vec<f64>> {
        let mut out = vec![0.0; self.particle_count() * self.dimension()];
        self.state_into(velocities, &mut out).then_some(out)
    }

    /// Histogram of `b / σ` of all pair collisions so far (many-grain engines).
    pub fn impact_histogram(&self) -> Option<Histogram> {
        self.engine.impact_histogram()
    }

    /// Advances to exactly `until` (a time not before [`Simulation::time`]).
    pub fn advance(&mut self, until: f64) -> Result<(), EngineError> {
        while self.advance_chunk(until, CHUNK_EVENTS)? == Progress::BudgetExhausted {}
        Ok(())
    }

    /// Advances towards `until`, processing at most `max_events` events: the step of a
    /// loop that does something between chunks (report progress, check for Ctrl-C). It
    /// also returns (with [`Progress::BudgetExhausted`]: call again) at the time of an entry
    /// of the scenario's `[[schedule]]`, after making its changes.
    pub fn advance_chunk(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        self.step_towards(until, max_events)
            .map_err(in_scenario_words)
    }

    /// [`Simulation::advance_chunk`] with the engine's own errors: the `[[schedule]]`
    /// entries due at the current time are applied first, and the engine stops at the
    /// next one (it acts from its time on).
    fn step_towards(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        self.apply_due_schedule()?;
        let target = match self.next_scheduled_time() {
            Some(t) if t < until => t,
            _ => until,
        };
        let progress = self.engine.as_engine().advance(target, max_events.max(1))?;
        if progress == Progress::Reached && target < until {
            self.apply_due_schedule()?;
            return Ok(Progress::BudgetExhausted);
        }
        Ok(progress)
    }

    /// The next time of the output grid (`(k + 1) × output.interval`, or its logarithmic
    /// counterpart with `output.spacing = "log"`), or the stop time when it comes first.
    pub fn next_output_time(&self) -> f64 {
        let mut next = self.scenario.output.time(self.outputs_done + 1);
        if let Some(t) = self.scenario.stop.time {
            next = next.min(t);
        }
        next
    }

    /// Runs until the scenario's stop rule, in memory: the same trajectory as
    /// `granular run` of the same scenario (the stop rules are checked on the same output
    /// grid).
    pub fn run(&mut self) -> Result<StopReason, EngineError> {
        self.run_with(&mut NoHooks)
    }

    /// The run loop with hooks at chunks and outputs (the run directory, progress bars,
    /// interruption). The stop rules live here and only here: `time`,
    /// `collisions_per_particle`, `collisions`, `events` and `energy_fraction` are checked
    /// at output times; `events` and `wall_seconds` also between chunks.
    pub fn run_with<H: RunHooks>(&mut self, hooks: &mut H) -> Result<StopReason, H::Error> {
        let stop = self.scenario.stop.clone();
        // Output times already passed (a simulation advanced by hand before the run).
        while self.scenario.output.time(self.outputs_done + 1) < self.time() {
            self.outputs_done += 1;
        }
        loop {
            let next = self.next_output_time();
            loop {
                let budget = match stop.events {
                    Some(e) => CHUNK_EVENTS.min(e.saturating_sub(self.events())).max(1),
                    None => CHUNK_EVENTS,
                };
                let progress = match self.step_towards(next, budget) {
                    Ok(p) => p,
                    Err(e) => {
                        let e = in_scenario_words(e);
                        hooks.on_engine_error(self, &e);
                        return Err(e.into());
                    }
                };
                hooks.after_chunk(self)?;
                if progress == Progress::Reached {
                    break;
                }
                let mid_interval = if stop.events.is_some_and(|e| self.events() >= e) {
                    Some(StopReason::Events)
                } else if stop.wall_seconds.is_some_and(|w| self.wall_time_up(w)) {
                    Some(StopReason::WallSeconds)
                } else {
                    None
                };
                if let Some(reason) = mid_interval {
                    self.outputs_done += 1;
                    hooks.at_output(self)?;
                    return Ok(reason);
                }
            }
            self.outputs_done += 1;
            hooks.at_output(self)?;
            if let Some(reason) = self.stop_reached(&stop) {
                return Ok(reason);
            }
            hooks.after_output(self)?;
        }
    }

    /// The first stop rule reached at an output time, in the order of `docs/scenario.md`.
    fn stop_reached(&self, stop: &StopSpec) -> Option<StopReason> {
        let n = self.particle_count().max(1) as f64;
        let collisions = self.collisions();
        if stop.time.is_some_and(|t| self.time() >= t) {
            Some(StopReason::Time)
        } else if stop
            .collisions_per_particle
            .is_some_and(|c| 2.0 * collisions as f64 / n >= c)
        {
            Some(StopReason::CollisionsPerParticle)
        } else if stop.collisions.is_some_and(|c| collisions >= c) {
            Some(StopReason::Collisions)
        } else if stop.events.is_some_and(|e| self.events() >= e) {
            Some(StopReason::Events)
        } else if stop
            .energy_fraction
            .is_some_and(|f| self.engine.kinetic_energy() <= f * self.initial_kinetic_energy)
        {
            Some(StopReason::EnergyFraction)
        } else if stop.wall_seconds.is_some_and(|w| self.wall_time_up(w)) {
            Some(StopReason::WallSeconds)
        } else {
            None
        }
    }

    /// Fraction of the run done, in `[0, 1]`, from the stop rule nearest to its end (the
    /// energy rule on a logarithmic scale, `ln(K_0 / K) / ln(1 / f)`).
    pub fn fraction_done(&self) -> f64 {
        let stop = &self.scenario.stop;
        let n = self.particle_count().max(1) as f64;
        let mut f: f64 = 0.0;
        if let Some(t) = stop.time {
            f = f.max(self.time() / t);
        }
        if let Some(c) = stop.collisions_per_particle {
            f = f.max(2.0 * self.collisions() as f64 / n / c);
        }
        if let Some(c) = stop.collisions {
            f = f.max(self.collisions() as f64 / c.max(1) as f64);
        }
        if let Some(e) = stop.events {
            f = f.max(self.events() as f64 / e as f64);
        }
        if let Some(frac) = stop.energy_fraction {
            let k = self.engine.kinetic_energy();
            if self.initial_kinetic_energy > 0.0 && k > 0.0 {
                f = f.max((self.initial_kinetic_energy / k).ln() / (1.0 / frac).ln());
            }
        }
        if let Some(w) = stop.wall_seconds {
            f = f.max(self.wall_seconds() / w);
        }
        f.clamp(0.0, 1.0)
    }
}

/// An engine's error as the user of a scenario reads it: an inelastic collapse with the
/// advice in the scenario's keys ([`crate::scenario::advice`]).
fn in_scenario_words(error: EngineError) -> EngineError {
    match error {
        EngineError::Collapse(mut collapse) => {
            collapse.advice = Some(crate::scenario::advice::collapse(&collapse));
            EngineError::Collapse(collapse)
        }
        other => other,
    }
}
