//! The Gaussian bath (G-14): fluxes through the scaled function `h` and the exact sampler
//! of the colliding particle's velocity (G-12, G-13).

use std::f64::consts::FRAC_1_SQRT_2;

use rand::Rng;
use serde::{Deserialize, Serialize};

use super::{BathDistribution, BathError, FRAC_1_SQRT_PI, SQRT_PI, Side};
use crate::random::{RngExt, Stream, exp1, std_normal, unit_f64};

/// Gaussian bath `f(v) = sqrt(a/pi) exp(-a v^2)` (G-14), `a = m / (2 T_B)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gaussian {
    /// The paper's `a` (inverse squared velocity).
    pub a: f64,
    s: f64,
    inv_s: f64,
}

impl Gaussian {
    /// Gaussian with parameter `a > 0`.
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

    /// Gaussian of temperature `t_b` for bath particles of mass `m` (`a = m/(2 T_B)`).
    pub fn with_temperature(t_b: f64, m: f64) -> Result<Self, BathError> {
        if !(t_b > 0.0 && m > 0.0) {
            return Err(BathError::Parameter(format!(
                "temperature and mass must be positive, got T_B = {t_b}, m = {m}"
            )));
        }
        Self::new(m / (2.0 * t_b))
    }

    /// `sqrt(a)`.
    #[inline]
    pub fn sqrt_a(&self) -> f64 {
        self.s
    }
}

/// `h(x) = x erfc(-x) + exp(-x^2)/sqrt(pi)` so that `phi_+(v1) = h(sqrt(a) v1)/(2 sqrt(a))`
/// (G-15 rewritten); accurate for all x, including the far left tail where it is
/// exponentially small (asymptotic series of erfcx for `x < -8`).
#[inline]
pub(crate) fn gaussian_h(x: f64) -> f64 {
    if x >= -3.0 {
        h_direct(x)
    } else if x >= -8.0 {
        h_erfcx(x)
    } else {
        h_asymptotic(x)
    }
}

#[inline]
pub(super) fn h_direct(x: f64) -> f64 {
    x * libm::erfc(-x) + (-x * x).exp() * FRAC_1_SQRT_PI
}

pub(super) fn h_erfcx(x: f64) -> f64 {
    let z = -x;
    (-x * x).exp() * (FRAC_1_SQRT_PI - z * puruspe::erfcx(z))
}

/// `x erfcx(-x) + 1/sqrt(pi) = (1/sqrt(pi)) sum_{k>=1} (-1)^(k+1) (2k-1)!! / (2 x^2)^k`
/// (asymptotic; at `|x| >= 8` its smallest term is far below machine precision).
pub(super) fn h_asymptotic(x: f64) -> f64 {
    let z2 = x * x;
    let r = 1.0 / (2.0 * z2);
    let mut term = r;
    let mut sum = 0.0;
    for k in 1..=20 {
        sum += term;
        term *= -((2 * k + 1) as f64) * r;
    }
    (-z2).exp() * FRAC_1_SQRT_PI * sum
}

/// Draws `w >= 0` with density proportional to `w exp(-(w - c)^2)`, exactly, for any `c`.
///
/// Three rejection schemes, each exact by the standard acceptance-rejection argument (a
/// proposal with density `q` and acceptance probability `p(w) <= 1` yields accepted values
/// with density proportional to `q(w) p(w)`, which is the target in each case):
///
/// * `c >= 0`: write `w = c + z`; target `(c + z) e^{-z^2}` on `z >= -c` is dominated by
///   `(c + |z|) e^{-z^2}` on the real line, a mixture of `N(0, 1/2)` (weight `c sqrt(pi)`)
///   and the two-sided Rayleigh `|z| e^{-z^2}` (weight 1, `z = +-sqrt(E)`, `E ~ Exp(1)`).
///   Accept if `z >= -c` and `U (c + |z|) <= c + z`. Acceptance
///   `[c sqrt(pi) (1 + erf c)/2 + e^{-c^2}/2] / (c sqrt(pi) + 1)`: 1/2 at `c = 0`, at least
///   0.5 for all `c >= 0` (minimum 0.5 at c = 0), tending to 1.
/// * `-1/sqrt(2) < c < 0`: Rayleigh proposal `2 w e^{-w^2}` (`w = sqrt(E)`), accepted with
///   probability `e^{2 c w}`; acceptance `R(c) = 1 - sqrt(pi) |c| erfcx(|c|)` >= 0.34.
/// * `c <= -1/sqrt(2)`: Gamma(2, rate `2|c|`) proposal `w e^{-2|c| w}`, accepted with
///   probability `e^{-w^2}`; acceptance `2 c^2 R(c)` >= 0.34, tending to 1 as `c -> -inf`.
#[inline]
pub fn sample_w_gaussian(c: f64, rng: &mut Stream) -> f64 {
    if c >= 0.0 {
        let weight_gauss = c * SQRT_PI;
        let p_gauss = weight_gauss / (weight_gauss + 1.0);
        loop {
            let z = if rng.random::<f64>() < p_gauss {
                std_normal(rng) * FRAC_1_SQRT_2
            } else {
                let e = exp1(rng);
                let r = e.sqrt();
                if rng.random::<bool>() { r } else { -r }
            };
            if z < -c {
                continue;
            }
            if rng.random::<f64>() * (c + z.abs()) <= c + z {
                return c + z;
            }
        }
    } else if c > -FRAC_1_SQRT_2 {
        let two_abs_c = -2.0 * c;
        loop {
            let e = exp1(rng);
            let w = e.sqrt();
            let e2 = exp1(rng);
            // U < exp(2 c w)  <=>  -ln U > 2 |c| w, and -ln U ~ Exp(1).
            if e2 >= two_abs_c * w {
                return w;
            }
        }
    } else {
        let rate = -2.0 * c;
        loop {
            let e1 = exp1(rng);
            let e2 = exp1(rng);
            let w = (e1 + e2) / rate;
            let e3 = exp1(rng);
            if e3 >= w * w {
                return w;
            }
        }
    }
}

impl BathDistribution for Gaussian {
    #[inline]
    fn density(&self, v: f64) -> f64 {
        self.s * FRAC_1_SQRT_PI * (-self.a * v * v).exp()
    }
    fn cdf(&self, v: f64) -> f64 {
        0.5 * libm::erfc(-self.s * v)
    }
    fn sf(&self, v: f64) -> f64 {
        0.5 * libm::erfc(self.s * v)
    }
    fn second_moment(&self) -> f64 {
        0.5 / self.a
    }
    fn mean_speed(&self) -> f64 {
        FRAC_1_SQRT_PI / self.s
    }
    #[inline]
    fn flux_plus(&self, v1: f64) -> f64 {
        gaussian_h(self.s * v1) / (2.0 * self.s)
    }
    #[inline]
    fn flux_minus(&self, v1: f64) -> f64 {
        gaussian_h(-self.s * v1) / (2.0 * self.s)
    }
    /// G-16.
    #[inline]
    fn flux(&self, v1: f64) -> f64 {
        let x = self.s * v1;
        ((-x * x).exp() * FRAC_1_SQRT_PI + x * libm::erf(x)) / self.s
    }
    #[inline]
    fn sample(&self, rng: &mut Stream) -> f64 {
        std_normal(rng) * (FRAC_1_SQRT_2 * self.inv_s)
    }
    #[inline]
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        // |v| f(v) ∝ |v| exp(-a v^2): a v^2 ~ Exp(1), symmetric sign.
        let e = exp1(rng);
        let r = e.sqrt() * self.inv_s;
        if rng.random::<bool>() { r } else { -r }
    }
    /// As the default, with one `u64` for both the mixture choice (its 53 high bits, the
    /// same uniform as `random::<f64>()`) and the sign of the speed-weighted branch (its
    /// lowest bit, independent of the high bits and of the choice), so a draw costs one
    /// random word less; same law.
    #[inline]
    fn sample_mark(&self, w: f64, mean_speed: f64, rng: &mut Stream) -> f64 {
        let bits = rng.next_u64();
        if unit_f64(bits) * (w + mean_speed) < w {
            std_normal(rng) * (FRAC_1_SQRT_2 * self.inv_s)
        } else {
            let r = exp1(rng).sqrt() * self.inv_s;
            // r >= 0: set the sign bit from the free low bit.
            f64::from_bits(r.to_bits() | (bits << 63))
        }
    }
    #[inline]
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64 {
        match side {
            Side::Right => v1 - sample_w_gaussian(self.s * v1, rng) * self.inv_s,
            Side::Left => v1 + sample_w_gaussian(-self.s * v1, rng) * self.inv_s,
        }
    }
}
