//! Velocity moments of a set of grains: the fourth cumulant `a2` of the peculiar
//! velocities, of all grains and per species (the Sonine coefficient of the homogeneous
//! cooling state, T. P. C. van Noije and M. H. Ernst, Granular Matter 1, 57 (1998);
//! DSMC-4 for one species).

use crate::vector::Vector;

/// `a2 = D/(D+2) <ε²>/<ε>² - 1` of the peculiar kinetic energies `ε = m |v - u|² / 2`
/// (`u` the velocity of the centre of mass of all grains), over all grains and over each
/// species. For grains of one mass this is DSMC-4, `D/(D+2) <c⁴>/<c²>² - 1`; weighting
/// by the mass makes the value of a mixture zero in equilibrium (a Gaussian of each
/// species at one temperature). `grain(i)` gives the species, mass and velocity of grain
/// `i < n`; it is called twice per grain. NaN for a species without grains or with all
/// grains at rest.
pub(crate) fn a2_by_species<const D: usize>(
    n: usize,
    species: usize,
    grain: impl Fn(usize) -> (usize, f64, Vector<D>),
) -> (f64, Vec<f64>) {
    let mut momentum = Vector::<D>::zero();
    let mut mass = 0.0;
    for i in 0..n {
        let (_, m, v) = grain(i);
        momentum = momentum.add_scaled(m, &v);
        mass += m;
    }
    let u = Vector::<D>::zero().add_scaled(1.0 / mass, &momentum);
    // Per species and (last) all: grains, Σ ε, Σ ε².
    let mut sums = vec![(0u64, 0.0f64, 0.0f64); species + 1];
    for i in 0..n {
        let (s, m, v) = grain(i);
        let e = 0.5 * m * (v - u).norm_squared();
        for k in [s.min(species), species] {
            let t = &mut sums[k];
            t.0 += 1;
            t.1 += e;
            t.2 += e * e;
        }
    }
    let d = D as f64;
    let a2 = |(count, s1, s2): (u64, f64, f64)| {
        let c = count as f64;
        d / (d + 2.0) * (s2 / c) / ((s1 / c) * (s1 / c)) - 1.0
    };
    let all = a2(sums[species]);
    (all, sums[..species].iter().map(|&t| a2(t)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;
    use rand::RngExt;
    use rand_distr::StandardNormal;

    /// Gaussian velocities of two species at one temperature, drifting together: a2 is
    /// zero within its sampling error, `sqrt(Var(a2)) ≈ sqrt(8/(D(D+2)) / N)`.
    #[test]
    fn a_maxwellian_mixture_has_zero_a2() {
        let n = 200_000;
        let mut rng = stream(3, &[1]);
        let masses = [1.0f64, 4.0];
        let grains: Vec<(usize, f64, Vector<2>)> = (0..n)
            .map(|i| {
                let s = i % 2;
                let sd = (1.0 / masses[s]).sqrt();
                let v = Vector([
                    5.0 + sd * rng.sample::<f64, _>(StandardNormal),
                    -1.0 + sd * rng.sample::<f64, _>(StandardNormal),
                ]);
                (s, masses[s], v)
            })
            .collect();
        let (all, per) = a2_by_species(n, 2, |i| grains[i]);
        let sigma = |count: f64| (8.0 / 8.0 / count).sqrt();
        assert!(all.abs() < 4.0 * sigma(n as f64), "all: {all}");
        for a in per {
            assert!(a.abs() < 4.0 * sigma(n as f64 / 2.0), "species: {a}");
        }
    }

    /// Speeds of one value in 2D: ε constant, so `<ε²>/<ε>² = 1` and `a2 = 1/2 - 1`.
    #[test]
    fn equal_speeds_give_minus_one_half() {
        let grains: Vec<Vector<2>> = (0..1000)
            .map(|i| {
                let a = i as f64 * 2.0 * std::f64::consts::PI / 1000.0;
                Vector([a.cos(), a.sin()])
            })
            .collect();
        let (all, per) = a2_by_species(1000, 1, |i| (0, 2.0, grains[i]));
        assert!((all + 0.5).abs() < 1e-12, "{all}");
        assert_eq!(per[0], all);
    }
}
