//! The crater measure of a `[crater]` table: how many grains of the bed species moved
//! farther than a threshold since `t = 0` (the hard-disk assignment's Problem 4).

use super::Output;
use crate::observation::Observation;
use crate::run::summary::CraterSummary;
use crate::run::{RunError, Summary};
use crate::scenario::CraterSpec;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};

/// Bed grains displaced since the start (the initial positions are kept in memory).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Crater {
    spec: CraterSpec,
    /// Initial positions of the bed species' grains, `D` values each, in grain order.
    initial: Vec<f64>,
}

impl Crater {
    /// The measure of `spec`.
    pub fn new(spec: CraterSpec) -> Crater {
        Crater {
            spec,
            initial: Vec::new(),
        }
    }

    /// Positions of the bed species' grains (row-major) and the dimension.
    fn bed_positions(&self, simulation: &Simulation) -> Option<(Vec<f64>, usize)> {
        let snap = simulation.snapshot()?;
        let index = snap
            .species_names
            .iter()
            .position(|n| *n == self.spec.species)?;
        let d = snap.dimension;
        let positions = (0..snap.radii.len())
            .filter(|&i| snap.species[i] as usize == index)
            .flat_map(|i| snap.positions[i * d..(i + 1) * d].to_vec())
            .collect();
        Some((positions, d))
    }
}

impl Output for Crater {
    /// The bed's initial positions; refuses a run over ranks above
    /// `GATHER_LIMIT` (10^6) grains (every rank gathers the whole system
    /// at the start and the end).
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        crate::run::grains::refuse_whole_gather(simulation, "crater")?;
        self.initial = self.bed_positions(simulation).map_or(Vec::new(), |p| p.0);
        Ok(())
    }

    fn observe(&mut self, _: &Simulation, _: &Observation) -> Result<(), RunError> {
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let Some((now, d)) = self.bed_positions(simulation) else {
            return Ok(());
        };
        let threshold2 = self.spec.displacement * self.spec.displacement;
        let total = now.len() / d;
        let displaced = (0..total)
            .filter(|&i| {
                let r2: f64 = (0..d)
                    .map(|k| (now[i * d + k] - self.initial[i * d + k]).powi(2))
                    .sum();
                r2 > threshold2
            })
            .count();
        summary.crater = Some(CraterSummary {
            species: self.spec.species.clone(),
            displacement: self.spec.displacement,
            grains: total,
            displaced,
            fraction: displaced as f64 / total.max(1) as f64,
        });
        Ok(())
    }
}
