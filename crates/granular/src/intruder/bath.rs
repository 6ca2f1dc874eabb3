//! Bath velocity distributions f(v) of the thermalised point particles (one velocity
//! component, the one normal to the intruder's surface), their side fluxes (G-5 to G-7) and
//! exact samplers of the velocity of the bath particle that collides (G-12 and G-13).
//!
//! All fluxes here are *per unit bath density*: multiply by `rho` to get G-5 to G-7.
//!
//! Sides: [`Side::Right`] is the paper's "+" side (G-5): bath particles with `v < v1`
//! that the intruder catches up with on its right; [`Side::Left`] is "-" (G-6).

use std::f64::consts::{FRAC_1_SQRT_2, FRAC_2_SQRT_PI, PI, SQRT_2};

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::random::{RngExt, Stream, exp1, open01, std_normal, unit_f64};

/// `1/sqrt(pi)`.
pub const FRAC_1_SQRT_PI: f64 = 0.5 * FRAC_2_SQRT_PI;
/// `sqrt(pi)`.
pub const SQRT_PI: f64 = 1.772_453_850_905_516;

/// The side of the intruder hit by a bath particle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// "+" side (G-5, G-12): the bath particle has `v <= v1`.
    Right,
    /// "-" side (G-6, G-13): the bath particle has `v >= v1`.
    Left,
}

/// Why a bath distribution could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BathError {
    /// The table file could not be read.
    #[error("cannot read bath table {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A line of the table could not be parsed.
    #[error("bath table {path}, line {line}: {message}")]
    Parse {
        /// The file (or `<inline>`).
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The table is not a valid density.
    #[error("invalid bath table: {0}")]
    Invalid(String),
    /// A parameter is out of range.
    #[error("invalid bath parameter: {0}")]
    Parameter(String),
}

/// Interface of a bath velocity distribution (one velocity component).
pub trait BathDistribution {
    /// Probability density f(v).
    fn density(&self, v: f64) -> f64;
    /// Cumulative distribution `F(v) = int_{-inf}^{v} f`.
    fn cdf(&self, v: f64) -> f64;
    /// Survival function `1 - F(v)`, accurate in the upper tail.
    fn sf(&self, v: f64) -> f64 {
        1.0 - self.cdf(v)
    }
    /// `<v^2>` (the bath temperature is `m <v^2>`).
    fn second_moment(&self) -> f64;
    /// `<|v|>`; the collision rate of an intruder at rest is `rho <|v|>`.
    fn mean_speed(&self) -> f64;
    /// `phi_+(v1)/rho = int_{-inf}^{v1} (v1 - v) f(v) dv` (G-5).
    fn flux_plus(&self, v1: f64) -> f64;
    /// `phi_-(v1)/rho = int_{v1}^{inf} (v - v1) f(v) dv` (G-6).
    fn flux_minus(&self, v1: f64) -> f64;
    /// Total rate per unit density (G-7).
    fn flux(&self, v1: f64) -> f64 {
        self.flux_plus(v1) + self.flux_minus(v1)
    }
    /// Flux on one side.
    fn flux_side(&self, side: Side, v1: f64) -> f64 {
        match side {
            Side::Right => self.flux_plus(v1),
            Side::Left => self.flux_minus(v1),
        }
    }
    /// A bath velocity drawn from f.
    fn sample(&self, rng: &mut Stream) -> f64;
    /// A velocity drawn from the speed-weighted density `|v| f(v) / <|v|>`.
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64;
    /// A velocity from the thinning mark density `(w + |v|) f(v) / (w + <|v|>)` for
    /// `w >= 0` (`mean_speed` is `<|v|>`): the mixture of `f` (weight `w`) and of
    /// `|v| f / <|v|>` (weight `<|v|>`).
    #[inline]
    fn sample_mark(&self, w: f64, mean_speed: f64, rng: &mut Stream) -> f64 {
        if rng.random::<f64>() * (w + mean_speed) < w {
            self.sample(rng)
        } else {
            self.sample_speed_weighted(rng)
        }
    }
    /// An exact draw from g_+ (G-12) or g_- (G-13).
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64;
    /// Cumulative distribution function of g_side(., v1) (G-12, G-13) at `v` (tests, figures).
    ///
    /// Uses `int_{-inf}^{v} (v1 - w) f(w) dw = phi_+(v) + (v1 - v) F(v)` (and its mirror
    /// image), so it is exact whenever the fluxes and F are.
    fn colliding_cdf(&self, side: Side, v1: f64, v: f64) -> f64 {
        match side {
            Side::Right => {
                if v >= v1 {
                    1.0
                } else {
                    ((self.flux_plus(v) + (v1 - v) * self.cdf(v)) / self.flux_plus(v1)).min(1.0)
                }
            }
            Side::Left => {
                if v <= v1 {
                    0.0
                } else {
                    let upper = self.flux_minus(v) + (v - v1) * self.sf(v);
                    (1.0 - upper / self.flux_minus(v1)).max(0.0)
                }
            }
        }
    }
    /// Density g_side(v, v1) of G-12 and G-13.
    fn colliding_density(&self, side: Side, v1: f64, v: f64) -> f64 {
        let (w, phi) = match side {
            Side::Right => (v1 - v, self.flux_plus(v1)),
            Side::Left => (v - v1, self.flux_minus(v1)),
        };
        if w < 0.0 {
            0.0
        } else {
            w * self.density(v) / phi
        }
    }
}

// ---------------------------------------------------------------------------------------
// Gaussian bath (G-14)
// ---------------------------------------------------------------------------------------

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
pub fn gaussian_h(x: f64) -> f64 {
    if x >= -3.0 {
        h_direct(x)
    } else if x >= -8.0 {
        h_erfcx(x)
    } else {
        h_asymptotic(x)
    }
}

#[inline]
fn h_direct(x: f64) -> f64 {
    x * libm::erfc(-x) + (-x * x).exp() * FRAC_1_SQRT_PI
}

fn h_erfcx(x: f64) -> f64 {
    let z = -x;
    (-x * x).exp() * (FRAC_1_SQRT_PI - z * puruspe::erfcx(z))
}

/// `x erfcx(-x) + 1/sqrt(pi) = (1/sqrt(pi)) sum_{k>=1} (-1)^(k+1) (2k-1)!! / (2 x^2)^k`
/// (asymptotic; at `|x| >= 8` its smallest term is far below machine precision).
fn h_asymptotic(x: f64) -> f64 {
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

// ---------------------------------------------------------------------------------------
// Power-law bath (G-19)
// ---------------------------------------------------------------------------------------

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
pub fn power_law_cdf_scaled(y: f64) -> f64 {
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

// ---------------------------------------------------------------------------------------
// Tabulated bath
// ---------------------------------------------------------------------------------------

/// Draws `t` in `[0, 1]` with density proportional to `A(t) B(t)`, where `A` and `B` are
/// linear and non-negative on `[0, 1]` (`A(0) = a0`, ...). Exact: in the Bernstein basis
/// `A B = a0 b0 (1-t)^2 + (a0 b1 + a1 b0) t (1-t) + a1 b1 t^2`, a mixture of Beta(1,3),
/// Beta(2,2) and Beta(3,1) with weights `a0 b0/3`, `(a0 b1 + a1 b0)/6`, `a1 b1/3`.
pub fn sample_linear_product(a0: f64, a1: f64, b0: f64, b1: f64, rng: &mut Stream) -> f64 {
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
pub const MAX_TABLE_MAGNITUDE: f64 = 1e100;

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
    /// integral, or beyond [`MAX_TABLE_MAGNITUDE`] in magnitude.
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

// ---------------------------------------------------------------------------------------
// Configuration and the closed set of baths
// ---------------------------------------------------------------------------------------

/// Bath velocity distribution of an intruder engine (the scenario's `[intruder.bath]`
/// table is read into it by `scenario::BathTable`).
#[derive(Clone, Debug, PartialEq)]
pub enum BathConfig {
    /// Gaussian, G-14, `a = m / (2 T_B)`.
    Gaussian {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Power law, G-19, `a = m / T_B` (since `<v^2> = 1/a`).
    PowerLaw {
        /// Bath temperature `T_B = m <v^2>` (energy units, `k_B = 1`).
        temperature: f64,
    },
    /// Piecewise-linear density through the points `(v, f)` (velocity units, density in
    /// 1/velocity), normalised ([`Tabulated::new`]).
    Tabulated {
        /// The points, velocities increasing.
        points: Vec<(f64, f64)>,
    },
}

impl Default for BathConfig {
    fn default() -> Self {
        // a = 1 with m = 1, as in the paper's figures.
        BathConfig::Gaussian { temperature: 0.5 }
    }
}

/// One of the supported baths (static dispatch); serialisable for checkpoints.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Bath {
    /// G-14.
    Gaussian(Gaussian),
    /// G-19.
    PowerLaw(PowerLaw),
    /// Tabulated.
    Tabulated(Box<Tabulated>),
}

impl BathConfig {
    /// Builds the bath for bath particles of mass `m`.
    pub fn build(&self, m: f64) -> Result<Bath, BathError> {
        Ok(match self {
            BathConfig::Gaussian { temperature } => {
                Bath::Gaussian(Gaussian::with_temperature(*temperature, m)?)
            }
            BathConfig::PowerLaw { temperature } => {
                Bath::PowerLaw(PowerLaw::with_temperature(*temperature, m)?)
            }
            BathConfig::Tabulated { points } => Bath::Tabulated(Box::new(Tabulated::new(points)?)),
        })
    }
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bath::Gaussian($b) => $e,
            Bath::PowerLaw($b) => $e,
            Bath::Tabulated($b) => $e,
        }
    };
}

impl BathDistribution for Bath {
    #[inline]
    fn density(&self, v: f64) -> f64 {
        dispatch!(self, b => b.density(v))
    }
    fn cdf(&self, v: f64) -> f64 {
        dispatch!(self, b => b.cdf(v))
    }
    fn sf(&self, v: f64) -> f64 {
        dispatch!(self, b => b.sf(v))
    }
    fn second_moment(&self) -> f64 {
        dispatch!(self, b => b.second_moment())
    }
    #[inline]
    fn mean_speed(&self) -> f64 {
        dispatch!(self, b => b.mean_speed())
    }
    #[inline]
    fn flux_plus(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux_plus(v1))
    }
    #[inline]
    fn flux_minus(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux_minus(v1))
    }
    #[inline]
    fn flux(&self, v1: f64) -> f64 {
        dispatch!(self, b => b.flux(v1))
    }
    #[inline]
    fn sample(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample(rng))
    }
    #[inline]
    fn sample_speed_weighted(&self, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_speed_weighted(rng))
    }
    #[inline]
    fn sample_mark(&self, w: f64, mean_speed: f64, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_mark(w, mean_speed, rng))
    }
    #[inline]
    fn sample_colliding(&self, side: Side, v1: f64, rng: &mut Stream) -> f64 {
        dispatch!(self, b => b.sample_colliding(side, v1, rng))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::stream;

    #[test]
    fn power_law_cdf_is_continuous_and_normalised() {
        for &y in &[-2.0f64, 2.0] {
            let a = power_law_cdf_scaled(y - 1e-12);
            let b = power_law_cdf_scaled(y + 1e-12);
            assert!((a - b).abs() < 1e-10, "{y}: {a} {b}");
        }
        assert!((power_law_cdf_scaled(0.0) - 0.5).abs() < 1e-15);
        assert!(power_law_cdf_scaled(1e6) >= 1.0 - 1e-15);
        assert!(power_law_cdf_scaled(-1e6) > 0.0);
    }

    #[test]
    fn gaussian_h_branches_agree() {
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(rel(h_direct(-3.0), h_erfcx(-3.0)) < 1e-9);
        assert!(rel(h_asymptotic(-8.0), h_erfcx(-8.0)) < 1e-12);
    }

    #[test]
    fn linear_product_sampler_mean() {
        let mut rng = stream(3, &[1]);
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|_| sample_linear_product(1.0, 0.0, 1.0, 0.0, &mut rng))
            .sum::<f64>()
            / n as f64;
        // density 3 (1-t)^2: mean 1/4
        assert!((mean - 0.25).abs() < 4.0 * (3.0f64 / 80.0).sqrt() / (n as f64).sqrt());
    }

    /// The Gaussian thinning mark sampler (one random word for the mixture choice and the
    /// sign) draws `(w + |v|) f(v) / (w + <|v|>)`: chi-square against its exact CDF
    /// `(w F(v) + S(v)) / (w + <|v|>)`, `S(v) = int_{-inf}^v |u| f(u) du`.
    #[test]
    fn gaussian_mark_sampler_is_exact() {
        let g = Gaussian::new(1.7).unwrap();
        let ms = g.mean_speed();
        let s_cdf = |v: f64| {
            let tail = (-g.a * v * v).exp() * 0.5 * ms;
            if v < 0.0 { tail } else { ms - tail }
        };
        for (k, &w) in [0.0, 0.3, 2.5].iter().enumerate() {
            let mut rng = stream(21, &[k as u64]);
            let mut h = crate::stats::Histogram::new(-3.0, 3.0, 60);
            for _ in 0..400_000 {
                h.push(g.sample_mark(w, ms, &mut rng));
            }
            let c = crate::stats::chi_square_test(&h, |v| (w * g.cdf(v) + s_cdf(v)) / (w + ms));
            assert!(c.p_value > 1e-4, "w = {w}: {c:?}");
        }
    }

    #[test]
    fn table_bound_is_the_scenario_bound() {
        assert_eq!(MAX_TABLE_MAGNITUDE, crate::scenario::MAGNITUDE);
    }
}
