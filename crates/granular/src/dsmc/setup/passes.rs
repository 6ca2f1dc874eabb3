//! The engine of a set-up, built in passes over the keyed streams (see the parent's
//! "Decomposed set-up"), so that a rank never holds its block of ids in `f64` beside its
//! records:
//!
//! 1. the block's velocities (checking every position against the box on the way): the
//!    sums for `initial.zero_momentum` and the initial temperature, which fix the time
//!    step and so the cell grid and the lattice; then dropped;
//! 2. over ranks, the block's positions again: its grains per cell plane, which give the
//!    first cuts (with a balance) and the grains each rank sends to each other one;
//! 3. the records, allocated once at their exact size: every rank knows how many grains
//!    it receives from each source rank, so the arrivals of a source go at that source's
//!    running offset and the records end in id order, whatever the ranks; the grains are
//!    created anew round by round (at most [`round_length`] ids) and sent packed.
//!
//! The peak of a rank is then its records (and the sort's scratch after them), or the
//! block's velocities, whichever is larger, plus one round's buffers.

use super::{
    Draw, GrainSetup, OnRanks, OwnGrainsCheck, RankLoad, fold_in_id_order, id_block, round_length,
};
use crate::boundary::SimulationBox;
use crate::dsmc::cells::CellIndex;
use crate::dsmc::config::DsmcConfig;
use crate::dsmc::domain::{BalanceMode, Domain, balanced_cuts};
use crate::dsmc::engine::{Derived, DsmcEngine, DsmcError};
use crate::dsmc::grains::Grains;
use crate::dsmc::lattice::Lattice;
use crate::vector::Vector;
use std::ops::Range;

impl<const D: usize> DsmcEngine<D> {
    /// The engine of `setup` (see the module docs): the whole engine without `ranks` (or
    /// with one rank), else this rank's slab (collective over `ranks.comm`; the same bits
    /// as the slab of the whole engine). `dynamics_seed` keys the collisions' streams.
    /// `check` sees the most loaded rank's grains (every grain on one rank) before the
    /// grains go to their slabs (a memory estimate); its error stops every rank. Errors
    /// (the same on every rank) as [`DsmcEngine::from_state`], when a given position lies
    /// outside the box, when there are more ranks than cell planes, and when `check`
    /// refuses.
    pub(crate) fn from_setup(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        setup: &GrainSetup<D>,
        dynamics_seed: u64,
        ranks: Option<OnRanks>,
        check: Option<OwnGrainsCheck<'_>>,
    ) -> Result<Self, DsmcError> {
        let ranks = ranks.filter(|r| r.comm.size() > 1);
        let comm = ranks.as_ref().map(|r| r.comm.clone());
        let balance = ranks.as_ref().map(|r| r.balance).unwrap_or_default();
        let n = setup.len();
        if n == 0 {
            return Err(DsmcError::Invalid("need at least 1 particle, got 0".into()));
        }
        let ids_layout = comm.clone().map(|c| Domain::for_ids(c, n));
        let (rank, ranks) = ids_layout.as_ref().map_or((0, 1), |d| (d.rank(), d.size()));
        let block = id_block(n, rank, ranks);
        if let Some(check) = check {
            // Before any grain exists: the largest block of ids (every rank checks the
            // same load, so all agree); the cells are counted after the grid is known.
            let first = RankLoad {
                own: n.div_ceil(ranks),
                rank: 0,
                ranks,
                grains: n,
                cells: 0,
            };
            agree(
                ids_layout.as_ref(),
                check(&first).map_err(DsmcError::Invalid),
            )?;
        }
        // Pass 1: the block's velocities, every position checked against the box.
        let mut vel = Vec::with_capacity(block.len());
        let mut outside = None;
        setup.for_each_grain(&sim_box, block.clone(), Draw::All, |id, mut x, v, _| {
            if outside.is_none() && !placed(&sim_box, &mut x) {
                outside = Some(id);
            }
            vel.push(v);
        });
        if let Some(id) = first_over_ranks(ids_layout.as_ref(), outside) {
            let (s, j) = species_index(setup, id);
            return Err(DsmcError::Invalid(format!(
                "grain {j} of species `{}` starts outside the box (lengths {:?})",
                setup.species[s].name, sim_box.lengths.0
            )));
        }
        let (drift, derived) = sums(&config, &sim_box, setup, ids_layout.as_ref(), &mut vel)?;
        drop(vel);
        let source = Source {
            setup,
            sim_box: &sim_box,
            lattice: derived.lattice,
            index: CellIndex::new(&derived.grid, &derived.lattice),
            drift,
            collision_times: config.law.has_tc(),
        };
        let (grains, domain) = match ids_layout {
            None => {
                if let Some(check) = check {
                    check(&RankLoad {
                        own: n,
                        rank: 0,
                        ranks: 1,
                        grains: n,
                        cells: derived.grid.len(),
                    })
                    .map_err(DsmcError::Invalid)?;
                }
                // Pass 3 on one rank: every grain straight into its record.
                let mut grains = source.records(n);
                let mut record = Vec::with_capacity(grains.words());
                source.walk(0..n, &mut record, |id, rec| grains.set_packed(id, rec));
                (grains, None)
            }
            Some(layout) => {
                layout.hold(block.len());
                let mut domain = layout.with_grid(&derived.grid.dims)?;
                domain.balance = balance;
                // Pass 2: the block's grains per cell plane.
                let mut planes = vec![0u64; domain.planes()];
                setup.for_each_grain(&sim_box, block.clone(), Draw::Positions, |id, x, _, _| {
                    planes[domain.plane(source.cell(id, x))] += 1;
                });
                if balance.mode != BalanceMode::Off {
                    // The first cuts share the grains evenly (a species in a region would
                    // otherwise load the ranks of its slabs only).
                    let totals = domain.plane_totals(&planes);
                    let loads: Vec<f64> = totals.iter().map(|&c| c as f64).collect();
                    domain.set_cuts(&balanced_cuts(&loads, domain.size()));
                }
                let grains = domain.scatter_setup(&source, block, &planes, check)?;
                (grains, Some(domain))
            }
        };
        let mut engine = Self::assemble_grains(
            config,
            sim_box,
            setup.radius,
            setup.mass,
            dynamics_seed,
            derived,
            grains,
            domain,
            setup.inertia,
        );
        engine.set_species(setup.table());
        Ok(engine)
    }
}

/// Wraps `x` into the box (periodic axes); whether it lies in the box.
fn placed<const D: usize>(sim_box: &SimulationBox<D>, x: &mut Vector<D>) -> bool {
    sim_box.wrap(x);
    (0..D).all(|k| (0.0..=sim_box.lengths[k]).contains(&x[k]))
}

/// The sums over the block's velocities `vel` (in id order; every rank's block, over
/// ranks): removes the centre-of-mass drift when the set-up asks (returned, to be
/// removed again from the velocities created anew), and derives the engine's grid,
/// lattice and time step (from the initial temperature).
fn sums<const D: usize>(
    config: &DsmcConfig,
    sim_box: &SimulationBox<D>,
    setup: &GrainSetup<D>,
    ids_layout: Option<&Domain>,
    vel: &mut [Vector<D>],
) -> Result<(Option<Vector<D>>, Derived<D>), DsmcError> {
    let n = setup.len();
    let fold = |v: &[Vector<D>]| -> Vector<D> {
        Vector(fold_in_id_order::<D, D>(
            ids_layout,
            v.len(),
            |i| v[i].0,
            |a, x| *a = (Vector(*a) + Vector(*x)).0,
            |a, x| *a = (Vector(*a) + Vector(*x)).0,
        ))
    };
    let mut drift = None;
    if setup.zero_momentum {
        // Equal masses: the centre-of-mass velocity is the mean velocity.
        let d = fold(vel) * (1.0 / n as f64);
        for v in vel.iter_mut() {
            *v -= d;
        }
        drift = Some(d);
    }
    let mass = setup.mass;
    let t0 = || {
        let u = fold(vel) * (1.0 / n as f64);
        let [s2] = fold_in_id_order::<1, 1>(
            ids_layout,
            vel.len(),
            |i| [(vel[i] - u).norm_squared()],
            |a, x| a[0] += x[0],
            |a, x| a[0] += x[0],
        );
        mass * s2 / (D * n) as f64
    };
    let derived = Derived::new(config, sim_box, n, setup.radius, mass, t0)?;
    Ok((drift, derived))
}

/// The grains of a set-up as records of the engine's lattice (pass 3).
struct Source<'a, const D: usize> {
    setup: &'a GrainSetup<D>,
    sim_box: &'a SimulationBox<D>,
    lattice: Lattice<D>,
    index: CellIndex<D>,
    /// The centre-of-mass velocity removed from every grain (`initial.zero_momentum`).
    drift: Option<Vector<D>>,
    collision_times: bool,
}

impl<const D: usize> Source<'_, D> {
    /// The cell of grain `id` at `x` (as drawn).
    fn cell(&self, id: usize, mut x: Vector<D>) -> u32 {
        placed(self.sim_box, &mut x);
        self.index.of(&self.lattice.words(&x, id as u32))
    }

    /// `n` zero records of the set-up's kind (collision times, spins).
    fn records(&self, n: usize) -> Grains<D> {
        let spins = match self.setup.inertia {
            Some(_) => crate::collision_law::rough::rotational_dof(D),
            None => 0,
        };
        Grains::zeroed(self.lattice, n, self.collision_times, spins)
    }

    /// Calls `f(id, record)` for every grain of `ids` in id order, its record packed as
    /// [`Grains::pack`] packs it (no previous collision) in `record`.
    fn walk(&self, ids: Range<usize>, record: &mut Vec<f64>, mut f: impl FnMut(usize, &[f64])) {
        let r = crate::collision_law::rough::rotational_dof(D);
        self.setup
            .for_each_grain(self.sim_box, ids, Draw::All, |id, mut x, mut v, w| {
                placed(self.sim_box, &mut x);
                if let Some(d) = self.drift {
                    v -= d;
                }
                record.clear();
                let words = self.lattice.words(&x, id as u32);
                record.extend(words.iter().map(|&b| f64::from_bits(b)));
                record.extend_from_slice(&v.0);
                if self.collision_times {
                    record.push(f64::NEG_INFINITY);
                }
                if let Some(w) = w {
                    record.extend_from_slice(&w[3 - r..]);
                }
                f(id, record);
            });
    }
}

/// Species and index within it of grain `id`.
fn species_index<const D: usize>(setup: &GrainSetup<D>, id: usize) -> (usize, usize) {
    let mut first = 0;
    for (s, sp) in setup.species.iter().enumerate() {
        if id < first + sp.count {
            return (s, id - first);
        }
        first += sp.count;
    }
    (setup.species.len().saturating_sub(1), 0)
}

/// `local` when every rank succeeded; otherwise the error of the first rank that failed
/// (the same on every rank: a rank whose own part succeeded reports the other's failure
/// by its number).
fn agree<T>(domain: Option<&Domain>, local: Result<T, DsmcError>) -> Result<T, DsmcError> {
    let Some(domain) = domain else {
        return local;
    };
    let failed = domain
        .all_gather(&[f64::from(u8::from(local.is_err()))])
        .iter()
        .position(|v| v[0] != 0.0);
    match (local, failed) {
        (Err(e), _) => Err(e),
        (Ok(_), Some(r)) => Err(DsmcError::Invalid(format!(
            "rank {r} could not create its grains (its message is above)"
        ))),
        (Ok(v), None) => Ok(v),
    }
}

/// The smallest of every rank's `local` id (collective).
fn first_over_ranks(domain: Option<&Domain>, local: Option<usize>) -> Option<usize> {
    let Some(domain) = domain else {
        return local;
    };
    domain
        .min_over_ranks(local.map(|x| x as u64))
        .map(|m| m as usize)
}

impl Domain {
    /// Creates the grains of this rank's block of ids `block` anew and sends each to the
    /// rank owning its cell (collective), in rounds of at most [`round_length`] ids;
    /// `planes`: the block's grains per cell plane (pass 2). Returns this rank's own
    /// records in id order: they are allocated once, at their exact size, and the
    /// arrivals of each source rank go at its running offset (the sources in rank order,
    /// which is the order of the ids). `check` sees the number of own grains before they
    /// are allocated; its error stops every rank.
    fn scatter_setup<const D: usize>(
        &self,
        source: &Source<'_, D>,
        block: Range<usize>,
        planes: &[u64],
        check: Option<OwnGrainsCheck<'_>>,
    ) -> Result<Grains<D>, DsmcError> {
        let (me, k) = (self.rank(), self.size());
        let cuts = self.cuts();
        let counts: Vec<Vec<f64>> = (0..k)
            .map(|q| {
                let sending: u64 = planes[cuts[q]..cuts[q + 1]].iter().sum();
                vec![f64::from_bits(sending)]
            })
            .collect();
        let arriving: Vec<usize> = self
            .exchange(counts)
            .iter()
            .map(|v| v.first().map_or(0, |w| w.to_bits() as usize))
            .collect();
        let own: usize = arriving.iter().sum();
        if let Some(check) = check {
            // Every rank checks the most loaded one: the same verdict and message on all.
            let owns = self.all_gather(&[own as f64]);
            let (rank, most) = owns
                .iter()
                .map(|v| v.first().map_or(0, |&x| x as usize))
                .enumerate()
                .fold(
                    (0, 0),
                    |best, (r, c)| if c > best.1 { (r, c) } else { best },
                );
            check(&RankLoad {
                own: most,
                rank,
                ranks: k,
                grains: self.n_global,
                cells: (cuts[rank + 1] - cuts[rank]) * self.stride,
            })
            .map_err(DsmcError::Invalid)?;
        }
        let mut cursor: Vec<usize> = arriving
            .iter()
            .scan(0, |acc, &c| {
                let at = *acc;
                *acc += c;
                Some(at)
            })
            .collect();
        let mut grains = source.records(own);
        let w = grains.words();
        let mut record = Vec::with_capacity(w);
        let longest = self.n_global.div_ceil(k);
        let round = round_length(longest);
        for round_index in 0..longest.div_ceil(round).max(1) {
            let at = |i: usize| (block.start + i * round).min(block.end);
            let mut outgoing: Vec<Vec<f64>> = vec![Vec::new(); k];
            let mut sent = 0;
            source.walk(
                at(round_index)..at(round_index + 1),
                &mut record,
                |_, rec| {
                    let words: [u64; D] = std::array::from_fn(|a| rec[a].to_bits());
                    let q = self.owner(source.index.of(&words));
                    if q == me {
                        grains.set_packed(cursor[me], rec);
                        cursor[me] += 1;
                    } else {
                        outgoing[q].extend_from_slice(rec);
                        sent += 1;
                    }
                },
            );
            let incoming = self.exchange(outgoing);
            let received: usize = incoming.iter().map(|v| v.len() / w).sum();
            self.hold(own + sent + received);
            for (q, words) in incoming.iter().enumerate() {
                for g in words.chunks_exact(w) {
                    grains.set_packed(cursor[q], g);
                    cursor[q] += 1;
                }
            }
        }
        Ok(grains)
    }
}
