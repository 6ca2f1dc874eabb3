//! The radial pair correlation function `g(r)` of a hard-grain gas, per pair of species,
//! and its contact value `g(σ)`.
//!
//! `g_ab(r)` is the number of pairs of grains of species `a` and `b` whose centres are a
//! distance in `[r, r + Δr)` apart, divided by the number an ideal gas of the same grains
//! in the same box would have (the *exact* pair-distance density of the box, so that an
//! ideal gas gives `g = 1` in every bin, also next to walls):
//!
//! `P(r) dr = S_D r^(D-1) K(r) dr / A²`, with `A = Π_k a_k` and `K(r)` the angular average
//! of the set covariogram `γ(x) = Π_k (a_k - |x_k|)` of the box of centres (Matheron,
//! *Random Sets and Integral Geometry*, 1975; for the rectangle this gives the classical
//! distribution of the distance between two uniform points, Ghosh, Calcutta Math. Soc.
//! Bull. 43, 17 (1951)). On a periodic axis `a_k = L_k` and the factor is constant; on a
//! walled axis `a_k = L_k - R_a - R_b` (the length open to the centres; exact for one
//! species, to `O((R_a - R_b)²)` for two radii) and contributes `a_k - r |u_k|`. The
//! angular averages of products of `|u_k|` over the unit sphere are
//! `<|u_1|> = 2/π, <|u_1 u_2|> = 1/π` in 2D and `1/2, 2/(3π), 1/(4π)` in 3D, so `K(r)` is
//! a polynomial, valid for `r <= a_k` on walled axes and `r <= L_k / 2` on periodic axes
//! (the minimum image), and the expected count of a bin is its exact integral. In a fully
//! periodic box this is the ideal-gas shell `v_D (r₂^D - r₁^D) / V`.
//!
//! Pairs are counted with a cell list of edge `>= r_max` (cost `O(N n r_max^D)` per
//! sample), or directly over all pairs (`O(N²)`) when an axis holds fewer than three
//! cells, i.e. in boxes smaller than `3 r_max`.
//!
//! The contact value `g(σ_ab)`, `σ_ab = R_a + R_b`, is extrapolated from the first
//! [`CONTACT_FIT_BINS`] bins above contact: a weighted least-squares straight line through
//! `ln g` at the bin centres (weights the bin counts, the inverse Poisson variance of
//! `ln g`), evaluated at `σ_ab`. Its error comes from blocks of consecutive samples
//! ([`PairCorrelation::contact_value`]). For one species the pressure follows from the contact theorem,
//! `Z = P / (n T) = 1 + 2^(D-1) φ g(σ) (N - 1) / N` (the factor `(N - 1)/N` because `g` is
//! normalised by the `N (N - 1) / 2` pairs of a finite box).

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Bins above contact that the contact-value fit uses.
pub const CONTACT_FIT_BINS: usize = 4;

/// Blocks of consecutive samples for the error of the contact value.
pub const CONTACT_BLOCKS: usize = 10;

/// What the pair counter needs to know about the box and the grains.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairGeometry {
    /// Edge lengths (length units).
    pub lengths: Vec<f64>,
    /// Whether each axis is periodic (else walled).
    pub periodic: Vec<bool>,
    /// Radius per species (length units).
    pub radii: Vec<f64>,
    /// Grains per species.
    pub counts: Vec<usize>,
}

impl PairGeometry {
    /// Dimension `D`.
    pub fn dimension(&self) -> usize {
        self.lengths.len()
    }

    /// The largest `r` at which the exact normalisation holds for the pair `(a, b)`:
    /// half the shortest periodic edge, the shortest accessible walled edge.
    pub fn max_distance(&self, a: usize, b: usize) -> f64 {
        let reach = self.radii[a] + self.radii[b];
        self.lengths
            .iter()
            .zip(&self.periodic)
            .map(|(&l, &p)| if p { 0.5 * l } else { l - reach })
            .fold(f64::INFINITY, f64::min)
    }

    /// Species pairs `(a, b)`, `a <= b`, in the order of the columns.
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        let s = self.radii.len();
        (0..s).flat_map(|a| (a..s).map(move |b| (a, b))).collect()
    }

    /// Ideal-gas pairs of the species pair `(a, b)` expected in `[r1, r2)` in one sample
    /// (see the module documentation).
    pub fn ideal_pairs(&self, a: usize, b: usize, r1: f64, r2: f64) -> f64 {
        let d = self.dimension();
        let reach = self.radii[a] + self.radii[b];
        let access: Vec<f64> = self
            .lengths
            .iter()
            .zip(&self.periodic)
            .map(|(&l, &p)| if p { l } else { l - reach })
            .collect();
        let area: f64 = access.iter().product();
        // <Π_{k in S} |u_k|> over the unit sphere for |S| = 0..=D.
        let mean_abs: &[f64] = if d == 2 {
            &[1.0, 2.0 / PI, 1.0 / PI]
        } else {
            &[1.0, 0.5, 2.0 / (3.0 * PI), 1.0 / (4.0 * PI)]
        };
        let sphere = if d == 2 { 2.0 * PI } else { 4.0 * PI };
        let mut integral = 0.0;
        for subset in 0u32..(1 << d) {
            if (0..d).any(|k| subset & (1 << k) != 0 && self.periodic[k]) {
                continue;
            }
            let s = subset.count_ones() as usize;
            let rest: f64 = (0..d)
                .filter(|k| subset & (1 << k) == 0)
                .map(|k| access[k])
                .product();
            let p = (d + s) as i32;
            let sign = if s.is_multiple_of(2) { 1.0 } else { -1.0 };
            integral += sign * mean_abs[s] * rest * (r2.powi(p) - r1.powi(p)) / p as f64;
        }
        let pairs = if a == b {
            let n = self.counts[a] as f64;
            0.5 * n * (n - 1.0)
        } else {
            self.counts[a] as f64 * self.counts[b] as f64
        };
        pairs * sphere * integral / (area * area)
    }
}

/// Counts of pair distances per species pair and bin, accumulated over samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairCorrelation {
    /// The box and grains.
    pub geometry: PairGeometry,
    /// Bins over `[0, r_max)`.
    pub bins: usize,
    /// Largest distance (length units).
    pub r_max: f64,
    /// Counts per species pair (in [`PairGeometry::pairs`] order) and bin, summed over
    /// samples.
    pub counts: Vec<Vec<u64>>,
    /// Samples accumulated.
    pub samples: u64,
    /// Per sample, per species pair: the counts of the contact-fit bins (for the block
    /// error of the contact value).
    pub contact_rows: Vec<Vec<Vec<u64>>>,
}

impl PairCorrelation {
    /// An empty accumulator; an error (what is wrong and the largest allowed `r_max`) when
    /// `r_max` exceeds the range of the exact normalisation of some pair.
    pub fn new(geometry: PairGeometry, bins: usize, r_max: f64) -> Result<Self, String> {
        let d = geometry.dimension();
        if !(d == 2 || d == 3) {
            return Err(format!(
                "g(r) is defined here for 2D and 3D boxes, not {d}D"
            ));
        }
        let limit = geometry
            .pairs()
            .iter()
            .map(|&(a, b)| geometry.max_distance(a, b))
            .fold(f64::INFINITY, f64::min);
        if !(r_max > 0.0 && r_max <= limit) {
            return Err(format!(
                "reaches r = {r_max}, beyond the {limit} up to which the box's pair-distance density is exact (half the shortest periodic edge, the shortest walled edge less a diameter)"
            ));
        }
        let pairs = geometry.pairs().len();
        Ok(PairCorrelation {
            geometry,
            bins,
            r_max,
            counts: vec![vec![0; bins]; pairs],
            samples: 0,
            contact_rows: Vec::new(),
        })
    }

    /// Bin width (length units).
    pub fn width(&self) -> f64 {
        self.r_max / self.bins as f64
    }

    /// Bin centres (length units).
    pub fn centres(&self) -> Vec<f64> {
        (0..self.bins)
            .map(|b| (b as f64 + 0.5) * self.width())
            .collect()
    }

    /// Index of the first bin whose lower edge is at or above contact, for pair `p`.
    fn first_contact_bin(&self, p: usize) -> usize {
        let (a, b) = self.geometry.pairs()[p];
        let sigma = self.geometry.radii[a] + self.geometry.radii[b];
        ((sigma / self.width()) * (1.0 - 1e-9)).ceil() as usize
    }

    /// Adds one sample: positions (`n * D`, row-major) and species index per grain.
    pub fn add(&mut self, positions: &[f64], species: &[u32]) {
        let hist = pair_histogram(&self.geometry, positions, species, self.bins, self.r_max);
        let rows = (0..hist.len())
            .map(|p| {
                let first = self.first_contact_bin(p);
                (first..(first + CONTACT_FIT_BINS).min(self.bins))
                    .map(|b| hist[p][b])
                    .collect()
            })
            .collect();
        self.contact_rows.push(rows);
        for (total, h) in self.counts.iter_mut().zip(&hist) {
            for (t, c) in total.iter_mut().zip(h) {
                *t += c;
            }
        }
        self.samples += 1;
    }

    /// `g(r)` per species pair and bin (NaN before the first sample).
    pub fn g(&self) -> Vec<Vec<f64>> {
        let w = self.width();
        self.geometry
            .pairs()
            .iter()
            .zip(&self.counts)
            .map(|(&(a, b), counts)| {
                counts
                    .iter()
                    .enumerate()
                    .map(|(k, &c)| {
                        let ideal =
                            self.geometry
                                .ideal_pairs(a, b, k as f64 * w, (k + 1) as f64 * w);
                        c as f64 / (ideal * self.samples as f64)
                    })
                    .collect()
            })
            .collect()
    }

    /// The contact value `g(σ_ab)` of pair `p` with its standard error (blocks of
    /// consecutive samples, [`CONTACT_BLOCKS`] of them or one per sample when fewer; NaN
    /// error with fewer than two blocks). `None` when the fit bins lie beyond `r_max` or
    /// hold no pairs.
    pub fn contact_value(&self, p: usize) -> Option<(f64, f64)> {
        let (a, b) = self.geometry.pairs()[p];
        let first = self.first_contact_bin(p);
        if first + CONTACT_FIT_BINS > self.bins {
            return None;
        }
        let w = self.width();
        let sigma = self.geometry.radii[a] + self.geometry.radii[b];
        let bins: Vec<(f64, f64)> = (first..first + CONTACT_FIT_BINS)
            .map(|k| {
                let centre = (k as f64 + 0.5) * w - sigma;
                let ideal = self
                    .geometry
                    .ideal_pairs(a, b, k as f64 * w, (k + 1) as f64 * w);
                (centre, ideal)
            })
            .collect();
        let fit = |rows: &[Vec<Vec<u64>>]| -> Option<f64> {
            let n = rows.len() as f64;
            let counts: Vec<u64> = (0..CONTACT_FIT_BINS)
                .map(|i| rows.iter().map(|r| r[p][i]).sum())
                .collect();
            let points: Vec<(f64, f64, f64)> = bins
                .iter()
                .zip(&counts)
                .map(|(&(x, ideal), &c)| (x, (c as f64 / (ideal * n)).ln(), c as f64))
                .collect();
            exp_extrapolation(&points)
        };
        let value = fit(&self.contact_rows)?;
        let blocks = CONTACT_BLOCKS.min(self.contact_rows.len());
        let per = self.contact_rows.len() / blocks.max(1);
        let block_values: Vec<f64> = (0..blocks)
            .filter_map(|k| fit(&self.contact_rows[k * per..(k + 1) * per]))
            .collect();
        let error = if block_values.len() >= 2 && block_values.len() == blocks {
            let m = block_values.len() as f64;
            let mean = block_values.iter().sum::<f64>() / m;
            let var = block_values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1.0);
            (var / m).sqrt()
        } else {
            f64::NAN
        };
        Some((value, error))
    }
}

/// `exp(α)` of the weighted least-squares line `ln g = α + β x` through points
/// `(x, ln g, weight)`; `None` when a bin is empty.
fn exp_extrapolation(points: &[(f64, f64, f64)]) -> Option<f64> {
    if points.len() < 2 || points.iter().any(|&(_, y, w)| w <= 0.0 || !y.is_finite()) {
        return None;
    }
    let sw: f64 = points.iter().map(|p| p.2).sum();
    let mx = points.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let my = points.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = points.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| p.2 * (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    Some((my - slope * mx).exp())
}

/// Histogram of pair distances below `r_max` per species pair (one sample).
pub fn pair_histogram(
    geometry: &PairGeometry,
    positions: &[f64],
    species: &[u32],
    bins: usize,
    r_max: f64,
) -> Vec<Vec<u64>> {
    let d = geometry.dimension();
    let s = geometry.radii.len();
    let mut pair_index = vec![0usize; s * s];
    for (p, &(a, b)) in geometry.pairs().iter().enumerate() {
        pair_index[a * s + b] = p;
        pair_index[b * s + a] = p;
    }
    let npairs = geometry.pairs().len();
    let n = species.len();
    let scale = bins as f64 / r_max;
    let r2max = r_max * r_max;
    let separation = |i: usize, j: usize| -> f64 {
        let mut r2 = 0.0;
        for k in 0..d {
            let mut dx = positions[i * d + k] - positions[j * d + k];
            if geometry.periodic[k] {
                let l = geometry.lengths[k];
                dx -= l * (dx / l).round();
            }
            r2 += dx * dx;
        }
        r2
    };
    let record = |hist: &mut Vec<u64>, i: usize, j: usize| {
        let r2 = separation(i, j);
        if r2 < r2max {
            let bin = ((r2.sqrt() * scale) as usize).min(bins - 1);
            let p = pair_index[species[i] as usize * s + species[j] as usize];
            hist[p * bins + bin] += 1;
        }
    };
    let cells: Vec<usize> = geometry
        .lengths
        .iter()
        .map(|&l| ((l / r_max).floor() as usize).max(1))
        .collect();
    let flat = if cells.iter().any(|&c| c < 3) {
        // Direct count over all pairs (boxes smaller than three r_max on an axis).
        (0..n)
            .into_par_iter()
            .fold(
                || vec![0u64; npairs * bins],
                |mut h, i| {
                    for j in i + 1..n {
                        record(&mut h, i, j);
                    }
                    h
                },
            )
            .reduce(|| vec![0u64; npairs * bins], add_counts)
    } else {
        // Cell of each grain (axis 0 fastest), then the grains sorted by cell.
        let cell_of = |i: usize| -> usize {
            let mut f = 0;
            for k in (0..d).rev() {
                let x = (positions[i * d + k] / geometry.lengths[k]).rem_euclid(1.0);
                f = f * cells[k] + ((x * cells[k] as f64) as usize).min(cells[k] - 1);
            }
            f
        };
        let total: usize = cells.iter().product();
        let cell: Vec<usize> = (0..n).map(cell_of).collect();
        let mut start = vec![0usize; total + 1];
        for &c in &cell {
            start[c + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut order = vec![0usize; n];
        for (i, &c) in cell.iter().enumerate() {
            order[fill[c]] = i;
            fill[c] += 1;
        }
        let neighbours = 3usize.pow(d as u32);
        (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .fold(
                || vec![0u64; npairs * bins],
                |mut h, i| {
                    let mut c = [0i64; 3];
                    let mut rest = cell[i];
                    for k in 0..d {
                        c[k] = (rest % cells[k]) as i64;
                        rest /= cells[k];
                    }
                    'offsets: for f in 0..neighbours {
                        let mut flat = 0usize;
                        let mut code = f;
                        let mut stride = 1usize;
                        for k in 0..d {
                            let m = cells[k] as i64;
                            let v = c[k] + (code % 3) as i64 - 1;
                            code /= 3;
                            let v = if geometry.periodic[k] {
                                v.rem_euclid(m)
                            } else if (0..m).contains(&v) {
                                v
                            } else {
                                continue 'offsets;
                            };
                            flat += v as usize * stride;
                            stride *= cells[k];
                        }
                        for &j in &order[start[flat]..start[flat + 1]] {
                            if j > i {
                                record(&mut h, i, j);
                            }
                        }
                    }
                    h
                },
            )
            .reduce(|| vec![0u64; npairs * bins], add_counts)
    };
    flat.chunks(bins).map(|c| c.to_vec()).collect()
}

fn add_counts(mut a: Vec<u64>, b: Vec<u64>) -> Vec<u64> {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{open01, stream};

    /// `n` points uniform in the box, `margin` from its faces on walled axes.
    fn uniform(n: usize, lengths: &[f64], periodic: &[bool], margin: f64, seed: u64) -> Vec<f64> {
        let mut rng = stream(seed, &[]);
        (0..n)
            .flat_map(|_| {
                lengths
                    .iter()
                    .zip(periodic)
                    .map(|(&l, &p)| {
                        let m = if p { 0.0 } else { margin };
                        m + open01(&mut rng) * (l - 2.0 * m)
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// An ideal gas (uniform points) gives `g = 1` in every bin within its error (the
    /// spread over 20 independent batches: in a walled box pair counts sharing a grain
    /// are correlated, so Poisson errors would be too small), in a periodic, a walled and
    /// a mixed box, 2D and 3D: the normalisation is the exact pair-distance density.
    #[test]
    fn ideal_gas_has_unit_pair_correlation() {
        for (lengths, periodic) in [
            (vec![1.0, 1.5], vec![true, true]),
            (vec![1.0, 1.5], vec![false, false]),
            (vec![1.0, 1.2, 0.8], vec![false, true, false]),
        ] {
            let n = 300;
            let radius = 0.01;
            let geometry = PairGeometry {
                lengths: lengths.clone(),
                periodic: periodic.clone(),
                radii: vec![radius],
                counts: vec![n],
            };
            let r_max = geometry.max_distance(0, 0).min(0.4);
            let species = vec![0u32; n];
            let batches: Vec<Vec<f64>> = (0..20)
                .map(|batch| {
                    let mut g = PairCorrelation::new(geometry.clone(), 10, r_max).unwrap();
                    for seed in 0..20 {
                        let x = uniform(n, &lengths, &periodic, radius, 100 * batch + seed);
                        g.add(&x, &species);
                    }
                    g.g().remove(0)
                })
                .collect();
            for k in 0..10 {
                let values: Vec<f64> = batches.iter().map(|b| b[k]).collect();
                let m = values.len() as f64;
                let mean = values.iter().sum::<f64>() / m;
                let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1.0);
                let error = (var / m).sqrt();
                assert!(
                    (mean - 1.0).abs() < 4.0 * error,
                    "{lengths:?} {periodic:?} bin {k}: g = {mean} +- {error}"
                );
            }
        }
    }

    /// The cell list counts the same pairs as a direct loop over all pairs.
    #[test]
    fn cell_list_matches_direct_count() {
        let lengths = vec![1.0, 1.0];
        let x = uniform(500, &lengths, &[true, true], 0.0, 7);
        let species: Vec<u32> = (0..500).map(|i| (i % 2) as u32).collect();
        let geometry = PairGeometry {
            lengths,
            periodic: vec![true, false],
            radii: vec![0.01, 0.02],
            counts: vec![250, 250],
        };
        let fast = pair_histogram(&geometry, &x, &species, 10, 0.1);
        for p in 0..3 {
            let a: u64 = fast[p].iter().sum();
            let exact: u64 = (0..500)
                .flat_map(|i| (i + 1..500).map(move |j| (i, j)))
                .filter(|&(i, j)| {
                    let pair = [species[i].min(species[j]), species[i].max(species[j])];
                    let want = [[0, 0], [0, 1], [1, 1]][p];
                    pair == want && {
                        let mut dx = x[2 * i] - x[2 * j];
                        dx -= dx.round();
                        let dy = x[2 * i + 1] - x[2 * j + 1];
                        dx * dx + dy * dy < 0.01
                    }
                })
                .count() as u64;
            assert_eq!(a, exact, "pair {p}");
        }
    }
}
