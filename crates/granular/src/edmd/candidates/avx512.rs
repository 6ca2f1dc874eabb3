//! The same search eight candidates at a time with AVX-512: each field of eight
//! candidates' records comes in one gather, where the AVX2 search fills its four lanes one
//! value at a time. No fused multiply-add: every operation rounds as in the scalar path,
//! in the same order, so the time and partner are the same to the last bit (tested).

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
