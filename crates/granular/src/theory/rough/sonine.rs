//! The first Sonine approximation of the homogeneous cooling state and of the white-noise
//! driven state of rough grains (RS-8, RS-9): the velocity distribution
//!
//! `f(c, w) = φ(c) φ(w) [1 + a20 S2(c²) + a02 S2(w²) + a11 S1(c²) S1(w²)]`
//!
//! in the scaled velocity `c = v / sqrt(2 T_t / m)` and angular velocity
//! `w = ω / sqrt(2 T_r / I)` (Gaussians `φ ∝ exp(-c²)`, `exp(-w²)`; Sonine polynomials
//! `S1(x) = d/2 - x`, `S2(x) = x²/2 - (d+2) x/2 + d(d+2)/8` in `d = d_t` or `d_r`
//! dimensions), so that `<c⁴> = d_t(d_t+2)/4 (1 + a20)`, `<w⁴> = d_r(d_r+2)/4 (1 + a02)`,
//! `<c² w²> = d_t d_r/4 (1 + a11)` (the cumulants of Santos, Kremer and dos Santos,
//! arXiv 1009.6180, and Megías and Santos, arXiv 2303.00057; the correlation of the
//! directions of `c` and `w` of spheres is left out).
//!
//! The collisional rates of change of `c²`, `w²`, `c⁴`, `w⁴` and `c² w²` are computed
//! exactly, linear in the cumulants (products of two cumulants dropped): the collision rule
//! RS-1 is linear in the velocities of a pair, so every change `Δψ` is a polynomial in
//! them, and the average over colliding pairs of a polynomial times the Gaussians is a
//! sum of products of one-dimensional Gaussian moments. The pair is written in its
//! centre-of-mass velocity `V` (variance 1/4 per component), relative velocity `g`
//! (variance 1; along the normal `n = e_0` weighted by the collision rate `(g_0)⁺`) and the
//! two angular velocities `w` (variance 1/2). The angular velocities enter the contact
//! velocity as `u = sqrt(θ/κ) w`, so a term of `Δψ` of degree `k` in `u` carries
//! `(θ/κ)^(k/2)`: one expansion gives the rates at every θ, and the temperature ratio is
//! the root of a one-dimensional equation. Derivation in `docs/rough.md`.

use super::RoughGas;
use std::collections::BTreeMap;

/// A monomial: four bits of exponent per variable (at most 12 variables, total degree 8).
type Key = u64;

/// A polynomial in the pair's variables.
#[derive(Clone, Debug, Default)]
struct Poly(BTreeMap<Key, f64>);

impl Poly {
    fn var(index: usize) -> Poly {
        let mut p = Poly::default();
        p.0.insert(1u64 << (4 * index), 1.0);
        p
    }

    fn constant(c: f64) -> Poly {
        let mut p = Poly::default();
        if c != 0.0 {
            p.0.insert(0, c);
        }
        p
    }

    fn add(&self, o: &Poly, s: f64) -> Poly {
        let mut out = self.clone();
        for (k, c) in &o.0 {
            *out.0.entry(*k).or_insert(0.0) += s * c;
        }
        out.0.retain(|_, c| *c != 0.0);
        out
    }

    fn scale(&self, s: f64) -> Poly {
        Poly(self.0.iter().map(|(k, c)| (*k, s * c)).collect())
    }

    fn mul(&self, o: &Poly) -> Poly {
        let mut out: BTreeMap<Key, f64> = BTreeMap::new();
        for (ka, ca) in &self.0 {
            for (kb, cb) in &o.0 {
                *out.entry(ka + kb).or_insert(0.0) += ca * cb;
            }
        }
        out.retain(|_, c| *c != 0.0);
        Poly(out)
    }
}

/// The exponent of variable `v` in monomial `k`.
fn exponent(k: Key, v: usize) -> usize {
    ((k >> (4 * v)) & 0xf) as usize
}

/// A vector of linear forms (a velocity of the pair).
type Form = Vec<Poly>;

fn dot(a: &Form, b: &Form) -> Poly {
    a.iter()
        .zip(b)
        .fold(Poly::default(), |acc, (x, y)| acc.add(&x.mul(y), 1.0))
}

/// `e_0 × x` for the tangential form `x` (`D` components; for disks a spin's one `z`
/// component), and `x × e_0` as a velocity.
fn normal_cross(d: usize, x: &Form) -> Form {
    if d == 2 {
        // e_0 × (x_0, x_1, 0) has z component x_1.
        vec![x[1].clone()]
    } else {
        // e_0 × (x_0, x_1, x_2) = (0, -x_2, x_1).
        vec![Poly::default(), x[2].scale(-1.0), x[1].clone()]
    }
}

fn spin_cross_normal(d: usize, w: &Form) -> Form {
    if d == 2 {
        // (0, 0, w) × e_0 = (0, w, 0).
        vec![Poly::default(), w[0].clone()]
    } else {
        // w × e_0 = (0, w_2, -w_1).
        vec![Poly::default(), w[2].clone(), w[1].scale(-1.0)]
    }
}

/// The scaled collisional rates, as sums `Σ_k r^k E_k` over powers of `r = sqrt(θ/κ)`.
#[derive(Clone, Debug, Default)]
struct Series(Vec<(i32, f64)>);

impl Series {
    fn at(&self, r: f64) -> f64 {
        self.0.iter().map(|(k, c)| c * r.powi(*k)).sum()
    }
}

/// The five moments, in the order `c²`, `w²`, `c⁴`, `w⁴`, `c² w²`, and the four terms of
/// the distribution, `1`, `a20`, `a02`, `a11`: `rates[ψ][term]` is the average over colliding
/// Maxwellian pairs of `(g_0)⁺ Δψ` times the term's Sonine polynomial (summed over both
/// grains of the pair), as a series in `r`.
struct Rates {
    /// Rows `c²`, `w²`, `c⁴`, `w⁴`, `c² w²`, and last the collision rate itself (`Δψ`
    /// replaced by 1).
    rates: [[Series; 4]; 6],
    dt: f64,
    dr: f64,
    inertia: f64,
}

/// `E[(g_0)⁺]` for a unit Gaussian, `1 / sqrt(2π)`: the collision rate per unit `ν`.
const MEAN_FLUX: f64 = 0.398_942_280_401_432_7;

impl Rates {
    fn new(gas: &RoughGas) -> Rates {
        let d = gas.dimension;
        let dr = gas.rotational_dof();
        let nr = dr as usize;
        // Variables: V (d), g (d), w_i (nr), w_j (nr).
        let v_idx = |k: usize| k;
        let g_idx = |k: usize| d + k;
        let wi_idx = |k: usize| 2 * d + k;
        let wj_idx = |k: usize| 2 * d + nr + k;
        let nvars = 2 * d + 2 * nr;
        let big_v: Form = (0..d).map(|k| Poly::var(v_idx(k))).collect();
        let g: Form = (0..d).map(|k| Poly::var(g_idx(k))).collect();
        let wi: Form = (0..nr).map(|k| Poly::var(wi_idx(k))).collect();
        let wj: Form = (0..nr).map(|k| Poly::var(wj_idx(k))).collect();
        let ci: Form = (0..d).map(|k| big_v[k].add(&g[k], 0.5)).collect();
        let cj: Form = (0..d).map(|k| big_v[k].add(&g[k], -0.5)).collect();
        // The rule RS-1 for equal grains with n = e_0, spins as u = r w (the w slots).
        let eta_n = 0.5 * (1.0 + gas.normal_restitution);
        let eta_t = gas.tangential_factor();
        let ws: Form = (0..nr).map(|k| wi[k].add(&wj[k], 1.0)).collect();
        let rot = spin_cross_normal(d, &ws);
        let mut gt: Form = (0..d).map(|k| g[k].add(&rot[k], 1.0)).collect();
        gt[0] = Poly::default();
        let mut ci2 = ci.clone();
        let mut cj2 = cj.clone();
        for k in 0..d {
            ci2[k] = ci2[k].add(&gt[k], -eta_t);
            cj2[k] = cj2[k].add(&gt[k], eta_t);
        }
        ci2[0] = ci2[0].add(&g[0], -eta_n);
        cj2[0] = cj2[0].add(&g[0], eta_n);
        let torque = normal_cross(d, &gt);
        let wi2: Form = (0..nr)
            .map(|k| wi[k].add(&torque[k], -eta_t / gas.inertia))
            .collect();
        let wj2: Form = (0..nr)
            .map(|k| wj[k].add(&torque[k], -eta_t / gas.inertia))
            .collect();
        // The moments before and after, summed over the pair; w-degree q of each.
        let moments = |c: &Form, w: &Form| {
            let c2 = dot(c, c);
            let w2 = dot(w, w);
            [
                c2.clone(),
                w2.clone(),
                c2.mul(&c2),
                w2.mul(&w2),
                c2.mul(&w2),
            ]
        };
        let q = [0, 2, 0, 4, 2, 0];
        let (bi, bj, ai, aj) = (
            moments(&ci, &wi),
            moments(&cj, &wj),
            moments(&ci2, &wi2),
            moments(&cj2, &wj2),
        );
        // The Sonine terms of the pair (in w: the distribution's variable).
        let (dt, drf) = (d as f64, dr);
        let s1 = |x: &Poly, dim: f64| Poly::constant(dim / 2.0).add(x, -1.0);
        let s2 = |x: &Poly, dim: f64| {
            x.mul(x)
                .scale(0.5)
                .add(x, -(dim + 2.0) / 2.0)
                .add(&Poly::constant(dim * (dim + 2.0) / 8.0), 1.0)
        };
        let (ci_sq, cj_sq, wi_sq, wj_sq) =
            (dot(&ci, &ci), dot(&cj, &cj), dot(&wi, &wi), dot(&wj, &wj));
        let terms = [
            Poly::constant(1.0),
            s2(&ci_sq, dt).add(&s2(&cj_sq, dt), 1.0),
            s2(&wi_sq, drf).add(&s2(&wj_sq, drf), 1.0),
            s1(&ci_sq, dt)
                .mul(&s1(&wi_sq, drf))
                .add(&s1(&cj_sq, dt).mul(&s1(&wj_sq, drf)), 1.0),
        ];
        // One-dimensional moments: V (variance 1/4), g_0 (half line, weight g_0),
        // other g (variance 1), w (variance 1/2).
        let gauss = |s2: f64, e: usize| -> f64 {
            if e % 2 == 1 {
                0.0
            } else {
                let mut m = 1.0;
                let mut k = 1;
                while k < e {
                    m *= k as f64 * s2;
                    k += 2;
                }
                m
            }
        };
        let half = |e: usize| -> f64 {
            // ∫_0^∞ x^(e+1) φ(x) dx = 2^(e/2) Γ(e/2 + 1) / sqrt(2π).
            2f64.powf(e as f64 / 2.0) * libm::tgamma(e as f64 / 2.0 + 1.0) * MEAN_FLUX
        };
        let mut table = vec![[0.0f64; 16]; nvars];
        for (v, row) in table.iter_mut().enumerate() {
            for (e, m) in row.iter_mut().enumerate() {
                *m = if v < d {
                    gauss(0.25, e)
                } else if v == d {
                    half(e)
                } else if v < 2 * d {
                    gauss(1.0, e)
                } else {
                    gauss(0.5, e)
                };
            }
        }
        // Parity of every variable but g_0: a product integrates to zero unless even.
        let parity = |k: Key| -> u32 {
            let mut p = 0;
            for v in 0..nvars {
                if v != d && exponent(k, v) % 2 == 1 {
                    p |= 1 << v;
                }
            }
            p
        };
        let u_degree = |k: Key| -> i32 { (2 * d..nvars).map(|v| exponent(k, v) as i32).sum() };
        let grouped: Vec<BTreeMap<u32, Vec<(Key, f64)>>> = terms
            .iter()
            .map(|t| {
                let mut m: BTreeMap<u32, Vec<(Key, f64)>> = BTreeMap::new();
                for (k, c) in &t.0 {
                    m.entry(parity(*k)).or_default().push((*k, *c));
                }
                m
            })
            .collect();
        let mut rates: [[Series; 4]; 6] = Default::default();
        for (p, row) in rates.iter_mut().enumerate() {
            let delta = if p == 5 {
                Poly::constant(1.0)
            } else {
                ai[p].add(&aj[p], 1.0).add(&bi[p], -1.0).add(&bj[p], -1.0)
            };
            for (t, series) in row.iter_mut().enumerate() {
                let mut by_power: BTreeMap<i32, f64> = BTreeMap::new();
                for (ka, ca) in &delta.0 {
                    let Some(partners) = grouped[t].get(&parity(*ka)) else {
                        continue;
                    };
                    let mut sum = 0.0;
                    for (kb, cb) in partners {
                        let k = ka + kb;
                        let mut m = *cb;
                        for (v, row) in table.iter().enumerate() {
                            m *= row[exponent(k, v)];
                        }
                        sum += m;
                    }
                    *by_power.entry(u_degree(*ka) - q[p]).or_insert(0.0) += ca * sum;
                }
                let mut s: Vec<(i32, f64)> = by_power.into_iter().collect();
                s.sort_by_key(|(k, _)| *k);
                *series = Series(s);
            }
        }
        Rates {
            rates,
            dt,
            dr: drf,
            inertia: gas.inertia,
        }
    }

    /// `K[ψ]` at temperature ratio `theta` for the cumulants `a = [a20, a02, a11]`.
    fn rate(&self, psi: usize, theta: f64, a: &[f64; 3]) -> f64 {
        let r = (theta / self.inertia).sqrt();
        let row = &self.rates[psi];
        row[0].at(r) + a[0] * row[1].at(r) + a[1] * row[2].at(r) + a[2] * row[3].at(r)
    }

    /// The coefficients `(K_0, [K_20, K_02, K_11])` of `K[ψ]` at `theta`.
    fn linear(&self, psi: usize, theta: f64) -> (f64, [f64; 3]) {
        let r = (theta / self.inertia).sqrt();
        let row = &self.rates[psi];
        (row[0].at(r), [row[1].at(r), row[2].at(r), row[3].at(r)])
    }

    /// The translational and rotational cooling rates over `ν` (RS-2, RS-3 with the
    /// cumulants): `ζ_t/ν = -K[c²] / (d_t E)`, `ζ_r/ν = -K[w²] / (d_r E)`, `E = 1/sqrt(2π)`.
    fn cooling_rates(&self, theta: f64, a: &[f64; 3]) -> (f64, f64) {
        (
            -self.rate(0, theta, a) / (self.dt * MEAN_FLUX),
            -self.rate(1, theta, a) / (self.dr * MEAN_FLUX),
        )
    }
}

/// Solves the 3×3 system `m a = rhs` (Cramer); `None` if singular.
fn solve3(m: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let mut mc = m;
        for r in 0..3 {
            mc[r][c] = rhs[r];
        }
        *o = det(&mc) / d;
    }
    Some(out)
}

/// A steady state in the first Sonine approximation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SonineState {
    /// `θ = T_r / T_t`.
    pub temperature_ratio: f64,
    /// Cumulant `a20 = d_t/(d_t+2) <c⁴>/<c²>² - 1` of the translational velocities.
    pub a20: f64,
    /// Cumulant `a02 = d_r/(d_r+2) <w⁴>/<w²>² - 1` of the angular velocities.
    pub a02: f64,
    /// Cumulant `a11 = <c² w²>/(<c²><w²>) - 1`.
    pub a11: f64,
    /// The translational cooling rate `ζ_t / ν` (RS-2 with the cumulants): in the
    /// homogeneous cooling state the cooling rate of every temperature.
    pub cooling_rate: f64,
    /// The cooling rate of the total energy over `ν` (equal to `cooling_rate` in the
    /// homogeneous cooling state; `d_t ζ_t / (d_t + d_r θ)` in the white-noise state).
    pub total_cooling_rate: f64,
    /// The collision frequency over the Maxwellian one, `1 + a20 E[g_n⁺ S2 terms]/E[g_n⁺]`
    /// (`1 - a20/16`): what a measured collision rate has to be divided by.
    pub collision_frequency_factor: f64,
}

/// Which steady state.
#[derive(Clone, Copy, Debug, PartialEq)]
enum State {
    Cooling,
    WhiteNoise,
}

/// The linear equations of the cumulants at `theta` (rows: the `c⁴`, `w⁴` and `c² w²`
/// balances, linearised in the cumulants; `docs/rough.md`), solved.
fn cumulants(rates: &Rates, state: State, theta: f64) -> Option<[f64; 3]> {
    let (dt, dr) = (rates.dt, rates.dr);
    let (c2_0, c2) = rates.linear(0, theta);
    let (w2_0, w2) = rates.linear(1, theta);
    let mut m = [[0.0; 3]; 3];
    let mut rhs = [0.0; 3];
    for psi in 0..3 {
        let (k0, k) = rates.linear(2 + psi, theta);
        // Each balance reads K[ψ] = Σ_x λ_x K[x] (1 + a_ψ) (HCS) or Σ_x λ_x K[x] (white
        // noise), with K[x] for x = c², w²; linearised: the products of cumulants dropped.
        let (lc, lw, own) = match (state, psi) {
            (State::Cooling, 0) => (dt + 2.0, 0.0, Some(0)),
            (State::Cooling, 1) => (0.0, dr + 2.0, Some(1)),
            (State::Cooling, _) => (dr / 2.0, dt / 2.0, Some(2)),
            (State::WhiteNoise, 0) => (dt + 2.0, 0.0, None),
            (State::WhiteNoise, 1) => (0.0, 0.0, None),
            (State::WhiteNoise, _) => (dr / 2.0, 0.0, None),
        };
        let base = lc * c2_0 + lw * w2_0;
        for j in 0..3 {
            m[psi][j] = k[j] - lc * c2[j] - lw * w2[j];
        }
        if let Some(o) = own {
            m[psi][o] -= base;
        }
        rhs[psi] = base - k0;
    }
    solve3(m, rhs)
}

/// The residual whose root is θ: `ζ_t - ζ_r` (HCS) or `ζ_r` (white noise).
fn residual(rates: &Rates, state: State, theta: f64) -> Option<f64> {
    let a = cumulants(rates, state, theta)?;
    let (zt, zr) = rates.cooling_rates(theta, &a);
    Some(match state {
        State::Cooling => zt - zr,
        State::WhiteNoise => zr,
    })
}

/// The root nearest `guess`: the residual is scanned outwards from `guess` in steps of
/// 2 % (down to `guess/20` and up to `20 guess`), every sign change bisected, and a sign
/// change kept only where the residual vanishes there (a pole of the linear equations of
/// the cumulants also changes sign, with a residual that grows without bound).
fn steady_state(rates: &Rates, state: State, guess: f64) -> Option<SonineState> {
    let f = |t: f64| residual(rates, state, t);
    let bisect = |mut lo: f64, mut hi: f64| -> Option<f64> {
        let mut flo = f(lo)?;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            let fm = f(mid)?;
            if fm.signum() == flo.signum() {
                lo = mid;
                flo = fm;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-14 * hi {
                break;
            }
        }
        let root = 0.5 * (lo + hi);
        (f(root)?.abs() < 1e-9).then_some(root)
    };
    let step = 1.02f64;
    let (mut down, mut up) = (guess, guess);
    let (mut f_down, mut f_up) = (f(guess)?, f(guess)?);
    if f_down == 0.0 {
        return finish(rates, state, guess);
    }
    while up < 20.0 * guess {
        let (lo, hi) = (down / step, up * step);
        let (f_lo, f_hi) = (f(lo)?, f(hi)?);
        if f_lo.signum() != f_down.signum()
            && let Some(root) = bisect(lo, down)
        {
            return finish(rates, state, root);
        }
        if f_hi.signum() != f_up.signum()
            && let Some(root) = bisect(up, hi)
        {
            return finish(rates, state, root);
        }
        (down, up, f_down, f_up) = (lo, hi, f_lo, f_hi);
    }
    None
}

/// The state at the temperature ratio `theta`.
fn finish(rates: &Rates, state: State, theta: f64) -> Option<SonineState> {
    let a = cumulants(rates, state, theta)?;
    let (zt, zr) = rates.cooling_rates(theta, &a);
    let total = (rates.dt * zt + rates.dr * theta * zr) / (rates.dt + rates.dr * theta);
    Some(SonineState {
        temperature_ratio: theta,
        a20: a[0],
        a02: a[1],
        a11: a[2],
        cooling_rate: zt,
        total_cooling_rate: total,
        collision_frequency_factor: rates.rate(5, theta, &a) / MEAN_FLUX,
    })
}

impl RoughGas {
    /// RS-8: the homogeneous cooling state in the first Sonine approximation (θ, the
    /// cumulants and `ζ/ν`); `None` for smooth grains (β = -1) or where the linear
    /// equations have no solution.
    pub fn sonine_cooling_state(&self) -> Option<SonineState> {
        let guess = self.cooling_temperature_ratio()?;
        steady_state(&Rates::new(self), State::Cooling, guess)
    }

    /// RS-9: the white-noise driven state (kicks on the translational velocities) in the
    /// first Sonine approximation; `None` for smooth grains.
    pub fn sonine_white_noise_state(&self) -> Option<SonineState> {
        if self.tangential_restitution <= -1.0 {
            return None;
        }
        let guess = self.white_noise_temperature_ratio();
        steady_state(&Rates::new(self), State::WhiteNoise, guess)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gas(dimension: usize, alpha: f64, beta: f64, inertia: f64) -> RoughGas {
        RoughGas {
            dimension,
            normal_restitution: alpha,
            tangential_restitution: beta,
            inertia,
        }
    }

    /// With the cumulants zero the exact rates are the Maxwellian RS-2 and RS-3.
    #[test]
    fn maxwellian_rates_are_rs2_and_rs3() {
        for (d, a, b, k, theta) in [
            (2, 0.9, 0.0, 0.5, 0.7),
            (3, 0.7, -0.5, 0.4, 2.0),
            (3, 0.5, 1.0, 0.4, 0.3),
            (2, 0.8, 0.6, 1.0, 1.3),
        ] {
            let g = gas(d, a, b, k);
            let rates = Rates::new(&g);
            let (zt, zr) = rates.cooling_rates(theta, &[0.0; 3]);
            assert!(
                (zt - g.translational_cooling_rate(theta)).abs() < 1e-12,
                "{d} {zt}"
            );
            assert!(
                (zr - g.rotational_cooling_rate(theta)).abs() < 1e-12,
                "{d} {zr}"
            );
        }
    }

    /// Smooth grains: the rotation decouples and the translational balance alone gives
    /// a20 = van Noije and Ernst's a2 of the homogeneous cooling state (their first
    /// estimate, `theory::sonine::cooling_a2_first`, is this linearisation: the product
    /// `a2 K_20[c²]` dropped) and of the white-noise state.
    #[test]
    fn smooth_limit_is_van_noije_and_ernst() {
        for d in [2, 3] {
            for e in [0.3, 0.6, 0.9] {
                let rates = Rates::new(&gas(d, e, -1.0, 0.4));
                let (k0, k) = rates.linear(2, 1.0);
                let (c0, c) = rates.linear(0, 1.0);
                let dt = d as f64;
                // K0 + K20 a = (d+2) (c0 + c20 a + c0 a)   (HCS)
                let hcs = ((dt + 2.0) * c0 - k0) / (k[0] - (dt + 2.0) * (c[0] + c0));
                let want = crate::theory::sonine::cooling_a2_first(d, e);
                assert!((hcs - want).abs() < 1e-12, "{d} {e}: {hcs} {want}");
                // K0 + K20 a = (d+2) (c0 + c20 a)   (white noise)
                let wn = ((dt + 2.0) * c0 - k0) / (k[0] - (dt + 2.0) * c[0]);
                let want = crate::theory::sonine::white_noise_a2(d, e);
                assert!((wn - want).abs() < 1e-12, "{d} {e}: {wn} {want}");
            }
        }
    }

    /// Perfectly rough elastic grains are in equilibrium: θ = 1, no cumulants, no cooling.
    #[test]
    fn elastic_rough_grains_are_in_equilibrium() {
        for (d, k) in [(2, 0.5), (3, 0.4)] {
            let s = gas(d, 1.0, 1.0, k).sonine_cooling_state().unwrap();
            assert!((s.temperature_ratio - 1.0).abs() < 1e-10, "{s:?}");
            assert!(s.a20.abs() < 1e-10 && s.a02.abs() < 1e-10 && s.a11.abs() < 1e-10);
            assert!(s.cooling_rate.abs() < 1e-12);
        }
    }

    /// The exact rates `K[ψ][term]` against a Monte Carlo average of the collision rule
    /// itself (`collision_law::rough::collide_pair`, not the polynomial map above) over
    /// colliding Maxwellian pairs (normal relative velocity from the collision-weighted
    /// density), of `Δψ` times each Sonine term: the mean is `K / E[(g_0)⁺]`. Four standard
    /// errors, 4·10⁵ pairs per case.
    fn monte_carlo<const D: usize>(alpha: f64, beta: f64, kappa: f64, theta: f64) {
        use crate::collision_law::rough::{Body, Tangential, collide_pair};
        use crate::random::{open01, std_normal, stream};
        use crate::vector::Vector;
        let g = gas(D, alpha, beta, kappa);
        let rates = Rates::new(&g);
        let r = (theta / kappa).sqrt();
        let body = Body {
            mass: 1.0,
            radius: 0.5,
            inertia: kappa,
        };
        let (dt, dr) = (g.translational_dof(), g.rotational_dof());
        let s1 = |x: f64, d: f64| d / 2.0 - x;
        let s2 = |x: f64, d: f64| x * x / 2.0 - (d + 2.0) * x / 2.0 + d * (d + 2.0) / 8.0;
        let mut rng = stream(7, &[D as u64]);
        let samples = 400_000;
        let mut sums = [[[0.0f64; 2]; 4]; 5];
        let first = if D == 2 { 2 } else { 0 };
        for _ in 0..samples {
            let mut rel = Vector::<D>::zero();
            let mut centre = Vector::<D>::zero();
            rel[0] = (-2.0 * open01(&mut rng).ln()).sqrt();
            for k in 0..D {
                if k > 0 {
                    rel[k] = std_normal(&mut rng);
                }
                centre[k] = 0.5 * std_normal(&mut rng);
            }
            let (mut vi, mut vj) = (centre.add_scaled(0.5, &rel), centre.add_scaled(-0.5, &rel));
            let (mut wi, mut wj) = ([0.0; 3], [0.0; 3]);
            for k in first..3 {
                wi[k] = std_normal(&mut rng) * 0.5f64.sqrt() * 2.0 * r;
                wj[k] = std_normal(&mut rng) * 0.5f64.sqrt() * 2.0 * r;
            }
            let scaled = |v: &Vector<D>, w: &[f64; 3]| {
                let c2 = v.norm_squared();
                let w2 = w.iter().map(|x| x * x).sum::<f64>() / (4.0 * r * r);
                (c2, w2)
            };
            let psi = |c2: f64, w2: f64| [c2, w2, c2 * c2, w2 * w2, c2 * w2];
            let ((ci, wi2), (cj, wj2)) = (scaled(&vi, &wi), scaled(&vj, &wj));
            let terms = [
                1.0,
                s2(ci, dt) + s2(cj, dt),
                s2(wi2, dr) + s2(wj2, dr),
                s1(ci, dt) * s1(wi2, dr) + s1(cj, dt) * s1(wj2, dr),
            ];
            let before = [psi(ci, wi2), psi(cj, wj2)];
            let mut n = Vector::<D>::zero();
            n[0] = 1.0;
            collide_pair(
                alpha,
                Tangential::Constant(beta),
                &n,
                &body,
                &body,
                &mut vi,
                &mut vj,
                &mut wi,
                &mut wj,
            );
            let ((ci, wi2), (cj, wj2)) = (scaled(&vi, &wi), scaled(&vj, &wj));
            let after = [psi(ci, wi2), psi(cj, wj2)];
            for p in 0..5 {
                let delta = after[0][p] + after[1][p] - before[0][p] - before[1][p];
                for t in 0..4 {
                    let x = delta * terms[t];
                    sums[p][t][0] += x;
                    sums[p][t][1] += x * x;
                }
            }
        }
        let nf = samples as f64;
        for (p, row) in sums.iter().enumerate() {
            for (t, sum) in row.iter().enumerate() {
                let mean = sum[0] / nf;
                let err = ((sum[1] / nf - mean * mean) / nf).sqrt();
                let exact = rates.rates[p][t].at(r) / MEAN_FLUX;
                assert!(
                    (mean - exact).abs() < 4.0 * err + 1e-12,
                    "D = {D} ψ {p} term {t}: MC {mean} ± {err}, exact {exact}"
                );
            }
        }
    }

    #[test]
    fn exact_rates_match_a_monte_carlo_average_of_the_rule() {
        monte_carlo::<2>(0.8, 0.3, 0.5, 0.7);
        monte_carlo::<3>(0.7, -0.2, 0.4, 1.6);
    }

    /// The collision frequency of the Sonine distribution is `ν_M (1 - a20/16)` in both
    /// dimensions (the classical factor of smooth hard grains: only the translational
    /// distribution enters the collision rate).
    #[test]
    fn collision_frequency_factor_is_one_minus_a20_over_16() {
        for d in [2, 3] {
            let g = gas(d, 0.8, 0.2, 0.4);
            let rates = Rates::new(&g);
            let factor = rates.rate(5, 0.7, &[0.1, 0.3, -0.2]) / MEAN_FLUX;
            assert!((factor - (1.0 - 0.1 / 16.0)).abs() < 1e-14, "{d}: {factor}");
        }
    }
}
