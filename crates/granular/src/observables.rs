//! Spatial observables shared by every many-particle engine: the static structure factor
//! `S(k)` of the density field (Fig. 3 of Müller & Herrmann's DSMC paper) and the coarse-grained density map
//! (the clustering instability of the paper's section 3.2).
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

/// The integer wave-vector indices `n` with `max_k |n_k| <= m`, `n != 0`, one of each pair
/// `+-n` (the half space whose first non-zero component is positive), in the order of
/// the flat index over `[-m, m]^D` with the first axis fastest.
fn half_space_indices<const D: usize>(m: i64) -> Vec<[i64; D]> {
    let side = (2 * m + 1) as usize;
    let total = side.pow(D as u32);
    let mut ns: Vec<[i64; D]> = Vec::new();
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
    ns
}

/// `S(k) = |sum_j exp(i k.x_j)|^2 / N` by a direct Fourier sum over particles for the
/// wave vectors `k = 2 pi (n_0/L_0, ..., n_{D-1}/L_{D-1})`, integer `n` with
/// `max_k |n_k| <= max_index`, `n != 0`, one of each pair `+-n`; bins of width
/// `2 pi / max_k L_k` in `|k|`. Deterministic: partial sums over fixed chunks of
/// particles are added in order. Cost `O(N (2 max_index + 1)^D / 2)` products, done as a
/// blocked outer product (see `chunk_sums`): the same numbers as the plain loop over
/// particles and wave vectors, several times faster.
pub(crate) fn structure_factor<const D: usize>(
    pos: &[Vector<D>],
    lengths: &[f64],
    max_index: usize,
) -> StructureFactor {
    let Some(plan) = SkPlan::<D>::new(lengths, max_index) else {
        return StructureFactor::default();
    };
    if pos.is_empty() {
        return StructureFactor::default();
    }
    let sums: Vec<Vec<(f64, f64)>> = pos
        .par_chunks(SK_CHUNK)
        .map(|chunk| plan.chunk_sums(chunk))
        .collect();
    let mut tot = vec![(0.0, 0.0); plan.sums_len()];
    for part in &sums {
        for (t, p) in tot.iter_mut().zip(part) {
            t.0 += p.0;
            t.1 += p.1;
        }
    }
    plan.shells(&tot, pos.len())
}

/// Particles per chunk of the sums of [`structure_factor`] (in the grains' order): fixed,
/// so that the additions do not depend on the number of threads or ranks.
pub(crate) const SK_CHUNK: usize = 4096;

/// The wave vectors of [`structure_factor`] for a box and a `max_index`: the sums of one
/// chunk of grains ([`SkPlan::chunk_sums`]) and `S(k)` in shells of `|k|` from the sums
/// over all grains ([`SkPlan::shells`]). The run directory's ranks add the chunks of their
/// blocks of grain ids in the same order as [`structure_factor`].
pub(crate) struct SkPlan<const D: usize> {
    ns: Vec<[i64; D]>,
    grid: WaveGrid<D>,
    lengths: Vec<f64>,
}

impl<const D: usize> SkPlan<D> {
    /// `None` when there is no wave vector (`max_index = 0`).
    pub(crate) fn new(lengths: &[f64], max_index: usize) -> Option<Self> {
        let m = max_index as i64;
        let ns = half_space_indices::<D>(m);
        (!ns.is_empty()).then(|| SkPlan {
            ns,
            grid: WaveGrid::<D>::new(m),
            lengths: lengths.to_vec(),
        })
    }

    /// Length of the table of sums (one complex sum per slot of the grid).
    pub(crate) fn sums_len(&self) -> usize {
        self.grid.rows.len() * (2 * self.grid.m + 1) as usize
    }

    /// `sum_j exp(i k.x_j)` over `chunk`, as a table of [`SkPlan::sums_len`] slots.
    pub(crate) fn chunk_sums(&self, chunk: &[Vector<D>]) -> Vec<(f64, f64)> {
        chunk_sums(chunk, &self.lengths, &self.grid)
    }

    /// `S(k)` in shells of `|k|` from the sums `tot` over all `n` grains.
    pub(crate) fn shells(&self, tot: &[(f64, f64)], n: usize) -> StructureFactor {
        let lengths = &self.lengths;
        let lmax = lengths.iter().cloned().fold(0.0, f64::max);
        let dk = 2.0 * PI / lmax;
        let nf = n as f64;
        let mut bins: Vec<(f64, f64, usize)> = Vec::new();
        for n in &self.ns {
            let t = tot[self.grid.slot(n)];
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
}

/// The wave vectors of [`structure_factor`] as a grid: a *row* is a choice of the first
/// `D - 1` components `(n_0, ..., n_{D-2})` whose first non-zero one is positive (every
/// last component `n_{D-1}` in `-m..=m` completes it to a half-space vector), plus the
/// all-zero row (last components `1..=m` only).
struct WaveGrid<const D: usize> {
    m: i64,
    /// The rows' first `D - 1` components; the zero row is the first.
    rows: Vec<[i64; D]>,
    /// Row of each choice of the first `D - 1` components, by flat index (component 0
    /// fastest); `usize::MAX` where it is not a row.
    row_of: Vec<usize>,
}

impl<const D: usize> WaveGrid<D> {
    fn new(m: i64) -> Self {
        let side = (2 * m + 1) as usize;
        let heads = side.pow(D as u32 - 1);
        let mut rows = vec![[0i64; D]];
        let mut row_of = vec![usize::MAX; heads];
        for (flat, slot) in row_of.iter_mut().enumerate() {
            let mut n = [0i64; D];
            let mut r = flat;
            for c in n.iter_mut().take(D - 1) {
                *c = (r % side) as i64 - m;
                r /= side;
            }
            match n.iter().find(|&&c| c != 0) {
                None => *slot = 0,
                Some(&first) if first > 0 => {
                    *slot = rows.len();
                    rows.push(n);
                }
                Some(_) => {}
            }
        }
        Self { m, rows, row_of }
    }

    /// Index of the half-space vector `n` in a row-major `rows x (2m + 1)` table.
    fn slot(&self, n: &[i64; D]) -> usize {
        let side = (2 * self.m + 1) as usize;
        let flat = (0..D - 1)
            .rev()
            .fold(0, |acc, d| acc * side + (n[d] + self.m) as usize);
        self.row_of[flat] * side + (n[D - 1] + self.m) as usize
    }
}

/// Particles per block of [`chunk_sums`]: their row phases fit in a few tens of kB.
const BLOCK_PHASES: usize = 4096;

/// `sum_j exp(i k.x_j)` over the particles of `chunk`, for every vector of `grid` (table
/// of [`WaveGrid::slot`]). Each term is `((1 * p_0) * p_1) ... * p_{D-1}` with
/// `p_d = exp(i 2 pi n_d x_d / L_d)` from the same recurrence as before, and each sum runs
/// over the particles in order, so the result is that of the plain double loop bit for
/// bit; but the loops are blocked (particles in blocks, the last component innermost,
/// real and imaginary parts apart) so the compiler vectorises the products.
fn chunk_sums<const D: usize>(
    chunk: &[Vector<D>],
    lengths: &[f64],
    grid: &WaveGrid<D>,
) -> Vec<(f64, f64)> {
    let m = grid.m;
    let side = (2 * m + 1) as usize;
    let rows = grid.rows.len();
    let block = (BLOCK_PHASES / rows).clamp(1, 64);
    let mut acc_re = vec![0.0f64; rows * side];
    let mut acc_im = vec![0.0f64; rows * side];
    // phase[d][m + n] = exp(i 2 pi n x_d / L_d), n = -m ..= m, of one particle.
    let mut phase = vec![[(0.0f64, 0.0f64); D]; side];
    // Per particle of the block: the row factors and the last axis's phases.
    let mut head = vec![(0.0f64, 0.0f64); block * rows];
    let mut last_re = vec![0.0f64; block * side];
    let mut last_im = vec![0.0f64; block * side];
    for part in chunk.chunks(block) {
        for (j, x) in part.iter().enumerate() {
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
            for (h, row) in head[j * rows..(j + 1) * rows].iter_mut().zip(&grid.rows) {
                let (mut re, mut im) = (1.0, 0.0);
                for d in 0..D - 1 {
                    let (pr, pi) = phase[(row[d] + m) as usize][d];
                    let r = re * pr - im * pi;
                    im = re * pi + im * pr;
                    re = r;
                }
                *h = (re, im);
            }
            for (i, p) in phase.iter().enumerate() {
                last_re[j * side + i] = p[D - 1].0;
                last_im[j * side + i] = p[D - 1].1;
            }
        }
        for r in 0..rows {
            // The zero row holds only positive last components.
            let from = if r == 0 { m as usize + 1 } else { 0 };
            let are = &mut acc_re[r * side + from..(r + 1) * side];
            let aim = &mut acc_im[r * side + from..(r + 1) * side];
            for j in 0..part.len() {
                let (re, im) = head[j * rows + r];
                let pre = &last_re[j * side + from..(j + 1) * side];
                let pim = &last_im[j * side + from..(j + 1) * side];
                for (((ar, ai), &pr), &pi) in are.iter_mut().zip(aim.iter_mut()).zip(pre).zip(pim) {
                    *ar += re * pr - im * pi;
                    *ai += re * pi + im * pr;
                }
            }
        }
    }
    acc_re.into_iter().zip(acc_im).collect()
}

/// Number density on a grid of `dims` bins covering the box (axis 0 fastest).
pub(crate) fn density_map<const D: usize>(
    pos: &[Vector<D>],
    lengths: &[f64],
    dims: [usize; D],
) -> DensityMap {
    let dims = dims.map(|d| d.max(1));
    density_from_counts(density_counts(pos, lengths, dims), lengths, &dims)
}

/// Grains per bin of [`density_map`] (`dims` at least 1 each).
pub(crate) fn density_counts<const D: usize>(
    pos: &[Vector<D>],
    lengths: &[f64],
    dims: [usize; D],
) -> Vec<u64> {
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
    counts
}

/// The [`DensityMap`] of grain counts per bin (`dims` at least 1 each).
pub(crate) fn density_from_counts(counts: Vec<u64>, lengths: &[f64], dims: &[usize]) -> DensityMap {
    let bin_volume: f64 = (0..dims.len())
        .map(|d| lengths[d] / dims[d] as f64)
        .product();
    DensityMap {
        dims: dims.to_vec(),
        values: counts.iter().map(|&c| c as f64 / bin_volume).collect(),
    }
}

/// Copies the row-major positions of a snapshot (`n x D`) into vectors.
pub(crate) fn vectors<const D: usize>(flat: &[f64]) -> Vec<Vector<D>> {
    flat.chunks_exact(D)
        .map(|c| {
            let mut v = Vector::zero();
            v.0.copy_from_slice(c);
            v
        })
        .collect()
}

/// `structure_factor` of a snapshot's positions in a box of edges `lengths` (2D or 3D;
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

/// `density_map` of a snapshot's positions; `dims` has one entry per axis (2D or 3D).
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

    /// The plain double loop that [`structure_factor`] replaced: `S(k) = |sum_j exp(i k.x_j)|^2 / N` by a direct Fourier sum over particles for the
    /// wave vectors `k = 2 pi (n_0/L_0, ..., n_{D-1}/L_{D-1})`, integer `n` with
    /// `max_k |n_k| <= max_index`, `n != 0`, one of each pair `+-n`; bins of width
    /// `2 pi / max_k L_k` in `|k|`. Deterministic: partial sums over fixed chunks of
    /// particles are added in order. Cost `O(N (2 max_index + 1)^D / 2)`.
    fn direct_structure_factor<const D: usize>(
        pos: &[Vector<D>],
        lengths: &[f64],
        max_index: usize,
    ) -> StructureFactor {
        let m = max_index as i64;
        let side = (2 * m + 1) as usize;
        let ns = half_space_indices::<D>(m);
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

    /// Positions from a fixed linear congruential sequence (no RNG needed here).
    fn scattered<const D: usize>(n: usize, lengths: &[f64]) -> Vec<Vector<D>> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let mut v = Vector::zero();
                for (c, l) in v.0.iter_mut().zip(lengths) {
                    *c = next() * l;
                }
                v
            })
            .collect()
    }

    /// The blocked sum gives the plain double loop's numbers bit for bit (2D over two
    /// chunks of particles and a partial block; 3D; a rectangular box).
    #[test]
    fn blocked_structure_factor_is_the_direct_sum_bit_for_bit() {
        let l2 = [1.0, 0.7];
        let p2 = scattered::<2>(5000, &l2);
        for m in [1, 7, 16] {
            assert_eq!(
                structure_factor(&p2, &l2, m),
                direct_structure_factor(&p2, &l2, m),
                "2D m = {m}"
            );
        }
        let l3 = [1.0, 1.3, 0.9];
        let p3 = scattered::<3>(700, &l3);
        for m in [1, 4] {
            assert_eq!(
                structure_factor(&p3, &l3, m),
                direct_structure_factor(&p3, &l3, m),
                "3D m = {m}"
            );
        }
    }

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
