//! The one collision law of every engine: the same walled inelastic scenario applies the
//! same wall law (normal and tangential restitution, HD-3/HD-4) and the same TC rule
//! (section 2.3 of the hard-disk assignment) with the same counter in the event-driven engine and
//! in DSMC; DSMC's non-finite check, species name and validity warnings.

use granular::collision_law::{CollisionLaw, WallRestitution};
use granular::dsmc::{DsmcConfig, DsmcEngine};
use granular::edmd::ParticleSet;
use granular::edmd::init::{self as setup, Region};
use granular::edmd::{Edmd, EdmdOptions};
use granular::engine::{Engine, EngineError};
use granular::random::stream;
use granular::run::{AnyEngine, build};
use granular::scenario::Scenario;
use granular::{AxisKind, SimulationBox, Vector};

/// One grain heading for the corner of a walled unit square: it hits the wall `x = 1`
/// (centre at `1 - r`), then 0.49 (0.5 in DSMC, whose walls act on the centre) later the
/// wall `y = 1`, within the contact duration 0.6: that second collision is elastic.
const PROBE: &str = r#"
engine = "edmd"
dimension = 2
seed = 1

[box]
lengths = [1.0, 1.0]
boundary = "wall"

[[species]]
name = "probe"
count = 1
radius = 0.01
mass = 1.0
positions = [[0.5, 0.5]]
velocity = { distribution = "given", velocity = [1.0, 0.8] }

[collisions]
restitution = 0.9
wall_restitution = 0.5
wall_tangential_restitution = 0.25
contact_duration = 0.6

[stop]
time = 1.2

[output]
interval = 0.1
"#;

fn probe(engine: &str) -> AnyEngine {
    let mut o: Vec<String> = vec![format!("engine={engine}")];
    if engine == "dsmc" {
        o.extend(["dsmc.time_step=0.03".into(), "dsmc.cell_size=0.5".into()]);
    }
    let s = Scenario::from_toml(PROBE, &o).expect("valid scenario");
    build(&s).expect("builds")
}

/// Velocity and position of grain 0, from the snapshot (the same for every engine).
fn state(e: &mut AnyEngine) -> ([f64; 2], [f64; 2]) {
    let s = e.as_engine().snapshot().expect("snapshot");
    (
        [s.velocities[0], s.velocities[1]],
        [s.positions[0], s.positions[1]],
    )
}

fn tc_elastic(e: &AnyEngine) -> u64 {
    match e {
        AnyEngine::Edmd2(e) => e.totals().tc_elastic_collisions,
        AnyEngine::Dsmc2(e) => e.tc_elastic_collisions(),
        _ => unreachable!("a 2D test"),
    }
}

/// After one wall collision the velocity is exactly `(-e_w v_x, e_t v_y)` in both engines,
/// and the position is the exact free flight with the wall law; the second wall collision,
/// within `t_c` of the first, is elastic in both (normal and tangential) and counted once.
#[test]
fn both_engines_apply_the_same_wall_law() {
    let law = Scenario::from_toml(PROBE, &[]).unwrap().collisions().law();
    let first = WallRestitution {
        normal: law.wall_restitution,
        tangential: law.wall_tangential_restitution,
    };
    let after_one = first.apply(&Vector([1.0, 0.8]), 0).0;
    assert_eq!(after_one, [-0.5, 0.25 * 0.8]);
    // Wall contact of the centre: at 1 - r in the event-driven engine, at 1 in DSMC.
    for (engine, reach) in [("edmd", 1.0 - 0.01), ("dsmc", 1.0)] {
        let mut e = probe(engine);
        let t1 = reach - 0.5; // first hit (v_x = 1)
        e.as_engine().advance(0.7, u64::MAX).unwrap();
        let (v, x) = state(&mut e);
        assert_eq!(v, after_one, "{engine}: velocity after one wall collision");
        let expect = [
            reach + after_one[0] * (0.7 - t1),
            0.5 + 0.8 * t1 + after_one[1] * (0.7 - t1),
        ];
        for k in 0..2 {
            assert!(
                (x[k] - expect[k]).abs() < 1e-12,
                "{engine}: {x:?} vs {expect:?}"
            );
        }
        assert_eq!(
            tc_elastic(&e),
            0,
            "{engine}: the first collision is inelastic"
        );
        // Second hit, on y = reach at t2 = t1 + (reach - y(t1)) / (e_t v_y): elastic.
        let y1 = 0.5 + 0.8 * t1;
        let t2 = t1 + (reach - y1) / after_one[1];
        assert!(t2 - t1 < law.contact_duration && t2 < 1.2);
        e.as_engine().advance(1.2, u64::MAX).unwrap();
        let (v, x) = state(&mut e);
        assert_eq!(v, [after_one[0], -after_one[1]], "{engine}: elastic by TC");
        assert_eq!(tc_elastic(&e), 1, "{engine}: one TC-elastic collision");
        let expect = [
            reach + after_one[0] * (1.2 - t1),
            reach - after_one[1] * (1.2 - t2),
        ];
        for k in 0..2 {
            assert!(
                (x[k] - expect[k]).abs() < 1e-12,
                "{engine}: {x:?} vs {expect:?}"
            );
        }
    }
}

/// Energy lost at the walls by an ideal gas in a short time, against its exact expectation
/// given the initial velocities: with walls at `x = 0, L` (periodic along y) and `Δt` so
/// short that no grain crosses the box, grain `i` hits a wall with probability
/// `p_i = |v_x,i| Δt / L_free` (its centre uniform on the free length `L_free`) and then
/// loses `m/2 ((1 - e_w²) v_x² + (1 - e_t²) v_y²)`. The sum of these independent Bernoulli
/// losses has mean `Σ p_i ΔE_i` and variance `Σ p_i (1 - p_i) ΔE_i²`; both engines must
/// agree with it within 4 standard deviations. Pair collisions (elastic, grains of radius
/// 1e-7) are rare (about 100) and conserve energy.
#[test]
fn both_engines_lose_the_expected_energy_at_walls() {
    let n = 50_000;
    let r = 1e-7;
    let dt = 0.1;
    let law = CollisionLaw {
        restitution: 1.0,
        wall_restitution: 0.8,
        wall_tangential_restitution: 0.3,
        contact_duration: 0.0,
        ..CollisionLaw::default()
    };
    let bx = SimulationBox::<2> {
        lengths: Vector([1.0, 1.0]),
        axes: [AxisKind::Wall, AxisKind::Periodic],
    };
    let mut rng = stream(2024, &[0]);
    let radii = vec![r; n];
    let positions =
        setup::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 100).unwrap();
    let masses = vec![1.0; n];
    let velocities = setup::maxwell_boltzmann::<2>(&masses, 1.0, &mut rng);
    let set = ParticleSet {
        positions,
        velocities: velocities.clone(),
        radii,
        masses,
        species: vec![0; n],
        species_names: vec!["gas".into()],
        ..Default::default()
    };
    // Centres of the event-driven engine live on [r, 1 - r] and touch a wall at r or
    // 1 - r; DSMC's reach the wall at 0 or 1 (from the same positions).
    let expectation = |et: f64, dsmc: bool| {
        let (mut mean, mut var) = (0.0, 0.0);
        for v in &velocities {
            let travel = v[0].abs() * dt - if dsmc { r } else { 0.0 };
            let p = (travel / (1.0 - 2.0 * r)).max(0.0);
            let loss = 0.5 * ((1.0 - 0.8f64.powi(2)) * v[0] * v[0] + (1.0 - et * et) * v[1] * v[1]);
            mean += p * loss;
            var += p * (1.0 - p) * loss * loss;
        }
        (mean, var.sqrt())
    };
    let mut edmd = Edmd::new(bx.clone(), set.clone(), law.clone(), EdmdOptions::default());
    let config = DsmcConfig {
        time_step: Some(dt),
        cell_size: Some(0.1),
        law: law.clone(),
        ..DsmcConfig::default()
    };
    let mut dsmc = DsmcEngine::from_particles(config, bx, set, 9).unwrap();
    for (name, engine, is_dsmc) in [
        ("edmd", &mut edmd as &mut dyn Engine, false),
        ("dsmc", &mut dsmc as &mut dyn Engine, true),
    ] {
        let k0 = engine.kinetic_energy();
        engine.advance(dt, u64::MAX).unwrap();
        let lost = k0 - engine.kinetic_energy();
        let (mean, sd) = expectation(0.3, is_dsmc);
        assert!(
            (lost - mean).abs() < 4.0 * sd,
            "{name}: lost {lost}, expected {mean} +- {sd}"
        );
        // The test tells the wall laws apart: smooth walls (e_t = 1) lose far less.
        let (smooth, _) = expectation(1.0, is_dsmc);
        assert!((smooth - mean).abs() > 10.0 * sd);
        assert!(
            engine.collisions() < 1000,
            "{name}: {}",
            engine.collisions()
        );
    }
}

/// With a contact duration longer than the whole run, every collision of a grain that has
/// collided before is elastic. After a first, elastic phase in which every grain collides
/// (about 20 times), an inelastic law with that contact duration makes every collision
/// elastic: the TC counter grows by exactly the number of collisions (pair and wall), and
/// the kinetic energy is conserved to round-off. Both engines.
#[test]
fn tc_counter_counts_every_collision_made_elastic() {
    let n = 2000;
    let forever = 1e9;
    let elastic = CollisionLaw {
        contact_duration: forever,
        ..CollisionLaw::default()
    };
    let inelastic = CollisionLaw {
        contact_duration: forever,
        ..CollisionLaw::uniform(0.5)
    };
    let bx = SimulationBox::<2>::unit_walled();
    let r = (0.05 / (n as f64 * std::f64::consts::PI)).sqrt();
    let mut rng = stream(77, &[0]);
    let radii = vec![r; n];
    let masses = vec![1.0; n];
    let set = ParticleSet {
        positions: setup::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 1000)
            .unwrap(),
        velocities: setup::maxwell_boltzmann::<2>(&masses, 1.0, &mut rng),
        radii,
        masses,
        species: vec![0; n],
        species_names: vec!["grain".into()],
        ..Default::default()
    };
    // Event-driven: collisions counted as pair + wall.
    let mut e = Edmd::new(
        bx.clone(),
        set.clone(),
        elastic.clone(),
        EdmdOptions::default(),
    );
    let collisions = |e: &Edmd<2>| e.totals().pair_collisions + e.totals().wall_collisions;
    let mut t = 0.0;
    while e.totals().pair_collisions < 10 * n as u64 {
        t += 0.1;
        e.advance(t, u64::MAX).unwrap();
    }
    assert_eq!(
        e.totals().tc_elastic_collisions,
        0,
        "elastic law: nothing to count"
    );
    e.set_collision_law(inelastic.clone());
    let (c0, k0) = (collisions(&e), e.kinetic_energy_now());
    e.advance(t + 0.5, u64::MAX).unwrap();
    let made = collisions(&e) - c0;
    assert!(made > 5 * n as u64, "{made} collisions");
    assert_eq!(e.totals().tc_elastic_collisions, made);
    assert!((e.kinetic_energy_now() - k0).abs() < 1e-9 * k0);
    // DSMC: its wall collisions are not in `collisions()` (pair collisions only) but the
    // counter counts them too: more counted than pair collisions, energy conserved.
    let config = DsmcConfig {
        cell_size: Some(0.1),
        time_step: Some(0.002),
        law: elastic,
        ..DsmcConfig::default()
    };
    let mut d = DsmcEngine::from_particles(config, bx, set, 5).unwrap();
    while d.collisions() < 10 * n as u64 {
        d.step(0.002);
    }
    assert_eq!(
        d.tc_elastic_collisions(),
        0,
        "elastic law: nothing to count"
    );
    d.set_collision_law(inelastic.clone()).unwrap();
    let (c0, k0) = (d.collisions(), d.kinetic_energy_now());
    let tc0 = d.tc_elastic_collisions();
    for _ in 0..300 {
        d.step(0.002);
    }
    let made = d.collisions() - c0;
    assert!(made > 5 * n as u64, "{made} collisions");
    let counted = d.tc_elastic_collisions() - tc0;
    assert!(counted > made, "{counted} counted, {made} pair collisions");
    assert!((d.kinetic_energy_now() - k0).abs() < 1e-9 * k0);
    // Periodic box: only pair collisions, so the counter equals the collision count.
    let bxp = SimulationBox::<2>::uniform(Vector([1.0; 2]), AxisKind::Periodic);
    let config = DsmcConfig {
        cell_size: Some(0.1),
        time_step: Some(0.002),
        law: CollisionLaw {
            restitution: 1.0,
            ..inelastic.clone()
        },
        ..DsmcConfig::default()
    };
    let mut p = DsmcEngine::<2>::new(config, bxp, n, r, 1.0, 1.0, 6).unwrap();
    while p.collisions() < 10 * n as u64 {
        p.step(0.002);
    }
    p.set_collision_law(inelastic).unwrap();
    let c0 = p.collisions();
    for _ in 0..100 {
        p.step(0.002);
    }
    assert_eq!(p.tc_elastic_collisions(), p.collisions() - c0);
}

/// A velocity that overflows is reported whatever the grain's place in storage (the check
/// looked at the first stored velocity only): under a gravity of 1e308 along the walled
/// axis, a grain starting at 1.7e308 overflows in the first step of 1 time unit while
/// every other grain stays finite. It sits in the top row of cells, so it is not stored
/// first (storage is by cell).
#[test]
fn dsmc_reports_a_non_finite_velocity_of_any_grain() {
    let n = 50;
    let bad = 37;
    let mut rng = stream(3, &[0]);
    let bx = SimulationBox::<2> {
        lengths: Vector([1.0, 1.0]),
        axes: [AxisKind::Wall, AxisKind::Periodic],
    };
    let radii = vec![1e-4; n];
    let mut pos =
        setup::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 100).unwrap();
    pos[bad] = Vector([0.5, 0.99]);
    let mut vel = setup::maxwell_boltzmann::<2>(&vec![1.0; n], 1.0, &mut rng);
    vel[bad] = Vector([1.7e308, 0.0]);
    let config = DsmcConfig {
        time_step: Some(1.0),
        cell_size: Some(0.25),
        gravity: vec![1e308, 0.0],
        ..DsmcConfig::default()
    };
    let mut e = DsmcEngine::<2>::from_state(config, bx, 1e-4, 1.0, pos, vel, 1).unwrap();
    let err = e.advance(1.0, u64::MAX).expect_err("overflow");
    match err {
        EngineError::Numerical(m) => assert!(m.contains(&format!("particle {bad} ")), "{m}"),
        other => panic!("{other}"),
    }
    assert_eq!(e.first_non_finite(), Some(bad as u32));
    assert_ne!(
        e.ids()[0] as usize,
        bad,
        "the bad grain is not stored first"
    );
    assert!(e.velocities()[0].0.iter().all(|c| c.is_finite()));
}

/// DSMC snapshots carry the scenario's species name; the validity warnings of the
/// initial state are computed when the engine is built and do not change as it runs.
#[test]
fn dsmc_snapshot_names_the_species_and_build_computes_validity_warnings() {
    let text = std::fs::read_to_string(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/dsmc-cooling.toml"),
    )
    .unwrap();
    let o: Vec<String> = vec![
        "species[0].name=argon".into(),
        "species[0].count=2000".into(),
        // Cells of a quarter box: larger than the mean free path (guard ii).
        "dsmc.cell_size=0.25".into(),
    ];
    let s = Scenario::from_toml(&text, &o).unwrap();
    let mut e = build(&s).unwrap();
    let snap = e.as_engine().snapshot().unwrap();
    assert_eq!(snap.species_names, vec!["argon".to_string()]);
    assert_eq!(snap.species, vec![0; 2000]);
    let AnyEngine::Dsmc2(d) = &mut e else {
        panic!("a 2D DSMC engine")
    };
    assert_eq!(d.species_name(), "argon");
    let at_build = d.validity_warnings().to_vec();
    assert!(
        at_build
            .iter()
            .any(|w| w.kind == granular::dsmc::GuardKind::CellLargerThanMeanFreePath),
        "{at_build:?}"
    );
    assert_eq!(at_build, d.check_validity());
    d.advance(0.05, u64::MAX).unwrap();
    assert_eq!(d.validity_warnings(), &at_build[..]);
}
