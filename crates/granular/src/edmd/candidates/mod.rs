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
//! times to the last bit (tested): trajectories do not depend on the processor. Each packed
//! search is a file of this module (`avx512.rs`, `avx2.rs`, `sse2.rs`), the test of all
//! against the scalar search is `tests.rs`.

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

#[cfg(target_arch = "x86_64")]
mod sse2;

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

#[cfg(target_arch = "x86_64")]
mod avx512;

#[cfg(target_arch = "x86_64")]
mod avx2;

#[cfg(test)]
mod tests;
