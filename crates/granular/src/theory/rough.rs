//! Kinetic theory of a dilute gas of rough inelastic hard disks or spheres (constant normal
//! restitution α, tangential restitution β, reduced moment of inertia κ) in the Maxwellian
//! approximation: the translational and rotational cooling rates (RS-2, RS-3), the
//! temperature ratio and cooling rate of the homogeneous cooling state (RS-4, RS-5) and the
//! temperature ratio of the gas heated by white noise on the translational velocities
//! (RS-6).
//!
//! Disks and spheres are written alike, with `d_t = D` translational and `d_r = D(D-1)/2`
//! rotational degrees of freedom (`d_t = 2`, `d_r = 1` for disks; `d_t = d_r = 3` for
//! spheres), as A. Megías and A. Santos do (arXiv 2303.00057; earlier
//! M. Huthmann and A. Zippelius, Phys. Rev. E 56, R6275 (1997); S. Luding, M. Huthmann,
//! S. McNamara and A. Zippelius, Phys. Rev. E 58, 3416 (1998) for spheres; S. McNamara and
//! S. Luding, Phys. Rev. E 58, 2247 (1998) for disks; A. Santos, G. M. Kremer and M. dos
//! Santos, arXiv 1009.6180, for the white-noise state). The translational temperature is
//! `T_t = m <|v - u|²> / d_t`, the rotational one `T_r = I <|ω|²> / d_r`, their ratio
//! `θ = T_r / T_t`. Rates are per unit time, written as multiples of the collision
//! frequency `ν` of a Maxwellian gas at `T_t` ([`crate::theory::haff::collision_frequency`]).
//! Every formula is derived in `docs/rough.md`; the collisional averages behind RS-2 and
//! RS-3 are checked below against a Monte Carlo average of the collision rule RS-1
//! ([`crate::collision_law::rough`]) over Maxwellian pairs.

pub mod sonine;

pub use sonine::SonineState;

/// A homogeneous state of a rough gas with a fixed temperature ratio.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RoughState {
    /// The homogeneous cooling state (free, or held by rescaling): RS-4, RS-5, RS-8.
    Cooling,
    /// The gas heated by white noise on the translational velocities: RS-6, RS-9.
    WhiteNoise,
}

/// The approximation of the velocity distribution a theory value is taken in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Approximation {
    /// Both distributions Maxwellian (RS-4 to RS-6).
    Maxwell,
    /// The first Sonine approximation (RS-8, RS-9).
    Sonine,
}

/// One species of rough grains in `dimension` dimensions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughGas {
    /// `D`: 2 (disks) or 3 (spheres).
    pub dimension: usize,
    /// Normal restitution α in `[0, 1]`.
    pub normal_restitution: f64,
    /// Tangential restitution β in `[-1, 1]` (`-1` smooth, `+1` perfectly rough).
    pub tangential_restitution: f64,
    /// Reduced moment of inertia `κ = 4 I / (m σ²)` (1/2 uniform disk, 2/5 uniform sphere).
    pub inertia: f64,
}

impl RoughGas {
    /// `d_t = D`.
    pub fn translational_dof(&self) -> f64 {
        self.dimension as f64
    }

    /// `d_r = D (D - 1) / 2`: 1 for disks, 3 for spheres.
    pub fn rotational_dof(&self) -> f64 {
        crate::collision_law::rough::rotational_dof(self.dimension) as f64
    }

    /// `η_t = κ (1 + β) / (2 (1 + κ))`: the fraction of the tangential contact velocity a
    /// grain of a colliding pair loses, `v_1' = v_1 - η_n g_n n - η_t g_t` with
    /// `η_n = (1 + α)/2` (RS-1 for equal grains).
    pub fn tangential_factor(&self) -> f64 {
        let k = self.inertia;
        k * (1.0 + self.tangential_restitution) / (2.0 * (1.0 + k))
    }

    /// The three coefficients of the Maxwellian energy balance (RS-2, RS-3):
    /// `a = (1 - α²)/2 + (d_t - 1) η_t (1 - η_t)`, `b = (d_t - 1) η_t²/κ`,
    /// `c = (d_t - 1) (η_t/κ) (1 - η_t/κ)`.
    fn coefficients(&self) -> (f64, f64, f64) {
        let alpha = self.normal_restitution;
        let eta = self.tangential_factor();
        let q = eta / self.inertia;
        let tangential = self.translational_dof() - 1.0;
        let a = 0.5 * (1.0 - alpha * alpha) + tangential * eta * (1.0 - eta);
        let b = tangential * eta * q;
        let c = tangential * q * (1.0 - q);
        (a, b, c)
    }

    /// RS-2: the translational cooling rate `ζ_t = -d ln T_t / dt` over the collision
    /// frequency `ν(T_t)`, at temperature ratio `theta = T_r / T_t`:
    /// `ζ_t / ν = (2 / d_t) [ (1 - α²)/2 + (d_t - 1) η_t (1 - η_t) - (d_t - 1) (η_t²/κ) θ ]`.
    pub fn translational_cooling_rate(&self, theta: f64) -> f64 {
        let (a, b, _) = self.coefficients();
        2.0 / self.translational_dof() * (a - b * theta)
    }

    /// RS-3: the rotational cooling rate `ζ_r = -d ln T_r / dt` over `ν(T_t)`:
    /// `ζ_r / ν = (2 / d_r) (d_t - 1) [ (η_t/κ) (1 - η_t/κ) - (η_t²/κ) / θ ]`
    /// (`theta > 0`).
    pub fn rotational_cooling_rate(&self, theta: f64) -> f64 {
        let (_, b, c) = self.coefficients();
        2.0 / self.rotational_dof() * (c - b / theta)
    }

    /// The cooling rate of the total temperature `T = (d_t T_t + d_r T_r)/(d_t + d_r)`
    /// over `ν(T_t)`: `ζ / ν = (d_t ζ_t + d_r θ ζ_r) / (ν (d_t + d_r θ))`.
    pub fn total_cooling_rate(&self, theta: f64) -> f64 {
        let (dt, dr) = (self.translational_dof(), self.rotational_dof());
        (dt * self.translational_cooling_rate(theta)
            + dr * theta * self.rotational_cooling_rate(theta))
            / (dt + dr * theta)
    }

    /// RS-4: the temperature ratio `θ = T_r / T_t` of the homogeneous cooling state, where
    /// both temperatures cool at the same rate (`ζ_t = ζ_r`): the positive root of
    /// `d_r b θ² + (d_t c - d_r a) θ - d_t b = 0`, i.e. `θ = h + sqrt(h² + d_t/d_r)` with
    /// `h = (d_r a - d_t c) / (2 d_r b)` (coefficients of RS-2, RS-3). `None` for smooth
    /// grains (β = -1), whose rotation is decoupled.
    pub fn cooling_temperature_ratio(&self) -> Option<f64> {
        let (a, b, c) = self.coefficients();
        if b <= 0.0 {
            return None;
        }
        let (dt, dr) = (self.translational_dof(), self.rotational_dof());
        let h = (dr * a - dt * c) / (2.0 * dr * b);
        let root = (h * h + dt / dr).sqrt();
        // Either form of the same root, free of cancellation.
        Some(if h >= 0.0 {
            h + root
        } else {
            dt / dr / (root - h)
        })
    }

    /// RS-5: the cooling rate of the homogeneous cooling state over `ν(T_t)`,
    /// `ζ / ν = ζ_t(θ_HCS) / ν` (RS-2 at RS-4; every temperature cools at this rate, and
    /// since `ν ~ sqrt(T_t)`, `T_t(t) = T_t(0) / (1 + ζ(0) t / 2)²`). For smooth grains
    /// the translational rate `(1 - α²)/d_t`.
    pub fn cooling_rate(&self) -> f64 {
        match self.cooling_temperature_ratio() {
            Some(theta) => self.translational_cooling_rate(theta),
            None => self.translational_cooling_rate(0.0),
        }
    }

    /// RS-6: the temperature ratio of the steady state heated by white noise acting on the
    /// translational velocities only: the rotational temperature is steady when
    /// `ζ_r = 0`, `θ = κ (1 + β) / (1 + 2κ - β)`, the same for disks and spheres and
    /// independent of α. (`0` for smooth grains, which never spin up.)
    pub fn white_noise_temperature_ratio(&self) -> f64 {
        let (k, b) = (self.inertia, self.tangential_restitution);
        k * (1.0 + b) / (1.0 + 2.0 * k - b)
    }

    /// The steady translational temperature of the white-noise driven gas: noise of
    /// strength `ξ0² = strength` on every translational velocity component of `particles`
    /// grains of mass `mass` injects `(d_t/2) m ξ0² (N - 1)` per unit time (the mean kick
    /// is removed), which balances the collisional loss `(N/2) d_t ζ_t T_t` (the rotational
    /// loss vanishes in the steady state); since `ζ_t = ν(1) sqrt(T_t) (ζ_t/ν)(θ_WN)`,
    /// `T_t = (m ξ0² (1 - 1/N) / (ν(1) (ζ_t/ν)(θ_WN)))^(2/3)`, with
    /// `collision_frequency_at_unit_temperature = ν(T_t = 1)`.
    pub fn white_noise_temperature(
        &self,
        strength: f64,
        mass: f64,
        particles: usize,
        collision_frequency_at_unit_temperature: f64,
    ) -> f64 {
        let heating = mass * strength * (1.0 - 1.0 / particles as f64);
        let rate = self.translational_cooling_rate(self.white_noise_temperature_ratio());
        (heating / (collision_frequency_at_unit_temperature * rate)).powf(2.0 / 3.0)
    }

    /// The temperature ratio `θ = T_r / T_t` of `state` in `approximation`: RS-4 or RS-6
    /// (Maxwellian), RS-8 or RS-9 (Sonine). `None` for smooth grains in the cooling state
    /// or where the Sonine equations have no solution.
    pub fn temperature_ratio(
        &self,
        state: RoughState,
        approximation: Approximation,
    ) -> Option<f64> {
        match approximation {
            Approximation::Maxwell => match state {
                RoughState::Cooling => self.cooling_temperature_ratio(),
                RoughState::WhiteNoise => Some(self.white_noise_temperature_ratio()),
            },
            Approximation::Sonine => self.sonine_state(state).map(|s| s.temperature_ratio),
        }
    }

    /// The cooling rate of the total energy per collision of a grain, `ζ/ν`, in `state`:
    /// Maxwellian, `total_cooling_rate` at RS-4 (= RS-5) or at RS-6 (`d_t ζ_t/(d_t + d_r θ)`,
    /// the rotational loss vanishing); Sonine, the same with the cumulants of RS-8/RS-9,
    /// divided by the Sonine collision frequency over the Maxwellian one (`1 - a20/16`), as
    /// a rate measured per collision is. `None` where [`Self::temperature_ratio`] is.
    pub fn reduced_cooling_rate(
        &self,
        state: RoughState,
        approximation: Approximation,
    ) -> Option<f64> {
        match approximation {
            Approximation::Maxwell => self
                .temperature_ratio(state, approximation)
                .map(|theta| self.total_cooling_rate(theta)),
            Approximation::Sonine => self
                .sonine_state(state)
                .map(|s| s.total_cooling_rate / s.collision_frequency_factor),
        }
    }

    /// RS-8 or RS-9.
    pub fn sonine_state(&self, state: RoughState) -> Option<SonineState> {
        match state {
            RoughState::Cooling => self.sonine_cooling_state(),
            RoughState::WhiteNoise => self.sonine_white_noise_state(),
        }
    }

    /// The two temperatures of a freely cooling gas at the `times` (ascending, from 0),
    /// from `T_t(0) = translational`, `T_r(0) = rotational`: RS-2 and RS-3 integrated,
    /// `dT_t/dt = -ζ_t T_t`, `dT_r/dt = -ζ_r T_r` with `ν = ν(1) sqrt(T_t)` and
    /// `collision_frequency_at_unit_temperature = ν(1)` (classical fourth-order Runge-Kutta
    /// in steps of at most 1/200 of the current collision time). Returns `(T_t, T_r)` at each
    /// time.
    pub fn evolve(
        &self,
        translational: f64,
        rotational: f64,
        collision_frequency_at_unit_temperature: f64,
        times: &[f64],
    ) -> Vec<(f64, f64)> {
        let (a, b, c) = self.coefficients();
        let (dt_dof, dr_dof) = (self.translational_dof(), self.rotational_dof());
        let nu1 = collision_frequency_at_unit_temperature;
        let rhs = |s: (f64, f64)| {
            let nu = nu1 * s.0.max(0.0).sqrt();
            (
                -nu * 2.0 / dt_dof * (a * s.0 - b * s.1),
                -nu * 2.0 / dr_dof * (c * s.1 - b * s.0),
            )
        };
        let mut state = (translational, rotational);
        let mut now = 0.0;
        let mut out = Vec::with_capacity(times.len());
        for &t in times {
            while now < t {
                let nu = nu1 * state.0.max(f64::MIN_POSITIVE).sqrt();
                let h = (t - now).min(0.005 / nu);
                let k1 = rhs(state);
                let k2 = rhs((state.0 + 0.5 * h * k1.0, state.1 + 0.5 * h * k1.1));
                let k3 = rhs((state.0 + 0.5 * h * k2.0, state.1 + 0.5 * h * k2.1));
                let k4 = rhs((state.0 + h * k3.0, state.1 + h * k3.1));
                state.0 += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                state.1 += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
                now += h;
            }
            out.push(state);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision_law::rough::{Body, Tangential, collide_pair};
    use crate::random::{std_normal, stream};
    use crate::vector::Vector;

    fn gas(dimension: usize, alpha: f64, beta: f64, inertia: f64) -> RoughGas {
        RoughGas {
            dimension,
            normal_restitution: alpha,
            tangential_restitution: beta,
            inertia,
        }
    }

    /// Limits by hand: perfectly rough elastic grains keep equipartition (θ = 1, no
    /// cooling); the white-noise ratio is 1 at β = 1 and 0 at β = -1; smooth grains cool
    /// at `(1 - α²)/d_t` (Haff: `ζ/ω = (1 - e²)/D`, `theory::haff::cooling_rate`).
    #[test]
    fn limits_by_hand() {
        for (d, k) in [(2, 0.5), (3, 0.4), (3, 2.0 / 3.0), (2, 1.0)] {
            let g = gas(d, 1.0, 1.0, k);
            let theta = g.cooling_temperature_ratio().unwrap();
            assert!((theta - 1.0).abs() < 1e-14, "{d} {k} {theta}");
            assert!(g.cooling_rate().abs() < 1e-15);
            assert!(g.total_cooling_rate(0.3).abs() < 1e-15);
            assert!((g.white_noise_temperature_ratio() - 1.0).abs() < 1e-15);
            let smooth = gas(d, 0.8, -1.0, k);
            assert_eq!(smooth.cooling_temperature_ratio(), None);
            assert_eq!(smooth.white_noise_temperature_ratio(), 0.0);
            assert!((smooth.cooling_rate() - 0.36 / d as f64).abs() < 1e-15);
        }
        // RS-6 at κ = 2/5, β = 0: 0.4 / 1.8.
        assert!((gas(3, 0.5, 0.0, 0.4).white_noise_temperature_ratio() - 0.4 / 1.8).abs() < 1e-15);
        // The HCS ratio makes both rates equal.
        for (d, a, b, k) in [(2, 0.9, 0.0, 0.5), (3, 0.7, -0.5, 0.4), (3, 0.5, 1.0, 0.4)] {
            let g = gas(d, a, b, k);
            let theta = g.cooling_temperature_ratio().unwrap();
            let (zt, zr) = (
                g.translational_cooling_rate(theta),
                g.rotational_cooling_rate(theta),
            );
            assert!((zt - zr).abs() < 1e-13, "{zt} {zr}");
            assert!((g.total_cooling_rate(theta) - zt).abs() < 1e-13);
            assert!((g.cooling_rate() - zt).abs() < 1e-15);
        }
    }

    /// The evolution approaches the HCS ratio and, once there, Haff's law with RS-5.
    #[test]
    fn evolution_reaches_the_cooling_state() {
        let g = gas(3, 0.9, 0.5, 0.4);
        let times: Vec<f64> = (0..=2000).map(|k| k as f64 * 0.5).collect();
        let path = g.evolve(1.0, 1.0, 1.0, &times);
        let (tt, tr) = path[1500];
        let theta = g.cooling_temperature_ratio().unwrap();
        assert!(
            (tr / tt - theta).abs() < 1e-6 * theta,
            "{} {theta}",
            tr / tt
        );
        // From t = 750 to 1000: T_t(1000) = T_t(750) / (1 + ζ(750) 250 / 2)².
        let zeta = g.cooling_rate() * tt.sqrt();
        let haff = tt / (1.0 + 0.5 * zeta * 250.0).powi(2);
        assert!(
            (path[2000].0 - haff).abs() < 1e-6 * haff,
            "{} {haff}",
            path[2000].0
        );
    }

    /// The steady white-noise temperature balances heating and loss.
    #[test]
    fn white_noise_temperature_balances() {
        let g = gas(2, 0.8, 0.3, 0.5);
        let t = g.white_noise_temperature(2.0, 1.5, 100, 0.7);
        let loss =
            0.7 * t.sqrt() * g.translational_cooling_rate(g.white_noise_temperature_ratio()) * t;
        assert!((loss - 1.5 * 2.0 * 0.99).abs() < 1e-12, "{loss}");
    }

    /// RS-2 and RS-3 against a Monte Carlo average of the collision rule RS-1 over the pairs
    /// of grains that collide in a gas whose velocities and angular velocities are
    /// Maxwellian at `T_t` and `T_r`: the normal `n = e_1` (the gas is isotropic), the
    /// normal relative velocity drawn from the collision-weighted density
    /// `∝ g_n exp(-g_n² / 2s²)`, `s² = 2 T_t/m` (`g_n = s sqrt(-2 ln U)`), every other
    /// relative and centre-of-mass component and every spin component Gaussian. The mean
    /// energy changes per collision are `<ΔE_t> = -d_t (ζ_t/ν) T_t` and
    /// `<ΔE_r> = -d_r (ζ_r/ν) T_r` (a collision of a pair happens `N ν / 2` times per unit
    /// time). Tolerance: four standard errors of the sample means, 10⁶ pairs per case
    /// (about 0.3 % of the rates).
    fn monte_carlo_moments<const D: usize>(alpha: f64, beta: f64, kappa: f64, theta: f64) {
        let g = gas(D, alpha, beta, kappa);
        let (m, radius, tt) = (1.3, 0.37, 0.8);
        let tr = theta * tt;
        let body = Body {
            mass: m,
            radius,
            inertia: kappa,
        };
        let inertia = kappa * m * radius * radius;
        let mut rng = stream(
            2026,
            &[
                D as u64,
                (alpha * 100.0) as u64,
                (beta * 100.0 + 100.0) as u64,
            ],
        );
        let samples = 1_000_000;
        let mut n = Vector::<D>::zero();
        n[0] = 1.0;
        let s = (2.0 * tt / m).sqrt();
        let mut sums = [[0.0f64; 2]; 2]; // [Σ ΔE, Σ ΔE²] for translation, rotation
        for _ in 0..samples {
            let mut rel = Vector::<D>::zero();
            let mut centre = Vector::<D>::zero();
            let u: f64 = crate::random::open01(&mut rng);
            rel[0] = s * (-2.0 * u.ln()).sqrt();
            for k in 0..D {
                if k > 0 {
                    rel[k] = s * std_normal(&mut rng);
                }
                centre[k] = (0.5 * tt / m).sqrt() * std_normal(&mut rng);
            }
            let mut vi = centre.add_scaled(0.5, &rel);
            let mut vj = centre.add_scaled(-0.5, &rel);
            let mut wi = [0.0; 3];
            let mut wj = [0.0; 3];
            let spread = (tr / inertia).sqrt();
            for k in (if D == 2 { 2 } else { 0 })..3 {
                wi[k] = std_normal(&mut rng) * spread;
                wj[k] = std_normal(&mut rng) * spread;
            }
            let spin2 =
                |a: &[f64; 3], b: &[f64; 3]| a.iter().chain(b.iter()).map(|x| x * x).sum::<f64>();
            let et0 = 0.5 * m * (vi.norm_squared() + vj.norm_squared());
            let er0 = 0.5 * inertia * spin2(&wi, &wj);
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
            let det = 0.5 * m * (vi.norm_squared() + vj.norm_squared()) - et0;
            let der = 0.5 * inertia * spin2(&wi, &wj) - er0;
            for (acc, de) in sums.iter_mut().zip([det, der]) {
                acc[0] += de;
                acc[1] += de * de;
            }
        }
        let nf = samples as f64;
        let theory = [
            -g.translational_dof() * g.translational_cooling_rate(theta) * tt,
            -g.rotational_dof() * g.rotational_cooling_rate(theta) * tr,
        ];
        for (k, acc) in sums.iter().enumerate() {
            let mean = acc[0] / nf;
            let err = ((acc[1] / nf - mean * mean) / nf).sqrt();
            assert!(
                (mean - theory[k]).abs() < 4.0 * err,
                "D = {D}, α = {alpha}, β = {beta}, κ = {kappa}, θ = {theta}, {}: MC {mean} ± {err}, theory {}",
                ["translation", "rotation"][k],
                theory[k]
            );
        }
    }

    /// The collision frequency the rates are written in: `ν = n σ^(D-1) Ω_D <(g·n)⁺>` with
    /// `<(g·n)⁺> = s / sqrt(2π)` for a Gaussian relative velocity of variance `s² = 2T/m`
    /// per component (`docs/rough.md`), against `theory::haff::collision_frequency`.
    #[test]
    fn collision_frequency_is_the_one_of_the_rates() {
        let (t, m): (f64, f64) = (0.8, 1.3);
        let mean_normal = (2.0 * t / m).sqrt() / (2.0 * std::f64::consts::PI).sqrt();
        for (d, solid_angle) in [
            (2, 2.0 * std::f64::consts::PI),
            (3, 4.0 * std::f64::consts::PI),
        ] {
            let nu = crate::theory::haff::collision_frequency(d, 1.0, 0.5, t, m, 1.0);
            assert!((nu - solid_angle * mean_normal).abs() < 1e-14 * nu, "{d}");
        }
    }

    #[test]
    fn collisional_moments_match_a_monte_carlo_average_of_the_rule() {
        for (alpha, beta, kappa, theta) in [
            (0.9, 0.0, 0.4, 0.7),
            (0.7, -0.5, 0.4, 2.0),
            (0.5, 1.0, 2.0 / 3.0, 0.3),
            (0.9, 0.5, 0.1, 1.0),
        ] {
            monte_carlo_moments::<3>(alpha, beta, kappa, theta);
        }
        for (alpha, beta, kappa, theta) in [
            (0.9, 0.0, 0.5, 0.7),
            (0.7, -0.5, 0.5, 2.0),
            (0.5, 1.0, 1.0, 0.3),
            (0.9, 0.5, 0.25, 1.0),
        ] {
            monte_carlo_moments::<2>(alpha, beta, kappa, theta);
        }
    }
}
