//! The collision stage: candidate pairs per cell (DSMC-1), acceptance (DSMC-2), random
//! impact parameter and the shared collision law (HD-11 with normal restitution, the TC
//! rule with its counter: [`crate::collision_law`]).

use super::config::VmaxMode;
use crate::collision_law::{CollisionLaw, normal_velocity_change};
use crate::random::{
    DYNAMICS, RngExt, Stream, derive_key, extend_key, std_normal, stream_from_key, uniform_index,
};
use crate::vector::Vector;

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

/// Processes the consecutive cells `first_cell ..` whose particle ranges (relative to the
/// slices) are given by `bounds` (`bounds[k] .. bounds[k + 1]` for cell `first_cell + k`).
pub(crate) fn collide_group<const D: usize>(
    p: &StepParams,
    first_cell: usize,
    bounds: &[u32],
    pos: &mut [Vector<D>],
    vel: &mut [Vector<D>],
    last: &mut [f64],
) -> Tally {
    let mut tally = Tally {
        impact: vec![0; p.impact_bins],
        ..Tally::default()
    };
    let base = bounds[0] as usize;
    // The streams' common prefix `[DYNAMICS, step]`, hashed once per group.
    let step_key = derive_key(p.seed, &[DYNAMICS, p.step]);
    for k in 0..bounds.len() - 1 {
        let s = bounds[k] as usize - base;
        let e = bounds[k + 1] as usize - base;
        if e - s < 2 {
            continue;
        }
        let cell = (first_cell + k) as u64;
        // The cell's stream, `stream(seed, &[DYNAMICS, step, cell])`.
        let mut rng = stream_from_key(extend_key(step_key, cell));
        let last_c = if last.is_empty() {
            &mut [][..]
        } else {
            &mut last[s..e]
        };
        collide_cell(
            p,
            &mut rng,
            &mut pos[s..e],
            &mut vel[s..e],
            last_c,
            &mut tally,
        );
    }
    tally
}

/// `2 max_i |v_i - u|`, `u` the mean of `v`: an upper bound of every `|v_i - v_j|`.
pub(crate) fn relative_speed_bound<const D: usize>(v: &[Vector<D>]) -> f64 {
    let mut u = Vector::<D>::zero();
    for x in v {
        u += *x;
    }
    u = u * (1.0 / v.len() as f64);
    let mut m2: f64 = 0.0;
    for x in v {
        // `m2.max(d)`: `d >= 0` is never a negative zero and `m2` never NaN, so the
        // comparison (one `maxsd`) gives the same value, NaN `d` skipped as by `max`.
        let d = (*x - u).norm_squared();
        m2 = if d > m2 { d } else { m2 };
    }
    2.0 * m2.sqrt()
}

fn collide_cell<const D: usize>(
    p: &StepParams,
    rng: &mut Stream,
    pos: &mut [Vector<D>],
    vel: &mut [Vector<D>],
    last: &mut [f64],
    tally: &mut Tally,
) {
    let n = vel.len();
    let mut vmax = match p.vmax_mode {
        VmaxMode::Cell => relative_speed_bound(vel),
        VmaxMode::Global => p.global_vmax,
    };
    // No relative motion, or a non-finite velocity in the cell (reported by the engine
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
    let whole = expected.floor();
    let mut m = whole as u64;
    if rng.random::<f64>() < expected - whole {
        m += 1;
    }
    tally.candidates += m;
    let d = 2.0 * p.radius;
    for _ in 0..m {
        // `random_range(0..n)` and `random_range(0..n - 1)`, inlined.
        let i = uniform_index(rng, n);
        let mut j = uniform_index(rng, n - 1);
        if j >= i {
            j += 1;
        }
        let g = vel[i] - vel[j];
        let g2 = g.norm_squared();
        let z = rng.random::<f64>();
        if g2 == 0.0 {
            continue;
        }
        let gm = g2.sqrt();
        if gm > vmax {
            vmax = gm;
            tally.vmax_exceeded += 1;
        }
        // DSMC-2: accept with probability |v_i - v_j| / v_max.
        if gm <= z * vmax {
            continue;
        }
        let ghat = g * (1.0 / gm);
        // Impact parameter b / d uniform on the (D-1)-ball of radius 1, direction e_perp.
        let (r, eperp) = impact(rng, &ghat);
        let cos = (1.0 - r * r).max(0.0).sqrt();
        let normal = ghat * cos + eperp * r;
        let gn = gm * cos;
        // The TC rule (`last` is empty without it), then HD-11 with equal masses: the
        // normal relative velocity g.n changes by du, each grain takes half of it.
        let e = if last.is_empty() {
            p.law.pair_restitution(p.time, &[], &mut tally.tc_elastic)
        } else {
            let e = p
                .law
                .pair_restitution(p.time, &[last[i], last[j]], &mut tally.tc_elastic);
            last[i] = p.time;
            last[j] = p.time;
            e
        };
        let half = normal * (0.5 * normal_velocity_change(e, gn));
        vel[i] += half;
        vel[j] -= half;
        tally.collisions += 1;
        if !tally.impact.is_empty() {
            let b = ((r * tally.impact.len() as f64) as usize).min(tally.impact.len() - 1);
            tally.impact[b] += 1;
        }
        if p.consistent_boltzmann {
            // Each partner moves by 2R along its momentum change (-normal for i, +normal for j).
            pos[i] = pos[i].add_scaled(-d, &normal);
            pos[j] = pos[j].add_scaled(d, &normal);
            fold(p, &mut pos[i]);
            fold(p, &mut pos[j]);
        }
    }
}

/// Random impact parameter: returns `|b| / 2R` and a unit vector perpendicular to `ghat`.
#[inline]
fn impact<const D: usize>(rng: &mut Stream, ghat: &Vector<D>) -> (f64, Vector<D>) {
    if D == 2 {
        // b uniform on [-2R, 2R]: |b| uniform, sign from the perpendicular's orientation.
        let s = 2.0 * rng.random::<f64>() - 1.0;
        let mut e = Vector::<D>::zero();
        e[0] = -ghat[1] * s.signum();
        e[1] = ghat[0] * s.signum();
        (s.abs(), e)
    } else {
        // b uniform on the disk (ball) of radius 2R: |b|/2R = u^(1/(D-1)), isotropic direction.
        loop {
            let mut w = Vector::<D>::zero();
            for k in 0..D {
                // The crate's ziggurat: bit for bit `rand_distr::StandardNormal`.
                w[k] = std_normal(rng);
            }
            let w = w.add_scaled(-w.dot(ghat), ghat);
            let wn = w.norm();
            if wn > 1e-12 {
                let u: f64 = rng.random::<f64>();
                let r = if D == 3 {
                    u.sqrt()
                } else {
                    u.powf(1.0 / (D as f64 - 1.0))
                };
                return (r, w * (1.0 / wn));
            }
        }
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
