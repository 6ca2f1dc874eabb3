//! The first Sonine coefficient `a2` (the fourth cumulant of the scaled velocity
//! distribution, `a2 = D/(D+2) <c⁴>/<c²>² - 1`) of the steady states of a granular gas of
//! smooth hard grains with constant restitution `e` in `D` dimensions, from T. P. C. van
//! Noije and M. H. Ernst, *Velocity distributions in homogeneous granular fluids: the free
//! and the heated case*, Granular Matter 1, 57 (1998).
//!
//! The homogeneous cooling state has two estimates, both linear in `a2`; they differ in
//! which terms quadratic in `a2` of the collisional moment are dropped (see also J. M.
//! Montanero and A. Santos, Granular Matter 2, 53 (2000), and Santos and Montanero,
//! Granular Matter 11, 157 (2009), who compare both with simulations; DSMC follows the
//! second within a few thousandths, `docs/dsmc.md`). The heated (white-noise) state has
//! one. All three vanish at `e = 1` and change sign at `e = 1/√2`.

/// `16 (1-e)(1-2e²)`, the numerator of all three.
fn numerator(e: f64) -> f64 {
    16.0 * (1.0 - e) * (1.0 - 2.0 * e * e)
}

/// Homogeneous cooling state, the first estimate (van Noije and Ernst 1998), KT-10 (also
/// `theory::haff::sonine_a2`):
/// `a2 = 16 (1-e)(1-2e²) / (9 + 24D - e (41 - 8D) + 30 e² (1-e))`.
pub fn cooling_a2_first(dimension: usize, restitution: f64) -> f64 {
    let (d, e) = (dimension as f64, restitution);
    numerator(e) / (9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * e * e * (1.0 - e))
}

/// Homogeneous cooling state, the second estimate (van Noije and Ernst 1998), KT-11:
/// `a2 = 16 (1-e)(1-2e²) / (25 + 24D - e (57 - 8D) - 2 e² (1-e))`.
pub fn cooling_a2_second(dimension: usize, restitution: f64) -> f64 {
    let (d, e) = (dimension as f64, restitution);
    numerator(e) / (25.0 + 24.0 * d - e * (57.0 - 8.0 * d) - 2.0 * e * e * (1.0 - e))
}

/// The gas heated by white noise (random velocity kicks, van Noije and Ernst 1998), KT-12:
/// `a2 = 16 (1-e)(1-2e²) / (73 + 56D - 3e (35 + 8D) + 30 e² (1-e))`.
pub fn white_noise_a2(dimension: usize, restitution: f64) -> f64 {
    let (d, e) = (dimension as f64, restitution);
    numerator(e) / (73.0 + 56.0 * d - 3.0 * e * (35.0 + 8.0 * d) + 30.0 * e * e * (1.0 - e))
}

/// The stated accuracy of the cooling state's `a2`: the spread of the two truncations,
/// `|first - second|` (they differ by terms quadratic in `a2` that both drop).
pub fn cooling_a2_accuracy(dimension: usize, restitution: f64) -> f64 {
    (cooling_a2_first(dimension, restitution) - cooling_a2_second(dimension, restitution)).abs()
}

/// The stated accuracy of the heated gas's `a2`: the terms quadratic in `a2` that its one
/// estimate drops, taken as large relative to `a2²` as in the cooling state,
/// `|first - second| (a2_heated / a2_cooling,first)²` (an estimate; zero where both
/// vanish, at `e = 1` and `e = 1/√2`).
pub fn white_noise_a2_accuracy(dimension: usize, restitution: f64) -> f64 {
    let first = cooling_a2_first(dimension, restitution);
    if first == 0.0 {
        return 0.0;
    }
    cooling_a2_accuracy(dimension, restitution)
        * (white_noise_a2(dimension, restitution) / first).powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed values at `e = 0.5`, 2D: 4/52.25 and 4/48.25 (HCS), 4/112.25 (heated);
    /// the 3D white-noise formula is the familiar `16(1-e)(1-2e²)/(241 - 177e + 30e²(1-e))`.
    #[test]
    fn values_by_hand() {
        assert!((cooling_a2_second(2, 0.5) - 4.0 / 52.25).abs() < 1e-15);
        assert!((cooling_a2_first(2, 0.5) - 4.0 / 48.25).abs() < 1e-15);
        assert!((white_noise_a2(2, 0.5) - 4.0 / 112.25).abs() < 1e-15);
        let e: f64 = 0.8;
        let wn3 = numerator(e) / (241.0 - 177.0 * e + 30.0 * e * e * (1.0 - e));
        assert!((white_noise_a2(3, e) - wn3).abs() < 1e-15);
        assert_eq!(cooling_a2_first(3, 1.0), 0.0);
        assert!(cooling_a2_second(3, std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        assert_eq!(
            cooling_a2_first(2, 0.3),
            crate::theory::haff::sonine_a2(2, 0.3)
        );
    }
}
