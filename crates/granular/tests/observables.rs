//! The shared spatial observables (`granular::observables`) on states with known answers.

use granular::engine::Snapshot;
use granular::observables::{density_map_of, structure_factor_of};
use granular::random::stream;
use rand::RngExt;

fn uniform_snapshot(dimension: usize, n: usize, seed: u64) -> Snapshot {
    let mut rng = stream(seed, &[1]);
    Snapshot {
        dimension,
        positions: (0..n * dimension).map(|_| rng.random::<f64>()).collect(),
        ..Default::default()
    }
}

/// Ideal gas (independent uniform points): `S(k) = |sum_j exp(i k.x_j)|^2 / N` has mean
/// exactly `1 - delta_{k0}` for every reciprocal-lattice `k != 0`, and for large `N` it is
/// exponentially distributed (variance 1); distinct `k` are uncorrelated. The mode-weighted
/// mean over `M` modes and `R` configurations therefore has standard deviation
/// `1 / sqrt(M R)`; we require 4 of them.
#[test]
fn ideal_gas_structure_factor_is_one() {
    for (dimension, max_index) in [(2, 6), (3, 2)] {
        let (mut sum, mut modes) = (0.0, 0usize);
        for r in 0..10 {
            let snap = uniform_snapshot(dimension, 1000, 100 + r);
            let sk = structure_factor_of(&snap, &vec![1.0; dimension], max_index).unwrap();
            for (s, c) in sk.s.iter().zip(&sk.count) {
                sum += s * *c as f64;
                modes += c;
            }
        }
        let mean = sum / modes as f64;
        let sd = 1.0 / (modes as f64).sqrt();
        assert!(
            (mean - 1.0).abs() < 4.0 * sd,
            "D = {dimension}: mean S(k) = {mean} over {modes} modes, sd {sd}"
        );
    }
}

/// A square lattice has `S(k) = 0` away from Bragg peaks, and the density map of a
/// uniform state integrates to `N`.
#[test]
fn lattice_and_density_map_of_snapshots() {
    let n = 16;
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            positions.extend([(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64]);
        }
    }
    let snap = Snapshot {
        dimension: 2,
        positions,
        ..Default::default()
    };
    let sk = structure_factor_of(&snap, &[1.0, 1.0], 8).unwrap();
    assert!(sk.s.iter().all(|s| s.abs() < 1e-18), "{:?}", sk.s);
    let map = density_map_of(&snap, &[1.0, 1.0], &[4, 8]).unwrap();
    assert_eq!(map.dims, vec![4, 8]);
    let total: f64 = map.values.iter().map(|v| v / 32.0).sum();
    assert!((total - 256.0).abs() < 1e-9);
    assert!(structure_factor_of(&snap, &[1.0], 8).is_none());
    let uniform = uniform_snapshot(3, 500, 7);
    let map = density_map_of(&uniform, &[1.0, 2.0, 1.0], &[2, 2, 2]).unwrap();
    // Bins of 0.5 x 1 x 0.5.
    let total: f64 = map.values.iter().map(|v| v * 0.25).sum();
    assert!((total - 500.0).abs() < 1e-9);
}
