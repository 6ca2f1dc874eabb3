//! The standard benchmark state of the event-driven engine, shared by `granular bench
//! edmd` and the criterion benchmark: elastic grains in a periodic box, an equilibrated
//! fluid (lattice at the target density — random placement below 0.4 — melted by 5
//! collisions per grain).

use super::init::{self, InitError, Region};
use super::{Edmd, EdmdOptions, ParticleSet};
use crate::boundary::{AxisKind, SimulationBox};
use crate::collision_law::CollisionLaw;
use crate::engine::{Engine, EngineError};
use crate::random::stream;
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

/// `n` elastic grains at packing fraction `phi` in a periodic cube of side `n^(1/D)`,
/// melted by 5 collisions per grain.
pub fn equilibrated_fluid<const D: usize>(
    n: usize,
    phi: f64,
    seed: u64,
) -> Result<Edmd<D>, BenchError> {
    let side = (n as f64).powf(1.0 / D as f64);
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), AxisKind::Periodic);
    let r = (phi * bx.volume() / (n as f64 * init::ball_volume::<D>(1.0))).powf(1.0 / D as f64);
    let radii = vec![r; n];
    let mut rng = stream(seed, &[0]);
    let positions = if phi < 0.4 {
        init::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 100_000)?
    } else {
        init::lattice_placement(&bx, &Region::whole(&bx), &radii)?
    };
    let masses = vec![1.0; n];
    let mut velocities = init::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    init::remove_drift(&mut velocities, &masses);
    let set = ParticleSet {
        positions,
        velocities,
        radii,
        masses,
        species: vec![0; n],
        species_names: vec!["grain".into()],
    };
    let mut e = Edmd::new(bx, set, CollisionLaw::default(), EdmdOptions::default());
    advance_collisions(&mut e, 5 * n as u64 / 2)?;
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
