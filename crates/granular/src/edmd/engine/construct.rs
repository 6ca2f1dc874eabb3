//! Building the engine: the grain records and kinds, the cell grid, the first
//! predictions and the event queue.

use super::collapse::CollapseWatch;
use super::events::{FIRST_SPECIAL, Scheduled};
use super::{Edmd, EdmdOptions, RECORD_ALIGN, Records, Totals};
use crate::boundary::SimulationBox;
use crate::collision_law::{CollisionLaw, rough};
use crate::edmd::candidates::Grain;
use crate::edmd::queue::EventQueue;
use crate::neighbours::{Candidates, CellGrid, NONE};
use crate::particles::ParticleSet;
use crate::stats::Histogram;
use crate::vector::Vector;

impl<const D: usize> Edmd<D> {
    /// Builds the engine from grains in a box. The grains must not overlap (see
    /// `crate::setup` for placements); the caller validates inputs.
    pub fn new(
        bx: SimulationBox<D>,
        particles: ParticleSet<D>,
        law: CollisionLaw,
        options: EdmdOptions,
    ) -> Self {
        Self::with_growth(bx, particles, law, options, 0.0, 1.0)
    }

    /// Like [`Edmd::new`], with radii growing at relative rate `growth` and cells sized for
    /// radii up to `radius_scale` times the initial ones (compression).
    pub(crate) fn with_growth(
        bx: SimulationBox<D>,
        particles: ParticleSet<D>,
        law: CollisionLaw,
        options: EdmdOptions,
        growth: f64,
        radius_scale: f64,
    ) -> Self {
        let n = particles.len();
        assert!(
            (n as u64) < FIRST_SPECIAL as u64,
            "the event-driven engine holds fewer than {FIRST_SPECIAL} grains"
        );
        let mut gravity = Vector::zero();
        for (k, g) in options.gravity.iter().enumerate().take(D) {
            gravity[k] = *g;
        }
        let has_gravity = gravity.norm_squared() > 0.0;
        let max_radius = particles.radii.iter().cloned().fold(0.0, f64::max);
        let min_radius = particles
            .radii
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        // Grain kinds: distinct (radius, mass, species), numbered by first appearance.
        let mut kinds: std::collections::HashMap<(u64, u64, u32), u32> = Default::default();
        let (mut kind_radius, mut kind_mass, mut kind_species) = (vec![], vec![], vec![]);
        let mut grains = Records::with_capacity(RECORD_ALIGN, n);
        for i in 0..n {
            let (r, m) = (particles.radii[i], particles.masses[i]);
            let s = particles.species.get(i).copied().unwrap_or(0);
            let kind = *kinds
                .entry((r.to_bits(), m.to_bits(), s))
                .or_insert_with(|| {
                    kind_radius.push(r);
                    kind_mass.push(m);
                    kind_species.push(s);
                    (kind_radius.len() - 1) as u32
                });
            let mut x = particles.positions[i];
            bx.wrap(&mut x);
            grains.push(Grain {
                pos: x,
                vel: particles.velocities[i],
                time: 0.0,
                counter: 0,
                kind,
            });
        }
        // A few grains much larger than the rest stay out of the cell lists, so that
        // the cells fit the others (`neighbours::large_grain_cut`; not while radii grow).
        let (cells, cut) = CellGrid::for_radii(&bx, &particles.radii, radius_scale, growth == 0.0);
        let impact = Histogram::new(0.0, 1.0 + 1e-12, options.impact_bins.max(1));
        let last_collision = if law.contact_duration > 0.0 {
            vec![f64::NEG_INFINITY; n]
        } else {
            Vec::new()
        };
        let (kind_inertia, spin) = if law.is_rough() {
            rotation::<D>(&particles, &kind_species)
        } else {
            (Vec::new(), Vec::new())
        };
        let mut engine = Self {
            law,
            gravity,
            has_gravity,
            growth,
            options,
            grains,
            event: vec![Scheduled::NOTHING; n],
            last_partner: vec![NONE; n],
            last_collision,
            id: (0..n as u32).collect(),
            slot: std::sync::OnceLock::new(),
            kind_radius,
            kind_mass,
            kind_species,
            kind_inertia,
            spin,
            queue: EventQueue::new(n),
            cells,
            species_names: particles.species_names,
            now: 0.0,
            origin: 0.0,
            events_since_rebase: 0,
            totals: Totals::default(),
            impact,
            collapse: CollapseWatch::default(),
            max_radius,
            min_radius,
            bx,
            log: None,
            candidates: Candidates::default(),
            driving: None,
        };
        for i in 0..n {
            let c = engine.cells.coords_of(&engine.grains[i].pos.0);
            let r = engine.base_radius(i);
            engine.cells.insert_grain(i, c, r, cut);
        }
        engine.reorder();
        for i in 0..n {
            engine.predict(i);
        }
        engine.queue.rebuild(engine.now);
        engine
    }
}

/// The rotation of rough grains: κ of each kind (from its species, or that of a uniform
/// grain) and the angular velocities in input order (zero when the set has none).
pub(super) fn rotation<const D: usize>(
    particles: &ParticleSet<D>,
    kind_species: &[u32],
) -> (Vec<f64>, Vec<f64>) {
    let inertia = kind_species
        .iter()
        .map(|&s| {
            particles
                .inertia
                .get(s as usize)
                .copied()
                .unwrap_or(rough::uniform_inertia(D))
        })
        .collect();
    let values = rough::rotational_dof(D) * particles.len();
    let spin = if particles.angular_velocities.len() == values {
        particles.angular_velocities.clone()
    } else {
        vec![0.0; values]
    };
    (inertia, spin)
}
