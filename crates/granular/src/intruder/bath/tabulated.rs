//! A tabulated bath: a piecewise-linear `f(v)` read from a file or given as points, with
//! exact fluxes and samplers on each segment.

use serde::{Deserialize, Serialize};

use super::{BathDistribution, BathError, Side};
use crate::random::{RngExt, Stream};

/// Draws `t` in `[0, 1]` with density proportional to `A(t) B(t)`, where `A` and `B` are
/// linear and non-negative on `[0, 1]` (`A(0) = a0`, ...). Exact: in the Bernstein basis
/// `A B = a0 b0 (1-t)^2 + (a0 b1 + a1 b0) t (1-t) + a1 b1 t^2`, a mixture of Beta(1,3),
/// Beta(2,2) and Beta(3,1) with weights `a0 b0/3`, `(a0 b1 + a1 b0)/6`, `a1 b1/3`.
pub(crate) fn sample_linear_product(a0: f64, a1: f64, b0: f64, b1: f64, rng: &mut Stream) -> f64 {
    let w0 = a0 * b0 / 3.0;
    let w1 = (a0 * b1 + a1 * b0) / 6.0;
    let w2 = a1 * b1 / 3.0;
    let u = rng.random::<f64>() * (w0 + w1 + w2);
    if u < w0 {
        1.0 - rng.random::<f64>().cbrt()
    } else if u < w0 + w1 {
        // Beta(2,2): the median of three uniforms.
        let (x, y, z) = (
            rng.random::<f64>(),
            rng.random::<f64>(),
            rng.random::<f64>(),
        );
        x.max(y).min(x.min(y).max(z))
    } else {
        rng.random::<f64>().cbrt()
    }
}

/// One orientation of a table: breakpoints, density values and cumulative integrals.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Table {
    v: Vec<f64>,
    f: Vec<f64>,
    /// `F_k = int_{v_0}^{v_k} f`.
    cf: Vec<f64>,
    /// `M_k = int_{v_0}^{v_k} v f`.
    cm: Vec<f64>,
    /// `S_k = int_{v_0}^{v_k} |v| f` (a breakpoint at 0 is always present).
    cs: Vec<f64>,
}

impl Table {
    fn build(v: Vec<f64>, f: Vec<f64>) -> Self {
        let n = v.len();
        let (mut cf, mut cm, mut cs) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for k in 0..n - 1 {
            let (d, m1) = Self::segment_moments(v[k], v[k + 1], f[k], f[k + 1]);
            cf[k + 1] = cf[k] + d;
            cm[k + 1] = cm[k] + m1;
            cs[k + 1] = cs[k] + if v[k] + v[k + 1] >= 0.0 { m1 } else { -m1 };
        }
        Self { v, f, cf, cm, cs }
    }
    /// `(int f, int v f)` over one linear piece.
    fn segment_moments(v0: f64, v1: f64, f0: f64, f1: f64) -> (f64, f64) {
        let h = v1 - v0;
        (
            0.5 * h * (f0 + f1),
            h * (f0 * (2.0 * v0 + v1) + f1 * (v0 + 2.0 * v1)) / 6.0,
        )
    }
    fn segment(&self, v: f64) -> usize {
        // largest k with v_k <= v, clamped to a valid segment
        let k = self.v.partition_point(|&x| x <= v);
        k.saturating_sub(1).min(self.v.len() - 2)
    }
    fn interp(&self, k: usize, v: f64) -> f64 {
        let t = (v - self.v[k]) / (self.v[k + 1] - self.v[k]);
        self.f[k] + t * (self.f[k + 1] - self.f[k])
    }
    fn density(&self, v: f64) -> f64 {
        if v < self.v[0] || v > *self.v.last().unwrap_or(&0.0) {
            return 0.0;
        }
        let k = self.segment(v);
        self.interp(k, v)
    }
    /// `(F(v), M(v))`.
    fn partial(&self, v: f64) -> (f64, f64) {
        let n = self.v.len();
        if v <= self.v[0] {
            return (0.0, 0.0);
        }
        if v >= self.v[n - 1] {
            return (self.cf[n - 1], self.cm[n - 1]);
        }
        let k = self.segment(v);
        let (d, m1) = Self::segment_moments(self.v[k], v, self.f[k], self.interp(k, v));
        (self.cf[k] + d, self.cm[k] + m1)
    }
    fn flux_plus(&self, v1: f64) -> f64 {
        let (fv, mv) = self.partial(v1);
        (v1 * fv - mv).max(0.0)
    }
    /// Exact draw from g_+(., v1) for this orientation.
    fn sample_plus(&self, v1: f64, rng: &mut Stream) -> f64 {
        let n = self.v.len();
        let v1c = v1.min(self.v[n - 1]);
        // Segments 0..k_end fully below v1c, then the partial segment [v_k_end, v1c].
        let k_end = if v1c >= self.v[n - 1] {
            n - 1
        } else {
            self.segment(v1c)
        };
        let c = |k: usize| v1 * self.cf[k] - self.cm[k];
        let total = self.flux_plus(v1);
        let target = rng.random::<f64>() * total;
        // Find the segment: largest k <= k_end with c(k) <= target.
        let (mut lo, mut hi) = (0usize, k_end);
        while lo < hi {
            let mid = (lo + hi).div_ceil(2);
            if c(mid) <= target {
                lo = mid;
            } else {
                hi = mid - 1;
            }
        }
        let k = lo.min(n - 2);
        let a = self.v[k];
        let b = self.v[k + 1].min(v1);
        let fa = self.f[k];
        let fb = self.interp(k, b);
        let t = sample_linear_product(v1 - a, v1 - b, fa, fb, rng);
        (a + t * (b - a)).min(v1)
    }
    fn sample(&self, rng: &mut Stream) -> f64 {
        let n = self.v.len();
        let u = rng.random::<f64>() * self.cf[n - 1];
        let k = self
            .cf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 2);
        let t = sample_linear_product(1.0, 1.0, self.f[k], self.f[k + 1], rng);
        self.v[k] + t * (self.v[k + 1] - self.v[k])
    }
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        let n = self.v.len();
        let u = rng.random::<f64>() * self.cs[n - 1];
        let k = self
            .cs
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 2);
        let (a, b) = (self.v[k], self.v[k + 1]);
        let t = sample_linear_product(a.abs(), b.abs(), self.f[k], self.f[k + 1], rng);
        a + t * (b - a)
    }
}

/// Largest magnitude of a velocity or density of a tabulated bath: the moments `v^2 f`
/// and `v^3 f` of the table stay finite. The same bound as the scenario format's
/// `MAGNITUDE` for every dimensional number (a test checks that they agree).
pub(crate) const MAX_TABLE_MAGNITUDE: f64 = 1e100;

/// A bath density given by points `(v_k, f_k)`, linear in between, zero outside
/// `[v_0, v_n]`, normalised to unit integral. A breakpoint at `v = 0` is inserted if needed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tabulated {
    pos: Table,
    /// The mirror image `v -> -v`, used for the "-" side.
    neg: Table,
}

impl Tabulated {
    /// Builds the table; errors if the points are unsorted, negative, too few, of zero
    /// integral, or beyond `MAX_TABLE_MAGNITUDE` in magnitude.
    pub fn new(points: &[(f64, f64)]) -> Result<Self, BathError> {
        if points.len() < 2 {
            return Err(BathError::Invalid("need at least two points".into()));
        }
        for (i, &(v, f)) in points.iter().enumerate() {
            if !v.is_finite() || !f.is_finite() || f < 0.0 {
                return Err(BathError::Invalid(format!(
                    "point {i}: velocity must be finite and density finite and >= 0, got ({v}, {f})"
                )));
            }
            let big = MAX_TABLE_MAGNITUDE;
            if v.abs() > big || f > big {
                return Err(BathError::Invalid(format!(
                    "point {i}: ({v:e}, {f:e}) lies outside the range the engine can integrate (velocities between -1e100 and 1e100, densities at most 1e100, so that the moments v^2 f and v^3 f of the table stay finite); rescale the table to units in which the bath's speeds are of order 1"
                )));
            }
            if i > 0 && v <= points[i - 1].0 {
                return Err(BathError::Invalid(format!(
                    "velocities must increase strictly (point {i}: {v} after {})",
                    points[i - 1].0
                )));
            }
        }
        let mut v: Vec<f64> = Vec::with_capacity(points.len() + 1);
        let mut f: Vec<f64> = Vec::with_capacity(points.len() + 1);
        for (i, &(vi, fi)) in points.iter().enumerate() {
            if i > 0 {
                let (vp, fp) = points[i - 1];
                if vp < 0.0 && vi > 0.0 {
                    v.push(0.0);
                    f.push(fp + (fi - fp) * (-vp) / (vi - vp));
                }
            }
            v.push(vi);
            f.push(fi);
        }
        let norm = Table::build(v.clone(), f.clone())
            .cf
            .last()
            .copied()
            .unwrap_or(0.0);
        if norm.is_nan() || norm <= 0.0 {
            return Err(BathError::Invalid("the density integrates to zero".into()));
        }
        let f: Vec<f64> = f.iter().map(|x| x / norm).collect();
        let pos = Table::build(v.clone(), f.clone());
        let neg = Table::build(
            v.iter().rev().map(|x| -x).collect(),
            f.iter().rev().copied().collect(),
        );
        Ok(Self { pos, neg })
    }

    /// Support `[v_min, v_max]`.
    pub fn support(&self) -> (f64, f64) {
        (self.pos.v[0], *self.pos.v.last().unwrap_or(&0.0))
    }
}

impl BathDistribution for Tabulated {
    fn density(&self, v: f64) -> f64 {
        self.pos.density(v)
    }
    fn cdf(&self, v: f64) -> f64 {
        self.pos.partial(v).0
    }
    fn second_moment(&self) -> f64 {
        // int v^2 f over each piece, exact for linear f.
        let t = &self.pos;
        (0..t.v.len() - 1)
            .map(|k| {
                let (a, b, fa, fb) = (t.v[k], t.v[k + 1], t.f[k], t.f[k + 1]);
                let h = b - a;
                // int_0^1 (a + t h)^2 (fa (1-t) + fb t) h dt
                h * (fa * (a * a / 2.0 + a * h / 3.0 + h * h / 12.0)
                    + fb * (a * a / 2.0 + 2.0 * a * h / 3.0 + h * h / 4.0))
            })
            .sum()
    }
    fn mean_speed(&self) -> f64 {
        *self.pos.cs.last().unwrap_or(&0.0)
    }
    fn flux_plus(&self, v1: f64) -> f64 {
        self.pos.flux_plus(v1)
    }
    fn flux_minus(&self, v1: f64) -> f64 {
        self.neg.flux_plus(-v1)
    }
    fn sample(&self, rng: &mut Stream) -> f64 {
        self.pos.sample(rng)
    }
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        self.pos.sample_speed_weighted(rng)
    }
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64 {
        match side {
            Side::Right => self.pos.sample_plus(v1, rng),
            Side::Left => -self.neg.sample_plus(-v1, rng),
        }
    }
}
