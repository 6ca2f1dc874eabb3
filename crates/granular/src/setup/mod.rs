//! Initial states shared by every engine: the region grains are placed in, non-overlapping
//! placements (random, lattice), initial velocities and the overlap check of a finished
//! state (on the neighbour search's cell grid, `neighbours`). The event-driven
//! compression to dense states (Lubachevsky-Stillinger) needs the event-driven engine and
//! lives with it (`edmd::init`), above this module.
//!
//! * `placement`: random sequential and lattice placement in a [`Region`];
//! * `velocities`: fixed speed, Maxwell-Boltzmann, drift removal;
//! * `overlap`: rejects initial states in which grains overlap.

pub(crate) mod overlap;
pub(crate) mod placement;
pub(crate) mod velocities;

pub(crate) use overlap::check_overlaps;
pub(crate) use placement::Lattice;
pub use placement::{lattice_placement, random_placement};
pub use velocities::{fixed_speed, maxwell_boltzmann, remove_drift};

use crate::boundary::SimulationBox;
use crate::vector::Vector;

/// Why an initial state could not be built.
#[derive(Debug, thiserror::Error)]
pub enum InitError {
    /// Random sequential placement ran out of attempts.
    #[error(
        "could not place grain {placed_plus_one} of {total} without overlap after {attempts} random attempts \
         (packing fraction {packing_fraction:.3} of the region, with the grains placed before, is too high for random placement); \
         use placement = \"lattice\", or initial.compress_from (random placement at a lower density, then compression)"
    )]
    Placement {
        /// One-based index of the grain that did not fit.
        placed_plus_one: usize,
        /// Number of grains to place.
        total: usize,
        /// Attempts made for that grain.
        attempts: usize,
        /// Packing fraction of the region once all grains are placed (those placed before
        /// in the region included).
        packing_fraction: f64,
    },
    /// A grain is larger than the region that should hold it.
    #[error(
        "a grain of radius {radius} does not fit in the region {lo:?}..{hi:?} (its diameter exceeds the region's width)"
    )]
    DoesNotFit {
        /// Radius of the grain.
        radius: f64,
        /// Region lower corner.
        lo: Vec<f64>,
        /// Region upper corner.
        hi: Vec<f64>,
    },
    /// The lattice does not have room for the grains.
    #[error(
        "{n} grains of radius up to {radius} do not fit on a lattice in the region (spacing {spacing:.4} < diameter); \
         enlarge the region or reduce the number or size of grains"
    )]
    Lattice {
        /// Number of grains.
        n: usize,
        /// Largest radius.
        radius: f64,
        /// Lattice spacing.
        spacing: f64,
    },
    /// Compression jammed before reaching the target.
    #[error(
        "compression stopped at packing fraction {reached:.4} before the target {target:.4}: the grains jammed; \
         lower the target or the compression rate"
    )]
    Jammed {
        /// Packing fraction reached.
        reached: f64,
        /// Target packing fraction.
        target: f64,
    },
}

/// Volume of a `D`-ball of radius `r` (area of a disk in 2D): the grain volume of KT-1,
/// [`crate::theory::kinetic::grain_volume`].
pub fn ball_volume<const D: usize>(r: f64) -> f64 {
    crate::theory::kinetic::grain_volume(D, r)
}

/// Packing fraction of grains of the given radii in a region of the given volume (KT-2,
/// [`crate::theory::kinetic::mixture_packing_fraction`]).
pub fn packing_fraction<const D: usize>(radii: &[f64], volume: f64) -> f64 {
    crate::theory::kinetic::mixture_packing_fraction(D, radii.iter().map(|&r| (1, r)), volume)
}

/// Region of the box where grains are placed: `[lo, hi]` per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Region<const D: usize> {
    /// Lower corner.
    pub lo: Vector<D>,
    /// Upper corner.
    pub hi: Vector<D>,
}

impl<const D: usize> Region<D> {
    /// The whole box.
    pub fn whole(bx: &SimulationBox<D>) -> Self {
        Self {
            lo: Vector::zero(),
            hi: bx.lengths,
        }
    }

    /// Volume of the region.
    pub(crate) fn volume(&self) -> f64 {
        (0..D).map(|k| self.hi[k] - self.lo[k]).product()
    }

    /// Range of admissible centres for a grain of radius `r` along axis `k`: the region
    /// shrunk by `r`, except across periodic faces of the box that the region touches.
    pub(crate) fn centre_range(&self, bx: &SimulationBox<D>, k: usize, r: f64) -> (f64, f64) {
        let whole = self.lo[k] <= 0.0 && self.hi[k] >= bx.lengths[k];
        if bx.is_periodic(k) && whole {
            (0.0, bx.lengths[k])
        } else {
            (self.lo[k] + r, self.hi[k] - r)
        }
    }
}
