//! Turns a validated [`Scenario`] into an engine with its initial state: the engines of
//! every kind behind one type ([`AnyEngine`]), built below [`crate::Simulation`] (nothing
//! here imports the simulation or the run directory).

pub mod intruder;
mod rotation;

use crate::boundary::SimulationBox;
use crate::dsmc::config::DsmcConfig;
use crate::dsmc::engine::DsmcEngine;
use crate::edmd::init;
use crate::edmd::{Edmd, EdmdOptions};
use crate::engine::{Engine, EngineError, Observation, Progress, Snapshot};
use crate::particles::ParticleSet;
use crate::random::{self, stream};
use crate::scenario::{
    AngularVelocitySpec, EngineSpec, Placement, Resolved, Scenario, ScenarioError, VelocitySpec,
};
use crate::setup::{self, InitError, Region};
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// An engine of any kind and dimension, as stored in checkpoints.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[allow(clippy::large_enum_variant)]
pub enum AnyEngine {
    /// Event-driven, 2D.
    Edmd2(Edmd<2>),
    /// Event-driven, 3D.
    Edmd3(Edmd<3>),
    /// DSMC, 2D.
    Dsmc2(DsmcEngine<2>),
    /// DSMC, 3D.
    Dsmc3(DsmcEngine<3>),
    /// Gillespie intruder (1D, needle or DSMC twin), `engine = "intruder"`.
    Intruder(self::intruder::IntruderEngine),
}

macro_rules! each_engine {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            AnyEngine::Edmd2($e) => $body,
            AnyEngine::Edmd3($e) => $body,
            AnyEngine::Dsmc2($e) => $body,
            AnyEngine::Dsmc3($e) => $body,
            AnyEngine::Intruder($e) => $body,
        }
    };
}

impl AnyEngine {
    /// The engine behind the common interface.
    pub fn as_engine(&mut self) -> &mut dyn Engine {
        each_engine!(self, e => e)
    }

    /// Splits a DSMC engine over the ranks of `comm` (collective; see
    /// [`crate::dsmc::domain`]). Other engines cannot be split (unless there is one rank).
    pub fn decompose(
        &mut self,
        comm: std::sync::Arc<dyn crate::dsmc::Communicator>,
    ) -> Result<(), crate::dsmc::DomainError> {
        match self {
            AnyEngine::Dsmc2(e) => e.decompose(comm),
            AnyEngine::Dsmc3(e) => e.decompose(comm),
            _ if comm.size() == 1 => Ok(()),
            other => Err(crate::dsmc::DomainError::NotDecomposable {
                engine: other.name(),
                ranks: comm.size(),
            }),
        }
    }

    /// How a decomposed DSMC engine's slab cuts follow the grains (nothing otherwise).
    pub fn set_balance(&mut self, balance: crate::dsmc::Balance) {
        match self {
            AnyEngine::Dsmc2(e) => e.set_balance(balance),
            AnyEngine::Dsmc3(e) => e.set_balance(balance),
            _ => {}
        }
    }

    /// This rank's share of a decomposed DSMC engine (`None`: the whole engine).
    pub fn domain(&self) -> Option<&crate::dsmc::Domain> {
        match self {
            AnyEngine::Dsmc2(e) => e.domain(),
            AnyEngine::Dsmc3(e) => e.domain(),
            _ => None,
        }
    }

    /// A DSMC engine without its particles (the manifest of a decomposed run's
    /// checkpoint); other engines are cloned.
    pub(crate) fn shell(&self) -> AnyEngine {
        match self {
            AnyEngine::Dsmc2(e) => AnyEngine::Dsmc2(e.shell()),
            AnyEngine::Dsmc3(e) => AnyEngine::Dsmc3(e.shell()),
            other => other.clone(),
        }
    }

    /// Sets every grain's position and velocity (row-major `n × D` by grain id) and, for
    /// rough grains, angular velocity (`n × d_r`; empty for smooth grains) at absolute time
    /// `time`, and rebuilds what depends on them (`Edmd::restart`, `DsmcEngine::restart`);
    /// the arrays are checked by the caller (`Simulation::set_state`). The intruder engines
    /// have no grains: refused.
    pub fn restart(
        &mut self,
        time: f64,
        positions: &[f64],
        velocities: &[f64],
        angular_velocities: &[f64],
    ) -> Result<(), String> {
        let w = angular_velocities;
        match self {
            AnyEngine::Edmd2(e) => e.restart(time, positions, velocities, w),
            AnyEngine::Edmd3(e) => e.restart(time, positions, velocities, w),
            AnyEngine::Dsmc2(e) => e
                .restart(time, positions, velocities, w)
                .map_err(|e| e.to_string())?,
            AnyEngine::Dsmc3(e) => e
                .restart(time, positions, velocities, w)
                .map_err(|e| e.to_string())?,
            AnyEngine::Intruder(_) => {
                return Err("the intruder engine has no grains to set".into());
            }
        }
        Ok(())
    }

    /// Whether the grains are rough (they carry angular velocities).
    pub fn is_rough(&self) -> bool {
        match self {
            AnyEngine::Edmd2(e) => e.is_rough(),
            AnyEngine::Edmd3(e) => e.is_rough(),
            AnyEngine::Dsmc2(e) => e.is_rough(),
            AnyEngine::Dsmc3(e) => e.is_rough(),
            AnyEngine::Intruder(_) => false,
        }
    }

    /// Angular velocities of rough grains by id, `d_r` values per grain (`ω_z` in 2D,
    /// `ω_x, ω_y, ω_z` in 3D); empty for smooth grains and the intruder engines (gathered
    /// from all ranks for a decomposed DSMC engine, collectively).
    pub fn angular_velocities(&self) -> Vec<f64> {
        match self {
            AnyEngine::Edmd2(e) => e.angular_velocities(),
            AnyEngine::Edmd3(e) => e.angular_velocities(),
            AnyEngine::Dsmc2(e) => e.angular_velocities(),
            AnyEngine::Dsmc3(e) => e.angular_velocities(),
            AnyEngine::Intruder(_) => Vec::new(),
        }
    }

    /// The whole engine: a clone, gathered from all ranks for a decomposed DSMC engine
    /// (collective then).
    pub fn whole(&self) -> AnyEngine {
        match self {
            AnyEngine::Dsmc2(e) => AnyEngine::Dsmc2(e.whole()),
            AnyEngine::Dsmc3(e) => AnyEngine::Dsmc3(e.whole()),
            other => other.clone(),
        }
    }
}

impl Engine for AnyEngine {
    fn name(&self) -> &'static str {
        each_engine!(self, e => e.name())
    }
    fn time(&self) -> f64 {
        each_engine!(self, e => e.time())
    }
    fn events(&self) -> u64 {
        each_engine!(self, e => e.events())
    }
    fn collisions(&self) -> u64 {
        each_engine!(self, e => e.collisions())
    }
    fn particle_count(&self) -> usize {
        each_engine!(self, e => e.particle_count())
    }
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        self.as_engine().advance(until, max_events)
    }
    fn observe(&self) -> Observation {
        each_engine!(self, e => e.observe())
    }
    fn kinetic_energy(&self) -> f64 {
        each_engine!(self, e => e.kinetic_energy())
    }
    fn snapshot(&self) -> Option<Snapshot> {
        each_engine!(self, e => e.snapshot())
    }
    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        each_engine!(self, e => e.state_into(velocities, out))
    }
    fn impact_histogram(&self) -> Option<crate::stats::Histogram> {
        each_engine!(self, e => Engine::impact_histogram(e))
    }
}

/// Why a scenario could not be turned into an engine.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A value in the scenario is wrong.
    #[error("{0}")]
    Scenario(#[from] ScenarioError),
    /// The initial state could not be built.
    #[error("initial state of species `{species}`: {source}")]
    Init {
        /// Species being placed.
        species: String,
        /// What went wrong.
        source: InitError,
    },
    /// The DSMC engine rejected its input.
    #[error("DSMC: {0}")]
    Dsmc(String),
    /// The intruder engine rejected its input (e.g. an unreadable tabulated bath file).
    #[error("intruder: {0}")]
    Intruder(String),
    /// Given positions overlap.
    #[error(
        "grains {a} and {b} overlap at the start (distance {distance:.6} < sum of radii {sigma:.6}); move them apart or make them smaller"
    )]
    Overlap {
        /// First grain (global index).
        a: usize,
        /// Second grain.
        b: usize,
        /// Centre distance.
        distance: f64,
        /// Sum of radii.
        sigma: f64,
    },
}

/// Builds the engine named by the scenario (a DSMC engine checked against this
/// machine's available memory, [`MemoryBudget::this_node`]).
pub fn build(scenario: &Scenario) -> Result<AnyEngine, BuildError> {
    build_resolved(scenario).map(|(engine, _)| engine)
}

/// Builds the engine named by the scenario (a DSMC engine checked against this machine's
/// available memory) and resolves the scenario at the temperature of its drawn initial
/// state (`Resolved::at_temperature`); the engine takes its derived values (the DSMC
/// cell size, the driving's reference temperature) from it.
pub(crate) fn build_resolved(scenario: &Scenario) -> Result<(AnyEngine, Resolved), BuildError> {
    build_on(scenario, None, Some(MemoryBudget::this_node(1)))
}

/// The memory a DSMC run may use on each node, checked from the most loaded rank's own
/// grains before the ranks sort their grains into their slabs (the event-driven engine's
/// whole-system check is part of the scenario's validation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryBudget {
    /// Bytes available on the node (`MemAvailable` of `/proc/meminfo`).
    pub available: f64,
    /// Ranks of the run on the node, which share it.
    pub ranks_on_node: usize,
}

impl MemoryBudget {
    /// This node's available memory (`crate::scenario::available_memory`) shared by
    /// `ranks_on_node` ranks.
    pub fn this_node(ranks_on_node: usize) -> MemoryBudget {
        MemoryBudget {
            available: crate::scenario::available_memory(),
            ranks_on_node: ranks_on_node.max(1),
        }
    }

    /// Bytes each rank on the node may use.
    pub fn per_rank(&self) -> f64 {
        self.available / self.ranks_on_node.max(1) as f64
    }

    /// Whether the most loaded rank `load` of a `dimension`-dimensional DSMC run fits
    /// (`crate::dsmc::setup::RankLoad::bytes`); the error names the scenario's key, the
    /// estimate, what is available, and the number of ranks (at this many per node) that
    /// would fit.
    pub fn check(
        &self,
        scenario: &Scenario,
        dimension: usize,
        load: &crate::dsmc::setup::RankLoad,
    ) -> Result<(), String> {
        use crate::dsmc::setup::{BYTES_PER_CELL, bytes_per_own_grain};
        let need = load.bytes(dimension);
        let share = self.per_rank();
        if need <= share {
            return Ok(());
        }
        const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
        let per_grain = bytes_per_own_grain(dimension);
        let cells = load.cells as f64 * BYTES_PER_CELL;
        let key = scenario
            .species()
            .iter()
            .enumerate()
            .max_by_key(|(_, sp)| sp.count)
            .map_or("species[0].count".to_string(), |(s, _)| {
                format!("species[{s}].count")
            });
        let count = |x: usize| crate::output::format_number(x as f64);
        let holder = if load.ranks == 1 {
            format!("the run holds all {} grains", count(load.grains))
        } else {
            format!(
                "over {} ranks, rank {} would hold {} of the {} grains",
                load.ranks,
                load.rank,
                count(load.own),
                count(load.grains)
            )
        };
        let node = format!(
            "{:.1} GiB are available to each of the {} ranks on this node ({:.1} GiB available)",
            share / GIB,
            self.ranks_on_node,
            self.available / GIB
        );
        let fix = if cells >= share {
            "the cells of one rank's slab alone do not fit: give a larger dsmc.cell_size, or \
             run on more nodes"
                .to_string()
        } else {
            // The whole system (the grid as this rank's slab times the ranks) over the
            // share of one rank; ranks on the same node share its memory, so more ranks
            // help only on more nodes.
            let whole = load.grains as f64 * per_grain + cells * load.ranks as f64;
            let fit = ((whole / share).ceil() as usize).max(load.ranks + 1);
            let per_node = self.ranks_on_node;
            format!(
                "run on at least {fit} ranks with {per_node} per node ({} nodes), or lower \
                 {key}",
                fit.div_ceil(per_node)
            )
        };
        let cell_part = if load.cells > 0 {
            format!(", plus {:.2} GiB for the {} cells", cells / GIB, load.cells)
        } else {
            String::new()
        };
        Err(format!(
            "{key}: {holder}, about {:.1} GiB ({per_grain} bytes per grain{cell_part}), but \
             {node}: {fix}; `granular run --insist` runs it anyway",
            need / GIB,
        ))
    }
}

/// Builds the engine named by the scenario, split over the ranks of `comm` when it is
/// given (collective): a DSMC engine creates only this rank's grains (see
/// [`dsmc_setup`]), the same bits as the slab of the whole engine. With `memory`, the
/// most loaded rank's estimated memory ([`MemoryBudget::check`]) must fit in its share of
/// the node, else every rank stops with the same error before the grains go to their
/// slabs (`None`: no check, as `--insist`). Other engines are refused on several ranks.
/// Returns the engine and the scenario resolved at the temperature of the drawn initial
/// state.
pub(crate) fn build_on(
    scenario: &Scenario,
    comm: Option<std::sync::Arc<dyn crate::dsmc::Communicator>>,
    memory: Option<MemoryBudget>,
) -> Result<(AnyEngine, Resolved), BuildError> {
    scenario.validate()?;
    let nominal = scenario.resolve();
    let ranks = comm.as_ref().map_or(1, |c| c.size());
    let mut engine = match (&scenario.engine, scenario.dimension) {
        (EngineSpec::Dsmc { grains, dsmc }, d) => {
            let config = nominal
                .grains
                .as_ref()
                .and_then(|g| g.dsmc.as_ref())
                .map(|r| dsmc.config(grains, r))
                .ok_or_else(|| BuildError::Dsmc("the scenario resolved no DSMC values".into()))?;
            let on_ranks = comm.map(|comm| crate::dsmc::setup::OnRanks {
                comm,
                balance: dsmc.balance(),
            });
            if d == 2 {
                AnyEngine::Dsmc2(build_dsmc::<2>(scenario, config, on_ranks, memory)?)
            } else {
                AnyEngine::Dsmc3(build_dsmc::<3>(scenario, config, on_ranks, memory)?)
            }
        }
        _ if ranks > 1 => {
            return Err(BuildError::Dsmc(
                crate::dsmc::DomainError::NotDecomposable {
                    engine: match scenario.kind() {
                        crate::scenario::EngineKind::Edmd => "edmd",
                        _ => "intruder",
                    },
                    ranks,
                }
                .to_string(),
            ));
        }
        (EngineSpec::Intruder(_), _) => {
            AnyEngine::Intruder(self::intruder::build(scenario).map_err(BuildError::Intruder)?)
        }
        (EngineSpec::Edmd { grains, edmd }, 2) => {
            AnyEngine::Edmd2(build_edmd::<2>(scenario, edmd.options(grains))?)
        }
        (EngineSpec::Edmd { grains, edmd }, _) => {
            AnyEngine::Edmd3(build_edmd::<3>(scenario, edmd.options(grains))?)
        }
    };
    if nominal.grains.is_none() {
        return Ok((engine, nominal));
    }
    // The temperature of the drawn state, as the time series' first row reports it (on
    // several ranks a collective sum: every rank calls it).
    let resolved = nominal.at_temperature(scenario, engine.observe().temperature);
    // `[driving]`: a steady state (rescale defaults to the initial temperature), kicks from
    // the dynamics seed.
    let driving = resolved
        .grains
        .as_ref()
        .and_then(|g| g.driving.as_ref())
        .map(|d| d.driving.clone());
    let seed = crate::random::derive_key(scenario.seed, &[crate::random::DYNAMICS]);
    match &mut engine {
        AnyEngine::Edmd2(e) if driving.is_some() => e.set_driving(driving, seed),
        AnyEngine::Edmd3(e) if driving.is_some() => e.set_driving(driving, seed),
        AnyEngine::Dsmc2(e) => e.set_driving(driving),
        AnyEngine::Dsmc3(e) => e.set_driving(driving),
        _ => {}
    }
    Ok((engine, resolved))
}

fn vector<const D: usize>(v: &[f64]) -> Vector<D> {
    let mut out = Vector::zero();
    for (k, x) in v.iter().enumerate().take(D) {
        out[k] = *x;
    }
    out
}

/// The initial grains of a scenario in `D` dimensions (positions, velocities, radii...).
pub fn initial_particles<const D: usize>(
    scenario: &Scenario,
) -> Result<(SimulationBox<D>, ParticleSet<D>), BuildError> {
    let axes = scenario.axes();
    let mut ax = [crate::boundary::AxisKind::Wall; D];
    ax.copy_from_slice(&axes[..D]);
    let bx = SimulationBox {
        lengths: vector::<D>(&scenario.lengths()),
        axes: ax,
    };
    let mut rng = stream(scenario.seed, &[random::INITIAL_STATE]);
    let mut set = ParticleSet {
        positions: Vec::new(),
        velocities: Vec::new(),
        radii: Vec::new(),
        masses: Vec::new(),
        species: Vec::new(),
        species_names: scenario.species().iter().map(|s| s.name.clone()).collect(),
        ..Default::default()
    };
    // Grains with given positions first, so random placement avoids them.
    let mut fixed: Vec<(Vector<D>, f64)> = Vec::new();
    for (s, sp) in scenario.species().iter().enumerate() {
        if !sp.positions.is_empty() {
            let r = scenario.radius(s);
            fixed.extend(sp.positions.iter().map(|p| (vector::<D>(p), r)));
        }
    }
    let compress = scenario.initial().compress_from;
    // With compression every grain is placed with its radius divided by one common factor,
    // so that all of them together fill `compress_from` of the box, and then grown back
    // (Lubachevsky-Stillinger). (A factor per species placed each species alone at
    // `compress_from`: two species at 0.3 made 0.6, beyond random placement.)
    let shrink = match compress {
        Some(start) => {
            let grains: f64 = (0..scenario.species().len())
                .map(|s| {
                    scenario.species()[s].count as f64 * setup::ball_volume::<D>(scenario.radius(s))
                })
                .sum();
            let target = grains / bx.volume();
            (target / start).powf(1.0 / D as f64).max(1.0)
        }
        None => 1.0,
    };
    // Species are placed largest first (stable: equal radii keep the order of the scenario),
    // whatever the order they are listed in: small grains placed first leave no room for
    // large ones (a 3D bidisperse gas at packing fraction 0.27 failed with the small species
    // listed first). Each species draws its positions and then its velocities from the
    // stream, in placement order; a scenario listed largest first draws exactly as before.
    // The grains are stored in the order of the scenario (species as listed).
    let mut order: Vec<usize> = (0..scenario.species().len()).collect();
    order.sort_by(|&a, &b| scenario.radius(b).total_cmp(&scenario.radius(a)));
    let mut per_species: Vec<Option<(Vec<Vector<D>>, Vec<Vector<D>>)>> =
        vec![None; scenario.species().len()];
    for &s in &order {
        let sp = &scenario.species()[s];
        let r = scenario.radius(s);
        let region = match &sp.region {
            Some(reg) => Region {
                lo: vector::<D>(&reg.lo),
                hi: vector::<D>(&reg.hi),
            },
            None => Region::whole(&bx),
        };
        let positions = if !sp.positions.is_empty() {
            sp.positions.iter().map(vector::<D>).collect()
        } else {
            let place_r = r / shrink;
            let radii = vec![place_r; sp.count];
            let placed = match scenario.initial().placement {
                Placement::Random => setup::random_placement(
                    &bx,
                    &region,
                    &radii,
                    &fixed,
                    &mut rng,
                    scenario.initial().max_attempts,
                ),
                Placement::Lattice => setup::lattice_placement(&bx, &region, &radii),
            }
            .map_err(|source| BuildError::Init {
                species: sp.name.clone(),
                source,
            })?;
            fixed.extend(placed.iter().map(|x| (*x, place_r)));
            placed
        };
        let masses = vec![sp.mass; sp.count];
        let velocities: Vec<Vector<D>> = match &sp.velocity {
            VelocitySpec::Zero => vec![Vector::zero(); sp.count],
            VelocitySpec::FixedSpeed { speed } => {
                setup::fixed_speed::<D>(sp.count, *speed, &mut rng)
            }
            VelocitySpec::MaxwellBoltzmann { temperature } => {
                setup::maxwell_boltzmann::<D>(&masses, *temperature, &mut rng)
            }
            VelocitySpec::Given { velocity } => vec![vector::<D>(velocity); sp.count],
            VelocitySpec::PerGrain { velocities } => velocities.iter().map(vector::<D>).collect(),
        };
        per_species[s] = Some((positions, velocities));
    }
    for (s, sp) in scenario.species().iter().enumerate() {
        let r = scenario.radius(s);
        let (positions, velocities) = per_species[s].take().unwrap_or_default();
        set.positions.extend(positions);
        set.velocities.extend(velocities);
        set.radii.extend(std::iter::repeat_n(r, sp.count));
        set.masses.extend(std::iter::repeat_n(sp.mass, sp.count));
        set.species.extend(std::iter::repeat_n(s as u32, sp.count));
    }
    if scenario.initial().zero_momentum {
        setup::remove_drift(&mut set.velocities, &set.masses);
    }
    (set.inertia, set.angular_velocities) = rotation::rotation(scenario);
    if compress.is_some() {
        let mut small = set.clone();
        small.radii.iter_mut().for_each(|r| *r /= shrink);
        set.positions = init::compress(&bx, small, &set.radii, &mut rng).map_err(|source| {
            BuildError::Init {
                species: scenario.species()[0].name.clone(),
                source,
            }
        })?;
    }
    setup::check_overlaps(&bx, &set).map_err(|o| BuildError::Overlap {
        a: o.a,
        b: o.b,
        distance: o.distance,
        sigma: o.sigma,
    })?;
    Ok((bx, set))
}

fn build_edmd<const D: usize>(
    scenario: &Scenario,
    options: EdmdOptions,
) -> Result<Edmd<D>, BuildError> {
    let (bx, set) = initial_particles::<D>(scenario)?;
    Ok(Edmd::new(bx, set, scenario.collisions().law(), options))
}

/// The DSMC engine's initial state, grain by grain (`crate::dsmc::setup`): every grain's
/// position and velocity follow from its id, so that a run split over ranks creates on
/// each rank only its own grains, the same bits for any number of ranks and threads.
/// Unlike the event-driven engine's random *sequential* placement, random placement here
/// draws every grain independently (DSMC grains may overlap).
pub(crate) fn dsmc_setup<const D: usize>(
    scenario: &Scenario,
) -> Result<(SimulationBox<D>, crate::dsmc::GrainSetup<D>), BuildError> {
    use crate::dsmc::{GrainSetup, InitialVelocity, SpeciesSetup};
    let axes = scenario.axes();
    let mut ax = [crate::boundary::AxisKind::Wall; D];
    ax.copy_from_slice(&axes[..D]);
    let bx = SimulationBox {
        lengths: vector::<D>(&scenario.lengths()),
        axes: ax,
    };
    let radius = scenario.radius(0);
    let mass = scenario.species().first().map_or(1.0, |s| s.mass);
    let mut species = Vec::with_capacity(scenario.species().len());
    for (s, sp) in scenario.species().iter().enumerate() {
        let region = match &sp.region {
            Some(reg) => Region {
                lo: vector::<D>(&reg.lo),
                hi: vector::<D>(&reg.hi),
            },
            None => Region::whole(&bx),
        };
        let init_err = |source| BuildError::Init {
            species: sp.name.clone(),
            source,
        };
        let placement = if !sp.positions.is_empty() {
            crate::dsmc::Placement::Given(std::sync::Arc::new(
                sp.positions.iter().map(vector::<D>).collect(),
            ))
        } else {
            match scenario.initial().placement {
                Placement::Random => {
                    for k in 0..D {
                        let (a, b) = region.centre_range(&bx, k, scenario.radius(s));
                        if b < a {
                            return Err(init_err(InitError::DoesNotFit {
                                radius: scenario.radius(s),
                                lo: region.lo.0.to_vec(),
                                hi: region.hi.0.to_vec(),
                            }));
                        }
                    }
                    crate::dsmc::Placement::Random(region)
                }
                Placement::Lattice => crate::dsmc::Placement::Lattice(
                    setup::Lattice::new(&bx, &region, sp.count, scenario.radius(s))
                        .map_err(init_err)?,
                ),
            }
        };
        let velocity = match &sp.velocity {
            VelocitySpec::Zero => InitialVelocity::Zero,
            VelocitySpec::FixedSpeed { speed } => InitialVelocity::FixedSpeed(*speed),
            VelocitySpec::MaxwellBoltzmann { temperature } => {
                InitialVelocity::MaxwellBoltzmann(*temperature)
            }
            VelocitySpec::Given { velocity } => InitialVelocity::Given(vector::<D>(velocity)),
            VelocitySpec::PerGrain { velocities } => InitialVelocity::PerGrain(
                std::sync::Arc::new(velocities.iter().map(vector::<D>).collect()),
            ),
        };
        let angular_velocity = match &sp.angular_velocity {
            None | Some(AngularVelocitySpec::Zero) => crate::dsmc::InitialSpin::Zero,
            Some(AngularVelocitySpec::MaxwellBoltzmann { temperature }) => {
                crate::dsmc::InitialSpin::MaxwellBoltzmann(*temperature)
            }
            Some(AngularVelocitySpec::Given { angular_velocity }) => {
                // `[ω_z]` of a disk, `[ω_x, ω_y, ω_z]` of a sphere (validated).
                let mut w = [0.0; 3];
                let r = angular_velocity.len().min(3);
                w[3 - r..].copy_from_slice(&angular_velocity[..r]);
                crate::dsmc::InitialSpin::Given(w)
            }
        };
        species.push(SpeciesSetup {
            name: sp.name.clone(),
            count: sp.count,
            placement,
            velocity,
            angular_velocity,
        });
    }
    Ok((
        bx,
        GrainSetup {
            species,
            radius,
            mass,
            inertia: rotation::inertia(scenario).and_then(|k| k.first().copied()),
            zero_momentum: scenario.initial().zero_momentum,
            seed: scenario.seed,
        },
    ))
}

/// The DSMC engine of a scenario with its configuration `config` ([`DsmcSpec::config`]):
/// the whole engine, or with `ranks` this rank's slab (collective; see [`dsmc_setup`]).
/// With `memory`, the most loaded rank must fit in its share of the node
/// ([`MemoryBudget::check`]).
///
/// [`DsmcSpec::config`]: crate::scenario::DsmcSpec::config
fn build_dsmc<const D: usize>(
    scenario: &Scenario,
    config: DsmcConfig,
    ranks: Option<crate::dsmc::setup::OnRanks>,
    memory: Option<MemoryBudget>,
) -> Result<DsmcEngine<D>, BuildError> {
    let (bx, setup) = dsmc_setup::<D>(scenario)?;
    let seed = crate::random::derive_key(scenario.seed, &[crate::random::DYNAMICS]);
    let check = memory
        .map(|budget| move |load: &crate::dsmc::setup::RankLoad| budget.check(scenario, D, load));
    let check = check
        .as_ref()
        .map(|c| c as crate::dsmc::setup::OwnGrainsCheck<'_>);
    DsmcEngine::from_setup(config, bx, &setup, seed, ranks, check)
        .map_err(|e| BuildError::Dsmc(e.to_string()))
}
