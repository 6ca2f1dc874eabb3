//! Kinetic theory of a gas of smooth hard disks (`dimension = 2`) or spheres
//! (`dimension = 3`), written once: the grain volume (KT-1), the packing fraction (KT-2),
//! the collision cross-section (DSMC-1), the contact value of the pair correlation
//! (KT-3), the mean relative speed (KT-4), the collision frequency (KT-5), the mean free
//! path and time (KT-6) and random close packing (KT-7). Equation numbers: docs/equations.md,
//! section KT. Units: `k_B = 1`; lengths, masses and temperatures in the scenario's units.

use std::f64::consts::PI;

/// Panics unless `dimension` is 2 or 3 (the formulas below are for disks and spheres).
pub(crate) fn check_dimension(dimension: usize) {
    assert!(
        dimension == 2 || dimension == 3,
        "dimension must be 2 or 3, got {dimension}"
    );
}

/// Total collision cross-section of two equal grains of radius `radius`: the measure of
/// the set of impact parameters `|b| < 2R` that lead to a collision, i.e. the length `4R`
/// (twice the diameter) for disks and the area `pi (2R)^2` for spheres (DSMC-1's
/// `sigma_2D = 4R`, `sigma_3D = 4 pi R^2`; see `docs/dsmc.md`).
pub fn cross_section(dimension: usize, radius: f64) -> f64 {
    check_dimension(dimension);
    if dimension == 2 {
        4.0 * radius
    } else {
        PI * 4.0 * radius * radius
    }
}

/// Volume (area in 2D) of one grain, KT-1: `pi R^2` or `4 pi R^3 / 3` (length^D).
pub fn grain_volume(dimension: usize, radius: f64) -> f64 {
    check_dimension(dimension);
    if dimension == 2 {
        PI * radius * radius
    } else {
        4.0 / 3.0 * PI * radius.powi(3)
    }
}

/// The radius at which `count` equal grains fill `packing_fraction` of a region of volume
/// `volume` (KT-1 and KT-2 solved for `R`): `R = (phi V / (N v_D(1)))^(1/D)`.
pub fn radius_at_packing_fraction(
    dimension: usize,
    packing_fraction: f64,
    volume: f64,
    count: usize,
) -> f64 {
    let unit_ball = grain_volume(dimension, 1.0);
    (packing_fraction * volume / (count.max(1) as f64 * unit_ball)).powf(1.0 / dimension as f64)
}

/// Packing (area or volume) fraction `phi = n v_D(R)` at number density `n`, KT-2.
pub fn packing_fraction(dimension: usize, number_density: f64, radius: f64) -> f64 {
    number_density * grain_volume(dimension, radius)
}

/// Packing fraction of several species in a volume `volume`, KT-2 summed over species:
/// `phi = sum_s N_s v_D(R_s) / V`, `species` the pairs `(N_s, R_s)`.
pub fn mixture_packing_fraction(
    dimension: usize,
    species: impl IntoIterator<Item = (usize, f64)>,
    volume: f64,
) -> f64 {
    let grains: f64 = species
        .into_iter()
        .map(|(count, radius)| count as f64 * grain_volume(dimension, radius))
        .sum();
    grains / volume
}

/// Random-close-packing fraction used by the free-volume correction, KT-7: 0.82 for
/// disks, 0.64 for spheres (Berryman, Phys. Rev. A 27, 1053 (1983)).
pub fn random_close_packing(dimension: usize) -> f64 {
    check_dimension(dimension);
    if dimension == 2 { 0.82 } else { 0.64 }
}

/// Pair correlation at contact `chi(phi)` (the Enskog factor), KT-3: Henderson's
/// `(1 - 7 phi / 16) / (1 - phi)^2` for disks (Mol. Phys. 30, 971 (1975)), the
/// Carnahan-Starling `(1 - phi / 2) / (1 - phi)^3` for spheres (J. Chem. Phys. 51, 635
/// (1969)).
pub fn contact_value(dimension: usize, phi: f64) -> f64 {
    check_dimension(dimension);
    if dimension == 2 {
        (1.0 - 7.0 * phi / 16.0) / ((1.0 - phi) * (1.0 - phi))
    } else {
        (1.0 - 0.5 * phi) / (1.0 - phi).powi(3)
    }
}

/// Mean relative speed `<|v_1 - v_2|>` of two grains of mass `mass` drawn from a
/// Maxwell-Boltzmann distribution at temperature `T`, KT-4:
/// `sqrt(4T/m) Gamma((D+1)/2) / Gamma(D/2)`, i.e. `sqrt(pi T / m)` in 2D and
/// `4 sqrt(T / (pi m))` in 3D.
pub fn mean_relative_speed(dimension: usize, temperature: f64, mass: f64) -> f64 {
    check_dimension(dimension);
    let s = (temperature / mass).sqrt();
    if dimension == 2 {
        PI.sqrt() * s
    } else {
        4.0 / PI.sqrt() * s
    }
}

/// Collision frequency per grain, KT-5, `omega = chi n sigma <|v_12|>` (number of
/// collisions a given grain suffers per unit time) for a Maxwellian gas:
/// `2 chi n (2R) sqrt(pi T/m)` in 2D, `4 chi n (2R)^2 sqrt(pi T/m)` in 3D. `chi = 1` is the
/// Boltzmann value, `chi` from [`contact_value`] the Enskog value. Units: 1/time.
pub fn collision_frequency(
    dimension: usize,
    number_density: f64,
    radius: f64,
    temperature: f64,
    mass: f64,
    chi: f64,
) -> f64 {
    chi * number_density
        * cross_section(dimension, radius)
        * mean_relative_speed(dimension, temperature, mass)
}

/// Mean free time `1 / omega`, KT-6, with `omega` the [`collision_frequency`] (time units).
pub fn mean_free_time(
    dimension: usize,
    number_density: f64,
    radius: f64,
    temperature: f64,
    mass: f64,
    chi: f64,
) -> f64 {
    1.0 / collision_frequency(dimension, number_density, radius, temperature, mass, chi)
}

/// Mean free path `lambda = <|v|> / omega = 1 / (sqrt(2) chi n sigma)` of a Maxwellian
/// gas, KT-6 (length units).
pub fn mean_free_path(dimension: usize, number_density: f64, radius: f64, chi: f64) -> f64 {
    1.0 / (std::f64::consts::SQRT_2 * chi * number_density * cross_section(dimension, radius))
}
