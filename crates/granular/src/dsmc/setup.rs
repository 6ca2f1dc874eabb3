//! The initial state of a DSMC run, grain by grain: every grain's position and velocity
//! follow from its id alone, so that each rank of a decomposed run creates only the grains
//! it is given, and the state is the same bits for any number of ranks and threads.
//!
//! # Keyed streams
//!
//! The grains are numbered in the order of the species (as listed), `0 .. N`. Grain `j`
//! of species `s` (its index within the species) takes its random numbers from the two
//! streams `(seed, [INITIAL_STATE, GRAINS, s, c, POSITION])` and `(seed, [INITIAL_STATE,
//! GRAINS, s, c, VELOCITY])` of its *key chunk* `c = j / KEY_CHUNK`: the grains of a chunk
//! draw one after the other from the chunk's streams, so a grain is found by walking at
//! most [`KEY_CHUNK`] grains of its chunk, and positions and velocities are independent.
//!
//! * **Random placement**: uniform in the species' region (the centres at least a radius
//!   from a wall: `Region::centre_range`), independently for every grain. DSMC grains
//!   overlap freely (the method has no excluded volume in its free flight), so there is no
//!   rejection: unlike the event-driven engine's random *sequential* placement, which is
//!   global, this one is local to each grain.
//! * **Lattice placement**: site `j` of the species' lattice ([`Lattice::site`]).
//! * **Given positions**: the species' list, in order.
//! * Velocities: zero, a fixed speed in a uniformly random direction, Maxwell-Boltzmann
//!   at the species' temperature, one given velocity, or a list per grain.
//! * Angular velocities (rough grains only, [`GrainSetup::inertia`]): zero,
//!   Maxwell-Boltzmann at a rotational temperature (each of the `d_r` components Gaussian
//!   with variance `T_r / I`, `I = κ m R²`) from a third stream of the chunk,
//!   `(seed, [INITIAL_STATE, GRAINS, s, c, SPIN])`, or one given angular velocity.
//!
//! # Global sums
//!
//! The centre-of-mass drift (`initial.zero_momentum`) and the initial temperature (for
//! the automatic time step) are sums over all grains, taken over chunks of
//! `SUM_CHUNK` ids in id order, each chunk from zero, the
//! chunks then in order: on one rank with rayon, over ranks with the chained sums of
//! `Domain::ordered_fold` on the blocks of ids, the same bits.
//!
//! # Decomposed set-up
//!
//! Rank `r` of `K` creates the grains of its block of ids `r N / K .. (r + 1) N / K`
//! (`O(N / K)` time and memory), counts how many go to each slab (the rank owning the
//! cell of each position), and sends them there in rounds of at most [`ROUND`] grains,
//! so that no rank holds more than its own grains, the block it created and one round of
//! buffers. Every rank puts the arrivals in the order of the source ranks, which is the
//! order of the ids; the engine's stable counting sort by cell then gives every cell its
//! grains in id order, as on one rank.

use super::cells::CellIndex;
use super::domain::{Communicator, Domain};
use super::engine::{Derived, DsmcEngine, DsmcError};
use super::species::SpeciesTable;
use crate::boundary::SimulationBox;
use crate::dsmc::config::DsmcConfig;
use crate::random::{INITIAL_STATE, RngExt, Stream, derive_key, stream_from_key};
use crate::setup::{Lattice, Region};
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};
use std::ops::Range;
use std::sync::Arc;

/// Grains per key chunk: the grains `c KEY_CHUNK .. (c + 1) KEY_CHUNK` of a species draw
/// from the streams of chunk `c`.
pub(crate) const KEY_CHUNK: usize = 1024;

/// Most grains a rank sends in one round of the set-up's migration.
pub(crate) const ROUND: usize = 1 << 20;

/// The path element of the keyed initial streams (after `INITIAL_STATE`).
const GRAINS: u64 = 7;
const POSITION: u64 = 0;
const VELOCITY: u64 = 1;
const SPIN: u64 = 2;

/// How the grains of one species are placed.
#[derive(Clone, Debug)]
pub(crate) enum Placement<const D: usize> {
    /// Uniformly at random in the region (centres a radius away from walls).
    Random(Region<D>),
    /// On the sites of a lattice filling the region, in order.
    Lattice(Lattice<D>),
    /// At the given positions, in order (one per grain).
    Given(Arc<Vec<Vector<D>>>),
}

/// How the grains of one species start moving.
#[derive(Clone, Debug)]
pub(crate) enum InitialVelocity<const D: usize> {
    /// At rest.
    Zero,
    /// This speed in a uniformly random direction.
    FixedSpeed(f64),
    /// Maxwell-Boltzmann at this temperature (`k_B = 1`): each component Gaussian with
    /// variance `T / m`.
    MaxwellBoltzmann(f64),
    /// Every grain with this velocity.
    Given(Vector<D>),
    /// One velocity per grain, in order.
    PerGrain(Arc<Vec<Vector<D>>>),
}

/// How the rough grains of one species start spinning.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) enum InitialSpin {
    /// Not spinning.
    #[default]
    Zero,
    /// Maxwell-Boltzmann at this rotational temperature (`k_B = 1`): each of the `d_r`
    /// components Gaussian with variance `T_r / I`.
    MaxwellBoltzmann(f64),
    /// Every grain with this angular velocity (`[0, 0, ω_z]` for a disk).
    Given(crate::collision_law::Spin),
}

/// One species of a DSMC set-up: its name, its grains and how they start.
#[derive(Clone, Debug)]
pub(crate) struct SpeciesSetup<const D: usize> {
    /// The species' name (snapshots, histograms).
    pub name: String,
    /// Grains of the species.
    pub count: usize,
    /// Where they start.
    pub placement: Placement<D>,
    /// How they start moving.
    pub velocity: InitialVelocity<D>,
    /// How they start spinning (rough grains; ignored for smooth ones).
    pub angular_velocity: InitialSpin,
}

/// The initial state of a DSMC run: species of equal grains (one radius, one mass), in
/// id order.
#[derive(Clone, Debug)]
pub(crate) struct GrainSetup<const D: usize> {
    /// The species, in id order.
    pub species: Vec<SpeciesSetup<D>>,
    /// Grain radius (every species).
    pub radius: f64,
    /// Grain mass (every species).
    pub mass: f64,
    /// The reduced moment of inertia κ of rough grains (every species), `None` for smooth
    /// grains, which carry no angular velocity.
    pub inertia: Option<f64>,
    /// Remove the centre-of-mass velocity.
    pub zero_momentum: bool,
    /// The run's seed (the keyed streams are derived from it).
    pub seed: u64,
}

impl<const D: usize> GrainSetup<D> {
    /// Grains in all species.
    pub fn len(&self) -> usize {
        self.species.iter().map(|s| s.count).sum()
    }

    /// The species table of the grains.
    pub(crate) fn table(&self) -> SpeciesTable {
        let mut end = 0u32;
        SpeciesTable {
            names: self.species.iter().map(|s| s.name.clone()).collect(),
            ends: self
                .species
                .iter()
                .map(|s| {
                    end += s.count as u32;
                    end
                })
                .collect(),
        }
    }

    /// Positions, velocities and (rough grains; empty otherwise) angular velocities (`d_r`
    /// values each) of the grains `ids` (consecutive ids), in id order. An error names the
    /// first grain that cannot be created.
    pub(crate) fn grains(
        &self,
        sim_box: &SimulationBox<D>,
        ids: Range<usize>,
    ) -> Result<Created<D>, (usize, String)> {
        let mut pos = Vec::with_capacity(ids.len());
        let mut vel = Vec::with_capacity(ids.len());
        let mut spins = Vec::new();
        let mut first = 0;
        for (s, sp) in self.species.iter().enumerate() {
            let own = first..first + sp.count;
            first = own.end;
            let lo = ids.start.max(own.start);
            let hi = ids.end.min(own.end);
            if lo >= hi {
                continue;
            }
            let (a, b) = (lo - own.start, hi - own.start);
            // Key chunks of the species that the range touches.
            for c in a / KEY_CHUNK..b.div_ceil(KEY_CHUNK) {
                let chunk = c * KEY_CHUNK..((c + 1) * KEY_CHUNK).min(sp.count);
                let key = derive_key(self.seed, &[INITIAL_STATE, GRAINS, s as u64, c as u64]);
                let mut prng = stream_from_key(crate::random::extend_key(key, POSITION));
                let mut vrng = stream_from_key(crate::random::extend_key(key, VELOCITY));
                let mut srng = stream_from_key(crate::random::extend_key(key, SPIN));
                for j in chunk.start..chunk.end.min(b) {
                    let x = self.position(sim_box, sp, j, &mut prng);
                    let v = self.velocity(sp, j, &mut vrng);
                    let w = self.spin(sp, &mut srng);
                    if j >= a {
                        pos.push(x);
                        vel.push(v);
                        if let Some(w) = w {
                            let r = crate::collision_law::rough::rotational_dof(D);
                            spins.extend_from_slice(&w[3 - r..]);
                        }
                    }
                }
            }
        }
        Ok((pos, vel, spins))
    }

    /// A rough grain of species `sp`'s angular velocity (drawing from `rng` where it is
    /// random); `None` for smooth grains.
    fn spin(&self, sp: &SpeciesSetup<D>, rng: &mut Stream) -> Option<crate::collision_law::Spin> {
        let kappa = self.inertia?;
        Some(match &sp.angular_velocity {
            InitialSpin::Zero => [0.0; 3],
            InitialSpin::MaxwellBoltzmann(t) => {
                let s = (t / (kappa * self.mass * self.radius * self.radius)).sqrt();
                let mut w = [0.0; 3];
                for x in w
                    .iter_mut()
                    .skip(3 - crate::collision_law::rough::rotational_dof(D))
                {
                    let z: f64 = StandardNormal.sample(rng);
                    *x = s * z;
                }
                w
            }
            InitialSpin::Given(w) => *w,
        })
    }

    /// Grain `j` of species `sp`'s position (drawing from `rng` for random placement).
    fn position(
        &self,
        sim_box: &SimulationBox<D>,
        sp: &SpeciesSetup<D>,
        j: usize,
        rng: &mut Stream,
    ) -> Vector<D> {
        match &sp.placement {
            Placement::Random(region) => {
                let mut x = Vector::zero();
                for k in 0..D {
                    let (a, b) = region.centre_range(sim_box, k, self.radius);
                    x[k] = a + (b - a) * rng.random::<f64>();
                }
                sim_box.wrap(&mut x);
                x
            }
            Placement::Lattice(lattice) => lattice.site(j),
            Placement::Given(list) => list.get(j).copied().unwrap_or_default(),
        }
    }

    /// Grain `j` of species `sp`'s velocity (drawing from `rng` where it is random).
    fn velocity(&self, sp: &SpeciesSetup<D>, j: usize, rng: &mut Stream) -> Vector<D> {
        match &sp.velocity {
            InitialVelocity::Zero => Vector::zero(),
            InitialVelocity::FixedSpeed(speed) => fixed_speed(*speed, rng),
            InitialVelocity::MaxwellBoltzmann(t) => {
                let s = (t / self.mass).sqrt();
                let mut v = Vector::zero();
                for k in 0..D {
                    let z: f64 = StandardNormal.sample(rng);
                    v[k] = s * z;
                }
                v
            }
            InitialVelocity::Given(v) => *v,
            InitialVelocity::PerGrain(list) => list.get(j).copied().unwrap_or_default(),
        }
    }
}

/// A velocity of magnitude `speed` in a uniformly random direction (as
/// `crate::setup::fixed_speed` draws it for one grain).
fn fixed_speed<const D: usize>(speed: f64, rng: &mut Stream) -> Vector<D> {
    if D == 2 {
        let theta = 2.0 * std::f64::consts::PI * rng.random::<f64>();
        let mut v = Vector::zero();
        v[0] = speed * theta.cos();
        v[1] = speed * theta.sin();
        return v;
    }
    loop {
        let mut v = Vector::zero();
        for k in 0..D {
            v[k] = StandardNormal.sample(rng);
        }
        let norm = v.norm();
        if norm > 0.0 {
            return v * (speed / norm);
        }
    }
}

/// The block of ids `r N / K .. (r + 1) N / K` of rank `r` of `K`.
pub(crate) fn id_block(n: usize, rank: usize, ranks: usize) -> Range<usize> {
    rank * n / ranks..(rank + 1) * n / ranks
}

/// Grains created from a set-up: positions, velocities and angular velocities (`d_r`
/// values each; empty for smooth grains), in id order.
pub(crate) type Created<const D: usize> = (Vec<Vector<D>>, Vec<Vector<D>>, Vec<f64>);

/// A rank's own grains: positions, velocities, ids and angular velocities (`d_r` values
/// each; empty for smooth grains), in id order.
type OwnGrains<const D: usize> = (Vec<Vector<D>>, Vec<Vector<D>>, Vec<u32>, Vec<f64>);

/// The most loaded rank of a set-up, as the memory check sees it before any rank
/// allocates its own grains (`OwnGrainsCheck`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RankLoad {
    /// Grains of the most loaded rank (every grain on one rank).
    pub own: usize,
    /// That rank.
    pub rank: usize,
    /// Ranks of the run.
    pub ranks: usize,
    /// Grains of the whole system.
    pub grains: usize,
    /// Cells of that rank's slab (a rank holds only its own cells).
    pub cells: usize,
}

/// Bytes a rank holds per own grain at its peak, in `D` dimensions: the grains' records,
/// the sort's scratch arrays and cell indices, the migration buffers, and a snapshot's or
/// trajectory frame's block of ids with its exchange buffers. Measured peak resident
/// memory over own grains of `granular run` on 2 ranks with snapshots every output
/// (docs/cluster.md, "Memory"), rounded up.
pub(crate) const fn bytes_per_own_grain(dimension: usize) -> f64 {
    if dimension == 2 { 170.0 } else { 230.0 }
}

/// Bytes a rank holds per own cell of its slab.
pub(crate) const BYTES_PER_CELL: f64 = 64.0;

impl RankLoad {
    /// Estimated bytes of the most loaded rank in `D` dimensions.
    pub(crate) fn bytes(&self, dimension: usize) -> f64 {
        self.own as f64 * bytes_per_own_grain(dimension) + self.cells as f64 * BYTES_PER_CELL
    }
}

/// What a rank may hold, checked once the ranks know how many grains each will own
/// (before any allocates them), with the most loaded rank: an error refuses the run on
/// every rank.
pub(crate) type OwnGrainsCheck<'a> = &'a (dyn Fn(&RankLoad) -> Result<(), String> + Sync);

/// The ranks a DSMC engine is split over from its set-up.
#[derive(Clone)]
pub(crate) struct OnRanks {
    /// The ranks.
    pub comm: Arc<dyn Communicator>,
    /// How the slab cuts follow the grains; with a balance other than
    /// [`BalanceMode::Off`](super::domain::BalanceMode) the first cuts already share the
    /// grains evenly.
    pub balance: super::domain::Balance,
}

impl std::fmt::Debug for OnRanks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OnRanks")
            .field("ranks", &self.comm.size())
            .field("balance", &self.balance)
            .finish()
    }
}

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
            // same load, so all agree), which each rank creates before the grains go to
            // their slabs; the cells are counted after the grid is known.
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
        let made = setup.grains(&sim_box, block.clone());
        let bad =
            |(id, message): (usize, String)| DsmcError::Invalid(format!("grain {id}: {message}"));
        let (mut pos, mut vel, spins) = agree(ids_layout.as_ref(), made.map_err(bad))?;
        // Positions into the box (periodic wrap), refused outside it.
        let derived_place = |x: &mut Vector<D>| -> bool {
            sim_box.wrap(x);
            (0..D).all(|k| (0.0..=sim_box.lengths[k]).contains(&x[k]))
        };
        let outside = pos.iter_mut().position(|x| !derived_place(x));
        let first_outside = first_over_ranks(ids_layout.as_ref(), outside.map(|i| block.start + i));
        if let Some(id) = first_outside {
            let (s, j) = species_index(setup, id);
            return Err(DsmcError::Invalid(format!(
                "grain {j} of species `{}` starts outside the box (lengths {:?})",
                setup.species[s].name, sim_box.lengths.0
            )));
        }
        let fold = |v: &[Vector<D>]| -> Vector<D> {
            Vector(fold_in_id_order::<D, D>(
                ids_layout.as_ref(),
                v.len(),
                |i| v[i].0,
                |a, x| *a = (Vector(*a) + Vector(*x)).0,
                |a, x| *a = (Vector(*a) + Vector(*x)).0,
            ))
        };
        if setup.zero_momentum {
            // Equal masses: the centre-of-mass velocity is the mean velocity.
            let drift = fold(&vel) * (1.0 / n as f64);
            for v in vel.iter_mut() {
                *v -= drift;
            }
        }
        let mass = setup.mass;
        let t0 = || {
            let u = fold(&vel) * (1.0 / n as f64);
            let [s2] = fold_in_id_order::<1, 1>(
                ids_layout.as_ref(),
                vel.len(),
                |i| [(vel[i] - u).norm_squared()],
                |a, x| a[0] += x[0],
                |a, x| a[0] += x[0],
            );
            mass * s2 / (D * n) as f64
        };
        let derived = Derived::new(&config, &sim_box, n, setup.radius, mass, t0)?;
        let ids: Vec<u32> = (block.start as u32..block.end as u32).collect();
        let (pos, vel, ids, spins, domain) = match ids_layout {
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
                (pos, vel, ids, spins, None)
            }
            Some(layout) => {
                // The engine's cell of a position: exact, from its lattice words.
                let index = CellIndex::new(&derived.grid, &derived.lattice);
                let cell_of = |x: &Vector<D>| index.of(&derived.lattice.words(x, 0));
                layout.hold(pos.len());
                let mut domain = layout.with_grid(&derived.grid.dims)?;
                domain.balance = balance;
                if balance.mode != super::domain::BalanceMode::Off {
                    // The first cuts share the grains evenly (a species in a region would
                    // otherwise load the ranks of its slabs only).
                    let mut local = vec![0u64; domain.planes()];
                    for x in &pos {
                        local[domain.plane(cell_of(x))] += 1;
                    }
                    let totals = domain.plane_totals(&local);
                    let loads: Vec<f64> = totals.iter().map(|&c| c as f64).collect();
                    domain.set_cuts(&super::domain::balanced_cuts(&loads, domain.size()));
                }
                let (p, v, i, w) = domain.scatter_to_slabs(pos, vel, ids, spins, cell_of, check)?;
                (p, v, i, w, Some(domain))
            }
        };
        let mut engine = Self::assemble(
            config,
            sim_box,
            setup.radius,
            mass,
            dynamics_seed,
            derived,
            pos,
            vel,
            ids,
            domain,
            setup
                .inertia
                .map(|inertia| super::engine::Rotation { inertia, spins }),
        );
        engine.set_species(setup.table());
        Ok(engine)
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
    let word = f64::from_bits(local.map_or(u64::MAX, |x| x as u64));
    domain
        .all_gather(&[word])
        .iter()
        .map(|v| v[0].to_bits())
        .min()
        .filter(|&m| m != u64::MAX)
        .map(|m| m as usize)
}

/// The chunked fold of [`Domain::ordered_fold`] over values in id order: on one rank
/// (`None`) over chunks of `SUM_CHUNK` with rayon, the chunks
/// then in order; over ranks, each holding its block of ids, the chained sums. The same
/// bits either way.
pub(crate) fn fold_in_id_order<const E: usize, const A: usize>(
    domain: Option<&Domain>,
    n_local: usize,
    elem: impl Fn(usize) -> [f64; E] + Sync,
    fold: impl Fn(&mut [f64; A], &[f64; E]) + Sync,
    combine: impl Fn(&mut [f64; A], &[f64; A]),
) -> [f64; A] {
    use rayon::prelude::*;
    if let Some(d) = domain {
        return d.ordered_fold(n_local, elem, fold, combine);
    }
    let chunk = super::sums::SUM_CHUNK;
    let parts: Vec<[f64; A]> = (0..n_local.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let mut acc = [0.0; A];
            for i in c * chunk..((c + 1) * chunk).min(n_local) {
                fold(&mut acc, &elem(i));
            }
            acc
        })
        .collect();
    let mut total = [0.0; A];
    for p in &parts {
        combine(&mut total, p);
    }
    total
}

/// Grains per round of the set-up's migration for a rank holding about `block` grains:
/// an eighth of the block, at least 256 and at most [`ROUND`], so that the buffers stay
/// a small part of what a rank holds.
fn round_length(block: usize) -> usize {
    (block / 8).clamp(256, ROUND)
}

impl Domain {
    /// Sends the grains of this rank's block of ids (`pos`, `vel`, `ids`, and the `d_r`
    /// angular velocity components of each in `spins` for rough grains, in id order) to
    /// the ranks owning their cells (collective), in rounds of at most
    /// [`round_length`] grains; returns this rank's own grains in id order (the arrivals
    /// in the order of the source ranks). `check` sees the number of own grains before
    /// they are allocated; its error stops every rank.
    fn scatter_to_slabs<const D: usize>(
        &self,
        pos: Vec<Vector<D>>,
        vel: Vec<Vector<D>>,
        ids: Vec<u32>,
        spins: Vec<f64>,
        cell_of: impl Fn(&Vector<D>) -> u32,
        check: Option<OwnGrainsCheck<'_>>,
    ) -> Result<OwnGrains<D>, DsmcError> {
        let (me, k) = (self.rank(), self.size());
        let dest: Vec<u32> = pos.iter().map(|x| self.owner(cell_of(x)) as u32).collect();
        let mut sending = vec![0u64; k];
        for &q in &dest {
            sending[q as usize] += 1;
        }
        let counts: Vec<Vec<f64>> = sending.iter().map(|&c| vec![f64::from_bits(c)]).collect();
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
            let cuts = self.cuts();
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
        let mut out_pos = vec![Vector::<D>::zero(); own];
        let mut out_vel = vec![Vector::<D>::zero(); own];
        let mut out_ids = vec![0u32; own];
        // Angular velocity components per grain (0: smooth grains).
        let dr = if spins.is_empty() {
            0
        } else {
            crate::collision_law::rough::rotational_dof(D)
        };
        let mut out_spins = vec![0.0; dr * own];
        let longest = self.n_global.div_ceil(k);
        let round = round_length(longest);
        let w = 1 + 2 * D + dr;
        for round_index in 0..longest.div_ceil(round).max(1) {
            let range =
                (round_index * round).min(pos.len())..((round_index + 1) * round).min(pos.len());
            let mut outgoing: Vec<Vec<f64>> = vec![Vec::new(); k];
            let mut sent = 0;
            for i in range {
                let q = dest[i] as usize;
                if q == me {
                    let c = &mut cursor[me];
                    (out_pos[*c], out_vel[*c], out_ids[*c]) = (pos[i], vel[i], ids[i]);
                    out_spins[dr * *c..dr * *c + dr].copy_from_slice(&spins[dr * i..dr * i + dr]);
                    *c += 1;
                    continue;
                }
                let o = &mut outgoing[q];
                o.push(f64::from_bits(u64::from(ids[i])));
                o.extend_from_slice(&pos[i].0);
                o.extend_from_slice(&vel[i].0);
                o.extend_from_slice(&spins[dr * i..dr * i + dr]);
                sent += 1;
            }
            let incoming = self.exchange(outgoing);
            let received: usize = incoming.iter().map(|v| v.len() / w).sum();
            self.hold(pos.len() + own + sent + received);
            for (q, words) in incoming.iter().enumerate() {
                for g in words.chunks_exact(w) {
                    let c = &mut cursor[q];
                    out_ids[*c] = g[0].to_bits() as u32;
                    out_pos[*c] = Vector::from_slice(&g[1..1 + D]).unwrap_or_default();
                    out_vel[*c] = Vector::from_slice(&g[1 + D..1 + 2 * D]).unwrap_or_default();
                    out_spins[dr * *c..dr * *c + dr].copy_from_slice(&g[1 + 2 * D..w]);
                    *c += 1;
                }
            }
        }
        Ok((out_pos, out_vel, out_ids, out_spins))
    }
}
