//! Grains set from outside (`Simulation::set_state`, a run started from a snapshot): the
//! engine is rebuilt around the new positions and velocities at a given time, the cell
//! sort made again from the order of the ids, and the random streams keyed by that time,
//! so that what follows depends only on that state and time, not on the history before it.

use super::{Derived, DsmcEngine, DsmcError};
use crate::random::{RESTART, derive_key};
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// The counters at a restart of the grains ([`DsmcEngine::restart`]): the collision
/// streams after it are `(seed, [DYNAMICS, step - steps, cell])` and the kicks
/// `(seed, [KICKS, k - applications, id])`, with `seed = derive_key(engine seed,
/// [RESTART, t])`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(super) struct StreamRestart {
    /// Steps before the restart.
    steps: u64,
    /// Applications of the driving before the restart.
    applications: u64,
    /// The streams' seed after it.
    seed: u64,
}

impl<const D: usize> DsmcEngine<D> {
    /// Puts every grain at `positions` with `velocities` (row-major `n × D` by grain id,
    /// lengths and length / time) and, rough grains, `angular_velocities` (`d_r` values
    /// per grain by id; empty for smooth grains) at absolute time `time`, and rebuilds what
    /// depends on them: the cell sort (from the order of the ids, as when the engine was
    /// built) and the validity warnings. The configuration, the counters (steps,
    /// collisions), the tally and the driving are kept; the TC model's memory of the last
    /// collisions starts afresh, and the random streams restart under a key of `time`
    /// ([`crate::random::RESTART`]). Two engines of the same grains restarted with the same
    /// arrays at the same time therefore continue with the same bits, whatever they did
    /// before.
    ///
    /// Refused on a decomposed engine (its grains are spread over ranks). The caller
    /// validates the arrays (lengths, finite, inside the box).
    pub(crate) fn restart(
        &mut self,
        time: f64,
        positions: &[f64],
        velocities: &[f64],
        angular_velocities: &[f64],
    ) -> Result<(), DsmcError> {
        if self.domain.is_some() {
            return Err(DsmcError::Invalid(
                "the grains of a run split over ranks cannot be set from outside".into(),
            ));
        }
        let n = self.n_global();
        if positions.len() != n * D || velocities.len() != n * D {
            return Err(DsmcError::Invalid(format!(
                "{} position and {} velocity values for {n} grains in {D} dimensions",
                positions.len(),
                velocities.len()
            )));
        }
        let r = crate::collision_law::rough::rotational_dof(D);
        let spins = if self.is_rough() { r * n } else { 0 };
        if angular_velocities.len() != spins {
            return Err(DsmcError::Invalid(format!(
                "{} angular velocity values for {n} {} grains in {D} dimensions (give {spins})",
                angular_velocities.len(),
                if self.is_rough() { "rough" } else { "smooth" }
            )));
        }
        let rows = |a: &[f64]| -> Vec<Vector<D>> {
            a.chunks_exact(D)
                .map(|c| Vector::from_slice(c).unwrap_or_default())
                .collect()
        };
        let vel = rows(velocities);
        let mass = self.mass;
        let t0 = || {
            let mut u = Vector::<D>::zero();
            for v in &vel {
                u += *v;
            }
            u = u * (1.0 / n as f64);
            mass * vel.iter().map(|v| (*v - u).norm_squared()).sum::<f64>() / (D * n) as f64
        };
        let derived = Derived::new(&self.config, &self.sim_box, n, self.radius, mass, t0)?;
        let mut pos = rows(positions);
        for x in pos.iter_mut() {
            derived.place(&self.sim_box, x)?;
        }
        let ids = (0..n as u32).collect();
        let rotation = self.inertia.map(|inertia| super::Rotation {
            inertia,
            spins: angular_velocities.to_vec(),
        });
        let mut fresh = Self::assemble(
            self.config.clone(),
            self.sim_box.clone(),
            self.radius,
            mass,
            self.seed,
            derived,
            pos,
            vel,
            ids,
            None,
            rotation,
        );
        fresh.time = time;
        fresh.steps = self.steps;
        fresh.tally = std::mem::take(&mut self.tally);
        fresh.species = self.species.clone();
        fresh.driving = self.driving.clone();
        fresh.restart = Some(StreamRestart {
            steps: self.steps,
            applications: self.driving.as_ref().map_or(0, |d| d.applications),
            seed: derive_key(self.seed, &[RESTART, time.to_bits()]),
        });
        *self = fresh;
        Ok(())
    }

    /// Sets the uniform acceleration (length / time², `D` components; empty: none) from
    /// the next step on.
    pub(crate) fn set_gravity(&mut self, gravity: &[f64]) {
        self.gravity = Vector::from_slice(gravity).unwrap_or_default();
        self.config.gravity = gravity.to_vec();
    }

    /// The seed and the step index of the collision streams of the next step.
    pub(super) fn stream_seed_and_step(&self) -> (u64, u64) {
        match self.restart {
            Some(r) => (r.seed, self.steps - r.steps),
            None => (self.seed, self.steps),
        }
    }

    /// The seed and the application index of the driving's next kicks.
    pub(crate) fn kick_seed_and_application(&self) -> (u64, u64) {
        let k = self.driving.as_ref().map_or(0, |d| d.applications);
        match self.restart {
            Some(r) => (r.seed, k - r.applications),
            None => (self.seed, k),
        }
    }
}
