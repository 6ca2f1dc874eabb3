//! Positions as integer lattice coordinates: each coordinate of a DSMC grain is one 64-bit
//! word, a fixed-point number over the box whose low bits carry part of the grain's
//! identity.
//!
//! # The word of one coordinate
//!
//! Along a **periodic** axis of length `L` the word `W` stands for `x = W L / 2^64`: the
//! box is the whole 64-bit range, so the periodic wrap is the wrap of the integer
//! addition, exact and free. Along a **walled** axis `W` stands for `x = W L / 2^63`, so
//! `[0, L]` is `[0, 2^63]` and a grain that left the box through either wall (by less
//! than `L`) has a word above `2^63` (one unsigned comparison).
//!
//! The low `b` bits of every word are not position: they hold `b` bits of the grain's
//! identity (word `k` bits `k b .. (k + 1) b` of the id), with `b` the smallest number such
//! that `D b` bits hold every id `0 .. N - 1` (`b = 0` for one grain, 10 for 10^6 disks,
//! 7 for 10^6 spheres, at most 16 in 2D and 11 in 3D for `N < 2^32`). The position has
//! the other `64 - b` bits: a resolution of `L / 2^(64 - b)` (periodic), at least
//! `L / 2^48` (2D, `N` up to `2^32`), `L / 2^53` (3D), and `L / 2^54` for 10^6 disks,
//! finer than an `f64` coordinate (`2^-52 x`) near the far end of the box for up to
//! `2^24` disks or `2^36` spheres.
//!
//! The cell of a coordinate is `floor(x n / L)` computed exactly on the integers: the
//! high word of the 128-bit product of `W` (id bits cleared) and `n` (periodic) or `2 n`
//! (walled, clamped to `n - 1` for `x = L`).
//!
//! Conversions to and from `f64` box coordinates round to the nearest representable
//! value; a grain's position is thus its lattice point, and every cell index is computed
//! from the words, never from a rounded `f64`.

use crate::boundary::{AxisKind, SimulationBox};
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// `2^64` as `f64`.
const TWO_64: f64 = 18_446_744_073_709_551_616.0;
/// `2^63`: the far wall of a walled axis.
pub(crate) const WALL_END: u64 = 1 << 63;

/// The mapping between box coordinates and lattice words (see the module docs): the same
/// for every grain of an engine.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) struct Lattice<const D: usize> {
    /// Identity bits per word.
    id_bits: u32,
    /// Box lengths.
    #[serde(with = "crate::vector::serde_array")]
    lengths: [f64; D],
    /// Whether each axis is periodic (else walled).
    #[serde(with = "crate::vector::serde_array")]
    periodic: [bool; D],
}

impl<const D: usize> Lattice<D> {
    /// The lattice of `n` grains (ids `0 .. n - 1`, `n < 2^32`) in `sim_box`.
    pub(crate) fn new(sim_box: &SimulationBox<D>, n: usize) -> Self {
        let top = (n.max(1) - 1) as u64;
        let bits = 64 - top.leading_zeros();
        Self {
            id_bits: bits.div_ceil(D as u32),
            lengths: sim_box.lengths.0,
            periodic: sim_box.axes.map(|a| a == AxisKind::Periodic),
        }
    }

    /// Identity bits per word.
    #[cfg(test)]
    pub(crate) fn id_bits(&self) -> u32 {
        self.id_bits
    }

    /// The mask of the position bits of a word.
    #[inline(always)]
    pub(crate) fn position_mask(&self) -> u64 {
        u64::MAX.checked_shl(self.id_bits).unwrap_or(0)
    }

    /// Lattice units (of the whole word) per box length along axis `k`: `2^64` periodic,
    /// `2^63` walled.
    #[inline(always)]
    pub(crate) fn units(&self, k: usize) -> f64 {
        if self.periodic[k] {
            TWO_64
        } else {
            TWO_64 / 2.0
        }
    }

    /// Whether axis `k` is periodic.
    #[inline(always)]
    pub(crate) fn periodic(&self, k: usize) -> bool {
        self.periodic[k]
    }

    /// Box length along axis `k`.
    #[inline(always)]
    pub(crate) fn length(&self, k: usize) -> f64 {
        self.lengths[k]
    }

    /// The box coordinate of word `w` along axis `k` (nearest `f64`).
    #[inline]
    pub(crate) fn coordinate(&self, k: usize, w: u64) -> f64 {
        (w & self.position_mask()) as f64 * (self.lengths[k] / self.units(k))
    }

    /// The position of a grain from its words.
    #[inline]
    pub(crate) fn position(&self, words: &[u64; D]) -> Vector<D> {
        let mut x = Vector::zero();
        for k in 0..D {
            x[k] = self.coordinate(k, words[k]);
        }
        x
    }

    /// The position bits of the word of coordinate `x` along axis `k` (id bits zero):
    /// `x` must lie in the box (periodic: `[0, L)`, values at `L` wrap to 0; walled:
    /// `[0, L]`); values outside are clamped to the box.
    #[inline]
    pub(crate) fn word(&self, k: usize, x: f64) -> u64 {
        let units = self.units(k);
        let f = x / self.lengths[k] * units;
        let w = if self.periodic[k] {
            // `as u64` saturates: [0, 2^64) maps to itself, 2^64 (x = L) to the last word.
            let w = f as u64;
            if f >= TWO_64 { 0 } else { w }
        } else if f >= units {
            WALL_END
        } else {
            f as u64
        };
        w & self.position_mask()
    }

    /// The words of a grain at `x` with identity `id`.
    pub(crate) fn words(&self, x: &Vector<D>, id: u32) -> [u64; D] {
        let mut w = [0u64; D];
        for k in 0..D {
            w[k] = self.word(k, x[k]) | self.id_part(k, id);
        }
        w
    }

    /// Word `k`'s share of the identity bits of `id`.
    #[inline(always)]
    pub(crate) fn id_part(&self, k: usize, id: u32) -> u64 {
        let b = self.id_bits;
        if b == 0 {
            return 0;
        }
        (u64::from(id) >> (k as u32 * b)) & ((1u64 << b) - 1)
    }

    /// The identity held in the low bits of a grain's words.
    #[inline]
    pub(crate) fn id(&self, words: &[u64; D]) -> u32 {
        let b = self.id_bits;
        if b == 0 {
            return 0;
        }
        let low = (1u64 << b) - 1;
        let mut id = 0u64;
        for (k, &w) in words.iter().enumerate() {
            id |= (w & low) << (k as u32 * b);
        }
        id as u32
    }

    /// The per-axis multipliers of the cell index (`n_k` periodic, `2 n_k` walled) for
    /// a grid of `dims` cells.
    pub(crate) fn cell_multipliers(&self, dims: &[usize; D]) -> [u64; D] {
        let mut m = [0u64; D];
        for k in 0..D {
            m[k] = dims[k] as u64 * if self.periodic[k] { 1 } else { 2 };
        }
        m
    }
}

/// The cell coordinate along one axis of word `w` (id bits already cleared): the high
/// word of `w m` (`m` from [`Lattice::cell_multipliers`]), clamped to `n - 1`.
#[inline(always)]
pub(crate) fn axis_cell(w: u64, m: u64, last: u64) -> u64 {
    let c = ((u128::from(w) * u128::from(m)) >> 64) as u64;
    if c < last { c } else { last }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bx<const D: usize>(axes: [AxisKind; D], l: f64) -> SimulationBox<D> {
        SimulationBox {
            lengths: Vector([l; D]),
            axes,
        }
    }

    #[test]
    fn id_bits_hold_every_id() {
        let b = bx([AxisKind::Periodic; 2], 1.0);
        for (n, bits) in [
            (1, 0),
            (2, 1),
            (3, 1),
            (5, 2),
            (1_000_000, 10),
            (u32::MAX as usize, 16),
        ] {
            let lat = Lattice::<2>::new(&b, n);
            assert_eq!(lat.id_bits(), bits, "{n}");
            for id in [0u32, (n - 1) as u32, ((n - 1) / 2) as u32] {
                let w = lat.words(&Vector([0.3, 0.7]), id);
                assert_eq!(lat.id(&w), id);
            }
        }
        let b3 = bx([AxisKind::Periodic; 3], 1.0);
        assert_eq!(Lattice::<3>::new(&b3, 1_000_000).id_bits(), 7);
        assert_eq!(Lattice::<3>::new(&b3, u32::MAX as usize).id_bits(), 11);
    }

    #[test]
    fn coordinates_round_trip_and_cells_are_exact() {
        for axis in [AxisKind::Periodic, AxisKind::Wall] {
            let b = bx([axis; 2], 7.3);
            let lat = Lattice::<2>::new(&b, 1000);
            let dims = [13usize, 13];
            let m = lat.cell_multipliers(&dims);
            for j in 0..=1000 {
                let x = 7.3 * j as f64 / 1000.0;
                let w = lat.word(0, x);
                let back = lat.coordinate(0, w);
                if axis == AxisKind::Periodic && j == 1000 {
                    assert_eq!(back, 0.0);
                    continue;
                }
                assert!((back - x).abs() <= 1e-15 * 7.3, "{x} {back}");
                let c = axis_cell(w, m[0], 12);
                let want = ((back / 7.3) * 13.0).floor().min(12.0) as u64;
                // The exact cell and the f64 estimate agree away from the faces.
                let frac = (back / 7.3 * 13.0).fract();
                if frac > 1e-9 && frac < 1.0 - 1e-9 {
                    assert_eq!(c, want, "{x}");
                }
            }
        }
        // Walls: x = L is in the last cell, the word of a grain beyond a wall is above 2^63.
        let b = bx([AxisKind::Wall; 2], 2.0);
        let lat = Lattice::<2>::new(&b, 1);
        let m = lat.cell_multipliers(&[4, 4]);
        assert_eq!(lat.word(0, 2.0), WALL_END);
        assert_eq!(axis_cell(WALL_END, m[0], 3), 3);
        let below = lat.word(0, 0.0).wrapping_sub(1);
        assert!(below > WALL_END);
    }
}
