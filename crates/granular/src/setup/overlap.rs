//! The overlap check of an initial state: hard grains may touch but not overlap (given
//! positions, mostly, can break this; random and lattice placement never do).

use crate::boundary::SimulationBox;
use crate::particles::ParticleSet;

/// Two grains that overlap at the start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "grains {a} and {b} overlap at the start (distance {distance:.6} < sum of radii {sigma:.6}); move them apart or make them smaller"
)]
pub(crate) struct Overlap {
    /// First grain (index in the particle set).
    pub a: usize,
    /// Second grain (`b > a`).
    pub b: usize,
    /// Centre distance (minimum image), length units.
    pub distance: f64,
    /// Sum of the radii, length units.
    pub sigma: f64,
}

/// Rejects a state in which two grains overlap by more than a relative `1e-9` of their
/// contact distance: the first grain `a` (in input order) that overlaps a later grain is
/// reported. Neighbours are found on the event-driven engine's cell grid, which fits all
/// but a few large grains (cost `O(N)` for any size distribution).
pub(crate) fn check_overlaps<const D: usize>(
    bx: &SimulationBox<D>,
    set: &ParticleSet<D>,
) -> Result<(), Overlap> {
    let n = set.len();
    let (mut grid, cut) = crate::neighbours::CellGrid::<D>::for_radii(bx, &set.radii, 1.0, true);
    for i in 0..n {
        let c = grid.coords_of(&set.positions[i].0);
        grid.insert_grain(i, c, set.radii[i], cut);
    }
    for i in 0..n {
        let mut bad = None;
        grid.for_each_candidate(i, |j| {
            if j > i && bad.is_none() {
                let d = bx.separation(&set.positions[i], &set.positions[j]).norm();
                let sigma = set.radii[i] + set.radii[j];
                if d < sigma * (1.0 - 1e-9) {
                    bad = Some((j, d, sigma));
                }
            }
        });
        if let Some((b, distance, sigma)) = bad {
            return Err(Overlap {
                a: i,
                b,
                distance,
                sigma,
            });
        }
    }
    Ok(())
}
