//! The power-law bath (G-19): closed-form fluxes and the sampler by inversion.

use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2};

use serde::{Deserialize, Serialize};

use super::{BathDistribution, BathError, Side};
use crate::random::{RngExt, Stream, open01};

/// Power-law bath `f(v) = sqrt(2a)/pi / (1 + a^2 v^4)` (G-19); `<v^2> = 1/a`.
///
/// Closed forms (derived in `docs/intruder.md`), with `y = sqrt(a) v`, `x = sqrt(a) v1`:
/// `F(y) = 1/2 + ln((y^2+sqrt2 y+1)/(y^2-sqrt2 y+1))/(4 pi) + (atan(sqrt2 y+1)+atan(sqrt2 y-1))/(2 pi)`,
/// `int_{-inf}^{y} t f = -atan(1/y^2)/(sqrt(2) pi sqrt(a))`, hence
/// `phi_+(v1) = [x F(x) + atan(1/x^2)/(sqrt(2) pi)] / sqrt(a)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLaw {
    /// The paper's `a` in G-19.
    pub a: f64,
    s: f64,
    inv_s: f64,
}

/// `sqrt(2)/pi`, the normalisation of `1/(1+y^4)`.
const PL_NORM: f64 = SQRT_2 / PI;
/// `1/(sqrt(2) pi)`.
const PL_M1: f64 = 1.0 / (SQRT_2 * PI);

/// `int_y^inf dt/(1+t^4)` for `y >= 2` by its convergent series in `1/y^4`.
fn pl_tail_series(y: f64) -> f64 {
    let y4 = y * y * y * y;
    let inv4 = 1.0 / y4;
    let mut p = 1.0 / (y * y * y);
    let mut sum = 0.0;
    for k in 0..24 {
        let term = p / (4 * k + 3) as f64;
        sum += if k % 2 == 0 { term } else { -term };
        p *= inv4;
        if term < 1e-18 * sum.abs() {
            break;
        }
    }
    sum
}

/// Scaled CDF of `sqrt(2)/pi/(1+y^4)`.
pub(crate) fn power_law_cdf_scaled(y: f64) -> f64 {
    if y <= -2.0 {
        PL_NORM * pl_tail_series(-y)
    } else if y >= 2.0 {
        1.0 - PL_NORM * pl_tail_series(y)
    } else {
        let y2 = y * y;
        let l = ((y2 + SQRT_2 * y + 1.0) / (y2 - SQRT_2 * y + 1.0)).ln();
        0.5 + l / (4.0 * PI) + ((SQRT_2 * y + 1.0).atan() + (SQRT_2 * y - 1.0).atan()) / (2.0 * PI)
    }
}

/// `atan(1/y^2) = pi/2 - atan(y^2)`, accurate for all y.
#[inline]
fn acot_sq(y: f64) -> f64 {
    let y2 = y * y;
    if y2 < 1.0 {
        0.5 * PI - y2.atan()
    } else {
        (1.0 / y2).atan()
    }
}

/// Scaled `Q_x(y) = int_{-inf}^{y} (x - t) f_s(t) dt = x F(y) + atan(1/y^2)/(sqrt2 pi)`.
#[inline]
fn pl_q(x: f64, y: f64) -> f64 {
    x * power_law_cdf_scaled(y) + PL_M1 * acot_sq(y)
}

/// Solves `Q_x(y) = target`, `y <= x`, by Newton-Raphson safeguarded by bisection. `Q_x`
/// is increasing on `(-inf, x]` with derivative `(x - y) f_s(y)`.
fn pl_invert(x: f64, target: f64) -> f64 {
    // Bracket [lo, hi] with Q(lo) <= target <= Q(hi).
    let hi0 = x;
    // Tail Q ~ (sqrt2/pi)/(2 y^2) + O(|x|/|y|^3): start at that quantile.
    let guess = -(PL_NORM / (2.0 * target)).sqrt();
    let mut lo = (x - 1.0).min(guess);
    let mut qlo = pl_q(x, lo);
    while qlo > target {
        lo = x - 2.0 * (x - lo);
        qlo = pl_q(x, lo);
        if !lo.is_finite() {
            return lo;
        }
    }
    let mut hi = hi0;
    let mut y = 0.5 * (lo + hi);
    for _ in 0..200 {
        let q = pl_q(x, y);
        let r = q - target;
        if r > 0.0 {
            hi = y;
        } else {
            lo = y;
        }
        if r.abs() <= 1e-15 * target.max(1e-300) || (hi - lo) <= 1e-15 * (1.0 + y.abs()) {
            return y;
        }
        let d = (x - y) * PL_NORM / (1.0 + (y * y) * (y * y));
        let mut next = if d > 0.0 { y - r / d } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        y = next;
    }
    y
}

impl PowerLaw {
    /// Power law with parameter `a > 0`.
    pub fn new(a: f64) -> Result<Self, BathError> {
        if !(a > 0.0 && a.is_finite()) {
            return Err(BathError::Parameter(format!("a must be positive, got {a}")));
        }
        Ok(Self {
            a,
            s: a.sqrt(),
            inv_s: 1.0 / a.sqrt(),
        })
    }
    /// Power law of temperature `T_B = m <v^2> = m / a`.
    pub fn with_temperature(t_b: f64, m: f64) -> Result<Self, BathError> {
        if !(t_b > 0.0 && m > 0.0) {
            return Err(BathError::Parameter(format!(
                "temperature and mass must be positive, got T_B = {t_b}, m = {m}"
            )));
        }
        Self::new(m / t_b)
    }
    fn p_scaled(x: f64) -> f64 {
        pl_q(x, x)
    }
}

impl BathDistribution for PowerLaw {
    fn density(&self, v: f64) -> f64 {
        let y2 = self.a * v * v;
        self.s * PL_NORM / (1.0 + y2 * y2)
    }
    fn cdf(&self, v: f64) -> f64 {
        power_law_cdf_scaled(self.s * v)
    }
    fn sf(&self, v: f64) -> f64 {
        power_law_cdf_scaled(-self.s * v)
    }
    fn second_moment(&self) -> f64 {
        1.0 / self.a
    }
    fn mean_speed(&self) -> f64 {
        FRAC_1_SQRT_2 / self.s
    }
    fn flux_plus(&self, v1: f64) -> f64 {
        Self::p_scaled(self.s * v1) / self.s
    }
    fn flux_minus(&self, v1: f64) -> f64 {
        Self::p_scaled(-self.s * v1) / self.s
    }
    fn flux(&self, v1: f64) -> f64 {
        let x = self.s * v1;
        (x * (2.0 * power_law_cdf_scaled(x) - 1.0) + 2.0 * PL_M1 * acot_sq(x)) / self.s
    }
    fn sample(&self, rng: &mut Stream) -> f64 {
        // Cauchy proposal 1/(1+y^2), accepted with (1+y^2)/(1+y^4) / K, K = (1+sqrt2)/2
        // (maximum at y^2 = sqrt2 - 1); acceptance 1/(sqrt2 K) = 0.586.
        const K: f64 = 0.5 * (1.0 + SQRT_2);
        loop {
            let y = (PI * (rng.random::<f64>() - 0.5)).tan();
            let y2 = y * y;
            if rng.random::<f64>() * K * (1.0 + y2 * y2) <= 1.0 + y2 {
                return y * self.inv_s;
            }
        }
    }
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        // |y|/(1+y^4) dy = (1/2) dz/(1+z^2) with z = y^2: z = tan(pi U / 2).
        let z = (0.5 * PI * open01(rng)).tan();
        let r = z.sqrt() * self.inv_s;
        if rng.random::<bool>() { r } else { -r }
    }
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64 {
        // Exact inversion of the closed-form CDF of g_+ (scaled); g_- by the mirror symmetry
        // f(v) = f(-v): g_-(v, v1) = g_+(-v, -v1).
        let x = match side {
            Side::Right => self.s * v1,
            Side::Left => -self.s * v1,
        };
        let total = Self::p_scaled(x);
        let y = pl_invert(x, open01(rng) * total);
        match side {
            Side::Right => y / self.s,
            Side::Left => -y / self.s,
        }
    }
}
