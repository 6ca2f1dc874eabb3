//! Opt-in spatial and collision observables recorded by the runner at output times, for
//! every many-particle engine alike (the engines only expose snapshots and their
//! cumulative impact-parameter histogram; the files are written here):
//!
//! | file | content (NumPy arrays) |
//! |---|---|
//! | `impact_histograms.npz` | `t_start`, `t_end` (T), `edges` (B+1), `counts`, `density` (T x B): histogram of `b / σ` of the collisions between consecutive observation times |
//! | `structure_factor.npz` | `times` (T), `k` (K, inverse length), `modes` (K), `s` (T x K): `S(k)` of the density field, radially averaged over shells of `|k|` |
//! | `density_maps.npz` | `times` (T), `lengths` (D), `density` (T x n_y x n_x, or T x n_z x n_y x n_x): number density per bin |
//!
//! `[output]` keys: `impact_histograms`, `structure_factor`, `structure_factor_max_index`,
//! `density_map`, `observable_times` (see `docs/scenario.md`). These are the observables of
//! section 3.2 of Müller & Herrmann's DSMC paper: the impact-parameter distribution at several times
//! (Fig. 2b), `S(k)` (Fig. 3) and the clusters themselves.

use super::Output;
use crate::observables::{
    DensityMap, SK_CHUNK, SkPlan, StructureFactor, density_counts, density_from_counts, vectors,
};
use crate::observation::Observation;
use crate::output::npz::{NpzArray, NpzData, write_npz};
use crate::run::RunError;
use crate::run::grains::Grains;
use crate::scenario::OutputSpec;
use crate::simulation::Simulation;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The opt-in observables recorded so far (part of the checkpoint).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct SpatialObservables {
    #[serde(skip)]
    dir: PathBuf,
    /// Index of the next entry of `output.observable_times` to wait for.
    pub next_time: usize,
    /// Time of the previous observation (start of the next impact-histogram window).
    pub previous_time: f64,
    /// Cumulative impact-parameter counts at the previous observation.
    pub previous_counts: Vec<u64>,
    /// Bin edges of the impact-parameter histograms.
    pub impact_edges: Vec<f64>,
    /// Start of each impact-histogram window.
    pub impact_t_start: Vec<f64>,
    /// End of each impact-histogram window.
    pub impact_t_end: Vec<f64>,
    /// Counts per window (rows) and bin.
    pub impact_counts: Vec<Vec<u64>>,
    /// Observation times of `S(k)`.
    pub sk_times: Vec<f64>,
    /// Mean `|k|` per shell.
    pub sk_k: Vec<f64>,
    /// Wave vectors per shell.
    pub sk_modes: Vec<usize>,
    /// `S(k)` per observation (rows) and shell.
    pub sk_values: Vec<Vec<f64>>,
    /// Observation times of the density maps.
    pub density_times: Vec<f64>,
    /// Density maps, axis 0 fastest, one per observation.
    pub density_values: Vec<Vec<f64>>,
}

impl SpatialObservables {
    /// Observables written into `dir`.
    pub(crate) fn new(dir: &Path) -> SpatialObservables {
        SpatialObservables {
            dir: dir.to_path_buf(),
            ..SpatialObservables::default()
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.to_path_buf();
    }

    /// Writes the files of the recorded observables (all rows so far).
    fn write_files(&self, out: &OutputSpec, lengths: &[f64]) -> Result<(), RunError> {
        let st = self;
        if out.impact_histograms && !st.impact_edges.is_empty() {
            let bins = st.impact_edges.len() - 1;
            let rows = st.impact_counts.len();
            let width = st.impact_edges[1] - st.impact_edges[0];
            let counts: Vec<f64> = st
                .impact_counts
                .iter()
                .flatten()
                .map(|&c| c as f64)
                .collect();
            let density: Vec<f64> = st
                .impact_counts
                .iter()
                .flat_map(|row| {
                    let total: u64 = row.iter().sum();
                    row.iter().map(move |&c| {
                        if total > 0 {
                            c as f64 / (total as f64 * width)
                        } else {
                            f64::NAN
                        }
                    })
                })
                .collect();
            write_npz(
                self.dir.join(crate::run::RunFile::ImpactHistograms.name()),
                &[
                    ("t_start", NpzArray::f64_1d(st.impact_t_start.clone())),
                    ("t_end", NpzArray::f64_1d(st.impact_t_end.clone())),
                    ("edges", NpzArray::f64_1d(st.impact_edges.clone())),
                    ("counts", NpzArray::f64_2d(counts, rows, bins)?),
                    ("density", NpzArray::f64_2d(density, rows, bins)?),
                ],
            )?;
        }
        if out.structure_factor && !st.sk_times.is_empty() {
            let rows = st.sk_values.len();
            let shells = st.sk_k.len();
            write_npz(
                self.dir.join(crate::run::RunFile::StructureFactor.name()),
                &[
                    ("times", NpzArray::f64_1d(st.sk_times.clone())),
                    ("k", NpzArray::f64_1d(st.sk_k.clone())),
                    (
                        "modes",
                        NpzArray::u64_1d(st.sk_modes.iter().map(|&m| m as u64).collect()),
                    ),
                    ("s", NpzArray::f64_2d(st.sk_values.concat(), rows, shells)?),
                ],
            )?;
        }
        if !out.density_map.is_empty() && !st.density_times.is_empty() {
            // NumPy's C order has the last index fastest: (T, n_y, n_x) for axis 0 fastest.
            let mut shape = vec![st.density_values.len() as u64];
            shape.extend(out.density_map.iter().rev().map(|&d| d.max(1) as u64));
            let density = NpzArray {
                shape,
                data: NpzData::F64(st.density_values.concat()),
            };
            write_npz(
                self.dir.join(crate::run::RunFile::DensityMaps.name()),
                &[
                    ("times", NpzArray::f64_1d(st.density_times.clone())),
                    ("lengths", NpzArray::f64_1d(lengths.to_vec())),
                    ("density", density),
                ],
            )?;
        }
        Ok(())
    }
}

/// Whether the output at `now` is an observation time: every output when
/// `observable_times` is empty, else `t = 0` and the first output at or after each listed
/// time (`next_time`: the index of the next listed time to wait for).
pub(super) fn observation_due(
    next_time: &mut usize,
    out: &OutputSpec,
    now: f64,
    first: bool,
) -> bool {
    let times = &out.observable_times;
    if first || times.is_empty() {
        return true;
    }
    let mut due = false;
    // Tolerance for output times that land on a listed time up to round-off.
    let eps = 1e-9 * out.interval;
    while *next_time < times.len() && times[*next_time] <= now + eps {
        *next_time += 1;
        due = true;
    }
    due
}

impl Output for SpatialObservables {
    /// Records the observables at an observation time and rewrites their files.
    fn observe(&mut self, simulation: &Simulation, _: &Observation) -> Result<(), RunError> {
        let first = simulation.outputs_done() == 0;
        let out = &simulation.scenario().output;
        let now = simulation.time();
        if !observation_due(&mut self.next_time, out, now, first) {
            return Ok(());
        }
        let lengths = simulation.scenario().lengths();
        if out.impact_histograms
            && let Some(h) = simulation.impact_histogram()
        {
            let st = &mut *self;
            if first || st.previous_counts.len() != h.counts.len() {
                st.impact_edges = (0..=h.counts.len())
                    .map(|b| h.min + b as f64 * h.bin_width())
                    .collect();
            } else {
                let row = h
                    .counts
                    .iter()
                    .zip(&st.previous_counts)
                    .map(|(c, p)| c.saturating_sub(*p))
                    .collect();
                st.impact_t_start.push(st.previous_time);
                st.impact_t_end.push(now);
                st.impact_counts.push(row);
            }
            st.previous_counts = h.counts.clone();
            st.previous_time = now;
        }
        let grains = if out.structure_factor || !out.density_map.is_empty() {
            Grains::of(simulation)
        } else {
            None
        };
        if let Some(g) = &grains {
            if out.structure_factor
                && let Some(sk) = structure_factor_of(g, &lengths, out.structure_factor_max_index)
            {
                self.sk_times.push(now);
                self.sk_k = sk.k;
                self.sk_modes = sk.count;
                self.sk_values.push(sk.s);
            }
            if !out.density_map.is_empty()
                && let Some(map) = density_map_of(g, &lengths, &out.density_map)
            {
                self.density_times.push(now);
                self.density_values.push(map.values);
            }
        }
        self.write_files(out, &lengths)
    }
}

/// `S(k)` of the grains ([`crate::observables::structure_factor`], 2D or 3D; `None`
/// otherwise): under ranks each rank sums the chunks of grain ids that start in its block
/// and the chunks' sums are added in id order over the ranks ([`Grains::chain`]), so the
/// additions are the threaded run's.
fn structure_factor_of(g: &Grains, lengths: &[f64], max_index: usize) -> Option<StructureFactor> {
    if lengths.len() != g.snap.dimension {
        return None;
    }
    match g.snap.dimension {
        2 => Some(structure_factor_blocks::<2>(g, lengths, max_index)),
        3 => Some(structure_factor_blocks::<3>(g, lengths, max_index)),
        _ => None,
    }
}

fn structure_factor_blocks<const D: usize>(
    g: &Grains,
    lengths: &[f64],
    max_index: usize,
) -> StructureFactor {
    let Some(plan) = SkPlan::<D>::new(lengths, max_index) else {
        return StructureFactor::default();
    };
    let chunks = g.chunks_starting_here(&g.snap.positions, D, SK_CHUNK);
    let sums: Vec<Vec<(f64, f64)>> = chunks
        .par_iter()
        .map(|c| plan.chunk_sums(&vectors::<D>(c)))
        .collect();
    let words = g.chain(vec![0.0; 2 * plan.sums_len()], |mut tot| {
        for part in &sums {
            for (t, p) in tot.chunks_exact_mut(2).zip(part) {
                t[0] += p.0;
                t[1] += p.1;
            }
        }
        tot
    });
    let tot: Vec<(f64, f64)> = words.chunks_exact(2).map(|t| (t[0], t[1])).collect();
    plan.shells(&tot, g.total)
}

/// The density map of the grains on `dims` bins (one entry per axis, 2D or 3D): each
/// rank counts its block, the counts are summed over the ranks (exact).
fn density_map_of(g: &Grains, lengths: &[f64], dims: &[usize]) -> Option<DensityMap> {
    let d = g.snap.dimension;
    if lengths.len() != d || dims.len() != d {
        return None;
    }
    let dims: Vec<usize> = dims.iter().map(|&n| n.max(1)).collect();
    let counts = match d {
        2 => density_counts::<2>(&vectors(&g.snap.positions), lengths, [dims[0], dims[1]]),
        3 => density_counts::<3>(
            &vectors(&g.snap.positions),
            lengths,
            [dims[0], dims[1], dims[2]],
        ),
        _ => return None,
    };
    Some(density_from_counts(g.sum_u64(counts), lengths, &dims))
}
