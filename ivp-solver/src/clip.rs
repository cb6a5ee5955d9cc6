//! The last function's clipped bound (see [`Clip`]), for the search's nodes two or
//! more levels above it.

#[cfg(doc)]
use crate::last_index::LastIndex;
use crate::prepared::intersects;
use std::cmp::Ordering::{Equal, Less};

/// The last function's pieces, for a tighter bound of nodes two or more levels above
/// it when it is one cell and has no [`LastIndex`] (a waypoint's course × speed, or a
/// speed × depth function, below 1-D functions: their global bound is loose).
///
/// `max_q maxVal(q ∩ b)` over the pieces `q` meeting box `b` bounds the last
/// function over `b`: a leaf below `b` lies in `b ∩ q` for its piece `q`, so its value
/// is at most `maxVal(b) + Σ cheap bounds of the functions between + maxVal(q ∩ b)`
/// (up to rounding, which the search's slack covers, as for [`LastIndex`] bounds).
#[derive(Clone, Copy)]
pub(crate) struct Clip<'a> {
    pub(crate) boxes: &'a [i32],
    pub(crate) weights: &'a [f64],
    /// The pieces' `maxVal`s when the set-up made them (else empty).
    pub(crate) ubs: &'a [f64],
    pub(crate) n: usize,
    /// Bit `d`: the last function has problem dimension `d` (the others are whole,
    /// slope 0: a box narrow only there leaves the global bound as tight as this one).
    pub(crate) dims: u32,
    /// The first level (functions `from..` not yet fixed) whose nodes may be narrower
    /// in one of those dimensions: above it the bound is the global one.
    pub(crate) from: usize,
}

impl Clip<'_> {
    /// Whether box `b` is narrower than the domain in a dimension of the function.
    /// (Only the set bits of `dims` are looked at: every one is below `pts.len()`.)
    #[inline(always)]
    pub(crate) fn narrows(&self, b: &[i32], pts: &[i32]) -> bool {
        let mut m = self.dims;
        while m != 0 {
            let d = m.trailing_zeros() as usize;
            m &= m - 1;
            if d < pts.len() && (b[2 * d] > 0 || b[2 * d + 1] < pts[d] - 1) {
                return true;
            }
        }
        false
    }

    /// `prefix + bound(b) <= thr` ([`Clip::bound`]), without making the bound: that
    /// holds iff `prefix + maxVal(q ∩ b) <= thr` for every piece `q` meeting `b` (a
    /// rounded sum is monotone in each term, so the largest term makes the largest
    /// sum), and a NaN term (the bound's, kept) fails it. A piece with
    /// `prefix + maxVal(q) <= thr` passes unlooked at: `maxVal(q ∩ b) <= maxVal(q)`
    /// exactly (the same operations on a corner no farther out: each rounded product
    /// and sum monotone); a NaN `maxVal(q)` never passes so.
    #[inline]
    pub(crate) fn within(&self, b: &[i32], prefix: f64, thr: f64, dim: usize) -> bool {
        match dim {
            1 => self.within_dim::<1>(b, prefix, thr),
            2 => self.within_dim::<2>(b, prefix, thr),
            3 => self.within_dim::<3>(b, prefix, thr),
            _ => prefix + self.bound(b, dim) <= thr,
        }
    }

    /// [`Clip::within`] for `D` dimensions, the pieces' `maxVal`s read when made.
    #[inline(always)]
    fn within_dim<const D: usize>(&self, b: &[i32], prefix: f64, thr: f64) -> bool {
        if self.ubs.len() == self.n {
            self.within_ubs::<D, true>(b, prefix, thr)
        } else {
            self.within_ubs::<D, false>(b, prefix, thr)
        }
    }

    /// [`Clip::within`] for `D` dimensions, with (`U`) or without the pieces' `maxVal`s
    /// (chosen once, not per piece).
    #[inline(always)]
    fn within_ubs<const D: usize, const U: bool>(&self, b: &[i32], prefix: f64, thr: f64) -> bool {
        let (bl, wl) = (2 * D, D + 1);
        let b = &b[..bl];
        let pieces = self
            .boxes
            .chunks_exact(bl)
            .zip(self.weights.chunks_exact(wl))
            .take(self.n);
        let mut any = false;
        for (q, (qb, qw)) in pieces.enumerate() {
            if U && prefix + self.ubs[q] <= thr {
                continue;
            }
            if !intersects(b, qb, D) {
                continue;
            }
            let mut v = qw[D];
            for d in 0..D {
                let c = if qw[d] < 0.0 {
                    b[2 * d].max(qb[2 * d])
                } else {
                    b[2 * d + 1].min(qb[2 * d + 1])
                };
                v += qw[d] * f64::from(c);
            }
            // Not `<=` (NaN fails).
            if !matches!((prefix + v).partial_cmp(&thr), Some(Less | Equal)) {
                return false;
            }
            any = true;
        }
        // No piece meets `b`: the bound is `-inf`.
        any || prefix + f64::NEG_INFINITY <= thr
    }

    /// `max maxVal(q ∩ b)` over the pieces meeting `b` (`-inf` for none, NaN kept).
    #[inline]
    pub(crate) fn bound(&self, b: &[i32], dim: usize) -> f64 {
        let (bl, wl) = (2 * dim, dim + 1);
        let mut best = f64::NEG_INFINITY;
        let pieces = self
            .boxes
            .chunks_exact(bl)
            .zip(self.weights.chunks_exact(wl));
        for (qb, qw) in pieces.take(self.n) {
            if !intersects(b, qb, dim) {
                continue;
            }
            let mut v = qw[dim];
            for d in 0..dim {
                let c = if qw[d] < 0.0 {
                    b[2 * d].max(qb[2 * d])
                } else {
                    b[2 * d + 1].min(qb[2 * d + 1])
                };
                v += qw[d] * f64::from(c);
            }
            if v > best || v.is_nan() {
                best = v;
            }
        }
        best
    }
}
