//! The velocity moments of the DSMC gas: mean velocity, momentum, temperature, `a2`,
//! kinetic energy and the check for non-finite velocities. Every sum runs over fixed
//! chunks of [`SUM_CHUNK`] particles of the storage order, then over the chunks in order,
//! so its bits do not depend on the number of threads; a decomposed engine reduces them
//! over the ranks in the same order (`Domain::ordered_fold`).

use super::DsmcEngine;
use crate::dsmc::sums::SUM_CHUNK;
use crate::vector::Vector;
use rayon::prelude::*;

impl<const D: usize> DsmcEngine<D> {
    /// Mean velocity (deterministic chunked sum).
    pub fn mean_velocity(&self) -> Vector<D> {
        if let Some(d) = &self.domain {
            return self.mean_velocity_decomposed(d);
        }
        let parts: Vec<Vector<D>> = self
            .grains
            .vel
            .par_chunks(SUM_CHUNK)
            .map(|c| c.iter().fold(Vector::zero(), |a, v| a + *v))
            .collect();
        let s = parts.into_iter().fold(Vector::zero(), |a, v| a + v);
        s * (1.0 / self.grains.vel.len() as f64)
    }

    /// Total momentum `m sum_i v_i`.
    pub fn momentum(&self) -> Vector<D> {
        self.mean_velocity() * (self.mass * self.n_global() as f64)
    }

    /// Moments `(<c^2>, <c^4>)` of the peculiar velocity `c = v - u`.
    pub(super) fn peculiar_moments(&self) -> (f64, f64) {
        let u = self.mean_velocity();
        if let Some(d) = &self.domain {
            let (s2, s4) = self.peculiar_sums_decomposed(d, u);
            let n = d.n_global as f64;
            return (s2 / n, s4 / n);
        }
        let parts: Vec<(f64, f64)> = self
            .grains
            .vel
            .par_chunks(SUM_CHUNK)
            .map(|c| {
                c.iter().fold((0.0, 0.0), |(a, b), v| {
                    let c2 = (*v - u).norm_squared();
                    (a + c2, b + c2 * c2)
                })
            })
            .collect();
        let (s2, s4) = parts
            .into_iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let n = self.grains.vel.len() as f64;
        (s2 / n, s4 / n)
    }

    /// Granular temperature `T = m <|v - u|^2> / D`.
    pub fn temperature(&self) -> f64 {
        self.mass * self.peculiar_moments().0 / D as f64
    }

    /// Fourth cumulant `a2 = D/(D+2) <c^4>/<c^2>^2 - 1` of the peculiar velocity.
    pub fn a2(&self) -> f64 {
        let (c2, c4) = self.peculiar_moments();
        D as f64 / (D as f64 + 2.0) * c4 / (c2 * c2) - 1.0
    }

    /// Total kinetic energy `m/2 sum_i |v_i|^2` (deterministic chunked sum).
    pub fn kinetic_energy_now(&self) -> f64 {
        if let Some(d) = &self.domain {
            return 0.5 * self.mass * self.speed_squares_decomposed(d);
        }
        let parts: Vec<f64> = self
            .grains
            .vel
            .par_chunks(SUM_CHUNK)
            .map(|c| c.iter().map(|v| v.norm_squared()).sum::<f64>())
            .collect();
        0.5 * self.mass * parts.into_iter().sum::<f64>()
    }

    /// The identity of a particle whose velocity has a non-finite component (the smallest
    /// such identity), or `None` when every velocity is finite. Checks every particle
    /// (in parallel chunks).
    pub fn first_non_finite(&self) -> Option<u32> {
        let finite = |v: &Vector<D>| v.0.iter().all(|c| c.is_finite());
        let local = if self
            .grains
            .vel
            .par_chunks(SUM_CHUNK)
            .all(|c| c.iter().all(finite))
        {
            None
        } else {
            self.grains
                .vel
                .iter()
                .zip(&self.grains.ids)
                .filter(|(v, _)| !finite(v))
                .map(|(_, &id)| id)
                .min()
        };
        match &self.domain {
            Some(d) => self.first_non_finite_decomposed(d, local),
            None => local,
        }
    }
}
