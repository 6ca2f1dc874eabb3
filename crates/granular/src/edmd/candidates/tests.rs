use super::*;
use crate::random::{RngExt, stream};

/// The packed searches (AVX2, and AVX-512 where the processor has it) return exactly
/// (bit for bit) the time and partner of the scalar one: random candidates around a
/// probe, walled and periodic axes, with and without gravity, lists of every length
/// including partial blocks, skipped partners and ties.
#[test]
fn packed_search_matches_the_scalar_search() {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        check::<2>();
        check::<3>();
    }
}

/// The two-probe search returns for each probe exactly (bit for bit) the time and
/// partner of the scalar search over the same list.
#[test]
fn pair_search_matches_two_scalar_searches() {
    pair_check::<2>();
    pair_check::<3>();
}

/// Grains in the searches' tests, and the radii of their two kinds.
const GRAINS: usize = 64;
const KIND_RADIUS: [f64; 2] = [0.5, 0.3];

/// [`GRAINS`] grains of two kinds at random in a box of side 3, with clocks in the
/// past; grains 6 and 7 are identical (a tie, won by the first in a list).
fn random_grains<const D: usize>(rng: &mut impl RngExt) -> Vec<Grain<D>> {
    let mut grains: Vec<Grain<D>> = (0..GRAINS)
        .map(|j| {
            let mut g = Grain {
                pos: Vector::zero(),
                vel: Vector::zero(),
                time: -rng.random::<f64>() * 0.1,
                counter: 0,
                kind: (j % 2) as u32,
            };
            for k in 0..D {
                g.pos[k] = 3.0 * rng.random::<f64>();
                g.vel[k] = rng.random::<f64>() - 0.5;
            }
            g
        })
        .collect();
    grains[7] = grains[6];
    grains
}

/// The box of side 3, periodic and walled.
fn boxes<const D: usize>() -> [SimulationBox<D>; 2] {
    use crate::boundary::AxisKind;
    [AxisKind::Periodic, AxisKind::Wall].map(|kind| SimulationBox::uniform(Vector([3.0; D]), kind))
}

/// Trial `trial`'s candidates (0 to 29, repeats allowed) and gravity (every fifth).
fn random_trial<const D: usize>(
    rng: &mut impl RngExt,
    trial: usize,
) -> (Vec<u32>, Option<Vector<D>>) {
    let candidates = (0..trial % 30)
        .map(|_| rng.random_range(0..GRAINS as u32))
        .collect();
    let gravity = trial.is_multiple_of(5).then(|| {
        let mut g = Vector::zero();
        g[D - 1] = -1.0;
        g
    });
    (candidates, gravity)
}

/// A probe at a random place in `bx` with a random velocity, skipping nothing.
fn random_probe<'a, const D: usize>(
    rng: &mut impl RngExt,
    radius: f64,
    gravity: Option<Vector<D>>,
    bx: &'a SimulationBox<D>,
) -> Probe<'a, D> {
    let mut p = Probe {
        slot: rng.random_range(0..GRAINS as u32),
        skip: NONE,
        pos: Vector::zero(),
        vel: Vector::zero(),
        radius,
        now: 0.0,
        gravity,
        bx,
        wrap: true,
    };
    for k in 0..D {
        p.pos[k] = 3.0 * rng.random::<f64>();
        p.vel[k] = rng.random::<f64>() - 0.5;
    }
    p
}

fn pair_check<const D: usize>() {
    let mut rng = stream(6, &[D as u64]);
    let boxes = boxes::<D>();
    let grains = random_grains::<D>(&mut rng);
    let mut found = 0;
    for trial in 0..2000 {
        let (candidates, gravity) = random_trial::<D>(&mut rng, trial);
        let bx = &boxes[trial % 2];
        // As after a collision: each skips the other.
        let mut a = random_probe(&mut rng, 0.4, gravity, bx);
        let mut b = random_probe(&mut rng, 0.3, gravity, bx);
        a.skip = b.slot;
        b.skip = a.slot;
        let pair = earliest_contacts_pair(&grains, &KIND_RADIUS, &candidates, [&a, &b]);
        for (p, got) in [&a, &b].into_iter().zip(pair) {
            let want =
                earliest_contact_scalar(&grains, &KIND_RADIUS, &candidates, p, f64::INFINITY);
            assert_eq!(want.0.to_bits(), got.0.to_bits(), "trial {trial}");
            assert_eq!(want.1, got.1, "trial {trial}");
            found += usize::from(want.1 != NONE);
        }
    }
    assert!(found > 1000, "only {found} searches found a contact");
}

#[cfg(target_arch = "x86_64")]
fn check<const D: usize>() {
    let mut rng = stream(5, &[D as u64]);
    let boxes = boxes::<D>();
    let grains = random_grains::<D>(&mut rng);
    let mut found = 0;
    for trial in 0..2000 {
        let (candidates, gravity) = random_trial::<D>(&mut rng, trial);
        let mut probe = random_probe(&mut rng, 0.4, gravity, &boxes[trial % 2]);
        if trial % 3 == 0 {
            probe.skip = candidates.first().copied().unwrap_or(NONE);
        }
        let limit = if trial % 4 == 0 { 0.5 } else { f64::INFINITY };
        let scalar = earliest_contact_scalar(&grains, &KIND_RADIUS, &candidates, &probe, limit);
        #[allow(unsafe_code)]
        // SAFETY: AVX2 checked by the caller.
        let packed = unsafe {
            avx2::earliest_contact::<D, true>(&grains, &KIND_RADIUS, &candidates, &probe, limit)
        };
        assert_eq!(scalar.0.to_bits(), packed.0.to_bits(), "trial {trial}");
        assert_eq!(scalar.1, packed.1, "trial {trial}");
        found += usize::from(scalar.1 != NONE);
        if avx512::usable(&grains) {
            // Both forms of the eight-lane search, each against the scalar one.
            let (g, r, c) = (&grains[..], &KIND_RADIUS[..], &candidates[..]);
            #[allow(unsafe_code)]
            // SAFETY: the features checked by `usable`.
            let wide = unsafe {
                [
                    avx512::earliest_contact::<D, true>(g, r, c, &probe, limit),
                    avx512::earliest_contact::<D, false>(g, r, c, &probe, limit),
                ]
            };
            let plain = scalar_search::<D, false>(g, r, c, &probe, limit);
            for (want, got) in [scalar, plain].into_iter().zip(wide) {
                assert_eq!(want.0.to_bits(), got.0.to_bits(), "trial {trial}");
                assert_eq!(want.1, got.1, "trial {trial}");
            }
        }
    }
    assert!(found > 500, "only {found} trials found a contact");
}
