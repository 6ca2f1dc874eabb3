//! Exact results used to validate the engines.

/// Martin-Piasecki stationary temperature ratio `T/T_B` of a 1D intruder of mass `mass` in a
/// Gaussian bath of particles of mass `bath_mass` (G-18 generalised to `m != 1`):
///
/// `T/T_B = (1 + alpha) / (2 + (1 - alpha) m / M)`.
///
/// With `m = 1` this is G-18. Derivation (see `docs/intruder.md`): the stationary
/// intruder distribution is Gaussian [Martin & Piasecki]; the energy balance
/// `<|g| (v1'^2 - v1^2)> = 0` with `v1' = v1 + (1+alpha) mu g`, `mu = m/(m+M)`,
/// `g = v - v1`, gives `2 (T/M) / (T/M + T_B/m) = (1 + alpha) mu`.
pub fn martin_piasecki_ratio(restitution: f64, mass: f64, bath_mass: f64) -> f64 {
    (1.0 + restitution) / (2.0 + (1.0 - restitution) * bath_mass / mass)
}

/// Whether the exact power-law case applies: `M/m = alpha` (the post-collision velocity
/// of the intruder is then the pre-collision velocity of the bath particle, so the
/// stationary intruder distribution equals the bath distribution, G-19 with the same
/// `a`, i.e. temperature `T = M <v^2> = alpha T_B`).
pub fn power_law_exact_case(restitution: f64, mass: f64, bath_mass: f64) -> bool {
    (mass / bath_mass - restitution).abs() <= 1e-12 * (1.0 + restitution)
}

/// Temperature ratio `T/T_B = alpha` in the exact case `M/m = alpha` (any bath, in
/// particular the power law of G-19).
pub fn power_law_exact_ratio(restitution: f64) -> f64 {
    restitution
}

/// Kurtosis `<v^4>/<v^2>^2` of a Gaussian.
pub const GAUSSIAN_KURTOSIS: f64 = 3.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elastic_intruder_is_at_bath_temperature() {
        for &m in &[0.1, 1.0, 7.0] {
            assert!((martin_piasecki_ratio(1.0, m, 1.0) - 1.0).abs() < 1e-15);
        }
        // G-18 with m = 1, M = 1, alpha = 0: 1/3.
        assert!((martin_piasecki_ratio(0.0, 1.0, 1.0) - 1.0 / 3.0).abs() < 1e-15);
        // Only the mass ratio matters.
        assert!(
            (martin_piasecki_ratio(0.3, 2.0, 4.0) - martin_piasecki_ratio(0.3, 0.5, 1.0)).abs()
                < 1e-15
        );
    }
}
