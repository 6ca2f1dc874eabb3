//! Initial states: non-overlapping placements (random, lattice), compression to dense
//! states with the event engine itself (Lubachevsky-Stillinger), and velocity
//! distributions.

use super::engine::{Edmd, EdmdOptions, ParticleSet};
use crate::boundary::SimulationBox;
use crate::collision_law::CollisionLaw;
use crate::engine::{Engine, Progress};
use crate::random::{RngExt, Stream};
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};

/// Why an initial state could not be built.
#[derive(Debug, thiserror::Error)]
pub enum InitError {
    /// Random sequential placement ran out of attempts.
    #[error(
        "could not place grain {placed_plus_one} of {total} without overlap after {attempts} random attempts \
         (packing fraction {packing_fraction:.3} of the region, with the grains placed before, is too high for random placement); \
         use placement = \"lattice\", or initial.compress_from (random placement at a lower density, then compression)"
    )]
    Placement {
        /// One-based index of the grain that did not fit.
        placed_plus_one: usize,
        /// Number of grains to place.
        total: usize,
        /// Attempts made for that grain.
        attempts: usize,
        /// Packing fraction of the region once all grains are placed (those placed before
        /// in the region included).
        packing_fraction: f64,
    },
    /// A grain is larger than the region that should hold it.
    #[error(
        "a grain of radius {radius} does not fit in the region {lo:?}..{hi:?} (its diameter exceeds the region's width)"
    )]
    DoesNotFit {
        /// Radius of the grain.
        radius: f64,
        /// Region lower corner.
        lo: Vec<f64>,
        /// Region upper corner.
        hi: Vec<f64>,
    },
    /// The lattice does not have room for the grains.
    #[error(
        "{n} grains of radius up to {radius} do not fit on a lattice in the region (spacing {spacing:.4} < diameter); \
         enlarge the region or reduce the number or size of grains"
    )]
    Lattice {
        /// Number of grains.
        n: usize,
        /// Largest radius.
        radius: f64,
        /// Lattice spacing.
        spacing: f64,
    },
    /// Compression jammed before reaching the target.
    #[error(
        "compression stopped at packing fraction {reached:.4} before the target {target:.4}: the grains jammed; \
         lower the target or the compression rate"
    )]
    Jammed {
        /// Packing fraction reached.
        reached: f64,
        /// Target packing fraction.
        target: f64,
    },
}

/// Volume of a `D`-ball of radius `r` (area of a disk in 2D).
pub fn ball_volume<const D: usize>(r: f64) -> f64 {
    match D {
        1 => 2.0 * r,
        2 => std::f64::consts::PI * r * r,
        3 => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
        _ => {
            let d = D as f64;
            std::f64::consts::PI.powf(d / 2.0) / libm::tgamma(d / 2.0 + 1.0) * r.powf(d)
        }
    }
}

/// Packing fraction of grains of the given radii in a region of the given volume.
pub fn packing_fraction<const D: usize>(radii: &[f64], volume: f64) -> f64 {
    radii.iter().map(|&r| ball_volume::<D>(r)).sum::<f64>() / volume
}

/// Region of the box where grains are placed: `[lo, hi]` per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Region<const D: usize> {
    /// Lower corner.
    pub lo: Vector<D>,
    /// Upper corner.
    pub hi: Vector<D>,
}

impl<const D: usize> Region<D> {
    /// The whole box.
    pub fn whole(bx: &SimulationBox<D>) -> Self {
        Self {
            lo: Vector::zero(),
            hi: bx.lengths,
        }
    }

    /// Volume of the region.
    pub fn volume(&self) -> f64 {
        (0..D).map(|k| self.hi[k] - self.lo[k]).product()
    }

    /// Range of admissible centres for a grain of radius `r` along axis `k`: the region
    /// shrunk by `r`, except across periodic faces of the box that the region touches.
    fn centre_range(&self, bx: &SimulationBox<D>, k: usize, r: f64) -> (f64, f64) {
        let whole = self.lo[k] <= 0.0 && self.hi[k] >= bx.lengths[k];
        if bx.is_periodic(k) && whole {
            (0.0, bx.lengths[k])
        } else {
            (self.lo[k] + r, self.hi[k] - r)
        }
    }
}

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

/// Places grains on a simple square (cubic) lattice filling `region`, row by row; the
/// spacing is the largest that holds all grains. Fails if it is smaller than a diameter.
pub fn lattice_placement<const D: usize>(
    bx: &SimulationBox<D>,
    region: &Region<D>,
    radii: &[f64],
) -> Result<Vec<Vector<D>>, InitError> {
    let n = radii.len();
    let r_max = radii.iter().cloned().fold(0.0, f64::max);
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
    // Choose sites per axis proportional to extents so that spacing is as large as possible.
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
    let mut out = Vec::with_capacity(n);
    let mut idx = [0usize; D];
    for _ in 0..n {
        let mut x = Vector::zero();
        for k in 0..D {
            x[k] = offsets[k] + idx[k] as f64 * if steps[k].is_finite() { steps[k] } else { 0.0 };
        }
        out.push(x);
        let mut k = 0;
        while k < D {
            idx[k] += 1;
            if idx[k] < counts[k] {
                break;
            }
            idx[k] = 0;
            k += 1;
        }
    }
    Ok(out)
}

/// Velocities of magnitude `speed` in uniformly random directions (Problem 1 of the seed:
/// `v = v0 (cos θ, sin θ)` with θ uniform; in 3D uniform on the sphere).
pub fn fixed_speed<const D: usize>(n: usize, speed: f64, rng: &mut Stream) -> Vec<Vector<D>> {
    (0..n)
        .map(|_| {
            if D == 2 {
                let theta = 2.0 * std::f64::consts::PI * rng.random::<f64>();
                let mut v = Vector::zero();
                v[0] = speed * theta.cos();
                v[1] = speed * theta.sin();
                v
            } else {
                loop {
                    let mut v = Vector::zero();
                    for k in 0..D {
                        v[k] = StandardNormal.sample(rng);
                    }
                    let norm = v.norm();
                    if norm > 0.0 {
                        break v * (speed / norm);
                    }
                }
            }
        })
        .collect()
}

/// Maxwell-Boltzmann velocities at temperature `temperature` (`k_B = 1`): each component
/// Gaussian with variance `T / m_i`.
pub fn maxwell_boltzmann<const D: usize>(
    masses: &[f64],
    temperature: f64,
    rng: &mut Stream,
) -> Vec<Vector<D>> {
    masses
        .iter()
        .map(|&m| {
            let s = (temperature / m).sqrt();
            let mut v = Vector::zero();
            for k in 0..D {
                let z: f64 = StandardNormal.sample(rng);
                v[k] = s * z;
            }
            v
        })
        .collect()
}

/// Removes the centre-of-mass velocity so that the total momentum vanishes.
pub fn remove_drift<const D: usize>(velocities: &mut [Vector<D>], masses: &[f64]) {
    let total: f64 = masses.iter().sum();
    if total <= 0.0 {
        return;
    }
    let mut p = Vector::<D>::zero();
    for (v, &m) in velocities.iter().zip(masses) {
        p = p.add_scaled(m, v);
    }
    let drift = p * (1.0 / total);
    for v in velocities.iter_mut() {
        *v -= drift;
    }
}

/// Lubachevsky-Stillinger compression: the grains, given at radii `radii * scale^-1`
/// (non-overlapping), grow uniformly with the event engine itself until their radii reach
/// `radii`. Velocities are rescaled to temperature 1 every collision per grain (growth
/// heats the gas). Returns positions at the end; velocities are left to the caller.
pub fn compress<const D: usize>(
    bx: &SimulationBox<D>,
    mut particles: ParticleSet<D>,
    final_radii: &[f64],
    rng: &mut Stream,
) -> Result<Vec<Vector<D>>, InitError> {
    let n = particles.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let scale = final_radii[0] / particles.radii[0];
    let target = packing_fraction::<D>(final_radii, bx.volume());
    particles.velocities = maxwell_boltzmann::<D>(&particles.masses, 1.0, rng);
    remove_drift(&mut particles.velocities, &particles.masses);
    let r_max = particles.radii.iter().cloned().fold(0.0, f64::max);
    let m_min = particles
        .masses
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    // Contact distances grow at 2% of the thermal speed: slow enough to stay near
    // equilibrium, fast enough to take a few hundred collisions per grain.
    let growth = 0.01 * (1.0 / m_min).sqrt() / r_max;
    let t_final = (scale - 1.0) / growth;
    let mut engine = Edmd::with_growth(
        bx.clone(),
        particles,
        CollisionLaw::default(),
        EdmdOptions::default(),
        growth,
        scale,
    );
    let chunk = n as u64;
    let budget = 20_000 * n as u64 + 1_000_000;
    let mut used = 0u64;
    loop {
        let progress = engine
            .advance(t_final, chunk)
            .map_err(|_| InitError::Jammed {
                reached: packing_fraction::<D>(&engine.radii(), bx.volume()),
                target,
            })?;
        used += chunk;
        let k = engine.kinetic_energy_now();
        let t_now = 2.0 * k / (D as f64 * n as f64);
        if t_now > 0.0 {
            engine.scale_velocities((1.0 / t_now).sqrt());
        }
        if progress == Progress::Reached {
            break;
        }
        if used > budget {
            return Err(InitError::Jammed {
                reached: packing_fraction::<D>(&engine.radii(), bx.volume()),
                target,
            });
        }
    }
    engine.freeze_growth();
    Ok(engine.particle_set().positions)
}
