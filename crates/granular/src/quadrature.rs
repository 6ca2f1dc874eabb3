//! Numerical quadrature shared by the engines and their tests.

/// Nodes and weights of the 8-point Gauss-Legendre rule on `[-1, 1]`.
pub(crate) const GAUSS_LEGENDRE_8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

/// `∫_lo^hi f` by the composite 8-point Gauss-Legendre rule on `panels` equal panels
/// (exact for polynomials of degree 15 on each panel).
pub fn gauss_legendre(f: impl Fn(f64) -> f64, lo: f64, hi: f64, panels: usize) -> f64 {
    let panels = panels.max(1);
    let h = (hi - lo) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = lo + (p as f64 + 0.5) * h;
        let mut s = 0.0;
        for (x, w) in GAUSS_LEGENDRE_8 {
            s += w * f(mid + 0.5 * h * x);
        }
        sum += 0.5 * h * s;
    }
    sum
}

#[cfg(test)]
mod tests {
    #[test]
    fn integrates_polynomials_and_smooth_functions() {
        let p = super::gauss_legendre(|x| x.powi(15) + 3.0 * x * x, -1.0, 2.0, 1);
        assert!((p - ((2f64.powi(16) - 1.0) / 16.0 + 9.0)).abs() < 1e-10);
        let e = super::gauss_legendre(f64::exp, 0.0, 1.0, 4);
        assert!((e - (std::f64::consts::E - 1.0)).abs() < 1e-14);
    }
}
