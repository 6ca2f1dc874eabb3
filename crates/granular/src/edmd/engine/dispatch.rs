//! The event loop: the earliest event is taken from the queue and dispatched by its kind
//! (pair collision, stale pair, cell crossing, wall collision).

use super::Edmd;
use super::collapse::COLLAPSE_WINDOW;
use super::events::{
    CROSSING_END, FIRST_SPECIAL, HINT_NO_PAIR, HINT_NONE, NOTHING, Scheduled, WALL, decode_crossing,
};
use super::predict::Search;
use crate::engine::{EngineError, Progress};

impl<const D: usize> Edmd<D> {
    /// Processes the earliest event, of slot `i`. The clock must already be at its time.
    pub(super) fn process(&mut self, i: usize) -> Result<(), EngineError> {
        self.totals.events += 1;
        self.events_since_rebase += 1;
        let Scheduled {
            code,
            partner_counter,
        } = self.event[i];
        if code < FIRST_SPECIAL {
            let j = code as usize;
            self.advance_particle(i);
            if self.grains[j].counter != partner_counter {
                self.predict(i);
                return Ok(());
            }
            self.advance_particle(j);
            self.collide_pair(i, j);
            self.predict_pair(i, j);
        } else if code < CROSSING_END {
            self.advance_particle(i);
            let (k, upward, hint) = decode_crossing(code);
            let step = if upward { 1 } else { -1 };
            if self.cells.shift(i, k, step) {
                let l = self.bx.lengths[k];
                self.grains[i].pos[k] += if upward { -l } else { l };
            }
            let released = self.release_if_approaching(i);
            let search = match hint {
                _ if released => Search::Full,
                HINT_NONE => Search::Full,
                HINT_NO_PAIR => Search::Layer {
                    axis: k,
                    step,
                    known: None,
                },
                j if self.grains[j as usize].counter == partner_counter => Search::Layer {
                    axis: k,
                    step,
                    known: Some(j),
                },
                _ => Search::Full,
            };
            let key = self.predict_with(i, search);
            self.queue.update(i, key);
        } else if code != NOTHING {
            self.advance_particle(i);
            self.collide_wall(i, ((code - WALL) / 2) as usize, (code - WALL) % 2 == 1);
            self.predict(i);
        } else {
            return Err(EngineError::Numerical(format!(
                "particle {} scheduled an empty event at a finite time",
                self.id[i]
            )));
        }
        Ok(())
    }
}

impl<const D: usize> Edmd<D> {
    /// The event loop: events up to `until` (absolute time), at most `max_events`.
    pub(super) fn advance_events(
        &mut self,
        until: f64,
        max_events: u64,
    ) -> Result<Progress, EngineError> {
        let interval = self
            .options
            .reorder_interval
            .unwrap_or(8 * self.len() as u64 + 1024);
        let mut until_now = until - self.origin;
        // Large systems: prefetch what the events about to come will read (see
        // `prefetch_coming`).
        let look_ahead = self.queue.looks_ahead();
        let mut coming = usize::MAX;
        let mut earlier = usize::MAX;
        for _ in 0..max_events {
            let Some((i, t)) = self.queue.min() else {
                self.now = self.now.max(until_now);
                return Ok(Progress::Reached);
            };
            if look_ahead {
                self.prefetch_coming(&mut coming, &mut earlier);
            }
            if t > until_now {
                self.now = self.now.max(until_now);
                return Ok(Progress::Reached);
            }
            if t < self.now {
                return Err(EngineError::Numerical(format!(
                    "event of particle {} scheduled at {t:e}, before the current time {:e}",
                    self.id[i], self.now
                )));
            }
            self.now = t;
            self.process(i)?;
            if self.totals.events & (COLLAPSE_WINDOW - 1) == 0 {
                self.check_collapse()?;
            }
            // At a fixed event count, so that the trajectory does not depend on how the
            // run is cut into `advance` calls.
            if self.events_since_rebase >= interval {
                self.rebase();
                until_now = until - self.origin;
            }
        }
        Ok(Progress::BudgetExhausted)
    }
}
