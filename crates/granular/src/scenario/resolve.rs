//! [`Resolved`]: every quantity a run derives from its scenario, computed once, here, by
//! the formulas of [`crate::theory`]: the grains' radii (from `radius` or
//! `packing_fraction`), masses and volumes, the number density and packing fraction, the
//! contact value `χ` of the collision rate, the initial temperature, the collision
//! frequency, mean free time and path, Haff's time with its Sonine factor and the HCS `a2`,
//! the DSMC time step and cell size, the steady state of `[driving]`, and for rough grains
//! their reduced moments of inertia and the cooling rate of their homogeneous cooling state.
//!
//! [`Scenario::resolve`] resolves a scenario at the initial temperature its velocities
//! describe (`granular check`, the pre-flight estimate); the simulation built from it
//! resolves it again at the temperature of the drawn initial state
//! ([`Resolved::at_temperature`]), which `summary.json`'s `resolved` block, the
//! steady-state output and the report read. Nobody else recomputes these numbers.

use super::{Scenario, VelocitySpec};
use crate::collision_law::rough::uniform_inertia;
use crate::driving::{Driving, GasTheory};
use crate::dsmc::cells::cells_along;
use crate::dsmc::config::{AT_REST_TIME_STEP, automatic_time_step, default_cell_size};
use crate::theory::rough::RoughGas;
use crate::theory::{haff, kinetic, sonine};

/// One species, resolved.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SpeciesResolved {
    /// Its name.
    pub name: String,
    /// Number of grains.
    pub count: usize,
    /// Grain radius (length units): `radius`, or from `packing_fraction` (KT-1, KT-2).
    pub radius: f64,
    /// Grain mass (mass units).
    pub mass: f64,
    /// Volume (area in 2D) of one grain, KT-1 (length^D).
    pub grain_volume: f64,
    /// Kinetic temperature of its initial velocities as the scenario gives them
    /// (`m <|v|^2> / D`; energy units).
    pub temperature: f64,
}

/// Haff's law for a gas of smooth grains that cools (`collisions.restitution < 1`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cooling {
    /// `1 + 3 a2 / 16` with the first estimate: the Sonine factor of the cooling rate (KT-8).
    pub sonine_factor: f64,
    /// Haff's time `t0 = 2 / zeta(T0)` (KT-9, DSMC-3) with the contact value [`Grains::chi`]
    /// and the Sonine factor (time units).
    pub haff_time: f64,
    /// Haff's time of the dilute Maxwellian estimate (`χ = 1`, no Sonine factor), the
    /// pre-flight estimate's clock.
    pub dilute_haff_time: f64,
}

/// The numerical choices of the DSMC engine, resolved.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DsmcResolved {
    /// The time step `τ`: `dsmc.time_step`, or the automatic step
    /// ([`automatic_time_step`]) at the initial temperature.
    pub time_step: f64,
    /// Whether the step follows the mean free time (no `dsmc.time_step`).
    pub follows_mean_free_time: bool,
    /// The requested cell edge: `dsmc.cell_size`, or `default_cell_size`.
    pub cell_size: f64,
    /// The cells' edge along each axis: the box length over the cells that fit
    /// (the DSMC engine's grid rule), at least [`DsmcResolved::cell_size`].
    pub cell_edges: Vec<f64>,
    /// Bins of the impact-parameter histogram.
    pub impact_bins: usize,
}

/// The steady state of `[driving]` and its kinetic theory.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DrivingResolved {
    /// What the engine applies (`rescale`'s temperature resolved to the initial
    /// temperature where the scenario leaves it out).
    pub driving: Driving,
    /// The kinetic theory of the driven gas (one species).
    pub gas: GasTheory,
    /// The Sonine `a2` of the state (KT-11 for `rescale`, KT-12 for `white_noise`); for
    /// rough grains the translational `a20` (RS-8, RS-9; NaN where it has no solution).
    pub a2: f64,
    /// `rescale` of smooth grains: the HCS's first estimate (KT-10), for comparison.
    pub a2_first: Option<f64>,
    /// The state's temperature: `rescale`'s fixed one, or the white-noise energy balance
    /// (KT-13; for rough grains the translational temperature of RS-6's balance).
    pub temperature: f64,
}

/// Rough grains (`collisions.tangential_restitution` above -1), resolved.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RoughResolved {
    /// Tangential restitution β of a pair collision (RS-1); with `collisions.friction`
    /// the sticking value β₀ of Walton's rule (RS-7).
    pub tangential_restitution: f64,
    /// Coulomb friction coefficient μ of Walton's rule, if any.
    pub friction: Option<f64>,
    /// The reduced moment of inertia `κ = 4I/(mσ²)` of each species, in the scenario's
    /// order: `species[i].inertia`, or the uniform grain's
    /// (`crate::collision_law::rough::uniform_inertia`).
    pub inertia: Vec<f64>,
    /// The cooling rate `ζ / ν` of the homogeneous cooling state of the first species
    /// in the Maxwellian approximation (RS-4, RS-5; Walton's rule read as its β₀).
    pub cooling_rate: f64,
    /// `2 / (ζ ω₀)` with the dilute collision frequency ω₀ at the initial temperature,
    /// the pre-flight estimate's clock (infinite when the gas does not cool).
    pub dilute_haff_time: f64,
}

impl RoughResolved {
    /// The kinetic theory of the first species ([`crate::theory::rough`]) at normal
    /// restitution `restitution`.
    pub fn gas(&self, dimension: usize, restitution: f64) -> RoughGas {
        RoughGas {
            dimension,
            normal_restitution: restitution,
            tangential_restitution: self.tangential_restitution,
            inertia: self
                .inertia
                .first()
                .copied()
                .unwrap_or(uniform_inertia(dimension)),
        }
    }
}

/// The many-grain engines' resolved quantities.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Grains {
    /// Each species, in the scenario's order.
    pub species: Vec<SpeciesResolved>,
    /// Box volume (area in 2D).
    pub volume: f64,
    /// Number of grains `N`.
    pub particles: usize,
    /// `n = N / V`.
    pub number_density: f64,
    /// `φ = Σ N_s v_D(R_s) / V`, KT-2.
    pub packing_fraction: f64,
    /// Pair restitution `e`.
    pub restitution: f64,
    /// The homogeneous cooling state's `a2` at `e`, the first and the second estimate of
    /// van Noije and Ernst (1998), KT-10 and KT-11 (0 for an elastic gas).
    pub hcs_a2: [f64; 2],
    /// The radius of the kinetic estimates: the grains' mean radius (one species: its own).
    pub radius: f64,
    /// The mass of the kinetic estimates: the grains' mean mass.
    pub mass: f64,
    /// The Enskog contact value `χ(φ)`, KT-3.
    pub contact_value: f64,
    /// Whether the engine's collision rate carries the Enskog factor (event-driven
    /// dynamics, and DSMC with `dsmc.enskog`); DSMC without it simulates the Boltzmann gas.
    pub enskog: bool,
    /// The contact value of the engine's collision rate: [`Grains::contact_value`] with
    /// the Enskog factor, 1 without.
    pub chi: f64,
    /// The initial temperature (energy units): the count-weighted mean of the species'
    /// temperatures for [`Scenario::resolve`], the drawn state's for a simulation.
    pub temperature: f64,
    /// Collision frequency per grain at the initial temperature, KT-5 with [`Grains::chi`]
    /// (1/time).
    pub collision_frequency: f64,
    /// Mean free time `1 / ω`, KT-6 (time units).
    pub mean_free_time: f64,
    /// Mean free path, KT-6 with [`Grains::chi`] (length units).
    pub mean_free_path: f64,
    /// The dilute (Boltzmann, `χ = 1`) collision frequency, the pre-flight estimate's.
    pub dilute_collision_frequency: f64,
    /// Haff's law, for smooth grains with `e < 1` (rough grains cool at RS-5: [`Grains::rough`]).
    pub cooling: Option<Cooling>,
    /// Rough grains: their inertia and cooling (`None` for smooth grains).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rough: Option<RoughResolved>,
    /// `engine = "dsmc"`: its step and cells.
    pub dsmc: Option<DsmcResolved>,
    /// `[driving]`: its steady state.
    pub driving: Option<DrivingResolved>,
}

/// Every derived quantity of a scenario: what it holds, who computes and who reads it is
/// told in `scenario/resolve.rs`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Resolved {
    /// Spatial dimension of the state (the intruder models: 1 or 2).
    pub dimension: usize,
    /// The many-grain engines' quantities (`None` for the intruder engine).
    pub grains: Option<Grains>,
}

/// Kinetic temperature `m <|v|^2> / D` of a species' initial velocities as written.
fn velocity_temperature(v: &VelocitySpec, mass: f64, d: f64) -> f64 {
    let sq = |u: &[f64]| u.iter().map(|x| x * x).sum::<f64>();
    match v {
        VelocitySpec::Zero => 0.0,
        VelocitySpec::FixedSpeed { speed } => mass * speed * speed / d,
        VelocitySpec::MaxwellBoltzmann { temperature } => *temperature,
        VelocitySpec::Given { velocity } => mass * sq(velocity) / d,
        VelocitySpec::PerGrain { velocities } => {
            let n = velocities.len().max(1) as f64;
            velocities.iter().map(|u| mass * sq(u) / d).sum::<f64>() / n
        }
    }
}

impl Resolved {
    /// Resolves a validated scenario at the initial temperature of its velocities.
    pub(crate) fn of(sc: &Scenario) -> Resolved {
        let grains = sc.grains().is_some().then(|| Grains::of(sc));
        let dimension = sc.intruder().map_or(sc.dimension, |i| i.dimension());
        Resolved { dimension, grains }
    }

    /// The same scenario resolved at initial temperature `temperature` (the drawn
    /// state's): every quantity that depends on it is computed again, the others are kept.
    pub fn at_temperature(&self, sc: &Scenario, temperature: f64) -> Resolved {
        let mut out = self.clone();
        if let Some(g) = out.grains.as_mut() {
            g.kinetics(sc, temperature);
        }
        out
    }
}

impl Grains {
    fn of(sc: &Scenario) -> Grains {
        let d = sc.dimension;
        let volume: f64 = sc.lengths().iter().product();
        let species: Vec<SpeciesResolved> = sc
            .species()
            .iter()
            .enumerate()
            .map(|(s, sp)| {
                let radius = sc.radius(s);
                SpeciesResolved {
                    name: sp.name.clone(),
                    count: sp.count,
                    radius,
                    mass: sp.mass,
                    grain_volume: kinetic::grain_volume(d, radius),
                    temperature: velocity_temperature(&sp.velocity, sp.mass, d as f64),
                }
            })
            .collect();
        let particles: usize = species.iter().map(|s| s.count).sum();
        let n = particles as f64;
        // Count-weighted means (one species: its own values).
        let (mut temperature, mut radius, mut mass) = (0.0, 0.0, 0.0);
        for s in &species {
            let w = s.count as f64 / n;
            temperature += w * s.temperature;
            radius += w * s.radius;
            mass += w * s.mass;
        }
        let packing_fraction = kinetic::mixture_packing_fraction(
            d,
            species.iter().map(|s| (s.count, s.radius)),
            volume,
        );
        let contact_value = kinetic::contact_value(d, packing_fraction);
        let enskog = sc.dsmc().is_none_or(|d| d.enskog);
        let law = sc.collisions().law();
        let rough = law.is_rough().then(|| RoughResolved {
            tangential_restitution: law.tangential_restitution,
            friction: law.friction,
            inertia: sc
                .species()
                .iter()
                .map(|sp| sp.inertia.unwrap_or(uniform_inertia(d)))
                .collect(),
            cooling_rate: f64::NAN,
            dilute_haff_time: f64::INFINITY,
        });
        let mut g = Grains {
            species,
            volume,
            particles,
            number_density: n / volume,
            packing_fraction,
            restitution: sc.collisions().restitution,
            hcs_a2: [
                sonine::cooling_a2_first(d, sc.collisions().restitution),
                sonine::cooling_a2_second(d, sc.collisions().restitution),
            ],
            radius,
            mass,
            contact_value,
            enskog,
            chi: if enskog { contact_value } else { 1.0 },
            temperature,
            collision_frequency: f64::NAN,
            mean_free_time: f64::NAN,
            mean_free_path: f64::NAN,
            dilute_collision_frequency: f64::NAN,
            cooling: None,
            rough,
            dsmc: None,
            driving: None,
        };
        g.kinetics(sc, temperature);
        g
    }

    /// The quantities that depend on the initial temperature `t`.
    fn kinetics(&mut self, sc: &Scenario, t: f64) {
        let d = sc.dimension;
        let (n, r, m, e, chi) = (
            self.number_density,
            self.radius,
            self.mass,
            self.restitution,
            self.chi,
        );
        self.temperature = t;
        self.collision_frequency = kinetic::collision_frequency(d, n, r, t, m, chi);
        self.mean_free_time = 1.0 / self.collision_frequency;
        self.mean_free_path = kinetic::mean_free_path(d, n, r, chi);
        self.dilute_collision_frequency = kinetic::collision_frequency(d, n, r, t, m, 1.0);
        let first = self.hcs_a2[0];
        if let Some(rough) = self.rough.as_mut() {
            let zeta = rough.gas(d, e).cooling_rate();
            rough.cooling_rate = zeta;
            rough.dilute_haff_time = if zeta > 0.0 {
                2.0 / (zeta * self.dilute_collision_frequency)
            } else {
                f64::INFINITY
            };
        }
        self.cooling = (e < 1.0 && self.rough.is_none()).then(|| Cooling {
            sonine_factor: 1.0 + 3.0 * first / 16.0,
            haff_time: haff::haff_time(d, n, r, t, m, e, chi, true),
            dilute_haff_time: haff::haff_time(d, n, r, t, m, e, 1.0, false),
        });
        self.dsmc = sc.dsmc().map(|spec| {
            let cell_size = spec
                .cell_size
                .unwrap_or_else(|| default_cell_size(d, n, self.mean_free_path));
            DsmcResolved {
                time_step: spec.time_step.unwrap_or_else(|| {
                    automatic_time_step(self.collision_frequency).unwrap_or(AT_REST_TIME_STEP)
                }),
                follows_mean_free_time: spec.time_step.is_none(),
                cell_size,
                cell_edges: sc
                    .lengths()
                    .iter()
                    .map(|&l| l / cells_along(l, cell_size) as f64)
                    .collect(),
                impact_bins: spec.impact_bins(),
            }
        });
        let rough = self.rough.as_ref().map(|r| r.gas(d, e));
        self.driving = sc.driving().map(|spec| {
            let gas = GasTheory {
                dimension: d,
                restitution: e,
                number_density: n,
                radius: self.species.first().map_or(0.0, |s| s.radius),
                mass: self.species.first().map_or(1.0, |s| s.mass),
                chi,
                particles: self.particles,
            };
            let driving = spec.driving(t);
            let (a2, temperature, a2_first) = match &rough {
                Some(rough) => {
                    let (a2, temperature) = rough_steady_state(rough, &gas, &driving);
                    (a2, temperature, None)
                }
                None => {
                    let a2 = gas.a2(&driving);
                    match driving {
                        Driving::Rescale { temperature } => (a2, temperature, Some(first)),
                        Driving::WhiteNoise { strength } => {
                            (a2, gas.white_noise_temperature(strength, a2), None)
                        }
                    }
                }
            };
            DrivingResolved {
                driving,
                gas,
                a2,
                a2_first,
                temperature,
            }
        });
    }
}

/// The steady state of rough grains under `driving` (docs/rough.md), as `(a2,
/// temperature)`: `a2` is the Sonine `a20` of the state (RS-8 held by rescaling, RS-9 under
/// white noise; NaN where the Sonine equations have no solution); the temperature is
/// rescaling's, or under white noise the Maxwellian energy balance at the ratio of RS-6
/// ([`RoughGas::white_noise_temperature`]), with the collision frequency of `smooth`'s
/// grains at unit temperature.
fn rough_steady_state(rough: &RoughGas, smooth: &GasTheory, driving: &Driving) -> (f64, f64) {
    match *driving {
        Driving::Rescale { temperature } => (
            rough.sonine_cooling_state().map_or(f64::NAN, |s| s.a20),
            temperature,
        ),
        Driving::WhiteNoise { strength } => {
            let nu = smooth.collision_frequency(1.0);
            (
                rough.sonine_white_noise_state().map_or(f64::NAN, |s| s.a20),
                rough.white_noise_temperature(strength, smooth.mass, smooth.particles, nu),
            )
        }
    }
}

impl Scenario {
    /// Every derived quantity of this (validated) scenario, at the initial temperature its
    /// velocities describe (`Resolved`).
    pub fn resolve(&self) -> Resolved {
        Resolved::of(self)
    }
}
