//! The same search four candidates at a time with AVX2 (no fused multiply-add: every
//! operation rounds as in the scalar path).

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
