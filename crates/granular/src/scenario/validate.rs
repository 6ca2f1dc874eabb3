//! Validation of the shared tables, one function per table. Every error names the key, the
//! value and the fix; the limits are documented in `docs/scenario.md` ("Limits").

use super::{EngineKind, Scenario, ScenarioError};
use crate::boundary::AxisKind;

/// Largest magnitude of a dimensional number (length, mass, speed, temperature, time,
/// acceleration), and the inverse of the smallest non-zero one: squares and products of
/// two or three such numbers stay finite and normal in `f64`.
pub(crate) const MAGNITUDE: f64 = 1e100;
/// Most bins of a speed or impact-parameter histogram.
pub(crate) const MAX_BINS: usize = 100_000;
/// Most outputs per decade of time (`output.per_decade`).
pub(crate) const MAX_PER_DECADE: u32 = 10_000;
/// Largest `output.histogram_max_speed` (in units of the initial r.m.s. speed).
pub(crate) const MAX_HISTOGRAM_SPEED: f64 = 1000.0;

/// `x` as written in a message: plain in [1e-4, 1e15), else in scientific notation (a
/// 1e-300 box edge prints as `1e-300`, not as 300 zeros).
pub(super) fn num(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` must be finite, positive and within [1/MAGNITUDE, MAGNITUDE].
pub(super) fn positive(key: &str, x: f64, what: &str) -> Result<(), ScenarioError> {
    if !(x > 0.0 && x.is_finite()) {
        return Err(ScenarioError::new(
            key,
            format!("is {}; {what} must be positive and finite", num(x)),
        ));
    }
    in_range(key, x, what)
}

/// `x` must be finite, `>= 0` and at most MAGNITUDE (and not below 1/MAGNITUDE unless 0).
pub(super) fn non_negative(key: &str, x: f64, what: &str) -> Result<(), ScenarioError> {
    if !(x >= 0.0 && x.is_finite()) {
        return Err(ScenarioError::new(
            key,
            format!("is {}; {what} must be finite and >= 0", num(x)),
        ));
    }
    in_range(key, x, what)
}

/// `x` must be finite and of magnitude at most MAGNITUDE (0 allowed).
pub(super) fn finite(key: &str, x: f64, what: &str) -> Result<(), ScenarioError> {
    if !x.is_finite() {
        return Err(ScenarioError::new(
            key,
            format!("is {}; {what} must be a finite number", num(x)),
        ));
    }
    in_range(key, x, what)
}

fn in_range(key: &str, x: f64, what: &str) -> Result<(), ScenarioError> {
    let a = x.abs();
    if a != 0.0 && !(1.0 / MAGNITUDE..=MAGNITUDE).contains(&a) {
        return Err(ScenarioError::new(
            key,
            format!(
                "is {}; {what} must lie between 1e-100 and 1e100 in magnitude (or be 0 where 0 is allowed), so that its squares and products stay finite; change the units",
                num(x)
            ),
        ));
    }
    Ok(())
}

/// A coefficient of restitution in [0, 1].
pub(super) fn unit_interval(key: &str, v: f64) -> Result<(), ScenarioError> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(ScenarioError::new(
            key,
            format!(
                "is {v}; a restitution coefficient must lie in [0, 1] (1 = elastic, 0 = perfectly inelastic)"
            ),
        ))
    }
}

/// `dimension`.
pub(super) fn dimension(sc: &Scenario) -> Result<(), ScenarioError> {
    let d = sc.dimension;
    if d != 2 && d != 3 {
        return Err(ScenarioError::new(
            "dimension",
            format!("is {d}; use 2 (disks) or 3 (spheres)"),
        ));
    }
    Ok(())
}

/// `[box]`: one positive length and one boundary kind per axis.
pub(super) fn simulation_box(sc: &Scenario) -> Result<(), ScenarioError> {
    let d = sc.dimension;
    let lengths = sc.lengths();
    if lengths.len() != d {
        return Err(ScenarioError::new(
            "box.lengths",
            format!(
                "has {} entries for dimension {d}; give one length per axis",
                lengths.len()
            ),
        ));
    }
    for (k, &l) in lengths.iter().enumerate() {
        positive(&format!("box.lengths[{k}]"), l, "a box length")?;
    }
    if sc.axes().len() != d {
        return Err(ScenarioError::new(
            "box.boundary",
            format!(
                "lists {} axes for dimension {d}; give one per axis or a single \"wall\"/\"periodic\"",
                sc.axes().len()
            ),
        ));
    }
    Ok(())
}

/// `[collisions]`.
pub(super) fn collisions(sc: &Scenario) -> Result<(), ScenarioError> {
    let c = &sc.collisions();
    unit_interval("collisions.restitution", c.restitution)?;
    if let Some(w) = c.wall_restitution {
        unit_interval("collisions.wall_restitution", w)?;
    }
    // Rough grains: a factor on the contact point's tangential velocity, checked with the
    // other rough keys (scenario::rough).
    if let Some(w) = c.wall_tangential_restitution
        && !c.law().is_rough()
    {
        unit_interval("collisions.wall_tangential_restitution", w)?;
    }
    non_negative(
        "collisions.contact_duration",
        c.contact_duration,
        "the TC contact duration t_c (0 disables the TC model)",
    )
}

/// `gravity`: one finite component per axis, none along a periodic axis (in a fully
/// periodic box the centre of mass would accelerate for ever).
pub(super) fn gravity(sc: &Scenario) -> Result<(), ScenarioError> {
    let d = sc.dimension;
    if sc.gravity().is_empty() {
        return Ok(());
    }
    if sc.gravity().len() != d {
        return Err(ScenarioError::new(
            "gravity",
            format!(
                "has {} components; give {d} (one per axis) or leave it out",
                sc.gravity().len()
            ),
        ));
    }
    for (k, &g) in sc.gravity().iter().enumerate() {
        finite(&format!("gravity[{k}]"), g, "a gravity component")?;
    }
    let pulls_along_periodic = sc
        .gravity()
        .iter()
        .zip(sc.axes())
        .any(|(&g, a)| g != 0.0 && a == AxisKind::Periodic);
    if pulls_along_periodic {
        return Err(ScenarioError::new(
            "gravity",
            format!(
                "is {:?} along a periodic axis: nothing stops the fall, so the centre of mass accelerates for ever; put walls on that axis (box.boundary) or remove gravity",
                sc.gravity()
            ),
        ));
    }
    Ok(())
}

/// `[initial]`: `compress_from` in (0, target) and at least one placement attempt.
pub(super) fn initial(sc: &Scenario) -> Result<(), ScenarioError> {
    if sc.initial().max_attempts == 0 {
        return Err(ScenarioError::new(
            "initial.max_attempts",
            "is 0; give the random placement attempts per grain, e.g. 100000",
        ));
    }
    let Some(p) = sc.initial().compress_from else {
        return Ok(());
    };
    if !(p > 0.0 && p < 1.0) {
        return Err(ScenarioError::new(
            "initial.compress_from",
            format!("is {p}; give the packing fraction to start the compression from, in (0, 1)"),
        ));
    }
    let target = target_packing_fraction(sc);
    if p >= target {
        return Err(ScenarioError::new(
            "initial.compress_from",
            format!(
                "is {p}, not below the packing fraction of the grains ({target:.4}): there is nothing to compress; give a smaller value or remove it"
            ),
        ));
    }
    Ok(())
}

/// Packing fraction of all grains at their radii in the box (KT-2).
pub(super) fn target_packing_fraction(sc: &Scenario) -> f64 {
    let volume: f64 = sc.lengths().iter().product();
    crate::theory::kinetic::mixture_packing_fraction(
        sc.dimension,
        (0..sc.species().len()).map(|s| (sc.species()[s].count, sc.radius(s))),
        volume,
    )
}

/// `[stop]`: each rule in its range (the reachability is checked by `preflight`).
pub(super) fn stop(sc: &Scenario) -> Result<(), ScenarioError> {
    let s = &sc.stop;
    if let Some(t) = s.time {
        positive("stop.time", t, "the simulation time to stop at")?;
    }
    if let Some(c) = s.collisions_per_particle {
        positive(
            "stop.collisions_per_particle",
            c,
            "the collisions per grain to stop at",
        )?;
    }
    if let Some(w) = s.wall_seconds {
        positive(
            "stop.wall_seconds",
            w,
            "the wall-clock seconds to stop after",
        )?;
    }
    if s.events == Some(0) {
        return Err(ScenarioError::new(
            "stop.events",
            "is 0: the run would stop before it starts; give at least 1 or leave it out",
        ));
    }
    if s.collisions == Some(0) {
        return Err(ScenarioError::new(
            "stop.collisions",
            "is 0: the run would stop before it starts; give at least 1 or leave it out",
        ));
    }
    if let Some(f) = s.energy_fraction
        && !(f > 0.0 && f < 1.0)
    {
        return Err(ScenarioError::new(
            "stop.energy_fraction",
            format!("is {f}; give the fraction of the initial energy at which to stop, in (0, 1)"),
        ));
    }
    let any = s.time.is_some()
        || s.collisions.is_some()
        || s.collisions_per_particle.is_some()
        || s.events.is_some()
        || s.energy_fraction.is_some()
        || s.wall_seconds.is_some();
    if !any {
        let rules = if sc.kind() == EngineKind::Intruder {
            "stop.collisions (e.g. 500000, the paper's statistics) or stop.time"
        } else {
            "at least one of time, collisions, collisions_per_particle, events, energy_fraction, wall_seconds"
        };
        return Err(ScenarioError::new(
            "stop",
            format!("has no rule; set {rules}"),
        ));
    }
    Ok(())
}

/// `[output]`: the interval, the histograms, the checkpoints and the observables.
pub(super) fn output(sc: &Scenario) -> Result<(), ScenarioError> {
    let o = &sc.output;
    positive(
        "output.interval",
        o.interval,
        "the time between outputs (with spacing = \"log\": the first output time)",
    )?;
    if !(1..=MAX_PER_DECADE).contains(&o.per_decade) {
        return Err(ScenarioError::new(
            "output.per_decade",
            format!(
                "is {}; give the outputs per decade of time of spacing = \"log\", 1 to {MAX_PER_DECADE} (default 10)",
                o.per_decade
            ),
        ));
    }
    let c = o.checkpoint_seconds;
    if c.is_nan() || c <= 0.0 || (c.is_finite() && c < 1.0 / MAGNITUDE) {
        return Err(ScenarioError::new(
            "output.checkpoint_seconds",
            format!(
                "is {}; give the wall-clock seconds between checkpoints, a positive number (default 60; inf: never; a tiny value such as 1e-9 checkpoints after every chunk of events)",
                num(c)
            ),
        ));
    }
    trajectory(sc)?;
    if let Some(t) = o.equilibration_time {
        non_negative(
            "output.equilibration_time",
            t,
            "the time before the time series enters the summary's averages",
        )?;
    }
    if sc.kind() == EngineKind::Intruder {
        return Ok(());
    }
    if o.histogram_bins == 0 || o.histogram_bins > MAX_BINS {
        return Err(ScenarioError::new(
            "output.histogram_bins",
            format!("is {}; use between 1 and {MAX_BINS}", o.histogram_bins),
        ));
    }
    let h = o.histogram_max_speed;
    if !(h > 0.0 && h <= MAX_HISTOGRAM_SPEED) {
        return Err(ScenarioError::new(
            "output.histogram_max_speed",
            format!(
                "is {h}; give the histogram's upper edge in units of the initial r.m.s. speed, in (0, {MAX_HISTOGRAM_SPEED}] (default 3.5)"
            ),
        ));
    }
    non_negative(
        "output.equilibration_collisions_per_particle",
        o.equilibration_collisions_per_particle,
        "the collisions per grain before the equilibrium histogram",
    )?;
    non_negative(
        "output.histogram_sample_spacing",
        o.histogram_sample_spacing,
        "the collisions per grain between histogram samples",
    )?;
    if o.histogram_sample_spacing == 0.0 {
        // Every output pooled: snapshots a fraction of a collision apart repeat the same
        // speeds, and the Maxwell-Boltzmann test would count them as independent.
        return Err(ScenarioError::new(
            "output.histogram_sample_spacing",
            "is 0; the pooled speeds must come from snapshots at least some collisions per grain \
             apart to be independent samples (appendix C.2 of the hard-disk assignment); give a \
             spacing above 0, e.g. 5 (the default)",
        ));
    }
    o.validate_observables(sc.dimension)?;
    super::observables::validate_structure_and_transport(sc)
}

/// `[dsmc]`: positive, finite step and cell (their size against the gas is checked by
/// `preflight`).
pub(super) fn dsmc(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(spec) = sc.dsmc() else {
        return Ok(());
    };
    if let Some(bins) = spec.impact_bins
        && (bins == 0 || bins > MAX_BINS)
    {
        return Err(ScenarioError::new(
            "dsmc.impact_bins",
            format!("is {bins}; use between 1 and {MAX_BINS} bins (default 20)"),
        ));
    }
    if spec.balance_every == Some(0) {
        return Err(ScenarioError::new(
            "dsmc.balance_every",
            "is 0; give the steps between two looks at the ranks' loads, at least 1 \
             (default 20), or dsmc.balance = \"off\" for fixed cuts"
                .to_string(),
        ));
    }
    // Species of equal grains (names, counts, regions, placements and velocities may
    // differ): DSMC's collision rule here is that of one radius and one mass.
    for s in 1..sc.species().len() {
        let (r0, r) = (sc.radius(0), sc.radius(s));
        if r != r0 {
            return Err(ScenarioError::new(
                format!("species[{s}]"),
                format!(
                    "has radius {} but species[0] has {}: the DSMC engine takes species of \
                     equal grains (one radius, one mass); give every species the same radius \
                     (or use engine = \"edmd\" for a mixture)",
                    num(r),
                    num(r0)
                ),
            ));
        }
        let (m0, m) = (sc.species()[0].mass, sc.species()[s].mass);
        if m != m0 {
            return Err(ScenarioError::new(
                format!("species[{s}].mass"),
                format!(
                    "is {} but species[0].mass is {}: the DSMC engine takes species of equal \
                     grains (one radius, one mass); give every species the same mass (or use \
                     engine = \"edmd\" for a mixture)",
                    num(m),
                    num(m0)
                ),
            ));
        }
    }
    if sc.initial().compress_from.is_some() {
        return Err(ScenarioError::new(
            "initial.compress_from",
            "does not apply to the DSMC engine: its grains are placed independently of each \
             other (they may overlap: DSMC has no excluded volume in its free flight), so \
             there is nothing to compress; remove the key"
                .to_string(),
        ));
    }
    if let Some(t) = spec.time_step {
        positive(
            "dsmc.time_step",
            t,
            "the time step (well below the mean free time)",
        )?;
    }
    if let Some(l) = spec.cell_size {
        positive(
            "dsmc.cell_size",
            l,
            "the cell edge (below the mean free path)",
        )?;
    }
    Ok(())
}

/// `[edmd]`: the collapse threshold and the impact-parameter bins.
pub(super) fn edmd(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(e) = sc.edmd() else {
        return Ok(());
    };
    if !(e.collapse_ratio > 0.0 && e.collapse_ratio < 1.0) {
        return Err(ScenarioError::new(
            "edmd.collapse_ratio",
            format!(
                "is {}; give the inelastic-collapse threshold in (0, 1) (default 1e-6)",
                e.collapse_ratio
            ),
        ));
    }
    if e.impact_bins == 0 || e.impact_bins > MAX_BINS {
        return Err(ScenarioError::new(
            "edmd.impact_bins",
            format!(
                "is {}; use between 1 and {MAX_BINS} bins (default 20)",
                e.impact_bins
            ),
        ));
    }
    Ok(())
}

/// `[crater]`: a species of the scenario and a positive displacement.
pub(super) fn crater(sc: &Scenario) -> Result<(), ScenarioError> {
    let Some(c) = &sc.crater() else {
        return Ok(());
    };
    if !sc.species().iter().any(|s| s.name == c.species) {
        return Err(ScenarioError::new(
            "crater.species",
            format!(
                "\"{}\" is not a species of this scenario; use one of the [[species]] names",
                c.species
            ),
        ));
    }
    positive(
        "crater.displacement",
        c.displacement,
        "the displacement threshold",
    )
}

/// `output.trajectory`: each format once, and only for the engines with grains.
fn trajectory(sc: &Scenario) -> Result<(), ScenarioError> {
    let formats = &sc.output.trajectory;
    if sc.kind() == EngineKind::Intruder && !formats.is_empty() {
        return Err(ScenarioError::new(
            "output.trajectory",
            "is set, but the intruder engine has no grain trajectories (one intruder in a bath that is not simulated grain by grain); remove output.trajectory",
        ));
    }
    for (k, f) in formats.iter().enumerate() {
        if formats[..k].contains(f) {
            return Err(ScenarioError::new(
                "output.trajectory",
                format!("lists \"{}\" twice; give each format once", f.name()),
            ));
        }
    }
    Ok(())
}
