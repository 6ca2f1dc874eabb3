//! The pre-flight check run by `check` and at the start of `run`: can the stop rule be
//! reached and does the run fit in memory ([`check`], part of validation), and what will
//! it cost ([`Cost`]: outputs, snapshots, bytes written, collisions, events or time steps),
//! against limits that `--insist` lifts. The estimates come from the scenario's resolved
//! initial state ([`super::Resolved`]) with the Boltzmann collision frequency (Enskog
//! factor χ = 1), Haff's law for a cooling gas (KT-9, DSMC-3) and, for the intruder, the
//! bath's mean speed. Limits are documented in `docs/scenario.md`.

use super::validate::num;
use super::{BathTable, EngineKind, IntruderSpec, Scenario, ScenarioError};
use crate::boundary::AxisKind;
use crate::intruder::ball::BallParams;
use crate::output::format_number;

/// Most outputs (rows of `timeseries.csv`) a run may write.
pub const MAX_OUTPUTS: f64 = 1e6;
/// Most pair collisions a run may be estimated to need (several days of computing).
pub(crate) const MAX_COLLISIONS: f64 = 1e12;
/// Memory assumed available when `/proc/meminfo` cannot be read (bytes).
pub(crate) const FALLBACK_MEMORY: f64 = 16.0 * GIB;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The initial gas of the estimate, from the scenario's resolved values
/// ([`super::Resolved`]): grains, mean temperature, the dilute (Boltzmann, `χ = 1`)
/// collision frequency ω0 per grain (KT-5) and Haff's time of that estimate (KT-9 without
/// the Sonine factor, or `2 / ζ` of RS-5 for rough grains; infinite for an elastic gas).
struct Gas {
    n: f64,
    temperature: f64,
    omega: f64,
    haff: f64,
}

fn gas(sc: &Scenario) -> Gas {
    let resolved = sc.resolve();
    let Some(g) = resolved.grains else {
        return Gas {
            n: 0.0,
            temperature: 0.0,
            omega: f64::NAN,
            haff: f64::INFINITY,
        };
    };
    Gas {
        n: g.particles as f64,
        temperature: g.temperature,
        omega: g.dilute_collision_frequency,
        // Rough grains: `2 / ζ` with the cooling rate of their cooling state (RS-5).
        haff: match (&g.rough, &g.cooling) {
            (Some(r), _) => r.dilute_haff_time,
            (None, Some(c)) => c.dilute_haff_time,
            (None, None) => f64::INFINITY,
        },
    }
}

fn elastic_everywhere(sc: &Scenario) -> bool {
    let law = sc.collisions().law();
    let walls = sc.axes().contains(&AxisKind::Wall);
    // Rough grains lose energy to the tangential restitution too, unless β = ±1.
    let rough_elastic =
        !law.is_rough() || (law.friction.is_none() && law.tangential_restitution.abs() == 1.0);
    law.restitution == 1.0
        && rough_elastic
        && (!walls || (law.wall_restitution == 1.0 && law.wall_tangential_restitution == 1.0))
}

/// Runs the pre-flight checks of a validated scenario that no flag lifts: the stop rule
/// can be reached, the grains fit in memory, the DSMC step is below the mean free time.
/// The cost limits are apart ([`Cost::check_limits`]): `--insist` lifts them.
pub(super) fn check(sc: &Scenario) -> Result<(), ScenarioError> {
    if sc.kind() == EngineKind::Intruder {
        return Ok(());
    }
    let g = gas(sc);
    reachable(sc, &g)?;
    memory(sc, g.n)?;
    dsmc_step(sc, &g)
}

/// The stop rules that can never be met.
fn reachable(sc: &Scenario, g: &Gas) -> Result<(), ScenarioError> {
    let s = &sc.stop;
    let gravity = sc.gravity().iter().any(|&x| x != 0.0);
    if s.energy_fraction.is_some() && elastic_everywhere(sc) {
        return Err(ScenarioError::new(
            "stop.energy_fraction",
            "can never be reached: every collision is elastic (collisions.restitution = 1, and the walls elastic), so no energy is lost; set a restitution below 1 or stop by time or collisions",
        ));
    }
    let at_rest = g.temperature == 0.0 && !gravity;
    let single = g.n < 2.0;
    let reason = if at_rest {
        Some("every grain is at rest and there is no gravity: nothing ever moves or collides")
    } else if single {
        Some("there is a single grain: it has no partner to collide with")
    } else {
        None
    };
    let Some(reason) = reason else { return Ok(()) };
    let time_bound = s.time.is_some() || s.wall_seconds.is_some();
    let events_bound = s.events.is_some() && !at_rest;
    if time_bound || events_bound {
        return Ok(());
    }
    let rule = if s.energy_fraction.is_some() {
        "stop.energy_fraction"
    } else if s.collisions_per_particle.is_some() {
        "stop.collisions_per_particle"
    } else if s.collisions.is_some() {
        "stop.collisions"
    } else {
        "stop.events"
    };
    let fix = if at_rest {
        "give the grains a velocity (species[i].velocity) or stop by stop.time"
    } else {
        "add grains or stop by stop.time or stop.events"
    };
    Err(ScenarioError::new(
        rule,
        format!("can never be reached: {reason}; {fix}"),
    ))
}

/// Bytes per grain of the event-driven engine: state, cells, event queue and output
/// buffers. Measured peak resident memory at `count = 10^6`: 223 (2D) and 267 (3D) bytes
/// per grain; rounded up.
fn bytes_per_grain(sc: &Scenario) -> f64 {
    if sc.dimension == 2 { 300.0 } else { 400.0 }
}

/// Available memory: `MemAvailable` of `/proc/meminfo`, else [`FALLBACK_MEMORY`].
pub(crate) fn available_memory() -> f64 {
    crate::host::available_memory().unwrap_or(FALLBACK_MEMORY)
}

/// The event-driven engine's grains must fit in the available memory. A DSMC run is
/// checked when it is built, rank by rank from the grains each will own (it may be split
/// over ranks and nodes: `build::MemoryBudget`); here only its cell grid, which no number
/// of ranks makes larger than the engine can index.
fn memory(sc: &Scenario, n: f64) -> Result<(), ScenarioError> {
    if sc.kind() == EngineKind::Dsmc {
        return dsmc_cells(sc);
    }
    let need = n * bytes_per_grain(sc);
    let have = available_memory();
    if need <= have {
        return Ok(());
    }
    let gib = |b: f64| format_number((b / GIB * 10.0).round() / 10.0);
    let (s, _) = sc
        .species()
        .iter()
        .enumerate()
        .max_by_key(|(_, sp)| sp.count)
        .unwrap_or((0, &sc.species()[0]));
    Err(ScenarioError::new(
        format!("species[{s}].count"),
        format!(
            "gives {} grains in all, which need about {} GiB (about {} bytes per grain), but {} GiB are available; lower the count",
            format_number(n),
            gib(need),
            bytes_per_grain(sc),
            gib(have)
        ),
    ))
}

/// The DSMC cell grid must have fewer cells than the engine can index (`2^32 - 1`, its
/// cell numbers are 32-bit), however many ranks share it: `n_k = max(1, floor(L_k /
/// cell_size))` cells along axis `k`, as the engine cuts the box.
fn dsmc_cells(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(l) = sc.dsmc().and_then(|d| d.cell_size).filter(|l| *l > 0.0) else {
        return Ok(());
    };
    let cells: f64 = sc
        .lengths()
        .iter()
        .map(|x| (x / l).floor().max(1.0))
        .product();
    let limit = u32::MAX as f64;
    if cells < limit {
        return Ok(());
    }
    Err(ScenarioError::new(
        "dsmc.cell_size",
        format!(
            "is {}: it cuts the box into {} cells, more than the {} the DSMC engine can number (whatever the number of ranks); give a larger cell, about the mean free path (leave it out for the automatic size)",
            format_number(l),
            format_number(cells),
            format_number(limit)
        ),
    ))
}

/// The DSMC time step must stay below the initial mean free time.
fn dsmc_step(sc: &Scenario, g: &Gas) -> Result<(), ScenarioError> {
    if g.omega.is_nan() || g.omega <= 0.0 {
        return Ok(());
    }
    let Some(tau) = sc.dsmc().and_then(|d| d.time_step) else {
        return Ok(());
    };
    let free_time = 1.0 / g.omega;
    if tau > free_time {
        return Err(ScenarioError::new(
            "dsmc.time_step",
            format!(
                "is {tau}, longer than the initial mean free time (about {free_time:.3e}): a grain would collide several times per step; give a step well below it (leave it out for one tenth of it)"
            ),
        ));
    }
    Ok(())
}

/// Pair collisions per grain by time `t` and its inverse: Haff's law for an inelastic gas
/// without gravity (`ω0 t0 ln(1 + t/t0)`, the integral of KT-5 along KT-9's `T(t)`),
/// `ω0 t` for an elastic one.
struct Clock {
    omega: f64,
    /// Haff time t0 = 2D / ((1 - e²) ω0); infinite for an elastic gas.
    haff: f64,
}

impl Clock {
    fn per_grain(&self, t: f64) -> f64 {
        if self.haff.is_finite() {
            self.omega * self.haff * (t / self.haff).ln_1p()
        } else {
            self.omega * t
        }
    }

    /// The time at which each grain has had `c` collisions.
    fn time_of(&self, c: f64) -> f64 {
        if self.haff.is_finite() {
            self.haff * (c / (self.omega * self.haff)).exp_m1()
        } else {
            c / self.omega
        }
    }
}

/// What a run will cost, estimated before it starts from the initial state (printed by
/// `granular check`, checked against the limits at the start of `run`).
#[derive(Clone, Debug, PartialEq)]
pub struct Cost {
    /// Expected simulated time at the stop (infinite where it cannot be told, e.g. a run
    /// under gravity stopped by collisions).
    pub end_time: f64,
    /// The stop rule expected to end the run.
    pub rule: &'static str,
    /// Rows of `timeseries.csv`.
    pub outputs: f64,
    /// Snapshots (`snapshots/*.npz`).
    pub snapshots: f64,
    /// Pair collisions (the intruder's collisions).
    pub collisions: f64,
    /// Events of the event-driven engine (`EDMD_EVENTS_PER_COLLISION` per collision);
    /// time steps of DSMC (about ten per mean free time); `None` for the intruder.
    pub steps: Option<(f64, &'static str)>,
    /// Bytes the run writes: the time series, snapshots and observables.
    pub bytes: f64,
    /// For a cooling gas: the time series was estimated with Haff's law (an upper estimate
    /// of the time to a collision count: a clustering gas collides more often).
    pub cooling: bool,
    /// A lower bound of the stop time (collisions at the initial collision frequency; 0
    /// for rules that may stop a run at any time).
    pub earliest_time: f64,
    /// The outputs up to [`Cost::earliest_time`], used for the limit: a cooling gas may
    /// reach its collisions sooner than Haff's law says (clusters collide more often).
    pub outputs_at_least: f64,
    /// The key that sets the outputs (`output.interval`, or the rule that ends the run).
    output_key: &'static str,
}

/// Collisions per second assumed for a run stopped only by `stop.wall_seconds` (an upper
/// estimate of one run's speed on one core).
pub(crate) const NOMINAL_COLLISIONS_PER_SECOND: f64 = 1e7;
/// Events per pair collision of the event-driven engine in the estimate (measured 1.35 to
/// 1.45 in 2D gases, `docs/performance.md`; cell crossings add more in dilute gases).
pub(crate) const EDMD_EVENTS_PER_COLLISION: f64 = 2.0;
/// Most bytes a run may be estimated to write (100 GB).
pub(crate) const MAX_BYTES: f64 = 1e11;
/// Above this many estimated outputs of a cooling gas with `output.spacing = "linear"`,
/// the run warns and proposes logarithmic spacing.
pub(crate) const WARN_OUTPUTS: f64 = 1e4;

/// Bytes of one number in `timeseries.csv` (shortest round-trip decimal and separator).
const CSV_NUMBER: f64 = 24.0;

fn bytes_written(sc: &Scenario, n: f64, outputs: f64, snapshots: f64) -> f64 {
    let d = sc.dimension as f64;
    let columns = 12.0 + 2.0 * sc.species().len() as f64;
    let mut bytes = outputs * columns * CSV_NUMBER;
    // Positions, velocities, radius, mass (f64) and species (u32) per grain.
    bytes += snapshots * n * ((2.0 * d + 2.0) * 8.0 + 4.0);
    let o = &sc.output;
    let observed = if o.observable_times.is_empty() {
        outputs
    } else {
        o.observable_times.len() as f64
    };
    let cells: f64 = o.density_map.iter().map(|&b| b as f64).product();
    if !o.density_map.is_empty() {
        bytes += observed * cells * 8.0;
    }
    if o.structure_factor {
        bytes += observed * (o.structure_factor_max_index as f64).powi(sc.dimension as i32) * 16.0;
    }
    bytes
}

impl Cost {
    /// The limits (`MAX_OUTPUTS`, `MAX_COLLISIONS`, `MAX_BYTES`): the first exceeded, as an
    /// error naming the key to change (and `--insist`).
    pub fn check_limits(&self) -> Result<(), ScenarioError> {
        let insist = "or pass --insist to run it anyway";
        // A wall-clock rule bounds the computing by itself.
        let timed = self.rule == "stop.wall_seconds";
        if !timed && self.collisions.is_finite() && self.collisions > MAX_COLLISIONS {
            return Err(ScenarioError::new(
                self.rule,
                format!(
                    "would take about {:.3e} pair collisions (stop at t ~ {}); the limit is {MAX_COLLISIONS:e} (days of computing): lower it, or bound the run with stop.events or stop.wall_seconds, {insist}",
                    self.collisions,
                    sig(self.end_time)
                ),
            ));
        }
        if self.outputs_at_least > MAX_OUTPUTS {
            return Err(ScenarioError::new(
                self.output_key,
                format!(
                    "gives at least {:.3e} outputs before {} can stop the run (at t >= {}); the limit is {MAX_OUTPUTS:e}: write fewer outputs (a longer output.interval, or output.spacing = \"log\"), {insist}",
                    self.outputs_at_least,
                    self.rule,
                    sig(self.end_time)
                ),
            ));
        }
        if self.bytes.is_finite() && self.bytes > MAX_BYTES {
            let key = if self.snapshots * 1e3 > self.outputs {
                "output.snapshot_every"
            } else {
                self.output_key
            };
            return Err(ScenarioError::new(
                key,
                format!(
                    "makes the run write about {} GB ({:.3e} outputs, {:.3e} snapshots); the limit is {} GB: write fewer outputs or snapshots, {insist}",
                    num((self.bytes / 1e9).round()),
                    self.outputs,
                    self.snapshots,
                    MAX_BYTES / 1e9
                ),
            ));
        }
        Ok(())
    }

    /// A warning for a cooling gas with many evenly spaced outputs.
    pub fn warning(&self, sc: &Scenario) -> Option<String> {
        use super::OutputSpacing;
        (self.cooling && sc.output.spacing == OutputSpacing::Linear && self.outputs > WARN_OUTPUTS)
            .then(|| {
                format!(
                    "the gas cools: {} is reached at t ~ {} by Haff's law (sooner if the gas clusters, at t >= {}), after {:.3e} to {:.3e} evenly spaced outputs at output.interval = {}; output.spacing = \"log\" writes {} outputs per decade of time instead",
                    self.rule,
                    sig(self.end_time),
                    sig(self.earliest_time),
                    self.outputs_at_least,
                    self.outputs,
                    num(sc.output.interval),
                    sc.output.per_decade
                )
            })
    }

    /// The estimate as lines for the terminal (counts whole, to three significant digits:
    /// `163`, `2.35e7`).
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!(
            "stops by {} at t ~ {}{}",
            self.rule,
            sig(self.end_time),
            if self.cooling {
                " (Haff's law for the cooling gas; a clustering gas gets there sooner)"
            } else {
                ""
            }
        )];
        out.push(format!(
            "{} outputs, {} snapshots, about {} written",
            sig(self.outputs.ceil()),
            sig(self.snapshots.ceil()),
            human_bytes(self.bytes)
        ));
        let mut work = format!("{} collisions", sig(self.collisions.ceil()));
        if let Some((steps, what)) = self.steps {
            work.push_str(&format!(", {} {what}", sig(steps.ceil())));
        }
        out.push(work);
        out
    }
}

/// `x` to three significant digits, as [`num`] writes it (`23905.09` becomes `2.39e4`).
fn sig(x: f64) -> String {
    num(format!("{x:.2e}").parse::<f64>().unwrap_or(x))
}

fn human_bytes(b: f64) -> String {
    if !b.is_finite() {
        return "an unknown amount".into();
    }
    let units = ["bytes", "kB", "MB", "GB", "TB", "PB"];
    let mut x = b;
    let mut u = 0;
    while x >= 1000.0 && u + 1 < units.len() {
        x /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{x:.0} bytes")
    } else {
        format!("{x:.1} {}", units[u])
    }
}

/// How one stop rule is expected to end a run.
#[derive(Clone, Copy)]
struct End {
    /// Expected time.
    time: f64,
    /// A lower bound of the time.
    earliest: f64,
    /// Pair collisions by then.
    collisions: f64,
    rule: &'static str,
}

impl End {
    fn new(time: f64, earliest: f64, collisions: f64, rule: &'static str) -> Self {
        Self {
            time,
            earliest,
            collisions,
            rule,
        }
    }
}

/// The cost of a scenario of grains (EDMD or DSMC).
fn grains_cost(sc: &Scenario, g: &Gas) -> Cost {
    let s = &sc.stop;
    let gravity = sc.gravity().iter().any(|&x| x != 0.0);
    let e = sc.collisions().restitution;
    // A driven gas (`[driving]`) does not cool: its clock runs at the initial
    // temperature (the rescaled one's exactly, the heated one's near its steady value).
    let law = sc.collisions().law();
    let cooling = (e < 1.0 || law.is_rough())
        && !gravity
        && sc.collisions().contact_duration == 0.0
        && sc.driving().is_none();
    let clock = Clock {
        omega: g.omega,
        haff: if cooling { g.haff } else { f64::INFINITY },
    };
    let elastic = Clock {
        omega: g.omega,
        haff: f64::INFINITY,
    };
    let moving = g.omega > 0.0 && g.omega.is_finite() && !gravity;
    let unknown = f64::INFINITY;
    let mut ends: Vec<End> = Vec::new();
    if let Some(t) = s.time {
        let collisions = if moving {
            g.n / 2.0 * clock.per_grain(t)
        } else {
            f64::NAN
        };
        ends.push(End::new(t, t, collisions, "stop.time"));
    }
    // `bound`: the rule gives a lower bound of the stop time (collision counts do, at the
    // initial collision frequency; events and the wall clock do not: they may stop a run
    // at any time).
    let mut by_collisions = |per_grain: f64, rule, bound: bool| {
        let t = if moving {
            clock.time_of(per_grain)
        } else {
            unknown
        };
        let t_min = if moving && bound {
            elastic.time_of(per_grain)
        } else {
            0.0
        };
        ends.push(End::new(t, t_min, g.n / 2.0 * per_grain, rule));
    };
    if let Some(c) = s.collisions_per_particle {
        by_collisions(c, "stop.collisions_per_particle", true);
    }
    if let Some(c) = s.collisions {
        by_collisions(2.0 * c as f64 / g.n, "stop.collisions", true);
    }
    if let Some(ev) = s.events {
        let per_collision = if sc.kind() == EngineKind::Edmd {
            EDMD_EVENTS_PER_COLLISION
        } else {
            1.0
        };
        by_collisions(2.0 * ev as f64 / per_collision / g.n, "stop.events", false);
    }
    if let Some(w) = s.wall_seconds {
        let per_grain = 2.0 * w * NOMINAL_COLLISIONS_PER_SECOND / g.n;
        by_collisions(per_grain, "stop.wall_seconds", false);
    }
    if let Some(f) = s.energy_fraction {
        if moving && clock.haff.is_finite() {
            // T = f T0 at t = t0 (f^-1/2 - 1); each grain has had ω0 t0 ln(f^-1/2).
            let t = clock.haff * (f.powf(-0.5) - 1.0);
            let c = g.n / 2.0 * g.omega * clock.haff * -0.5 * f.ln();
            ends.push(End::new(t, t / 10.0, c, "stop.energy_fraction"));
        } else {
            ends.push(End::new(unknown, 0.0, f64::NAN, "stop.energy_fraction"));
        }
    }
    // The rule expected first; among rules beyond reach of the estimate (an infinite
    // time), the one with the fewest collisions.
    let first = ends
        .iter()
        .copied()
        .min_by(|a, b| {
            a.time
                .total_cmp(&b.time)
                .then(a.collisions.total_cmp(&b.collisions))
        })
        .unwrap_or(End::new(unknown, 0.0, f64::NAN, "stop"));
    let (end_time, rule, collisions) = (first.time, first.rule, first.collisions);
    let earliest = (
        ends.iter().map(|e| e.earliest).fold(unknown, f64::min),
        rule,
    );
    let o = &sc.output;
    let outputs = if end_time.is_finite() {
        o.count_until(end_time)
    } else {
        f64::NAN
    };
    let outputs_at_least = if earliest.0.is_finite() {
        o.count_until(earliest.0)
    } else {
        0.0
    };
    let snapshots = if o.snapshot_every == 0 {
        2.0
    } else {
        2.0 + outputs / o.snapshot_every as f64
    };
    let steps = match sc.kind() {
        EngineKind::Edmd => Some((collisions * EDMD_EVENTS_PER_COLLISION, "events")),
        _ => Some((
            match sc.dsmc().and_then(|d| d.time_step) {
                Some(tau) => end_time / tau,
                // The automatic step, `STEP_FRACTION` of the mean free time: that many
                // steps per collision of a grain.
                None => collisions * 2.0 / g.n / crate::dsmc::config::STEP_FRACTION,
            },
            "time steps",
        )),
    };
    Cost {
        end_time,
        rule,
        outputs,
        snapshots,
        collisions,
        steps,
        bytes: bytes_written(sc, g.n, outputs, snapshots),
        cooling: cooling && rule != "stop.time",
        earliest_time: earliest.0,
        outputs_at_least,
        output_key: "output.interval",
    }
}

/// The cost of `sc` (validated).
pub(super) fn cost(sc: &Scenario) -> Cost {
    if sc.kind() == EngineKind::Intruder {
        intruder_cost(sc)
    } else {
        grains_cost(sc, &gas(sc))
    }
}

/// The intruder's cost: its collision rate ν ≈ ρ ⟨|v|⟩ (times the needle's length, the
/// disk's or sphere's cross-section σ_d); for
/// the limit, ten times that rate (an intruder faster than the bath collides more often).
fn intruder_cost(sc: &Scenario) -> Cost {
    let mean_speed = |t: f64, m: f64| (2.0 * t / (std::f64::consts::PI * m)).sqrt();
    let rate = match &sc.intruder() {
        Some(IntruderSpec::Needle(c)) => {
            c.bath_density * c.length * mean_speed(c.bath_temperature, c.bath_mass)
        }
        Some(spec @ (IntruderSpec::Disk(c) | IntruderSpec::Sphere(c))) => {
            // rho sigma_d <c> (G-32 at rest); NaN for a bath file not read yet.
            let d = spec.dimension();
            c.config(d)
                .and_then(|cfg| BallParams::new(&cfg, d))
                .map_or(f64::NAN, |p| 1.0 / p.rest_collision_time())
        }
        Some(spec) => match spec.one_d() {
            Some(c) => match &c.bath {
                BathTable::Gaussian { temperature } | BathTable::PowerLaw { temperature } => {
                    c.bath_density * mean_speed(*temperature, c.bath_mass)
                }
                BathTable::Tabulated { .. } => f64::NAN,
            },
            None => f64::NAN,
        },
        None => f64::NAN,
    };
    let s = &sc.stop;
    let mut ends: Vec<(f64, f64, &'static str)> = Vec::new();
    if let Some(x) = s.time {
        ends.push((x, x, "stop.time"));
    }
    let by_count = |c: f64| (c / rate, c / rate / 10.0);
    if let Some(c) = s.collisions {
        let (t, t_min) = by_count(c as f64);
        ends.push((t, t_min, "stop.collisions"));
    }
    if let Some(e) = s.events {
        let (t, t_min) = by_count(e as f64);
        ends.push((t, t_min, "stop.events"));
    }
    if let Some(w) = s.wall_seconds {
        let (t, _) = by_count(w * NOMINAL_COLLISIONS_PER_SECOND);
        ends.push((t, 0.0, "stop.wall_seconds"));
    }
    let nan_last = |a: (f64, &'static str), b: (f64, &'static str)| {
        if b.0 < a.0 || a.0.is_nan() { b } else { a }
    };
    let (end_time, rule) = ends
        .iter()
        .map(|&(t, _, r)| (t, r))
        .fold((f64::INFINITY, "stop"), nan_last);
    let (earliest, _) = ends
        .iter()
        .map(|&(_, t, r)| (t, r))
        .fold((f64::INFINITY, "stop"), nan_last);
    let o = &sc.output;
    // Unknown where the bath's collision rate is (a tabulated bath).
    let outputs = if end_time.is_finite() {
        o.count_until(end_time)
    } else {
        f64::NAN
    };
    Cost {
        end_time,
        rule,
        outputs,
        snapshots: 0.0,
        collisions: end_time * rate,
        steps: None,
        bytes: bytes_written(sc, 1.0, outputs, 0.0),
        cooling: false,
        earliest_time: earliest,
        outputs_at_least: if earliest.is_finite() {
            o.count_until(earliest)
        } else {
            0.0
        },
        output_key: "output.interval",
    }
}
