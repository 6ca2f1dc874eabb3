//! One DSMC time step: collisions and free flight in one pass over groups of cells, then
//! the stable sort by cell (after migration between ranks when decomposed).
//!
//! A step of length `dt` starting at time `t`:
//!
//! 1. **collisions** in every cell of the sorted state, at time `t` (DSMC-1, DSMC-2,
//!    each cell with its own random stream, see `collide`), then, while the group's
//!    grains are still in the cache, the **free flight** of the group to `t + dt` (walls,
//!    periodic wrap, each grain's new cell; see `flight`). Groups of consecutive cells
//!    (about [`GROUP`] grains) run on all rayon threads; the grouping changes nothing;
//! 2. **migration**: grains whose new cell belongs to another rank are sent there (see
//!    `domain`);
//! 3. the **stable sort** by the new cells (`cells::assign_slots`, `Grains::reorder`).
//!
//! Collisions before the flight rather than after it is the same splitting of the
//! Boltzmann equation (Bird 1976), shifted by half a step: the state between steps is
//! sorted by cell, with the velocities after the collisions and the positions after the
//! flight.

use super::{DsmcEngine, SUM_CHUNK};
use crate::dsmc::cells::{CellIndex, assign_slots};
use crate::dsmc::collide::{StepParams, Tally, collide_group};
use crate::dsmc::config::{DensityScope, VmaxMode};
use crate::dsmc::flight::Flight;
use crate::theory::haff;
use rayon::prelude::*;

/// The number of grains a group of cells aims at: its records (32 bytes a grain in 2D,
/// 48 in 3D) stay in a core's level-2 cache between the collisions and the flight.
const GROUP: usize = 4096;

impl<const D: usize> DsmcEngine<D> {
    /// One time step of length `dt` (see the module docs).
    pub fn step(&mut self, dt: f64) {
        let threads = rayon::current_num_threads().max(1);
        let global_vmax = match self.config.vmax_mode {
            VmaxMode::Global => self.global_speed_bound(),
            VmaxMode::Cell => 0.0,
        };
        let (seed, step) = self.stream_seed_and_step();
        let params = StepParams {
            seed,
            step,
            time: self.time,
            dt,
            sigma: haff::cross_section(D, self.radius),
            radius: self.radius,
            cell_volume: self.grid.volume,
            law: self.config.law.clone(),
            body: self.body(),
            vmax_mode: self.config.vmax_mode,
            global_vmax,
            enskog_global: (self.config.enskog
                && self.config.density_scope == DensityScope::Global)
                .then_some(self.chi_global),
            enskog_local: self.config.enskog && self.config.density_scope == DensityScope::Cell,
            free_volume: self.config.free_volume,
            grain_volume: haff::grain_volume(D, self.radius),
            nu_rcp: haff::random_close_packing(D),
            consistent_boltzmann: self.config.consistent_boltzmann,
            impact_bins: self.config.impact_bins,
            lengths: self.sim_box.lengths.0.to_vec(),
            periodic: (0..D).map(|k| self.sim_box.is_periodic(k)).collect(),
        };
        let lattice = *self.grains.lattice();
        let flight = Flight {
            bx: &self.sim_box,
            lattice: &lattice,
            cells: CellIndex::new(&self.grid, &lattice),
            law: &self.config.law,
            body: self.body(),
            gravity: self.gravity,
            dt,
            t_end: self.time + dt,
        };
        let n = self.grains.len();
        let owned = self.owned_cells();
        let target = (n / (8 * threads)).clamp(256, GROUP) as u32;
        let groups = groups(&self.start, target);
        self.dest.resize(n, 0);
        let mut jobs = Vec::with_capacity(groups.len());
        let mut rest = self.grains.columns();
        let mut rest_dest = &mut self.dest[..];
        for &(a, b) in &groups {
            let len = (self.start[b] - self.start[a]) as usize;
            let (cols, r) = rest.split_at(len);
            let (dest, rd) = rest_dest.split_at_mut(len);
            rest = r;
            rest_dest = rd;
            jobs.push((owned.start + a, &self.start[a..=b], cols, dest));
        }
        let results: Vec<(Tally, u64)> = jobs
            .into_par_iter()
            .map(|(first, bounds, mut cols, dest)| {
                let tally = collide_group(&params, &lattice, first, bounds, &mut cols);
                let tc = flight.fly(&mut cols, dest);
                (tally, tc)
            })
            .collect();
        let mut step_tally = Tally::default();
        for (t, tc) in &results {
            step_tally.add(t);
            step_tally.tc_elastic += tc;
        }
        self.time += dt;
        let (arrivals, mut arrival_cells, before) = self.exchange_leavers();
        // The cuts may have moved (load balance): the sort keeps the cells owned now.
        let owned = self.owned_cells();
        let total = assign_slots(
            &mut self.dest,
            &mut arrival_cells,
            before,
            owned,
            &mut self.start,
        );
        self.grains
            .reorder(&self.dest, total, &arrivals, &arrival_cells);
        self.tally.add(&self.reduce_tally(step_tally));
        self.steps += 1;
    }

    /// Sorts the grains by cell from their positions (construction, restored states):
    /// the stable order of their storage. Grains outside the owned cells are dropped.
    pub(super) fn sort_in_place(&mut self) {
        let index = CellIndex::new(&self.grid, self.grains.lattice());
        let n = self.grains.len();
        self.dest.clear();
        self.dest
            .extend((0..n).map(|i| index.of(&self.grains.words_of(i))));
        let owned = self.owned_cells();
        let total = assign_slots(&mut self.dest, &mut [], 0, owned, &mut self.start);
        self.grains.reorder(&self.dest, total, &[], &[]);
    }

    /// `2 max_i |v_i - u|` over every grain (`u` the mean velocity): the global bound of
    /// the relative speeds (`vmax_mode = "global"`).
    fn global_speed_bound(&self) -> f64 {
        let u = self.mean_velocity();
        let g = &self.grains;
        let n = g.len();
        let m2 = (0..n.div_ceil(SUM_CHUNK))
            .into_par_iter()
            .map(|c| {
                (c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n))
                    .map(|i| (g.velocity(i) - u).norm_squared())
                    .fold(0.0, f64::max)
            })
            .reduce(|| 0.0, f64::max);
        2.0 * self.max_over_ranks(m2).sqrt()
    }
}

/// Groups of consecutive cells (indices into `start`, which holds each cell's first slot
/// and then the number of grains) of about `target` grains each: `(first, end)`.
fn groups(start: &[u32], target: u32) -> Vec<(usize, usize)> {
    let cells = start.len() - 1;
    let mut groups = Vec::new();
    let mut c0 = 0;
    while c0 < cells {
        let mut c1 = c0 + 1;
        while c1 < cells && start[c1] - start[c0] < target {
            c1 += 1;
        }
        groups.push((c0, c1));
        c0 = c1;
    }
    groups
}
