//! The earliest pair contact among a prediction's candidates, and the grain record it
//! reads.
//!
//! A prediction tests every grain of the neighbouring cells (8 in dense 2D, 25 in 3D),
//! each test a square root and a division. With many candidates (3D) the tests run eight
//! at a time in AVX-512 registers, each field of eight records loaded by one gather
//! (`avx512::earliest_contact`), or four at a time in AVX2 registers on processors
//! without AVX-512 (`avx2::earliest_contact`; both checked at run time), otherwise one
//! at a time; after a 2D pair collision both grains are tested against each candidate at
//! once, in two SSE2 lanes (`sse2::earliest_contacts_pair`). All paths do the same
//! operations in the same order (no fused multiply-add), so they give the same contact
//! times to the last bit (tested): trajectories do not depend on the processor.

use crate::boundary::SimulationBox;
use crate::neighbours::NONE;
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

/// Fewest candidates for which a packed search is used. Measured (collisions per CPU
/// second, whole engine): with the 25 candidates of dense 3D the AVX2 search is 11-18 %
/// faster than the scalar one (3D N = 10^5, φ = 0.45), and the AVX-512 search another
/// 9-11 % (+1 % at 3D N = 10^6); for all 8 of dense 2D the AVX2 search was 6-8 % slower
/// (its lanes are filled and emptied one value at a time, and eight one-candidate chains
/// already overlap in the processor) and the AVX-512 one no faster at 2D N = 10^4 and 6 %
/// slower at 10^5, so 2D predictions keep the one-at-a-time path.
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
    if candidates.len() >= PACKED_MIN {
        if avx512::usable(grains) {
            #[allow(unsafe_code)]
            // SAFETY: `usable` checked the processor's features.
            return unsafe {
                if probe.wrap {
                    avx512::earliest_contact::<D, true>(
                        grains,
                        kind_radius,
                        candidates,
                        probe,
                        limit,
                    )
                } else {
                    avx512::earliest_contact::<D, false>(
                        grains,
                        kind_radius,
                        candidates,
                        probe,
                        limit,
                    )
                }
            };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            #[allow(unsafe_code)]
            // SAFETY: the only requirement of a `#[target_feature]` function is that the
            // processor has the feature, checked on the line above.
            return unsafe {
                if probe.wrap {
                    avx2::earliest_contact::<D, true>(grains, kind_radius, candidates, probe, limit)
                } else {
                    avx2::earliest_contact::<D, false>(
                        grains,
                        kind_radius,
                        candidates,
                        probe,
                        limit,
                    )
                }
            };
        }
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
        let (xj, vj) = advanced(g, probe.now, probe.gravity.as_ref());
        // Minimum image as in `SimulationBox::separation`, with the half lengths computed
        // once per prediction rather than per candidate (2 % of the engine at 2D 10^4).
        // The packed lanes compute the same values as `d - 1 L`, `d + 1 L` or `d - 0 + 0`.
        let mut dx = xj - probe.pos;
        if WRAP {
            for k in 0..D {
                if dx[k] > half[k] {
                    dx[k] -= probe.bx.lengths[k];
                } else if dx[k] < -half[k] {
                    dx[k] += probe.bx.lengths[k];
                }
            }
        }
        let dv = vj - probe.vel;
        // `pair_contact_time` without growth (HD-7 to HD-10), written without
        // unpredictable branches (the sign of `b` is a coin toss for neighbours): every
        // candidate costs a square root and a division, which pipeline, instead of a
        // mispredicted branch. Same arithmetic, so the same times.
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

/// [`earliest_contact_scalar`] for the two grains of a pair collision at once, over one
/// candidate list (the union of their neighbourhoods, which overlap in most cells): each
/// candidate's record is read and brought to the current time once, and the two contact
/// times are computed side by side in the two lanes of an SSE2 register (one square root
/// and one division for both; `sse2::earliest_contacts_pair`). Each lane does the
/// operations of the scalar search in the same order, so each probe gets the time and
/// partner that [`earliest_contact_scalar`] gives over the same list, to the last bit
/// (tested). The probes must share `now`, `gravity` and `bx`, and skip each other (each
/// is the other's `skip`: two grains that have just collided); no limit.
#[inline(always)]
pub(super) fn earliest_contacts_pair<const D: usize>(
    grains: &[Grain<D>],
    kind_radius: &[f64],
    candidates: &[u32],
    probes: [&Probe<'_, D>; 2],
) -> [(f64, u32); 2] {
    let [a, b] = probes;
    debug_assert!(a.now == b.now && a.gravity == b.gravity && std::ptr::eq(a.bx, b.bx));
    debug_assert!(a.skip == b.slot && b.skip == a.slot);
    #[cfg(target_arch = "x86_64")]
    {
        #[allow(unsafe_code)]
        // SAFETY: the only requirement of a `#[target_feature]` function is that the
        // processor has the feature, and SSE2 is part of every x86_64 processor.
        unsafe {
            let args = (grains, kind_radius, candidates, [a, b]);
            match (a.gravity.is_some(), a.wrap || b.wrap) {
                (false, false) => sse2::earliest_contacts_pair::<D, false, false>(args),
                (false, true) => sse2::earliest_contacts_pair::<D, false, true>(args),
                (true, false) => sse2::earliest_contacts_pair::<D, true, false>(args),
                (true, true) => sse2::earliest_contacts_pair::<D, true, true>(args),
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    [
        earliest_contact_scalar(grains, kind_radius, candidates, a, f64::INFINITY),
        earliest_contact_scalar(grains, kind_radius, candidates, b, f64::INFINITY),
    ]
}

/// The two-probe search in SSE2 registers (lane 0: the first probe).
#[cfg(target_arch = "x86_64")]
mod sse2 {
    use super::{Grain, NONE, Probe, advanced, half_lengths};
    use std::arch::x86_64::*;

    /// A register holding `a` in lane 0 and `b` in lane 1.
    #[target_feature(enable = "sse2")]
    #[inline]
    fn lanes(a: f64, b: f64) -> __m128d {
        _mm_set_pd(b, a)
    }

    /// See [`super::earliest_contacts_pair`]; `GRAVITY`: whether `probes` carry one,
    /// `WRAP`: whether the minimum image must be taken. Written with intrinsics: the
    /// compiler's own packing of a two-lane loop kept the square roots scalar and turned
    /// the lanes' conditions into unpredictable branches (30 % slower than two scalar
    /// searches).
    #[target_feature(enable = "sse2")]
    pub(super) fn earliest_contacts_pair<const D: usize, const GRAVITY: bool, const WRAP: bool>(
        (grains, kind_radius, candidates, probes): (
            &[Grain<D>],
            &[f64],
            &[u32],
            [&Probe<'_, D>; 2],
        ),
    ) -> [(f64, u32); 2] {
        let [a, b] = probes;
        let half = half_lengths(a.bx);
        let gravity = a.gravity.unwrap_or_default();
        let zero = _mm_setzero_pd();
        let sign = _mm_set1_pd(-0.0);
        let pos: [__m128d; D] = std::array::from_fn(|k| lanes(a.pos[k], b.pos[k]));
        let vel: [__m128d; D] = std::array::from_fn(|k| lanes(a.vel[k], b.vel[k]));
        let half: [__m128d; D] = std::array::from_fn(|k| _mm_set1_pd(half[k]));
        let length: [__m128d; D] = std::array::from_fn(|k| _mm_set1_pd(a.bx.lengths[k]));
        let radius = lanes(a.radius, b.radius);
        let mut best = _mm_set1_pd(f64::INFINITY);
        let mut partner = [NONE; 2];
        for &j in candidates {
            if j == a.slot || j == b.slot {
                continue;
            }
            let g = &grains[j as usize];
            let (xj, vj) = advanced(g, a.now, GRAVITY.then_some(&gravity));
            let mut dot = zero;
            let mut dx2 = zero;
            let mut dv2 = zero;
            for k in 0..D {
                // The minimum image: `d - L` beyond half the box, `d - (-L)` (which is
                // `d + L` exactly) below minus half, `d - 0` (`d`) otherwise: the scalar
                // branches' values.
                let mut d = _mm_sub_pd(_mm_set1_pd(xj[k]), pos[k]);
                if WRAP {
                    let beyond = _mm_cmpgt_pd(_mm_andnot_pd(sign, d), half[k]);
                    let shift = _mm_and_pd(beyond, _mm_or_pd(length[k], _mm_and_pd(sign, d)));
                    d = _mm_sub_pd(d, shift);
                }
                let u = _mm_sub_pd(_mm_set1_pd(vj[k]), vel[k]);
                dot = _mm_add_pd(dot, _mm_mul_pd(d, u));
                dx2 = _mm_add_pd(dx2, _mm_mul_pd(d, d));
                dv2 = _mm_add_pd(dv2, _mm_mul_pd(u, u));
            }
            let sigma = _mm_add_pd(radius, _mm_set1_pd(kind_radius[g.kind as usize]));
            let c = _mm_sub_pd(dx2, _mm_mul_pd(sigma, sigma));
            let disc = _mm_sub_pd(_mm_mul_pd(dot, dot), _mm_mul_pd(dv2, c));
            // `max(x, 0)` returns 0 for a NaN `x`, as `f64::max` does.
            let s = _mm_sqrt_pd(_mm_max_pd(disc, zero));
            let root = _mm_max_pd(_mm_div_pd(c, _mm_add_pd(_mm_xor_pd(dot, sign), s)), zero);
            // `t < best` per lane for approaching grains, as the scalar search's strict
            // comparison (ties keep the earlier candidate).
            let approaching = _mm_and_pd(_mm_cmplt_pd(dot, zero), _mm_cmpgt_pd(disc, zero));
            let earlier = _mm_and_pd(approaching, _mm_cmplt_pd(root, best));
            best = _mm_or_pd(_mm_and_pd(earlier, root), _mm_andnot_pd(earlier, best));
            let earlier = _mm_movemask_pd(earlier);
            partner[0] = if earlier & 1 != 0 { j } else { partner[0] };
            partner[1] = if earlier & 2 != 0 { j } else { partner[1] };
        }
        let low = _mm_cvtsd_f64(best);
        let high = _mm_cvtsd_f64(_mm_unpackhi_pd(best, best));
        [(low, partner[0]), (high, partner[1])]
    }
}

/// Position and velocity of grain `g` at time `now` (HD-6; under uniform `gravity`, if any):
/// the one-candidate and two-grain searches advance their candidates alike.
#[inline(always)]
fn advanced<const D: usize>(
    g: &Grain<D>,
    now: f64,
    gravity: Option<&Vector<D>>,
) -> (Vector<D>, Vector<D>) {
    let dt = now - g.time;
    let mut x = g.pos.add_scaled(dt, &g.vel);
    let mut v = g.vel;
    if let Some(gravity) = gravity {
        x = x.add_scaled(0.5 * dt * dt, gravity);
        v = v.add_scaled(dt, gravity);
    }
    (x, v)
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

/// The same search eight candidates at a time with AVX-512: each field of eight
/// candidates' records comes in one gather, where the AVX2 search fills its four lanes one
/// value at a time. No fused multiply-add: every operation rounds as in the scalar path,
/// in the same order, so the time and partner are the same to the last bit (tested).
#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::{Grain, NONE, Probe, half_lengths};
    use std::arch::x86_64::*;
    use std::mem::{offset_of, size_of};

    /// Lanes of a register: candidates per block.
    const LANES: usize = 8;

    /// Whether the processor has the features of [`earliest_contact`] and the gathers'
    /// 32-bit offsets (in units of 4 bytes, for the kind) reach every record of `grains`.
    #[inline]
    pub(super) fn usable<const D: usize>(grains: &[Grain<D>]) -> bool {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && grains.len() < i32::MAX as usize / size_of::<Grain<D>>() * 4
    }

    /// [`super::earliest_contact`] over blocks of eight candidates, with the minimum image
    /// (`WRAP`) or without; the caller checks [`usable`].
    #[target_feature(enable = "avx512f,avx512vl")]
    pub(super) fn earliest_contact<const D: usize, const WRAP: bool>(
        grains: &[Grain<D>],
        kind_radius: &[f64],
        candidates: &[u32],
        probe: &Probe<'_, D>,
        limit: f64,
    ) -> (f64, u32) {
        const { assert!(size_of::<Grain<D>>().is_multiple_of(8)) };
        // Record layout in 8-byte words (the kind in 4-byte words).
        let words = (size_of::<Grain<D>>() / 8) as i32;
        let pos_at = (offset_of!(Grain<D>, pos) / 8) as i32;
        let vel_at = (offset_of!(Grain<D>, vel) / 8) as i32;
        let time_at = (offset_of!(Grain<D>, time) / 8) as i32;
        let kind_at = (offset_of!(Grain<D>, kind) / 4) as i32;
        let records = grains.as_ptr() as *const f64;
        let half = half_lengths(probe.bx);
        let up_from: [__m512d; D] = std::array::from_fn(|k| _mm512_set1_pd(half[k]));
        let down_from: [__m512d; D] = std::array::from_fn(|k| _mm512_set1_pd(-half[k]));
        let length: [__m512d; D] = std::array::from_fn(|k| _mm512_set1_pd(probe.bx.lengths[k]));
        let pos: [__m512d; D] = std::array::from_fn(|k| _mm512_set1_pd(probe.pos[k]));
        let vel: [__m512d; D] = std::array::from_fn(|k| _mm512_set1_pd(probe.vel[k]));
        let radius = _mm512_set1_pd(probe.radius);
        let now = _mm512_set1_pd(probe.now);
        let zero = _mm512_setzero_pd();
        let sign = _mm512_set1_epi64(i64::MIN);
        let (own, skip) = (
            _mm256_set1_epi32(probe.slot as i32),
            _mm256_set1_epi32(probe.skip as i32),
        );
        let (n_grains, n_kinds) = (
            _mm256_set1_epi32(grains.len() as i32),
            _mm256_set1_epi32(kind_radius.len() as i32),
        );
        // Per lane: the earliest time so far and the position of its candidate in the list.
        let mut best = _mm512_set1_pd(limit);
        let mut best_at = _mm512_set1_epi64(i64::MAX);
        let mut at = _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0);
        for block in candidates.chunks(LANES) {
            let in_block = (u16::MAX >> (16 - block.len())) as __mmask8;
            #[allow(unsafe_code)]
            // SAFETY: the mask reads the `block.len()` values of `block`.
            let slot = unsafe { _mm256_maskz_loadu_epi32(in_block, block.as_ptr().cast()) };
            // A candidate beyond the records panics, as slice indexing does (never expected).
            let beyond = _mm256_mask_cmpge_epu32_mask(in_block, slot, n_grains);
            assert!(beyond == 0, "candidate beyond the grain records");
            let live = _mm256_mask_cmpneq_epu32_mask(
                _mm256_mask_cmpneq_epu32_mask(in_block, slot, own),
                slot,
                skip,
            );
            let word = _mm256_mullo_epi32(slot, _mm256_set1_epi32(words));
            #[allow(unsafe_code)]
            // SAFETY: the gathers read the live lanes only, whose slots are below
            // `grains.len()` (checked above), at `word + offset`, a field of that slot's
            // record (`usable` keeps the offsets within `i32`); a kind read is checked
            // against `kind_radius` before it indexes it.
            let (x, v, time, rj) = unsafe {
                let field = |offset: i32| {
                    _mm512_mask_i32gather_pd::<8>(
                        zero,
                        live,
                        _mm256_add_epi32(word, _mm256_set1_epi32(offset)),
                        records,
                    )
                };
                let x: [__m512d; D] = std::array::from_fn(|k| field(pos_at + k as i32));
                let v: [__m512d; D] = std::array::from_fn(|k| field(vel_at + k as i32));
                let kind = _mm256_mmask_i32gather_epi32::<4>(
                    _mm256_setzero_si256(),
                    live,
                    _mm256_add_epi32(_mm256_add_epi32(word, word), _mm256_set1_epi32(kind_at)),
                    records.cast(),
                );
                let unknown = _mm256_mask_cmpge_epu32_mask(live, kind, n_kinds);
                assert!(unknown == 0, "grain kind beyond the kind table");
                let rj = _mm512_mask_i32gather_pd::<8>(zero, live, kind, kind_radius.as_ptr());
                (x, v, field(time_at), rj)
            };
            // Each candidate brought to the current time, as `super::advanced` does.
            let dt = _mm512_sub_pd(now, time);
            let mut dot = zero;
            let mut dx2 = zero;
            let mut dv2 = zero;
            for k in 0..D {
                let mut xj = _mm512_add_pd(x[k], _mm512_mul_pd(dt, v[k]));
                let mut vj = v[k];
                if let Some(gravity) = &probe.gravity {
                    let g = _mm512_set1_pd(gravity[k]);
                    let half_dt2 = _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(0.5), dt), dt);
                    xj = _mm512_add_pd(xj, _mm512_mul_pd(half_dt2, g));
                    vj = _mm512_add_pd(vj, _mm512_mul_pd(dt, g));
                }
                let mut d = _mm512_sub_pd(xj, pos[k]);
                if WRAP {
                    // The minimum image as the scalar branches take it: `d - L` beyond half
                    // the box, `d + L` below minus half.
                    let up = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(d, up_from[k]);
                    let down = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(d, down_from[k]);
                    d = _mm512_mask_sub_pd(d, up, d, length[k]);
                    d = _mm512_mask_add_pd(d, down, d, length[k]);
                }
                let u = _mm512_sub_pd(vj, vel[k]);
                dot = _mm512_add_pd(dot, _mm512_mul_pd(d, u));
                dx2 = _mm512_add_pd(dx2, _mm512_mul_pd(d, d));
                dv2 = _mm512_add_pd(dv2, _mm512_mul_pd(u, u));
            }
            let sigma = _mm512_add_pd(radius, rj);
            let c = _mm512_sub_pd(dx2, _mm512_mul_pd(sigma, sigma));
            let disc = _mm512_sub_pd(_mm512_mul_pd(dot, dot), _mm512_mul_pd(dv2, c));
            // `max(x, 0)` returns 0 for a NaN `x`, as `f64::max` does.
            let s = _mm512_sqrt_pd(_mm512_max_pd(disc, zero));
            let minus_dot = _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(dot), sign));
            let root = _mm512_max_pd(_mm512_div_pd(c, _mm512_add_pd(minus_dot, s)), zero);
            let approaching = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(live, dot, zero)
                & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(disc, zero);
            // Strictly earlier, as the scalar search: a lane keeps its first candidate of
            // a tie.
            let earlier = _mm512_mask_cmp_pd_mask::<_CMP_LT_OQ>(approaching, root, best);
            best = _mm512_mask_mov_pd(best, earlier, root);
            best_at = _mm512_mask_mov_epi64(best_at, earlier, at);
            at = _mm512_add_epi64(at, _mm512_set1_epi64(LANES as i64));
        }
        // The earliest time over the lanes and, of the lanes that hold it, the candidate
        // first in the list (none improved on `limit`: no lane holds a position).
        let t = _mm512_reduce_min_pd(best);
        let tied = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(best, _mm512_set1_pd(t));
        let first = _mm512_mask_reduce_min_epi64(tied, best_at);
        match usize::try_from(first).ok().and_then(|i| candidates.get(i)) {
            Some(&j) => (t, j),
            None => (limit, NONE),
        }
    }
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
        [AxisKind::Periodic, AxisKind::Wall]
            .map(|kind| SimulationBox::uniform(Vector([3.0; D]), kind))
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
}
