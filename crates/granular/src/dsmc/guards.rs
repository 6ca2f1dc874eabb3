//! Validity guards: the conditions under which DSMC approximates the Boltzmann (Enskog)
//! equation (Sec. 2 of Müller & Herrmann's DSMC paper), checked with kinetic-theory estimates for a Maxwellian
//! gas (see `crate::theory::haff`).

use crate::theory::haff;
use serde::{Deserialize, Serialize};

/// Which condition is violated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GuardKind {
    /// (i) Not in the collisional regime: the mean free path is not small against the
    /// system size (Knudsen number `lambda / L_box` above `MAX_KNUDSEN`).
    NotCollisional,
    /// (ii) The cell edge exceeds the mean free path.
    CellLargerThanMeanFreePath,
    /// (iii) The time step is not well below the mean free time (`tau omega` above
    /// `MAX_STEP_FRACTION`).
    TimeStepTooLong,
    /// Too few particles per cell on average (below `MIN_PER_CELL`): the pair-count
    /// statistics of DSMC-1 become poor and spurious correlations grow.
    TooFewParticlesPerCell,
}

/// A violated condition, with the measured value and the limit it was compared with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ValidityWarning {
    /// The condition.
    pub kind: GuardKind,
    /// The measured value (ratio or count, see `message`).
    pub value: f64,
    /// The limit.
    pub limit: f64,
    /// A human-readable sentence with the numbers.
    pub message: String,
}

/// Largest accepted Knudsen number `lambda / L_box`.
pub(crate) const MAX_KNUDSEN: f64 = 0.1;
/// Largest accepted `tau / t_free` (expected collisions per particle per step).
pub(crate) const MAX_STEP_FRACTION: f64 = 0.2;
/// Smallest accepted mean number of particles per cell.
pub(crate) const MIN_PER_CELL: f64 = 5.0;

/// The state the guards look at.
#[derive(Clone, Debug)]
pub(crate) struct GuardInput {
    /// 2 or 3.
    pub dimension: usize,
    /// `N / V`.
    pub number_density: f64,
    /// Grain radius.
    pub radius: f64,
    /// Grain mass.
    pub mass: f64,
    /// Granular temperature.
    pub temperature: f64,
    /// Enskog factor (1 for the Boltzmann gas).
    pub chi: f64,
    /// Largest cell edge.
    pub cell_edge: f64,
    /// Time step.
    pub time_step: f64,
    /// Mean number of particles per cell.
    pub particles_per_cell: f64,
    /// Smallest box length.
    pub system_size: f64,
}

/// Mean free path `lambda = 1 / (sqrt 2 chi n sigma)`.
pub(crate) fn mean_free_path(g: &GuardInput) -> f64 {
    haff::mean_free_path(g.dimension, g.number_density, g.radius, g.chi)
}

/// Mean free time `1 / omega`.
pub(crate) fn mean_free_time(g: &GuardInput) -> f64 {
    1.0 / haff::collision_frequency(
        g.dimension,
        g.number_density,
        g.radius,
        g.temperature,
        g.mass,
        g.chi,
    )
}

/// All violated conditions (empty when the set-up is within the validity range).
pub(crate) fn check(g: &GuardInput) -> Vec<ValidityWarning> {
    let mut out = Vec::new();
    let lambda = mean_free_path(g);
    let kn = lambda / g.system_size;
    if kn > MAX_KNUDSEN {
        out.push(ValidityWarning {
            kind: GuardKind::NotCollisional,
            value: kn,
            limit: MAX_KNUDSEN,
            message: format!(
                "not collisional: mean free path {lambda:.4e} is {kn:.3} of the box size {:.4e} (limit {MAX_KNUDSEN})",
                g.system_size
            ),
        });
    }
    let r = g.cell_edge / lambda;
    if r > 1.0 {
        out.push(ValidityWarning {
            kind: GuardKind::CellLargerThanMeanFreePath,
            value: r,
            limit: 1.0,
            message: format!(
                "cell edge {:.4e} is {r:.3} mean free paths ({lambda:.4e}); use cells no larger than the mean free path",
                g.cell_edge
            ),
        });
    }
    let tf = mean_free_time(g);
    let s = g.time_step / tf;
    if s > MAX_STEP_FRACTION {
        out.push(ValidityWarning {
            kind: GuardKind::TimeStepTooLong,
            value: s,
            limit: MAX_STEP_FRACTION,
            message: format!(
                "time step {:.4e} is {s:.3} mean free times ({tf:.4e}); keep it below {MAX_STEP_FRACTION}",
                g.time_step
            ),
        });
    }
    if g.particles_per_cell < MIN_PER_CELL {
        out.push(ValidityWarning {
            kind: GuardKind::TooFewParticlesPerCell,
            value: g.particles_per_cell,
            limit: MIN_PER_CELL,
            message: format!(
                "{:.2} particles per cell on average; use at least {MIN_PER_CELL}",
                g.particles_per_cell
            ),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input() -> GuardInput {
        // 2D, n = 1, R = 0.05 (sigma = 4R = 0.2): lambda = 1/(sqrt2 * 0.2) = 3.54;
        // omega = 0.2 sqrt(pi) = 0.354, t_free = 2.82.
        GuardInput {
            dimension: 2,
            number_density: 1.0,
            radius: 0.05,
            mass: 1.0,
            temperature: 1.0,
            chi: 1.0,
            cell_edge: 3.0,
            time_step: 0.5,
            particles_per_cell: 9.0,
            system_size: 100.0,
        }
    }

    #[test]
    fn valid_set_up_has_no_warning() {
        assert!(check(&input()).is_empty());
    }

    #[test]
    fn each_condition_warns_with_numbers() {
        let mut g = input();
        g.cell_edge = 14.0;
        g.time_step = 2.0;
        g.particles_per_cell = 2.0;
        g.system_size = 20.0;
        let w = check(&g);
        let kinds: Vec<_> = w.iter().map(|w| w.kind).collect();
        assert_eq!(
            kinds,
            vec![
                GuardKind::NotCollisional,
                GuardKind::CellLargerThanMeanFreePath,
                GuardKind::TimeStepTooLong,
                GuardKind::TooFewParticlesPerCell
            ]
        );
        assert!((w[1].value - 14.0 * 0.2 * std::f64::consts::SQRT_2).abs() < 1e-12);
        assert!(w[2].message.contains("mean free times"));
    }
}
