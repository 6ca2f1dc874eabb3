//! The DSMC engine's side of a domain decomposition (see [`super::domain`] for the
//! scheme): splitting a whole engine into slabs, migrating particles after a free
//! flight, the reductions of the observables, and gathering the whole system back (for
//! checkpoints and snapshots).

use super::collide::Tally;
use super::domain::{Communicator, Domain, DomainError};
use super::engine::DsmcEngine;
use super::grains::Grains;
use crate::vector::Vector;
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
        let a = self.start[domain.cells.start] as usize;
        let b = self.start[domain.cells.end] as usize;
        self.grains = self.grains.range(a..b);
        self.cell_of = self.cell_of[a..b].to_vec();
        for s in self.start.iter_mut() {
            *s = (*s as usize).clamp(a, b) as u32 - a as u32;
        }
        self.domain = Some(domain);
        Ok(())
    }

    /// Grains this engine holds (its rank's own when decomposed).
    pub fn local_len(&self) -> usize {
        self.grains.len()
    }

    /// This rank's share, when the engine is decomposed.
    pub fn domain(&self) -> Option<&Domain> {
        self.domain.as_ref()
    }

    /// Particles on all ranks.
    pub(super) fn n_global(&self) -> usize {
        self.domain
            .as_ref()
            .map_or(self.grains.len(), |d| d.n_global)
    }

    /// Sends every particle whose cell (`cell_of`, from the free flight) belongs to another
    /// rank to that rank, and takes in the arrivals: in the order of the source ranks, this
    /// rank's own particles at its own place, so that the ranks' arrays put end to end stay
    /// in the whole engine's order. `cell_of` must be recomputed afterwards (the sort does).
    pub(super) fn migrate(&mut self) {
        self.rebalance();
        let Some(domain) = self.domain.as_ref() else {
            return;
        };
        let (me, k) = (domain.rank(), domain.size());
        let g = &mut self.grains;
        let mut out: Vec<Vec<f64>> = vec![Vec::new(); k];
        let mut kept = 0;
        for i in 0..g.len() {
            let q = domain.owner(self.cell_of[i]);
            if q == me {
                g.copy(i, kept);
                kept += 1;
                continue;
            }
            g.pack(i, &mut out[q]);
        }
        let w = g.words();
        let sent: usize = out.iter().map(|v| v.len() / w).sum();
        let incoming = domain.exchange(out);
        let arrivals: usize = incoming.iter().map(|v| v.len() / w).sum();
        let total = kept + arrivals;
        domain.hold(kept + sent + arrivals);
        let before: usize = incoming[..me].iter().map(|v| v.len() / w).sum();
        // Own particles move up behind the arrivals from lower ranks.
        g.resize(total.max(g.len()));
        g.copy_within(0..kept, before);
        let mut slot = 0;
        for (q, words) in incoming.iter().enumerate() {
            if q == me {
                slot += kept;
                continue;
            }
            for r in words.chunks_exact(w) {
                g.set_packed(slot, r);
                slot += 1;
            }
        }
        g.truncate(total);
        self.cell_of.resize(total, 0);
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
        for &c in &self.cell_of {
            let p = domain.plane(c);
            if planes.contains(&p) {
                counts[p - planes.start] += 1;
            }
        }
        domain.rebalance(&counts);
    }

    /// How the slab cuts follow the grains (see [`super::domain::Balance`]); nothing
    /// when the engine is not decomposed.
    pub fn set_balance(&mut self, balance: super::domain::Balance) {
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

    /// The mean velocity over all ranks, bit-identical to the whole engine's chunked sum.
    pub(super) fn mean_velocity_decomposed(&self, domain: &Domain) -> Vector<D> {
        let g = &self.grains;
        let s = domain.ordered_fold::<D, D>(
            g.len(),
            |i| g.velocity(i).0,
            |a, v| *a = (Vector(*a) + Vector(*v)).0,
            |a, v| *a = (Vector(*a) + Vector(*v)).0,
        );
        Vector(s) * (1.0 / domain.n_global as f64)
    }

    /// `(sum c^2, sum c^4)` of the peculiar velocity over all ranks, as the whole engine.
    pub(super) fn peculiar_sums_decomposed(&self, domain: &Domain, u: Vector<D>) -> (f64, f64) {
        let g = &self.grains;
        let [s2, s4] = domain.ordered_fold::<1, 2>(
            g.len(),
            |i| [(g.velocity(i) - u).norm_squared()],
            |a, &[c2]| *a = [a[0] + c2, a[1] + c2 * c2],
            |a, x| *a = [a[0] + x[0], a[1] + x[1]],
        );
        (s2, s4)
    }

    /// `sum |v|^2` over all ranks, as the whole engine.
    pub(super) fn speed_squares_decomposed(&self, domain: &Domain) -> f64 {
        let g = &self.grains;
        domain.ordered_fold::<1, 1>(
            g.len(),
            |i| [g.velocity(i).norm_squared()],
            |a, x| a[0] += x[0],
            |a, x| a[0] += x[0],
        )[0]
    }

    /// The smallest id of a particle with a non-finite velocity on any rank.
    pub(super) fn first_non_finite_decomposed(
        &self,
        domain: &Domain,
        local: Option<u32>,
    ) -> Option<u32> {
        let word = f64::from_bits(local.map_or(u64::MAX, u64::from));
        domain
            .all_gather(&[word])
            .iter()
            .map(|v| v[0].to_bits())
            .min()
            .filter(|&m| m != u64::MAX)
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
        whole.grains = Grains::with_capacity(n, g.has_collision_times());
        for r in parts.iter().flat_map(|p| p.chunks_exact(w)) {
            whole.grains.push_packed(r);
        }
        whole.cell_of = vec![0; n];
        // The cells' storage ranges of the last sort: each rank's owned cells, shifted by
        // the particles of the ranks before it (positions may have left their cell since,
        // with consistent-Boltzmann advection, so they are not re-sorted).
        let bounds = domain.all_gather(
            &self.start[domain.cells.clone()]
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
