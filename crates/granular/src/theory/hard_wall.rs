//! Hard grains in a box with hard walls: what the walls do to the pressure a run measures
//! (W-1 to W-4 in `docs/equations.md`).
//!
//! A wall keeps every grain centre at least one radius `R` from it, so the centres move in
//! the *open* box of lengths `ℓ_k = L_k - 2R` along walled axes (`ℓ_k = L_k` along
//! periodic ones). Near a wall the fluid is not the bulk fluid: the grains pile up at the
//! wall (adsorption `Γ` per unit wall area, W-2) and the wall costs a free energy `γ` per
//! unit area (the wall tension, W-1), both measured from the surface of closest approach
//! of the centres (the boundary of the open box). With the grand potential
//! `Ω = -P V_o + γ S_o` (open volume `V_o = Π ℓ_k`, open wall area `S_o`) two exact
//! relations follow (W-3, W-4):
//!
//! - the grains are shared between the bulk and the wall layers,
//!   `N = n_b V_o + Γ(n_b) S_o`, which fixes the bulk density `n_b`;
//! - the force on a wall perpendicular to axis `k` is `F_k = -∂Ω/∂ℓ_k =
//!   P_b ∂V_o/∂ℓ_k - γ ∂S_o/∂ℓ_k` (moving a wall stretches the walls that meet it), and the
//!   virial theorem of hard grains turns the collisional virial of the run into
//!   `P_vir = Σ_k ℓ_k F_k / (D V)`, `V = Π L_k` the box volume the run divides by. Along
//!   a periodic axis, `F_k` is the force through a plane across the box, of the same form.
//!
//! `P_b = n_b T Z(η_b)` is the bulk equation of state
//! ([`super::equilibrium::compressibility`]). For `γ` and `Γ` the module takes scaled
//! particle theory (SPT; H. Reiss, H. L. Frisch and J. L. Lebowitz, J. Chem. Phys. 31, 369
//! (1959) in 3D; E. Helfand, H. L. Frisch and J. L. Lebowitz, J. Chem. Phys. 34, 1037 (1961)
//! in 2D): the work to open a cavity of radius `r` for the centres is
//! `-ln(1 - n v_D(r))` up to `r = σ/2` and a polynomial in `r` beyond, whose leading
//! coefficient is the pressure; the coefficient of the surface term is the wall tension of
//! a planar wall, and `Γ = -∂γ/∂μ` (Gibbs) follows with `∂μ/∂n = (1/n) ∂P/∂n`.
//!
//! Accuracy: SPT's `γ` and `Γ` are exact to second order in the density in 3D; in 2D the
//! exact second-order terms are `βγ = -n²σ³/3`, `Γ = 2n²σ³/3` (from the density profile
//! `ρ(z) = n (1 + n A(z))` at a wall, `A(z)` the part of the exclusion disk of radius `σ`
//! cut off by the wall), SPT's `-πn²σ³/8` and `πn²σ³/4` 18 % larger. Against event-driven
//! runs in walled boxes (2D: 2 500 and 10 000 disks at packing fractions 0.1, 0.2 and 0.4;
//! 3D: 10 000 spheres at 0.2 and 0.3; `docs/edmd.md`, "Pressure in a walled box") the
//! residuals were at most a tenth of the part of the prediction that `γ` and `Γ` make (0.1 %
//! to 17 % of `Z`); the stated accuracy, [`WALL_CORRECTION_ACCURACY`], is 15 % of that part.

use super::equilibrium::compressibility;
use super::haff::grain_volume;
use std::f64::consts::PI;

/// Relative accuracy of the part of the walled box's pressures that the wall tension and
/// adsorption make (see the module docs).
pub const WALL_CORRECTION_ACCURACY: f64 = 0.15;

/// The wall tension `βγ` (`γ / T`, per unit wall area: per unit length in 2D) of the
/// hard-disk or hard-sphere fluid at packing fraction `η` against a planar hard wall,
/// measured from the surface of closest approach of the centres, in scaled particle theory
/// (W-1): `βγ = -2η² / (π σ (1-η)²)` (disks), `βγ = -9η²(1+η) / (2π σ² (1-η)³)` (spheres),
/// `σ = 2R` the diameter. Units: 1 / length^(D-1).
pub fn wall_tension(dimension: usize, packing_fraction: f64, diameter: f64) -> f64 {
    let eta = packing_fraction;
    if dimension == 2 {
        -2.0 * eta * eta / (PI * diameter * (1.0 - eta).powi(2))
    } else {
        -9.0 * eta * eta * (1.0 + eta) / (2.0 * PI * diameter * diameter * (1.0 - eta).powi(3))
    }
}

/// The adsorption `Γ` (excess grains per unit wall area, per unit length in 2D) of the
/// hard-disk or hard-sphere fluid at packing fraction `η` at a planar hard wall, measured
/// from the surface of closest approach of the centres, in scaled particle theory
/// (W-2, `Γ = -∂γ/∂μ` of [`wall_tension`]): `Γ = 4η² / (π σ (1+η))` (disks),
/// `Γ = 9η² / (π σ² (1+2η))` (spheres). Units: 1 / length^(D-1).
pub fn wall_adsorption(dimension: usize, packing_fraction: f64, diameter: f64) -> f64 {
    let eta = packing_fraction;
    if dimension == 2 {
        4.0 * eta * eta / (PI * diameter * (1.0 + eta))
    } else {
        9.0 * eta * eta / (PI * diameter * diameter * (1.0 + 2.0 * eta))
    }
}

/// What the equation of state predicts for the pressures a run measures in a box with hard
/// walls on some axes ([`walled_box`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalledBox {
    /// Number density `n_b` of the bulk fluid, away from the walls (W-3).
    pub bulk_density: f64,
    /// Its packing fraction `η_b`.
    pub bulk_packing_fraction: f64,
    /// `P_vir / (n T)` with the collisional-virial pressure of the run (divided by the box
    /// volume `V`) and `n = N / V` (W-4): the compressibility factor a walled run reports.
    pub virial_compressibility: f64,
    /// The momentum given to the walls per unit time and wall area (the full faces,
    /// `2 V / L_k` per walled axis, as the run counts it) over `n T` (W-4); `NaN` without
    /// walls.
    pub wall_compressibility: f64,
    /// `Z(η)` of the bulk equation of state at the box's packing fraction `η = N v_D / V`,
    /// what a periodic box of the same density reports.
    pub uncorrected: f64,
    /// The absolute stated accuracy of `virial_compressibility`'s wall terms:
    /// [`WALL_CORRECTION_ACCURACY`] times the part of it that comes from `γ` and `Γ` (the
    /// geometry of the open box is exact).
    pub virial_accuracy: f64,
    /// The same for `wall_compressibility`.
    pub wall_accuracy: f64,
}

/// The pressures of `particles` grains of radius `radius` in a box of edge lengths
/// `lengths` with hard walls on the axes where `walls` is true, from the bulk equation of
/// state and the wall terms of scaled particle theory (W-3, W-4; see the module docs).
/// Dimension 2 or 3; in a periodic box both predictions are `Z(η)`.
pub fn walled_box(lengths: &[f64], walls: &[bool], particles: usize, radius: f64) -> WalledBox {
    let with = pressures(lengths, walls, particles, radius, true);
    let without = pressures(lengths, walls, particles, radius, false);
    let d = lengths.len();
    let volume: f64 = lengths.iter().product();
    let eta = particles as f64 * grain_volume(d, radius) / volume;
    WalledBox {
        bulk_density: with.0,
        bulk_packing_fraction: with.0 * grain_volume(d, radius),
        virial_compressibility: with.1,
        wall_compressibility: with.2,
        uncorrected: compressibility(d, eta),
        virial_accuracy: WALL_CORRECTION_ACCURACY * (with.1 - without.1).abs(),
        wall_accuracy: WALL_CORRECTION_ACCURACY * (with.2 - without.2).abs(),
    }
}

/// `(n_b, Z_virial, Z_wall)` of [`walled_box`], with the wall terms of scaled particle
/// theory (`spt`) or without them (the open box's geometry alone: `γ = Γ = 0`).
fn pressures(
    lengths: &[f64],
    walls: &[bool],
    particles: usize,
    radius: f64,
    spt: bool,
) -> (f64, f64, f64) {
    let d = lengths.len();
    let adsorption = |eta: f64, sigma: f64| {
        if spt {
            wall_adsorption(d, eta, sigma)
        } else {
            0.0
        }
    };
    let sigma = 2.0 * radius;
    let n = particles as f64;
    let volume: f64 = lengths.iter().product();
    let grain = grain_volume(d, radius);
    let open: Vec<f64> = lengths
        .iter()
        .zip(walls)
        .map(|(l, w)| if *w { l - sigma } else { *l })
        .collect();
    let open_volume: f64 = open.iter().product();
    // d Π_{i≠k} ℓ_i: the product of the open lengths without axes k (and j).
    let product_without = |skip: &[usize]| -> f64 {
        (0..d)
            .filter(|i| !skip.contains(i))
            .map(|i| open[i])
            .product()
    };
    let open_area: f64 = (0..d)
        .filter(|&j| walls[j])
        .map(|j| 2.0 * product_without(&[j]))
        .sum();
    // W-3: N = n_b V_o + Γ(n_b) S_o, by fixed-point iteration (Γ S_o is a small part of N).
    let mut bulk = n / open_volume;
    for _ in 0..200 {
        let next = (n - adsorption(bulk * grain, sigma) * open_area) / open_volume;
        let converged = (next - bulk).abs() <= 1e-15 * bulk;
        bulk = next;
        if converged {
            break;
        }
    }
    let eta_b = bulk * grain;
    let beta_p = bulk * compressibility(d, eta_b);
    let beta_gamma = if spt {
        wall_tension(d, eta_b, sigma)
    } else {
        0.0
    };
    // W-4: βF_k = βP_b Π_{j≠k} ℓ_j - βγ Σ_{walled j≠k} 2 Π_{i≠j,k} ℓ_i.
    let force = |k: usize| -> f64 {
        let stretched: f64 = (0..d)
            .filter(|&j| j != k && walls[j])
            .map(|j| 2.0 * product_without(&[j, k]))
            .sum();
        beta_p * product_without(&[k]) - beta_gamma * stretched
    };
    let virial: f64 = (0..d).map(|k| open[k] * force(k)).sum::<f64>() / (d as f64 * n);
    let wall_area: f64 = (0..d)
        .filter(|&k| walls[k])
        .map(|k| 2.0 * volume / lengths[k])
        .sum();
    let wall = if wall_area > 0.0 {
        let pushed: f64 = (0..d).filter(|&k| walls[k]).map(|k| 2.0 * force(k)).sum();
        pushed / wall_area / (n / volume)
    } else {
        f64::NAN
    };
    (bulk, virial, wall)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Γ = -∂γ/∂μ` with `β ∂μ/∂n = (1/n) ∂(βP)/∂n`, the scaled-particle pressure
    /// (`1/(1-η)²` for disks, Percus-Yevick compressibility for spheres), by central
    /// differences; and the low-density limits `βγ → -π n² σ^(D+1) / 8`, `Γ → π n² σ^(D+1) / 4`
    /// (exact in 3D).
    #[test]
    fn adsorption_is_the_gibbs_derivative_of_the_tension() {
        for d in [2usize, 3] {
            let sigma = 0.7;
            let v = grain_volume(d, sigma / 2.0);
            let spt_beta_p = |n: f64| {
                let eta = n * v;
                if d == 2 {
                    n / (1.0 - eta).powi(2)
                } else {
                    n * (1.0 + eta + eta * eta) / (1.0 - eta).powi(3)
                }
            };
            for eta in [0.05, 0.2, 0.4] {
                let n = eta / v;
                let h = 1e-6 * n;
                let dgamma = (wall_tension(d, (n + h) * v, sigma)
                    - wall_tension(d, (n - h) * v, sigma))
                    / (2.0 * h);
                let dmu = (spt_beta_p(n + h) - spt_beta_p(n - h)) / (2.0 * h) / n;
                let gibbs = -dgamma / dmu;
                let gamma = wall_adsorption(d, eta, sigma);
                assert!((gibbs - gamma).abs() < 1e-7 * gamma, "{d}D η = {eta}");
            }
            let n = 1e-4 / v;
            let scale = n * n * sigma.powi(d as i32 + 1);
            let t = wall_tension(d, n * v, sigma) / scale;
            let a = wall_adsorption(d, n * v, sigma) / scale;
            assert!((t + PI / 8.0).abs() < 1e-3, "{d}D: {t}");
            assert!((a - PI / 4.0).abs() < 1e-3, "{d}D: {a}");
        }
    }

    /// A periodic box is the bulk; walls raise the virial `Z` by about `-2βγ/(n ℓ)` per
    /// walled axis pair in 2D, and the wall pressure is the virial one times `L / ℓ`
    /// (the virial theorem with the walls at the centres' closest approach).
    #[test]
    fn walls_shift_the_measured_pressures() {
        let (n, phi) = (10_000usize, 0.2);
        let r = (phi / (n as f64 * PI)).sqrt();
        let periodic = walled_box(&[1.0, 1.0], &[false, false], n, r);
        assert!((periodic.virial_compressibility - compressibility(2, phi)).abs() < 1e-13);
        assert!(periodic.wall_compressibility.is_nan());
        assert!((periodic.bulk_packing_fraction - phi).abs() < 1e-15);
        let walled = walled_box(&[1.0, 1.0], &[true, true], n, r);
        let ratio = walled.wall_compressibility / walled.virial_compressibility;
        assert!((ratio - 1.0 / (1.0 - 2.0 * r)).abs() < 1e-12, "{ratio}");
        // The measured shift of the default scenario (docs/edmd.md): +0.15 % ± 0.02 %.
        let shift = walled.virial_compressibility / walled.uncorrected - 1.0;
        assert!((0.0009..0.0013).contains(&shift), "{shift}");
        // 3D: the same relation of the two pressures, walls on one axis only.
        let r3 = 0.01;
        let half = walled_box(&[1.0, 2.0, 1.0], &[false, true, false], 20_000, r3);
        let (vp, wp) = (half.virial_compressibility, half.wall_compressibility);
        assert!(vp > half.uncorrected && wp > vp, "{vp} {wp}");
    }
}
