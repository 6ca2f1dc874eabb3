//! How the temperature and the Sonine coefficient `a2` of a homogeneous granular gas of
//! smooth hard grains relax in time, heated by white noise of strength `ξ0²` (or cooling
//! freely, `ξ0² = 0`), in the first Sonine approximation: KT-14 and KT-15.
//!
//! This is the theory behind two memory effects of driven granular gases: the **Kovacs
//! effect** (A. Prados and E. Trizac, Phys. Rev. Lett. 112, 198001 (2014)): a gas brought
//! to the steady temperature of a new noise strength, but with the `a2` of another history,
//! first leaves that temperature and comes back (a hump); and the **Mpemba effect**
//! (A. Lasanta, F. Vega Reyes, A. Prados and A. Santos, Phys. Rev. Lett. 119, 148001
//! (2017)): of two samples cooled by the same thermostat, the initially hotter one, with a
//! larger `a2`, cools faster and crosses the other. Both papers write these two equations
//! (their kinetic coefficients for spheres, here for `D` = 2 and 3).
//!
//! With `c = v / v_T`, `v_T = sqrt(2T/m)`, the collisional moments of the Boltzmann
//! operator for a velocity distribution `f_M (1 + a2 S_2(c²))`, linear in `a2` (T. P. C. van
//! Noije and M. H. Ernst, Granular Matter 1, 57 (1998); N. V. Brilliantov and T. Pöschel,
//! *Kinetic Theory of Granular Gases* (2004), chapter 7) are, in units of `ω / 2` (KT-5's
//! collision frequency per grain):
//!
//! * `μ2 = (1 - α²)(1 + 3 a2 / 16)` (the cooling rate KT-8: `ζ = (ω / D) μ2`);
//! * `μ4 = (1 - α²)(D + 3/2 + α²) + B2 a2`, `B2 = (3/32)(10D + 39 + 10α²)(1 - α²) + (D - 1)(1 + α)`.
//!
//! The white noise adds `D ξ0²` to `d<v²>/dt` and `2 (D+2) ξ0² <v²>` to `d<v⁴>/dt`
//! (a velocity diffusion of coefficient `ξ0² / 2`); `<v⁴> = D (D+2) (T/m)² (1 + a2)`. Then
//!
//! * KT-14: `dT/dt = m ξ0² - ζ T`;
//! * KT-15: `da2/dt = -(2 m ξ0² / T) a2 + (2 ω / (D (D+2))) [(D+2)(1 - α²)(1 + 19 a2/16) - μ4]`,
//!
//! with `(1 + a2) μ2` linearised in the bracket. Without noise the fixed point of the
//! bracket is the cooling state's `a2` of KT-10 exactly; with noise the fixed point is
//! KT-12's `a2` and KT-13's temperature up to terms of order `a2²` (which both drop).
//! The engines subtract the mean kick from every grain, which leaves each grain a kick
//! variance `ξ0² (1 - 1/N)`: [`SonineRelaxation::new`] takes `N` for that factor.

use super::kinetic;

/// A homogeneous gas of smooth grains of one species, heated by white noise, whose
/// temperature and `a2` relax by KT-14 and KT-15.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SonineRelaxation {
    /// Spatial dimension, 2 or 3.
    pub dimension: usize,
    /// Normal restitution α, in `[0, 1]`.
    pub restitution: f64,
    /// Grain mass.
    pub mass: f64,
    /// KT-5's collision frequency per grain at unit temperature, `ω(T) = ω(1) sqrt(T)`
    /// (1/time; with the Enskog factor χ where the gas is dense).
    pub collision_frequency_at_unit_temperature: f64,
    /// The part of the kick variance each grain keeps once the mean kick is subtracted,
    /// `1 - 1/N` (1 for infinitely many grains).
    pub kick_fraction: f64,
}

/// The state of [`SonineRelaxation`]: temperature (energy units, `k_B = 1`) and `a2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SonineState {
    /// Granular temperature `T = m <|v - u|²> / D`.
    pub temperature: f64,
    /// First Sonine coefficient `a2 = D/(D+2) <c⁴>/<c²>² - 1`.
    pub a2: f64,
}

impl SonineRelaxation {
    /// The gas of `particles` grains (`None`: infinitely many) of `mass` and `radius` at
    /// `number_density`, with contact value `chi` (1 for a dilute gas or DSMC without
    /// Enskog's factor) and restitution α.
    pub fn new(
        dimension: usize,
        restitution: f64,
        mass: f64,
        number_density: f64,
        radius: f64,
        chi: f64,
        particles: Option<usize>,
    ) -> SonineRelaxation {
        SonineRelaxation {
            dimension,
            restitution,
            mass,
            collision_frequency_at_unit_temperature: kinetic::collision_frequency(
                dimension,
                number_density,
                radius,
                1.0,
                mass,
                chi,
            ),
            kick_fraction: particles.map_or(1.0, |n| 1.0 - 1.0 / n.max(1) as f64),
        }
    }

    /// KT-5's collision frequency at temperature `t`.
    fn omega(&self, t: f64) -> f64 {
        self.collision_frequency_at_unit_temperature * t.max(0.0).sqrt()
    }

    /// KT-14 and KT-15: `(dT/dt, da2/dt)` of `state` under white noise of strength
    /// `strength = ξ0²` (length²/time³; 0 for free cooling).
    pub fn rates(&self, state: SonineState, strength: f64) -> (f64, f64) {
        let d = self.dimension as f64;
        let e = self.restitution;
        let a = state.a2;
        let t = state.temperature;
        let heating = self.mass * strength * self.kick_fraction;
        let omega = self.omega(t);
        let inelastic = 1.0 - e * e;
        let zeta = super::haff::sonine_cooling_rate(self.dimension, e, omega, a);
        let b2 = 3.0 / 32.0 * (10.0 * d + 39.0 + 10.0 * e * e) * inelastic + (d - 1.0) * (1.0 + e);
        let mu4 = inelastic * (d + 1.5 + e * e) + b2 * a;
        let bracket = (d + 2.0) * inelastic * (1.0 + 19.0 * a / 16.0) - mu4;
        let dt = heating - zeta * t;
        let da = -2.0 * heating / t * a + 2.0 * omega / (d * (d + 2.0)) * bracket;
        (dt, da)
    }

    /// The state after `duration` under `strength` from `state` (KT-14, KT-15 integrated
    /// by the classical fourth-order Runge-Kutta rule, with steps of at most a hundredth of
    /// the mean free time and of the heating time `T / (m ξ0²)`).
    pub fn evolve(&self, state: SonineState, strength: f64, duration: f64) -> SonineState {
        let mut s = state;
        let mut left = duration.max(0.0);
        while left > 0.0 {
            let rate = self.omega(s.temperature)
                + self.mass * strength * self.kick_fraction / s.temperature.max(1e-300);
            let h = left.min(0.01 / rate.max(1e-300));
            s = self.runge_kutta(s, strength, h);
            left -= h;
        }
        s
    }

    fn runge_kutta(&self, s: SonineState, strength: f64, h: f64) -> SonineState {
        let at = |s: SonineState, k: (f64, f64), f: f64| SonineState {
            temperature: s.temperature + f * k.0,
            a2: s.a2 + f * k.1,
        };
        let k1 = self.rates(s, strength);
        let k2 = self.rates(at(s, k1, h / 2.0), strength);
        let k3 = self.rates(at(s, k2, h / 2.0), strength);
        let k4 = self.rates(at(s, k3, h), strength);
        SonineState {
            temperature: s.temperature + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0),
            a2: s.a2 + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1),
        }
    }

    /// The states at `times` (increasing, from 0) of a protocol that starts from
    /// `initial` at time 0 and whose noise strength is `strengths[k].1` from time
    /// `strengths[k].0` on (the first entry at time 0; increasing times).
    pub fn trajectory(
        &self,
        initial: SonineState,
        strengths: &[(f64, f64)],
        times: &[f64],
    ) -> Vec<SonineState> {
        let mut out = Vec::with_capacity(times.len());
        let mut s = initial;
        let mut now = 0.0;
        let strength_at = |t: f64| {
            strengths
                .iter()
                .rev()
                .find(|(from, _)| *from <= t)
                .map_or(0.0, |(_, x)| *x)
        };
        for &target in times {
            // Stop at every change of strength on the way.
            for &(from, _) in strengths {
                if from > now && from < target {
                    s = self.evolve(s, strength_at(now), from - now);
                    now = from;
                }
            }
            if target > now {
                s = self.evolve(s, strength_at(now), target - now);
                now = target;
            }
            out.push(s);
        }
        out
    }

    /// The noise strength `ξ0²` whose steady temperature is `temperature` (KT-13 solved
    /// for `ξ0²`, at KT-12's `a2`).
    pub fn strength_for_temperature(&self, temperature: f64) -> f64 {
        let a = super::sonine::white_noise_a2(self.dimension, self.restitution);
        let omega = self.omega(temperature);
        let zeta = super::haff::sonine_cooling_rate(self.dimension, self.restitution, omega, a);
        zeta * temperature / (self.mass * self.kick_fraction)
    }

    /// The time at which the temperature, relaxing from `state` under `strength`, first
    /// reaches `temperature` (`None` if it does not within `limit`): the waiting time of
    /// the Kovacs protocol. Found by bisection on [`SonineRelaxation::evolve`] to a
    /// relative precision of `1e-10`.
    pub fn time_to_reach(
        &self,
        state: SonineState,
        strength: f64,
        temperature: f64,
        limit: f64,
    ) -> Option<f64> {
        let above = state.temperature > temperature;
        let crossed = |s: SonineState| (s.temperature > temperature) != above;
        // Bracket the crossing by doubling, then bisect.
        let mut step = 1.0 / self.omega(state.temperature).max(1e-300);
        let (mut lo, mut s_lo) = (0.0, state);
        loop {
            let hi = (lo + step).min(limit);
            let s_hi = self.evolve(s_lo, strength, hi - lo);
            if crossed(s_hi) {
                let (mut a, mut b, mut s_a) = (lo, hi, s_lo);
                while b - a > 1e-10 * b {
                    let mid = 0.5 * (a + b);
                    let s_mid = self.evolve(s_a, strength, mid - a);
                    if crossed(s_mid) {
                        b = mid;
                    } else {
                        a = mid;
                        s_a = s_mid;
                    }
                }
                return Some(0.5 * (a + b));
            }
            if hi >= limit {
                return None;
            }
            lo = hi;
            s_lo = s_hi;
            step *= 2.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::sonine;

    fn gas(d: usize, e: f64) -> SonineRelaxation {
        SonineRelaxation::new(d, e, 1.0, 1000.0, 0.005, 1.0, None)
    }

    /// Free cooling in scaled variables: the bracket of KT-15 vanishes at KT-10's `a2`.
    #[test]
    fn the_free_cooling_fixed_point_is_kt10() {
        for d in [2, 3] {
            for e in [0.2, 0.5, 0.8, 0.95] {
                let a = sonine::cooling_a2_first(d, e);
                let g = gas(d, e);
                // da2/dt without noise, at T = 1.
                let (_, da) = g.rates(
                    SonineState {
                        temperature: 1.0,
                        a2: a,
                    },
                    0.0,
                );
                assert!(da.abs() < 1e-12, "d {d} e {e}: {da}");
            }
        }
    }

    /// With noise, the relaxation ends at KT-13's temperature and KT-12's `a2`, up to
    /// the terms of order `a2²` that both drop.
    #[test]
    fn the_heated_gas_relaxes_to_kt12_and_kt13() {
        for d in [2, 3] {
            for e in [0.3, 0.7, 0.9] {
                let g = gas(d, e);
                let strength = g.strength_for_temperature(2.0);
                let end = g.evolve(
                    SonineState {
                        temperature: 0.5,
                        a2: 0.0,
                    },
                    strength,
                    200.0 / g.omega(1.0),
                );
                let a = sonine::white_noise_a2(d, e);
                assert!(
                    (end.a2 - a).abs() < 2.0 * a * a,
                    "d {d} e {e}: {end:?} vs {a}"
                );
                assert!(
                    (end.temperature / 2.0 - 1.0).abs() < a * a,
                    "d {d} e {e}: {end:?}"
                );
            }
        }
    }

    /// Elastic grains under noise heat at exactly `m ξ0² (1 - 1/N)` and keep a Maxwellian.
    #[test]
    fn elastic_grains_heat_linearly() {
        let g = SonineRelaxation::new(2, 1.0, 2.0, 1000.0, 0.005, 1.0, Some(100));
        let end = g.trajectory(
            SonineState {
                temperature: 1.0,
                a2: 0.0,
            },
            &[(0.0, 0.5)],
            &[3.0],
        )[0];
        assert!((end.temperature - (1.0 + 3.0 * 2.0 * 0.5 * 0.99)).abs() < 1e-12);
        assert_eq!(end.a2, 0.0);
    }

    /// Haff's law: free cooling at the cooling state's `a2` follows KT-9.
    #[test]
    fn free_cooling_follows_haff() {
        let (d, e) = (3, 0.8);
        let g = gas(d, e);
        let a = sonine::cooling_a2_first(d, e);
        let zeta0 = crate::theory::haff::sonine_cooling_rate(d, e, g.omega(1.0), a);
        let t0 = 2.0 / zeta0;
        let s = g.evolve(
            SonineState {
                temperature: 1.0,
                a2: a,
            },
            0.0,
            3.0 * t0,
        );
        assert!((s.temperature - 1.0 / 16.0).abs() < 1e-9, "{s:?}");
        assert!((s.a2 - a).abs() < 1e-12);
    }

    #[test]
    fn the_waiting_time_lands_on_the_temperature() {
        let g = gas(2, 0.3);
        let start = SonineState {
            temperature: 1.0,
            a2: sonine::white_noise_a2(2, 0.3),
        };
        let weak = g.strength_for_temperature(0.05);
        let tw = g.time_to_reach(start, weak, 0.3, 100.0).expect("reached");
        let at = g.evolve(start, weak, tw);
        assert!((at.temperature - 0.3).abs() < 1e-8, "{at:?}");
        assert!(g.time_to_reach(start, weak, 0.01, 100.0).is_none());
    }
}
