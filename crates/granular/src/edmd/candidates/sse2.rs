//! The two-probe search in SSE2 registers (lane 0: the first probe).

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
    (grains, kind_radius, candidates, probes): (&[Grain<D>], &[f64], &[u32], [&Probe<'_, D>; 2]),
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
