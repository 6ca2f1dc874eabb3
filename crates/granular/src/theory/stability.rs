//! Where the homogeneous cooling state holds: the shear instability of a freely cooling
//! granular gas (HCS-1, HCS-2 in `docs/equations.md`).
//!
//! A cooling gas stays homogeneous, and follows Haff's law (DSMC-3), only in a box smaller
//! than a critical size. A transverse velocity field `u(k)` decays by shear viscosity at
//! the rate `η k² / (m n)`, while the temperature it is measured against decays at the rate
//! `ζ / 2` per unit time in `sqrt(T)`; in units of the thermal speed the shear mode grows
//! where `η k² / (m n) < ζ / 2`, i.e. for `k < k_c = sqrt(ζ* / (2 η*)) / ℓ`, with
//! `ℓ = sqrt(T/m) / ν0`, `ν0 = n T / η0` (both independent of `T`) and the reduced cooling
//! rate `ζ*` and shear viscosity `η*` of the inelastic Boltzmann gas (J. J. Brey,
//! J. W. Dufty, C. S. Kim and A. Santos, Phys. Rev. E 58, 4638 (1998); V. Garzó and
//! J. M. Montanero, Physica A 313, 336 (2002) in `D` dimensions; the instability:
//! P. Goldhirsch and G. Zanetti, Phys. Rev. Lett. 70, 1619 (1993), J. J. Brey,
//! M. J. Ruiz-Montanero and D. Cubero, Phys. Rev. E 54, 3664 (1996)). A periodic box whose
//! longest edge `L` exceeds `L_c = 2π / k_c` has a growing mode (`k = 2π / L`): vortices
//! and then clusters form, and the kinetic energy decays more slowly than Haff's law (in
//! the bundled `dsmc-cooling`, `L = 4.3 L_c`, by 2-3 % within the first `t0`).
//!
//! The dense gas is treated by the Enskog scaling of the collision rate only (`ℓ / χ`, no
//! collisional transfer of momentum), which underestimates `η` and so `L_c`: an estimate
//! for `φ` above a few per cent.

use std::f64::consts::PI;

/// The reduced cooling rate `ζ* = (D+2)/(4D) (1 - e²)(1 + 3 a2/16)`, `ζ` in units of
/// `ν0 = n T / η0` (HCS-1; with [`crate::theory::haff::cooling_rate`]:
/// `ζ = ζ* ν0`).
pub fn reduced_cooling_rate(dimension: usize, restitution: f64, a2: f64) -> f64 {
    let d = dimension as f64;
    (d + 2.0) / (4.0 * d) * (1.0 - restitution * restitution) * (1.0 + 3.0 * a2 / 16.0)
}

/// The reduced shear viscosity `η* = η / η0 = 1 / (ν_η* - ζ*/2)` of the inelastic
/// Boltzmann gas in the first Sonine approximation (HCS-1), with
/// `ν_η* = 3/(4D) (1 - e + 2D/3)(1 + e)(1 - a2/32)` and `ζ*` of
/// [`reduced_cooling_rate`]; `η0 = (D+2)/8 Γ(D/2) π^(-(D-1)/2) sqrt(m T) / σ^(D-1)` is the
/// elastic value (`sqrt(m T / π) / (2σ)` for disks, `5 sqrt(m T / π) / (16 σ²)` for
/// spheres). `η* = 1` at `e = 1`.
pub fn reduced_shear_viscosity(dimension: usize, restitution: f64, a2: f64) -> f64 {
    let (d, e) = (dimension as f64, restitution);
    let nu = 3.0 / (4.0 * d) * (1.0 - e + 2.0 * d / 3.0) * (1.0 + e) * (1.0 - a2 / 32.0);
    1.0 / (nu - 0.5 * reduced_cooling_rate(dimension, restitution, a2))
}

/// The length `ℓ = sqrt(T/m) / ν0 = η0 / (n sqrt(m T))` of the hydrodynamic modes of a gas
/// of `number_density` grains of radius `radius`, divided by the contact value `chi`
/// (Enskog; 1 for the Boltzmann gas): `1 / (2 sqrt(π) n σ)` for disks,
/// `5 / (16 sqrt(π) n σ²)` for spheres, `σ = 2R`.
fn mode_length(dimension: usize, number_density: f64, radius: f64, chi: f64) -> f64 {
    let sigma = 2.0 * radius;
    let d = dimension as f64;
    let eta0 = (d + 2.0) / 8.0 * libm::tgamma(d / 2.0) * PI.powf(-(d - 1.0) / 2.0)
        / sigma.powi(dimension as i32 - 1);
    eta0 / (number_density * chi)
}

/// The critical size `L_c = 2π ℓ sqrt(2 η* / ζ*)` of the homogeneous cooling state (HCS-2):
/// a periodic box whose longest edge exceeds it has a growing shear mode; `∞` for
/// elastic grains. Arguments: number density, grain radius, restitution `e`, the Sonine
/// `a2` of the cooling state ([`crate::theory::sonine::cooling_a2_first`]) and the contact
/// value `chi` (1: Boltzmann gas). Units: those of `radius`.
pub fn critical_length(
    dimension: usize,
    number_density: f64,
    radius: f64,
    restitution: f64,
    a2: f64,
    chi: f64,
) -> f64 {
    let zeta = reduced_cooling_rate(dimension, restitution, a2);
    if zeta <= 0.0 {
        return f64::INFINITY;
    }
    let eta = reduced_shear_viscosity(dimension, restitution, a2);
    2.0 * PI * mode_length(dimension, number_density, radius, chi) * (2.0 * eta / zeta).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::haff::{collision_frequency, cooling_rate, sonine_a2};

    /// `ζ* ν0` is the library's cooling rate, with `ν0 = sqrt(T/m) / ℓ`; the elastic
    /// viscosity is the textbook one; `L_c` of the bundled `dsmc-cooling` gas
    /// (`e = 0.9`, `N = 20000`, `φ = 0.05` in the unit square) by hand.
    #[test]
    fn reduced_rates_match_the_kinetic_theory_of_the_library() {
        for d in [2usize, 3] {
            let (n, r, t, m, e): (f64, f64, f64, f64, f64) = (40.0, 0.03, 1.7, 2.0, 0.7);
            let a2 = sonine_a2(d, e);
            let nu0 = (t / m).sqrt() / mode_length(d, n, r, 1.0);
            let zeta = reduced_cooling_rate(d, e, a2) * nu0;
            let library = cooling_rate(d, n, r, t, m, e, 1.0, true);
            assert!(
                (zeta / library - 1.0).abs() < 1e-12,
                "{d}D: {zeta} {library}"
            );
            // Elastic: η* = 1 and ν0 = ω (2D), 4ω/5 (3D).
            assert!((reduced_shear_viscosity(d, 1.0, 0.0) - 1.0).abs() < 1e-15);
            let omega = collision_frequency(d, n, r, t, m, 1.0);
            let expected = if d == 2 { omega } else { 0.8 * omega };
            assert!((nu0 / expected - 1.0).abs() < 1e-12, "{d}D");
        }
        assert_eq!(critical_length(2, 1.0, 0.1, 1.0, 0.0, 1.0), f64::INFINITY);
        // dsmc-cooling: ℓ = 1/(2 sqrt(π) n σ) = 0.00791, ζ* = 0.0945, η* = 1.0258.
        let radius = (0.05 / (20_000.0 * PI)).sqrt();
        let lc = critical_length(2, 20_000.0, radius, 0.9, sonine_a2(2, 0.9), 1.0);
        assert!((lc - 0.2313).abs() < 5e-4, "{lc}");
    }
}
