//! The DSMC engine behind the library's [`Engine`] trait: advancing to a time with the
//! automatic time step, the typed observation, the state copies and snapshots.

use super::DsmcEngine;
use crate::engine::{Engine, EngineError, Progress, Snapshot};
use crate::observation::{DsmcCounters, Observation};
use crate::stats::Histogram;

impl<const D: usize> Engine for DsmcEngine<D> {
    fn name(&self) -> &'static str {
        "dsmc"
    }

    fn time(&self) -> f64 {
        self.time
    }

    /// Time steps plus collisions.
    fn events(&self) -> u64 {
        self.steps + self.tally.collisions
    }

    fn collisions(&self) -> u64 {
        self.tally.collisions
    }

    fn particle_count(&self) -> usize {
        self.n_global()
    }

    /// Steps of `tau` (the last one shortened to land exactly on `until`); stops after the
    /// first step at which the events of this call reach `max_events`. Without an explicit
    /// `time_step`, `tau` is recomputed before every step as [`STEP_FRACTION`](super::STEP_FRACTION) of the
    /// current mean free time (see `DsmcEngine::follow_mean_free_time`). A steady-state
    /// driving ([`DsmcEngine::set_driving`]) acts after every step.
    fn advance(&mut self, until: f64, max_events: u64) -> Result<Progress, EngineError> {
        let e0 = self.events();
        while self.time < until {
            if self.config.time_step.is_none() {
                self.follow_mean_free_time();
            }
            let left = until - self.time;
            let dt = if left <= self.tau * (1.0 + 1e-9) {
                left
            } else {
                self.tau
            };
            self.step(dt);
            self.drive(dt);
            if left <= self.tau * (1.0 + 1e-9) {
                self.time = until;
            }
            if let Some(id) = self.first_non_finite() {
                return Err(EngineError::Numerical(format!(
                    "non-finite velocity of particle {id} at t = {}",
                    self.time
                )));
            }
            if self.time < until && self.events() - e0 >= max_events {
                return Ok(Progress::BudgetExhausted);
            }
        }
        Ok(Progress::Reached)
    }

    fn observe(&self) -> Observation {
        let (c2, c4) = self.peculiar_moments();
        let n = self.n_global();
        let d = D as f64;
        let kinetic = self.kinetic_energy_now();
        let rotational = self.rotational_energy_now();
        let volume = self.sim_box.volume();
        let wall_area: f64 = (0..D)
            .filter(|&k| !self.sim_box.is_periodic(k))
            .map(|k| 2.0 * volume / self.sim_box.lengths[k])
            .sum();
        Observation {
            engine: "dsmc".into(),
            dimension: D,
            particles: n,
            time: self.time,
            events: self.events(),
            collisions: self.tally.collisions,
            collisions_per_particle: 2.0 * self.tally.collisions as f64 / n as f64,
            kinetic_energy: kinetic,
            temperature: self.mass * c2 / d,
            species: Vec::new(),
            wall_collisions: None,
            dissipated_energy: self
                .driving
                .as_ref()
                .map(|s| s.dissipated(kinetic + rotational.unwrap_or(0.0))),
            tc_elastic_collisions: Some(self.tc_elastic_collisions()),
            virial: None,
            wall_impulse: None,
            volume,
            wall_area,
            a2: Some(d / (d + 2.0) * c4 / (c2 * c2) - 1.0),
            dsmc: Some(DsmcCounters {
                steps: self.steps,
                vmax_exceeded: self.tally.vmax_exceeded,
            }),
            engine_specific: self
                .driving
                .as_ref()
                .map(|s| vec![("injected_energy".to_string(), s.injected_energy)])
                .unwrap_or_default(),
            rotational_energy: rotational,
            rotational_temperature: rotational
                .map(|e| 2.0 * e / (crate::collision_law::rough::rotational_dof(D) * n) as f64),
        }
    }

    /// Translational plus (rough grains) rotational kinetic energy.
    fn kinetic_energy(&self) -> f64 {
        self.kinetic_energy_now() + self.rotational_energy_now().unwrap_or(0.0)
    }

    fn impact_histogram(&self) -> Option<Histogram> {
        Some(DsmcEngine::impact_histogram(self))
    }

    /// The stored order is the cells' (sorted every step); scattered by grain id.
    fn state_into(&self, velocities: bool, out: &mut [f64]) -> bool {
        if self.domain.is_some() {
            return self.whole().state_into(velocities, out);
        }
        let g = &self.grains;
        if velocities {
            crate::particles::scatter_by_id::<D>(&g.ids(), out, |s| g.velocity(s).0);
        } else {
            crate::particles::scatter_by_id::<D>(&g.ids(), out, |s| g.position(s).0);
        }
        true
    }

    fn snapshot(&self) -> Option<Snapshot> {
        let (p, v) = self.state_by_id();
        let n = p.len();
        Some(Snapshot {
            time: self.time,
            dimension: D,
            positions: p.iter().flat_map(|x| x.0).collect(),
            velocities: v.iter().flat_map(|x| x.0).collect(),
            radii: vec![self.radius; n],
            masses: vec![self.mass; n],
            species: (0..n as u32).map(|id| self.species.of(id)).collect(),
            species_names: self.species.names.clone(),
            angular_velocities: self.angular_velocities(),
        })
    }
}
