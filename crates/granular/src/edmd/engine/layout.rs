//! The memory layout in time and space: shifts of the time origin, and the spatial
//! reordering of the grains (cell order) that follows each shift.

use super::events::{CROSSING_END, FIRST_SPECIAL, HINT_NO_PAIR, Scheduled, decode_crossing};
use super::{Edmd, RECORD_ALIGN, Records};

impl<const D: usize> Edmd<D> {
    /// Moves the time origin to the current time: all grains are advanced to `now`, and
    /// every stored time is shifted, so that times stay small numbers. Then re-sorts the
    /// grains in cell order.
    pub(super) fn rebase(&mut self) {
        if self.growth != 0.0 || self.now == 0.0 {
            return;
        }
        for i in 0..self.len() {
            self.advance_particle(i);
            self.grains[i].time = 0.0;
        }
        for t in &mut self.last_collision {
            *t -= self.now;
        }
        self.queue.shift(self.now, 0.0);
        self.collapse.window_start_time -= self.now;
        self.origin += self.now;
        self.now = 0.0;
        self.events_since_rebase = 0;
        self.reorder();
    }

    /// Spatial reordering: stores the grains in cell order, so that the grains a
    /// prediction visits are close in memory. Only slots change; every event, counter and
    /// clock moves with its grain, so the trajectory is the same.
    pub(super) fn reorder(&mut self) {
        let order = self.cells.cell_order();
        let n = self.len();
        if order.len() != n {
            return;
        }
        let mut new_of_old = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_of_old[old as usize] = new as u32;
        }
        let map = |x: u32| {
            if x < FIRST_SPECIAL {
                new_of_old[x as usize]
            } else if x < CROSSING_END {
                // A crossing: relabel its partner hint, if it holds one.
                let (_, _, hint) = decode_crossing(x);
                if hint < HINT_NO_PAIR {
                    x - hint + new_of_old[hint as usize]
                } else {
                    x
                }
            } else {
                x
            }
        };
        self.grains =
            Records::from_iter(RECORD_ALIGN, order.iter().map(|&o| self.grains[o as usize]));
        let event = order
            .iter()
            .map(|&o| {
                let e = self.event[o as usize];
                Scheduled {
                    code: map(e.code),
                    partner_counter: e.partner_counter,
                }
            })
            .collect();
        self.event = event;
        let last_partner = order
            .iter()
            .map(|&o| map(self.last_partner[o as usize]))
            .collect();
        self.last_partner = last_partner;
        if !self.last_collision.is_empty() {
            let lc = order
                .iter()
                .map(|&o| self.last_collision[o as usize])
                .collect();
            self.last_collision = lc;
        }
        if !self.spin.is_empty() {
            let r = crate::collision_law::rough::rotational_dof(D);
            let spin = order
                .iter()
                .flat_map(|&o| {
                    let o = o as usize;
                    self.spin[r * o..r * o + r].iter().copied()
                })
                .collect();
            self.spin = spin;
        }
        self.id = order.iter().map(|&o| self.id[o as usize]).collect();
        self.slot = std::sync::OnceLock::new();
        self.queue.relabel(&new_of_old, self.now);
        self.cells.relabel(&new_of_old);
    }
}
