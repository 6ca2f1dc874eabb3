//! Spatial observables shared by every many-particle engine: the static structure factor
//! `S(k)` of the density field (Fig. 3 of the DSMC seed) and the coarse-grained density map
//! (the clustering instability of the seed's section 3.2).
//!
//! They take positions and box lengths only, so the runner computes them alike for the
//! event-driven and the DSMC engines (from [`Snapshot`]s, see [`structure_factor_of`] and
//! [`density_map_of`]).

use crate::engine::Snapshot;
use crate::vector::Vector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// `S(k)` binned by `|k|`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureFactor {
    /// Mean `|k|` of the wave vectors in each bin (inverse length units).
    pub k: Vec<f64>,
    /// Mean `S(k)` over the wave vectors of the bin.
    pub s: Vec<f64>,
    /// Number of wave vectors (counting `k` and `-k` once) in each bin.
    pub count: Vec<usize>,
}

/// A number-density field on a regular grid.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DensityMap {
    /// Bins per axis.
    pub dims: Vec<usize>,
    /// Number density per bin (particles per unit volume), axis 0 fastest.
    pub values: Vec<f64>,
}

/// `S(k) = |sum_j exp(i k.x_j)|^2 / N` by a direct Fourier sum over particles for the
/// wave vectors `k = 2 pi (n_0/L_0, ..., n_{D-1}/L_{D-1})`, integer `n` with
/// `max_k |n_k| <= max_index`, `n != 0`, one of each pair `+-n`; bins of width
/// `2 pi / max_k L_k` in `|k|`. Deterministic: partial sums over fixed chunks of
/// particles are added in order. Cost `O(N (2 max_index + 1)^D / 2)`.
pub fn structure_factor<const D: usize>(
    pos: &[Vector<D>],
    lengths: &[f64],
    max_index: usize,
) -> StructureFactor {
    let m = max_index as i64;
    // Half space: first non-zero component positive.
    let mut ns: Vec<[i64; D]> = Vec::new();
    let side = (2 * m + 1) as usize;
    let total = side.pow(D as u32);
    for flat in 0..total {
        let mut n = [0i64; D];
        let mut r = flat;
        for c in n.iter_mut() {
            *c = (r % side) as i64 - m;
            r /= side;
        }
        if let Some(&first) = n.iter().find(|&&c| c != 0)
            && first > 0
        {
            ns.push(n);
        }
    }
    if ns.is_empty() || pos.is_empty() {
        return StructureFactor::default();
    }
    let kk = ns.len();
    let sums: Vec<Vec<(f64, f64)>> = pos
        .par_chunks(4096)
        .map(|chunk| {
            let mut acc = vec![(0.0, 0.0); kk];
            // phase[k][m + n] = exp(i 2 pi n x_k / L_k), n = -m ..= m
            let mut phase = vec![[(0.0f64, 0.0f64); D]; side];
            for x in chunk {
                for d in 0..D {
                    let a = 2.0 * PI * x[d] / lengths[d];
                    let (s1, c1) = a.sin_cos();
                    let (mut cr, mut ci) = (1.0, 0.0);
                    phase[m as usize][d] = (1.0, 0.0);
                    for n in 1..=m as usize {
                        let nr = cr * c1 - ci * s1;
                        let ni = cr * s1 + ci * c1;
                        cr = nr;
                        ci = ni;
                        phase[m as usize + n][d] = (cr, ci);
                        phase[m as usize - n][d] = (cr, -ci);
                    }
                }
                for (a, n) in acc.iter_mut().zip(&ns) {
                    let (mut re, mut im) = (1.0, 0.0);
                    for d in 0..D {
                        let (pr, pi) = phase[(n[d] + m) as usize][d];
                        let r = re * pr - im * pi;
                        im = re * pi + im * pr;
                        re = r;
                    }
                    a.0 += re;
                    a.1 += im;
                }
            }
            acc
        })
        .collect();
    let mut tot = vec![(0.0, 0.0); kk];
    for part in &sums {
        for (t, p) in tot.iter_mut().zip(part) {
            t.0 += p.0;
            t.1 += p.1;
        }
    }
    let lmax = lengths.iter().cloned().fold(0.0, f64::max);
    let dk = 2.0 * PI / lmax;
    let nf = pos.len() as f64;
    let mut bins: Vec<(f64, f64, usize)> = Vec::new();
    for (n, t) in ns.iter().zip(&tot) {
        let mut k2 = 0.0;
        for d in 0..D {
            let kd = 2.0 * PI * n[d] as f64 / lengths[d];
            k2 += kd * kd;
        }
        let k = k2.sqrt();
        let b = (k / dk + 0.5).floor() as usize;
        if bins.len() <= b {
            bins.resize(b + 1, (0.0, 0.0, 0));
        }
        bins[b].0 += k;
        bins[b].1 += (t.0 * t.0 + t.1 * t.1) / nf;
        bins[b].2 += 1;
    }
    let mut out = StructureFactor::default();
    for (ks, ss, c) in bins.into_iter().filter(|b| b.2 > 0) {
        out.k.push(ks / c as f64);
        out.s.push(ss / c as f64);
        out.count.push(c);
    }
    out
}

/// Number density on a grid of `dims` bins covering the box (axis 0 fastest).
pub fn density_map<const D: usize>(
    pos: &[Vector<D>],
    lengths: &[f64],
    dims: [usize; D],
) -> DensityMap {
    let dims = dims.map(|d| d.max(1));
    let total: usize = dims.iter().product();
    let mut counts = vec![0u64; total];
    for x in pos {
        let mut idx = 0;
        let mut stride = 1;
        for d in 0..D {
            let c = ((x[d] / lengths[d] * dims[d] as f64) as isize).clamp(0, dims[d] as isize - 1);
            idx += c as usize * stride;
            stride *= dims[d];
        }
        counts[idx] += 1;
    }
    let bin_volume: f64 = (0..D).map(|d| lengths[d] / dims[d] as f64).product();
    DensityMap {
        dims: dims.to_vec(),
        values: counts.iter().map(|&c| c as f64 / bin_volume).collect(),
    }
}

/// Copies the row-major positions of a snapshot (`n x D`) into vectors.
fn vectors<const D: usize>(flat: &[f64]) -> Vec<Vector<D>> {
    flat.chunks_exact(D)
        .map(|c| {
            let mut v = Vector::zero();
            v.0.copy_from_slice(c);
            v
        })
        .collect()
}

/// [`structure_factor`] of a snapshot's positions in a box of edges `lengths` (2D or 3D;
/// `None` for other dimensions or when `lengths` does not have `dimension` entries).
pub fn structure_factor_of(
    snapshot: &Snapshot,
    lengths: &[f64],
    max_index: usize,
) -> Option<StructureFactor> {
    if lengths.len() != snapshot.dimension {
        return None;
    }
    match snapshot.dimension {
        2 => Some(structure_factor(
            &vectors::<2>(&snapshot.positions),
            lengths,
            max_index,
        )),
        3 => Some(structure_factor(
            &vectors::<3>(&snapshot.positions),
            lengths,
            max_index,
        )),
        _ => None,
    }
}

/// [`density_map`] of a snapshot's positions; `dims` has one entry per axis (2D or 3D).
pub fn density_map_of(snapshot: &Snapshot, lengths: &[f64], dims: &[usize]) -> Option<DensityMap> {
    if lengths.len() != snapshot.dimension || dims.len() != snapshot.dimension {
        return None;
    }
    match snapshot.dimension {
        2 => Some(density_map(
            &vectors::<2>(&snapshot.positions),
            lengths,
            [dims[0], dims[1]],
        )),
        3 => Some(density_map(
            &vectors::<3>(&snapshot.positions),
            lengths,
            [dims[0], dims[1], dims[2]],
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structure_factor_of_a_lattice_and_density_map() {
        // 4 x 4 square lattice in a unit box: S(k) = 0 for the lowest |n| < 4 modes,
        // except multiples of 4 (Bragg peaks, S = N).
        let mut pos = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                pos.push(Vector([(i as f64 + 0.5) / 4.0, (j as f64 + 0.5) / 4.0]));
            }
        }
        let s = structure_factor(&pos, &[1.0, 1.0], 4);
        // First shell |n| in [0.5, 1.5): (1,0), (0,1), (1,1), (1,-1).
        assert_eq!(s.count[0], 4);
        assert!((s.k[0] - PI * (1.0 + 2f64.sqrt())).abs() < 1e-12);
        assert!(s.s[0].abs() < 1e-20);
        // The |n| = 4 shell holds the Bragg peaks (4,0), (0,4) with S = N = 16.
        let smax = s.s.iter().cloned().fold(0.0, f64::max);
        assert!(smax > 1.0);
        let d = density_map(&pos, &[1.0, 1.0], [2, 2]);
        assert_eq!(d.values, vec![16.0; 4]);
    }
}
