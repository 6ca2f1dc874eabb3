//! Software prefetch for the events about to come (large systems; `docs/edmd.md`).

use super::Edmd;
use super::events::FIRST_SPECIAL;
use crate::prefetch::prefetch_all;

impl<const D: usize> Edmd<D> {
    /// Prefetch in stages for the events about to come, which in large systems are cache
    /// misses (+8-29 % at 10^5-10^6 grains; see `docs/edmd.md`). First stage: the grain
    /// the queue's look-ahead has reached (its event comes up in the next bucket): its
    /// record, its scheduled event and its cell index. Second stage, one event later, for
    /// the grain of the first stage (whose event and cell index are now in cache): its
    /// partner's record and queue links (which the partner's update reads to unlink it
    /// from its bucket: +1-3 % at 10^6 grains) and the cell heads around it. `coming`
    /// carries the first stage's grain to the second, `earlier` the second's to the
    /// third. Hints only: a grain relabelled or re-predicted meanwhile costs a useless
    /// prefetch, never a wrong result.
    #[inline(always)]
    pub(super) fn prefetch_coming(&self, coming: &mut usize, earlier: &mut usize) {
        // Third stage, in 2D only, one more event later (the heads are now in cache): the
        // first grain of each of the 9 neighbouring cells, its record and list link
        // (+5-7 % at 10^6 disks, +2 % at 10^5), and the cell heads around the partner
        // (+4-7 % at 10^6, -1 % at 10^5). In 3D the 27 cells' prefetches cost more than
        // they save (-3 % at 10^6 spheres and -8 % at 10^5 for the first grains; -3 % at
        // 10^5 for the partner's heads).
        if D == 2
            && let Some(e) = self.event.get(*earlier)
        {
            self.cells.prefetch_first_grains(*earlier, &self.grains);
            if e.code < FIRST_SPECIAL {
                self.cells.prefetch_heads(e.code as usize);
            }
        }
        *earlier = *coming;
        if let Some(e) = self.event.get(*coming) {
            if e.code < FIRST_SPECIAL {
                prefetch_all(&self.grains, &[e.code]);
                prefetch_all(&self.last_collision, &[e.code]);
                self.queue.prefetch_links(e.code);
                if D == 2 {
                    self.cells.prefetch_cell_index(e.code as usize);
                }
            }
            self.cells.prefetch_heads(*coming);
        }
        *coming = match self.queue.ahead() {
            Some(h) => {
                prefetch_all(&self.grains, &[h as u32]);
                prefetch_all(&self.event, &[h as u32]);
                prefetch_all(&self.last_collision, &[h as u32]);
                self.cells.prefetch_cell_index(h);
                h
            }
            None => usize::MAX,
        };
    }
}
