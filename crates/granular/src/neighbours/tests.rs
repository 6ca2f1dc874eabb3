use super::*;
use crate::boundary::AxisKind;
use crate::vector::Vector;
use std::collections::BTreeSet;

/// Coordinates of cell `f` (flat index, axis 0 fastest) of a grid with
/// `per_axis` cells along every axis.
fn cell_coords<const D: usize>(f: usize, per_axis: usize) -> [u32; D] {
    let mut c = [0u32; D];
    let mut r = f;
    for ck in c.iter_mut() {
        *ck = (r % per_axis) as u32;
        r /= per_axis;
    }
    c
}

fn neighbourhood<const D: usize>(g: &CellGrid<D>, c: &[u32; D]) -> BTreeSet<u32> {
    let mut out = Candidates::default();
    g.gather_neighbours(c, &mut out);
    out.as_slice().iter().copied().collect()
}

/// The layer a crossing gathers, with the cells the grain's old cell already had
/// around it, is exactly the new cell's neighbourhood, on walled and periodic axes,
/// at the faces and inside.
fn layer_completes_the_neighbourhood<const D: usize>(kind: AxisKind, side: f64) {
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
    let cells_per_axis = side as usize;
    let total = cells_per_axis.pow(D as u32);
    // One grain per cell (grain = flat cell index).
    let mut g = CellGrid::<D>::new(&bx, 1.0, total);
    for f in 0..total {
        g.insert(f, cell_coords(f, cells_per_axis));
    }
    for f in 0..total {
        let old = g.coords(f);
        for axis in 0..D {
            for step in [-1i32, 1] {
                let v = old[axis] as i64 + step as i64;
                let n = cells_per_axis as i64;
                if kind == AxisKind::Wall && (v < 0 || v >= n) {
                    continue;
                }
                let mut new = old;
                new[axis] = v.rem_euclid(n) as u32;
                let mut layer = Candidates::default();
                g.gather_layer(&new, axis, step, &mut layer);
                let layer: BTreeSet<u32> = layer.as_slice().iter().copied().collect();
                let before = neighbourhood(&g, &old);
                let after = neighbourhood(&g, &new);
                assert!(layer.is_subset(&after), "{old:?} -> {new:?}");
                let union: BTreeSet<u32> =
                    before.intersection(&after).chain(&layer).copied().collect();
                assert_eq!(union, after, "{old:?} -> {new:?} along {axis}");
            }
        }
    }
}

/// Crowded cells (a cluster, or a few wide cells) overflow the candidate buffer,
/// which grows and gathers again: every grain is still listed once, after the
/// candidates already in the list.
#[test]
fn gather_grows_its_buffer_for_crowded_cells() {
    let bx = SimulationBox::<2>::uniform(Vector([5.0; 2]), AxisKind::Wall);
    let n = 300;
    let mut g = CellGrid::<2>::new(&bx, 1.0, n);
    // Grain i in cell (i mod 3, 0): 100 grains in each of three neighbouring cells.
    for i in 0..n {
        g.insert(i, [(i % 3) as u32, 0]);
    }
    let mut out = Candidates::default();
    out.push(u32::MAX - 7);
    g.gather_neighbours(&[1, 0], &mut out);
    let listed = out.as_slice();
    assert_eq!(listed.len(), n + 1);
    assert_eq!(listed[0], u32::MAX - 7);
    let unique: BTreeSet<u32> = listed[1..].iter().copied().collect();
    assert_eq!(unique, (0..n as u32).collect());
    out.clear();
    g.gather_layer(&[1, 0], 0, 1, &mut out);
    assert_eq!(out.as_slice().len(), 100);
    assert!(out.as_slice().iter().all(|&j| j % 3 == 2));
}

/// The pair gather lists every grain of the union of the two neighbourhoods once,
/// for every pair of cells (adjacent or not), on walled and periodic grids.
fn pair_gather_is_the_union<const D: usize>(kind: AxisKind, side: f64) {
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
    let cells_per_axis = side as usize;
    let total = cells_per_axis.pow(D as u32);
    // Two grains per cell (grains f and f + total in cell f).
    let mut g = CellGrid::<D>::new(&bx, 1.0, 2 * total);
    let coords = |f: usize| cell_coords::<D>(f, cells_per_axis);
    for f in 0..2 * total {
        g.insert(f, coords(f % total));
    }
    for fa in 0..total {
        for fb in 0..total {
            let (a, b) = (coords(fa), coords(fb));
            let mut out = Candidates::default();
            g.gather_pair(&a, &b, &mut out);
            let listed = out.as_slice();
            let unique: BTreeSet<u32> = listed.iter().copied().collect();
            assert_eq!(
                unique.len(),
                listed.len(),
                "{a:?} {b:?}: a grain listed twice"
            );
            let union: BTreeSet<u32> = neighbourhood(&g, &a)
                .union(&neighbourhood(&g, &b))
                .copied()
                .collect();
            assert_eq!(unique, union, "{a:?} {b:?}");
        }
    }
}

#[test]
fn pair_gather_lists_both_neighbourhoods_once() {
    pair_gather_is_the_union::<2>(AxisKind::Wall, 6.0);
    pair_gather_is_the_union::<2>(AxisKind::Periodic, 6.0);
    pair_gather_is_the_union::<2>(AxisKind::Periodic, 3.0);
    pair_gather_is_the_union::<3>(AxisKind::Wall, 4.0);
    pair_gather_is_the_union::<3>(AxisKind::Periodic, 4.0);
}

/// The multiplication gives the quotient and remainder of `/` and `%` for counts and
/// indices over the whole 32-bit range (powers of two, 1 and the extremes included),
/// and a checkpoint stores the cell counts alone.
#[test]
fn count_divisor_divides_every_index_exactly() {
    use crate::random::{RngExt, stream};
    let mut rng = stream(11, &[0]);
    let mut counts = vec![
        1u32,
        2,
        3,
        7,
        64,
        105,
        1000,
        65_537,
        1 << 31,
        u32::MAX - 1,
        u32::MAX,
    ];
    counts.extend((0..200).map(|_| rng.random_range(1..=u32::MAX)));
    counts.extend((0..200).map(|_| rng.random_range(1..=4096u32)));
    for &n in &counts {
        let d = CountDivisor::from(n);
        let mut indices = vec![0, 1, n - 1, n, n.saturating_add(1), u32::MAX - 1, u32::MAX];
        indices.extend((1..4).map(|k| n.saturating_mul(k).saturating_sub(1)));
        indices.extend((0..500).map(|_| rng.random_range(0..=u32::MAX)));
        for f in indices {
            assert_eq!(d.div_rem(f), (f / n, f % n), "{f} / {n}");
        }
    }
    // Stored as the counts alone, the divisors rebuilt on reading.
    let grid = CellCounts::from([105, 7, 65_537]);
    let bytes = rmp_serde::to_vec(&grid).expect("serialise");
    let stored: Vec<usize> = rmp_serde::from_slice(&bytes).expect("counts");
    assert_eq!(stored, [105, 7, 65_537]);
    assert_eq!(
        rmp_serde::from_slice::<CellCounts<3>>(&bytes).expect("read"),
        grid
    );
}

/// Where `without_wrap` holds, every two points of the cells around the given cells
/// are nearer directly than through the periodic faces (the minimum image is the
/// plain difference); it holds away from the faces of a large grid.
#[test]
fn without_wrap_means_plain_differences() {
    let bx = SimulationBox::<2>::uniform(Vector([12.0, 9.0]), AxisKind::Periodic);
    let g = CellGrid::<2>::new(&bx, 1.0, 200);
    assert_eq!(g.counts, [12, 9]);
    let mut held = 0;
    for a in 0..12 * 9 {
        for b in 0..12 * 9 {
            let (ca, cb) = ([a % 12, a / 12], [b % 12, b / 12]);
            if !g.without_wrap(&[ca, cb]) {
                continue;
            }
            held += 1;
            // Extreme points of the span of cells around both.
            for k in 0..2 {
                let lo = ca[k].min(cb[k]) as f64 - 1.0;
                let hi = ca[k].max(cb[k]) as f64 + 2.0;
                let d = (hi - lo) * g.widths[k];
                assert!(lo >= 0.0 && hi * g.widths[k] <= bx.lengths[k]);
                assert!(d < 0.5 * bx.lengths[k], "{ca:?} {cb:?} axis {k}");
            }
        }
    }
    assert!(held > 100, "{held}");
    assert!(g.without_wrap(&[[5, 4]]));
    assert!(!g.without_wrap(&[[0, 4]]));
    assert!(!g.without_wrap(&[[5, 8]]));
    assert!(!g.without_wrap(&[[2, 4], [6, 4]]));
}

#[test]
fn crossing_layer_completes_the_neighbourhood() {
    layer_completes_the_neighbourhood::<2>(AxisKind::Wall, 5.0);
    layer_completes_the_neighbourhood::<2>(AxisKind::Periodic, 5.0);
    layer_completes_the_neighbourhood::<2>(AxisKind::Periodic, 3.0);
    layer_completes_the_neighbourhood::<3>(AxisKind::Wall, 4.0);
    layer_completes_the_neighbourhood::<3>(AxisKind::Periodic, 4.0);
}

#[test]
fn large_grains_are_split_off_only_when_few_and_much_larger() {
    // One kind: no split. Half and half (1:1.4): too many to test from every grain.
    assert_eq!(large_grain_cut::<2>(&[1.0; 100], 1e4), None);
    let mixture: Vec<f64> = (0..100)
        .map(|i| if i % 2 == 0 { 1.0 } else { 1.4 })
        .collect();
    assert_eq!(large_grain_cut::<2>(&mixture, 1e4), None);
    // The crater of Problem 4: 5000 bed grains and a 5 times larger projectile.
    let mut crater = vec![0.003989; 5000];
    crater.push(0.019945);
    assert_eq!(large_grain_cut::<2>(&crater, 1.0), Some(0.003989));
    // Two intruders of two sizes among 10^4 spheres: both large.
    let mut bath = vec![1.0; 10_000];
    bath.extend([8.0, 12.0]);
    assert_eq!(large_grain_cut::<3>(&bath, 1e6), Some(1.0));
    // A grain only slightly larger: the cells would hardly shrink.
    let mut near = vec![1.0; 1000];
    near.push(1.2);
    assert_eq!(large_grain_cut::<2>(&near, 1e4), None);
}

/// With large grains kept out of the lists, `for_each_candidate` still offers every
/// pair within contact distance from at least one of its grains, walled and periodic.
fn candidates_cover_every_contact<const D: usize>(kind: AxisKind) {
    use crate::random::stream;
    use rand::RngExt;
    let side = 20.0;
    let bx = SimulationBox::<D>::uniform(Vector([side; D]), kind);
    let mut rng = stream(5, &[D as u64]);
    let mut radii = vec![0.5; 600];
    radii.extend([3.0, 4.5]);
    let positions: Vec<Vector<D>> = radii
        .iter()
        .map(|_| Vector(std::array::from_fn(|_| side * rng.random::<f64>())))
        .collect();
    let (mut g, cut) = CellGrid::<D>::for_radii(&bx, &radii, 1.0, true);
    assert!(cut.is_some(), "a split");
    for (i, x) in positions.iter().enumerate() {
        g.insert_grain(i, g.coords_of(&x.0), radii[i], cut);
    }
    assert_eq!(g.large(), &[600, 601]);
    let mut offered = BTreeSet::new();
    for i in 0..radii.len() {
        g.for_each_candidate(i, |j| {
            offered.insert((i.min(j), i.max(j)));
        });
    }
    let mut contacts = 0;
    for i in 0..radii.len() {
        for j in i + 1..radii.len() {
            let d = bx.separation(&positions[i], &positions[j]).norm();
            if d < radii[i] + radii[j] {
                contacts += 1;
                assert!(
                    offered.contains(&(i, j)),
                    "{D}D {kind:?}: pair ({i}, {j}) at {d}"
                );
            }
        }
    }
    assert!(contacts > 50, "{contacts}");
    // The order of the cells puts every grain somewhere, large ones included.
    assert_eq!(g.cell_order().len(), radii.len());
}

#[test]
fn large_grains_reach_every_grain_they_can_touch() {
    candidates_cover_every_contact::<2>(AxisKind::Wall);
    candidates_cover_every_contact::<2>(AxisKind::Periodic);
    candidates_cover_every_contact::<3>(AxisKind::Wall);
    candidates_cover_every_contact::<3>(AxisKind::Periodic);
}
