//! The benchmark states of the event-driven engine, shared by `granular bench edmd`, the
//! criterion benchmark and the tests of the engine's speed paths: the standard one of the engine-performance issue (elastic
//! grains in a periodic box, an equilibrated fluid: a lattice at the target density —
//! random placement below 0.4 — melted by 5 collisions per grain), and the same with
//! walls, inelastic collisions, two kinds of grains or gravity ([`FluidCase`]).

use super::BenchError;
use crate::boundary::{AxisKind, SimulationBox};
use crate::collision_law::CollisionLaw;
use crate::edmd::init;
use crate::edmd::{Edmd, EdmdOptions};
use crate::engine::{Engine, EngineError};
use crate::particles::ParticleSet;
use crate::random::stream;
use crate::setup::{self, InitError, Region};
use crate::vector::Vector;
use serde::Serialize;
use std::time::Instant;

/// A benchmark state: `n` grains at packing fraction `packing_fraction` in a square
/// (cubic) box of side `n^(1/D)`. [`FluidCase::standard`] is the case of the
/// engine-performance issue (elastic, monodisperse, periodic); the other fields choose
/// the engine's general paths (walls, gravity, polydispersity, restitution and the TC
/// model, where the engine-performance issue asks for the same speed), so that `granular
/// bench edmd` can show what they cost.
#[derive(Clone, Debug, PartialEq)]
pub struct FluidCase {
    /// Number of grains.
    pub n: usize,
    /// Fraction of the box's volume the grains cover.
    pub packing_fraction: f64,
    /// Hard walls on every face instead of periodic boundaries.
    pub walls: bool,
    /// Restitution ξ of pair and wall collisions (walls smooth). Below 1 the TC model
    /// is on, with a contact duration of 10^-3 mean free times of the melted fluid, so
    /// that dense inelastic gases cannot collapse (section 2.3 of the hard-disk assignment).
    pub restitution: f64,
    /// Radius of the second half of the grains over the first's (a 50:50 mixture of two
    /// sizes; 1: monodisperse).
    pub size_ratio: f64,
    /// Mass of the second half of the grains over the first's.
    pub mass_ratio: f64,
    /// Acceleration of gravity along the last axis, downwards (0: none; with periodic
    /// boundaries the grains would fall forever, so use it with walls). In the units of
    /// the bench (temperature 1, the first kind's mass 1, box side `n^(1/D)`), `g` = 0.1
    /// makes the barometric height `T / (m g)` of that kind ten grain spacings.
    pub gravity: f64,
    /// Tangential restitution β of pair collisions (RS-1): -1 smooth grains (the engine's
    /// smooth path, no angular storage); above -1 rough grains with the κ of uniform disks
    /// or spheres, starting without spin once melted (walls stay smooth for the contact
    /// point, `e_t = 1`).
    pub tangential_restitution: f64,
}

impl FluidCase {
    /// Elastic, monodisperse grains in a periodic box: the engine-performance issue's case.
    pub fn standard(n: usize, packing_fraction: f64) -> Self {
        Self {
            n,
            packing_fraction,
            walls: false,
            restitution: 1.0,
            size_ratio: 1.0,
            mass_ratio: 1.0,
            gravity: 0.0,
            tangential_restitution: -1.0,
        }
    }

    /// Whether this is [`FluidCase::standard`].
    pub fn is_standard(&self) -> bool {
        *self == Self::standard(self.n, self.packing_fraction)
    }
}

/// `n` elastic grains at packing fraction `phi` in a periodic cube of side `n^(1/D)`,
/// melted by 5 collisions per grain: [`fluid`] of [`FluidCase::standard`].
pub fn equilibrated_fluid<const D: usize>(
    n: usize,
    phi: f64,
    seed: u64,
) -> Result<Edmd<D>, BenchError> {
    fluid(&FluidCase::standard(n, phi), seed)
}

/// The state of `case`, melted by 5 collisions per grain with elastic collisions, then
/// given the case's restitution.
///
/// Placement: random below packing fraction 0.4; above, a square (cubic) lattice at the
/// target density, or, where the grains do not fit on it (two sizes, walls), a lattice of
/// shrunken grains compressed to the target ([`init::compress`]). Velocities:
/// Maxwell-Boltzmann at temperature 1, without drift. With two sizes or masses, grain `i`
/// belongs to the second species for odd `i`.
pub fn fluid<const D: usize>(case: &FluidCase, seed: u64) -> Result<Edmd<D>, BenchError> {
    let &FluidCase {
        n,
        packing_fraction: phi,
        walls,
        restitution,
        size_ratio,
        mass_ratio,
        gravity,
        tangential_restitution,
    } = case;
    let side = (n as f64).powf(1.0 / D as f64);
    let kind = if walls {
        AxisKind::Wall
    } else {
        AxisKind::Periodic
    };
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
    // Mean grain volume phi V / n = v(r) (1 + size_ratio^D) / 2.
    let mean = (1.0 + size_ratio.powi(D as i32)) / 2.0;
    let r =
        (phi * bx.volume() / (n as f64 * mean * setup::ball_volume::<D>(1.0))).powf(1.0 / D as f64);
    let second = |i: usize| i % 2 == 1;
    let radii: Vec<f64> = (0..n)
        .map(|i| if second(i) { r * size_ratio } else { r })
        .collect();
    let masses: Vec<f64> = (0..n)
        .map(|i| if second(i) { mass_ratio } else { 1.0 })
        .collect();
    let (species, species_names): (Vec<u32>, Vec<String>) =
        if size_ratio == 1.0 && mass_ratio == 1.0 {
            (vec![0; n], vec!["grain".into()])
        } else {
            let species = (0..n).map(|i| second(i) as u32).collect();
            (species, vec!["first".into(), "second".into()])
        };
    let mut rng = stream(seed, &[0]);
    let region = Region::whole(&bx);
    let positions = if phi < 0.4 {
        setup::random_placement(&bx, &region, &radii, &[], &mut rng, 100_000)?
    } else {
        match setup::lattice_placement(&bx, &region, &radii) {
            Ok(p) => p,
            Err(InitError::Lattice {
                radius, spacing, ..
            }) => {
                // Shrunken grains on the lattice, grown back by compression.
                let shrink = 0.95 * spacing / (2.0 * radius);
                let small: Vec<f64> = radii.iter().map(|r| r * shrink).collect();
                let start = ParticleSet {
                    positions: setup::lattice_placement(&bx, &region, &small)?,
                    velocities: vec![Vector::zero(); n],
                    radii: small,
                    masses: masses.clone(),
                    species: species.clone(),
                    species_names: species_names.clone(),
                    ..Default::default()
                };
                init::compress(&bx, start, &radii, &mut rng)?
            }
            Err(e) => return Err(e.into()),
        }
    };
    let mut velocities = setup::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    setup::remove_drift(&mut velocities, &masses);
    let set = ParticleSet {
        positions,
        velocities,
        radii,
        masses,
        species,
        species_names,
        ..Default::default()
    };
    let mut options = EdmdOptions::default();
    if gravity != 0.0 {
        options.gravity = vec![0.0; D];
        options.gravity[D - 1] = -gravity;
    }
    let mut e = Edmd::new(bx, set, CollisionLaw::default(), options);
    advance_collisions(&mut e, 5 * n as u64 / 2)?;
    if restitution != 1.0 || tangential_restitution != -1.0 {
        e.set_collision_law(CollisionLaw {
            restitution,
            wall_restitution: restitution,
            wall_tangential_restitution: 1.0,
            contact_duration: if restitution != 1.0 {
                1e-3 * e.mean_free_time_so_far()
            } else {
                0.0
            },
            tangential_restitution,
            ..CollisionLaw::default()
        });
    }
    Ok(e)
}

/// Advances until `collisions` more pair collisions have happened.
pub fn advance_collisions<const D: usize>(
    e: &mut Edmd<D>,
    collisions: u64,
) -> Result<(), EngineError> {
    let target = e.collisions() + collisions;
    let mut t = e.time();
    while e.collisions() < target {
        t += 0.05;
        e.advance(t, u64::MAX)?;
    }
    Ok(())
}

/// One standard case of the engine-performance issue with the speed of the fastest public
/// event-driven code on this machine kind (Smallenburg, Eur. Phys. J. E 45, 22 (2022),
/// and its 2D port).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandardCase {
    /// 2 or 3.
    pub dimension: usize,
    /// Number of grains.
    pub n: usize,
    /// Packing fraction.
    pub packing_fraction: f64,
    /// Collisions per CPU second of the reference code (NaN: none).
    pub reference: f64,
}

const fn standard(
    dimension: usize,
    n: usize,
    packing_fraction: f64,
    reference: f64,
) -> StandardCase {
    StandardCase {
        dimension,
        n,
        packing_fraction,
        reference,
    }
}

/// The standard cases, in the order `granular bench edmd` runs them.
pub const CASES: &[StandardCase] = &[
    standard(2, 10_000, 0.7, 1.3e6),
    standard(2, 100_000, 0.7, 5.0e5),
    standard(2, 1_000_000, 0.7, 3.5e5),
    standard(2, 10_000, 0.2, 5.2e5),
    standard(3, 100_000, 0.45, 2.6e5),
    standard(3, 1_000_000, 0.45, 1.8e5),
];

/// The standard cases that match every given filter; where none does, exactly the case
/// asked for (2D, 10^4 grains and packing fraction 0.5 where not given), without a
/// reference.
pub fn select_cases(
    dimension: Option<usize>,
    n: Option<usize>,
    packing_fraction: Option<f64>,
) -> Vec<StandardCase> {
    let cases: Vec<StandardCase> = CASES
        .iter()
        .copied()
        .filter(|c| dimension.is_none_or(|d| d == c.dimension))
        .filter(|c| n.is_none_or(|n| n == c.n))
        .filter(|c| packing_fraction.is_none_or(|p| (p - c.packing_fraction).abs() < 1e-9))
        .collect();
    if cases.is_empty() {
        return vec![standard(
            dimension.unwrap_or(2),
            n.unwrap_or(10_000),
            packing_fraction.unwrap_or(0.5),
            f64::NAN,
        )];
    }
    cases
}

/// Peak bytes per grain of the event-driven bench (set-up included; about 300 measured
/// for 10^5 grains in 3D), for the memory check before allocating.
pub const BYTES_PER_GRAIN: f64 = 400.0;

/// One measurement of [`measure`] (`granular bench edmd`, one JSON object per case).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// `"edmd"`.
    pub engine: &'static str,
    /// 2 or 3.
    pub dimension: usize,
    /// Number of grains.
    pub n: usize,
    /// Packing fraction.
    pub packing_fraction: f64,
    /// Pair collisions timed.
    pub collisions: u64,
    /// Wall seconds of the timed part.
    pub seconds: f64,
    /// CPU seconds of the timed part (NaN where the system does not say).
    pub cpu_seconds: f64,
    /// Collisions per CPU second (per wall second where the CPU clock is unavailable).
    pub collisions_per_second: f64,
    /// Events per CPU second.
    pub events_per_second: f64,
    /// The engine's memory per grain.
    pub bytes_per_particle: f64,
    /// See [`FluidCase::walls`].
    pub walls: bool,
    /// See [`FluidCase::restitution`].
    pub restitution: f64,
    /// See [`FluidCase::size_ratio`].
    pub size_ratio: f64,
    /// See [`FluidCase::mass_ratio`].
    pub mass_ratio: f64,
    /// See [`FluidCase::gravity`].
    pub gravity: f64,
    /// See [`FluidCase::tangential_restitution`].
    pub tangential_restitution: f64,
    /// Wall seconds to build and melt the fluid.
    pub setup_seconds: f64,
    /// Worker threads (the engine is sequential: 1).
    pub threads: usize,
    /// The reference code's collisions per CPU second, for a standard case.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_collisions_per_second: Option<f64>,
}

/// Times `case` in `dimension` dimensions: builds and melts the fluid ([`fluid`], seed
/// 2024), then advances it by `collisions_per_particle` collisions per grain on the
/// calling thread. `reference` (the [`StandardCase`]'s) is kept for the standard case only.
pub fn measure(
    dimension: usize,
    case: &FluidCase,
    collisions_per_particle: f64,
    reference: f64,
) -> Result<Measurement, BenchError> {
    let mut m = match dimension {
        2 => measure_in::<2>(case, collisions_per_particle),
        3 => measure_in::<3>(case, collisions_per_particle),
        d => Err(BenchError::Dimension(d)),
    }?;
    if case.is_standard() && reference.is_finite() {
        m.reference_collisions_per_second = Some(reference);
    }
    Ok(m)
}

fn measure_in<const D: usize>(c: &FluidCase, cpp: f64) -> Result<Measurement, BenchError> {
    let (n, phi) = (c.n, c.packing_fraction);
    let setup = Instant::now();
    let mut e = fluid::<D>(c, 2024)?;
    let setup_seconds = setup.elapsed().as_secs_f64();
    let (c0, ev0) = (e.collisions(), e.events());
    let start = Instant::now();
    let cpu_start = super::thread_cpu_seconds();
    advance_collisions(&mut e, (cpp * n as f64 / 2.0) as u64)?;
    let cpu = super::thread_cpu_seconds() - cpu_start;
    let wall = start.elapsed().as_secs_f64();
    // Rates per CPU second (per wall second where the CPU clock is unavailable).
    let secs = if cpu.is_finite() && cpu > 0.0 {
        cpu
    } else {
        wall
    };
    let collisions = e.collisions() - c0;
    let events = e.events() - ev0;
    Ok(Measurement {
        engine: "edmd",
        dimension: D,
        n,
        packing_fraction: phi,
        collisions,
        seconds: wall,
        cpu_seconds: cpu,
        collisions_per_second: collisions as f64 / secs,
        events_per_second: events as f64 / secs,
        bytes_per_particle: e.memory_bytes() as f64 / n as f64,
        walls: c.walls,
        restitution: c.restitution,
        size_ratio: c.size_ratio,
        mass_ratio: c.mass_ratio,
        gravity: c.gravity,
        tangential_restitution: c.tangential_restitution,
        setup_seconds,
        threads: 1,
        reference_collisions_per_second: None,
    })
}
