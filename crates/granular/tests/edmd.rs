//! Event-driven engine: the test cases of appendix B of the hard-disk assignment, exactness
//! under long runs and dense packings, and equilibrium physics against exact results.

use granular::boundary::{AxisKind, SimulationBox};
use granular::collision_law::CollisionLaw;
use granular::edmd::init::{self, Region};
use granular::edmd::{Edmd, EdmdOptions, ParticleSet};
use granular::engine::{CollapseRemedy, Engine, EngineError, Progress};
use granular::random::stream;
use granular::stats::{Histogram, RunningStats, batch_means, chi_square_test};
use granular::theory::equilibrium;
use granular::vector::Vector;

fn set<const D: usize>(
    pos: Vec<Vector<D>>,
    vel: Vec<Vector<D>>,
    radius: Vec<f64>,
    mass: Vec<f64>,
) -> ParticleSet<D> {
    let n = pos.len();
    ParticleSet {
        positions: pos,
        velocities: vel,
        radii: radius,
        masses: mass,
        species: vec![0; n],
        species_names: vec!["grain".into()],
        ..Default::default()
    }
}

fn run_to<const D: usize>(e: &mut Edmd<D>, t: f64) {
    while e.advance(t, u64::MAX).expect("engine error") != Progress::Reached {}
}

fn run_collisions<const D: usize>(e: &mut Edmd<D>, collisions: u64) {
    let target = e.collisions() + collisions;
    let mut t = e.time();
    while e.collisions() < target {
        t += 1.0;
        e.advance(t, collisions).expect("engine error");
    }
}

fn one_particle(x: [f64; 2], v: [f64; 2], xi: f64) -> Edmd<2> {
    Edmd::new(
        SimulationBox::unit_walled(),
        set(vec![Vector(x)], vec![Vector(v)], vec![0.05], vec![1.0]),
        CollisionLaw::uniform(xi),
        EdmdOptions::default(),
    )
}

// ---------------------------------------------------------------- B.1 one particle

#[test]
fn b1_head_on_wall_bounce_reverses_velocity() {
    let mut e = one_particle([0.5, 0.5], [1.0, 0.0], 1.0);
    run_to(&mut e, 0.6); // hits x = 0.95 at t = 0.45
    assert_eq!(e.totals().wall_collisions, 1);
    assert_eq!(e.velocity(0).0, [-1.0, 0.0]);
}

#[test]
fn b1_oblique_wall_bounce_obeys_the_law_of_reflection() {
    let (vx, vy) = (0.8, 0.3);
    let mut e = one_particle([0.5, 0.5], [vx, vy], 1.0);
    run_to(&mut e, 0.7); // right wall at t = 0.5625, top wall not before 1.5
    assert_eq!(e.totals().wall_collisions, 1);
    let v = e.velocity(0);
    let incidence = (vy / vx).atan();
    let reflection = (v[1] / -v[0]).atan();
    assert!(
        (incidence - reflection).abs() < 1e-15
            && (v.norm() - (vx * vx + vy * vy).sqrt()).abs() < 1e-15
    );
}

#[test]
fn b1_diagonal_particle_hits_each_wall_once_and_returns() {
    let (x0, y0, v0, r) = (0.3, 0.6, 0.7, 0.05);
    let mut e = one_particle([x0, y0], [v0, v0], 1.0);
    let period = 2.0 * (1.0 - 2.0 * r) / v0;
    run_to(&mut e, period * (1.0 - 1e-9));
    assert_eq!(e.totals().wall_collisions, 4);
    run_to(&mut e, period);
    let x = e.position(0);
    assert!(
        (x[0] - x0).abs() < 1e-12 && (x[1] - y0).abs() < 1e-12,
        "{x:?}"
    );
    assert_eq!(e.velocity(0).0, [v0, v0]);
}

#[test]
fn b1_inelastic_wall_stops_the_particle() {
    let mut e = one_particle([0.5, 0.5], [1.0, 0.4], 0.0);
    run_to(&mut e, 1.0);
    assert_eq!(e.totals().wall_collisions, 1);
    assert_eq!(e.velocity(0).0, [0.0, 0.0]);
    // And it stays there without scheduling anything.
    run_to(&mut e, 100.0);
    assert_eq!(e.totals().wall_collisions, 1);
}

// ---------------------------------------------------------------- B.2 two particles

fn two_particles(b: f64, xi: f64) -> Edmd<2> {
    let r = 0.05;
    Edmd::new(
        SimulationBox::unit_walled(),
        set(
            vec![Vector([0.3, 0.5 - b / 2.0]), Vector([0.7, 0.5 + b / 2.0])],
            vec![Vector([1.0, 0.0]), Vector([-1.0, 0.0])],
            vec![r, r],
            vec![1.0, 1.0],
        ),
        CollisionLaw::uniform(xi),
        EdmdOptions::default(),
    )
}

#[test]
fn b2_head_on_equal_masses_bounce_back() {
    let mut e = two_particles(0.0, 1.0);
    run_to(&mut e, 0.2);
    assert_eq!(e.collisions(), 1);
    assert_eq!(e.velocity(0).0, [-1.0, 0.0]);
    assert_eq!(e.velocity(1).0, [1.0, 0.0]);
}

#[test]
fn b2_impact_parameter_over_sqrt2_deflects_by_right_angles() {
    let b = 0.1 / 2f64.sqrt();
    let mut e = two_particles(b, 1.0);
    run_to(&mut e, 0.2);
    assert_eq!(e.collisions(), 1);
    for (i, sign) in [(0, 1.0), (1, -1.0)] {
        let v = e.velocity(i);
        assert!((v.norm() - 1.0).abs() < 1e-14, "speed kept");
        assert!(
            v[0].abs() < 1e-14,
            "moves at right angles to its initial direction: {v:?}"
        );
        assert!(v[1] * sign < 0.0);
    }
}

#[test]
fn b2_perfectly_inelastic_head_on_stops_both() {
    let mut e = two_particles(0.0, 0.0);
    run_to(&mut e, 1.0);
    assert_eq!(e.collisions(), 1);
    assert_eq!(e.velocity(0).0, [0.0, 0.0]);
    assert_eq!(e.velocity(1).0, [0.0, 0.0]);
}

// ---------------------------------------------------------------- B.3 and exactness

fn gas<const D: usize>(
    n: usize,
    phi: f64,
    kind: AxisKind,
    seed: u64,
    lattice: bool,
) -> (SimulationBox<D>, ParticleSet<D>) {
    let bx = SimulationBox::<D>::uniform(Vector([1.0; D]), kind);
    let r = (phi / (n as f64 * init::ball_volume::<D>(1.0))).powf(1.0 / D as f64);
    let radii = vec![r; n];
    let mut rng = stream(seed, &[0]);
    let pos = if lattice {
        init::lattice_placement(&bx, &Region::whole(&bx), &radii).expect("lattice")
    } else {
        init::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 10_000)
            .expect("placement")
    };
    let masses = vec![1.0; n];
    let mut vel = init::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    init::remove_drift(&mut vel, &masses);
    (bx, set(pos, vel, radii, masses))
}

#[test]
fn b3_energy_is_constant_to_round_off_over_a_million_collisions() {
    let (bx, p) = gas::<2>(1000, 0.4, AxisKind::Wall, 11, false);
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    let k0 = e.kinetic_energy_now();
    run_collisions(&mut e, 1_000_000);
    let k1 = e.kinetic_energy_now();
    assert!(
        ((k1 - k0) / k0).abs() < 1e-11,
        "relative energy change {}",
        (k1 - k0) / k0
    );
}

#[test]
fn momentum_is_conserved_in_a_periodic_box() {
    let (bx, p) = gas::<3>(500, 0.3, AxisKind::Periodic, 12, false);
    let mut e = Edmd::new(bx, p, CollisionLaw::uniform(0.7), EdmdOptions::default());
    let p0 = e.momentum();
    let k0 = e.kinetic_energy_now();
    run_collisions(&mut e, 100_000);
    assert!((e.momentum() - p0).norm() < 1e-11 * (2.0 * k0 * 500.0).sqrt());
}

#[test]
fn no_overlap_after_a_million_collisions_dense_2d() {
    let (bx, p) = gas::<2>(2500, 0.7, AxisKind::Periodic, 13, true);
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    run_collisions(&mut e, 1_000_000);
    let r = e.radii()[0];
    assert!(e.max_overlap() < 1e-10 * r, "overlap {}", e.max_overlap());
}

#[test]
fn no_overlap_after_a_million_collisions_dense_3d() {
    let (bx, p) = gas::<3>(1728, 0.5, AxisKind::Periodic, 14, true);
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    run_collisions(&mut e, 1_000_000);
    let r = e.radii()[0];
    assert!(e.max_overlap() < 1e-10 * r, "overlap {}", e.max_overlap());
}

/// Two disks that have just collided separate, and in a periodic box meet again through
/// the other image: head on at relative speed 2 in a box 20 long, with diameter 1, they
/// collide at t = 1 and then every 9 time units (the gap of 18 through the image closes
/// at speed 2). The engine used to skip its last partner while neither had collided
/// again, and the two passed through each other.
#[test]
fn last_partners_meet_again_through_the_periodic_image() {
    let bx = SimulationBox::uniform(Vector([20.0, 20.0]), AxisKind::Periodic);
    let particles = set(
        vec![Vector([5.0, 10.0]), Vector([8.0, 10.0])],
        vec![Vector([1.0, 0.0]), Vector([-1.0, 0.0])],
        vec![0.5, 0.5],
        vec![1.0, 1.0],
    );
    let mut e = Edmd::new(
        bx,
        particles,
        CollisionLaw::uniform(1.0),
        EdmdOptions::default(),
    );
    let mut worst: f64 = 0.0;
    for k in 1..=300 {
        run_to(&mut e, k as f64 * 0.1);
        worst = worst.max(e.max_overlap());
    }
    // Collisions at t = 1, 10, 19, 28.
    assert_eq!(e.collisions(), 4, "overlap {worst}");
    assert!(worst < 1e-12, "overlap {worst}");
}

/// A white-noise kick right after a collision can send the two partners towards each
/// other again; the engine must then predict their next contact (it used to skip the pair
/// as "separating", and grains passed through each other: 0.83 sigma apart in a 300-disk
/// run at t = 0.3). Checked at 2000 instants (400 kicks) in 2D and 3D, dilute and dense,
/// and with the rescaling thermostat, whose kicks keep every pair's approach sign.
#[test]
fn driven_gases_never_overlap() {
    use granular::driving::Driving;
    fn check<const D: usize>(n: usize, phi: f64, seed: u64, driving: Driving) {
        let (bx, p) = gas::<D>(n, phi, AxisKind::Periodic, seed, false);
        let mut e = Edmd::new(bx, p, CollisionLaw::uniform(0.9), EdmdOptions::default());
        e.set_driving(Some(driving.clone()), seed);
        let r = e.radii()[0];
        let dt = e.driving_interval().expect("driven") / 5.0;
        let mut worst: f64 = 0.0;
        for k in 1..=2000 {
            run_to(&mut e, k as f64 * dt);
            worst = worst.max(e.max_overlap());
        }
        assert!(
            e.collisions() > 5 * n as u64,
            "{} collisions",
            e.collisions()
        );
        assert!(
            worst < 1e-10 * r,
            "D = {D}, phi = {phi}, {driving:?}: overlap {worst} (radius {r})"
        );
    }
    let noise = Driving::WhiteNoise { strength: 1.0 };
    check::<2>(300, 0.1, 5, noise.clone());
    check::<2>(400, 0.5, 6, noise.clone());
    check::<3>(300, 0.2, 7, noise);
    check::<2>(400, 0.5, 8, Driving::Rescale { temperature: 1.0 });
}

// ---------------------------------------------------------------- B.4 scattering angle

#[test]
fn b4_scattering_angle_matches_hard_sphere_law() {
    let (r1, r2) = (0.1, 0.001);
    let big = 1e6;
    for &ratio in &[0.05, 0.2, 0.4, 0.6, 0.8, 0.95] {
        let r12 = r1 + r2;
        let b = ratio * r12;
        let mut e = Edmd::new(
            SimulationBox::unit_walled(),
            set(
                vec![Vector([0.5, 0.5]), Vector([0.2, 0.5 + b])],
                vec![Vector([0.0, 0.0]), Vector([1.0, 0.0])],
                vec![r1, r2],
                vec![big, 1.0],
            ),
            CollisionLaw::default(),
            EdmdOptions::default(),
        );
        while e.collisions() == 0 {
            e.advance(e.time() + 0.01, 10).expect("engine");
        }
        let v = e.velocity(1);
        let angle = v[1].atan2(v[0]).abs();
        // Exact for an infinitely heavy target: θ = π - 2 arcsin(b / R12); the recoil of
        // a target 10^6 times heavier changes θ by O(10^-6).
        let exact = std::f64::consts::PI - 2.0 * ratio.asin();
        assert!(
            (angle - exact).abs() < 5e-6,
            "b/R12 = {ratio}: {angle} vs {exact}"
        );
    }
}

// ---------------------------------------------------------------- equilibrium physics

#[test]
fn speed_distribution_is_maxwell_boltzmann() {
    // Problem 1 in small: fixed initial speed, walls, elastic.
    let n = 1000;
    let bx = SimulationBox::<2>::unit_walled();
    let r = (0.2 / (n as f64 * std::f64::consts::PI)).sqrt();
    let mut rng = stream(21, &[0]);
    let radii = vec![r; n];
    let pos = init::random_placement(&bx, &Region::whole(&bx), &radii, &[], &mut rng, 10_000)
        .expect("placement");
    let vel = init::fixed_speed::<2>(n, 1.0, &mut rng);
    let mut e = Edmd::new(
        bx,
        set(pos, vel, radii, vec![1.0; n]),
        CollisionLaw::default(),
        EdmdOptions::default(),
    );
    run_collisions(&mut e, 10 * n as u64);
    let temperature = e.kinetic_energy_now() / n as f64; // 2K / (D N), D = 2
    let mut hist = Histogram::new(0.0, 4.0, 40);
    for _ in 0..40 {
        run_collisions(&mut e, 2 * n as u64); // 4 collisions per grain between samples
        for i in 0..n {
            hist.push(e.velocity(i).norm());
        }
    }
    let fit = chi_square_test(&hist, |v| equilibrium::speed_cdf(2, v, 1.0, temperature));
    assert!(fit.p_value > 1e-3, "{fit:?}");
    // And the test has power: a 5% wrong temperature is rejected.
    let wrong = chi_square_test(&hist, |v| {
        equilibrium::speed_cdf(2, v, 1.0, 1.05 * temperature)
    });
    assert!(wrong.p_value < 1e-3, "{wrong:?}");
}

/// Measures Z = P / (n T) and the collision frequency in a periodic box.
fn measure_pressure<const D: usize>(
    n: usize,
    phi: f64,
    seed: u64,
) -> (RunningStats, f64, f64, f64) {
    let (bx, p) = gas::<D>(n, phi, AxisKind::Periodic, seed, phi > 0.4);
    let r = p.radii[0];
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    let start = e.observe();
    run_collisions(&mut e, 20 * n as u64);
    let temperature = 2.0 * e.kinetic_energy_now() / (D as f64 * n as f64);
    let density = n as f64; // unit box
    // The collision frequency over the equilibration, from t = 0.
    let mean_free_time = 1.0
        / e.observe()
            .rates_since(&start)
            .collision_frequency
            .max(1e-300);
    let dt = 2.0 * mean_free_time; // two collisions per grain per interval
    let mut z = Vec::new();
    let mut freq = Vec::new();
    let mut t = e.time();
    let mut previous = e.observe();
    for _ in 0..400 {
        t += dt;
        run_to(&mut e, t);
        let now = e.observe();
        let rates = now.rates_since(&previous);
        z.push(rates.pressure / (density * temperature));
        freq.push(rates.collision_frequency);
        previous = now;
    }
    let (zm, ze) = batch_means(&z, 20);
    let (fm, fe) = batch_means(&freq, 20);
    let mut stats = RunningStats::new();
    z.iter().for_each(|&x| stats.push(x));
    let nu_from_z =
        equilibrium::collision_frequency_from_pressure(D, zm, 2.0 * r, 1.0, temperature);
    assert!(
        (fm - nu_from_z).abs() < 4.0 * (fe + nu_from_z * ze / (zm - 1.0)),
        "collision frequency {fm} ± {fe} vs {nu_from_z} from Z"
    );
    (stats, zm, ze, temperature)
}

#[test]
fn hard_disk_pressure_matches_the_equation_of_state() {
    for (phi, seed) in [(0.2, 31), (0.4, 32), (0.6, 33)] {
        let (_, z, err, _) = measure_pressure::<2>(1000, phi, seed);
        let exact = equilibrium::hard_disk_compressibility(phi);
        // Statistical error (4 σ, batch means) plus the stated accuracy of the equation of
        // state and the O(1/N) finite-size effect: 0.5 %.
        assert!(
            (z - exact).abs() < 4.0 * err + 5e-3 * exact,
            "phi = {phi}: Z = {z} ± {err}, EOS {exact}"
        );
    }
}

#[test]
fn hard_sphere_pressure_matches_carnahan_starling() {
    let phi = 0.3;
    let (_, z, err, _) = measure_pressure::<3>(1000, phi, 41);
    let exact = equilibrium::hard_sphere_compressibility(phi);
    assert!(
        (z - exact).abs() < 4.0 * err + 5e-3 * exact,
        "Z = {z} ± {err}, CS {exact}"
    );
}

// ---------------------------------------------------------------- TC model and collapse

#[test]
fn tc_model_makes_rapid_recollisions_elastic() {
    // A grain bouncing between two walls 0.1 apart every 0.1 time units: with t_c = 1 every
    // collision after the first is elastic, so the energy after the first bounce stays.
    let bx = SimulationBox::<2> {
        lengths: Vector([0.2, 1.0]),
        axes: [AxisKind::Wall, AxisKind::Wall],
    };
    let mut law = CollisionLaw::uniform(0.5);
    law.wall_tangential_restitution = 1.0;
    law.contact_duration = 1.0;
    let mut e = Edmd::new(
        bx,
        set(
            vec![Vector([0.1, 0.5])],
            vec![Vector([1.0, 0.0])],
            vec![0.05],
            vec![1.0],
        ),
        law,
        EdmdOptions::default(),
    );
    run_to(&mut e, 3.0);
    assert!(e.totals().wall_collisions > 5);
    assert_eq!(e.velocity(0)[0].abs(), 0.5);
    assert_eq!(
        e.totals().tc_elastic_collisions,
        e.totals().wall_collisions - 1
    );
}

fn collapsing_gas(contact_duration: f64) -> Result<u64, EngineError> {
    let (bx, p) = gas::<2>(400, 0.5, AxisKind::Periodic, 51, true);
    let mut law = CollisionLaw::uniform(0.1);
    law.contact_duration = contact_duration;
    let mut e = Edmd::new(bx, p, law, EdmdOptions::default());
    let mut t = 0.0;
    for _ in 0..200 {
        t += 0.05;
        e.advance(t, 5_000_000)?;
    }
    Ok(e.collisions())
}

#[test]
fn collapse_detector_fires_and_names_the_tc_model() {
    match collapsing_gas(0.0) {
        // The engine's judgement, typed: the TC model at 1e-3 of the mean free time (the
        // scenario layer words it with `collisions.contact_duration`, unit-tested there).
        Err(EngineError::Collapse(c)) => match c.remedy {
            CollapseRemedy::EnableContactDuration {
                advised,
                under_gravity: false,
            } => assert_eq!(advised, 1e-3 * c.mean_free_time, "{c:?}"),
            _ => panic!("expected the TC model as the remedy: {c:?}"),
        },
        other => panic!("expected a collapse, got {other:?}"),
    }
    // With the TC model the same gas runs on.
    collapsing_gas(1e-5).expect("TC model prevents the collapse");
}

/// 200 disks of radius 0.005 falling to the floor of a 0.2 x 1 box under gravity 1, at
/// restitution 0.5 and TC model `t_c` (0: off), until t = 10; the run's error message on
/// a collapse, or its final kinetic energy over the initial one.
fn settling_bed(seed: u64, contact_duration: f64) -> Result<f64, String> {
    use granular::run::Run;
    use granular::scenario::Scenario;
    let text = format!(
        r#"
engine = "edmd"
dimension = 2
seed = {seed}
gravity = [0.0, -1.0]
[box]
lengths = [0.2, 1.0]
boundary = "wall"
[[species]]
name = "grain"
count = 200
radius = 0.005
[collisions]
restitution = 0.5
contact_duration = {contact_duration:e}
[stop]
time = 10.0
[output]
interval = 0.5
checkpoint_seconds = 1e9
"#
    );
    let scenario = Scenario::from_toml(&text, &[]).expect("valid scenario");
    let dir = crate::spine::tmp(&format!("bed-{seed}-{contact_duration:e}"));
    let result = Run::create(&dir, scenario)
        .expect("run directory")
        .run_to_end(&mut |_| {}, None);
    let _ = std::fs::remove_dir_all(&dir);
    let summary = result.map_err(|e| e.to_string())?;
    let final_energy = summary.final_observables["kinetic_energy"];
    Ok(final_energy / summary.initial_kinetic_energy)
}

/// The `t_c` a collapse message advises (`collisions.contact_duration = X`).
fn advised_contact_duration(message: &str) -> f64 {
    let key = "collisions.contact_duration = ";
    let at = message
        .find(key)
        .unwrap_or_else(|| panic!("no advice in: {message}"));
    let value = &message[at + key.len()..];
    let end = value.find([' ', ',']).unwrap_or(value.len());
    value[..end]
        .parse()
        .unwrap_or_else(|_| panic!("no number in: {message}"))
}

#[test]
fn collapse_advice_lets_a_bed_settle_under_gravity() {
    // Without the TC model a disk bouncing on the floor collapses at t = 0.38. The advice
    // under gravity (0.1 of the mean free time; 1e-3 of it collapses again once the bed
    // forms, at t = 2.2) lets the bed come to rest: after a few collisions per grain at
    // restitution 0.5 almost all of its initial energy is gone.
    let message = settling_bed(7, 0.0).expect_err("collapse without the TC model");
    let advised = advised_contact_duration(&message);
    assert!(
        (1e-3..1e-1).contains(&advised),
        "advice {advised} is not about a tenth of the mean free time (0.068): {message}"
    );
    let left = settling_bed(7, advised).expect("the advised t_c lets the bed settle");
    assert!(left < 1e-3, "kinetic energy left: {left} of the initial");
    // With the TC model on but too short, the advice is a longer t_c, never a shorter one
    // (an earlier version advised 1e-3 of the mean free time, which the collapse itself
    // had shrunk below the t_c that failed).
    let message = settling_bed(7, 1e-4).expect_err("t_c = 1e-4 collapses when the bed forms");
    let advised = advised_contact_duration(&message);
    assert!((advised / 1e-3 - 1.0).abs() < 1e-9, "{message}");
}

#[test]
fn a_perfectly_inelastic_floor_is_named_as_the_cause() {
    // With wall restitution 0 a landed grain hits the floor again at once, forever; the TC
    // model cannot help, and the advice says so instead of asking for a longer t_c.
    let bx = SimulationBox::<2> {
        lengths: Vector([0.2, 1.0]),
        axes: [AxisKind::Wall, AxisKind::Wall],
    };
    let mut law = CollisionLaw::uniform(0.5);
    law.wall_restitution = 0.0;
    law.contact_duration = 1e-2;
    let options = EdmdOptions {
        gravity: vec![0.0, -1.0],
        ..EdmdOptions::default()
    };
    let grain = set(
        vec![Vector([0.1, 0.5])],
        vec![Vector([0.0, 0.0])],
        vec![0.05],
        vec![1.0],
    );
    let mut e = Edmd::new(bx, grain, law, options);
    match e.advance(10.0, 1 << 20) {
        Err(EngineError::Collapse(c)) => {
            assert_eq!(c.remedy, CollapseRemedy::WallRestitutionAboveZero, "{c:?}")
        }
        other => panic!("expected the zero-interval wall collisions to be caught: {other:?}"),
    }
}

// ---------------------------------------------------------------- initial states

/// Places `n` grains at packing fraction `start`, compresses to `phi`, and checks overlaps.
fn compress_to<const D: usize>(n: usize, phi: f64, start: f64, seed: u64) {
    let bx = SimulationBox::<D>::uniform(Vector([1.0; D]), AxisKind::Periodic);
    let r = (phi / (n as f64 * init::ball_volume::<D>(1.0))).powf(1.0 / D as f64);
    let scale = (phi / start).powf(1.0 / D as f64);
    let small = vec![r / scale; n];
    let mut rng = stream(seed, &[0]);
    let pos = init::random_placement(&bx, &Region::whole(&bx), &small, &[], &mut rng, 10_000)
        .expect("placement");
    let masses = vec![1.0; n];
    let vel = init::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    let pos = init::compress(
        &bx,
        set(pos, vel.clone(), small, masses.clone()),
        &vec![r; n],
        &mut rng,
    )
    .expect("compression");
    let e = Edmd::new(
        bx,
        set(pos, vel, vec![r; n], masses),
        CollisionLaw::default(),
        EdmdOptions::default(),
    );
    assert!(e.max_overlap() < 1e-9 * r, "overlap {}", e.max_overlap());
    let reached = init::packing_fraction::<D>(&e.radii(), 1.0);
    assert!((reached - phi).abs() < 1e-9, "reached {reached}");
}

#[test]
fn compression_reaches_dense_states() {
    compress_to::<2>(1000, 0.75, 0.35, 61);
    compress_to::<3>(1000, 0.55, 0.25, 62);
}

#[test]
fn same_input_gives_bit_identical_trajectories() {
    let run = || {
        let (bx, p) = gas::<2>(500, 0.5, AxisKind::Periodic, 71, true);
        let mut e = Edmd::new(bx, p, CollisionLaw::uniform(0.9), EdmdOptions::default());
        run_collisions(&mut e, 50_000);
        e.snapshot().expect("snapshot")
    };
    let (a, b) = (run(), run());
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.velocities, b.velocities);
}

#[test]
fn trajectory_does_not_depend_on_how_the_run_is_cut_into_calls() {
    // Time-origin shifts and spatial reordering happen at fixed event counts, so one long
    // call and many short ones (as a run with frequent outputs makes) give the same bits.
    let build = || {
        let (bx, p) = gas::<2>(400, 0.5, AxisKind::Periodic, 73, true);
        Edmd::new(bx, p, CollisionLaw::uniform(0.95), EdmdOptions::default())
    };
    let mut one = build();
    let mut many = build();
    let end = 3.0;
    run_to(&mut one, end);
    let mut t = 0.0;
    while t < end {
        t = (t + 0.0137).min(end);
        run_to(&mut many, t);
    }
    assert!(one.events() > 20 * 400, "{} events", one.events());
    assert_eq!(one.events(), many.events());
    let (a, b) = (
        one.snapshot().expect("snapshot"),
        many.snapshot().expect("snapshot"),
    );
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.velocities, b.velocities);
}

// ---------------------------------------------------------------- 3D, gravity, polydispersity

#[test]
fn speed_distribution_is_maxwell_boltzmann_in_3d() {
    let n = 1000;
    let (bx, mut p) = gas::<3>(n, 0.2, AxisKind::Wall, 22, false);
    let mut rng = stream(22, &[5]);
    p.velocities = init::fixed_speed::<3>(n, 1.0, &mut rng);
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    run_collisions(&mut e, 10 * n as u64);
    let temperature = 2.0 * e.kinetic_energy_now() / (3.0 * n as f64);
    let mut hist = Histogram::new(0.0, 3.0, 40);
    for _ in 0..40 {
        run_collisions(&mut e, 2 * n as u64);
        for i in 0..n {
            hist.push(e.velocity(i).norm());
        }
    }
    let fit = chi_square_test(&hist, |v| equilibrium::speed_cdf(3, v, 1.0, temperature));
    assert!(fit.p_value > 1e-3, "{fit:?}");
}

#[test]
fn free_fall_under_gravity_is_exact_and_bounces_elastically() {
    let bx = SimulationBox::<2>::unit_walled();
    let options = EdmdOptions {
        gravity: vec![0.0, -1.0],
        ..EdmdOptions::default()
    };
    let (y0, r) = (0.8, 0.05);
    let mut e = Edmd::new(
        bx,
        set(
            vec![Vector([0.5, y0])],
            vec![Vector([0.0, 0.0])],
            vec![r],
            vec![1.0],
        ),
        CollisionLaw::default(),
        options,
    );
    // Falls (y0 - r) to the floor in sqrt(2 (y0 - r) / g), bounces back to y0 after twice that.
    let t_floor = (2.0 * (y0 - r)).sqrt();
    run_to(&mut e, 0.5 * t_floor);
    assert!((e.position(0)[1] - (y0 - 0.125 * t_floor * t_floor)).abs() < 1e-14);
    run_to(&mut e, 2.0 * t_floor);
    assert_eq!(e.totals().wall_collisions, 1);
    assert!((e.position(0)[1] - y0).abs() < 1e-12, "{:?}", e.position(0));
    assert!(e.velocity(0)[1].abs() < 1e-12);
    // Many bouncing grains under gravity conserve total (kinetic + potential) energy.
    let (bx, p) = gas::<2>(500, 0.3, AxisKind::Wall, 23, false);
    let options = EdmdOptions {
        gravity: vec![0.0, -2.0],
        ..EdmdOptions::default()
    };
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), options);
    let energy = |e: &Edmd<2>| {
        e.kinetic_energy_now() + (0..e.len()).map(|i| 2.0 * e.position(i)[1]).sum::<f64>()
    };
    let e0 = energy(&e);
    run_collisions(&mut e, 200_000);
    assert!(((energy(&e) - e0) / e0).abs() < 1e-10);
    assert!(e.max_overlap() < 1e-12);
}

#[test]
fn large_projectile_in_a_bed_of_small_grains() {
    // The crater setup of Problem 4: a 5x larger, 25x heavier projectile at (0.5, 0.75)
    // falling at speed 5 into 2000 grains at rest in the lower half, ξ = 0.5.
    let n = 2000;
    let bx = SimulationBox::<2>::unit_walled();
    let r = (0.5 * 0.5 / (n as f64 * std::f64::consts::PI)).sqrt();
    let mut rng = stream(81, &[0]);
    let region = Region {
        lo: Vector([0.0, 0.0]),
        hi: Vector([1.0, 0.5]),
    };
    let projectile = (Vector([0.5, 0.75]), 5.0 * r);
    let bed = init::lattice_placement(&bx, &region, &vec![r; n]).expect("bed");
    let _ = &mut rng;
    let mut pos = vec![projectile.0];
    pos.extend(bed);
    let mut vel = vec![Vector([0.0, -5.0])];
    vel.extend(std::iter::repeat_n(Vector([0.0, 0.0]), n));
    let mut radii = vec![5.0 * r];
    radii.extend(std::iter::repeat_n(r, n));
    let mut masses = vec![25.0];
    masses.extend(std::iter::repeat_n(1.0, n));
    let p = ParticleSet {
        positions: pos,
        velocities: vel,
        radii,
        masses,
        species: std::iter::once(0)
            .chain(std::iter::repeat_n(1, n))
            .collect(),
        species_names: vec!["projectile".into(), "bed".into()],
        ..Default::default()
    };
    let mut law = CollisionLaw::uniform(0.5);
    law.contact_duration = 1e-6;
    let mut e = Edmd::new(bx, p, law, EdmdOptions::default());
    let k0 = e.kinetic_energy_now();
    let mut t = 0.0;
    while e.kinetic_energy_now() > 0.1 * k0 {
        t += 0.01;
        run_to(&mut e, t);
        assert!(t < 20.0, "energy should fall to 10% well before t = 20");
    }
    assert!(e.max_overlap() < 1e-10 * r, "overlap {}", e.max_overlap());
    let lost = e.totals().dissipated_energy;
    assert!(
        (k0 - e.kinetic_energy_now() - lost).abs() < 1e-9 * k0,
        "energy bookkeeping"
    );
}

/// Systems above `TOURNAMENT_MAX_GRAINS` use the calendar queue, which from
/// `LOOK_AHEAD_MIN_GRAINS` on prefetches the events to come (hints that must never change
/// the result): the trajectory of a large gas is exact (energy to round-off, no overlap)
/// and the same whether it runs in one call or in many small ones.
#[test]
fn large_systems_with_look_ahead_stay_exact_and_reproducible() {
    use granular::bench::edmd::{advance_collisions, equilibrated_fluid};
    use granular::edmd::internals::{LOOK_AHEAD_MIN_GRAINS, TOURNAMENT_MAX_GRAINS};
    let n = TOURNAMENT_MAX_GRAINS.max(LOOK_AHEAD_MIN_GRAINS) + 1000;
    let mut a = equilibrated_fluid::<2>(n, 0.6, 3).expect("bench state");
    let mut b = a.clone();
    let e0 = a.kinetic_energy_now();
    advance_collisions(&mut a, n as u64).expect("engine");
    let target = a.time();
    while b.time() < target {
        b.advance(target, 997).expect("engine");
    }
    assert_eq!(a.collisions(), b.collisions());
    assert_eq!(a.position(17).0, b.position(17).0);
    assert!(((a.kinetic_energy_now() - e0) / e0).abs() < 1e-12);
    assert!(a.max_overlap() < 1e-12, "overlap {}", a.max_overlap());
}

/// The memory target of the engine-performance issue — at most 100 bytes per grain in
/// 2D and 120 in 3D — holds on the benchmark states, with either queue, and does not grow
/// when the engine rebases and reorders its arrays (every 8 N events; 20 collisions per
/// grain cross several of them).
#[test]
fn memory_stays_within_the_target_per_grain() {
    use granular::bench::edmd::{advance_collisions, equilibrated_fluid};
    use granular::edmd::internals::TOURNAMENT_MAX_GRAINS;
    fn check<const D: usize>(n: usize, phi: f64, limit: f64) {
        let mut e = equilibrated_fluid::<D>(n, phi, 1).expect("bench state");
        let before = e.memory_bytes();
        advance_collisions(&mut e, 10 * n as u64).expect("engine");
        let after = e.memory_bytes();
        let per_grain = after as f64 / n as f64;
        // The calendar's heap of the current bucket keeps whatever capacity its busiest
        // bucket needed since the last rebuild: a few hundred bytes, not per grain.
        assert!(
            after <= before + n / 10,
            "{D}D N = {n}, phi = {phi}: memory grew from {before} to {after} bytes"
        );
        assert!(
            per_grain <= limit,
            "{D}D N = {n}, phi = {phi}: {per_grain:.1} bytes per grain, target {limit}"
        );
    }
    check::<2>(10_000, 0.7, 100.0);
    check::<2>(10_000, 0.2, 100.0);
    check::<3>(10_000, 0.45, 120.0);
    check::<2>(TOURNAMENT_MAX_GRAINS + 1000, 0.7, 100.0);
    check::<3>(TOURNAMENT_MAX_GRAINS + 1000, 0.45, 120.0);
}

/// The benchmark's general cases (`granular bench edmd --walls --restitution ...`) build
/// what they say: no overlap, the requested packing fraction reached through compression
/// where two sizes do not fit on a lattice, a 50:50 mixture of the two kinds, and the
/// inelastic law with the TC model and gravity in force (energy is dissipated, and
/// kinetic plus potential energy falls by exactly what the collisions dissipated).
#[test]
fn general_benchmark_states_are_what_they_say() {
    use granular::bench::edmd::{FluidCase, advance_collisions, fluid};
    use granular::edmd::init::packing_fraction;
    fn check<const D: usize>(n: usize, phi: f64) {
        let case = FluidCase {
            walls: true,
            restitution: 0.9,
            size_ratio: 1.4,
            mass_ratio: 4.0,
            gravity: 0.1,
            ..FluidCase::standard(n, phi)
        };
        assert!(!case.is_standard());
        let mut e = fluid::<D>(&case, 5).expect("bench state");
        assert!(e.max_overlap() < 1e-12, "overlap {}", e.max_overlap());
        let reached = packing_fraction::<D>(&e.radii(), e.simulation_box().volume());
        assert!((reached - phi).abs() < 1e-9 * phi, "{D}D: phi {reached}");
        let radii = e.radii();
        let r_min = radii.iter().cloned().fold(f64::INFINITY, f64::min);
        let large = radii.iter().filter(|&&r| r > 1.2 * r_min).count();
        assert_eq!(large, n / 2);
        let heavy = e.masses().iter().filter(|&&m| m == 4.0).count();
        assert_eq!(heavy, n / 2);
        let law = e.collision_law();
        assert_eq!(law.restitution, 0.9);
        assert!(law.contact_duration > 0.0);
        // Kinetic plus potential energy, the potential m g x_{D-1}.
        let energy = |e: &granular::edmd::Edmd<D>| {
            let masses = e.masses();
            e.kinetic_energy_now()
                + (0..n)
                    .map(|i| masses[i] * 0.1 * e.position(i)[D - 1])
                    .sum::<f64>()
        };
        let (k0, e0) = (e.kinetic_energy_now(), energy(&e));
        let dissipated0 = e.totals().dissipated_energy;
        advance_collisions(&mut e, 5 * n as u64).expect("engine");
        let dissipated = e.totals().dissipated_energy - dissipated0;
        assert!(
            dissipated > 0.1 * k0,
            "{D}D: dissipated {dissipated} of {k0}"
        );
        assert!(
            ((e0 - energy(&e) - dissipated) / e0).abs() < 1e-9,
            "{D}D: energy bookkeeping"
        );
        assert!(e.max_overlap() < 1e-12, "overlap {}", e.max_overlap());
    }
    check::<2>(2000, 0.7);
    check::<3>(2000, 0.45);
}

/// Long validation of exactness (about 2 minutes in release):
/// `cargo test --release -p granular --test physics -- --ignored long_runs`.
/// 10^8 pair collisions of 10^4 elastic disks at φ = 0.70 (the tournament-tree queue),
/// 3 x 10^7 at φ = 0.76, 3 x 10^7 of 10^5 spheres at φ = 0.45 (the calendar queue with
/// its look-ahead), 10^7 of the benchmark's general case (walls, gravity, ξ = 0.9 with
/// the TC model, two sizes and masses), and 2 x 10^7 of 10^4 disks with three intruders
/// 8 times larger (kept out of the cell lists), each checked ten times on the way: the
/// energy (kinetic, plus potential and dissipated where they apply) to round-off, no
/// overlap, and the clock moving on (no stuck events). Prints what it measured.
#[test]
#[ignore = "long validation, about 2 minutes in release"]
fn long_runs_stay_exact() {
    use granular::bench::edmd::{FluidCase, advance_collisions, fluid};
    fn run<const D: usize>(case: FluidCase, collisions: u64) {
        let g = case.gravity;
        let n = case.n;
        let mut e = fluid::<D>(&case, 11).expect("bench state");
        let energy = |e: &Edmd<D>| {
            let masses = e.masses();
            e.kinetic_energy_now()
                + e.totals().dissipated_energy
                + (0..n)
                    .map(|i| masses[i] * g * e.position(i)[D - 1])
                    .sum::<f64>()
        };
        let e0 = energy(&e);
        let r_min = e.radii().iter().cloned().fold(f64::INFINITY, f64::min);
        let (mut drift, mut overlap) = (0.0f64, 0.0f64);
        let c0 = e.collisions();
        let start = std::time::Instant::now();
        for _ in 0..10 {
            let t = e.time();
            advance_collisions(&mut e, collisions / 10).expect("engine");
            assert!(e.time() > t, "the clock is stuck at {t}");
            drift = drift.max(((energy(&e) - e0) / e0).abs());
            overlap = overlap.max(e.max_overlap());
            assert!(
                drift < 1e-11,
                "{D}D {case:?}: relative energy drift {drift:e}"
            );
            assert!(
                overlap < 1e-10 * r_min,
                "{D}D {case:?}: overlap {overlap:e} (radius {r_min})"
            );
        }
        eprintln!(
            "{D}D N = {n} phi = {}: {} collisions, {} events in {:.0} s; largest energy drift {drift:.1e}, largest overlap {:.1e} radii",
            case.packing_fraction,
            e.collisions() - c0,
            e.events(),
            start.elapsed().as_secs_f64(),
            overlap / r_min,
        );
    }
    run::<2>(FluidCase::standard(10_000, 0.70), 100_000_000);
    run::<2>(FluidCase::standard(10_000, 0.76), 30_000_000);
    run::<3>(FluidCase::standard(100_000, 0.45), 30_000_000);
    run::<2>(
        FluidCase {
            walls: true,
            restitution: 0.9,
            size_ratio: 1.4,
            mass_ratio: 4.0,
            gravity: 0.1,
            ..FluidCase::standard(10_000, 0.7)
        },
        10_000_000,
    );
    // Three intruders 8 times larger (and 64 times heavier) among 10^4 disks, kept out of
    // the cell lists (`neighbours::large_grain_cut`): elastic, periodic, 2 x 10^7 collisions.
    let (bx, mut p) = gas::<2>(10_000, 0.3, AxisKind::Periodic, 31, false);
    let r0 = p.radii[0];
    let intruders = [[0.25, 0.25], [0.75, 0.5], [0.4, 0.8]];
    let clear = |x: &Vector<2>| {
        intruders.iter().all(|c| {
            let d = bx.separation(x, &Vector(*c)).norm();
            d > 9.0 * r0 + 1e-12
        })
    };
    let keep: Vec<usize> = (0..p.len()).filter(|&i| clear(&p.positions[i])).collect();
    p = ParticleSet {
        positions: keep.iter().map(|&i| p.positions[i]).collect(),
        velocities: keep.iter().map(|&i| p.velocities[i]).collect(),
        radii: keep.iter().map(|&i| p.radii[i]).collect(),
        masses: keep.iter().map(|&i| p.masses[i]).collect(),
        species: keep.iter().map(|&i| p.species[i]).collect(),
        species_names: p.species_names,
        ..Default::default()
    };
    for c in intruders {
        p.positions.push(Vector(c));
        p.velocities.push(Vector([0.1, -0.05]));
        p.radii.push(8.0 * r0);
        p.masses.push(64.0);
        p.species.push(0);
    }
    assert!(init::packing_fraction::<2>(&p.radii, 1.0) > 0.3);
    assert!(granular::edmd::internals::large_grain_cut::<2>(&p.radii, 1.0).is_some());
    let n = p.len();
    let mut e = Edmd::new(bx, p, CollisionLaw::default(), EdmdOptions::default());
    let k0 = e.kinetic_energy_now();
    let start = std::time::Instant::now();
    let (mut drift, mut overlap) = (0.0f64, 0.0f64);
    for _ in 0..10 {
        let t = e.time();
        advance_collisions(&mut e, 2_000_000).expect("engine");
        assert!(e.time() > t, "the clock is stuck at {t}");
        drift = drift.max(((e.kinetic_energy_now() - k0) / k0).abs());
        overlap = overlap.max(e.max_overlap());
        assert!(drift < 1e-11, "intruders: relative energy drift {drift:e}");
        assert!(overlap < 1e-10 * r0, "intruders: overlap {overlap:e}");
    }
    eprintln!(
        "2D N = {n} with 3 intruders: {} collisions, {} events in {:.0} s; largest energy drift {drift:.1e}, largest overlap {:.1e} radii",
        e.collisions(),
        e.events(),
        start.elapsed().as_secs_f64(),
        overlap / r0,
    );
}
