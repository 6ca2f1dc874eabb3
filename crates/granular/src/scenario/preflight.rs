//! The pre-flight check run by `check` and at the start of `run`: can the stop rule be
//! reached, how many outputs and collisions will the run cost, and does it fit in memory.
//! The estimates come from the initial state with the Boltzmann collision frequency
//! (Enskog factor χ = 1), Haff's law for a cooling gas (HD-17, DSMC-5) and, for the
//! intruder, the bath's mean speed. Limits are documented in `docs/scenario.md`.

use super::validate::num;
use super::{EngineKind, IntruderSpec, Scenario, ScenarioError, VelocitySpec};
use crate::boundary::AxisKind;
use crate::intruder::BathConfig;

/// Most outputs (rows of `timeseries.csv`) a run may write.
pub const MAX_OUTPUTS: f64 = 1e6;
/// Most pair collisions a run may be estimated to need (several days of computing).
pub const MAX_COLLISIONS: f64 = 1e12;
/// Memory assumed available when `/proc/meminfo` cannot be read (bytes).
pub const FALLBACK_MEMORY: f64 = 16.0 * GIB;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The initial gas: grains, mean temperature, per-grain collision frequency ω0.
struct Gas {
    n: f64,
    temperature: f64,
    omega: f64,
}

fn kinetic_temperature(v: &VelocitySpec, mass: f64, d: f64) -> f64 {
    let sq = |u: &[f64]| u.iter().map(|x| x * x).sum::<f64>();
    match v {
        VelocitySpec::Zero => 0.0,
        VelocitySpec::FixedSpeed { speed } => mass * speed * speed / d,
        VelocitySpec::MaxwellBoltzmann { temperature } => *temperature,
        VelocitySpec::Given { velocity } => mass * sq(velocity) / d,
        VelocitySpec::PerGrain { velocities } => {
            let n = velocities.len().max(1) as f64;
            velocities.iter().map(|u| mass * sq(u) / d).sum::<f64>() / n
        }
    }
}

fn gas(sc: &Scenario) -> Gas {
    let d = sc.dimension as f64;
    let n: f64 = sc.species.iter().map(|s| s.count as f64).sum();
    let volume: f64 = sc.lengths().iter().product();
    let (mut t, mut m, mut sigma) = (0.0, 0.0, 0.0);
    for (s, sp) in sc.species.iter().enumerate() {
        let w = sp.count as f64 / n;
        t += w * kinetic_temperature(&sp.velocity, sp.mass, d);
        m += w * sp.mass;
        sigma += w * 2.0 * sc.radius(s);
    }
    let density = n / volume;
    let root_pi = std::f64::consts::PI.sqrt();
    // Boltzmann collision frequency of hard disks / spheres (HD-16 with χ = 1).
    let omega = if sc.dimension == 2 {
        2.0 * root_pi * density * sigma * (t / m).sqrt()
    } else {
        4.0 * root_pi * density * sigma * sigma * (t / m).sqrt()
    };
    Gas {
        n,
        temperature: t,
        omega,
    }
}

fn elastic_everywhere(sc: &Scenario) -> bool {
    let law = sc.collisions.law();
    let walls = sc.axes().contains(&AxisKind::Wall);
    law.restitution == 1.0
        && (!walls || (law.wall_restitution == 1.0 && law.wall_tangential_restitution == 1.0))
}

/// Runs every pre-flight check of a validated scenario.
pub(super) fn check(sc: &Scenario) -> Result<(), ScenarioError> {
    if sc.engine == EngineKind::Intruder {
        return intruder_outputs(sc);
    }
    let g = gas(sc);
    reachable(sc, &g)?;
    memory(sc, g.n)?;
    dsmc_step(sc, &g)?;
    cost(sc, &g)
}

/// The stop rules that can never be met.
fn reachable(sc: &Scenario, g: &Gas) -> Result<(), ScenarioError> {
    let s = &sc.stop;
    let gravity = sc.gravity.iter().any(|&x| x != 0.0);
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

/// Bytes per grain of the many-grain engines: state, cells, event queue and output
/// buffers. Measured peak resident memory at `count = 10^6`: EDMD 223 (2D) and 267 (3D),
/// DSMC 211 (2D) and above 323 (3D) bytes per grain; rounded up.
fn bytes_per_grain(sc: &Scenario) -> f64 {
    if sc.dimension == 2 { 300.0 } else { 400.0 }
}

/// Available memory: `MemAvailable` of `/proc/meminfo`, else [`FALLBACK_MEMORY`].
pub fn available_memory() -> f64 {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("MemAvailable:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(FALLBACK_MEMORY, |kb| kb * 1024.0)
}

/// The grains (and DSMC cells) must fit in the available memory.
fn memory(sc: &Scenario, n: f64) -> Result<(), ScenarioError> {
    let mut need = n * bytes_per_grain(sc);
    if sc.engine == EngineKind::Dsmc
        && let Some(l) = sc.dsmc.cell_size
    {
        let cells: f64 = sc.lengths().iter().map(|x| (x / l).ceil()).product();
        need += cells * 64.0;
    }
    let have = available_memory();
    if need <= have {
        return Ok(());
    }
    let (s, _) = sc
        .species
        .iter()
        .enumerate()
        .max_by_key(|(_, sp)| sp.count)
        .unwrap_or((0, &sc.species[0]));
    Err(ScenarioError::new(
        format!("species[{s}].count"),
        format!(
            "gives {n:.3e} grains in all, which need about {} GiB (about {} bytes per grain), but {:.1} GiB are available; lower the count",
            num((need / GIB * 10.0).round() / 10.0),
            bytes_per_grain(sc),
            have / GIB
        ),
    ))
}

/// The DSMC time step must stay below the initial mean free time.
fn dsmc_step(sc: &Scenario, g: &Gas) -> Result<(), ScenarioError> {
    if sc.engine != EngineKind::Dsmc || g.omega.is_nan() || g.omega <= 0.0 {
        return Ok(());
    }
    let Some(tau) = sc.dsmc.time_step else {
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

/// Pair collisions per grain by time `t` (Haff's law for an inelastic gas without
/// gravity, ω0 t for an elastic one), and its inverse.
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
}

/// Outputs and collisions the run will cost, against [`MAX_OUTPUTS`] and
/// [`MAX_COLLISIONS`].
fn cost(sc: &Scenario, g: &Gas) -> Result<(), ScenarioError> {
    let s = &sc.stop;
    let gravity = sc.gravity.iter().any(|&x| x != 0.0);
    let e = sc.collisions.restitution;
    let d = sc.dimension as f64;
    let clock = Clock {
        omega: g.omega,
        haff: if e < 1.0 && !gravity && sc.collisions.contact_duration == 0.0 {
            2.0 * d / ((1.0 - e * e) * g.omega)
        } else {
            f64::INFINITY
        },
    };
    let moving = g.omega > 0.0 && g.omega.is_finite() && !gravity;
    // Earliest time any rule can stop the run (a lower bound), with the rule.
    let mut earliest: Vec<(f64, &str)> = Vec::new();
    let mut collisions: Vec<(f64, &str)> = Vec::new();
    if let Some(t) = s.time {
        earliest.push((t, "stop.time"));
        if moving {
            collisions.push((g.n / 2.0 * clock.per_grain(t), "stop.time"));
        }
    }
    if let Some(c) = s.collisions_per_particle {
        earliest.push((
            if moving { c / g.omega } else { 0.0 },
            "stop.collisions_per_particle",
        ));
        collisions.push((g.n * c / 2.0, "stop.collisions_per_particle"));
    }
    if let Some(c) = s.collisions {
        earliest.push((
            if moving {
                2.0 * c as f64 / (g.n * g.omega)
            } else {
                0.0
            },
            "stop.collisions",
        ));
        collisions.push((c as f64, "stop.collisions"));
    }
    if let Some(f) = s.energy_fraction {
        let t = if clock.haff.is_finite() && moving {
            clock.haff * (f.powf(-0.5) - 1.0) / 10.0
        } else {
            0.0
        };
        earliest.push((t, "stop.energy_fraction"));
        if moving && clock.haff.is_finite() {
            let per_grain = g.omega * clock.haff * -0.5 * f.ln();
            collisions.push((g.n / 2.0 * per_grain, "stop.energy_fraction"));
        }
    }
    if s.events.is_some() || s.wall_seconds.is_some() {
        earliest.push((0.0, "stop"));
        collisions.push((0.0, "stop"));
    }
    let (c, rule) = first(&collisions);
    if c.is_finite() && c > MAX_COLLISIONS {
        return Err(ScenarioError::new(
            rule,
            format!(
                "would take about {c:.3e} pair collisions ({:.0} grains, initial collision frequency {:.3e} per grain); the limit is {MAX_COLLISIONS:e} (days of computing): lower it, or bound the run with stop.events or stop.wall_seconds",
                g.n, g.omega
            ),
        ));
    }
    let (t, rule) = first(&earliest);
    let outputs = t / sc.output.interval;
    if t.is_finite() && outputs > MAX_OUTPUTS {
        return Err(ScenarioError::new(
            "output.interval",
            format!(
                "is {}: the run would write at least {outputs:.3e} outputs before {rule} can stop it (at t >= {t:.3e}); the limit is {MAX_OUTPUTS:e}: raise output.interval to at least {:.3e}",
                num(sc.output.interval),
                t / MAX_OUTPUTS
            ),
        ));
    }
    Ok(())
}

/// The smallest bound and its rule.
fn first<'a>(v: &[(f64, &'a str)]) -> (f64, &'a str) {
    v.iter().copied().fold(
        (f64::INFINITY, "stop"),
        |a, b| if b.0 < a.0 { b } else { a },
    )
}

/// The intruder's outputs: its collision rate ν ≈ ρ ⟨|v|⟩ (times the needle's length),
/// with a margin of 10, against [`MAX_OUTPUTS`].
fn intruder_outputs(sc: &Scenario) -> Result<(), ScenarioError> {
    let mean_speed = |t: f64, m: f64| (2.0 * t / (std::f64::consts::PI * m)).sqrt();
    let rate = match &sc.intruder {
        Some(IntruderSpec::Needle(c)) => {
            c.bath_density * c.length * mean_speed(c.bath_temperature, c.bath_mass)
        }
        Some(spec) => match spec.one_d() {
            Some(c) => match &c.bath {
                BathConfig::Gaussian { temperature } | BathConfig::PowerLaw { temperature } => {
                    c.bath_density * mean_speed(*temperature, c.bath_mass)
                }
                BathConfig::Tabulated { .. } => f64::INFINITY,
            },
            None => f64::INFINITY,
        },
        None => f64::INFINITY,
    };
    let s = &sc.stop;
    let mut t = f64::INFINITY;
    let mut rule = "stop.time";
    if let Some(x) = s.time {
        t = x;
    }
    if let Some(c) = s.collisions {
        let tc = c as f64 / rate / 10.0;
        if tc < t {
            (t, rule) = (tc, "stop.collisions");
        }
    }
    if s.events.is_some() || s.wall_seconds.is_some() || s.collisions_per_particle.is_some() {
        return Ok(());
    }
    let outputs = t / sc.output.interval;
    if t.is_finite() && outputs > MAX_OUTPUTS {
        return Err(ScenarioError::new(
            "output.interval",
            format!(
                "is {}: the run would write about {outputs:.3e} outputs before {rule} stops it (at t ~ {t:.3e}); the limit is {MAX_OUTPUTS:e}: raise output.interval to at least {:.3e}",
                num(sc.output.interval),
                t / MAX_OUTPUTS
            ),
        ));
    }
    Ok(())
}
