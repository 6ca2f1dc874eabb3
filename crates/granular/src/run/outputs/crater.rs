//! The crater measure of a `[crater]` table: how many grains of the bed species moved
//! farther than a threshold since `t = 0` (the hard-disk assignment's Problem 4).

use super::Output;
use crate::observation::Observation;
use crate::run::grains::Grains;
use crate::run::summary::CraterSummary;
use crate::run::{RunError, Summary};
use crate::scenario::CraterSpec;
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Bed grains displaced since `t = 0` (the event-driven engine's initial positions are kept
/// in memory; DSMC's are recomputed from the grains' ids at the end).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Crater {
    spec: CraterSpec,
    /// Initial positions of the bed species' grains, `D` values each, in grain order.
    initial: Vec<f64>,
}

impl Crater {
    /// The measure of `spec`.
    pub(crate) fn new(spec: CraterSpec) -> Crater {
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

/// The `t = 0` positions of the DSMC grains `ids` (row-major), as the engine placed them:
/// every grain's initial state follows from its id (`crate::dsmc::setup`), so a rank
/// recomputes its block's instead of keeping them through the run.
fn initial_rows(
    scenario: &crate::scenario::Scenario,
    ids: Range<usize>,
) -> Result<Vec<f64>, RunError> {
    match scenario.dimension {
        2 => initial_rows_of::<2>(scenario, ids),
        _ => initial_rows_of::<3>(scenario, ids),
    }
}

fn initial_rows_of<const D: usize>(
    scenario: &crate::scenario::Scenario,
    ids: Range<usize>,
) -> Result<Vec<f64>, RunError> {
    let failed = |message: String| RunError::Output {
        key: "crater".into(),
        message: format!("could not recompute the bed's initial positions: {message}"),
    };
    let (bx, setup) = crate::build::dsmc_setup::<D>(scenario).map_err(|e| failed(e.to_string()))?;
    let (positions, _, _) = setup
        .grains(&bx, ids)
        .map_err(|(id, m)| failed(format!("grain {id}: {m}")))?;
    Ok(positions
        .into_iter()
        .flat_map(|mut x| {
            bx.wrap(&mut x);
            x.0
        })
        .collect())
}

/// Whether the run's engine is DSMC (whose initial state is recomputed grain by grain).
fn is_dsmc(simulation: &Simulation) -> bool {
    matches!(
        simulation.engine(),
        crate::run::AnyEngine::Dsmc2(_) | crate::run::AnyEngine::Dsmc3(_)
    )
}

impl Crater {
    /// Bed grains displaced and bed grains of a DSMC run, over its ranks when it is
    /// decomposed (collective): each rank compares its block of ids with the block's
    /// recomputed initial positions ([`initial_rows`]); the counts are summed (integers,
    /// exact). On one rank the block is every grain.
    fn count_by_blocks(&self, simulation: &Simulation) -> Result<Option<(usize, usize)>, RunError> {
        let Some(g) = Grains::of(simulation) else {
            return Ok(None);
        };
        let Some(index) = g
            .snap
            .species_names
            .iter()
            .position(|n| *n == self.spec.species)
        else {
            return Ok(None);
        };
        let d = g.snap.dimension;
        let initial = initial_rows(simulation.scenario(), g.first..g.first + g.len())?;
        let threshold2 = self.spec.displacement * self.spec.displacement;
        let (mut displaced, mut total) = (0u64, 0u64);
        for i in (0..g.len()).filter(|&i| g.snap.species[i] as usize == index) {
            let now = &g.snap.positions[i * d..(i + 1) * d];
            let r2: f64 = (0..d).map(|k| (now[k] - initial[i * d + k]).powi(2)).sum();
            total += 1;
            displaced += u64::from(r2 > threshold2);
        }
        let sums = g.sum_u64(vec![displaced, total]);
        Ok(Some((sums[0] as usize, sums[1] as usize)))
    }
}

impl Output for Crater {
    /// The bed's initial positions (event-driven engine). A DSMC run keeps none: at the
    /// end each rank recomputes its block's (the whole system on one rank), so the crater
    /// needs no gather of the whole system over ranks.
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        if is_dsmc(simulation) {
            return Ok(());
        }
        self.initial = self.bed_positions(simulation).map_or(Vec::new(), |p| p.0);
        Ok(())
    }

    fn observe(&mut self, _: &Simulation, _: &Observation) -> Result<(), RunError> {
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        let counted = if is_dsmc(simulation) {
            self.count_by_blocks(simulation)?
        } else {
            self.bed_positions(simulation).map(|(now, d)| {
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
                (displaced, total)
            })
        };
        let Some((displaced, total)) = counted else {
            return Ok(());
        };
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
