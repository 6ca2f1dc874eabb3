//! The benchmark states of the event-driven engine, shared by `granular bench edmd` and
//! the criterion benchmark: the standard one of the engine-performance issue (elastic
//! grains in a periodic box, an equilibrated fluid: a lattice at the target density —
//! random placement below 0.4 — melted by 5 collisions per grain), and the same with
//! walls, inelastic collisions, two kinds of grains or gravity ([`FluidCase`]).

use super::init;
use super::{Edmd, EdmdOptions};
use crate::boundary::{AxisKind, SimulationBox};
use crate::collision_law::CollisionLaw;
use crate::engine::{Engine, EngineError};
use crate::particles::ParticleSet;
use crate::random::stream;
use crate::setup::{self, InitError, Region};
use crate::vector::Vector;

/// Why the benchmark state could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// Placement failed.
    #[error(transparent)]
    Init(#[from] InitError),
    /// The engine failed while melting.
    #[error(transparent)]
    Engine(#[from] EngineError),
}

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
    /// that dense inelastic gases cannot collapse (section 2.3 of the hard-disk seed).
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
    };
    let mut options = EdmdOptions::default();
    if gravity != 0.0 {
        options.gravity = vec![0.0; D];
        options.gravity[D - 1] = -gravity;
    }
    let mut e = Edmd::new(bx, set, CollisionLaw::default(), options);
    advance_collisions(&mut e, 5 * n as u64 / 2)?;
    if restitution != 1.0 {
        e.set_collision_law(CollisionLaw {
            restitution,
            wall_restitution: restitution,
            wall_tangential_restitution: 1.0,
            contact_duration: 1e-3 * e.mean_free_time_so_far(),
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
