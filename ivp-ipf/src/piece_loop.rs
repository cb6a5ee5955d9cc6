//! The piece loop of the usual dimension counts (1 to 3): pieces formatted into the
//! batch with the interval and slope caches.

use super::{PieceText, Utf8Out};
use crate::intervals::{IntervalCache, SlopeCache};

/// The pieces of `D` dimensions (`B` = 2·D bounds and `W` = D + 1 weights each),
/// into `text` (taken and given back by value, and the loop out of line: its length
/// and pointers then stay in registers through the loop).
#[inline(never)]
pub(crate) fn pieces_n<'b, const D: usize, const B: usize, const W: usize>(
    bounds: &[i32],
    weights: &[f64],
    mut text: PieceText<'b>,
    out: &mut Utf8Out<'_>,
    mut intervals: [&mut IntervalCache; D],
    slopes: &mut [SlopeCache; 3],
) -> PieceText<'b> {
    debug_assert!(B == 2 * D && W == D + 1);
    let (bounds, _) = bounds.as_chunks::<B>();
    let (weights, _) = weights.as_chunks::<W>();
    // The slope cache pays where slopes repeat (a Waypoint's few); where they rarely
    // do (a contact function's), filling it costs more than it saves. Once PROBE
    // nonzero slopes were looked up, it stays in use only while at least a third of
    // them were found (checked every PROBE pieces). The text is the same either way.
    // The pieces go by PROBE at a time, so a piece tests no flag or count: the slopes
    // of ±0 and the misses are counted on their own (rarer) paths, the hits follow.
    const PROBE: usize = 32;
    let (mut zeros, mut missed) = (0usize, 0usize);
    let mut done = 0;
    for (bs, ws) in bounds.chunks(PROBE).zip(weights.chunks(PROBE)) {
        let looked = D * done - zeros;
        if looked >= PROBE && 2 * (looked - missed) < missed {
            break;
        }
        for (b, w) in bs.iter().zip(ws) {
            text.make_room(B * PieceText::BOUND_MAX + W * PieceText::WEIGHT_MAX, out);
            piece_intervals::<D, B>(b, &mut text, &mut intervals);
            // Unrolled by hand (`D` is a constant).
            text.slope(w[0], &mut slopes[0], out, (&mut zeros, &mut missed));
            if D >= 2 {
                text.slope(w[1], &mut slopes[1], out, (&mut zeros, &mut missed));
            }
            if D >= 3 {
                text.slope(w[2], &mut slopes[2], out, (&mut zeros, &mut missed));
            }
            text.intercept_or_slow(w[D], out);
        }
        done += bs.len();
    }
    // Without the cache from here on.
    for (b, w) in bounds[done..].iter().zip(&weights[done..]) {
        text.make_room(B * PieceText::BOUND_MAX + W * PieceText::WEIGHT_MAX, out);
        piece_intervals::<D, B>(b, &mut text, &mut intervals);
        // Unrolled by hand (`D` is a constant, 1 to 3): no loop count per weight.
        text.weight_or_slow(w[0], out);
        if D >= 2 {
            text.weight_or_slow(w[1], out);
        }
        if D >= 3 {
            text.weight_or_slow(w[2], out);
        }
        text.intercept_or_slow(w[D], out);
    }
    text
}

/// A piece's `D` intervals (`,lo,hi` each).
#[inline(always)]
fn piece_intervals<const D: usize, const B: usize>(
    b: &[i32; B],
    text: &mut PieceText,
    intervals: &mut [&mut IntervalCache; D],
) {
    for d in 0..D {
        text.interval(b[2 * d], b[2 * d + 1], intervals[d]);
    }
}
