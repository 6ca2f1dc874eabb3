//! Criterion benchmark of the event loop's hot path: elastic hard disks and spheres in a
//! periodic box, from an equilibrated fluid, 10^4 collisions per iteration.
//!
//! `cargo bench -p granular --bench edmd`. The CLI's `granular bench edmd` measures the
//! standard cases (up to 10^6 grains) end to end; see docs/performance.md.

use criterion::{Criterion, criterion_group, criterion_main};
use granular::boundary::{AxisKind, SimulationBox};
use granular::collision_law::CollisionLaw;
use granular::edmd::init::{self, Region};
use granular::edmd::{Edmd, EdmdOptions, ParticleSet};
use granular::engine::Engine;
use granular::random::stream;
use granular::vector::Vector;
use std::hint::black_box;

fn fluid<const D: usize>(n: usize, phi: f64) -> Edmd<D> {
    let side = (n as f64).powf(1.0 / D as f64);
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), AxisKind::Periodic);
    let r = (phi * bx.volume() / (n as f64 * init::ball_volume::<D>(1.0))).powf(1.0 / D as f64);
    let radii = vec![r; n];
    let pos = init::lattice_placement(&bx, &Region::whole(&bx), &radii).expect("lattice");
    let masses = vec![1.0; n];
    let mut rng = stream(7, &[0]);
    let vel = init::maxwell_boltzmann::<D>(&masses, 1.0, &mut rng);
    let set = ParticleSet {
        positions: pos,
        velocities: vel,
        radii,
        masses,
        species: vec![0; n],
        species_names: vec!["grain".into()],
    };
    let mut e = Edmd::new(bx, set, CollisionLaw::default(), EdmdOptions::default());
    advance(&mut e, 5 * n as u64 / 2);
    e
}

fn advance<const D: usize>(e: &mut Edmd<D>, collisions: u64) {
    let target = e.collisions() + collisions;
    let mut t = e.time();
    while e.collisions() < target {
        t += 0.01;
        e.advance(t, u64::MAX).expect("engine");
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("edmd_10k_collisions");
    g.sample_size(20);
    let mut e2 = fluid::<2>(10_000, 0.7);
    g.bench_function("2d_n1e4_phi0.7", |b| {
        b.iter(|| advance(black_box(&mut e2), 10_000))
    });
    let mut e2l = fluid::<2>(10_000, 0.2);
    g.bench_function("2d_n1e4_phi0.2", |b| {
        b.iter(|| advance(black_box(&mut e2l), 10_000))
    });
    let mut e3 = fluid::<3>(10_000, 0.45);
    g.bench_function("3d_n1e4_phi0.45", |b| {
        b.iter(|| advance(black_box(&mut e3), 10_000))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
