//! Self-diffusion of a hard-disk or hard-sphere gas in kinetic theory.
//!
//! Chapman-Enskog, first Sonine approximation (Chapman and Cowling, *The Mathematical
//! Theory of Non-Uniform Gases*, 3rd ed. 1970, section 10.1 for spheres; Gass, J. Chem.
//! Phys. 54, 1898 (1971) for disks): the tagged grain's momentum relaxes at the rate
//! `γ = (1/D) n σ^(D-1) c_D <g³> m / (D T)` with `c_D = ∫ (ĝ·n)³ dn` over the half sphere
//! (`4/3` in 2D, `π/2` in 3D) and `D_0 = T / (m γ)`, which gives
//!
//! - 2D: `D_0 = (1 / (2 n σ)) sqrt(T / (π m))`,
//! - 3D: `D_0 = (3 / (8 n σ²)) sqrt(T / (π m))`,
//!
//! with `σ = 2R` the diameter and `k_B = 1`. Enskog's dense-gas theory divides by the
//! contact value, `D_E = D_0 / χ` (Chapman and Cowling section 16.5).
//!
//! The second Sonine approximation raises `D_0` of hard spheres by the factor
//! `1 + (6C* - 5)² / (16 A* + 40) = 1 + 1/56 ≈ 1.018` (Hirschfelder, Curtiss and Bird,
//! *Molecular Theory of Gases and Liquids*, 1954, section 8.2, with `A* = C* = 1` for
//! rigid spheres; quoted, not re-derived here); further approximations are quoted to add
//! about 0.1 % ([`SPHERE_SONINE_FACTOR`]). For disks no second approximation is given
//! here.

use super::haff::contact_value;
use std::f64::consts::PI;

/// The second-Sonine factor of the self-diffusion coefficient of hard spheres,
/// `1 + 1/56` (HCB section 8.2).
pub const SPHERE_SONINE_FACTOR: f64 = 1.0 + 1.0 / 56.0;

/// The Chapman-Enskog self-diffusion coefficient `D_0` of a dilute gas in the first Sonine
/// approximation (length²/time): number density `n` (per unit volume or area), grain
/// radius `R`, temperature `T` (energy units), mass `m`.
pub fn chapman_enskog_self_diffusion(
    dimension: usize,
    number_density: f64,
    radius: f64,
    temperature: f64,
    mass: f64,
) -> f64 {
    let sigma = 2.0 * radius;
    let thermal = (temperature / (PI * mass)).sqrt();
    match dimension {
        2 => thermal / (2.0 * number_density * sigma),
        3 => 3.0 * thermal / (8.0 * number_density * sigma * sigma),
        _ => panic!("self-diffusion is given for dimension 2 or 3, not {dimension}"),
    }
}

/// Enskog's self-diffusion coefficient `D_E = D_0 / χ(φ)`, `χ` from
/// [`contact_value`] at the packing fraction `φ`.
pub fn enskog_self_diffusion(
    dimension: usize,
    number_density: f64,
    radius: f64,
    temperature: f64,
    mass: f64,
    phi: f64,
) -> f64 {
    chapman_enskog_self_diffusion(dimension, number_density, radius, temperature, mass)
        / contact_value(dimension, phi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::haff::collision_frequency;

    /// `D_0 ω = (D/2) T / m` in both dimensions (the tagged grain's velocity relaxes at
    /// `2 ω / D`, with `ω` the Boltzmann collision frequency).
    #[test]
    fn diffusion_times_collision_frequency() {
        for d in [2, 3] {
            let (n, r, t, m) = (3.0, 0.05, 1.7, 2.3);
            let d0 = chapman_enskog_self_diffusion(d, n, r, t, m);
            let omega = collision_frequency(d, n, r, t, m, 1.0);
            let expected = 0.5 * d as f64 * t / m;
            assert!((d0 * omega - expected).abs() < 1e-12 * expected, "{d}D");
        }
    }
}
