//! Rough grains in the event-driven engine (RS-1 to RS-9, `docs/rough.md`): exact
//! conservation laws of the engine, equipartition of elastic rough grains, and the
//! homogeneous cooling and white-noise states against the Maxwellian (RS-4 to RS-6) and
//! first Sonine (RS-8, RS-9) theory.

use crate::common::{STANDARD_ERRORS, observations};
use granular::boundary::{AxisKind, SimulationBox};
use granular::collision_law::CollisionLaw;
use granular::edmd::init::{self, Region};
use granular::edmd::{Edmd, EdmdOptions, ParticleSet};
use granular::engine::Engine;
use granular::random::{std_normal, stream};
use granular::scenario::Scenario;
use granular::theory::rough::{Approximation, RoughGas, RoughState};
use granular::vector::Vector;

/// A gas of `n` rough grains of two kinds (radius `r` and `1.3 r`, mass 1 and 2.5, κ from
/// `inertia`) at packing fraction `phi` in the unit box, Maxwellian at `T_t = 1` with
/// zero total momentum and Maxwellian spins at `T_r = 1`.
fn rough_gas<const D: usize>(
    n: usize,
    phi: f64,
    kind: AxisKind,
    seed: u64,
    inertia: [f64; 2],
) -> (SimulationBox<D>, ParticleSet<D>) {
    let bx = SimulationBox::<D>::uniform(Vector([1.0; D]), kind);
    let species: Vec<u32> = (0..n).map(|i| (i % 2) as u32).collect();
    let scale = [1.0, 1.3];
    let volume: f64 = species
        .iter()
        .map(|&s| init::ball_volume::<D>(scale[s as usize]))
        .sum();
    let r = (phi / volume).powf(1.0 / D as f64);
    let radii: Vec<f64> = species.iter().map(|&s| r * scale[s as usize]).collect();
    let masses: Vec<f64> = species.iter().map(|&s| [1.0, 2.5][s as usize]).collect();
    let mut rng = stream(seed, &[0]);
    let positions = init::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 10_000)
        .expect("placement");
    let mut velocities = init::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    init::remove_drift(&mut velocities, &masses);
    let dr = D * (D - 1) / 2;
    let mut angular_velocities = Vec::with_capacity(dr * n);
    for i in 0..n {
        let moment = inertia[species[i] as usize] * masses[i] * radii[i] * radii[i];
        for _ in 0..dr {
            angular_velocities.push(std_normal(&mut rng) / moment.sqrt());
        }
    }
    let set = ParticleSet {
        positions,
        velocities,
        radii,
        masses,
        species,
        species_names: vec!["small".into(), "large".into()],
        angular_velocities,
        inertia: inertia.to_vec(),
    };
    (bx, set)
}

/// Translational plus rotational kinetic energy.
fn total_energy<const D: usize>(e: &Edmd<D>) -> f64 {
    e.kinetic_energy_now() + e.rotational_energy_now().expect("rough grains")
}

/// Elastic rough grains (α = 1, β = ±1; at walls α_w = 1, `e_t = ±1`) conserve the total
/// energy to round-off, with no overlap; β = -1 (here Walton's rule with sticking value -1,
/// which always gives β = -1 yet keeps the grains' spins) leaves every angular velocity bit
/// for bit untouched. `collisions` per case; the engine's `dissipated_energy` stays at
/// round-off too.
fn conserves_energy<const D: usize>(kind: AxisKind, beta: f64, wall_et: f64, collisions: u64) {
    let inertia = if D == 2 { [0.5, 0.8] } else { [0.4, 0.6] };
    let (bx, set) = rough_gas::<D>(600, 0.25, kind, 7, inertia);
    let mut law = CollisionLaw::uniform(1.0);
    law.wall_tangential_restitution = wall_et;
    if beta == -1.0 {
        law.tangential_restitution = -1.0;
        law.friction = Some(0.3);
    } else {
        law.tangential_restitution = beta;
    }
    // (Walton's rule counts as inelastic for `is_elastic`, although with β₀ = -1 it is.)
    assert!(law.is_rough() && (beta == -1.0 || law.is_elastic()));
    let mut e = Edmd::new(bx, set, law, EdmdOptions::default());
    let spins0 = e.angular_velocities();
    let e0 = total_energy(&e);
    let r_min = e.radii().iter().cloned().fold(f64::INFINITY, f64::min);
    let (mut drift, mut overlap) = (0.0f64, 0.0f64);
    let target = e.collisions() + collisions;
    for k in 1..=10 {
        let t = e.time();
        let goal = e.collisions() + collisions / 10;
        let mut until = t;
        while e.collisions() < goal {
            until += 1.0;
            e.advance(until, goal - e.collisions()).expect("engine");
        }
        assert!(e.time() > t, "the clock is stuck at {t}");
        drift = drift.max(((total_energy(&e) - e0) / e0).abs());
        overlap = overlap.max(e.max_overlap());
        assert!(
            drift < 1e-11,
            "{D}D β = {beta}, e_t = {wall_et}: relative energy drift {drift:e} after {k}/10"
        );
        assert!(overlap < 1e-10 * r_min, "{D}D: overlap {overlap:e}");
    }
    assert!(e.collisions() >= target);
    assert!(e.totals().dissipated_energy.abs() < 1e-11 * e0);
    if beta == -1.0 {
        assert_eq!(e.angular_velocities(), spins0, "β = -1 changed a spin");
    } else {
        // β = 1 exchanges energy with the spins.
        assert_ne!(e.angular_velocities(), spins0);
    }
    eprintln!(
        "{D}D β = {beta} e_t = {wall_et}: {} collisions, largest energy drift {drift:.1e}, overlap {:.1e} radii",
        e.collisions(),
        overlap / r_min
    );
}

#[test]
fn elastic_rough_grains_conserve_energy_2d() {
    conserves_energy::<2>(AxisKind::Periodic, 1.0, 1.0, 2_000_000);
    conserves_energy::<2>(AxisKind::Wall, 1.0, -1.0, 1_000_000);
    conserves_energy::<2>(AxisKind::Wall, -1.0, 1.0, 1_000_000);
}

#[test]
fn elastic_rough_grains_conserve_energy_3d() {
    conserves_energy::<3>(AxisKind::Periodic, 1.0, 1.0, 1_000_000);
    conserves_energy::<3>(AxisKind::Wall, 1.0, -1.0, 1_000_000);
    conserves_energy::<3>(AxisKind::Periodic, -1.0, 1.0, 1_000_000);
}

/// The issue's long check: 10⁷ collisions of perfectly rough elastic grains in each
/// dimension (2D periodic, 3D with perfectly rough walls).
#[test]
#[ignore = "long validation, about a minute in release"]
fn elastic_rough_grains_conserve_energy_over_ten_million_collisions() {
    conserves_energy::<2>(AxisKind::Periodic, 1.0, 1.0, 10_000_000);
    conserves_energy::<3>(AxisKind::Wall, 1.0, -1.0, 10_000_000);
}

fn cross<const D: usize>(a: &Vector<D>, b: &Vector<D>) -> [f64; 3] {
    if D == 2 {
        [0.0, 0.0, a[0] * b[1] - a[1] * b[0]]
    } else {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
}

/// Every pair collision of the engine conserves momentum, the total angular momentum
/// (orbital about any point plus spin, `Σ m r × v + I ω`) to round-off, and loses exactly
/// the energy it adds to `dissipated_energy`; for inelastic rough grains of two kinds
/// (constant β and Walton's rule).
fn conserves_angular_momentum<const D: usize>(law: &CollisionLaw) {
    let inertia = if D == 2 { [0.5, 0.9] } else { [0.4, 0.25] };
    let (bx, set) = rough_gas::<D>(200, 0.2, AxisKind::Periodic, 5, inertia);
    let mut e = Edmd::new(bx.clone(), set, law.clone(), EdmdOptions::default());
    e.record_collisions(true);
    let n = e.len();
    let kappa: Vec<f64> = e.species().iter().map(|&s| inertia[s as usize]).collect();
    let radii = e.radii();
    let masses = e.masses();
    let moment = |i: usize| kappa[i] * masses[i] * radii[i] * radii[i];
    let mut checked = 0;
    while checked < 3000 {
        let (v0, w0, log0) = (
            (0..n).map(|i| e.velocity(i)).collect::<Vec<_>>(),
            (0..n).map(|i| e.angular_velocity(i)).collect::<Vec<_>>(),
            e.collision_log().len(),
        );
        let energy0 = total_energy(&e) + e.totals().dissipated_energy;
        e.advance(f64::INFINITY, 1).expect("engine");
        if e.collision_log().len() == log0 {
            continue;
        }
        let rec = *e.collision_log().last().expect("a collision");
        let (i, j) = (rec.i as usize, rec.j.expect("no walls") as usize);
        let dx = bx.separation(&e.position(i), &e.position(j));
        let (dvi, dvj) = (e.velocity(i) - v0[i], e.velocity(j) - v0[j]);
        let (mi, mj) = (e.mass_of(i), e.mass_of(j));
        let dp = dvi * mi + dvj * mj;
        let scale = mi * dvi.norm();
        assert!(dp.norm() < 1e-13 * scale, "momentum changed by {dp:?}");
        // About the centre of i: the orbital part changes by dx × m_j Δv_j.
        let orbital = cross(&dx, &(dvj * mj));
        let (wi, wj) = (e.angular_velocity(i), e.angular_velocity(j));
        for k in 0..3 {
            let spin = moment(i) * (wi[k] - w0[i][k]) + moment(j) * (wj[k] - w0[j][k]);
            let dl = orbital[k] + spin;
            assert!(
                dl.abs() < 1e-12 * scale * dx.norm(),
                "{D}D collision {checked}: angular momentum component {k} changed by {dl:e} (scale {:e})",
                scale * dx.norm()
            );
        }
        let energy1 = total_energy(&e) + e.totals().dissipated_energy;
        assert!(
            (energy1 - energy0).abs() < 1e-12 * energy0,
            "energy not accounted for"
        );
        checked += 1;
    }
}

#[test]
fn pair_collisions_conserve_angular_momentum() {
    let mut law = CollisionLaw::uniform(0.7);
    law.tangential_restitution = 0.4;
    conserves_angular_momentum::<2>(&law);
    conserves_angular_momentum::<3>(&law);
    law.tangential_restitution = 0.6;
    law.friction = Some(0.2);
    conserves_angular_momentum::<2>(&law);
    conserves_angular_momentum::<3>(&law);
}

pub(crate) fn scenario(text: &str, over: &[String]) -> Scenario {
    Scenario::from_toml(text, over).expect("valid scenario")
}

pub(crate) fn dimension_keys(d: usize) -> Vec<String> {
    vec![
        format!("dimension={d}"),
        format!(
            "box.lengths={}",
            if d == 2 { "[1.0,1.0]" } else { "[1.0,1.0,1.0]" }
        ),
    ]
}

/// Elastic perfectly rough grains (α = β = 1) starting without spin relax to
/// equipartition, `T_r = T_t`: exact equilibrium statistical mechanics (the collisions
/// conserve energy and mix both kinds of degrees of freedom). With the total momentum
/// held at zero, `T_t` (counted over `d_t N` degrees of freedom) is `(N-1)/N` of the
/// equilibrium temperature: the expected ratio is `N/(N-1)`. Batch means of the ratio
/// after 20 collisions per grain, 4 standard errors.
#[test]
fn perfectly_rough_elastic_grains_reach_equipartition() {
    const TEXT: &str = r#"
engine = "edmd"
dimension = 2
seed = 21
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "grain"
count = 500
packing_fraction = 0.05
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[initial]
zero_momentum = true
[collisions]
restitution = 1.0
tangential_restitution = 1.0
[stop]
collisions_per_particle = 220.0
[output]
interval = 0.05
"#;
    for d in [2, 3] {
        let obs = observations(scenario(TEXT, &dimension_keys(d)));
        assert_eq!(obs[0].rotational_temperature, Some(0.0));
        let late: Vec<f64> = obs
            .iter()
            .filter(|o| o.collisions_per_particle > 20.0)
            .map(|o| o.rotational_temperature.expect("rough") / o.temperature)
            .collect();
        let (mean, err) = crate::common::batch_estimate(&late);
        let expected = 500.0 / 499.0;
        eprintln!(
            "{d}D α = β = 1: T_r/T_t = {mean:.4} ± {err:.4} over {} samples (expected {expected:.4})",
            late.len()
        );
        assert!(
            (mean - expected).abs() < STANDARD_ERRORS * err,
            "{d}D: T_r/T_t = {mean} ± {err}, expected {expected}"
        );
    }
}

/// A dilute gas of rough grains held in its homogeneous cooling state by rescaling
/// (`kind = "rescale"`: velocities and spins by the same factor, so the temperature ratio
/// is the collisions' alone). The 2D box is about 5 mean free paths wide (packing fraction
/// 0.0025) and the 3D one about 3 (0.01), small enough that the shear instability of the
/// cooling state does not grow; the theory is that of the Boltzmann equation, and the
/// density enters θ and ζ/ν only through the collision frequency, which both divide out.
pub(crate) const EDMD_HCS: &str = r#"
engine = "edmd"
dimension = 2
seed = 3
[box]
lengths = [1.0, 1.0]
boundary = "periodic"
[[species]]
name = "grain"
count = 1000
packing_fraction = 0.0025
velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
angular_velocity = { distribution = "maxwell_boltzmann", temperature = 1.0 }
[initial]
zero_momentum = true
[collisions]
restitution = 0.9
tangential_restitution = 0.0
[driving]
kind = "rescale"
temperature = 1.0
[stop]
collisions_per_particle = 200.0
[output]
interval = 0.05
equilibration_collisions_per_particle = 20.0
"#;

/// Relative error allowed the Maxwellian approximation of θ (RS-4, RS-6) where the Sonine
/// cumulants are small (|a| ≲ 0.2): its Sonine correction (RS-8, RS-9) moves θ by 1-5 %
/// at the four (α, β) tested (`docs/rough.md`).
pub(crate) const MAXWELL_RATIO: f64 = 0.05;
/// The same for the Maxwellian ζ/ν (RS-5): the Sonine correction moves it by less than 2 %.
pub(crate) const MAXWELL_RATE: f64 = 0.02;
/// Relative error allowed the first Sonine approximation (RS-8, RS-9), of θ and of ζ/ν:
/// the products of two cumulants it drops, `|a|² ≲ 0.02` for |a| ≲ 0.15.
pub(crate) const SONINE: f64 = 0.02;

pub(crate) fn hcs_overrides(d: usize, alpha: f64, beta: f64) -> Vec<String> {
    let mut over = dimension_keys(d);
    if d == 3 {
        over.push("species[0].packing_fraction=0.01".into());
    }
    over.push(format!("collisions.restitution={alpha}"));
    over.push(format!("collisions.tangential_restitution={beta}"));
    over
}

/// `measured = (mean, standard error)` within `STANDARD_ERRORS` errors plus the relative
/// `allowance` of `theory`.
pub(crate) fn agrees(
    what: &str,
    measured: (f64, f64),
    theory: f64,
    allowance: f64,
) -> Result<(), String> {
    let (mean, err) = measured;
    let tol = STANDARD_ERRORS * err + allowance * theory.abs();
    if (mean - theory).abs() <= tol {
        Ok(())
    } else {
        Err(format!(
            "{what}: measured {mean:.4} ± {err:.4}, theory {theory:.4} (tolerance {tol:.4})"
        ))
    }
}

/// The measured θ and ζ/ν of a run after 20 collisions per grain: means and standard
/// errors of 10 batch means of the time series (the ratio at each output, the reduced
/// cooling rate over each output interval).
pub(crate) fn measured(scenario: Scenario) -> ((f64, f64), (f64, f64)) {
    let obs = observations(scenario);
    let late: Vec<usize> = (1..obs.len())
        .filter(|&k| obs[k - 1].collisions_per_particle >= 20.0)
        .collect();
    let theta: Vec<f64> = late
        .iter()
        .map(|&k| obs[k].rotational_temperature.expect("rough") / obs[k].temperature)
        .collect();
    let zeta: Vec<f64> = late
        .iter()
        .map(|&k| obs[k].rates_since(&obs[k - 1]).reduced_cooling_rate)
        .collect();
    (
        crate::common::batch_estimate(&theta),
        crate::common::batch_estimate(&zeta),
    )
}

pub(crate) fn uniform_gas(d: usize, alpha: f64, beta: f64) -> RoughGas {
    RoughGas {
        dimension: d,
        normal_restitution: alpha,
        tangential_restitution: beta,
        inertia: if d == 2 { 0.5 } else { 0.4 },
    }
}

/// The homogeneous cooling state of rough grains at the issue's four (α, β): the measured
/// temperature ratio θ and cooling rate ζ/ν of the total energy (after 20 collisions per
/// grain, over 180) against the Maxwellian theory (RS-4, RS-5) and the first Sonine
/// approximation (RS-8), with the allowances above. At (0.7, -0.5) the Sonine expansion
/// has broken down (`a02` ≈ 10-20) and neither approximation is expected to hold to better
/// than tens of per cent (Santos, Kremer and dos Santos 2011 for the quasi-smooth limit):
/// there the measured θ is checked to lie between the two approximations.
fn hcs_matches_theory(d: usize) {
    hcs_of_engine_matches_theory(d, "", |alpha, beta| {
        scenario(EDMD_HCS, &hcs_overrides(d, alpha, beta))
    });
}

/// [`hcs_matches_theory`] for the runs `run(α, β)` of an engine (`engine` in the
/// messages).
pub(crate) fn hcs_of_engine_matches_theory(
    d: usize,
    engine: &str,
    run: impl Fn(f64, f64) -> Scenario,
) {
    let mut failures = Vec::new();
    for (alpha, beta) in [(0.9, 0.0), (0.9, 0.5), (0.7, -0.5), (0.5, 1.0)] {
        let (theta, zeta) = measured(run(alpha, beta));
        let gas = uniform_gas(d, alpha, beta);
        let (cooling, maxwell, sonine) = (
            RoughState::Cooling,
            Approximation::Maxwell,
            Approximation::Sonine,
        );
        let tm = gas
            .temperature_ratio(cooling, maxwell)
            .expect("Maxwellian θ");
        let zm = gas
            .reduced_cooling_rate(cooling, maxwell)
            .expect("Maxwellian ζ");
        let state = gas.sonine_state(cooling);
        let (ts, zs) = (
            gas.temperature_ratio(cooling, sonine),
            gas.reduced_cooling_rate(cooling, sonine),
        );
        eprintln!(
            "{engine}{d}D α = {alpha} β = {beta}: θ = {:.4} ± {:.4} (Maxwell {tm:.4}, Sonine {ts:.4?}); ζ/ν = {:.4} ± {:.4} (Maxwell {zm:.4}, Sonine {zs:.4?})",
            theta.0, theta.1, zeta.0, zeta.1,
        );
        let small = state.is_some_and(|s| [s.a20, s.a02, s.a11].iter().all(|x| x.abs() < 0.5));
        let label = format!("{engine}{d}D α = {alpha} β = {beta}");
        let checks = if small {
            let (ts, zs) = (ts.expect("Sonine θ"), zs.expect("Sonine ζ"));
            vec![
                agrees(&format!("{label} θ vs Maxwell"), theta, tm, MAXWELL_RATIO),
                agrees(&format!("{label} θ vs Sonine"), theta, ts, SONINE),
                agrees(&format!("{label} ζ/ν vs Maxwell"), zeta, zm, MAXWELL_RATE),
                agrees(&format!("{label} ζ/ν vs Sonine"), zeta, zs, SONINE),
            ]
        } else {
            let ts = ts.unwrap_or(0.0);
            let (lo, hi) = (ts.min(tm), ts.max(tm));
            vec![if theta.0 > lo && theta.0 < hi {
                Ok(())
            } else {
                Err(format!(
                    "{label}: θ = {:.4} outside [{lo:.4}, {hi:.4}]",
                    theta.0
                ))
            }]
        };
        failures.extend(checks.into_iter().filter_map(Result::err));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn homogeneous_cooling_state_of_rough_disks_matches_theory() {
    hcs_matches_theory(2);
}

#[test]
fn homogeneous_cooling_state_of_rough_spheres_matches_theory() {
    hcs_matches_theory(3);
}

/// The white-noise driven gas of rough grains (kicks on the translational velocities
/// only): θ against RS-6 (Maxwellian, allowance 3 %: its Sonine correction RS-9 moves it
/// by 1-3 %) and RS-9 (allowance [`SONINE`]); ζ/ν of the total energy against the same
/// two (allowances [`MAXWELL_RATE`] and [`SONINE`]).
#[test]
fn white_noise_state_of_rough_grains_matches_theory() {
    white_noise_of_engine_matches_theory("", |d, alpha, beta| {
        let mut over = hcs_overrides(d, alpha, beta);
        over.push("driving.kind=\"white_noise\"".into());
        over.push("driving.strength=1.0".into());
        let text = EDMD_HCS.replace("temperature = 1.0\n[stop]", "[stop]");
        scenario(&text, &over)
    });
}

/// The white-noise check above for the runs `run(d, α, β)` of an engine (`engine` in the
/// messages), at (d, α, β) = (2, 0.9, 0) and (3, 0.7, 0.5).
pub(crate) fn white_noise_of_engine_matches_theory(
    engine: &str,
    run: impl Fn(usize, f64, f64) -> Scenario,
) {
    let mut failures = Vec::new();
    for (d, alpha, beta) in [(2, 0.9, 0.0), (3, 0.7, 0.5)] {
        let (theta, zeta) = measured(run(d, alpha, beta));
        let gas = uniform_gas(d, alpha, beta);
        let (noise, maxwell, sonine) = (
            RoughState::WhiteNoise,
            Approximation::Maxwell,
            Approximation::Sonine,
        );
        let (tm, ts) = (
            gas.temperature_ratio(noise, maxwell).expect("θ"),
            gas.temperature_ratio(noise, sonine).expect("θ"),
        );
        let (zm, zs) = (
            gas.reduced_cooling_rate(noise, maxwell).expect("ζ"),
            gas.reduced_cooling_rate(noise, sonine).expect("ζ"),
        );
        eprintln!(
            "{engine}{d}D white noise α = {alpha} β = {beta}: θ = {:.4} ± {:.4} (Maxwell {tm:.4}, Sonine {ts:.4}); ζ/ν = {:.4} ± {:.4} (Maxwell {zm:.4}, Sonine {zs:.4})",
            theta.0, theta.1, zeta.0, zeta.1
        );
        let label = format!("{engine}{d}D white noise α = {alpha} β = {beta}");
        failures.extend(
            [
                agrees(&format!("{label} θ vs Maxwell"), theta, tm, 0.03),
                agrees(&format!("{label} θ vs Sonine"), theta, ts, SONINE),
                agrees(&format!("{label} ζ/ν vs Maxwell"), zeta, zm, MAXWELL_RATE),
                agrees(&format!("{label} ζ/ν vs Sonine"), zeta, zs, SONINE),
            ]
            .into_iter()
            .filter_map(Result::err),
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A run of rough grains (held in the cooling state by rescaling) killed in the middle of
/// an output interval and resumed from its checkpoint ends with the same bits (the spins
/// are part of the engine's checkpoint).
#[test]
fn rough_run_resumes_bit_identical() {
    let o: Vec<String> = [
        "output.interval=1e6",
        "output.checkpoint_seconds=1e-9",
        "stop.collisions_per_particle=1e4",
        "stop.events=1000000",
    ]
    .map(String::from)
    .to_vec();
    crate::spine::assert_resume_mid_interval("rough", scenario(EDMD_HCS, &o));
}
