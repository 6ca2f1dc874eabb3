//! The DSMC engine's side of a domain decomposition (see [`super::domain`] for the
//! scheme): splitting a whole engine into slabs, migrating particles after a free
//! flight, the reductions of the observables, and gathering the whole system back (for
//! checkpoints and snapshots).

use super::cells::CellIndex;
use super::collide::Tally;
use super::domain::{Communicator, Domain, DomainError};
use super::engine::DsmcEngine;
use super::grains::Grains;
use std::sync::Arc;

impl<const D: usize> DsmcEngine<D> {
    /// Keeps only this rank's slab of a whole engine (built or restored identically on
    /// every rank): collective over `comm`. From then on every step migrates particles
    /// between the ranks and every observable is reduced over them, bit-identical to the
    /// whole engine's. Errors when there are more ranks than cell planes along the last
    /// axis.
    pub fn decompose(&mut self, comm: Arc<dyn Communicator>) -> Result<(), DomainError> {
        if self.domain.is_some() {
            return Ok(());
        }
        let domain = Domain::new(comm, &self.grid.dims, self.grains.len())?;
        // The owned cells are one contiguous storage range (sorted by cell).
        let cells = domain.cells.clone();
        let a = self.start[cells.start];
        self.grains = self
            .grains
            .range(a as usize..self.start[cells.end] as usize);
        self.start = self.start[cells.start..=cells.end]
            .iter()
            .map(|&s| s - a)
            .collect();
        self.dest = Vec::new();
        self.domain = Some(domain);
        Ok(())
    }

    /// Grains this engine holds (its rank's own when decomposed).
    pub(crate) fn local_len(&self) -> usize {
        self.grains.len()
    }

    /// This rank's share, when the engine is decomposed.
    pub(crate) fn domain(&self) -> Option<&Domain> {
        self.domain.as_ref()
    }

    /// Particles on all ranks.
    pub(super) fn n_global(&self) -> usize {
        self.domain
            .as_ref()
            .map_or(self.grains.len(), |d| d.n_global)
    }

    /// Moves the slab cuts when the balance asks (see `rebalance`), then sends every grain
    /// whose new cell (`dest`, from the free flight) belongs to another rank to that rank
    /// (packed records, in storage order), and returns the records that arrived (packed,
    /// from the lower ranks in rank order, then from the higher ranks), their cells, and
    /// how many came from lower ranks. The sort then puts every grain in the whole
    /// engine's order. Not decomposed: nothing moves.
    pub(super) fn exchange_leavers(&mut self) -> (Vec<f64>, Vec<u32>, usize) {
        self.rebalance();
        let Some(domain) = self.domain.as_ref() else {
            return (Vec::new(), Vec::new(), 0);
        };
        let (me, k) = (domain.rank(), domain.size());
        let g = &self.grains;
        let mut out: Vec<Vec<f64>> = vec![Vec::new(); k];
        for (i, &c) in self.dest.iter().enumerate() {
            let q = domain.owner(c);
            if q != me {
                g.pack(i, &mut out[q]);
            }
        }
        let w = g.words();
        let mut incoming = domain.exchange(out);
        let arriving: usize = incoming.iter().map(|v| v.len() / w).sum();
        // The peak: every grain of the step (the leavers are still in the columns until the
        // sort) and the arrivals.
        domain.hold(g.len() + arriving);
        let before: usize = incoming[..me].iter().map(|v| v.len() / w).sum();
        let arrivals: Vec<f64> = incoming
            .iter_mut()
            .enumerate()
            .filter(|&(q, _)| q != me)
            .flat_map(|(_, v)| std::mem::take(v))
            .collect();
        let index = CellIndex::new(&self.grid, g.lattice());
        let cells = arrivals
            .chunks_exact(w)
            .map(|r| index.of(&std::array::from_fn(|k| r[k].to_bits())))
            .collect();
        (arrivals, cells, before)
    }

    /// Every `balance.every` steps, moves the slab cuts to the grains (collective; see
    /// [`Domain::rebalance`]): from the cells of the free flight just made, the grains
    /// per plane of this rank's slab. The migration that follows sends the grains of the
    /// planes that changed owner. The cuts never change the trajectory.
    fn rebalance(&mut self) {
        let steps = self.steps();
        let Some(domain) = self.domain.as_mut() else {
            return;
        };
        let every = domain.balance.every;
        if domain.balance.mode == super::domain::BalanceMode::Off
            || every == 0
            || !steps.is_multiple_of(every)
        {
            return;
        }
        let planes = domain.own_planes();
        let mut counts = vec![0u64; planes.len()];
        for &c in &self.dest {
            let p = domain.plane(c);
            if planes.contains(&p) {
                counts[p - planes.start] += 1;
            }
        }
        domain.rebalance(&counts);
    }

    /// How the slab cuts follow the grains (see [`super::domain::Balance`]); nothing
    /// when the engine is not decomposed.
    pub(crate) fn set_balance(&mut self, balance: super::domain::Balance) {
        if let Some(d) = self.domain.as_mut() {
            d.balance = balance;
        }
    }

    /// The counters of one step summed over the ranks (exact: integers).
    pub(super) fn reduce_tally(&self, local: Tally) -> Tally {
        let Some(domain) = self.domain.as_ref() else {
            return local;
        };
        let mut words = vec![
            local.collisions,
            local.candidates,
            local.vmax_exceeded,
            local.tc_elastic,
        ];
        words.extend_from_slice(&local.impact);
        let s = domain.sum_u64(&words);
        Tally {
            collisions: s[0],
            candidates: s[1],
            vmax_exceeded: s[2],
            tc_elastic: s[3],
            impact: s[4..].to_vec(),
        }
    }

    /// The smallest id of a particle with a non-finite velocity on any rank.
    pub(super) fn first_non_finite_decomposed(
        &self,
        domain: &Domain,
        local: Option<u32>,
    ) -> Option<u32> {
        domain
            .min_over_ranks(local.map(u64::from))
            .map(|m| m as u32)
    }

    /// The largest of every rank's `local` value (the global `v_max` bound).
    pub(super) fn max_over_ranks(&self, local: f64) -> f64 {
        match self.domain.as_ref() {
            Some(d) => d.max_f64(local),
            None => local,
        }
    }

    /// The whole system as one undecomposed engine, on every rank (collective): the
    /// ranks' arrays put end to end, which is the whole engine's storage order. A plain
    /// clone when the engine is not decomposed. Checkpoints and snapshots hold this, so a
    /// run resumes on any number of ranks (or threads).
    pub fn whole(&self) -> DsmcEngine<D> {
        let Some(domain) = self.domain.as_ref() else {
            return self.clone();
        };
        let g = &self.grains;
        let w = g.words();
        let mut words = Vec::with_capacity(g.len() * w);
        for i in 0..g.len() {
            g.pack(i, &mut words);
        }
        let parts = domain.all_gather(&words);
        domain.hold(self.grains.len() + domain.n_global);
        let mut whole = self.clone();
        whole.domain = None;
        let n = domain.n_global;
        whole.grains = Grains::with_capacity(*g.lattice(), n, g.has_collision_times());
        if g.is_rough() {
            whole.grains.set_spins(Some(&[]));
        }
        for r in parts.iter().flat_map(|p| p.chunks_exact(w)) {
            whole.grains.push_packed(r);
        }
        whole.dest = Vec::new();
        // The cells' storage ranges of the last sort: each rank's owned cells, shifted by
        // the particles of the ranks before it (positions may have left their cell since,
        // with consistent-Boltzmann advection, so they are not re-sorted).
        let bounds = domain.all_gather(
            &self.start[..self.start.len() - 1]
                .iter()
                .map(|&s| s as f64)
                .collect::<Vec<_>>(),
        );
        let counts: Vec<usize> = parts.iter().map(|p| p.len() / w).collect();
        let mut start = Vec::with_capacity(self.grid.len() + 1);
        let mut offset = 0;
        for (b, c) in bounds.iter().zip(&counts) {
            start.extend(b.iter().map(|&s| (offset + s as usize) as u32));
            offset += c;
        }
        start.push(n as u32);
        whole.start = start;
        whole
    }
}
