//! Single-grain transport: the mean-square displacement `<|x(t+τ) - x(t)|²>` and the
//! velocity autocorrelation `<v(t) · v(t+τ)>` on logarithmically spaced lags, and the
//! self-diffusion coefficient from both (Einstein and Green-Kubo).
//!
//! **Samples.** The correlator is fed samples spaced by a fixed interval `Δ` (the output
//! interval): unwrapped positions and velocities of all grains ([`Unwrapper`] removes the
//! periodic wraps).
//!
//! **Log-lag scheme** ([`LogLagCorrelator`]): level `k` keeps the last [`POINTS`] samples
//! taken every `2^k Δ` (the samples themselves, no block averages, so that every lag is
//! exact). Each new sample of a level is correlated with the ones it keeps: level 0 gives
//! the lags `0, 1, ..., p - 1` (in units of `Δ`), level `k >= 1` the lags
//! `j 2^k`, `j = p/2, ..., p - 1`, so lags grow geometrically with `p/2` lags per octave.
//! This is the multiple-tau correlator of Ramírez, Sukumaran, Vorselaars and Likhtman
//! (J. Chem. Phys. 133, 154103 (2010)) with decimation instead of averaging. Memory is
//! `2 p N D` numbers per level and levels are added as the run reaches their lag: it grows
//! as `log₂` of the run length, bounded by [`MAX_LEVELS`]; the work per sample is about
//! `1.5 p N D` operations.
//!
//! **Errors.** The sums are kept per group of grains (each species split into
//! [`GROUPS`] groups by index). Grains of a dilute or moderately dense gas move nearly
//! independently, so the spread of a quantity over groups gives its standard error
//! (the mean over groups is the estimate).
//!
//! **Diffusion.** `D_s` is the slope of a straight line through the MSD over a lag window
//! divided by `2 D` (Einstein); the Green-Kubo value is `(1/D) ∫₀^τ C(s) ds`, the
//! trapezoid rule over the lags up to the start of the window (the MSD's slope at `τ` is
//! `2 ∫₀^τ C`, so both agree once `C` has decayed).

use serde::{Deserialize, Serialize};

/// Samples kept per level (`p`; even).
pub const POINTS: usize = 16;
/// Most levels: lags up to `p 2^(MAX_LEVELS - 1) Δ`.
pub const MAX_LEVELS: usize = 40;
/// Groups of grains per species for the error estimates.
pub const GROUPS: usize = 16;

/// Minimum-image unwrapping of positions sampled at intervals, with a guard against
/// ambiguous wraps: between two samples no grain may have moved half a periodic edge.
/// No grain is faster than `sqrt(2 K / m)` (it cannot hold more than the total kinetic
/// energy `K`), so the guard is `Δt sqrt(2 K_max / m_min) < L_k / 2` with `K_max` the
/// larger kinetic energy of the two samples: rigorous when no energy is injected between
/// samples (elastic or inelastic collisions, fixed walls, no gravity or driving).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Unwrapper {
    /// Edge lengths.
    pub lengths: Vec<f64>,
    /// Periodic axes.
    pub periodic: Vec<bool>,
    /// Wrapped positions at the previous sample.
    pub previous: Vec<f64>,
    /// Unwrapped positions.
    pub unwrapped: Vec<f64>,
    /// Time of the previous sample.
    pub time: f64,
    /// Kinetic energy at the previous sample.
    pub kinetic_energy: f64,
}

impl Unwrapper {
    /// Starts at the wrapped `positions` (`n * D`) at `time`.
    pub fn new(
        lengths: Vec<f64>,
        periodic: Vec<bool>,
        positions: &[f64],
        time: f64,
        kinetic_energy: f64,
    ) -> Unwrapper {
        Unwrapper {
            lengths,
            periodic,
            previous: positions.to_vec(),
            unwrapped: positions.to_vec(),
            time,
            kinetic_energy,
        }
    }

    /// The longest interval between samples the guard accepts at kinetic energy `k` and
    /// lightest mass `m_min` (infinite without periodic axes).
    pub fn max_interval(&self, k: f64, m_min: f64) -> f64 {
        let speed = (2.0 * k / m_min).sqrt();
        self.lengths
            .iter()
            .zip(&self.periodic)
            .filter(|(_, p)| **p)
            .map(|(&l, _)| 0.5 * l / speed)
            .fold(f64::INFINITY, f64::min)
    }

    /// Moves to the next sample; an error (the interval and the longest allowed) when a
    /// grain could have crossed half a periodic edge since the previous one.
    pub fn update(
        &mut self,
        positions: &[f64],
        time: f64,
        kinetic_energy: f64,
        m_min: f64,
    ) -> Result<&[f64], String> {
        let dt = time - self.time;
        let allowed = self.max_interval(self.kinetic_energy.max(kinetic_energy), m_min);
        if dt >= allowed {
            return Err(format!(
                "the samples are {dt} apart; a grain as fast as the kinetic energy allows could cross half a periodic edge in {allowed}, so the periodic images are ambiguous"
            ));
        }
        let d = self.lengths.len();
        for (i, (&x, prev)) in positions.iter().zip(self.previous.iter_mut()).enumerate() {
            let k = i % d;
            let mut dx = x - *prev;
            if self.periodic[k] {
                let l = self.lengths[k];
                dx -= l * (dx / l).round();
            }
            self.unwrapped[i] += dx;
            *prev = x;
        }
        self.time = time;
        self.kinetic_energy = kinetic_energy;
        Ok(&self.unwrapped)
    }
}

/// One level of the correlator: the last samples taken every `2^k Δ`, newest last.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
struct Level {
    positions: std::collections::VecDeque<Vec<f64>>,
    velocities: std::collections::VecDeque<Vec<f64>>,
}

/// Mean-square displacement and velocity autocorrelation on log-spaced lags, summed per
/// group of grains (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogLagCorrelator {
    dimension: usize,
    /// Group of each grain.
    group: Vec<u32>,
    /// Grains per group.
    pub group_sizes: Vec<usize>,
    /// Species of each group.
    pub group_species: Vec<usize>,
    /// Samples fed.
    pub samples: u64,
    levels: Vec<Level>,
    /// Lags in units of the sample interval, increasing.
    pub lags: Vec<u64>,
    /// Time origins summed per lag.
    pub origins: Vec<u64>,
    /// Per lag, per group: `Σ |Δx|²`.
    pub msd_sums: Vec<Vec<f64>>,
    /// Per lag, per group: `Σ v(t) · v(t + τ)`.
    pub vacf_sums: Vec<Vec<f64>>,
}

impl LogLagCorrelator {
    /// A correlator for grains of the given species (index per grain, `species_count`
    /// species).
    #[cfg(test)]
    pub fn new(dimension: usize, species: &[u32], species_count: usize) -> LogLagCorrelator {
        let totals: Vec<usize> = (0..species_count)
            .map(|s| species.iter().filter(|&&x| x as usize == s).count())
            .collect();
        LogLagCorrelator::for_block(dimension, species, &vec![0; species_count], &totals)
    }

    /// A correlator for a block of consecutive grains of a larger system (a rank's block
    /// of ids): `species` per grain of the block, `before[s]` the grains of species `s`
    /// before the block, `totals[s]` those of the whole system. Its sums are the whole
    /// system's when every block's grains are folded in order
    /// ([`LogLagCorrelator::add_chained`]); the whole system is the block of all grains.
    pub fn for_block(
        dimension: usize,
        species: &[u32],
        before: &[usize],
        totals: &[usize],
    ) -> LogLagCorrelator {
        let species_count = totals.len();
        let groups: Vec<usize> = totals.iter().map(|&n| n.clamp(1, GROUPS)).collect();
        let offsets: Vec<usize> = groups
            .iter()
            .scan(0, |acc, &g| {
                let o = *acc;
                *acc += g;
                Some(o)
            })
            .collect();
        let mut seen = before.to_vec();
        let group: Vec<u32> = species
            .iter()
            .map(|&s| {
                let s = s as usize;
                let g = offsets[s] + seen[s] % groups[s];
                seen[s] += 1;
                g as u32
            })
            .collect();
        let total: usize = groups.iter().sum();
        // Grain `j` of species `s` is in group `j mod G_s`.
        let mut group_sizes = vec![0usize; total];
        for s in 0..species_count {
            for g in 0..groups[s] {
                group_sizes[offsets[s] + g] =
                    totals[s] / groups[s] + usize::from(g < totals[s] % groups[s]);
            }
        }
        let group_species = (0..species_count)
            .flat_map(|s| std::iter::repeat_n(s, groups[s]))
            .collect();
        let mut lags: Vec<u64> = (0..POINTS as u64).collect();
        for k in 1..MAX_LEVELS {
            lags.extend((POINTS / 2..POINTS).map(|j| (j as u64) << k));
        }
        let n = lags.len();
        LogLagCorrelator {
            dimension,
            group,
            group_sizes,
            group_species,
            samples: 0,
            levels: Vec::new(),
            lags,
            origins: vec![0; n],
            msd_sums: vec![vec![0.0; total]; n],
            vacf_sums: vec![vec![0.0; total]; n],
        }
    }

    /// Index into `lags` of lag `j` of level `k`.
    fn lag_index(k: usize, j: usize) -> usize {
        if k == 0 {
            j
        } else {
            POINTS + (k - 1) * (POINTS / 2) + (j - POINTS / 2)
        }
    }

    /// Feeds one sample: unwrapped positions and velocities (`n * D` each).
    #[cfg(test)]
    pub fn add(&mut self, positions: &[f64], velocities: &[f64]) {
        self.add_chained(positions, velocities, &mut |acc, fold| fold(acc));
    }

    /// Feeds one sample of this block's grains (`positions`, `velocities`: the block's
    /// unwrapped positions and velocities). The sums of the lags the sample reaches are
    /// continued over the grains in order: `chain(acc, fold)` must return `acc` folded
    /// over every block's grains in id order (`fold` folds this block's), for one block
    /// `fold(acc)` (as [`LogLagCorrelator::add`]); over the ranks of a decomposed run
    /// the chained sum of the run's outputs that hands the accumulator from rank to rank. The
    /// additions are those of one loop over all grains, in its order.
    pub fn add_chained(&mut self, positions: &[f64], velocities: &[f64], chain: &mut Chain<'_>) {
        let count = self.samples;
        self.samples += 1;
        // The (level, lag) pairs this sample reaches.
        let mut reached: Vec<(usize, usize)> = Vec::new();
        for k in 0..MAX_LEVELS {
            if !count.is_multiple_of(1u64 << k) {
                break;
            }
            if self.levels.len() <= k {
                self.levels.push(Level::default());
            }
            let level = &mut self.levels[k];
            if level.positions.len() == POINTS {
                level.positions.pop_front();
                level.velocities.pop_front();
            }
            level.positions.push_back(positions.to_vec());
            level.velocities.push_back(velocities.to_vec());
            let first = if k == 0 { 0 } else { POINTS / 2 };
            reached.extend((first..level.positions.len()).map(|j| (k, j)));
        }
        let groups = self.group_sizes.len();
        let mut acc = Vec::with_capacity(2 * groups * reached.len());
        for &(k, j) in &reached {
            let index = Self::lag_index(k, j);
            acc.extend_from_slice(&self.msd_sums[index]);
            acc.extend_from_slice(&self.vacf_sums[index]);
        }
        let d = self.dimension;
        let (levels, group) = (&self.levels, &self.group);
        let mut fold = |mut acc: Vec<f64>| {
            for (r, &(k, j)) in reached.iter().enumerate() {
                let level = &levels[k];
                let held = level.positions.len();
                let (x, v) = (&level.positions[held - 1], &level.velocities[held - 1]);
                let old_x = &level.positions[held - 1 - j];
                let old_v = &level.velocities[held - 1 - j];
                let (msd, vacf) = acc[2 * r * groups..2 * (r + 1) * groups].split_at_mut(groups);
                for (i, &g) in group.iter().enumerate() {
                    let mut dx2 = 0.0;
                    let mut vv = 0.0;
                    for c in i * d..(i + 1) * d {
                        let dx = x[c] - old_x[c];
                        dx2 += dx * dx;
                        vv += v[c] * old_v[c];
                    }
                    msd[g as usize] += dx2;
                    vacf[g as usize] += vv;
                }
            }
            acc
        };
        let acc = chain(acc, &mut fold);
        for (r, &(k, j)) in reached.iter().enumerate() {
            let index = Self::lag_index(k, j);
            let part = &acc[2 * r * groups..2 * (r + 1) * groups];
            self.msd_sums[index].copy_from_slice(&part[..groups]);
            self.vacf_sums[index].copy_from_slice(&part[groups..]);
            self.origins[index] += 1;
        }
    }

    /// Indices of the lags with at least one origin.
    pub fn filled(&self) -> Vec<usize> {
        (0..self.lags.len())
            .filter(|&i| self.origins[i] > 0)
            .collect()
    }

    /// Per group, the mean of `sums` at lag index `i` per grain and origin.
    fn group_means(&self, sums: &[Vec<f64>], i: usize) -> Vec<f64> {
        sums[i]
            .iter()
            .zip(&self.group_sizes)
            .map(|(s, &n)| s / (n as f64 * self.origins[i] as f64))
            .collect()
    }

    /// MSD (length²) of species `s` at lag index `i` with its standard error over groups.
    pub fn msd(&self, s: usize, i: usize) -> (f64, f64) {
        self.species_stat(s, &self.group_means(&self.msd_sums, i))
    }

    /// VACF (velocity²) of species `s` at lag index `i` with its standard error.
    pub fn vacf(&self, s: usize, i: usize) -> (f64, f64) {
        self.species_stat(s, &self.group_means(&self.vacf_sums, i))
    }

    /// Mean over the groups of species `s` (weighted by size) and standard error.
    fn species_stat(&self, s: usize, per_group: &[f64]) -> (f64, f64) {
        let members: Vec<(f64, f64)> = per_group
            .iter()
            .zip(&self.group_sizes)
            .zip(&self.group_species)
            .filter(|(_, sp)| **sp == s)
            .map(|((&v, &n), _)| (v, n as f64))
            .collect();
        mean_and_error(&members)
    }

    /// Self-diffusion coefficient of species `s` (length²/time) from the MSD slope over
    /// the lags in `[from, to]` (time units, `interval` the sample spacing): per group,
    /// least-squares slope / `2 D`. `None` with fewer than two lags in the window.
    pub fn einstein(&self, s: usize, interval: f64, from: f64, to: f64) -> Option<(f64, f64)> {
        let window: Vec<usize> = self
            .filled()
            .into_iter()
            .filter(|&i| {
                let t = self.lags[i] as f64 * interval;
                t >= from && t <= to
            })
            .collect();
        if window.len() < 2 {
            return None;
        }
        let d2 = 2.0 * self.dimension as f64;
        let per_group: Vec<f64> = (0..self.group_sizes.len())
            .map(|g| {
                let pts: Vec<(f64, f64)> = window
                    .iter()
                    .map(|&i| {
                        let t = self.lags[i] as f64 * interval;
                        let m = self.msd_sums[i][g]
                            / (self.group_sizes[g] as f64 * self.origins[i] as f64);
                        (t, m)
                    })
                    .collect();
                slope(&pts) / d2
            })
            .collect();
        Some(self.species_stat(s, &per_group))
    }

    /// Green-Kubo self-diffusion coefficient of species `s`: `(1/D) ∫₀^upto C(τ) dτ`
    /// (trapezoid rule over the lags up to `upto`, time units).
    pub fn green_kubo(&self, s: usize, interval: f64, upto: f64) -> Option<(f64, f64)> {
        let lags: Vec<usize> = self
            .filled()
            .into_iter()
            .filter(|&i| self.lags[i] as f64 * interval <= upto)
            .collect();
        if lags.len() < 2 {
            return None;
        }
        let d = self.dimension as f64;
        let per_group: Vec<f64> = (0..self.group_sizes.len())
            .map(|g| {
                let c = |i: usize| {
                    self.vacf_sums[i][g] / (self.group_sizes[g] as f64 * self.origins[i] as f64)
                };
                lags.windows(2)
                    .map(|w| {
                        let dt = (self.lags[w[1]] - self.lags[w[0]]) as f64 * interval;
                        0.5 * dt * (c(w[0]) + c(w[1]))
                    })
                    .sum::<f64>()
                    / d
            })
            .collect();
        Some(self.species_stat(s, &per_group))
    }
}

/// The per-grain state of an [`Unwrapper`] and a [`LogLagCorrelator`] for the grains
/// `first .. first + len` (a rank's block of ids): written into a decomposed run's
/// checkpoint parts, and cut again into other blocks when the run resumes on another
/// number of ranks ([`GrainRows::cut`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GrainRows {
    /// The first grain.
    pub first: usize,
    /// Grains.
    pub len: usize,
    /// Values per grain of the position arrays.
    pub dimension: usize,
    /// Group of each grain.
    pub group: Vec<u32>,
    /// Wrapped positions at the previous sample.
    pub previous: Vec<f64>,
    /// Unwrapped positions.
    pub unwrapped: Vec<f64>,
    /// Per level, the samples' positions and velocities, oldest first.
    pub levels: Vec<LevelRows>,
}

/// One lag level's samples of a block of grains: positions and velocities, oldest first.
pub type LevelRows = (Vec<Vec<f64>>, Vec<Vec<f64>>);

/// The chained sum of [`LogLagCorrelator::add_chained`]: `chain(acc, fold)` folds `acc`
/// over every block's grains in id order.
pub type Chain<'a> = dyn FnMut(Vec<f64>, &mut dyn FnMut(Vec<f64>) -> Vec<f64>) -> Vec<f64> + 'a;

impl GrainRows {
    /// The grains `a .. b` from `parts` (blocks in order that cover them, each holding
    /// the same levels and samples).
    pub fn cut(parts: &[GrainRows], a: usize, b: usize) -> GrainRows {
        let d = parts.first().map_or(0, |p| p.dimension);
        let take = |values: &dyn Fn(&GrainRows) -> &[f64], width: usize| -> Vec<f64> {
            let mut out = Vec::with_capacity((b - a) * width);
            for p in parts {
                let lo = a.max(p.first);
                let hi = b.min(p.first + p.len);
                if lo < hi {
                    let v = values(p);
                    out.extend_from_slice(&v[(lo - p.first) * width..(hi - p.first) * width]);
                }
            }
            out
        };
        let mut group = Vec::with_capacity(b - a);
        for p in parts {
            let lo = a.max(p.first);
            let hi = b.min(p.first + p.len);
            if lo < hi {
                group.extend_from_slice(&p.group[lo - p.first..hi - p.first]);
            }
        }
        let levels = parts.first().map_or(Vec::new(), |first| {
            (0..first.levels.len())
                .map(|k| {
                    let samples = first.levels[k].0.len();
                    let side = |vel: bool| -> Vec<Vec<f64>> {
                        (0..samples)
                            .map(|t| {
                                take(
                                    &|p: &GrainRows| {
                                        let l = &p.levels[k];
                                        if vel { &l.1[t] } else { &l.0[t] }
                                    },
                                    d,
                                )
                            })
                            .collect()
                    };
                    (side(false), side(true))
                })
                .collect()
        });
        GrainRows {
            first: a,
            len: b - a,
            dimension: d,
            group,
            previous: take(&|p: &GrainRows| &p.previous, d),
            unwrapped: take(&|p: &GrainRows| &p.unwrapped, d),
            levels,
        }
    }
}

impl LogLagCorrelator {
    /// Moves the per-grain state of this correlator and `unwrapper` out (for grains
    /// `first ..`), leaving both without grains.
    pub fn take_rows(&mut self, unwrapper: &mut Unwrapper, first: usize) -> GrainRows {
        let len = self.group.len();
        GrainRows {
            first,
            len,
            dimension: self.dimension,
            group: std::mem::take(&mut self.group),
            previous: std::mem::take(&mut unwrapper.previous),
            unwrapped: std::mem::take(&mut unwrapper.unwrapped),
            levels: self
                .levels
                .iter_mut()
                .map(|l| {
                    (
                        std::mem::take(&mut l.positions).into(),
                        std::mem::take(&mut l.velocities).into(),
                    )
                })
                .collect(),
        }
    }

    /// Puts per-grain state back ([`LogLagCorrelator::take_rows`], perhaps of another
    /// block: [`GrainRows::cut`]).
    pub fn put_rows(&mut self, unwrapper: &mut Unwrapper, rows: GrainRows) {
        self.group = rows.group;
        unwrapper.previous = rows.previous;
        unwrapper.unwrapped = rows.unwrapped;
        for (l, (p, v)) in self.levels.iter_mut().zip(rows.levels) {
            l.positions = p.into();
            l.velocities = v.into();
        }
    }
}

/// Least-squares slope through `(x, y)` points.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    sxy / sxx
}

/// Weighted mean of `(value, weight)` and the standard error of the mean from the spread
/// of the values (NaN with one value).
fn mean_and_error(values: &[(f64, f64)]) -> (f64, f64) {
    let w: f64 = values.iter().map(|v| v.1).sum();
    let mean = values.iter().map(|v| v.0 * v.1).sum::<f64>() / w;
    let m = values.len() as f64;
    if values.len() < 2 {
        return (mean, f64::NAN);
    }
    let var = values.iter().map(|v| (v.0 - mean).powi(2)).sum::<f64>() / (m - 1.0);
    (mean, (var / m).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ballistic grains (`x = v t`): the MSD is `|v|² τ²` and the VACF `|v|²` at every
    /// lag the correlator holds, exactly.
    #[test]
    fn ballistic_motion_gives_exact_lags() {
        let n = 40;
        let species: Vec<u32> = (0..n).map(|i| (i % 2) as u32).collect();
        let v: Vec<f64> = (0..2 * n).map(|i| 0.1 + 0.01 * i as f64).collect();
        let mut c = LogLagCorrelator::new(2, &species, 2);
        for t in 0..1000u64 {
            let x: Vec<f64> = v.iter().map(|&u| u * t as f64).collect();
            c.add(&x, &v);
        }
        let filled = c.filled();
        assert!(
            c.lags[*filled.last().unwrap()] >= 256,
            "lags reach {:?}",
            filled.last()
        );
        for s in 0..2 {
            let v2: f64 = (0..n)
                .filter(|&i| species[i] == s as u32)
                .map(|i| v[2 * i].powi(2) + v[2 * i + 1].powi(2))
                .sum::<f64>()
                / (n / 2) as f64;
            for &i in &filled {
                let tau = c.lags[i] as f64;
                let (m, _) = c.msd(s, i);
                assert!(
                    (m - v2 * tau * tau).abs() <= 1e-9 * (1.0 + m),
                    "lag {tau}: {m}"
                );
                let (a, _) = c.vacf(s, i);
                assert!((a - v2).abs() <= 1e-12 * v2, "lag {tau}: {a}");
            }
        }
    }

    /// Unwrapping follows a grain through the periodic faces; the guard refuses samples
    /// too far apart.
    #[test]
    fn unwrapping_and_its_guard() {
        let mut u = Unwrapper::new(vec![1.0, 1.0], vec![true, false], &[0.9, 0.5], 0.0, 0.5);
        // Speed bound sqrt(2 K / m) = 1: half an edge takes 0.5.
        assert_eq!(u.max_interval(0.5, 1.0), 0.5);
        let x = u.update(&[0.1, 0.6], 0.25, 0.5, 1.0).unwrap().to_vec();
        assert!((x[0] - 1.1).abs() < 1e-12 && (x[1] - 0.6).abs() < 1e-12);
        assert!(u.update(&[0.2, 0.6], 0.85, 0.5, 1.0).is_err());
    }
}
