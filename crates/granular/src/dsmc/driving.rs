//! The steady-state driving of the DSMC engine ([`crate::driving`]): applied after every
//! step, outside the move and collision kernels. Rescaling uses the engine's chunked
//! reductions; the white-noise kicks come from per-grain streams named by the grain's
//! identity, and their mean is an ordered chunked sum over the storage order, so both are
//! bit-identical for any number of threads or ranks.

use super::engine::DsmcEngine;
use super::sums::SUM_CHUNK;
use crate::driving::{Driving, DrivingState, KICKS, rescale_factor};
use crate::random::{std_normal, stream};
use crate::vector::Vector;
use rayon::prelude::*;

impl<const D: usize> DsmcEngine<D> {
    /// Attaches a steady-state driving from now on (replacing any earlier one); its energy
    /// tally starts at the current kinetic energy.
    pub fn set_driving(&mut self, driving: Option<Driving>) {
        let k = self.kinetic_energy_now();
        self.driving = driving.map(|d| DrivingState::new(d, k));
    }

    /// The driving and its tally, if any.
    pub fn driving(&self) -> Option<&DrivingState> {
        self.driving.as_ref()
    }

    /// Applies the driving once, after a step of length `dt` (time units).
    pub(super) fn drive(&mut self, dt: f64) {
        let Some(state) = self.driving.as_ref() else {
            return;
        };
        let before = self.kinetic_energy_now();
        match state.driving {
            Driving::Rescale { temperature } => {
                let u = self.mean_velocity();
                let lambda = rescale_factor(temperature, self.temperature());
                self.grains
                    .vel
                    .par_iter_mut()
                    .for_each(|v| *v = u + (*v - u) * lambda);
            }
            Driving::WhiteNoise { strength } => {
                let width = (strength * dt).sqrt();
                let (seed, k) = (self.seed, state.applications);
                let kicks: Vec<Vector<D>> = self
                    .grains
                    .ids
                    .par_iter()
                    .map(|&id| {
                        let mut rng = stream(seed, &[KICKS, k, u64::from(id)]);
                        let mut v = Vector::<D>::zero();
                        for c in 0..D {
                            v[c] = width * std_normal(&mut rng);
                        }
                        v
                    })
                    .collect();
                let mean = self.ordered_mean(&kicks);
                self.grains
                    .vel
                    .par_iter_mut()
                    .zip(kicks.par_iter())
                    .for_each(|(v, kick)| *v += *kick - mean);
            }
        }
        let after = self.kinetic_energy_now();
        if let Some(s) = self.driving.as_mut() {
            s.applications += 1;
            s.injected_energy += after - before;
        }
    }

    /// The mean of one vector per stored grain, summed as [`DsmcEngine::mean_velocity`]:
    /// fixed chunks of [`SUM_CHUNK`] in storage order (over all ranks when decomposed).
    fn ordered_mean(&self, x: &[Vector<D>]) -> Vector<D> {
        if let Some(d) = &self.domain {
            let s = d.ordered_fold::<D, D>(
                x.len(),
                |i| x[i].0,
                |a, v| *a = (Vector(*a) + Vector(*v)).0,
                |a, v| *a = (Vector(*a) + Vector(*v)).0,
            );
            return Vector(s) * (1.0 / d.n_global as f64);
        }
        let s = x
            .par_chunks(SUM_CHUNK)
            .map(|c| c.iter().fold(Vector::zero(), |a, v| a + *v))
            .collect::<Vec<_>>()
            .into_iter()
            .fold(Vector::zero(), |a, v| a + v);
        s * (1.0 / x.len() as f64)
    }
}
