//! The [`Engine`] trait of the event-driven engine: clock, counters, the driven or free
//! advance, observation, state arrays and snapshots.

use super::Edmd;
use crate::edmd::candidates::Grain;
use crate::engine::{Engine, EngineError, Progress, Snapshot};
use crate::observation::{Observation, SpeciesObservation};

impl<const D: usize> Engine for Edmd<D> {
    fn name(&self) -> &'static str {
        "edmd"
    }

    fn time(&self) -> f64 {
        self.origin + self.now
    }

    fn events(&self) -> u64 {
        self.totals.events
    }

    fn collisions(&self) -> u64 {
        self.totals.pair_collisions
    }

    fn particle_count(&self) -> usize {
        self.len()
    }

    /// Events up to `until`; a steady-state driving ([`Edmd::set_driving`]) acts at its
    /// fixed times in between.
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        if self.driving.is_some() {
            self.advance_driven(until, max_events)
        } else {
            self.advance_events(until, max_events)
        }
    }

    fn observe(&self) -> Observation {
        let n = self.len();
        let volume = self.bx.volume();
        let kinetic = self.kinetic_energy_now();
        let rotation = self.rotational_energy_now();
        let (a2, species_a2) = self.a2_by_species();
        let species = if self.species_names.len() > 1 {
            self.species_kinetic_energy()
                .iter()
                .enumerate()
                .map(|(s, &(k, count))| {
                    let c = count.max(1) as f64;
                    SpeciesObservation {
                        name: self.species_names[s].clone(),
                        grains: count,
                        kinetic_energy_per_grain: k / c,
                        temperature: 2.0 * k / (D as f64 * c),
                        a2: species_a2.get(s).copied(),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        let wall_area: f64 = (0..D)
            .filter(|&k| !self.bx.is_periodic(k))
            .map(|k| 2.0 * volume / self.bx.lengths[k])
            .sum();
        Observation {
            engine: "edmd".into(),
            dimension: D,
            particles: n,
            time: self.time(),
            events: self.totals.events,
            collisions: self.totals.pair_collisions,
            collisions_per_particle: 2.0 * self.totals.pair_collisions as f64 / n as f64,
            kinetic_energy: kinetic,
            temperature: 2.0 * kinetic / (D as f64 * n as f64),
            species,
            rotational_energy: rotation,
            rotational_temperature: rotation.map(|e| {
                2.0 * e / (crate::collision_law::rough::rotational_dof(D) as f64 * n as f64)
            }),
            wall_collisions: Some(self.totals.wall_collisions),
            dissipated_energy: Some(self.totals.dissipated_energy),
            tc_elastic_collisions: Some(self.totals.tc_elastic_collisions),
            virial: Some(self.totals.virial),
            wall_impulse: Some(self.totals.wall_impulse),
            volume,
            wall_area,
            a2: Some(a2),
            dsmc: None,
            engine_specific: self
                .driving
                .as_ref()
                .map(|d| vec![("injected_energy".to_string(), d.state.injected_energy)])
                .unwrap_or_default(),
        }
    }

    /// Translational plus (rough grains) rotational kinetic energy.
    fn kinetic_energy(&self) -> f64 {
        match self.rotational_energy_now() {
            Some(e) => self.kinetic_energy_now() + e,
            None => self.kinetic_energy_now(),
        }
    }

    fn impact_histogram(&self) -> Option<crate::stats::Histogram> {
        Some(Edmd::impact_histogram(self).clone())
    }

    /// Gathers the records by grain id through the slot table (`particles::gather_by_slot`,
    /// built on the first query after a reordering and kept until the next), prefetching
    /// the records a few grains ahead: the output is written in order, on all of rayon's
    /// workers. (A scatter in slot order, the earlier way, scanned the whole order once
    /// per worker and wrote each row at random.)
    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        let grains: &[Grain<D>] = &self.grains;
        let ahead = |next: &[u32]| crate::prefetch::prefetch_all(grains, next);
        if velocities {
            crate::particles::gather_by_slot::<D>(self.slots(), out, ahead, |s| {
                self.velocity_slot(s).0
            });
        } else {
            crate::particles::gather_by_slot::<D>(self.slots(), out, ahead, |s| {
                let mut x = self.position_raw(s);
                self.bx.wrap(&mut x);
                x.0
            });
        }
        true
    }

    fn snapshot(&self) -> Option<Snapshot> {
        let n = self.len();
        let mut positions = Vec::with_capacity(n * D);
        let mut velocities = Vec::with_capacity(n * D);
        for i in 0..n {
            positions.extend_from_slice(&self.position(i).0);
            velocities.extend_from_slice(&self.velocity(i).0);
        }
        Some(Snapshot {
            time: self.time(),
            dimension: D,
            positions,
            velocities,
            radii: self.radii(),
            masses: self.masses(),
            species: self.species(),
            species_names: self.species_names.clone(),
            angular_velocities: self.angular_velocities(),
        })
    }
}
