//! The piece loop of the usual dimension counts (1 to 3): pieces formatted into the
//! batch with the interval and slope caches.

use super::{PieceText, Utf8Out};
use crate::intervals::{IntervalCache, SlopeCache};

/// The pieces of `D` dimensions (`B` = 2·D bounds and `W` = D + 1 weights each).
#[inline(always)]
pub(crate) fn pieces_n<const D: usize, const B: usize, const W: usize>(
    bounds: &[i32],
    weights: &[f64],
    text: &mut PieceText,
    out: &mut Utf8Out<'_>,
    intervals: [&mut IntervalCache; D],
    slopes: &mut [SlopeCache; 3],
) {
    debug_assert!(B == 2 * D && W == D + 1);
    let (bounds, _) = bounds.as_chunks::<B>();
    let (weights, _) = weights.as_chunks::<W>();
    // The slope cache pays where slopes repeat (a Waypoint's few); where they rarely
    // do (a contact function's), filling it costs more than it saves. Once PROBE
    // nonzero slopes were looked up, it stays in use only while at least a third of
    // them were found (checked every PROBE pieces). The text is the same either way.
    const PROBE: u32 = 32;
    let (mut found, mut missed, mut cached) = (0u32, 0u32, true);
    for (i, (b, w)) in bounds.iter().zip(weights).enumerate() {
        if cached && i % PROBE as usize == 0 && found + missed >= PROBE {
            cached = 2 * found >= missed;
        }
        text.make_room(B * PieceText::BOUND_MAX + W * PieceText::WEIGHT_MAX, out);
        for d in 0..D {
            text.interval(b[2 * d], b[2 * d + 1], intervals[d]);
        }
        for d in 0..D {
            if !cached {
                text.weight_or_slow(w[d], out);
            } else if let Some(hit) = text.slope(w[d], &mut slopes[d], out) {
                (found, missed) = if hit {
                    (found + 1, missed)
                } else {
                    (found, missed + 1)
                };
            }
        }
        text.weight_or_slow(w[D], out);
    }
}
