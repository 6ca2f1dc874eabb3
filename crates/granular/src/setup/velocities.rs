//! Initial velocities: fixed speed in random directions, Maxwell-Boltzmann, and the removal
//! of the centre-of-mass drift.

use crate::random::{RngExt, Stream};
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};

/// Velocities of magnitude `speed` in uniformly random directions (Problem 1 of the hard-disk assignment:
/// `v = v0 (cos θ, sin θ)` with θ uniform; in 3D uniform on the sphere).
pub fn fixed_speed<const D: usize>(n: usize, speed: f64, rng: &mut Stream) -> Vec<Vector<D>> {
    (0..n)
        .map(|_| {
            if D == 2 {
                let theta = 2.0 * std::f64::consts::PI * rng.random::<f64>();
                let mut v = Vector::zero();
                v[0] = speed * theta.cos();
                v[1] = speed * theta.sin();
                v
            } else {
                loop {
                    let mut v = Vector::zero();
                    for k in 0..D {
                        v[k] = StandardNormal.sample(rng);
                    }
                    let norm = v.norm();
                    if norm > 0.0 {
                        break v * (speed / norm);
                    }
                }
            }
        })
        .collect()
}

/// Maxwell-Boltzmann velocities at temperature `temperature` (`k_B = 1`): each component
/// Gaussian with variance `T / m_i`.
pub fn maxwell_boltzmann<const D: usize>(
    masses: &[f64],
    temperature: f64,
    rng: &mut Stream,
) -> Vec<Vector<D>> {
    masses
        .iter()
        .map(|&m| {
            let s = (temperature / m).sqrt();
            let mut v = Vector::zero();
            for k in 0..D {
                let z: f64 = StandardNormal.sample(rng);
                v[k] = s * z;
            }
            v
        })
        .collect()
}

/// Removes the centre-of-mass velocity so that the total momentum vanishes.
pub fn remove_drift<const D: usize>(velocities: &mut [Vector<D>], masses: &[f64]) {
    let total: f64 = masses.iter().sum();
    if total <= 0.0 {
        return;
    }
    let mut p = Vector::<D>::zero();
    for (v, &m) in velocities.iter().zip(masses) {
        p = p.add_scaled(m, v);
    }
    let drift = p * (1.0 / total);
    for v in velocities.iter_mut() {
        *v -= drift;
    }
}
