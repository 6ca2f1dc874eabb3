//! The velocity moments of the DSMC gas: mean velocity, momentum, temperature, `a2`,
//! kinetic energy and the check for non-finite velocities. Every sum runs over fixed
//! chunks of `SUM_CHUNK` particles of the storage order, then over the chunks in order
//! (`dsmc::sums`), so its bits do not depend on the number of threads; a decomposed
//! engine reduces them over the ranks in the same order (`Domain::ordered_fold`).

use super::DsmcEngine;
use crate::dsmc::sums;
use crate::vector::Vector;
use rayon::prelude::*;

/// `a += x`, componentwise.
fn add<const A: usize>(a: &mut [f64; A], x: &[f64; A]) {
    for (a, x) in a.iter_mut().zip(x) {
        *a += x;
    }
}

impl<const D: usize> DsmcEngine<D> {
    /// The chunked fold of `elem(i)` over every grain (over all ranks when decomposed),
    /// in the order of the whole engine's storage (see `dsmc::sums`).
    pub(crate) fn ordered_fold<const E: usize, const A: usize>(
        &self,
        elem: impl Fn(usize) -> [f64; E] + Sync,
        fold: impl Fn(&mut [f64; A], &[f64; E]) + Sync,
        combine: impl Fn(&mut [f64; A], &[f64; A]),
    ) -> [f64; A] {
        let n = self.grains.len();
        match &self.domain {
            Some(d) => d.ordered_fold(n, elem, fold, combine),
            None => sums::ordered_fold(n, elem, fold, combine),
        }
    }

    /// Mean velocity (deterministic chunked sum).
    pub fn mean_velocity(&self) -> Vector<D> {
        let g = &self.grains;
        let s = self.ordered_fold::<D, D>(|i| g.velocity(i).0, add, add);
        Vector(s) * (1.0 / self.n_global() as f64)
    }

    /// Total momentum `m sum_i v_i`.
    pub fn momentum(&self) -> Vector<D> {
        self.mean_velocity() * (self.mass * self.n_global() as f64)
    }

    /// Moments `(<c^2>, <c^4>)` of the peculiar velocity `c = v - u`.
    pub(super) fn peculiar_moments(&self) -> (f64, f64) {
        let u = self.mean_velocity();
        let g = &self.grains;
        let [s2, s4] = self.ordered_fold::<1, 2>(
            |i| [(g.velocity(i) - u).norm_squared()],
            |a, &[c2]| *a = [a[0] + c2, a[1] + c2 * c2],
            add,
        );
        let n = self.n_global() as f64;
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
        let g = &self.grains;
        let [s] = self.ordered_fold::<1, 1>(|i| [g.velocity(i).norm_squared()], add, add);
        0.5 * self.mass * s
    }

    /// Rotational kinetic energy `Σ I |ω|² / 2` (`I = κ m R²`) of rough grains, a
    /// deterministic chunked sum as the kinetic energy's; `None` for smooth grains.
    pub(crate) fn rotational_energy_now(&self) -> Option<f64> {
        let body = self.body();
        self.inertia?;
        let g = &self.grains;
        let [s] = self.ordered_fold::<1, 1>(
            |i| {
                let w = g.spin(i);
                [w[0] * w[0] + w[1] * w[1] + w[2] * w[2]]
            },
            add,
            add,
        );
        Some(0.5 * body.inertia * body.mass * body.radius * body.radius * s)
    }

    /// The identity of a particle whose velocity has a non-finite component (the smallest
    /// such identity), or `None` when every velocity is finite. Checks every particle
    /// (in parallel).
    pub fn first_non_finite(&self) -> Option<u32> {
        let g = &self.grains;
        let bad = |i: usize| !(0..D).all(|k| g.velocity_column(k)[i].is_finite());
        let local = (0..g.len())
            .into_par_iter()
            .filter(|&i| bad(i))
            .map(|i| g.id(i))
            .min();
        match &self.domain {
            Some(d) => self.first_non_finite_decomposed(d, local),
            None => local,
        }
    }
}
