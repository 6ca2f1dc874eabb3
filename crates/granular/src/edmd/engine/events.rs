//! The scheduled event of a grain: its 8-byte internal form ([`Scheduled`]: a partner
//! slot, or a code above every slot for cell crossings, walls and "nothing") and the codes.

use serde::{Deserialize, Serialize};

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
