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
//! (`O(N / K)` time) and sends each to the rank owning its cell, in rounds of at most
//! [`ROUND`] grains. It never holds its block in `f64` beside its records: the keyed
//! streams make a grain cheap to create again, so the block is walked in passes
//! (`passes`): its velocities for the global sums (then dropped), its positions for the
//! grains it sends to each rank, which tells every rank how many it receives from each
//! source, and then the grains themselves, sent round by round into records allocated
//! once at their exact size. Every rank puts the arrivals of each source rank at that
//! source's offset, in the order of the source ranks, which is the order of the ids; the
//! engine's stable counting sort by cell then gives every cell its grains in id order,
//! as on one rank. On one rank the grains go straight into their records the same way.
//! A rank's peak is its records (`dsmc::grains`) and one round's buffers, or the block's
//! velocities before them, whichever is larger.

use super::domain::{Communicator, Domain};
use super::species::SpeciesTable;
use crate::boundary::SimulationBox;
use crate::random::{INITIAL_STATE, RngExt, Stream, derive_key, stream_from_key};
use crate::setup::{Lattice, Region};
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};
use std::ops::Range;
use std::sync::Arc;

mod passes;

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
        let r = crate::collision_law::rough::rotational_dof(D);
        self.for_each_grain(sim_box, ids, Draw::All, |_, x, v, w| {
            pos.push(x);
            vel.push(v);
            if let Some(w) = w {
                spins.extend_from_slice(&w[3 - r..]);
            }
        });
        Ok((pos, vel, spins))
    }

    /// Calls `f(id, x, v, w)` for every grain of `ids` (consecutive ids) in id order:
    /// its position `x` as drawn (given positions not yet wrapped into the box), its
    /// velocity `v` and its angular velocity `w` (`None` for smooth grains), as `draw`
    /// asks (a quantity not drawn is zero or `None`; the streams are independent, so what
    /// is drawn is the same bits whatever is left out). Nothing is held but the chunk's
    /// streams: a rank walks its block as often as it needs at no cost in memory.
    pub(crate) fn for_each_grain(
        &self,
        sim_box: &SimulationBox<D>,
        ids: Range<usize>,
        draw: Draw,
        mut f: impl FnMut(usize, Vector<D>, Vector<D>, Option<crate::collision_law::Spin>),
    ) {
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
                // The walk from the chunk's start to the range's first grain.
                let from = chunk.start.max(a);
                for j in chunk.start..from {
                    self.position(sim_box, sp, j, &mut prng);
                    if draw == Draw::All {
                        self.velocity(sp, j, &mut vrng);
                        self.spin(sp, &mut srng);
                    }
                }
                for j in from..chunk.end.min(b) {
                    let x = self.position(sim_box, sp, j, &mut prng);
                    let (v, w) = match draw {
                        Draw::All => (self.velocity(sp, j, &mut vrng), self.spin(sp, &mut srng)),
                        Draw::Positions => (Vector::zero(), None),
                    };
                    f(own.start + j, x, v, w);
                }
            }
        }
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

/// What [`GrainSetup::for_each_grain`] draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Draw {
    /// Positions, velocities and angular velocities.
    All,
    /// Positions only.
    Positions,
}

/// Grains per round of a migration in rounds (the set-up's, an output's block of ids)
/// for a rank holding about `block` grains: an eighth of the block, at least 256 and at
/// most [`ROUND`], so that the buffers stay a small part of what a rank holds.
pub(crate) fn round_length(block: usize) -> usize {
    (block / 8).clamp(256, ROUND)
}

/// The block of ids `r N / K .. (r + 1) N / K` of rank `r` of `K`.
pub(crate) fn id_block(n: usize, rank: usize, ranks: usize) -> Range<usize> {
    rank * n / ranks..(rank + 1) * n / ranks
}

/// Grains created from a set-up: positions, velocities and angular velocities (`d_r`
/// values each; empty for smooth grains), in id order.
pub(crate) type Created<const D: usize> = (Vec<Vector<D>>, Vec<Vector<D>>, Vec<f64>);

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
