//! Exact results for a disk (2D) or sphere (3D) intruder of radius `R` in a bath of point
//! particles with an isotropic velocity distribution `f(u)` (`docs/intruder.md`, "Disk and
//! sphere intruders"; equations G-31 to G-45 of `docs/equations.md`).
//!
//! Units: `k_B = 1`; a temperature is an energy, `T = mass <u_x^2>`. The bath's Gaussian
//! parameter is `a = m / (2 T_B)` as in G-14. Speeds are in velocity units, rates in
//! collisions per unit time.
//!
//! The one-dimensional forms of these results are G-5 to G-18 (`intruder::bath`,
//! `intruder::theory`); the Martin-Piasecki ratio G-18 holds unchanged in any
//! dimension (G-40) and is `intruder::theory::martin_piasecki_ratio`.

use std::f64::consts::PI;

use crate::quadrature::gauss_legendre;

fn check_dimension(dimension: usize) {
    assert!(
        (1..=3).contains(&dimension),
        "dimension must be 1, 2 or 3, got {dimension}"
    );
}

/// Area `S_{d-1} = 2 pi^{d/2} / Gamma(d/2)` of the unit sphere in `d` dimensions: 2 (the two
/// directions of a line), `2 pi` (circle), `4 pi` (sphere).
pub fn unit_sphere_area(dimension: usize) -> f64 {
    check_dimension(dimension);
    match dimension {
        1 => 2.0,
        2 => 2.0 * PI,
        _ => 4.0 * PI,
    }
}

/// Collision cross-section `sigma_d` of an intruder of radius `R` for point particles
/// (G-32): the measure of the impact parameters that hit it, `sigma_d = pi^{(d-1)/2}
/// R^{d-1} / Gamma((d+1)/2)`: 1 in 1D (a point, both sides), the diameter `2R` of a disk,
/// the disk area `pi R^2` of a sphere. Also `sigma_d = R^{d-1} int dOmega max(0, cos)`.
/// Units: length^{d-1}.
pub fn intruder_cross_section(dimension: usize, radius: f64) -> f64 {
    check_dimension(dimension);
    match dimension {
        1 => 1.0,
        2 => 2.0 * radius,
        _ => PI * radius * radius,
    }
}

/// Surface `S_{d-1} R^{d-1}` of the intruder (2 sides in 1D, `2 pi R`, `4 pi R^2`), the
/// measure over which the DSMC twin draws its impact normals (G-45). Units: length^{d-1}.
pub fn intruder_surface(dimension: usize, radius: f64) -> f64 {
    unit_sphere_area(dimension) * radius.powi(dimension as i32 - 1)
}

/// `e^{-z} I_0(z)` and `e^{-z} I_1(z)` for `z >= 0` (modified Bessel functions, scaled):
/// puruspe's rational approximations (relative error about 1e-15) up to `z = 700`, the
/// asymptotic series `(2 pi z)^{-1/2} sum_k (-1)^k a_k(nu) / z^k`,
/// `a_k(nu) = prod_{j=1}^{k} (4 nu^2 - (2j - 1)^2) / (k! 8^k)`, beyond (its smallest term is
/// below 1e-300 there).
fn scaled_bessel_i0_i1(z: f64) -> (f64, f64) {
    if z <= 700.0 {
        let e = (-z).exp();
        (puruspe::In(0, z) * e, puruspe::In(1, z) * e)
    } else {
        let series = |nu2: f64| {
            let (mut term, mut sum) = (1.0, 1.0);
            for k in 1..=30 {
                let j = (2 * k - 1) as f64;
                term *= -(4.0 * nu2 - j * j) / (k as f64 * 8.0 * z);
                sum += term;
            }
            sum / (2.0 * PI * z).sqrt()
        };
        (series(0.0), series(1.0))
    }
}

/// Mean relative speed `<|u - V|>` of an intruder moving at speed `|V| = speed` in a
/// Gaussian bath `f(u) = (a/pi)^{d/2} exp(-a u^2)`, `a = m / (2 T_B)` (G-33):
///
/// `<|u - V|> = Gamma((d+1)/2) / (Gamma(d/2) sqrt(a)) 1F1(-1/2; d/2; -x^2)`, `x = sqrt(a) |V|`,
///
/// * 2D: `sqrt(pi/(4a)) e^{-x^2/2} [(1 + x^2) I_0(x^2/2) + x^2 I_1(x^2/2)]` (Rice mean);
/// * 3D: `[e^{-x^2}/sqrt(pi) + (x + 1/(2x)) erf(x)] / sqrt(a)`, `2/sqrt(pi a)` at `x = 0`;
/// * 1D: `[e^{-x^2}/sqrt(pi) + x erf(x)] / sqrt(a)`, the rate per unit density G-7 of the
///   Gaussian bath (G-16, the sum of `intruder::Gaussian`'s `flux_plus` and `flux_minus`).
///
/// Units: velocity.
pub fn gaussian_mean_relative_speed(dimension: usize, a: f64, speed: f64) -> f64 {
    check_dimension(dimension);
    let s = a.sqrt();
    let x = s * speed.abs();
    let scaled = if dimension == 1 {
        (-x * x).exp() / PI.sqrt() + x * libm::erf(x)
    } else if dimension == 2 {
        let z = 0.5 * x * x;
        let (i0, i1) = scaled_bessel_i0_i1(z);
        0.5 * PI.sqrt() * ((1.0 + x * x) * i0 + x * x * i1)
    } else if x < 1e-4 {
        // (x + 1/(2x)) erf(x) + e^{-x^2}/sqrt(pi) = (2/sqrt(pi)) (1 + x^2/3 - x^4/30 + ...)
        2.0 / PI.sqrt() * (1.0 + x * x / 3.0)
    } else {
        (-x * x).exp() / PI.sqrt() + (x + 0.5 / x) * libm::erf(x)
    };
    scaled / s
}

/// Collision rate `phi_d(V) = rho sigma_d <|u - V|>` of a disk (2D) or sphere (3D) of
/// radius `radius` moving at speed `speed` through a Gaussian bath of density
/// `bath_density`, temperature `bath_temperature` and particle mass `bath_mass`
/// (G-32 with G-33). Units: collisions per unit time.
pub fn gaussian_collision_rate(
    dimension: usize,
    speed: f64,
    radius: f64,
    bath_density: f64,
    bath_temperature: f64,
    bath_mass: f64,
) -> f64 {
    let a = bath_mass / (2.0 * bath_temperature);
    bath_density
        * intruder_cross_section(dimension, radius)
        * gaussian_mean_relative_speed(dimension, a, speed)
}

/// Complete elliptic integrals `(K(k), E(k))` of the first and second kind for the
/// complementary modulus `k' = sqrt(1 - k^2)` in `(0, 1]`, by the arithmetic-geometric
/// mean: `K = pi / (2 M(1, k'))`, `E = K (1 - sum_n 2^{n-1} c_n^2)` with `c_0 = k`.
fn elliptic_k_e(k_prime: f64) -> (f64, f64) {
    let mut a = 1.0f64;
    let mut g = k_prime;
    let mut sum = 0.5 * (1.0 - k_prime * k_prime);
    let mut weight = 0.5;
    for _ in 0..64 {
        let c = 0.5 * (a - g);
        if c.abs() <= 1e-17 * a {
            break;
        }
        let next = 0.5 * (a + g);
        g = (a * g).sqrt();
        a = next;
        weight *= 2.0;
        sum += weight * c * c;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// Mean of `|c e - V|` over the directions `e` (uniform on the unit sphere), for a bath
/// particle of speed `c` and an intruder of speed `v` (G-34):
///
/// * 1D: `max(c, v)`;
/// * 2D: `(2/pi) (c + v) E(k)`, `k = 2 sqrt(c v)/(c + v)` (complete elliptic integral of
///   the second kind; `4c/pi` at `c = v`);
/// * 3D: `c + v^2/(3c)` for `c >= v`, `v + c^2/(3v)` for `c < v`.
///
/// Units: velocity.
pub fn direction_averaged_relative_speed(dimension: usize, c: f64, v: f64) -> f64 {
    check_dimension(dimension);
    let (c, v) = (c.abs(), v.abs());
    match dimension {
        1 => c.max(v),
        2 => {
            let sum = c + v;
            if sum == 0.0 {
                return 0.0;
            }
            let k_prime = (c - v).abs() / sum;
            if k_prime == 0.0 {
                return 4.0 * c / PI;
            }
            2.0 / PI * sum * elliptic_k_e(k_prime).1
        }
        _ => {
            let (hi, lo) = if c >= v { (c, v) } else { (v, c) };
            if hi == 0.0 {
                0.0
            } else {
                hi + lo * lo / (3.0 * hi)
            }
        }
    }
}

/// `<|u - V|>` for an isotropic bath given by its speed density `p(c)` (G-34):
/// `int_0^inf p(c) K_d(c, |V|) dc` with `K_d` from [`direction_averaged_relative_speed`].
///
/// `breakpoints` (increasing, the first `>= 0`) are points where `p` or its derivatives may
/// jump (a tabulated density's nodes); the last may be `f64::INFINITY`, and the density is
/// taken as zero beyond a finite last breakpoint. `scale` is a typical speed of the bath
/// (the map of the infinite piece). Composite 8-point Gauss-Legendre on each piece, with
/// panels graded geometrically towards `c = |V|`, where `K_d` has a kink (3D) or a
/// logarithmic second derivative (2D); the infinite piece is mapped by
/// `c = c_0 + s t / (1 - t)`, `s = max(c_0, scale)`. Relative accuracy about 1e-10 for the baths of
/// `intruder::ball` (unit tests). Units: velocity.
pub fn isotropic_mean_relative_speed(
    dimension: usize,
    speed: f64,
    speed_density: &dyn Fn(f64) -> f64,
    breakpoints: &[f64],
    scale: f64,
) -> f64 {
    check_dimension(dimension);
    let v = speed.abs();
    let integrand = |c: f64| speed_density(c) * direction_averaged_relative_speed(dimension, c, v);
    let mut points: Vec<f64> = breakpoints.to_vec();
    if let (Some(&first), Some(&last)) = (points.first(), points.last())
        && v > first
        && v < last
        && !points.contains(&v)
    {
        let at = points.partition_point(|&p| p < v);
        points.insert(at, v);
    }
    let mut total = 0.0;
    for w in points.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        if hi.is_infinite() {
            let mut lo = lo;
            if lo == v {
                // Grade the neighbourhood of the kink before mapping the rest.
                total += graded_piece(&integrand, v, v + scale, v, scale);
                lo = v + scale;
            }
            let s = lo.max(scale);
            let mapped = |t: f64| {
                let one_minus = 1.0 - t;
                let c = lo + s * t / one_minus;
                integrand(c) * s / (one_minus * one_minus)
            };
            total += gauss_legendre(mapped, 0.0, 1.0, 64);
        } else if hi > lo {
            total += graded_piece(&integrand, lo, hi, v, scale);
        }
    }
    total
}

/// `int_lo^hi g` by composite Gauss-Legendre with panels of at most `scale/4`; if an
/// endpoint equals `v`, the last `min(hi - lo, scale)` before it is covered by panels graded
/// geometrically towards it (ratio 2, 32 levels of 4 panels).
fn graded_piece(g: &dyn Fn(f64) -> f64, lo: f64, hi: f64, v: f64, scale: f64) -> f64 {
    let uniform = |a: f64, b: f64| {
        let panels = ((b - a) / (0.25 * scale)).ceil().clamp(16.0, 4096.0) as usize;
        gauss_legendre(g, a, b, panels)
    };
    let toward_lo = lo == v;
    let toward_hi = hi == v;
    if !(toward_lo || toward_hi) {
        return uniform(lo, hi);
    }
    let len = (hi - lo).min(scale);
    let mut total = if toward_lo {
        uniform(lo + len, hi)
    } else {
        uniform(lo, hi - len)
    };
    let mut outer = 1.0;
    for _ in 0..32 {
        let inner = 0.5 * outer;
        let (a, b) = if toward_lo {
            (lo + inner * len, lo + outer * len)
        } else {
            (hi - outer * len, hi - inner * len)
        };
        total += gauss_legendre(g, a, b, 4);
        outer = inner;
    }
    // The last sliver of relative length 2^-32, by one panel.
    let (a, b) = if toward_lo {
        (lo, lo + outer * len)
    } else {
        (hi - outer * len, hi)
    };
    total + gauss_legendre(g, a, b, 1)
}

/// Kurtosis `<|V|^4> / <|V|^2>^2 = (d + 2)/d` of a `d`-dimensional Maxwellian (G-41): 3 in
/// 1D (`intruder::theory::GAUSSIAN_KURTOSIS`), 2 for a disk, 5/3 for a sphere.
pub fn maxwellian_kurtosis(dimension: usize) -> f64 {
    check_dimension(dimension);
    (dimension as f64 + 2.0) / dimension as f64
}

/// Mean collision rate of a Maxwellian intruder (mass `M`, temperature `T`) in a Gaussian
/// bath (G-42): the relative velocity `u - V` is Gaussian with variance
/// `T_B/m + T/M` per component, so
/// `<phi> = rho sigma_d sqrt(2 (T_B/m + T/M)) Gamma((d+1)/2) / Gamma(d/2)`
/// (`theory::equilibrium::mean_speed` of unit mass at temperature `T_B/m + T/M`).
/// With `T/T_B` from G-40 this is the stationary rate. Units: collisions per unit time.
pub fn maxwellian_mean_collision_rate(
    dimension: usize,
    radius: f64,
    bath_density: f64,
    bath_temperature: f64,
    bath_mass: f64,
    temperature: f64,
    mass: f64,
) -> f64 {
    bath_density
        * intruder_cross_section(dimension, radius)
        * super::equilibrium::mean_speed(
            dimension,
            1.0,
            bath_temperature / bath_mass + temperature / mass,
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// `<|u - V|>` by brute-force quadrature over the whole velocity space, independent of
    /// the kernels `K_d`: polar coordinates `(c, theta)` in 2D, `(c, mu = cos theta)` in 3D
    /// (the azimuth integrates to `2 pi` exactly), Gauss-Legendre in each.
    fn brute_force(dimension: usize, a: f64, v: f64) -> f64 {
        let f = |c: f64| (a / PI).powf(dimension as f64 / 2.0) * (-a * c * c).exp();
        let cmax = 12.0 / a.sqrt() + v;
        let radial = |c: f64| {
            // |c e - V| with 1 - cos = 2 s^2: sqrt((c - v)^2 + 4 c v s^2), smooth in s.
            let dist = |s2: f64| ((c - v) * (c - v) + 4.0 * c * v * s2).max(0.0).sqrt();
            if dimension == 2 {
                // int_0^{2 pi} dtheta = 2 int_0^pi, s = sin(theta/2).
                2.0 * c * f(c) * gauss_legendre(|t| dist((0.5 * t).sin().powi(2)), 0.0, PI, 64)
            } else {
                // mu = 1 - 2 s^2, dmu = 4 s ds.
                2.0 * PI * c * c * f(c) * gauss_legendre(|s| 4.0 * s * dist(s * s), 0.0, 1.0, 64)
            }
        };
        // Split at c = v (kink of the angular integral's integrand).
        if v > 0.0 && v < cmax {
            gauss_legendre(radial, 0.0, v, 50) + gauss_legendre(radial, v, cmax, 100)
        } else {
            gauss_legendre(radial, 0.0, cmax, 100)
        }
    }

    /// G-33 against brute-force quadrature over the velocity space and against the speed
    /// quadrature G-34 (with the Maxwell speed density), from rest to 30 thermal speeds.
    #[test]
    fn gaussian_closed_form_matches_quadrature() {
        for dimension in [2usize, 3] {
            for &a in &[0.5, 3.0] {
                let p =
                    |c: f64| crate::theory::equilibrium::speed_density(dimension, c, 1.0, 0.5 / a);
                for &x in &[0.0, 1e-3, 0.1, 0.5, 1.0, 2.0, 5.0, 12.0, 30.0] {
                    let v = x / a.sqrt();
                    let closed = gaussian_mean_relative_speed(dimension, a, v);
                    let brute = brute_force(dimension, a, v);
                    assert!(
                        rel(closed, brute) < 1e-9,
                        "d = {dimension}, a = {a}, x = {x}: closed {closed}, brute force {brute}"
                    );
                    let quad = isotropic_mean_relative_speed(
                        dimension,
                        v,
                        &p,
                        &[0.0, f64::INFINITY],
                        1.0 / a.sqrt(),
                    );
                    assert!(
                        rel(closed, quad) < 1e-10,
                        "d = {dimension}, a = {a}, x = {x}: closed {closed}, speed quadrature {quad}"
                    );
                }
            }
        }
    }

    /// Limits: at rest the mean bath speed (`sqrt(pi/(4a))`, `2/sqrt(pi a)`); far away
    /// `|V| + (d - 1)/(4 a |V|)`; the Bessel branch switch at `z = 700` is continuous.
    #[test]
    fn gaussian_limits() {
        let a = 2.0;
        assert!(
            rel(
                gaussian_mean_relative_speed(2, a, 0.0),
                (PI / (4.0 * a)).sqrt()
            ) < 1e-14
        );
        assert!(
            rel(
                gaussian_mean_relative_speed(3, a, 0.0),
                2.0 / (PI * a).sqrt()
            ) < 1e-14
        );
        for d in [2usize, 3] {
            let v = 1e3;
            let expected = v + (d as f64 - 1.0) / (4.0 * a * v);
            assert!(rel(gaussian_mean_relative_speed(d, a, v), expected) < 1e-12);
        }
        let (below, above) = (
            scaled_bessel_i0_i1(700.0),
            scaled_bessel_i0_i1(700.0 + 1e-9),
        );
        assert!(rel(below.0, above.0) < 1e-12 && rel(below.1, above.1) < 1e-12);
        // Small-x branch of the 3D form.
        let (s, t) = (
            gaussian_mean_relative_speed(3, 1.0, 0.99e-4),
            gaussian_mean_relative_speed(3, 1.0, 1.01e-4),
        );
        assert!(rel(s, t) < 1e-8);
    }

    /// 1D: the Gaussian bath's rate per unit density G-7 (its `flux`, G-16), at rest
    /// `1/sqrt(pi a)`, at any speed.
    #[test]
    fn gaussian_one_dimensional_form_is_the_bath_flux() {
        use crate::intruder::bath::{BathDistribution, Gaussian};
        for a in [0.5, 2.0] {
            let bath = Gaussian::new(a).expect("a > 0");
            assert!(
                rel(
                    gaussian_mean_relative_speed(1, a, 0.0),
                    1.0 / (PI * a).sqrt()
                ) < 1e-14
            );
            for v in [-3.0, -0.2, 0.0, 1e-3, 0.7, 4.0, 40.0] {
                let (closed, flux) = (gaussian_mean_relative_speed(1, a, v), bath.flux(v));
                assert!(
                    rel(closed, flux) < 1e-13,
                    "a = {a}, v = {v}: {closed} vs {flux}"
                );
            }
        }
    }

    /// The kernels `K_d` against direct angular quadrature, including `c = v`.
    #[test]
    fn direction_average_matches_angular_quadrature() {
        for &(c, v) in &[
            (1.0, 0.0),
            (0.0, 2.0),
            (1.0, 1.0),
            (0.3, 2.0),
            (2.0, 0.3),
            (1.0, 0.999),
        ] {
            // Smooth forms: cos(theta) = 1 - 2 sin^2(theta/2) in 2D, mu = 1 - 2 s^2 in 3D.
            let dist = |s2: f64| ((c - v) * (c - v) + 4.0 * c * v * s2).max(0.0).sqrt();
            let k2 = gauss_legendre(|t| dist((0.5 * t).sin().powi(2)), 0.0, PI, 4000) / PI;
            let k3 = 0.5 * gauss_legendre(|s| 4.0 * s * dist(s * s), 0.0, 1.0, 4000);
            assert!(
                rel(direction_averaged_relative_speed(2, c, v), k2) < 1e-10,
                "2D c = {c} v = {v}"
            );
            assert!(
                rel(direction_averaged_relative_speed(3, c, v), k3) < 1e-10,
                "3D c = {c} v = {v}"
            );
            assert_eq!(direction_averaged_relative_speed(1, c, v), c.max(v));
        }
    }

    #[test]
    fn maxwellian_moments() {
        assert_eq!(maxwellian_kurtosis(1), 3.0);
        assert_eq!(maxwellian_kurtosis(2), 2.0);
        assert!((maxwellian_kurtosis(3) - 5.0 / 3.0).abs() < 1e-15);
        // Intruder at rest limit: T = 0 gives rho sigma <c> of the bath.
        let r = maxwellian_mean_collision_rate(3, 0.5, 2.0, 1.0, 1.0, 0.0, 1.0);
        let at_rest = gaussian_collision_rate(3, 0.0, 0.5, 2.0, 1.0, 1.0);
        assert!(rel(r, at_rest) < 1e-14);
        assert_eq!(intruder_cross_section(2, 0.5), 1.0);
        assert!(rel(intruder_surface(3, 2.0), 16.0 * PI) < 1e-15);
    }
}
