//! Non-overlapping placements: random sequential (with a cell grid for the overlap tests)
//! and lattice.

use super::{InitError, Region, ball_volume, packing_fraction};
use crate::boundary::SimulationBox;
use crate::random::{RngExt, Stream};
use crate::vector::Vector;

/// Uniform grid used to test overlaps during placement.
struct PlacementGrid<const D: usize> {
    counts: [usize; D],
    width: [f64; D],
    cells: Vec<Vec<u32>>,
}

impl<const D: usize> PlacementGrid<D> {
    fn new(bx: &SimulationBox<D>, min_width: f64, n: usize) -> Self {
        let mut counts = [1; D];
        let mut width = [0.0; D];
        let budget = (4 * n).max(1) as f64;
        let mut cell = min_width;
        loop {
            let total: f64 = (0..D)
                .map(|k| (bx.lengths[k] / cell).floor().max(1.0))
                .product();
            if total <= budget {
                break;
            }
            cell *= 1.5;
        }
        for k in 0..D {
            counts[k] = ((bx.lengths[k] / cell).floor() as usize).max(1);
            width[k] = bx.lengths[k] / counts[k] as f64;
        }
        Self {
            counts,
            width,
            cells: vec![Vec::new(); counts.iter().product()],
        }
    }

    fn coord(&self, x: &Vector<D>, k: usize) -> i64 {
        ((x[k] / self.width[k]).floor() as i64).clamp(0, self.counts[k] as i64 - 1)
    }

    fn flat(&self, c: &[i64; D]) -> usize {
        let mut f = 0usize;
        for k in (0..D).rev() {
            f = f * self.counts[k] + c[k] as usize;
        }
        f
    }

    fn insert(&mut self, x: &Vector<D>, i: usize) {
        let mut c = [0i64; D];
        for (k, ck) in c.iter_mut().enumerate() {
            *ck = self.coord(x, k);
        }
        let f = self.flat(&c);
        self.cells[f].push(i as u32);
    }

    /// Whether a grain at `x` with radius `r` overlaps any placed grain (reach: how many
    /// cells around to search).
    fn overlaps(
        &self,
        bx: &SimulationBox<D>,
        x: &Vector<D>,
        r: f64,
        reach: f64,
        pos: &[Vector<D>],
        radii: &[f64],
    ) -> bool {
        let mut lo = [0i64; D];
        let mut hi = [0i64; D];
        for k in 0..D {
            let span = (reach / self.width[k]).ceil() as i64;
            let c = self.coord(x, k);
            let n = self.counts[k] as i64;
            if bx.is_periodic(k) && 2 * span + 1 >= n {
                lo[k] = 0;
                hi[k] = n - 1;
            } else {
                lo[k] = c - span;
                hi[k] = c + span;
                if !bx.is_periodic(k) {
                    lo[k] = lo[k].max(0);
                    hi[k] = hi[k].min(n - 1);
                }
            }
        }
        let mut idx = lo;
        loop {
            let mut c = [0i64; D];
            for k in 0..D {
                c[k] = idx[k].rem_euclid(self.counts[k] as i64);
            }
            for &j in &self.cells[self.flat(&c)] {
                let j = j as usize;
                let d2 = bx.separation(x, &pos[j]).norm_squared();
                let s = r + radii[j];
                if d2 < s * s {
                    return true;
                }
            }
            let mut k = 0;
            loop {
                if k == D {
                    return false;
                }
                idx[k] += 1;
                if idx[k] <= hi[k] {
                    break;
                }
                idx[k] = lo[k];
                k += 1;
            }
        }
    }
}

/// Random sequential placement: grains (largest first) are put at uniformly random
/// positions in `region`, and a position that overlaps an already placed grain or a wall
/// is redrawn, up to `max_attempts` times per grain. Works up to packing fractions of about
/// 0.45 (2D) and 0.3 (3D); beyond, use a lattice or compression.
pub fn random_placement<const D: usize>(
    bx: &SimulationBox<D>,
    region: &Region<D>,
    radii: &[f64],
    existing: &[(Vector<D>, f64)],
    rng: &mut Stream,
    max_attempts: usize,
) -> Result<Vec<Vector<D>>, InitError> {
    let n = radii.len();
    // Two grids: one sized for the grains placed now, one for the existing grains larger
    // than all of them (a projectile above a bed). A single grid sized for the largest
    // grain made every test of a small grain scan hundreds of cells (10^5 bed grains
    // under a 22 times larger projectile: 26 s instead of a fraction of one).
    let r_new = radii.iter().cloned().fold(0.0, f64::max);
    let r_big = existing
        .iter()
        .map(|&(_, r)| r)
        .filter(|&r| r > r_new)
        .fold(0.0, f64::max);
    let n_big = existing.iter().filter(|&&(_, r)| r > r_new).count();
    let mut grid = PlacementGrid::new(bx, 2.0 * r_new.max(1e-300), n + existing.len() - n_big);
    let mut big_grid = PlacementGrid::new(bx, 2.0 * r_big.max(1e-300), n_big.max(1));
    let mut all_pos: Vec<Vector<D>> = Vec::with_capacity(n + existing.len());
    let mut all_r: Vec<f64> = Vec::with_capacity(n + existing.len());
    for (x, r) in existing {
        if *r > r_new {
            big_grid.insert(x, all_pos.len());
        } else {
            grid.insert(x, all_pos.len());
        }
        all_pos.push(*x);
        all_r.push(*r);
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]).then(a.cmp(&b)));
    let mut out = vec![Vector::zero(); n];
    // What the region holds in the end, grains placed before (of other species) included.
    let before: f64 = existing
        .iter()
        .filter(|(x, _)| (0..D).all(|k| region.lo[k] <= x[k] && x[k] <= region.hi[k]))
        .map(|&(_, r)| ball_volume::<D>(r))
        .sum();
    let phi = packing_fraction::<D>(radii, region.volume()) + before / region.volume();
    for (placed, &i) in order.iter().enumerate() {
        let r = radii[i];
        let mut ranges = [(0.0, 0.0); D];
        for (k, range) in ranges.iter_mut().enumerate() {
            *range = region.centre_range(bx, k, r);
            if range.1 < range.0 {
                return Err(InitError::DoesNotFit {
                    radius: r,
                    lo: region.lo.0.to_vec(),
                    hi: region.hi.0.to_vec(),
                });
            }
        }
        let mut ok = false;
        for _ in 0..max_attempts {
            let mut x = Vector::zero();
            for k in 0..D {
                x[k] = ranges[k].0 + (ranges[k].1 - ranges[k].0) * rng.random::<f64>();
            }
            bx.wrap(&mut x);
            if !grid.overlaps(bx, &x, r, r + r_new, &all_pos, &all_r)
                && (n_big == 0 || !big_grid.overlaps(bx, &x, r, r + r_big, &all_pos, &all_r))
            {
                grid.insert(&x, all_pos.len());
                all_pos.push(x);
                all_r.push(r);
                out[i] = x;
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(InitError::Placement {
                placed_plus_one: placed + 1,
                total: n,
                attempts: max_attempts,
                packing_fraction: phi,
            });
        }
    }
    Ok(out)
}

/// A simple square (cubic) lattice filling a region, row by row (axis 0 fastest): the
/// spacing is the largest that holds `n` sites. Site `j` is computed on its own
/// ([`Lattice::site`]), so a rank of a decomposed DSMC run places only its own grains.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Lattice<const D: usize> {
    counts: [usize; D],
    offsets: [f64; D],
    steps: [f64; D],
    /// The smallest spacing between sites.
    pub spacing: f64,
}

impl<const D: usize> Lattice<D> {
    /// The lattice of `n` sites for grains of radius up to `r_max` in `region`. Fails if
    /// its spacing is smaller than a diameter.
    pub(crate) fn new(
        bx: &SimulationBox<D>,
        region: &Region<D>,
        n: usize,
        r_max: f64,
    ) -> Result<Lattice<D>, InitError> {
        let mut extent = [0.0; D];
        for (k, e) in extent.iter_mut().enumerate() {
            let (a, b) = region.centre_range(bx, k, r_max);
            let periodic_whole = bx.is_periodic(k) && a == 0.0 && b == bx.lengths[k];
            // On a periodic whole axis the last site must not touch the first one's image.
            *e = if periodic_whole {
                b - a
            } else {
                (b - a).max(0.0)
            };
        }
        // Choose sites per axis proportional to extents so that spacing is as large as
        // possible.
        let mut counts = [1usize; D];
        let volume: f64 = extent.iter().map(|e| e.max(1e-300)).product();
        let a0 = (volume / n.max(1) as f64).powf(1.0 / D as f64);
        for k in 0..D {
            counts[k] = ((extent[k] / a0).floor() as usize).max(1);
        }
        while counts.iter().product::<usize>() < n {
            // Add a row along the axis whose spacing is currently the largest.
            let k = (0..D)
                .max_by(|&a, &b| {
                    (extent[a] / counts[a] as f64).total_cmp(&(extent[b] / counts[b] as f64))
                })
                .unwrap_or(0);
            counts[k] += 1;
        }
        let mut spacing = f64::INFINITY;
        let mut offsets = [0.0; D];
        let mut steps = [0.0; D];
        for k in 0..D {
            let (a, b) = region.centre_range(bx, k, r_max);
            let periodic_whole = bx.is_periodic(k) && a == 0.0 && b == bx.lengths[k];
            if periodic_whole {
                steps[k] = (b - a) / counts[k] as f64;
                offsets[k] = a + 0.5 * steps[k];
            } else if counts[k] == 1 {
                steps[k] = f64::INFINITY;
                offsets[k] = 0.5 * (a + b);
            } else {
                steps[k] = (b - a) / (counts[k] - 1) as f64;
                offsets[k] = a;
            }
            spacing = spacing.min(steps[k]);
        }
        if spacing < 2.0 * r_max {
            return Err(InitError::Lattice {
                n,
                radius: r_max,
                spacing,
            });
        }
        Ok(Lattice {
            counts,
            offsets,
            steps,
            spacing,
        })
    }

    /// Site `j` (`0 ..`), row by row with axis 0 fastest.
    pub(crate) fn site(&self, j: usize) -> Vector<D> {
        let mut x = Vector::zero();
        let mut rest = j;
        for k in 0..D {
            let i = rest % self.counts[k];
            rest /= self.counts[k];
            let step = if self.steps[k].is_finite() {
                self.steps[k]
            } else {
                0.0
            };
            x[k] = self.offsets[k] + i as f64 * step;
        }
        x
    }
}

/// Places grains on a simple square (cubic) lattice filling `region`, row by row; the
/// spacing is the largest that holds all grains. Fails if it is smaller than a diameter.
pub fn lattice_placement<const D: usize>(
    bx: &SimulationBox<D>,
    region: &Region<D>,
    radii: &[f64],
) -> Result<Vec<Vector<D>>, InitError> {
    let n = radii.len();
    let r_max = radii.iter().cloned().fold(0.0, f64::max);
    let lattice = Lattice::new(bx, region, n, r_max)?;
    Ok((0..n).map(|j| lattice.site(j)).collect())
}
