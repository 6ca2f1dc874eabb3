//! The simulation box: an axis-aligned box `[0, L_0] x ... x [0, L_{D-1}]` whose faces are,
//! axis by axis, either hard walls or periodic.

use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// What happens at the two faces perpendicular to one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AxisKind {
    /// Hard walls at `x = 0` and `x = L` (HD-1 to HD-4).
    Wall,
    /// Periodic: a grain leaving at `x = L` re-enters at `x = 0`; distances use the
    /// minimum-image convention.
    Periodic,
}

/// An axis-aligned box in `D` dimensions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimulationBox<const D: usize> {
    /// Edge lengths `L_k`, in length units.
    pub lengths: Vector<D>,
    /// Boundary kind per axis.
    #[serde(with = "crate::vector::serde_array")]
    pub axes: [AxisKind; D],
}

impl<const D: usize> SimulationBox<D> {
    /// A box with the same boundary kind on every axis.
    pub fn uniform(lengths: Vector<D>, kind: AxisKind) -> Self {
        Self {
            lengths,
            axes: [kind; D],
        }
    }

    /// The hard-disk assignment's unit square (cube) with hard walls.
    pub fn unit_walled() -> Self {
        Self::uniform(Vector([1.0; D]), AxisKind::Wall)
    }

    /// The volume (area in 2D) of the box.
    pub fn volume(&self) -> f64 {
        self.lengths.0.iter().product()
    }

    /// Whether axis `k` is periodic.
    #[inline(always)]
    pub fn is_periodic(&self, k: usize) -> bool {
        self.axes[k] == AxisKind::Periodic
    }

    /// The minimum-image separation `b - a` (HD-8; plain difference along walled axes).
    #[inline(always)]
    pub fn separation(&self, a: &Vector<D>, b: &Vector<D>) -> Vector<D> {
        let mut d = *b - *a;
        for k in 0..D {
            if self.axes[k] == AxisKind::Periodic {
                let l = self.lengths[k];
                if d[k] > 0.5 * l {
                    d[k] -= l;
                } else if d[k] < -0.5 * l {
                    d[k] += l;
                }
            }
        }
        d
    }

    /// Folds a position back into the box along periodic axes.
    #[inline(always)]
    pub fn wrap(&self, x: &mut Vector<D>) {
        for k in 0..D {
            if self.axes[k] == AxisKind::Periodic {
                let l = self.lengths[k];
                if x[k] >= l {
                    x[k] -= l;
                    if x[k] >= l {
                        x[k] = x[k].rem_euclid(l);
                    }
                } else if x[k] < 0.0 {
                    x[k] += l;
                    if x[k] < 0.0 || x[k] >= l {
                        x[k] = x[k].rem_euclid(l);
                        if x[k] >= l {
                            x[k] = 0.0;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimum_image_and_wrap() {
        let b = SimulationBox::<2> {
            lengths: Vector([1.0, 2.0]),
            axes: [AxisKind::Periodic, AxisKind::Wall],
        };
        let d = b.separation(&Vector([0.05, 0.1]), &Vector([0.95, 1.9]));
        assert!((d[0] + 0.1).abs() < 1e-12);
        assert!((d[1] - 1.8).abs() < 1e-12);
        let mut x = Vector([1.25, 0.5]);
        b.wrap(&mut x);
        assert!((x[0] - 0.25).abs() < 1e-12);
        let mut y = Vector([-1e-18, 0.5]);
        b.wrap(&mut y);
        assert!(y[0] >= 0.0 && y[0] < 1.0);
    }
}
