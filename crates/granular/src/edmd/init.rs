//! Compression of an initial state to high densities with the event engine itself
//! (Lubachevsky-Stillinger). Placements and velocities are shared by every engine and live
//! in `crate::setup`; they are re-exported here so that `edmd::init::...` paths keep
//! working.

use super::engine::{Edmd, EdmdOptions};
use crate::boundary::SimulationBox;
use crate::collision_law::CollisionLaw;
use crate::engine::{Engine, Progress};
use crate::particles::ParticleSet;
use crate::random::Stream;
use crate::vector::Vector;

pub use crate::setup::{
    InitError, Region, ball_volume, fixed_speed, lattice_placement, maxwell_boltzmann,
    packing_fraction, random_placement, remove_drift,
};

/// Lubachevsky-Stillinger compression: the grains, given at radii `radii * scale^-1`
/// (non-overlapping), grow uniformly with the event engine itself until their radii reach
/// `radii`. Velocities are rescaled to temperature 1 every collision per grain (growth
/// heats the gas). Returns positions at the end; velocities are left to the caller.
pub fn compress<const D: usize>(
    bx: &SimulationBox<D>,
    mut particles: ParticleSet<D>,
    final_radii: &[f64],
    rng: &mut Stream,
) -> Result<Vec<Vector<D>>, InitError> {
    let n = particles.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let scale = final_radii[0] / particles.radii[0];
    let target = packing_fraction::<D>(final_radii, bx.volume());
    particles.velocities = maxwell_boltzmann::<D>(&particles.masses, 1.0, rng);
    remove_drift(&mut particles.velocities, &particles.masses);
    let r_max = particles.radii.iter().cloned().fold(0.0, f64::max);
    let m_min = particles
        .masses
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    // Contact distances grow at 2% of the thermal speed: slow enough to stay near
    // equilibrium, fast enough to take a few hundred collisions per grain.
    let growth = 0.01 * (1.0 / m_min).sqrt() / r_max;
    let t_final = (scale - 1.0) / growth;
    let mut engine = Edmd::with_growth(
        bx.clone(),
        particles,
        CollisionLaw::default(),
        EdmdOptions::default(),
        growth,
        scale,
    );
    let chunk = n as u64;
    let budget = 20_000 * n as u64 + 1_000_000;
    let mut used = 0u64;
    loop {
        let progress = engine
            .advance(t_final, chunk)
            .map_err(|_| InitError::Jammed {
                reached: packing_fraction::<D>(&engine.radii(), bx.volume()),
                target,
            })?;
        used += chunk;
        let k = engine.kinetic_energy_now();
        let t_now = 2.0 * k / (D as f64 * n as f64);
        if t_now > 0.0 {
            engine.scale_velocities((1.0 / t_now).sqrt());
        }
        if progress == Progress::Reached {
            break;
        }
        if used > budget {
            return Err(InitError::Jammed {
                reached: packing_fraction::<D>(&engine.radii(), bx.volume()),
                target,
            });
        }
    }
    engine.freeze_growth();
    Ok(engine.particle_set().positions)
}
