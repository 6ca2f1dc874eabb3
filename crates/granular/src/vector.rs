//! Fixed-size vectors over a compile-time dimension `D` (2 for disks, 3 for spheres).
//!
//! Written by hand rather than taken from nalgebra: the event loop touches these values
//! billions of times, and a plain `[f64; D]` with `#[inline]` operators compiles to the
//! same code as hand-unrolled arithmetic while keeping the hot particle records compact
//! and `serde`-serialisable without extra features.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// A point or displacement in `D` dimensions, in simulation length units (or a velocity,
/// in length per time unit, depending on context).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Vector<const D: usize>(#[serde(with = "serde_array")] pub [f64; D]);

/// Serde support for `[T; D]` with a const-generic `D` (serde derives only fixed sizes).
pub(crate) mod serde_array {
    use serde::{Deserialize, Deserializer, Serialize, Serializer, de::Error};
    pub fn serialize<S: Serializer, T: Serialize, const D: usize>(
        a: &[T; D],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        a.as_slice().serialize(s)
    }
    pub fn deserialize<'de, De: Deserializer<'de>, T: Deserialize<'de>, const D: usize>(
        d: De,
    ) -> Result<[T; D], De::Error> {
        let v = Vec::<T>::deserialize(d)?;
        let n = v.len();
        v.try_into()
            .map_err(|_| De::Error::custom(format!("expected {D} components, found {n}")))
    }
}

impl<const D: usize> Default for Vector<D> {
    fn default() -> Self {
        Self::zero()
    }
}

impl<const D: usize> Vector<D> {
    /// The zero vector.
    #[inline]
    pub const fn zero() -> Self {
        Vector([0.0; D])
    }

    /// Builds a vector from a slice of length `D`; `None` for any other length.
    pub fn from_slice(s: &[f64]) -> Option<Self> {
        s.try_into().ok().map(Vector)
    }

    /// The scalar product.
    #[inline(always)]
    pub fn dot(&self, other: &Self) -> f64 {
        let mut s = 0.0;
        for k in 0..D {
            s += self.0[k] * other.0[k];
        }
        s
    }

    /// The squared Euclidean norm.
    #[inline(always)]
    pub fn norm_squared(&self) -> f64 {
        self.dot(self)
    }

    /// The Euclidean norm.
    #[inline(always)]
    pub fn norm(&self) -> f64 {
        self.norm_squared().sqrt()
    }

    /// `self + s * other`, the update used by every free-flight step.
    #[inline(always)]
    pub fn add_scaled(&self, s: f64, other: &Self) -> Self {
        let mut r = *self;
        for k in 0..D {
            r.0[k] += s * other.0[k];
        }
        r
    }

    /// Components as a slice.
    pub fn as_slice(&self) -> &[f64] {
        &self.0
    }
}

impl<const D: usize> Index<usize> for Vector<D> {
    type Output = f64;
    #[inline(always)]
    fn index(&self, k: usize) -> &f64 {
        &self.0[k]
    }
}

impl<const D: usize> IndexMut<usize> for Vector<D> {
    #[inline(always)]
    fn index_mut(&mut self, k: usize) -> &mut f64 {
        &mut self.0[k]
    }
}

impl<const D: usize> Add for Vector<D> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
        self
    }
}

impl<const D: usize> Sub for Vector<D> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
        self
    }
}

impl<const D: usize> AddAssign for Vector<D> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
    }
}

impl<const D: usize> SubAssign for Vector<D> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
    }
}

impl<const D: usize> Mul<f64> for Vector<D> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, s: f64) -> Self {
        for k in 0..D {
            self.0[k] *= s;
        }
        self
    }
}

impl<const D: usize> Neg for Vector<D> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self * -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic() {
        let a = Vector([1.0, 2.0]);
        let b = Vector([3.0, -1.0]);
        assert_eq!((a + b).0, [4.0, 1.0]);
        assert_eq!((a - b).0, [-2.0, 3.0]);
        assert_eq!(a.dot(&b), 1.0);
        assert_eq!(a.add_scaled(2.0, &b).0, [7.0, 0.0]);
        assert_eq!((-a).0, [-1.0, -2.0]);
    }
}
