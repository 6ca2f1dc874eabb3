//! Prediction: a grain's earliest event, the earliest of its boundary events (cell
//! crossings and walls, HD-1, HD-2) and its pair contacts with the candidates of the cell
//! grid (HD-7 to HD-10), written into its scheduled event.

use super::Edmd;
use super::events::{
    CROSSING, CROSSING_END, HINT_NO_PAIR, HINT_NONE, NOTHING, Scheduled, WALL, crossing_code,
};
use crate::edmd::candidates::{Grain, Probe, earliest_contact, earliest_contacts_pair};
use crate::edmd::prediction::{downward_crossing, pair_contact_time, upward_crossing};
use crate::neighbours::{Candidates, NONE};
use crate::prefetch::prefetch_all;
use std::hint::select_unpredictable;

/// `if condition { a } else { b }`, without a branch in 2D (`D == 2`). A boundary
/// event's conditions (the sign of a velocity component; which axis's boundary comes
/// first) are coin tosses, and in 2D selects instead of branches measured +1.5-4 % (2D
/// N = 10^4 to 10^6, in one process); in 3D they measured 0.5-4 % slower (3D N = 10^5),
/// so there the branch stays.
#[inline(always)]
pub(super) fn choose<const D: usize, T>(condition: bool, a: T, b: T) -> T {
    if D == 2 {
        select_unpredictable(condition, a, b)
    } else if condition {
        a
    } else {
        b
    }
}

/// Which grains a prediction tests as partners.
#[derive(Clone, Copy)]
pub(super) enum Search {
    /// Every grain of the cells around the grain's cell.
    Full,
    /// After a cell crossing: only the grains of the layer of cells that the crossing made
    /// adjacent, plus `known`, the best partner of the last prediction (`None`: it found
    /// none). Exact because the grain has not collided since that prediction: a grain of
    /// the cells that stay adjacent either has not collided either, and then its contact
    /// time is no earlier than `known`'s (which has not collided: its counter is checked),
    /// or it has, and then it tested this grain itself when it re-predicted. Costs 3 of 9
    /// cells in 2D, 9 of 27 in 3D; no memory (the hint rides in the crossing's code).
    Layer {
        axis: usize,
        step: i32,
        known: Option<u32>,
    },
}

impl<const D: usize> Edmd<D> {
    /// Predicts slot `i`'s earliest event from its state at the current time (which must
    /// be stored, `time == now`) and puts it in the queue.
    pub(super) fn predict(&mut self, i: usize) {
        self.release_if_approaching(i);
        let key = self.predict_with(i, Search::Full);
        self.queue.update(i, key);
    }

    /// [`Edmd::predict`] testing the partners `search` says, without the queue: returns
    /// the event's time, for the caller to put in the queue.
    pub(super) fn predict_with(&mut self, i: usize, search: Search) -> f64 {
        debug_assert_eq!(self.grains[i].time, self.now);
        let coords = self.cells.coords(i);
        let (best, code) = self.boundary_event(i, &coords);
        // The earliest pair at any time (not only before the boundary event): a crossing
        // keeps it as the bound for its own prediction.
        let mut best_pair = f64::INFINITY;
        let mut partner = NONE;
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        let has_large = !self.cells.large().is_empty();
        if has_large {
            self.gather_with_large(i, &coords, search, &mut candidates);
        } else {
            self.gather(&coords, search, &mut candidates);
        }
        let candidates_now = candidates.as_slice();
        prefetch_all(&self.grains, candidates_now);
        if self.growth == 0.0 {
            // A layer search may test a hinted partner beyond the neighbouring cells, and
            // large grains lie anywhere.
            let wrap =
                has_large || !matches!(search, Search::Full) || !self.cells.without_wrap(&[coords]);
            let probe = self.probe(i, wrap);
            (best_pair, partner) = earliest_contact(
                &self.grains,
                &self.kind_radius,
                candidates_now,
                &probe,
                best_pair,
            );
        } else {
            // Lubachevsky-Stillinger compression: radii grow with time.
            let Grain {
                pos: xi, vel: vi, ..
            } = self.grains[i];
            let (ri, rate_i, now) = (
                self.radius_now(i),
                self.base_radius(i) * self.growth,
                self.now,
            );
            let skip = self.separating_partner(i);
            for &j in candidates_now {
                if j == i as u32 || j == skip {
                    continue;
                }
                let xj = self.position_raw(j as usize);
                let dx = self.bx.separation(&xi, &xj);
                let dv = self.velocity_slot(j as usize) - vi;
                let rj = self.base_radius(j as usize);
                let t = pair_contact_time(
                    dx.dot(&dv),
                    dx.norm_squared(),
                    dv.norm_squared(),
                    ri + rj * (1.0 + self.growth * now),
                    rate_i + rj * self.growth,
                )
                .unwrap_or(f64::INFINITY);
                if t < best_pair {
                    best_pair = t;
                    partner = j;
                }
            }
        }
        self.candidates = candidates;
        self.schedule(i, best, code, best_pair, partner)
    }

    /// The candidates of slot `i` (in cell `coords`) in a system with large grains
    /// (`neighbours::large_grain_cut`): for a large grain, the cells within its reach and the
    /// other large grains; for any other grain, what `search` says and every large grain.
    /// Out of line, so that the usual systems' predictions stay as they were.
    #[inline(never)]
    #[cold]
    pub(super) fn gather_with_large(
        &self,
        i: usize,
        coords: &[u32; D],
        search: Search,
        candidates: &mut Candidates,
    ) {
        if self.cells.is_large(i) {
            self.cells.gather_reach(i, coords, candidates);
            return;
        }
        self.gather(coords, search, candidates);
        candidates.extend_from(self.cells.large());
    }

    /// The candidates `search` says, around cell `coords` (large grains aside).
    #[inline(always)]
    pub(super) fn gather(&self, coords: &[u32; D], search: Search, candidates: &mut Candidates) {
        match search {
            Search::Full => self.cells.gather_neighbours(coords, candidates),
            Search::Layer { axis, step, known } => {
                self.cells.gather_layer(coords, axis, step, candidates);
                if let Some(j) = known {
                    candidates.push(j);
                }
            }
        }
    }

    /// [`Edmd::predict`] for both grains of a pair collision (`i` first, then `j`, as
    /// two calls would), in 2D: one gather of the union of their neighbourhoods and one
    /// pass over it that tests each candidate against both (`earliest_contacts_pair`;
    /// +3-6 % in 2D, slower in 3D). Each grain also tests its partner's neighbours, which
    /// stays exact: a contact found with one of them is real (that grain must cross into
    /// the neighbourhood first, which changes no velocity), and a pair beyond the grain's
    /// own crossing only becomes the crossing's hint, whose bound then holds over more
    /// grains than the layer search needs. Grains with growing radii, and systems with
    /// large grains (`neighbours::large_grain_cut`), take the one-grain path.
    pub(super) fn predict_pair(&mut self, i: usize, j: usize) {
        if D != 2 || self.growth != 0.0 || !self.cells.large().is_empty() {
            let key_i = self.predict_with(i, Search::Full);
            let key_j = self.predict_with(j, Search::Full);
            self.queue.update_pair(i, key_i, j, key_j);
            return;
        }
        debug_assert!(self.grains[i].time == self.now && self.grains[j].time == self.now);
        let coords_i = self.cells.coords(i);
        let coords_j = self.cells.coords(j);
        let (best_i, code_i) = self.boundary_event(i, &coords_i);
        let (best_j, code_j) = self.boundary_event(j, &coords_j);
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        self.cells
            .gather_pair(&coords_i, &coords_j, &mut candidates);
        let candidates_now = candidates.as_slice();
        prefetch_all(&self.grains, candidates_now);
        let wrap = !self.cells.without_wrap(&[coords_i, coords_j]);
        let [(pair_i, partner_i), (pair_j, partner_j)] = earliest_contacts_pair(
            &self.grains,
            &self.kind_radius,
            candidates_now,
            [&self.probe(i, wrap), &self.probe(j, wrap)],
        );
        self.candidates = candidates;
        let key_i = self.schedule(i, best_i, code_i, pair_i, partner_i);
        let key_j = self.schedule(j, best_j, code_j, pair_j, partner_j);
        self.queue.update_pair(i, key_i, j, key_j);
    }

    /// What a contact search needs to know about slot `i` (its state stored at the
    /// current time) and the box; `wrap`: whether its candidates may need the minimum
    /// image.
    #[inline(always)]
    pub(super) fn probe(&self, i: usize, wrap: bool) -> Probe<'_, D> {
        Probe {
            slot: i as u32,
            skip: self.separating_partner(i),
            pos: self.grains[i].pos,
            vel: self.grains[i].vel,
            radius: self.radius_now(i),
            now: self.now,
            gravity: self.has_gravity.then_some(self.gravity),
            bx: &self.bx,
            wrap,
        }
    }

    /// The earliest boundary event of slot `i` (in cell `coords`, its state stored at
    /// the current time): a cell crossing or a wall collision (HD-1, HD-2), as (time
    /// from now, code), or `(∞, NOTHING)`.
    #[inline(always)]
    pub(super) fn boundary_event(&self, i: usize, coords: &[u32; D]) -> (f64, u32) {
        let Grain {
            pos: xi, vel: vi, ..
        } = self.grains[i];
        let ri = self.radius_now(i);
        let rate_i = self.base_radius(i) * self.growth;
        let half_g = self.gravity * 0.5;
        let mut best = f64::INFINITY;
        let mut code = NOTHING;
        for k in 0..D {
            let n = self.cells.counts[k];
            let periodic = self.bx.is_periodic(k);
            let w = self.cells.widths[k];
            let ck = coords[k] as usize;
            let (v, a) = (vi[k], half_g[k]);
            if a == 0.0 && rate_i == 0.0 {
                // Uniform motion along k: only the boundaries ahead can be reached. The
                // arithmetic of `upward_crossing`/`downward_crossing` with a = 0, without
                // their branches on the sign of v (a coin toss; see `choose`).
                if v != 0.0 {
                    let up = v > 0.0;
                    // The cell boundary ahead (none at a walled face: the wall comes first).
                    let has_cell = periodic || if up { ck + 1 < n } else { ck > 0 };
                    let ahead = ck + up as usize;
                    let bound = choose::<D, _>(ahead == n, self.bx.lengths[k], ahead as f64 * w);
                    let t = (-(xi[k] - bound) / v).max(0.0);
                    let earlier = has_cell & (t < best);
                    best = choose::<D, _>(earlier, t, best);
                    code = choose::<D, _>(earlier, crossing_code(k, up), code);
                    if !periodic {
                        let c = choose::<D, _>(up, xi[k] + ri - self.bx.lengths[k], xi[k] - ri);
                        let t = (-c / v).max(0.0);
                        let earlier = t < best;
                        best = choose::<D, _>(earlier, t, best);
                        code = choose::<D, _>(earlier, WALL + 2 * k as u32 + up as u32, code);
                    }
                }
                continue;
            }
            // Cell boundaries (walled box faces excluded: the wall comes first).
            if periodic || ck + 1 < n {
                let hi = if ck + 1 == n {
                    self.bx.lengths[k]
                } else {
                    (ck + 1) as f64 * w
                };
                if let Some(t) = upward_crossing(xi[k] - hi, v, a)
                    && t < best
                {
                    best = t;
                    code = crossing_code(k, true);
                }
            }
            if periodic || ck > 0 {
                let lo = ck as f64 * w;
                if let Some(t) = downward_crossing(xi[k] - lo, v, a)
                    && t < best
                {
                    best = t;
                    code = crossing_code(k, false);
                }
            }
            if !periodic {
                let l = self.bx.lengths[k];
                if let Some(t) = upward_crossing(xi[k] + ri - l, v + rate_i, a)
                    && t < best
                {
                    best = t;
                    code = WALL + 2 * k as u32 + 1;
                }
                if let Some(t) = downward_crossing(xi[k] - ri, v - rate_i, a)
                    && t < best
                {
                    best = t;
                    code = WALL + 2 * k as u32;
                }
            }
        }
        (best, code)
    }

    /// The partner slot `i` must not be tested against: the partner of its last
    /// collision while the two are each other's last partners (they are separating, and
    /// round-off must not make them collide again: at restitution 0 they would, forever,
    /// at zero time intervals), or `NONE`.
    #[inline(always)]
    pub(super) fn separating_partner(&self, i: usize) -> u32 {
        let p = self.last_partner[i];
        if p != NONE && self.last_partner[p as usize] == i as u32 {
            p
        } else {
            NONE
        }
    }

    /// Forgets that slot `i` and its last partner are separating when they no longer
    /// are, and says whether it did (then a layer search is no longer exact: the two did
    /// not test each other). Two last partners separate from their collision on (`dx .
    /// dv` only grows while neither collides again), but they can approach once more if
    /// their velocities are changed (a white-noise kick) or, in a periodic box, through
    /// the other image once they are half a box apart; skipping each other then would let
    /// them pass through each other. Released when `dx . dv` is below `-1e-9 |dx| |dv|`
    /// (less the closing rate of growing radii): round-off after a collision at zero
    /// restitution (`dx . dv` of order `1e-16 |dx| |dv|`) keeps the pair skipped.
    pub(super) fn release_if_approaching(&mut self, i: usize) -> bool {
        let p = self.separating_partner(i);
        if p == NONE {
            return false;
        }
        let p = p as usize;
        let dx = self
            .bx
            .separation(&self.position_raw(i), &self.position_raw(p));
        let dv = self.velocity_slot(p) - self.velocity_slot(i);
        let (b, dx2, dv2) = (dx.dot(&dv), dx.norm_squared(), dv.norm_squared());
        let approaching = if self.growth == 0.0 {
            // `b < -1e-9 |dx| |dv|` without a square root (this runs at most crossings).
            b < 0.0 && b * b > 1e-18 * dx2 * dv2
        } else {
            let closing = (self.base_radius(i) + self.base_radius(p)) * self.growth;
            let dx_norm = dx2.sqrt();
            b - closing * dx_norm < -1e-9 * dx_norm * dv2.sqrt()
        };
        if approaching {
            self.last_partner[i] = NONE;
            self.last_partner[p] = NONE;
            true
        } else {
            false
        }
    }

    /// Schedules slot `i`'s earliest event: the boundary event `(best, code)` or, if
    /// earlier, the pair contact `(best_pair, partner)` (`partner == NONE`: none found).
    /// A crossing carries the pair as the hint of its layer search. Returns the event's
    /// time, for the caller to put in the queue.
    #[inline(always)]
    pub(super) fn schedule(
        &mut self,
        i: usize,
        mut best: f64,
        mut code: u32,
        best_pair: f64,
        partner: u32,
    ) -> f64 {
        let now = self.now;
        let mut partner_counter = 0;
        if partner != NONE && best_pair < best {
            best = best_pair;
            code = partner;
            partner_counter = self.grains[partner as usize].counter;
        } else if (CROSSING..CROSSING_END).contains(&code) {
            code += if self.growth != 0.0 || self.len() >= HINT_NO_PAIR as usize {
                HINT_NONE
            } else if partner == NONE {
                HINT_NO_PAIR
            } else {
                partner_counter = self.grains[partner as usize].counter;
                partner
            };
        }
        self.event[i] = Scheduled {
            code,
            partner_counter,
        };
        now + best
    }
}
