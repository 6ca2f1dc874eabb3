//! Homogeneous cooling of inelastic hard disks and spheres: Haff's law (DSMC-3), the
//! cooling rate with the first Sonine correction (KT-8) and Haff's time (KT-9), on the
//! Boltzmann/Enskog collision frequency of [`super::kinetic`].
//!
//! References: P. K. Haff, J. Fluid Mech. 134, 401 (1983); T. P. C. van Noije and
//! M. H. Ernst, Granular Matter 1, 57 (1998); V. Garzó and J. W. Dufty, Phys. Rev. E 59,
//! 5895 (1999); N. V. Brilliantov and T. Pöschel, *Kinetic Theory of Granular Gases*
//! (Oxford 2004). Derivations in `docs/dsmc.md`.

#[cfg(test)]
use std::f64::consts::PI;

use super::kinetic::check_dimension;
/// The kinetic theory the cooling rate rests on, written once in [`super::kinetic`] (KT-1
/// to KT-7) and re-exported here for the callers that know it from this module.
pub use super::kinetic::{
    collision_frequency, contact_value, cross_section, grain_volume, mean_free_path,
    mean_relative_speed, packing_fraction, random_close_packing,
};

/// First Sonine coefficient of the homogeneous cooling state, van Noije and Ernst (1998)'s
/// first estimate (KT-10), written in [`super::sonine`]:
/// `a2 = 16 (1-e)(1-2e^2) / (9 + 24 D + e (8 D - 41) + 30 e^2 (1-e))`.
pub fn sonine_a2(dimension: usize, restitution: f64) -> f64 {
    check_dimension(dimension);
    super::sonine::cooling_a2_first(dimension, restitution)
}

/// The cooling rate of KT-8 from the collision frequency `omega` and a Sonine coefficient
/// `a2`: `zeta = (1 - e^2) / D * omega * (1 + 3 a2 / 16)` (1/time), the rate of
/// `dT/dt = -zeta T` of a gas of restitution `e` whose velocity distribution has the
/// fourth cumulant `a2` (van Noije and Ernst 1998).
pub fn sonine_cooling_rate(dimension: usize, restitution: f64, omega: f64, a2: f64) -> f64 {
    (1.0 - restitution * restitution) / dimension as f64 * omega * (1.0 + 3.0 * a2 / 16.0)
}

/// Cooling rate `zeta` of `dT/dt = -zeta T` in the homogeneous cooling state, KT-8:
/// [`sonine_cooling_rate`] with `omega` the Maxwellian (Enskog) [`collision_frequency`] at
/// `T` and the HCS's [`sonine_a2`]; `sonine = false` drops the `a2` term (Haff's
/// Maxwellian estimate).
#[allow(clippy::too_many_arguments)]
pub fn cooling_rate(
    dimension: usize,
    number_density: f64,
    radius: f64,
    temperature: f64,
    mass: f64,
    restitution: f64,
    chi: f64,
    sonine: bool,
) -> f64 {
    let omega = collision_frequency(dimension, number_density, radius, temperature, mass, chi);
    let a2 = if sonine {
        sonine_a2(dimension, restitution)
    } else {
        0.0
    };
    sonine_cooling_rate(dimension, restitution, omega, a2)
}

/// The bound on the relative bias of the cooling rate of a gas whose collisions are
/// applied in steps of length `time_step` (DSMC), `0.75 zeta tau` (HCS-3): over one step
/// Haff's law lowers `T` by `zeta tau - (3/4)(zeta tau)² + ...`, the step's collisions by
/// `zeta tau` at the temperature of the step's start, a relative difference of `(3/4) zeta tau`
/// (measured in `docs/dsmc.md`: 1.4 % at `zeta tau = 0.05` in the rescaled HCS).
pub fn step_cooling_bias(zeta: f64, time_step: f64) -> f64 {
    0.75 * zeta * time_step
}

/// Haff's time `t0 = 2 / zeta(T(0))`, KT-9, so that `T(t) = T(0) / (1 + t/t0)^2` (because
/// `zeta ~ sqrt(T)`).
#[allow(clippy::too_many_arguments)]
pub fn haff_time(
    dimension: usize,
    number_density: f64,
    radius: f64,
    initial_temperature: f64,
    mass: f64,
    restitution: f64,
    chi: f64,
    sonine: bool,
) -> f64 {
    2.0 / cooling_rate(
        dimension,
        number_density,
        radius,
        initial_temperature,
        mass,
        restitution,
        chi,
        sonine,
    )
}

/// Haff's time `t0` of DSMC-3 from kinetic theory, as `granular compare` draws it: the
/// Enskog contact value [`contact_value`] at the packing fraction of `number_density`
/// grains of radius `radius`, and the first Sonine correction [`sonine_a2`]; that is,
/// [`haff_time`] with `chi = contact_value(D, packing_fraction(D, n, R))` and
/// `sonine = true`. Units: those of `radius`, `mass` and `initial_temperature`
/// (`k_B = 1`); `t0` in the matching time unit.
pub fn enskog_haff_time(
    dimension: usize,
    number_density: f64,
    radius: f64,
    initial_temperature: f64,
    mass: f64,
    restitution: f64,
) -> f64 {
    let phi = packing_fraction(dimension, number_density, radius);
    let chi = contact_value(dimension, phi);
    haff_time(
        dimension,
        number_density,
        radius,
        initial_temperature,
        mass,
        restitution,
        chi,
        true,
    )
}

/// Probability density of the reduced impact parameter `x = |b| / 2R` in `[0, 1]` under
/// molecular chaos, as DSMC draws it (DSMC section 2, after DSMC-2: `b` uniform on
/// `[-2R, 2R]` in 2D, uniform on the disk of radius `2R` in 3D): `1` for disks, `2x` for
/// spheres. Event-driven runs follow it while the gas stays homogeneous (Müller &
/// Herrmann's DSMC paper, Fig. 2b).
pub fn impact_parameter_density(dimension: usize, x: f64) -> f64 {
    check_dimension(dimension);
    if dimension == 2 { 1.0 } else { 2.0 * x }
}

/// Cumulative distribution of the reduced impact parameter under molecular chaos, the
/// integral of [`impact_parameter_density`] from 0 to `x` (clamped to `[0, 1]`): `x` for
/// disks, `x²` for spheres. For Pearson's test of a measured histogram.
pub fn impact_parameter_cdf(dimension: usize, x: f64) -> f64 {
    check_dimension(dimension);
    let x = x.clamp(0.0, 1.0);
    if dimension == 2 { x } else { x * x }
}

/// Haff's law, DSMC-3: `K(t) = K(0) / (1 + t / t0)^2`.
pub fn haff_energy(initial_energy: f64, t: f64, t0: f64) -> f64 {
    initial_energy / ((1.0 + t / t0) * (1.0 + t / t0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} != {b}");
    }

    #[test]
    fn impact_parameter_cdf_integrates_the_density() {
        for d in [2, 3] {
            // Midpoint rule on 1000 cells: exact for densities linear in x.
            let n = 1000;
            let integral: f64 = (0..n)
                .map(|i| impact_parameter_density(d, (i as f64 + 0.5) / n as f64) / n as f64)
                .sum();
            close(impact_parameter_cdf(d, 1.0), integral);
            close(impact_parameter_cdf(d, 0.0), 0.0);
        }
    }

    #[test]
    fn cross_sections_and_volumes() {
        close(cross_section(2, 0.5), 2.0);
        close(cross_section(3, 0.5), PI);
        close(grain_volume(2, 1.0), PI);
        close(grain_volume(3, 1.0), 4.18879020478639);
    }

    #[test]
    fn contact_values_by_hand() {
        // phi = 0.5: 2D (1 - 7/32) / 0.25 = 3.125; 3D 0.75 / 0.125 = 6.
        close(contact_value(2, 0.5), 3.125);
        close(contact_value(3, 0.5), 6.0);
        close(contact_value(2, 0.0), 1.0);
    }

    #[test]
    fn mean_relative_speed_by_hand() {
        // T = m = 1: 2D sqrt(pi) = 1.7724538509055159, 3D 4/sqrt(pi) = 2.256758334191025.
        close(mean_relative_speed(2, 1.0, 1.0), 1.772_453_850_905_516);
        close(mean_relative_speed(3, 1.0, 1.0), 2.256_758_334_191_025);
        // Scales as sqrt(T/m).
        close(
            mean_relative_speed(2, 4.0, 1.0),
            2.0 * 1.772_453_850_905_516,
        );
    }

    #[test]
    fn collision_frequency_by_hand() {
        // 2D: n = 2, R = 0.25 (d = 0.5, sigma = 2d = 1), T = m = 1:
        // 2 * 1 * sqrt(pi) = 3.5449077018110318.
        close(
            collision_frequency(2, 2.0, 0.25, 1.0, 1.0, 1.0),
            3.544_907_701_811_032,
        );
        // 3D: n = 1, R = 0.5 (d = 1), chi = 2: 4 * 2 * sqrt(pi) = 14.179630807244127.
        close(
            collision_frequency(3, 1.0, 0.5, 1.0, 1.0, 2.0),
            14.179_630_807_244_127,
        );
        // Mean free path of hard disks, 1 / (2 sqrt(2) n d), n = 1, d = 1: 0.35355339059327373;
        // of spheres, 1 / (sqrt(2) pi n d^2): 0.22507907903927651.
        close(mean_free_path(2, 1.0, 0.5, 1.0), 0.353_553_390_593_273_7);
        close(mean_free_path(3, 1.0, 0.5, 1.0), 0.225_079_079_039_276_5);
    }

    #[test]
    fn sonine_coefficient_by_hand() {
        // e = 0.5, 2D: 16 * 0.5 * 0.5 / (57 - 12.5 + 3.75) = 4 / 48.25.
        close(sonine_a2(2, 0.5), 4.0 / 48.25);
        // e = 0.5, 3D: 4 / (81 - 8.5 + 3.75) = 4 / 76.25.
        close(sonine_a2(3, 0.5), 4.0 / 76.25);
        // e = 0.9, 3D: 16*0.1*(1-1.62) / (81 - 15.3 + 2.43) = -0.992 / 68.13.
        close(sonine_a2(3, 0.9), -0.992 / 68.13);
        // Elastic limit and the sign change at e = 1/sqrt(2).
        close(sonine_a2(2, 1.0), 0.0);
        assert!(sonine_a2(3, std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
    }

    #[test]
    fn cooling_rate_and_haff_time_by_hand() {
        // 2D, n = 2, R = 0.25 (d = 0.5), T = m = 1, e = 0.5: omega = 2 sqrt(pi),
        // zeta0 = 0.75 / 2 * 2 sqrt(pi) = 1.329340388179137, which is Garzo & Dufty's
        // (1 - e^2) sqrt(pi) n d sqrt(T/m) for d = 2.
        let z0 = cooling_rate(2, 2.0, 0.25, 1.0, 1.0, 0.5, 1.0, false);
        close(z0, 1.329_340_388_179_137);
        let z = cooling_rate(2, 2.0, 0.25, 1.0, 1.0, 0.5, 1.0, true);
        close(z, 1.329_340_388_179_137 * (1.0 + 3.0 / 16.0 * 4.0 / 48.25));
        // 3D, n = 1, d = 1, e = 0.5: Garzo-Dufty (4 sqrt(pi) / 3)(1 - e^2) n d^2 = 1.7724538509055159.
        close(
            cooling_rate(3, 1.0, 0.5, 1.0, 1.0, 0.5, 1.0, false),
            1.772_453_850_905_516,
        );
        close(haff_time(2, 2.0, 0.25, 1.0, 1.0, 0.5, 1.0, false), 2.0 / z0);
        close(haff_energy(8.0, 1.0, 1.0), 2.0);
    }

    #[test]
    fn enskog_haff_time_by_hand() {
        // 2D, R = 0.25, n = 0.5 / (pi R^2) = 8 / pi: phi = 0.5, chi = 3.125 (Henderson),
        // e = 0.5, T = m = 1. omega = 3.125 n 4R sqrt(pi) = 25 / sqrt(pi) = 14.104739588693908,
        // a2 = 4 / 48.25, zeta = 0.75 / 2 omega (1 + 3 a2 / 16) = 5.371494092067369,
        // t0 = 2 / zeta = 0.3723358837820567.
        let n = 8.0 / PI;
        let omega = 25.0 / PI.sqrt();
        close(omega, 14.104_739_588_693_908);
        let zeta = 0.375 * omega * (1.0 + 3.0 / 16.0 * 4.0 / 48.25);
        close(zeta, 5.371_494_092_067_369);
        close(
            enskog_haff_time(2, n, 0.25, 1.0, 1.0, 0.5),
            0.372_335_883_782_056_7,
        );
        close(
            enskog_haff_time(3, 0.1, 0.5, 2.0, 3.0, 0.8),
            haff_time(
                3,
                0.1,
                0.5,
                2.0,
                3.0,
                0.8,
                contact_value(3, 0.1 * PI / 6.0),
                true,
            ),
        );
    }

    #[test]
    fn impact_parameter_densities_are_normalised() {
        // Midpoint rule is exact for densities linear in x.
        for d in [2, 3] {
            let total: f64 = (0..10)
                .map(|i| impact_parameter_density(d, (f64::from(i) + 0.5) / 10.0) / 10.0)
                .sum();
            close(total, 1.0);
        }
        close(impact_parameter_density(2, 0.3), 1.0);
        close(impact_parameter_density(3, 0.3), 0.6);
    }
}
