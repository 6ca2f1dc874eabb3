//! The DSMC engine: operator splitting of free flight and stochastic collisions.

use super::cells::CellGrid;
use super::collide::Tally;
use super::config::DsmcConfig;
use super::grains::Grains;
use super::guards::{self, ValidityWarning};
use super::lattice::Lattice;
use super::observables::{self, DensityMap, StructureFactor};
use super::sums::SUM_CHUNK;
use crate::boundary::SimulationBox;
use crate::collision_law::CollisionLaw;
use crate::particles::ParticleSet;
use crate::random::{INITIAL_STATE, RngExt, stream};
use crate::stats::Histogram;
use crate::theory::haff;
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};

mod as_engine;
mod moments;
mod restart;
mod slab;
mod step;
pub use slab::UniformGas;

/// Why a DSMC engine could not be built.
#[derive(Debug, thiserror::Error)]
pub enum DsmcError {
    /// A configuration value or an initial state is invalid; the message says which.
    #[error("invalid DSMC set-up: {0}")]
    Invalid(String),
    /// The engine cannot be split over the ranks asked for.
    #[error(transparent)]
    Domain(#[from] super::domain::DomainError),
}

pub use super::config::STEP_FRACTION;

/// Direct Simulation Monte Carlo of `N` equal hard grains (disks for `D = 2`, spheres
/// for `D = 3`), after Müller & Herrmann's DSMC paper. See the module docs.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct DsmcEngine<const D: usize> {
    config: DsmcConfig,
    sim_box: SimulationBox<D>,
    pub(super) grid: CellGrid<D>,
    radius: f64,
    mass: f64,
    pub(super) seed: u64,
    tau: f64,
    gravity: Vector<D>,
    chi_global: f64,
    /// The grains' records, sorted by cell (see `cells`).
    pub(super) grains: Grains<D>,
    /// The first storage slot of each owned cell (the cells of this rank's slab when
    /// decomposed, relative to its first cell; every cell otherwise), then the number of
    /// grains: cell `c` holds `start[c] .. start[c + 1]`.
    pub(super) start: Vec<u32>,
    /// Each grain's new cell after the free flight, then its slot in the sort (scratch of
    /// the step, kept between steps; not part of the state).
    #[serde(skip)]
    pub(super) dest: Vec<u32>,
    time: f64,
    steps: u64,
    pub(super) tally: Tally,
    /// The species of the grains (names and id ranges), for snapshots and histograms.
    pub(super) species: super::species::SpeciesTable,
    /// The validity conditions violated by the initial state (computed once at build).
    #[serde(default)]
    validity: Vec<ValidityWarning>,
    /// This rank's share of a decomposed run (`None`: the whole system, see `domain`);
    /// never written to checkpoints, which hold the whole system.
    #[serde(skip)]
    pub(super) domain: Option<super::domain::Domain>,
    /// The steady-state driving ([`crate::driving`]) and its tally, applied after every
    /// step; `None`: a free (cooling) gas.
    #[serde(default)]
    pub(super) driving: Option<crate::driving::DrivingState>,
    /// Where the random streams restarted after the grains were set from outside
    /// ([`DsmcEngine::restart`]); `None` before any.
    #[serde(default)]
    restart: Option<restart::StreamRestart>,
    /// The reduced moment of inertia κ = 4I/(mσ²) of rough grains (RS-1), whose records
    /// then carry angular velocities; `None` for smooth grains.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    inertia: Option<f64>,
}

/// The rotation of rough grains at construction: κ and the angular velocities (`d_r`
/// values per grain, in the order of the positions given with them).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Rotation {
    /// The reduced moment of inertia κ = 4I/(mσ²), in (0, 1] for disks and (0, 2/3] for
    /// spheres.
    pub inertia: f64,
    /// `ω_z` per disk, or `ω_x, ω_y, ω_z` per sphere (radians per time unit).
    pub spins: Vec<f64>,
}

fn default_species_name() -> String {
    "grain".into()
}

impl<const D: usize> DsmcEngine<D> {
    /// `n` grains of radius `radius` and mass `mass` at uniformly random positions, with
    /// Maxwell-Boltzmann velocities at temperature `temperature`, shifted to zero total
    /// momentum and rescaled so that the kinetic temperature is exactly `temperature`.
    pub fn new(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        n: usize,
        radius: f64,
        mass: f64,
        temperature: f64,
        seed: u64,
    ) -> Result<Self, DsmcError> {
        if n < 2 {
            return Err(DsmcError::Invalid(format!(
                "need at least 2 particles, got {n}"
            )));
        }
        if !positive(temperature) {
            return Err(DsmcError::Invalid(format!(
                "temperature {temperature} must be > 0"
            )));
        }
        let mut rng = stream(seed, &[INITIAL_STATE]);
        let mut pos = Vec::with_capacity(n);
        let mut vel = Vec::with_capacity(n);
        for _ in 0..n {
            let mut x = Vector::<D>::zero();
            for k in 0..D {
                x[k] = rng.random::<f64>() * sim_box.lengths[k];
            }
            pos.push(x);
        }
        let mut mean = Vector::<D>::zero();
        for _ in 0..n {
            let mut v = Vector::<D>::zero();
            for k in 0..D {
                v[k] = StandardNormal.sample(&mut rng);
            }
            mean += v;
            vel.push(v);
        }
        mean = mean * (1.0 / n as f64);
        let mut sum2 = 0.0;
        for v in vel.iter_mut() {
            *v -= mean;
            sum2 += v.norm_squared();
        }
        let scale = (temperature * (D * n) as f64 / (mass * sum2)).sqrt();
        for v in vel.iter_mut() {
            *v = *v * scale;
        }
        Self::from_state(config, sim_box, radius, mass, pos, vel, seed)
    }

    /// An engine from a particle set of one species (the shared placement and velocities
    /// of `crate::setup`): every grain must have the same radius and mass. Snapshots carry
    /// the set's species name.
    pub fn from_particles(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        particles: ParticleSet<D>,
        seed: u64,
    ) -> Result<Self, DsmcError> {
        let (Some(&radius), Some(&mass)) = (particles.radii.first(), particles.masses.first())
        else {
            return Err(DsmcError::Invalid(
                "need at least 2 particles, got 0".into(),
            ));
        };
        if particles.radii.iter().any(|&r| r != radius)
            || particles.masses.iter().any(|&m| m != mass)
        {
            return Err(DsmcError::Invalid(
                "the DSMC engine takes grains of one radius and one mass; give one species".into(),
            ));
        }
        let name = particles
            .species_names
            .first()
            .cloned()
            .unwrap_or_else(default_species_name);
        let mut engine = Self::from_state(
            config,
            sim_box,
            radius,
            mass,
            particles.positions,
            particles.velocities,
            seed,
        )?;
        engine.species = super::species::SpeciesTable::one(&name, engine.n_global());
        Ok(engine)
    }

    /// An engine from explicit positions and velocities (equal radius and mass). Its one
    /// species is called `grain`.
    pub fn from_state(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        radius: f64,
        mass: f64,
        positions: Vec<Vector<D>>,
        velocities: Vec<Vector<D>>,
        seed: u64,
    ) -> Result<Self, DsmcError> {
        let n = positions.len();
        if n != velocities.len() || n == 0 {
            return Err(DsmcError::Invalid(format!(
                "{} positions and {} velocities",
                n,
                velocities.len()
            )));
        }
        // Initial temperature for the automatic time step (sums in the order of the ids).
        let t0 = || {
            let mut u = Vector::<D>::zero();
            for v in &velocities {
                u += *v;
            }
            u = u * (1.0 / n as f64);
            mass * velocities
                .iter()
                .map(|v| (*v - u).norm_squared())
                .sum::<f64>()
                / (D * n) as f64
        };
        let derived = Derived::new(&config, &sim_box, n, radius, mass, t0)?;
        let mut pos = positions;
        for x in pos.iter_mut() {
            derived.place(&sim_box, x)?;
        }
        let ids = (0..n as u32).collect();
        Ok(Self::assemble(
            config, sim_box, radius, mass, seed, derived, pos, velocities, ids, None, None,
        ))
    }

    /// The engine holding `pos`, `vel` and `ids` (in the order of the ids), sorted by
    /// cell, with its validity warnings: the whole engine when `domain` is `None`, else
    /// this rank's slab (the particles of its cells, `n_global` in all; collective then).
    /// `rotation`: rough grains, their spins in the order of `pos`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn assemble(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        radius: f64,
        mass: f64,
        seed: u64,
        derived: Derived<D>,
        pos: Vec<Vector<D>>,
        vel: Vec<Vector<D>>,
        ids: Vec<u32>,
        domain: Option<super::domain::Domain>,
        rotation: Option<Rotation>,
    ) -> Self {
        let mut grains = Grains::from_parts(derived.lattice, &pos, &vel, &ids, config.law.has_tc());
        drop((pos, vel, ids));
        let inertia = rotation.map(|r| {
            grains.set_spins(Some(&r.spins));
            r.inertia
        });
        Self::assemble_grains(
            config, sim_box, radius, mass, seed, derived, grains, domain, inertia,
        )
    }

    /// [`Self::assemble`] of records already made (`inertia`: rough grains, whose records
    /// carry their spins).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn assemble_grains(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        radius: f64,
        mass: f64,
        seed: u64,
        derived: Derived<D>,
        grains: Grains<D>,
        domain: Option<super::domain::Domain>,
        inertia: Option<f64>,
    ) -> Self {
        let n = grains.len();
        let n_global = domain.as_ref().map_or(n, |d| d.n_global);
        let mut engine = Self {
            tally: Tally {
                impact: vec![0; config.impact_bins],
                ..Tally::default()
            },
            config,
            sim_box,
            grid: derived.grid,
            radius,
            mass,
            seed,
            tau: derived.tau,
            gravity: derived.gravity,
            chi_global: derived.chi_global,
            grains,
            start: Vec::new(),
            dest: Vec::new(),
            time: 0.0,
            steps: 0,
            species: super::species::SpeciesTable::one(&default_species_name(), n_global),
            validity: Vec::new(),
            domain,
            driving: None,
            restart: None,
            inertia,
        };
        engine.sort_in_place();
        engine.validity = engine.check_validity();
        engine
    }

    /// Replaces the collision law from the next step on (as the event-driven engine's
    /// `set_collision_law`). Turning the TC model on starts every grain with no previous
    /// collision; turning it off forgets the collision times. Smooth grains stay smooth
    /// (they carry no angular velocities: a rough law is refused); rough grains under a
    /// smooth law (β = -1) keep their angular velocities unchanged.
    pub fn set_collision_law(&mut self, law: CollisionLaw) -> Result<(), DsmcError> {
        check_law(&law)?;
        if law.is_rough() && !self.is_rough() {
            return Err(DsmcError::Invalid(format!(
                "law.tangential_restitution is {}, but the grains are smooth: they carry no angular velocities and cannot become rough in flight",
                law.tangential_restitution,
            )));
        }
        self.grains.set_collision_times(law.has_tc());
        self.config.law = law;
        Ok(())
    }

    /// The engine without its particles (what a checkpoint's manifest holds beside the
    /// parts): every parameter, the time, the counters. [`DsmcEngine::load_parts`] puts
    /// the particles back.
    pub(crate) fn shell(&self) -> DsmcEngine<D> {
        DsmcEngine {
            config: self.config.clone(),
            sim_box: self.sim_box.clone(),
            grid: self.grid.clone(),
            radius: self.radius,
            mass: self.mass,
            seed: self.seed,
            tau: self.tau,
            gravity: self.gravity,
            chi_global: self.chi_global,
            grains: self.grains.range(0..0),
            start: Vec::new(),
            dest: Vec::new(),
            time: self.time,
            steps: self.steps,
            tally: self.tally.clone(),
            species: self.species.clone(),
            validity: self.validity.clone(),
            domain: None,
            driving: self.driving.clone(),
            restart: self.restart,
            inertia: self.inertia,
        }
    }

    /// Makes the grains rough from now on: the rough collision law `law` (β > -1 or a
    /// friction coefficient), the reduced moment of inertia `inertia` (κ) and the angular
    /// velocities `spins_by_id` (`d_r` values per grain by id: `ω_z` in 2D, `ω_x, ω_y, ω_z`
    /// in 3D). Refused on a decomposed engine, for a smooth law, a κ out of range or a
    /// wrong number of values.
    pub fn make_rough(
        &mut self,
        law: CollisionLaw,
        inertia: f64,
        spins_by_id: &[f64],
    ) -> Result<(), DsmcError> {
        use crate::collision_law::rough::{max_inertia, rotational_dof, spin_at};
        let bad = |m: String| Err(DsmcError::Invalid(m));
        if self.domain.is_some() {
            return bad("the grains of a run split over ranks cannot be made rough".into());
        }
        if !law.is_rough() {
            return bad(
                "law.tangential_restitution is -1: the law is that of smooth grains".into(),
            );
        }
        if !(inertia > 0.0 && inertia <= max_inertia(D)) {
            return bad(format!(
                "inertia {inertia}: κ must lie in (0, {}]",
                max_inertia(D)
            ));
        }
        let n = self.grains.len();
        if spins_by_id.len() != rotational_dof(D) * n {
            return bad(format!(
                "{} angular velocity values for {n} grains in {D} dimensions (give {})",
                spins_by_id.len(),
                rotational_dof(D) * n
            ));
        }
        check_law(&law)?;
        let ids = self.grains.ids();
        let mut flat = vec![0.0; rotational_dof(D) * n];
        for (k, &id) in ids.iter().enumerate() {
            let w = spin_at::<D>(spins_by_id, id as usize);
            crate::collision_law::rough::set_spin::<D>(&mut flat, k, &w);
        }
        self.grains.set_spins(Some(&flat));
        self.grains.set_collision_times(law.has_tc());
        self.config.law = law;
        self.inertia = Some(inertia);
        Ok(())
    }

    /// Whether the grains are rough (they carry angular velocities).
    pub(crate) fn is_rough(&self) -> bool {
        self.inertia.is_some()
    }

    /// The grains as a rough collision sees them (`κ` 0 for smooth grains).
    pub(super) fn body(&self) -> crate::collision_law::Body {
        crate::collision_law::Body {
            mass: self.mass,
            radius: self.radius,
            inertia: self.inertia.unwrap_or(0.0),
        }
    }

    /// Angular velocities of rough grains by id, `d_r` values per grain (`ω_z` in 2D);
    /// empty for smooth grains.
    pub fn angular_velocities(&self) -> Vec<f64> {
        if self.domain.is_some() {
            return self.whole().angular_velocities();
        }
        let g = &self.grains;
        if !g.is_rough() {
            return Vec::new();
        }
        let r = crate::collision_law::rough::rotational_dof(D);
        let mut out = vec![0.0; r * g.len()];
        for k in 0..g.len() {
            let id = g.id(k) as usize;
            crate::collision_law::rough::set_spin::<D>(&mut out, id, &g.spin(k));
        }
        out
    }

    /// The time step `tau` in use.
    pub fn time_step(&self) -> f64 {
        self.tau
    }

    /// The cell grid in use.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.grid
    }

    /// The configuration.
    pub fn config(&self) -> &DsmcConfig {
        &self.config
    }

    /// The simulation box.
    pub fn sim_box(&self) -> &SimulationBox<D> {
        &self.sim_box
    }

    /// Grain radius.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Grain mass.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Number density `N / V`.
    pub fn number_density(&self) -> f64 {
        self.n_global() as f64 / self.sim_box.volume()
    }

    /// The global Enskog factor used when `enskog` is on with a global density (1 otherwise).
    pub fn enskog_factor(&self) -> f64 {
        self.chi_global
    }

    /// Number of time steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Collisions (pair and wall) made elastic by the TC rule so far (section 2.3 of the
    /// hard-disk assignment; counted by [`CollisionLaw`]): those that would otherwise have lost
    /// energy. Zero without the TC model.
    pub fn tc_elastic_collisions(&self) -> u64 {
        self.tally.tc_elastic
    }

    /// Name of the engine's first species (as in snapshots).
    pub fn species_name(&self) -> &str {
        self.species.names.first().map_or("grain", String::as_str)
    }

    /// The species of the grains: their names and id ranges.
    pub(crate) fn species(&self) -> &super::species::SpeciesTable {
        &self.species
    }

    /// Names the species of the grains (contiguous id ranges; the table must cover the
    /// engine's `N` grains).
    pub(super) fn set_species(&mut self, species: super::species::SpeciesTable) {
        self.species = species;
    }

    /// How often a candidate's relative speed exceeded the current `v_max`.
    pub fn vmax_exceeded(&self) -> u64 {
        self.tally.vmax_exceeded
    }

    /// Bytes this engine (this rank's share, when decomposed) holds for its grains and
    /// cells, from the capacities of its buffers: the grains' records and the sort's
    /// scratch column ([`Grains::bytes`]), each grain's destination of the step (4 bytes)
    /// and the owned cells' offsets (4 bytes a cell).
    pub(crate) fn held_bytes(&self) -> usize {
        self.grains.bytes() + 4 * self.dest.capacity() + 4 * self.start.capacity()
    }

    /// Positions in storage (cell) order (a copy).
    pub fn positions(&self) -> Vec<Vector<D>> {
        self.grains.positions()
    }

    /// Velocities in storage (cell) order (a copy).
    pub fn velocities(&self) -> Vec<Vector<D>> {
        self.grains.velocities()
    }

    /// Particle identities (their index at construction) in storage order (a copy).
    pub fn ids(&self) -> Vec<u32> {
        self.grains.ids()
    }

    /// The grains' records (this rank's, when decomposed), in storage order.
    pub(crate) fn grains(&self) -> &Grains<D> {
        &self.grains
    }

    /// Positions and velocities in the order of construction (ids `0 .. N`).
    pub fn state_by_id(&self) -> (Vec<Vector<D>>, Vec<Vector<D>>) {
        if self.domain.is_some() {
            return self.whole().state_by_id();
        }
        let g = &self.grains;
        let n = g.len();
        let mut p = vec![Vector::zero(); n];
        let mut v = vec![Vector::zero(); n];
        for k in 0..n {
            let id = g.id(k) as usize;
            p[id] = g.position(k);
            v[id] = g.velocity(k);
        }
        (p, v)
    }

    /// Histogram of `|b| / 2R` over all accepted collisions so far (`impact_bins` bins on
    /// `[0, 1)`): flat in 2D, density `2x` in 3D under molecular chaos.
    pub fn impact_histogram(&self) -> Histogram {
        let mut h = Histogram::new(0.0, 1.0, self.tally.impact.len().max(1));
        for (c, &k) in h.counts.iter_mut().zip(&self.tally.impact) {
            *c = k;
        }
        h
    }

    /// Static structure factor `S(k) = |sum_j exp(i k.x_j)|^2 / N` for the wave vectors
    /// `k = 2 pi (n_0 / L_0, ...)` with `0 < max_k |n_k| <= max_index`, binned by `|k|`.
    pub fn structure_factor(&self, max_index: usize) -> StructureFactor {
        observables::structure_factor(&self.grains.positions(), &self.sim_box.lengths.0, max_index)
    }

    /// Number density on a regular grid of `dims` bins (axis 0 fastest).
    pub fn density_map(&self, dims: [usize; D]) -> DensityMap {
        observables::density_map(&self.grains.positions(), &self.sim_box.lengths.0, dims)
    }

    /// The validity conditions of Müller & Herrmann's DSMC paper (Sec. 2) violated by the initial state,
    /// with numbers: computed once when the engine is built. See [`Self::check_validity`]
    /// for the current state.
    pub fn validity_warnings(&self) -> &[ValidityWarning] {
        &self.validity
    }

    /// The validity conditions of Müller & Herrmann's DSMC paper (Sec. 2) at the current state (the gas
    /// cools, so the mean free time grows): warnings, with numbers, for each one that is
    /// violated.
    pub fn check_validity(&self) -> Vec<ValidityWarning> {
        let edge = self.grid.edges.iter().cloned().fold(0.0, f64::max);
        let min_len = self
            .sim_box
            .lengths
            .0
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        guards::check(&guards::GuardInput {
            dimension: D,
            number_density: self.number_density(),
            radius: self.radius,
            mass: self.mass,
            temperature: self.temperature(),
            chi: self.chi_global,
            cell_edge: edge,
            time_step: self.tau,
            particles_per_cell: self.n_global() as f64 / self.grid.len() as f64,
            system_size: min_len,
        })
    }

    /// Sets the time step to [`STEP_FRACTION`] of the current mean free time `1 / omega(T)`
    /// (DSMC-3, `omega` the Enskog-Boltzmann collision frequency at the current granular
    /// temperature `T`). `T` is a chunked sum in a fixed order, so the step is the same for
    /// any number of threads. A gas at rest keeps the step it had. A fixed step (0.1 of
    /// the *initial* mean free time) made a cooling gas take ever more steps per collision:
    /// 180 908 steps for 250 collisions per grain of `dsmc-cooling`.
    pub(crate) fn follow_mean_free_time(&mut self) {
        let omega = haff::collision_frequency(
            D,
            self.number_density(),
            self.radius,
            self.temperature(),
            self.mass,
            self.chi_global,
        );
        if let Some(tau) = super::config::automatic_time_step(omega) {
            self.tau = tau;
        }
    }
}

/// Rejects restitutions outside `[0, 1]`, a tangential restitution outside `[-1, 1]` and a
/// negative or non-finite contact duration.
fn check_law(law: &CollisionLaw) -> Result<(), DsmcError> {
    let beta = law.tangential_restitution;
    if !(-1.0..=1.0).contains(&beta) {
        return Err(DsmcError::Invalid(format!(
            "law.tangential_restitution is {beta}; it must lie in [-1, 1] (-1 = smooth)"
        )));
    }
    for (key, x) in [
        ("restitution", law.restitution),
        ("wall_restitution", law.wall_restitution),
        (
            "wall_tangential_restitution",
            law.wall_tangential_restitution,
        ),
    ] {
        // Rough grains: the wall's tangential factor acts on the contact point, -β_w in
        // [-1, 1].
        let lo = if key == "wall_tangential_restitution" && law.is_rough() {
            -1.0
        } else {
            0.0
        };
        if !(lo..=1.0).contains(&x) {
            return Err(DsmcError::Invalid(format!(
                "law.{key} is {x}; a restitution must lie in [{lo}, 1] (1 = elastic)"
            )));
        }
    }
    let t = law.contact_duration;
    if !(t.is_finite() && t >= 0.0) {
        return Err(DsmcError::Invalid(format!(
            "law.contact_duration is {t}; give a duration >= 0 (0: no TC model)"
        )));
    }
    Ok(())
}

/// `x > 0` (false for NaN).
fn positive(x: f64) -> bool {
    x > 0.0
}

/// What an engine derives from its configuration and initial state before it holds any
/// particle: the same for the whole engine and for every rank's slab.
pub(super) struct Derived<const D: usize> {
    gravity: Vector<D>,
    chi_global: f64,
    tau: f64,
    pub(super) grid: CellGrid<D>,
    /// The lattice of the positions (box and number of grains).
    pub(super) lattice: Lattice<D>,
}

impl<const D: usize> Derived<D> {
    /// Checks the parameters of `n` grains and derives the Enskog factor, the cell grid
    /// and the time step; `t0` (the initial temperature, called only for the automatic
    /// time step) must be summed in the order of the ids, as [`DsmcEngine::from_state`].
    pub(super) fn new(
        config: &DsmcConfig,
        sim_box: &SimulationBox<D>,
        n: usize,
        radius: f64,
        mass: f64,
        t0: impl FnOnce() -> f64,
    ) -> Result<Self, DsmcError> {
        let bad = |m: String| Err(DsmcError::Invalid(m));
        if D != 2 && D != 3 {
            return bad(format!("dimension {D} is not supported (2 or 3)"));
        }
        if n == 0 || n > u32::MAX as usize {
            return bad(format!(
                "{n} grains: the DSMC engine holds from 1 to 4 294 967 295 grains (2^32 - 1: \
                 grain identities are 32 bits) per run"
            ));
        }
        if !positive(radius) || !positive(mass) {
            return bad(format!("radius {radius} and mass {mass} must be > 0"));
        }
        check_law(&config.law)?;
        if !config.gravity.is_empty() && config.gravity.len() != D {
            return bad(format!(
                "gravity has {} components, expected {D}",
                config.gravity.len()
            ));
        }
        if sim_box.lengths.0.iter().any(|&l| !positive(l)) {
            return bad("box lengths must be > 0".into());
        }
        let gravity = Vector::from_slice(&config.gravity).unwrap_or_default();
        let density = n as f64 / sim_box.volume();
        let phi = haff::packing_fraction(D, density, radius);
        if (config.enskog || config.free_volume) && phi >= haff::random_close_packing(D) {
            return bad(format!(
                "packing fraction {phi} exceeds random close packing"
            ));
        }
        let chi_global = if config.enskog {
            haff::contact_value(D, phi)
        } else {
            1.0
        };
        let lambda = haff::mean_free_path(D, density, radius, chi_global);
        let cell_size = match config.cell_size {
            Some(l) if l > 0.0 => l,
            Some(l) => return bad(format!("cell_size {l} must be > 0")),
            None => super::config::default_cell_size(D, density, lambda),
        };
        let tau = match config.time_step {
            Some(t) if t > 0.0 => t,
            Some(t) => return bad(format!("time_step {t} must be > 0")),
            None => super::config::automatic_time_step(haff::collision_frequency(
                D,
                density,
                radius,
                t0(),
                mass,
                chi_global,
            ))
            .unwrap_or(super::config::AT_REST_TIME_STEP),
        };
        let grid = CellGrid::new(sim_box, cell_size);
        if grid.len() >= u32::MAX as usize {
            return bad(format!("{} cells are too many", grid.len()));
        }
        Ok(Derived {
            gravity,
            chi_global,
            tau,
            grid,
            lattice: Lattice::new(sim_box, n),
        })
    }

    /// Wraps `x` into the box (periodic axes) and refuses a position outside it.
    pub(super) fn place(
        &self,
        sim_box: &SimulationBox<D>,
        x: &mut Vector<D>,
    ) -> Result<(), DsmcError> {
        sim_box.wrap(x);
        if (0..D).all(|k| (0.0..=sim_box.lengths[k]).contains(&x[k])) {
            Ok(())
        } else {
            Err(DsmcError::Invalid(format!(
                "position {:?} outside the box",
                x.0
            )))
        }
    }
}
