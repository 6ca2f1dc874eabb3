//! Criterion benchmark of the event loop's hot path: elastic hard disks and spheres in a
//! periodic box, from an equilibrated fluid, 10^4 collisions per iteration.
//!
//! `cargo bench -p granular --bench edmd`. The CLI's `granular bench edmd` measures the
//! standard cases (up to 10^6 grains) end to end; see docs/performance.md.

use criterion::{Criterion, criterion_group, criterion_main};
use granular::bench::edmd::{advance_collisions, equilibrated_fluid};
use granular::edmd::Edmd;
use std::hint::black_box;

fn fluid<const D: usize>(n: usize, phi: f64) -> Edmd<D> {
    equilibrated_fluid::<D>(n, phi, 7).expect("benchmark state")
}

fn advance<const D: usize>(e: &mut Edmd<D>, collisions: u64) {
    advance_collisions(e, collisions).expect("engine");
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
