//! Rough grains: the collision rule on the velocity of the contact point (RS-1), for a pair
//! and at a flat wall, with a constant tangential restitution β or Walton's Coulomb rule
//! (RS-7).
//!
//! Two grains `i`, `j` of masses `m`, radii `R` and reduced moments of inertia
//! `κ = I / (m R²) = 4 I / (m σ²)` touch along the unit normal `n` pointing from `i` to `j`.
//! The velocity of `i`'s contact point relative to `j`'s is
//! `g = v_i - v_j + (R_i ω_i + R_j ω_j) × n`; a collision makes its normal part
//! `g_n' = -α g_n` and its tangential part `g_t' = -β g_t` (Luding, Huthmann, McNamara and
//! Zippelius, Phys. Rev. E 58, 3416 (1998); Megías and Santos, arXiv 2303.00057, who write
//! disks and spheres alike). The impulse on `i` (minus that on `j`) that does it is
//! `J = -μ (1 + α) g_n n - M_t (1 + β) g_t`, with the reduced mass `μ = m_i m_j/(m_i + m_j)`
//! and the tangential mass `M_t = 1 / (1/μ + 1/(κ_i m_i) + 1/(κ_j m_j))`; then
//! `v_i' = v_i + J/m_i`, `v_j' = v_j - J/m_j`, `ω_i' = ω_i + n × J / (κ_i m_i R_i)` and
//! `ω_j' = ω_j + n × J / (κ_j m_j R_j)`. Momentum and the angular momentum about any point
//! are conserved; the energy lost is `μ (1 - α²) g_n²/2 + M_t (1 - β²) |g_t|²/2`, none for
//! `α = 1`, `β = ±1`. For `β = -1` the tangential impulse vanishes and the rule is HD-11.
//! Derivation in `docs/rough.md`.
//!
//! Disks (2D) spin about the axis normal to their plane: their angular velocity is the
//! third component of a `Spin`, the other two stay zero.

use crate::vector::Vector;

/// Angular velocity of a grain (radians per time unit) as a vector in three dimensions; a
/// disk spins about the `z` axis, `[0, 0, ω]`.
pub(crate) type Spin = [f64; 3];

/// Rotational degrees of freedom `d_r` of a grain in `dimension` dimensions: 1 for a disk
/// (rotation in its plane), 3 for a sphere; `d_r = D (D - 1) / 2`.
pub(crate) const fn rotational_dof(dimension: usize) -> usize {
    dimension * (dimension - 1) / 2
}

/// The reduced moment of inertia of a uniform grain: 1/2 for a disk, 2/5 for a sphere
/// (the default of `species[i].inertia`).
pub(crate) const fn uniform_inertia(dimension: usize) -> f64 {
    if dimension == 2 { 0.5 } else { 0.4 }
}

/// The largest reduced moment of inertia of a grain whose mass lies within its radius:
/// 1 for a ring (disks), 2/3 for a hollow sphere.
pub const fn max_inertia(dimension: usize) -> f64 {
    if dimension == 2 { 1.0 } else { 2.0 / 3.0 }
}

/// The spin of grain `i` from a flat array of `d_r` values per grain (the `z` component
/// alone for disks).
#[inline(always)]
pub(crate) fn spin_at<const D: usize>(flat: &[f64], i: usize) -> Spin {
    if D == 2 {
        [0.0, 0.0, flat[i]]
    } else {
        [flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]]
    }
}

/// Stores the spin of grain `i` into a flat array of `d_r` values per grain.
#[inline(always)]
pub(crate) fn set_spin<const D: usize>(flat: &mut [f64], i: usize, w: &Spin) {
    if D == 2 {
        flat[i] = w[2];
    } else {
        flat[3 * i..3 * i + 3].copy_from_slice(w);
    }
}

/// The rotational kinetic energy `I |ω|² / 2 = κ m R² |ω|² / 2` of a grain.
#[inline(always)]
pub(crate) fn rotational_energy(body: &Body, w: &Spin) -> f64 {
    0.5 * body.moment_of_inertia() * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
}

/// A grain as a collision sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Body {
    /// Mass `m` (mass units).
    pub mass: f64,
    /// Radius `R` (length units): the lever arm of the contact point.
    pub radius: f64,
    /// Reduced moment of inertia `κ = I / (m R²)`: 1/2 for a uniform disk, 2/5 for a
    /// uniform sphere, at most 1 (a ring) and 2/3 (a hollow sphere).
    pub inertia: f64,
}

impl Body {
    /// The moment of inertia `I = κ m R²` about any axis through the centre.
    #[inline(always)]
    pub(crate) fn moment_of_inertia(&self) -> f64 {
        self.inertia * self.mass * self.radius * self.radius
    }

    /// `κ m R`, the factor that turns the torque axis `n × J` into a change of angular
    /// velocity (`I / R`).
    #[inline(always)]
    fn inertia_over_radius(&self) -> f64 {
        self.inertia * self.mass * self.radius
    }
}

/// The tangential law of a collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Tangential {
    /// A constant tangential restitution β in `[-1, 1]` (RS-1).
    Constant(f64),
    /// Walton's rule (RS-7): the grains stick with restitution `sticking` (β₀) when the
    /// impact is steep enough, otherwise they slide and the tangential impulse is
    /// `friction` (μ) times the normal one.
    Coulomb {
        /// Coulomb friction coefficient μ ≥ 0.
        friction: f64,
        /// Tangential restitution β₀ of sticking contacts.
        sticking: f64,
    },
}

impl Tangential {
    /// The tangential restitution of one impact with normal restitution `alpha`, normal
    /// and tangential contact speeds `normal_speed = |g_n|` and `tangential_speed = |g_t|`
    /// and `mass_ratio = μ / M_t` (reduced over tangential mass). Walton's rule (RS-7):
    /// `β = min(β₀, -1 + μ_f (1 + α) (μ / M_t) |g_n| / |g_t|)`, the value at which the
    /// tangential impulse `M_t (1 + β) |g_t|` is `μ_f` times the normal one
    /// `μ (1 + α) |g_n|`.
    #[inline(always)]
    pub(crate) fn restitution(
        &self,
        alpha: f64,
        normal_speed: f64,
        tangential_speed: f64,
        mass_ratio: f64,
    ) -> f64 {
        match *self {
            Tangential::Constant(beta) => beta,
            Tangential::Coulomb { friction, sticking } => {
                if tangential_speed > 0.0 {
                    let sliding = -1.0
                        + friction * (1.0 + alpha) * mass_ratio * normal_speed / tangential_speed;
                    sticking.min(sliding)
                } else {
                    sticking
                }
            }
        }
    }
}

/// `ω × n` in `D` dimensions: the velocity of the point at unit lever arm `n` of a grain
/// spinning at `ω` (for a disk `ω_z (-n_y, n_x)`).
#[inline(always)]
pub(crate) fn spin_cross<const D: usize>(w: &Spin, n: &Vector<D>) -> Vector<D> {
    let mut out = Vector::<D>::zero();
    if D == 2 {
        out[0] = -w[2] * n[1];
        out[1] = w[2] * n[0];
    } else {
        out[0] = w[1] * n[2] - w[2] * n[1];
        out[1] = w[2] * n[0] - w[0] * n[2];
        out[2] = w[0] * n[1] - w[1] * n[0];
    }
    out
}

/// `n × J` as a spin vector (only the `z` component for disks).
#[inline(always)]
pub(crate) fn torque_axis<const D: usize>(n: &Vector<D>, j: &Vector<D>) -> Spin {
    if D == 2 {
        [0.0, 0.0, n[0] * j[1] - n[1] * j[0]]
    } else {
        [
            n[1] * j[2] - n[2] * j[1],
            n[2] * j[0] - n[0] * j[2],
            n[0] * j[1] - n[1] * j[0],
        ]
    }
}

/// A pair collision of rough grains (RS-1): grain `i` (`a`, velocity `vi`, spin `wi`)
/// touches grain `j` (`b`, `vj`, `wj`) along the unit normal `n` from `i` to `j`; normal
/// restitution `alpha`, tangential law `tangential`. Updates the four in place and returns
/// the energy dissipated, `μ (1 - α²) g_n²/2 + M_t (1 - β²) |g_t|²/2` (energy units). The
/// caller has checked that the grains approach (`(v_i - v_j)·n > 0`).
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn collide_pair<const D: usize>(
    alpha: f64,
    tangential: Tangential,
    n: &Vector<D>,
    a: &Body,
    b: &Body,
    vi: &mut Vector<D>,
    vj: &mut Vector<D>,
    wi: &mut Spin,
    wj: &mut Spin,
) -> f64 {
    let mut lever = [0.0; 3];
    for k in 0..3 {
        lever[k] = a.radius * wi[k] + b.radius * wj[k];
    }
    let g = (*vi - *vj) + spin_cross(&lever, n);
    let gn = g.dot(n);
    let gt = g.add_scaled(-gn, n);
    let gt2 = gt.norm_squared();
    let mu = a.mass * b.mass / (a.mass + b.mass);
    let mt = 1.0 / (1.0 / mu + 1.0 / (a.inertia * a.mass) + 1.0 / (b.inertia * b.mass));
    let beta = tangential.restitution(alpha, gn.abs(), gt2.sqrt(), mu / mt);
    // Only the tangential impulse has a torque (`n × n = 0`); computing it alone keeps
    // the spins bit for bit unchanged when β = -1.
    let jt = gt * (-mt * (1.0 + beta));
    let j = (*n * (-mu * (1.0 + alpha) * gn)) + jt;
    *vi = vi.add_scaled(1.0 / a.mass, &j);
    *vj = vj.add_scaled(-1.0 / b.mass, &j);
    let t = torque_axis(n, &jt);
    let (ka, kb) = (1.0 / a.inertia_over_radius(), 1.0 / b.inertia_over_radius());
    for k in 0..3 {
        wi[k] += ka * t[k];
        wj[k] += kb * t[k];
    }
    0.5 * mu * (1.0 - alpha * alpha) * gn * gn + 0.5 * mt * (1.0 - beta * beta) * gt2
}

/// A rough grain (`a`, velocity `v`, spin `w`) hits a flat, immovable wall whose outward
/// unit normal seen from the grain is `n` (from the centre to the contact point): RS-1
/// with the wall as a partner of infinite mass, `μ = m`, `M_t = κ m / (1 + κ)`. Normal
/// restitution `alpha` (`e_w`), tangential law `tangential` (`β_w`). Updates `v` and `w`
/// in place and returns the energy dissipated.
#[inline]
pub(crate) fn collide_wall<const D: usize>(
    alpha: f64,
    tangential: Tangential,
    n: &Vector<D>,
    a: &Body,
    v: &mut Vector<D>,
    w: &mut Spin,
) -> f64 {
    let lever = [a.radius * w[0], a.radius * w[1], a.radius * w[2]];
    let g = *v + spin_cross(&lever, n);
    let gn = g.dot(n);
    let gt = g.add_scaled(-gn, n);
    let gt2 = gt.norm_squared();
    let m = a.mass;
    let mt = a.inertia * m / (1.0 + a.inertia);
    let beta = tangential.restitution(alpha, gn.abs(), gt2.sqrt(), m / mt);
    let jt = gt * (-mt * (1.0 + beta));
    let j = (*n * (-m * (1.0 + alpha) * gn)) + jt;
    *v = v.add_scaled(1.0 / m, &j);
    let t = torque_axis(n, &jt);
    let k = 1.0 / a.inertia_over_radius();
    for c in 0..3 {
        w[c] += k * t[c];
    }
    0.5 * m * (1.0 - alpha * alpha) * gn * gn + 0.5 * mt * (1.0 - beta * beta) * gt2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, std_normal, stream};

    const DISK: Body = Body {
        mass: 1.0,
        radius: 0.5,
        inertia: 0.5,
    };

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-14 * (1.0 + b.abs())
    }

    /// Head-on, no spin: only the normal part acts, whatever β.
    #[test]
    fn normal_impact_by_hand() {
        let (mut vi, mut vj) = (Vector([1.0, 0.0]), Vector([-1.0, 0.0]));
        let (mut wi, mut wj) = ([0.0; 3], [0.0; 3]);
        let n = Vector([1.0, 0.0]);
        let lost = collide_pair(
            0.8,
            Tangential::Constant(0.5),
            &n,
            &DISK,
            &DISK,
            &mut vi,
            &mut vj,
            &mut wi,
            &mut wj,
        );
        // g_n = 2, J = -μ (1 + α) g_n = -0.5 * 1.8 * 2 = -1.8.
        assert!(close(vi[0], -0.8) && close(vj[0], 0.8), "{vi:?} {vj:?}");
        assert_eq!((vi[1], vj[1], wi, wj), (0.0, 0.0, [0.0; 3], [0.0; 3]));
        // μ (1 - α²) g_n² / 2 = 0.25 * 0.36 * 4.
        assert!(close(lost, 0.36));
    }

    /// Grazing contact of a moving disk with one at rest, β = 0: the tangential contact
    /// velocity is brought to rest. `M_t = 1 / (2 + 2/κ) = 1/6`, `J = (0, -1/6)`, both
    /// disks turn at `n × J / (κ m R) = (-1/6) / 0.25 = -2/3`.
    #[test]
    fn grazing_impact_by_hand() {
        let (mut vi, mut vj) = (Vector([0.0, 1.0]), Vector([0.0, 0.0]));
        let (mut wi, mut wj) = ([0.0; 3], [0.0; 3]);
        let n = Vector([1.0, 0.0]);
        let lost = collide_pair(
            0.9,
            Tangential::Constant(0.0),
            &n,
            &DISK,
            &DISK,
            &mut vi,
            &mut vj,
            &mut wi,
            &mut wj,
        );
        assert!(close(vi[1], 5.0 / 6.0) && close(vj[1], 1.0 / 6.0));
        assert!(close(wi[2], -2.0 / 3.0) && close(wj[2], -2.0 / 3.0));
        assert_eq!((vi[0], vj[0]), (0.0, 0.0));
        // M_t (1 - β²) |g_t|² / 2 = 1/12.
        assert!(close(lost, 1.0 / 12.0));
    }

    /// Two disks at rest spinning the same way (their surfaces rub at relative speed 1),
    /// perfectly rough (β = 1): the contact velocity is reversed, `J = (0, -1/3)`, each
    /// spin becomes `1 - (1/3)/0.25 = -1/3`, and the energy `I ω² = 1/8` is kept.
    #[test]
    fn spinning_grains_by_hand() {
        let (mut vi, mut vj) = (Vector([0.0, 0.0]), Vector([0.0, 0.0]));
        let (mut wi, mut wj) = ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]);
        let n = Vector([1.0, 0.0]);
        let lost = collide_pair(
            0.7,
            Tangential::Constant(1.0),
            &n,
            &DISK,
            &DISK,
            &mut vi,
            &mut vj,
            &mut wi,
            &mut wj,
        );
        assert!(close(vi[1], -1.0 / 3.0) && close(vj[1], 1.0 / 3.0));
        assert!(close(wi[2], -1.0 / 3.0) && close(wj[2], -1.0 / 3.0));
        assert_eq!(lost, 0.0);
        let energy = 0.5 * (vi.norm_squared() + vj.norm_squared())
            + 0.5 * 0.125 * (wi[2] * wi[2] + wj[2] * wj[2]);
        assert!(close(energy, 0.125), "{energy}");
    }

    /// A sliding disk hits a perfectly rough elastic wall (`β_w = 1`): the contact velocity
    /// `(1, 1)` becomes `(-1, -1)`; `M_t = κ m/(1 + κ) = 1/3`, `J = (-2, -2/3)`,
    /// `v' = (-1, 1/3)`, `ω' = (-2/3)/0.25 = -8/3`, energy 1 kept.
    #[test]
    fn wall_impact_by_hand() {
        let mut v = Vector([1.0, 1.0]);
        let mut w = [0.0; 3];
        let lost = collide_wall(
            1.0,
            Tangential::Constant(1.0),
            &Vector([1.0, 0.0]),
            &DISK,
            &mut v,
            &mut w,
        );
        assert!(close(v[0], -1.0) && close(v[1], 1.0 / 3.0), "{v:?}");
        assert!(close(w[2], -8.0 / 3.0));
        assert_eq!(lost, 0.0);
        let g = v + spin_cross(&[0.0, 0.0, 0.5 * w[2]], &Vector([1.0, 0.0]));
        assert!(close(g[0], -1.0) && close(g[1], -1.0));
        // A smooth wall (β_w = -1) leaves the spin and the tangential velocity alone.
        let mut v = Vector([1.0, 1.0, 0.5]);
        let mut w = [0.3, -0.2, 0.1];
        collide_wall(
            0.5,
            Tangential::Constant(-1.0),
            &Vector([0.0, 0.0, -1.0]),
            &DISK,
            &mut v,
            &mut w,
        );
        assert_eq!((v.0, w), ([1.0, 1.0, -0.25], [0.3, -0.2, 0.1]));
    }

    fn random_vector<const D: usize>(rng: &mut crate::random::Stream) -> Vector<D> {
        let mut v = Vector::<D>::zero();
        for k in 0..D {
            v[k] = std_normal(rng);
        }
        v
    }

    fn random_spin<const D: usize>(rng: &mut crate::random::Stream) -> Spin {
        if D == 2 {
            [0.0, 0.0, std_normal(rng)]
        } else {
            [std_normal(rng), std_normal(rng), std_normal(rng)]
        }
    }

    /// `r × p` as a spin vector (the `z` component in 2D).
    fn moment<const D: usize>(r: &Vector<D>, p: &Vector<D>) -> Spin {
        torque_axis(r, p)
    }

    /// Random collisions of unequal grains: `g_n' = -α g_n`, `g_t' = -β g_t`, momentum and
    /// the angular momentum (orbital about the origin plus spin) conserved for any α, β;
    /// the energy lost is the one returned, none for α = 1, β = ±1; β = -1 leaves the
    /// spins bit for bit untouched.
    fn random_pairs<const D: usize>() {
        let mut rng = stream(11, &[D as u64]);
        for trial in 0..2000 {
            let a = Body {
                mass: 0.5 + rng.random::<f64>(),
                radius: 0.2 + rng.random::<f64>(),
                inertia: 0.05 + 0.6 * rng.random::<f64>(),
            };
            let b = Body {
                mass: 0.5 + rng.random::<f64>(),
                radius: 0.2 + rng.random::<f64>(),
                inertia: 0.05 + 0.6 * rng.random::<f64>(),
            };
            let mut n = random_vector::<D>(&mut rng);
            n = n * (1.0 / n.norm());
            let ri = random_vector::<D>(&mut rng);
            let rj = ri.add_scaled(a.radius + b.radius, &n);
            let (mut vi, mut vj) = (random_vector::<D>(&mut rng), random_vector::<D>(&mut rng));
            let (mut wi, mut wj) = (random_spin::<D>(&mut rng), random_spin::<D>(&mut rng));
            let (alpha, beta) = match trial % 4 {
                0 => (1.0, 1.0),
                1 => (1.0, -1.0),
                2 => (rng.random::<f64>(), -1.0),
                _ => (rng.random::<f64>(), 2.0 * rng.random::<f64>() - 1.0),
            };
            let contact = |vi: &Vector<D>, vj: &Vector<D>, wi: &Spin, wj: &Spin| {
                let mut l = [0.0; 3];
                for k in 0..3 {
                    l[k] = a.radius * wi[k] + b.radius * wj[k];
                }
                (*vi - *vj) + spin_cross(&l, &n)
            };
            let energy = |vi: &Vector<D>, vj: &Vector<D>, wi: &Spin, wj: &Spin| {
                let spin2 = |w: &Spin| w.iter().map(|x| x * x).sum::<f64>();
                0.5 * a.mass * vi.norm_squared()
                    + 0.5 * b.mass * vj.norm_squared()
                    + 0.5 * a.inertia * a.mass * a.radius * a.radius * spin2(wi)
                    + 0.5 * b.inertia * b.mass * b.radius * b.radius * spin2(wj)
            };
            let angular = |vi: &Vector<D>, vj: &Vector<D>, wi: &Spin, wj: &Spin| {
                let (li, lj) = (moment(&ri, &(*vi * a.mass)), moment(&rj, &(*vj * b.mass)));
                let (ia, ib) = (
                    a.inertia * a.mass * a.radius * a.radius,
                    b.inertia * b.mass * b.radius * b.radius,
                );
                let mut l = [0.0; 3];
                for k in 0..3 {
                    l[k] = li[k] + lj[k] + ia * wi[k] + ib * wj[k];
                }
                l
            };
            let g = contact(&vi, &vj, &wi, &wj);
            let (e0, l0, p0) = (
                energy(&vi, &vj, &wi, &wj),
                angular(&vi, &vj, &wi, &wj),
                vi * a.mass + vj * b.mass,
            );
            let (wi0, wj0) = (wi, wj);
            let lost = collide_pair(
                alpha,
                Tangential::Constant(beta),
                &n,
                &a,
                &b,
                &mut vi,
                &mut vj,
                &mut wi,
                &mut wj,
            );
            let g1 = contact(&vi, &vj, &wi, &wj);
            let (gn, gn1) = (g.dot(&n), g1.dot(&n));
            let (gt, gt1) = (g.add_scaled(-gn, &n), g1.add_scaled(-gn1, &n));
            let scale = 1.0 + g.norm();
            assert!(
                (gn1 + alpha * gn).abs() < 1e-13 * scale,
                "{trial}: {gn1} {gn}"
            );
            assert!((gt1 + gt * beta).norm() < 1e-13 * scale, "{trial}");
            let (e1, l1, p1) = (
                energy(&vi, &vj, &wi, &wj),
                angular(&vi, &vj, &wi, &wj),
                vi * a.mass + vj * b.mass,
            );
            assert!(
                (e0 - e1 - lost).abs() < 1e-13 * e0,
                "{trial}: {e0} {e1} {lost}"
            );
            if alpha == 1.0 && beta.abs() == 1.0 {
                assert!(lost.abs() < 1e-14 * e0, "{trial}: {lost}");
            }
            assert!((p1 - p0).norm() < 1e-13 * (1.0 + p0.norm()));
            for k in 0..3 {
                assert!(
                    (l1[k] - l0[k]).abs() < 1e-12 * (1.0 + l0[k].abs()),
                    "{trial}"
                );
            }
            if beta == -1.0 {
                assert_eq!((wi, wj), (wi0, wj0), "{trial}");
            }
        }
    }

    #[test]
    fn random_pair_collisions_conserve_what_they_must_2d() {
        random_pairs::<2>();
    }

    #[test]
    fn random_pair_collisions_conserve_what_they_must_3d() {
        random_pairs::<3>();
    }

    /// Walton's rule in its limits: infinite friction is the constant β₀; no friction is
    /// smooth (β = -1); in between, a sliding contact has a tangential impulse of exactly
    /// μ times the normal one.
    #[test]
    fn coulomb_rule_limits() {
        let mut rng = stream(12, &[]);
        for _ in 0..200 {
            let n = Vector([1.0, 0.0, 0.0]);
            let v0 = random_vector::<3>(&mut rng);
            let v0 = Vector([v0[0].abs() + 0.1, v0[1], v0[2]]);
            let w0 = random_spin::<3>(&mut rng);
            let run = |t: Tangential| {
                let (mut vi, mut vj, mut wi, mut wj) = (v0, Vector::zero(), w0, [0.0; 3]);
                collide_pair(0.8, t, &n, &DISK, &DISK, &mut vi, &mut vj, &mut wi, &mut wj);
                (vi, wi, wj)
            };
            let sticking = run(Tangential::Constant(0.4));
            let stuck = run(Tangential::Coulomb {
                friction: 1e12,
                sticking: 0.4,
            });
            assert!((sticking.0 - stuck.0).norm() < 1e-12);
            let smooth = run(Tangential::Constant(-1.0));
            let frictionless = run(Tangential::Coulomb {
                friction: 0.0,
                sticking: 0.4,
            });
            assert_eq!(smooth.0.0, frictionless.0.0);
            assert_eq!((frictionless.1, frictionless.2), (w0, [0.0; 3]));
            // Small friction: always sliding, |J_t| = μ |J_n|.
            let (vi, _, _) = run(Tangential::Coulomb {
                friction: 0.001,
                sticking: 0.4,
            });
            let j = (vi - v0) * DISK.mass;
            let jn = j[0].abs();
            let jt = (j[1] * j[1] + j[2] * j[2]).sqrt();
            assert!((jt - 0.001 * jn).abs() < 1e-12 * jn, "{jt} {jn}");
        }
    }
}
