//! The collision stage: candidate pairs per cell (DSMC-1), acceptance (DSMC-2), random
//! impact parameter and the shared collision law (HD-11 with normal restitution, the TC
//! rule with its counter: [`crate::collision_law`]). Rough grains take the same candidates,
//! acceptance and impact direction (their cross-section is that of smooth spheres: the
//! acceptance uses the relative velocity of the centres) and then RS-1 on their velocities
//! and angular velocities ([`crate::collision_law::rough::collide_pair`]).
//!
//! # Each cell's random stream
//!
//! Cell `c` of step `s` draws from SplitMix64 (Steele, Lea and Flood 2014; the generator
//! of `rand_xoshiro`) started at `K_s + 2^32 c phi`, where `K_s` is the hash of
//! `(seed, [DYNAMICS, s])` and `phi` SplitMix64's increment: its `j`-th number is the
//! SplitMix64 output of the counter `2^32 c + j`. Within a step no two cells share a
//! counter (a cell draws fewer than `2^32` numbers), and the step keys are independent
//! hashes, so the streams are those of independent generators; starting one costs an
//! addition and a multiplication (a Xoshiro256++ stream seeded per cell cost about 70
//! instructions, a third of a cell's collisions at 10 grains per cell).
//!
//! # The candidates' bound
//!
//! `v_max` of a cell (DSMC-2) is the diagonal of the box spanned by its velocities,
//! `sqrt(sum_k (max_i v_ik - min_i v_ik)^2)`, an upper bound of every `|v_i - v_j|` in the
//! cell taken in one pass (minima and maxima of each component).

use super::config::VmaxMode;
use super::grains::Columns;
use super::lattice::Lattice;
use crate::collision_law::{Body, CollisionLaw, normal_velocity_change};
use crate::random::{DYNAMICS, derive_key, unit_f64};
use crate::vector::Vector;
use rand::{Rng, SeedableRng};
use rand_xoshiro::SplitMix64;

/// Everything a cell needs to know that is the same for all cells of a step.
#[derive(Clone, Debug)]
pub(crate) struct StepParams {
    pub seed: u64,
    pub step: u64,
    /// Time at which collisions of this step happen (end of the free flight).
    pub time: f64,
    pub dt: f64,
    /// Cross-section `sigma` (4R in 2D, pi (2R)^2 in 3D; see `theory::haff::cross_section`).
    pub sigma: f64,
    pub radius: f64,
    pub cell_volume: f64,
    /// The collision law (pair restitution and TC rule).
    pub law: CollisionLaw,
    /// The grains as a rough collision sees them (mass, radius, κ; rough grains only).
    pub body: Body,
    pub vmax_mode: VmaxMode,
    pub global_vmax: f64,
    /// `Some(chi)` with a global packing fraction, `None` with the cell's own.
    pub enskog_global: Option<f64>,
    pub enskog_local: bool,
    pub free_volume: bool,
    pub grain_volume: f64,
    pub nu_rcp: f64,
    pub consistent_boltzmann: bool,
    pub impact_bins: usize,
    /// Box lengths and which axes are periodic, for the consistent-Boltzmann displacement.
    pub lengths: Vec<f64>,
    pub periodic: Vec<bool>,
}

/// Counters of one group of cells, summed in cell order by the engine.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Tally {
    pub collisions: u64,
    pub candidates: u64,
    pub vmax_exceeded: u64,
    pub impact: Vec<u64>,
    /// Collisions (pair and wall) made elastic by the TC rule.
    #[serde(default)]
    pub tc_elastic: u64,
}

impl Tally {
    pub fn add(&mut self, o: &Tally) {
        self.collisions += o.collisions;
        self.candidates += o.candidates;
        self.vmax_exceeded += o.vmax_exceeded;
        self.tc_elastic += o.tc_elastic;
        if self.impact.len() < o.impact.len() {
            self.impact.resize(o.impact.len(), 0);
        }
        for (a, b) in self.impact.iter_mut().zip(&o.impact) {
            *a += b;
        }
    }
}

/// Processes the consecutive cells `first_cell ..` of a group of grains (`cols`, the
/// group's columns), whose ranges within the group are `bounds[k] - bounds[0] ..
/// bounds[k + 1] - bounds[0]` for cell `first_cell + k`.
pub(crate) fn collide_group<const D: usize>(
    p: &StepParams,
    lattice: &Lattice<D>,
    first_cell: usize,
    bounds: &[u32],
    cols: &mut Columns<'_, D>,
) -> Tally {
    let mut tally = Tally {
        impact: vec![0; p.impact_bins],
        ..Tally::default()
    };
    // Smooth and rough grains each get their own copy of the kernel: the smooth one has
    // no rough code, so its registers are those of the kernel before rough grains.
    if cols.spin.is_some() {
        collide_cells::<D, true>(p, lattice, first_cell, bounds, cols, &mut tally);
    } else {
        collide_cells::<D, false>(p, lattice, first_cell, bounds, cols, &mut tally);
    }
    tally
}

/// The cells of [`collide_group`], with rough grains (`ROUGH`: `cols` has their angular
/// velocities) or smooth ones.
#[inline(always)]
fn collide_cells<const D: usize, const ROUGH: bool>(
    p: &StepParams,
    lattice: &Lattice<D>,
    first_cell: usize,
    bounds: &[u32],
    cols: &mut Columns<'_, D>,
    tally: &mut Tally,
) {
    let base = bounds[0] as usize;
    let step_key = derive_key(p.seed, &[DYNAMICS, p.step]);
    for k in 0..bounds.len() - 1 {
        let s = bounds[k] as usize - base;
        let e = bounds[k + 1] as usize - base;
        if e - s < 2 {
            continue;
        }
        let mut rng = CellStream::new(step_key, (first_cell + k) as u64);
        collide_cell::<D, ROUGH>(p, lattice, &mut rng, cols, s..e, tally);
    }
}

/// The random stream of one cell in one step (see the module docs).
pub(crate) struct CellStream(SplitMix64);

impl CellStream {
    /// SplitMix64's increment (the golden ratio).
    const PHI: u64 = 0x9E37_79B9_7F4A_7C15;

    /// The stream of cell `cell` in the step whose key is `step_key`.
    #[inline(always)]
    pub(crate) fn new(step_key: u64, cell: u64) -> Self {
        Self(SplitMix64::seed_from_u64(
            step_key.wrapping_add((cell << 32).wrapping_mul(Self::PHI)),
        ))
    }

    /// The next 64 random bits.
    #[inline(always)]
    pub(crate) fn bits(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// A uniform deviate in `[0, 1)` (53 bits).
    #[inline(always)]
    pub(crate) fn unit(&mut self) -> f64 {
        unit_f64(self.bits())
    }

    /// A uniform integer in `0 .. n` from the 32 random bits `x` (Lemire's multiply and
    /// shift; a rejection, with new bits, in the rare case that would bias it: with
    /// probability below `n / 2^32`). `n >= 1`.
    #[inline(always)]
    fn below(&mut self, x: u32, n: u32) -> u32 {
        let mut m = u64::from(x) * u64::from(n);
        if (m as u32) < n {
            let threshold = n.wrapping_neg() % n;
            while (m as u32) < threshold {
                m = (self.bits() >> 32) * u64::from(n);
            }
        }
        (m >> 32) as u32
    }

    /// A uniformly random ordered pair of distinct indices in `0 .. n` (`2 <= n < 2^32`)
    /// from one 64-bit draw (its halves).
    #[inline(always)]
    pub(crate) fn pair(&mut self, n: usize) -> (usize, usize) {
        let r = self.bits();
        let i = self.below((r >> 32) as u32, n as u32);
        let mut j = self.below(r as u32, n as u32 - 1);
        if j >= i {
            j += 1;
        }
        (i as usize, j as usize)
    }
}

/// `v_max` of the cell `range` (the box diagonal of its velocities, see the module docs):
/// infinite when a velocity is infinite (a NaN component is passed over; the acceptance
/// test never accepts a pair with a NaN relative speed).
#[inline(always)]
fn box_diagonal<const D: usize>(vel: &[&mut [f64]; D], range: std::ops::Range<usize>) -> f64 {
    let mut d2 = 0.0;
    for col in vel.iter() {
        let c = &col[range.clone()];
        // Two lanes (minpd/maxpd on two grains at a time), then the odd grain.
        let (pairs, rest) = c.as_chunks::<2>();
        let mut lo = [c[0]; 2];
        let mut hi = [c[0]; 2];
        for p in pairs {
            for t in 0..2 {
                lo[t] = if p[t] < lo[t] { p[t] } else { lo[t] };
                hi[t] = if p[t] > hi[t] { p[t] } else { hi[t] };
            }
        }
        for &x in rest {
            lo[0] = if x < lo[0] { x } else { lo[0] };
            hi[0] = if x > hi[0] { x } else { hi[0] };
        }
        let lo = if lo[1] < lo[0] { lo[1] } else { lo[0] };
        let hi = if hi[1] > hi[0] { hi[1] } else { hi[0] };
        d2 += (hi - lo) * (hi - lo);
    }
    d2.sqrt()
}

fn collide_cell<const D: usize, const ROUGH: bool>(
    p: &StepParams,
    lattice: &Lattice<D>,
    rng: &mut CellStream,
    cols: &mut Columns<'_, D>,
    range: std::ops::Range<usize>,
    tally: &mut Tally,
) {
    let (s, n) = (range.start, range.len());
    let mut vmax = match p.vmax_mode {
        VmaxMode::Cell => box_diagonal(&cols.vel, range),
        VmaxMode::Global => p.global_vmax,
    };
    // No relative motion, or an infinite velocity in the cell (reported by the engine
    // after the step; an infinite bound would draw endless candidates).
    if !(vmax > 0.0 && vmax.is_finite()) {
        return;
    }
    let nf = n as f64;
    let mut volume = p.cell_volume;
    if p.free_volume {
        // Effective free volume V_c - V_b / nu_rcp, kept at least 1% of V_c.
        volume = (volume - nf * p.grain_volume / p.nu_rcp).max(0.01 * p.cell_volume);
    }
    let chi = match p.enskog_global {
        Some(chi) => chi,
        None if p.enskog_local => {
            let phi = (nf * p.grain_volume / p.cell_volume).min(0.99);
            crate::theory::haff::contact_value(D, phi)
        }
        None => 1.0,
    };
    // DSMC-1 (with the cross-section of docs/dsmc.md), fractional part drawn stochastically.
    let expected = nf * (nf - 1.0) * p.sigma * vmax * p.dt * chi / (2.0 * volume);
    // `floor` by truncation (`expected >= 0`; a library call on baseline x86-64).
    let mut m = expected as i64 as u64;
    if rng.unit() < expected - m as f64 {
        m += 1;
    }
    tally.candidates += m;
    for _ in 0..m {
        let vel = &mut cols.vel;
        let (i, j) = rng.pair(n);
        let (i, j) = (s + i, s + j);
        let g = Vector::<D>(std::array::from_fn(|k| vel[k][i] - vel[k][j]));
        let g2 = g.norm_squared();
        let z = rng.unit();
        if g2 == 0.0 {
            continue;
        }
        let gm = g2.sqrt();
        if gm > vmax {
            vmax = gm;
            tally.vmax_exceeded += 1;
        }
        // DSMC-2: accept with probability |v_i - v_j| / v_max (never a NaN speed).
        if gm <= z * vmax || gm.is_nan() {
            continue;
        }
        let ghat = g * (1.0 / gm);
        // Impact parameter b / d uniform on the (D-1)-ball of radius 1.
        let (r2, normal) = impact(rng, &ghat);
        if ROUGH {
            rough_pair(p, cols, i, j, &normal, tally);
        } else {
            let gn = gm * (1.0 - r2).max(0.0).sqrt();
            // The TC rule (`last` is empty without it), then HD-11 with equal masses: the
            // normal relative velocity g.n changes by du, each grain takes half of it.
            let e = if cols.last.is_empty() {
                p.law.pair_restitution(p.time, &[], &mut tally.tc_elastic)
            } else {
                let last = &mut cols.last;
                let e = p
                    .law
                    .pair_restitution(p.time, &[last[i], last[j]], &mut tally.tc_elastic);
                last[i] = p.time;
                last[j] = p.time;
                e
            };
            let half = 0.5 * normal_velocity_change(e, gn);
            for k in 0..D {
                let dv = normal[k] * half;
                vel[k][i] += dv;
                vel[k][j] -= dv;
            }
        }
        tally.collisions += 1;
        if !tally.impact.is_empty() {
            let r = r2.sqrt();
            let b = ((r * tally.impact.len() as f64) as usize).min(tally.impact.len() - 1);
            tally.impact[b] += 1;
        }
        if p.consistent_boltzmann {
            // Each partner moves by 2R along its momentum change (-normal for i, +normal for j).
            let d = 2.0 * p.radius;
            displace(p, lattice, cols, i, &(normal * -d));
            displace(p, lattice, cols, j, &(normal * d));
        }
    }
}

/// A pair collision of rough grains `i` and `j` along the contact normal `normal` (from
/// `i` to `j`, which approach along it): the TC rule for both restitutions
/// ([`CollisionLaw::rough_pair_now`]), then RS-1 on the velocities and angular velocities.
/// Out of line, so that the smooth kernel stays as it was.
#[inline(never)]
fn rough_pair<const D: usize>(
    p: &StepParams,
    cols: &mut Columns<'_, D>,
    i: usize,
    j: usize,
    normal: &Vector<D>,
    tally: &mut Tally,
) {
    let (alpha, tangential) = if cols.last.is_empty() {
        p.law.rough_pair_now(p.time, &[], &mut tally.tc_elastic)
    } else {
        let last = &mut cols.last;
        let law = p
            .law
            .rough_pair_now(p.time, &[last[i], last[j]], &mut tally.tc_elastic);
        last[i] = p.time;
        last[j] = p.time;
        law
    };
    let Some(spin) = cols.spin.as_mut() else {
        return;
    };
    let vel = &mut cols.vel;
    let mut vi = Vector::<D>(std::array::from_fn(|k| vel[k][i]));
    let mut vj = Vector::<D>(std::array::from_fn(|k| vel[k][j]));
    let (mut wi, mut wj) = (spin.get(i), spin.get(j));
    crate::collision_law::rough::collide_pair(
        alpha, tangential, normal, &p.body, &p.body, &mut vi, &mut vj, &mut wi, &mut wj,
    );
    for k in 0..D {
        vel[k][i] = vi[k];
        vel[k][j] = vj[k];
    }
    spin.set(i, &wi);
    spin.set(j, &wj);
}

/// The contact normal of a pair with unit relative velocity `ghat` and a random impact
/// parameter (`b / 2R` uniform on the unit (D-1)-ball): returns `|b / 2R|^2` and
/// `n = ghat sqrt(1 - |b / 2R|^2) + b / 2R` (a unit vector).
#[inline(always)]
fn impact<const D: usize>(rng: &mut CellStream, ghat: &Vector<D>) -> (f64, Vector<D>) {
    if D == 2 {
        // b / 2R uniform on [-1, 1], along the perpendicular (-g_y, g_x).
        let s = 2.0 * rng.unit() - 1.0;
        let r2 = s * s;
        let c = (1.0 - r2).max(0.0).sqrt();
        let mut n = Vector::<D>::zero();
        n[0] = ghat[0] * c - ghat[1] * s;
        n[1] = ghat[1] * c + ghat[0] * s;
        (r2, n)
    } else {
        // A point (a, b) uniform on the unit disk (by rejection from the square, two
        // 32-bit halves of one draw), on an orthonormal basis (e1, e2) of the plane
        // perpendicular to ghat (Duff et al., "Building an orthonormal basis, revisited",
        // JCGT 6 (2017)).
        const HALF: f64 = 1.0 / 2_147_483_648.0;
        let (a, b, r2) = loop {
            let r = rng.bits();
            let a = ((r >> 32) as f64 + 0.5) * HALF - 1.0;
            let b = ((r & 0xFFFF_FFFF) as f64 + 0.5) * HALF - 1.0;
            let r2 = a * a + b * b;
            if r2 < 1.0 {
                break (a, b, r2);
            }
        };
        let (x, y, z) = (ghat[0], ghat[1], ghat[2]);
        let sign = 1.0f64.copysign(z);
        let h = -1.0 / (sign + z);
        let xy = x * y * h;
        let e1 = [1.0 + sign * x * x * h, sign * xy, -sign * x];
        let e2 = [xy, sign + y * y * h, -y];
        let c = (1.0 - r2).max(0.0).sqrt();
        let mut n = Vector::<D>::zero();
        for k in 0..3 {
            n[k] = ghat[k] * c + a * e1[k] + b * e2[k];
        }
        (r2, n)
    }
}

/// Moves grain `i` by `d` (the consistent-Boltzmann displacement), back into the box:
/// periodic wrap, or mirror at a wall. Computed in box coordinates; the identity bits of
/// the words are kept.
fn displace<const D: usize>(
    p: &StepParams,
    lattice: &Lattice<D>,
    cols: &mut Columns<'_, D>,
    i: usize,
    d: &Vector<D>,
) {
    let old: [u64; D] = std::array::from_fn(|k| cols.pos[k][i]);
    let mut x = lattice.position(&old) + *d;
    fold(p, &mut x);
    let keep = !lattice.position_mask();
    for k in 0..D {
        cols.pos[k][i] = lattice.word(k, x[k]) | (old[k] & keep);
    }
}

/// Puts a displaced position back into the box: periodic wrap, or mirror at a wall.
fn fold<const D: usize>(p: &StepParams, x: &mut Vector<D>) {
    for k in 0..D {
        let l = p.lengths[k];
        if p.periodic[k] {
            x[k] = x[k].rem_euclid(l);
            if x[k] >= l {
                x[k] = 0.0;
            }
        } else {
            if x[k] < 0.0 {
                x[k] = -x[k];
            }
            if x[k] > l {
                x[k] = 2.0 * l - x[k];
            }
            x[k] = x[k].clamp(0.0, l);
        }
    }
}
