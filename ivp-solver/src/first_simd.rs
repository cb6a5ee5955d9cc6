//! AVX2 bodies of the first level's two tight loops (see `first_level.rs`), four
//! pieces a step: each lane makes the scalar loop's sums (the same additions in the
//! same order) and tests (ordered compares: a NaN passes none, as `<=` and `>` do), and
//! the step stops at the first lane the scalar loop stops at. Only whole groups of four
//! are done here; the caller's scalar loop goes on from the piece returned (the one it
//! stops at, or the last few).
//!
//! Each table read ends with one more entry, for the lanes without a cell: the cell
//! numbers are clamped below the table's length, so [`NO_CELL`] (and a number a list
//! made for another table might hold) reads that last entry, never outside: the last
//! index's bounds end with the last function's global bound (the scalar loops' bound
//! without a cell), the middle sums with NaN (no bound passes a test).
//!
//! [`NO_CELL`]: crate::last_index::NO_CELL

use std::arch::x86_64::*;

/// What the two-function loop reads (see [`pass_two`]).
pub(crate) struct Two<'a> {
    /// The first function's `maxVal`s and last-index cells ([`NO_CELL`] for none).
    ///
    /// [`NO_CELL`]: crate::last_index::NO_CELL
    pub(crate) mvs: &'a [f64],
    pub(crate) cells: &'a [u32],
    /// The last index's cell bounds, then `last_ub`.
    pub(crate) ub: &'a [f64],
    pub(crate) last_ub: f64,
    pub(crate) best: f64,
    pub(crate) floor: f64,
}

/// `table[c]` of the 4 cell numbers `c` at `p`, each clamped below `table.len()` (at
/// least 1).
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn gather(table: &[f64], p: *const u32) -> __m256d {
    let top = _mm_set1_epi32(table.len().min(i32::MAX as usize) as i32 - 1);
    // SAFETY: the caller has 4 readable `u32`s at `p`; every index is clamped below
    // `table.len()`.
    unsafe {
        let c = _mm_min_epu32(_mm_loadu_si128(p.cast()), top);
        _mm256_i32gather_pd::<8>(table.as_ptr(), c)
    }
}

/// The first lane of 4 whose bit in `pass` is clear (4 for none).
#[inline(always)]
fn first_fail(pass: i32) -> usize {
    (!pass | 0x10).trailing_zeros() as usize
}

/// The two-function loop of `Search::run_indexed` over whole groups of four from piece
/// `q` (at most `n`, no more than `t.mvs` and `t.cells` hold): per piece `rb = mv +
/// last_ub` passes at `rb <= best` (raising the returned doubt when `watch` and
/// `rb > floor`), else `tb = mv + ub[cell]` (`rb` without a cell) passes at
/// `tb <= floor`. Returns the first piece not passed (or where fewer than 4 remain) and
/// whether a piece before it raised doubt.
#[target_feature(enable = "avx2")]
pub(crate) fn pass_two(t: &Two, q: usize, n: usize, watch: bool) -> (usize, bool) {
    match watch {
        true => pass_two_body::<true>(t, q, n),
        false => pass_two_body::<false>(t, q, n),
    }
}

/// [`pass_two`] with `WATCH` for `watch`.
#[target_feature(enable = "avx2")]
#[inline]
fn pass_two_body<const WATCH: bool>(t: &Two, mut q: usize, n: usize) -> (usize, bool) {
    let n = n.min(t.mvs.len()).min(t.cells.len());
    if t.ub.is_empty() {
        return (q, false);
    }
    let (lu, best, floor) = (
        _mm256_set1_pd(t.last_ub),
        _mm256_set1_pd(t.best),
        _mm256_set1_pd(t.floor),
    );
    // The lanes raising doubt in the groups passed whole, and the first lanes of the
    // group stopped in.
    let (mut near, mut doubt) = (_mm256_setzero_pd(), false);
    while q + 4 <= n {
        // SAFETY: q + 4 <= n reads mvs[q..q+4] and cells[q..q+4].
        let (mv, ub) = unsafe {
            (
                _mm256_loadu_pd(t.mvs.as_ptr().add(q)),
                gather(t.ub, t.cells.as_ptr().add(q)),
            )
        };
        let rb = _mm256_add_pd(mv, lu);
        let low = _mm256_cmp_pd::<_CMP_LE_OQ>(rb, best);
        // Without a cell `ub` is `last_ub`: `tb` is `rb`, bit for bit.
        let tb = _mm256_add_pd(mv, ub);
        let under = _mm256_cmp_pd::<_CMP_LE_OQ>(tb, floor);
        let pass = _mm256_movemask_pd(_mm256_or_pd(low, under));
        let close = _mm256_and_pd(low, _mm256_cmp_pd::<_CMP_GT_OQ>(rb, floor));
        if pass != 0b1111 {
            let k = first_fail(pass);
            doubt = WATCH && _mm256_movemask_pd(close) & ((1 << k) - 1) != 0;
            q += k;
            break;
        }
        if WATCH {
            near = _mm256_or_pd(near, close);
        }
        q += 4;
    }
    (q, doubt || (WATCH && _mm256_movemask_pd(near) != 0))
}

/// What the quick-bound loop reads (see [`pass_mid`]).
pub(crate) struct Mid<'a> {
    pub(crate) mvs: &'a [f64],
    pub(crate) cells: &'a [u32],
    /// The last index's cell bounds, then the last function's global bound.
    pub(crate) ub: &'a [f64],
    /// The first pieces' middle cells ([`NO_CELL`] for none) and the cells' sums, then
    /// NaN.
    ///
    /// [`NO_CELL`]: crate::last_index::NO_CELL
    pub(crate) tops: &'a [u32],
    pub(crate) sums: &'a [f64],
    pub(crate) lim: f64,
}

/// The quick-bound loop of `Search::run_indexed` over whole groups of four from piece
/// `q` (at most `n`): a piece with a middle cell passes at
/// `(mv + sums[top]) + lb <= lim`, `lb` its index cell's bound (`last_ub` without one).
/// Returns the first piece not passed (or where fewer than 4 remain).
#[target_feature(enable = "avx2")]
pub(crate) fn pass_mid(t: &Mid, mut q: usize, n: usize) -> usize {
    let n = n.min(t.mvs.len()).min(t.cells.len()).min(t.tops.len());
    if t.ub.is_empty() || t.sums.is_empty() {
        return q;
    }
    let lim = _mm256_set1_pd(t.lim);
    while q + 4 <= n {
        // SAFETY: q + 4 <= n reads mvs, cells and tops at q..q+4.
        let (mv, lb, s) = unsafe {
            (
                _mm256_loadu_pd(t.mvs.as_ptr().add(q)),
                gather(t.ub, t.cells.as_ptr().add(q)),
                gather(t.sums, t.tops.as_ptr().add(q)),
            )
        };
        // Without a middle cell `s` is NaN: the lane fails, where the scalar loop stops.
        let v = _mm256_add_pd(_mm256_add_pd(mv, s), lb);
        let k = first_fail(_mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(v, lim)));
        q += k;
        if k < 4 {
            break;
        }
    }
    q
}
