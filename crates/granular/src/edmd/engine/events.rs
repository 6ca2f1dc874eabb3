//! The scheduled event of a grain: its 8-byte internal form ([`Scheduled`]: a partner
//! slot, or a code above every slot for cell crossings, walls and "nothing"), the codes,
//! and the public, decoded form ([`EventKind`]).

use super::Edmd;
use serde::{Deserialize, Serialize};

/// What a particle's scheduled event is (the public, decoded form of the internal
/// `Scheduled`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// Nothing will ever happen to this particle (it is at rest, without gravity).
    Nothing,
    /// Collision with particle `partner`, valid while its counter equals `partner_counter`.
    Pair {
        /// The other particle (grain id).
        partner: u32,
        /// The partner's collision counter when the event was predicted.
        partner_counter: u32,
    },
    /// Collision with the wall at the low (`upper = false`) or high end of `axis`.
    Wall {
        /// Axis perpendicular to the wall.
        axis: u8,
        /// Whether it is the wall at `x = L` (else `x = 0`).
        upper: bool,
    },
    /// The centre crosses into the neighbouring cell along `axis`.
    CellCrossing {
        /// Axis crossed.
        axis: u8,
        /// Whether the particle moves up (`+1`) or down (`-1`) the axis.
        upward: bool,
    },
}

/// First code of the non-pair events in [`Scheduled::code`]; grain indices stay below it.
pub(super) const FIRST_SPECIAL: u32 = 1 << 31;

/// Cell-crossing codes: `CROSSING + ((2 axis + upward) << HINT_BITS) + hint`, where the
/// hint is the best pair partner of the prediction that scheduled the crossing (see
/// [`Search::Layer`]), [`HINT_NO_PAIR`] or [`HINT_NONE`].
pub(super) const CROSSING: u32 = FIRST_SPECIAL;

/// Bits of a crossing code that hold the hint.
pub(super) const HINT_BITS: u32 = 28;

/// Hint of a crossing scheduled without a usable pair bound: the crossing re-predicts in
/// full.
pub(super) const HINT_NONE: u32 = (1 << HINT_BITS) - 1;

/// Hint of a crossing scheduled by a prediction that found no pair at all.
pub(super) const HINT_NO_PAIR: u32 = HINT_NONE - 1;

/// End of the crossing codes (2 directions on each of at most 3 axes).
pub(super) const CROSSING_END: u32 = CROSSING + (6 << HINT_BITS);

/// Wall codes: `WALL + 2 axis + upper`.
pub(super) const WALL: u32 = CROSSING_END;

/// Code of "nothing scheduled".
pub(super) const NOTHING: u32 = u32::MAX;

/// The code of a crossing along `axis` (up or down), without a hint.
#[inline(always)]
pub(super) fn crossing_code(axis: usize, upward: bool) -> u32 {
    CROSSING + ((2 * axis as u32 + upward as u32) << HINT_BITS)
}

/// Axis, direction and hint of a crossing code.
#[inline(always)]
pub(super) fn decode_crossing(code: u32) -> (usize, bool, u32) {
    let dir = (code - CROSSING) >> HINT_BITS;
    ((dir / 2) as usize, dir % 2 == 1, code & HINT_NONE)
}

/// A scheduled event in 8 bytes: a partner index (or a code above every index for walls,
/// cell crossings and "nothing") and the partner's collision counter at prediction time
/// (for a crossing with a hint: the hinted partner's counter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) struct Scheduled {
    pub(super) code: u32,
    pub(super) partner_counter: u32,
}

impl Scheduled {
    pub(super) const NOTHING: Scheduled = Scheduled {
        code: NOTHING,
        partner_counter: 0,
    };
}

impl<const D: usize> Edmd<D> {
    /// The scheduled event of grain `id` (partners as grain ids).
    pub fn scheduled_event(&self, id: usize) -> EventKind {
        let e = self.event[self.slot_of(id)];
        match e.code {
            NOTHING => EventKind::Nothing,
            c if c >= WALL => EventKind::Wall {
                axis: ((c - WALL) / 2) as u8,
                upper: (c - WALL) % 2 == 1,
            },
            c if c >= CROSSING => {
                let (axis, upward, _) = decode_crossing(c);
                EventKind::CellCrossing {
                    axis: axis as u8,
                    upward,
                }
            }
            c => EventKind::Pair {
                partner: self.id[c as usize],
                partner_counter: e.partner_counter,
            },
        }
    }
}
