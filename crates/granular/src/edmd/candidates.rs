//! The earliest pair contact among a prediction's candidates, and the grain record it
//! reads.
//!
//! A prediction tests every grain of the neighbouring cells (8 in dense 2D, 25 in 3D),
//! each test a square root and a division. With many candidates (3D) the tests run four
//! at a time in AVX2 registers (checked at run time; `avx2::earliest_contact`), otherwise
//! one at a time. Both paths do the same operations in the same order (no fused
//! multiply-add), so they give the same contact times to the last bit (tested).

use super::cells::NONE;
use crate::boundary::SimulationBox;
use crate::vector::Vector;
use serde::{Deserialize, Serialize};

/// The state of one grain that every prediction reads, in one record (48 bytes for disks,
/// one 64-byte cache line for spheres): position and velocity valid at the grain's own
/// clock `time`, its collision counter, and its kind (radius, mass, species).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub(super) struct Grain<const D: usize> {
    pub pos: Vector<D>,
    pub vel: Vector<D>,
    pub time: f64,
    /// Collisions so far (wrapping): a pair event is stale when its partner's counter
    /// changed. A stale event would be taken for valid only after exactly 2^32 collisions
    /// of the partner before the event time, which the event order excludes.
    pub counter: u32,
    pub kind: u32,
}

/// What the search needs to know about the predicted grain and the box.
pub(super) struct Probe<'a, const D: usize> {
    /// The predicted grain's slot (skipped among the candidates).
    pub slot: u32,
    /// A candidate to skip as well (the partner it has just collided with, when that
    /// partner's last partner is this grain), or `NONE`.
    pub skip: u32,
    /// Position and velocity at the current time `now`.
    pub pos: Vector<D>,
    pub vel: Vector<D>,
    pub radius: f64,
    pub now: f64,
    /// Uniform acceleration, if any.
    pub gravity: Option<Vector<D>>,
    /// The box (minimum image on its periodic axes).
    pub bx: &'a SimulationBox<D>,
    /// Whether a candidate may be nearer through a periodic face than directly, so that
    /// the minimum image must be taken; `false` (`CellGrid::without_wrap`) lets the
    /// search skip it (the plain difference is then the minimum image: same values).
    pub wrap: bool,
}

/// Fewest candidates for which the packed (AVX2) search is used. Measured (collisions per
/// CPU second, whole engine): with the 25 candidates of dense 3D it is 11-18 % faster (3D
/// N = 10^5, φ = 0.45); for all 8 of dense 2D it was 6-8 % slower (the lanes are filled
/// and emptied one value at a time, and eight one-candidate chains already overlap in
/// the processor), so 2D predictions keep the one-at-a-time path.
pub(super) const PACKED_MIN: usize = 12;

/// The candidate (slot) with the earliest contact strictly before `limit` and its time
/// from now, or `(limit, NONE)`. Ties go to the first candidate in `candidates`. Radii do
/// not grow (Lubachevsky-Stillinger compression takes the one-candidate path).
#[inline]
pub(super) fn earliest_contact<const D: usize>(
    grains: &[Grain<D>],
    kind_radius: &[f64],
    candidates: &[u32],
    probe: &Probe<'_, D>,
    limit: f64,
) -> (f64, u32) {
    #[cfg(target_arch = "x86_64")]
    if candidates.len() >= PACKED_MIN && std::arch::is_x86_feature_detected!("avx2") {
        #[allow(unsafe_code)]
        // SAFETY: the only requirement of a `#[target_feature]` function is that the
        // processor has the feature, checked on the line above.
        return unsafe {
            if probe.wrap {
                avx2::earliest_contact::<D, true>(grains, kind_radius, candidates, probe, limit)
            } else {
                avx2::earliest_contact::<D, false>(grains, kind_radius, candidates, probe, limit)
            }
        };
    }
    earliest_contact_scalar(grains, kind_radius, candidates, probe, limit)
}

/// [`earliest_contact`] one candidate at a time (any processor).
#[inline(always)]
pub(super) fn earliest_contact_scalar<const D: usize>(
    grains: &[Grain<D>],
    kind_radius: &[f64],
    candidates: &[u32],
    probe: &Probe<'_, D>,
    limit: f64,
) -> (f64, u32) {
    if probe.wrap {
        scalar_search::<D, true>(grains, kind_radius, candidates, probe, limit)
    } else {
        scalar_search::<D, false>(grains, kind_radius, candidates, probe, limit)
    }
}

/// [`earliest_contact_scalar`], with the minimum image (`WRAP`) or without.
#[inline(always)]
fn scalar_search<const D: usize, const WRAP: bool>(
    grains: &[Grain<D>],
    kind_radius: &[f64],
    candidates: &[u32],
    probe: &Probe<'_, D>,
    limit: f64,
) -> (f64, u32) {
    let half = half_lengths(probe.bx);
    let mut best = limit;
    let mut partner = NONE;
    for &j in candidates {
        if j == probe.slot || j == probe.skip {
            continue;
        }
        let g = &grains[j as usize];
        let dt = probe.now - g.time;
        let mut xj = g.pos.add_scaled(dt, &g.vel);
        let mut vj = g.vel;
        if let Some(gravity) = &probe.gravity {
            xj = xj.add_scaled(0.5 * dt * dt, gravity);
            vj = vj.add_scaled(dt, gravity);
        }
        // Minimum image as in `SimulationBox::separation`, with the half lengths computed
        // once per prediction rather than per candidate (2 % of the engine at 2D 10^4).
        // The packed lanes compute the same values as `d - 1 L`, `d + 1 L` or `d - 0 + 0`.
        let mut dx = xj - probe.pos;
        for k in 0..D {
            if !WRAP {
                break;
            }
            if dx[k] > half[k] {
                dx[k] -= probe.bx.lengths[k];
            } else if dx[k] < -half[k] {
                dx[k] += probe.bx.lengths[k];
            }
        }
        let dv = vj - probe.vel;
        // `pair_contact_time` without growth, written without unpredictable branches (the
        // sign of `b` is a coin toss for neighbours): every candidate costs a square root
        // and a division, which pipeline, instead of a mispredicted branch. Same
        // arithmetic, so the same times.
        let sigma = probe.radius + kind_radius[g.kind as usize];
        let b = dx.dot(&dv);
        let c = dx.norm_squared() - sigma * sigma;
        let d = b * b - dv.norm_squared() * c;
        let root = (c / (-b + d.max(0.0).sqrt())).max(0.0);
        let t = if b < 0.0 && d > 0.0 {
            root
        } else {
            f64::INFINITY
        };
        if t < best {
            best = t;
            partner = j;
        }
    }
    (best, partner)
}

/// Half the box length on periodic axes (beyond it the minimum image wraps, as in
/// [`SimulationBox::separation`]), infinity on walled axes.
fn half_lengths<const D: usize>(bx: &SimulationBox<D>) -> [f64; D] {
    std::array::from_fn(|k| {
        if bx.is_periodic(k) {
            0.5 * bx.lengths[k]
        } else {
            f64::INFINITY
        }
    })
}

/// The same search four candidates at a time with AVX2 (no fused multiply-add: every
/// operation rounds as in the scalar path).
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Grain, NONE, Probe, half_lengths};
    use std::arch::x86_64::*;

    /// Four values as one register (lane `l` = `a[l]`).
    #[target_feature(enable = "avx2")]
    #[inline]
    fn pack(a: [f64; 4]) -> __m256d {
        _mm256_set_pd(a[3], a[2], a[1], a[0])
    }

    /// The four lanes of a register.
    #[target_feature(enable = "avx2")]
    #[inline]
    fn unpack(v: __m256d) -> [f64; 4] {
        let lo = _mm256_castpd256_pd128(v);
        let hi = _mm256_extractf128_pd::<1>(v);
        [
            _mm_cvtsd_f64(lo),
            _mm_cvtsd_f64(_mm_unpackhi_pd(lo, lo)),
            _mm_cvtsd_f64(hi),
            _mm_cvtsd_f64(_mm_unpackhi_pd(hi, hi)),
        ]
    }

    /// [`super::earliest_contact`] over blocks of four candidates, with the minimum image
    /// (`WRAP`) or without; the caller checks that the processor has AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) fn earliest_contact<const D: usize, const WRAP: bool>(
        grains: &[Grain<D>],
        kind_radius: &[f64],
        candidates: &[u32],
        probe: &Probe<'_, D>,
        limit: f64,
    ) -> (f64, u32) {
        let half = half_lengths(probe.bx);
        let zero = _mm256_setzero_pd();
        let sign = _mm256_set1_pd(-0.0);
        let now = _mm256_set1_pd(probe.now);
        let radius = _mm256_set1_pd(probe.radius);
        let mut best = limit;
        let mut partner = NONE;
        for block in candidates.chunks(4) {
            // Lanes past the end of the list test the probe itself, masked out below.
            let mut slot = [probe.slot; 4];
            for (l, s) in slot.iter_mut().enumerate() {
                if let Some(&j) = block.get(l) {
                    *s = j;
                }
            }
            let mut x = [[0.0; 4]; D];
            let mut v = [[0.0; 4]; D];
            let mut time = [0.0; 4];
            let mut rj = [0.0; 4];
            for l in 0..4 {
                let g = &grains[slot[l] as usize];
                for k in 0..D {
                    x[k][l] = g.pos[k];
                    v[k][l] = g.vel[k];
                }
                time[l] = g.time;
                rj[l] = kind_radius[g.kind as usize];
            }
            let dt = _mm256_sub_pd(now, pack(time));
            let mut b = zero;
            let mut dx2 = zero;
            let mut dv2 = zero;
            for k in 0..D {
                let vk = pack(v[k]);
                let mut xj = _mm256_add_pd(pack(x[k]), _mm256_mul_pd(dt, vk));
                let mut vj = vk;
                if let Some(gravity) = &probe.gravity {
                    let g = _mm256_set1_pd(gravity[k]);
                    let half_dt2 = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0.5), dt), dt);
                    xj = _mm256_add_pd(xj, _mm256_mul_pd(half_dt2, g));
                    vj = _mm256_add_pd(vj, _mm256_mul_pd(dt, g));
                }
                let mut d = _mm256_sub_pd(xj, _mm256_set1_pd(probe.pos[k]));
                if WRAP {
                    let l_k = _mm256_set1_pd(probe.bx.lengths[k]);
                    let up = _mm256_cmp_pd::<_CMP_GT_OQ>(d, _mm256_set1_pd(half[k]));
                    let down = _mm256_cmp_pd::<_CMP_LT_OQ>(d, _mm256_set1_pd(-half[k]));
                    d = _mm256_add_pd(
                        _mm256_sub_pd(d, _mm256_and_pd(up, l_k)),
                        _mm256_and_pd(down, l_k),
                    );
                }
                let u = _mm256_sub_pd(vj, _mm256_set1_pd(probe.vel[k]));
                b = _mm256_add_pd(b, _mm256_mul_pd(d, u));
                dx2 = _mm256_add_pd(dx2, _mm256_mul_pd(d, d));
                dv2 = _mm256_add_pd(dv2, _mm256_mul_pd(u, u));
            }
            let sigma = _mm256_add_pd(radius, pack(rj));
            let c = _mm256_sub_pd(dx2, _mm256_mul_pd(sigma, sigma));
            let disc = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(dv2, c));
            // `max(x, 0)` returns 0 for a NaN `x`, as `f64::max` does.
            let s = _mm256_sqrt_pd(_mm256_max_pd(disc, zero));
            let root = _mm256_max_pd(
                _mm256_div_pd(c, _mm256_add_pd(_mm256_xor_pd(b, sign), s)),
                zero,
            );
            let approaching = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero),
                _mm256_cmp_pd::<_CMP_GT_OQ>(disc, zero),
            );
            let valid = _mm256_movemask_pd(approaching);
            let root = unpack(root);
            for l in 0..4 {
                let ok = (valid >> l) & 1 == 1 && slot[l] != probe.slot && slot[l] != probe.skip;
                let t = if ok { root[l] } else { f64::INFINITY };
                if t < best {
                    best = t;
                    partner = slot[l];
                }
            }
        }
        (best, partner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{RngExt, stream};

    /// The packed search returns exactly (bit for bit) the time and partner of the scalar
    /// one: random candidates around a probe, walled and periodic axes, with and without
    /// gravity, lists of every length including partial blocks, skipped partners and ties.
    #[test]
    fn packed_search_matches_the_scalar_search() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            check::<2>();
            check::<3>();
        }
    }

    /// `n` grains of two kinds at random in a box of side 3, with clocks in the past.
    fn random_grains<const D: usize>(rng: &mut impl RngExt, n: usize) -> Vec<Grain<D>> {
        let mut grains = Vec::new();
        for j in 0..n {
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
            grains.push(g);
        }
        // Two candidates with identical states: a tie, won by the first in the list.
        grains[7] = grains[6];
        grains
    }

    #[cfg(target_arch = "x86_64")]
    fn check<const D: usize>() {
        use crate::boundary::AxisKind;
        let mut rng = stream(5, &[D as u64]);
        let n = 64;
        let periodic = SimulationBox::<D>::uniform(Vector([3.0; D]), AxisKind::Periodic);
        let walled = SimulationBox::<D>::uniform(Vector([3.0; D]), AxisKind::Wall);
        let kind_radius = [0.5, 0.3];
        let grains = random_grains::<D>(&mut rng, n);
        let mut found = 0;
        for trial in 0..2000 {
            let len = trial % 30;
            let candidates: Vec<u32> = (0..len).map(|_| rng.random_range(0..n as u32)).collect();
            let mut probe = Probe {
                slot: rng.random_range(0..n as u32),
                skip: if trial % 3 == 0 {
                    candidates.first().copied().unwrap_or(NONE)
                } else {
                    NONE
                },
                pos: Vector::zero(),
                vel: Vector::zero(),
                radius: 0.4,
                now: 0.0,
                gravity: (trial % 5 == 0).then(|| {
                    let mut g = Vector::zero();
                    g[D - 1] = -1.0;
                    g
                }),
                bx: if trial % 2 == 0 { &periodic } else { &walled },
                wrap: true,
            };
            for k in 0..D {
                probe.pos[k] = 3.0 * rng.random::<f64>();
                probe.vel[k] = rng.random::<f64>() - 0.5;
            }
            let limit = if trial % 4 == 0 { 0.5 } else { f64::INFINITY };
            let scalar = earliest_contact_scalar(&grains, &kind_radius, &candidates, &probe, limit);
            #[allow(unsafe_code)]
            // SAFETY: AVX2 checked by the caller.
            let packed = unsafe {
                avx2::earliest_contact::<D, true>(&grains, &kind_radius, &candidates, &probe, limit)
            };
            assert_eq!(scalar.0.to_bits(), packed.0.to_bits(), "trial {trial}");
            assert_eq!(scalar.1, packed.1, "trial {trial}");
            found += usize::from(scalar.1 != NONE);
        }
        assert!(found > 500, "only {found} trials found a contact");
    }
}
