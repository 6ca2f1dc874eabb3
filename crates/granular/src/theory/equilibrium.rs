//! Equilibrium theory of hard disks and spheres: the Maxwell-Boltzmann speed distribution
//! and equations of state, used to validate the engines.

use std::f64::consts::PI;

/// Maxwell-Boltzmann probability density of the speed `v` in `D` dimensions, for grains of
/// mass `m` at temperature `T` (`k_B = 1`):
/// `p(v) = 2 (m/2T)^{D/2} / Γ(D/2) v^{D-1} exp(-m v²/2T)`. In 2D this is
/// `p(v) = (m v / T) exp(-m v² / 2T)`, HD-12.
pub fn speed_density(dimension: usize, v: f64, mass: f64, temperature: f64) -> f64 {
    if v < 0.0 {
        return 0.0;
    }
    let d = dimension as f64;
    let a = mass / (2.0 * temperature);
    2.0 * a.powf(d / 2.0) / libm::tgamma(d / 2.0) * v.powf(d - 1.0) * (-a * v * v).exp()
}

/// Cumulative distribution of the Maxwell-Boltzmann speed: `P(D/2, m v² / 2T)` (regularised
/// lower incomplete gamma function).
pub fn speed_cdf(dimension: usize, v: f64, mass: f64, temperature: f64) -> f64 {
    if v <= 0.0 {
        return 0.0;
    }
    puruspe::gammp(dimension as f64 / 2.0, mass * v * v / (2.0 * temperature))
}

/// Mean Maxwell-Boltzmann speed `<v> = sqrt(2T/m) Γ((D+1)/2) / Γ(D/2)`
/// (`sqrt(π T / 2m)` in 2D).
pub fn mean_speed(dimension: usize, mass: f64, temperature: f64) -> f64 {
    let d = dimension as f64;
    (2.0 * temperature / mass).sqrt() * libm::tgamma((d + 1.0) / 2.0) / libm::tgamma(d / 2.0)
}

/// Kinetic temperature from equipartition, `T = <m v²> / D` (`k_B = 1`): the temperature
/// of the Maxwell-Boltzmann distribution (HD-12 in 2D, [`speed_density`] in `D`
/// dimensions) whose mean of `m v²` is `mean_m_v2`. Units: energy (mass × speed²).
pub fn kinetic_temperature(dimension: usize, mean_m_v2: f64) -> f64 {
    mean_m_v2 / dimension as f64
}

/// Compressibility factor `Z = P / (n T)` of the hard-disk fluid at packing fraction `η`
/// (Liu 2020, arXiv:2010.10624, Eq. 1, fitted to the simulation data of Kolafa and Rottner
/// 2006): `Z = (1 + η²/8 + η³/18 - 4η⁴/21) / (1 - η)²`. Accuracy: [`compressibility_accuracy`]
/// (a few 10^-3 relative in the stable fluid, `η < 0.70`, by Liu's statement).
pub fn hard_disk_compressibility(eta: f64) -> f64 {
    (1.0 + eta * eta / 8.0 + eta.powi(3) / 18.0 - 4.0 * eta.powi(4) / 21.0)
        / ((1.0 - eta) * (1.0 - eta))
}

/// Compressibility factor of the hard-sphere fluid, Carnahan-Starling (1969):
/// `Z = (1 + η + η² - η³) / (1 - η)³`, accurate to a few 10^-3 up to `η ≈ 0.5`
/// ([`compressibility_accuracy`]).
pub fn hard_sphere_compressibility(eta: f64) -> f64 {
    (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3)
}

/// Compressibility factor of the hard-disk (`D = 2`) or hard-sphere (`D = 3`) fluid.
pub fn compressibility(dimension: usize, eta: f64) -> f64 {
    if dimension == 2 {
        hard_disk_compressibility(eta)
    } else {
        hard_sphere_compressibility(eta)
    }
}

/// The stated relative accuracy of [`compressibility`] at packing fraction `η`:
/// - disks (Liu's equation): `3·10⁻⁴` up to `η = 0.3` (against the virial series with the
///   coefficients `B_2..B_10` of Clisby and McCoy, J. Stat. Phys. 122, 15 (2006): 1·10⁻⁵
///   at 0.1, 1.1·10⁻⁴ at 0.2, 2.5·10⁻⁴ at 0.3), `10⁻³` up to 0.5 (periodic event-driven runs
///   of 10⁴ disks: 5·10⁻⁴ at 0.4, `docs/edmd.md`), `3·10⁻³` beyond (Liu's statement);
/// - spheres (Carnahan-Starling): `4·10⁻³` (it lies up to 0.31 % below the
///   Kolafa-Labík-Malijevský equation `(1 + η + η² - 2η³(1+η)/3) / (1-η)³`, Phys. Chem.
///   Chem. Phys. 6, 2335 (2004), which follows the virial series and simulations to
///   10⁻⁴; 0.13 % at 0.2, 0.31 % near 0.36).
pub fn compressibility_accuracy(dimension: usize, eta: f64) -> f64 {
    if dimension == 2 {
        if eta <= 0.3 {
            3e-4
        } else if eta <= 0.5 {
            1e-3
        } else {
            3e-3
        }
    } else {
        4e-3
    }
}

/// Long-wavelength limit of the static structure factor of the equilibrium hard-disk
/// (`D = 2`) or hard-sphere (`D = 3`) fluid at packing fraction `η`, from its equation of
/// state: `S(0) = k_B T (∂n/∂P)_T = 1 / (∂(η Z)/∂η)` (compressibility sum rule; Hansen &
/// McDonald, *Theory of Simple Liquids*, Eq. 2.4.25), with `Z` of
/// [`hard_disk_compressibility`] or [`hard_sphere_compressibility`], differentiated
/// analytically. For spheres this is `(1-η)⁴ / (1 + 4η + 4η² - 4η³ + η⁴)`.
pub fn structure_factor_zero(dimension: usize, eta: f64) -> f64 {
    let d_eta_z = if dimension == 2 {
        // η Z = η N(η) / (1-η)², N = 1 + η²/8 + η³/18 - 4η⁴/21.
        let n = 1.0 + eta * eta / 8.0 + eta.powi(3) / 18.0 - 4.0 * eta.powi(4) / 21.0;
        let dn = eta / 4.0 + eta * eta / 6.0 - 16.0 * eta.powi(3) / 21.0;
        ((n + eta * dn) * (1.0 - eta) + 2.0 * eta * n) / (1.0 - eta).powi(3)
    } else {
        (1.0 + 4.0 * eta + 4.0 * eta * eta - 4.0 * eta.powi(3) + eta.powi(4)) / (1.0 - eta).powi(4)
    };
    1.0 / d_eta_z
}

/// Collision frequency per grain implied by a compressibility factor, for equal grains of
/// diameter `σ` and mass `m` at temperature `T`. Exact for elastic hard grains in
/// equilibrium: both the collisional pressure and the collision rate are set by the
/// contact value of the pair distribution, which gives
/// `ν = 2D (Z - 1) sqrt(T / (π m)) / σ`.
pub fn collision_frequency_from_pressure(
    dimension: usize,
    z: f64,
    diameter: f64,
    mass: f64,
    temperature: f64,
) -> f64 {
    2.0 * dimension as f64 * (z - 1.0) * (temperature / (PI * mass)).sqrt() / diameter
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_density_is_normalised_and_matches_eq_12() {
        for d in [2, 3] {
            let n = 200_000;
            let h = 12.0 / n as f64;
            let total: f64 = (0..n)
                .map(|k| speed_density(d, (k as f64 + 0.5) * h, 2.0, 1.5) * h)
                .sum();
            assert!((total - 1.0).abs() < 1e-8, "D = {d}: {total}");
            assert!(
                (speed_cdf(d, 3.0, 2.0, 1.5)
                    - (0..n)
                        .map(|k| (k as f64 + 0.5) * h)
                        .filter(|&v| v < 3.0)
                        .map(|v| speed_density(d, v, 2.0, 1.5) * h)
                        .sum::<f64>())
                .abs()
                    < 1e-6
            );
        }
        let (m, t, v) = (2.0, 1.5, 0.7);
        assert!(
            (speed_density(2, v, m, t) - m * v / t * (-m * v * v / (2.0 * t)).exp()).abs() < 1e-14
        );
        assert!((mean_speed(2, m, t) - (PI * t / (2.0 * m)).sqrt()).abs() < 1e-14);
    }

    #[test]
    fn kinetic_temperature_inverts_the_maxwell_boltzmann_mean() {
        // <m v²> of p(v) at T = 1.5, m = 2 is D T: the midpoint sum recovers T.
        for d in [2, 3] {
            let n = 200_000;
            let h = 12.0 / n as f64;
            let mean_m_v2: f64 = (0..n)
                .map(|k| {
                    let v = (k as f64 + 0.5) * h;
                    2.0 * v * v * speed_density(d, v, 2.0, 1.5) * h
                })
                .sum();
            assert!(
                (kinetic_temperature(d, mean_m_v2) - 1.5).abs() < 1e-8,
                "D = {d}"
            );
        }
        assert_eq!(kinetic_temperature(2, 3.0), 1.5);
    }

    #[test]
    fn structure_factor_zero_is_the_inverse_derivative_of_eta_z() {
        // Against a central difference of η Z(η), and the ideal-gas limit S(0) = 1.
        for d in [2, 3] {
            assert!((structure_factor_zero(d, 0.0) - 1.0).abs() < 1e-15);
            for eta in [0.05, 0.25, 0.4] {
                let h = 1e-5;
                let f = |e: f64| e * compressibility(d, e);
                let numeric = 1.0 / ((f(eta + h) - f(eta - h)) / (2.0 * h));
                let exact = structure_factor_zero(d, eta);
                assert!((exact - numeric).abs() < 1e-8, "D = {d}, η = {eta}");
            }
        }
        // The value quoted in docs/dsmc.md for the section 3.2 gas.
        assert!((structure_factor_zero(2, 0.25) - 0.332).abs() < 5e-4);
    }

    /// The stated accuracy of [`compressibility_accuracy`] holds against the virial series
    /// of hard disks (`η ≤ 0.3`, where ten terms converge to 10⁻⁵) and against the
    /// Kolafa-Labík-Malijevský equation of hard spheres (`η ≤ 0.5`).
    #[test]
    fn equations_of_state_are_as_accurate_as_stated() {
        // Z = 1 + Σ b_k η^k, b_k = 2^k B_{k+1} / B_2^k (Clisby and McCoy 2006).
        let b = [
            2.0, 3.12802, 4.25785, 5.33690, 6.36296, 7.35186, 8.3225, 9.2801, 10.2318,
        ];
        for i in 1..=30 {
            let eta = 0.01 * i as f64;
            let series: f64 = 1.0
                + b.iter()
                    .enumerate()
                    .map(|(k, c)| c * eta.powi(k as i32 + 1))
                    .sum::<f64>();
            let z = hard_disk_compressibility(eta);
            assert!(
                (z / series - 1.0).abs() < compressibility_accuracy(2, eta),
                "disks at {eta}"
            );
        }
        for i in 1..=50 {
            let eta = 0.01 * i as f64;
            let klm = (1.0 + eta + eta * eta - 2.0 / 3.0 * eta.powi(3) * (1.0 + eta))
                / (1.0 - eta).powi(3);
            let z = hard_sphere_compressibility(eta);
            assert!(
                (z / klm - 1.0).abs() < compressibility_accuracy(3, eta),
                "spheres at {eta}"
            );
        }
    }

    #[test]
    fn equations_of_state_have_the_right_low_density_limit() {
        // Second virial coefficient: Z = 1 + 2η (disks), 1 + 4η (spheres).
        let eta = 1e-6;
        assert!(((hard_disk_compressibility(eta) - 1.0) / eta - 2.0).abs() < 1e-4);
        assert!(((hard_sphere_compressibility(eta) - 1.0) / eta - 4.0).abs() < 1e-4);
    }
}
