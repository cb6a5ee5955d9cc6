//! AVX2 bodies of the set-up's two passes over the pieces (see `weigh`) for the hot
//! shape: two-dimensional pieces, weights already in problem order (the contacts'
//! course × speed functions, thousands of pieces a decision). Four pieces a step,
//! read as array-of-structs (bounds `[lo0, hi0, lo1, hi1]`, weights `[w0, w1, c]`)
//! and spread into one vector per field. Every per-piece value is made with the same
//! operations in the same order as the scalar loops (separate multiply and add, never
//! fused), so it is the same bit for bit; what the lanes cannot know (which piece came
//! first, the last NaN) is tracked or left to the caller, as each function says.
//!
//! Only the whole groups of four are done here; the caller finishes the rest with its
//! scalar loop, starting from the values returned. The boxes are always a checked
//! function's (`0 <= lo <= hi`, see [`by_sign`]).

use std::arch::x86_64::*;

/// The bounds of the 4 pieces at `b` (16 `i32`s) as `[lo0, hi0, lo1, hi1]`, 4 lanes each.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn bounds4(b: *const i32) -> [__m256d; 4] {
    // SAFETY (all loads here): the caller has 16 readable `i32`s at `b`.
    let (p01, p23) = unsafe {
        (
            _mm256_loadu_si256(b.cast()),
            _mm256_loadu_si256(b.add(8).cast()),
        )
    };
    // [l0a h0a l1a h1a l0b ...] -> [l0a l0b h0a h0b | l1a l1b h1a h1b]
    let pair = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    let (p01, p23) = (
        _mm256_permutevar8x32_epi32(p01, pair),
        _mm256_permutevar8x32_epi32(p23, pair),
    );
    let (lo, hi) = (
        _mm256_unpacklo_epi64(p01, p23),
        _mm256_unpackhi_epi64(p01, p23),
    );
    [
        _mm256_cvtepi32_pd(_mm256_castsi256_si128(lo)),
        _mm256_cvtepi32_pd(_mm256_castsi256_si128(hi)),
        _mm256_cvtepi32_pd(_mm256_extracti128_si256::<1>(lo)),
        _mm256_cvtepi32_pd(_mm256_extracti128_si256::<1>(hi)),
    ]
}

/// 4 pieces' weights, 3 vectors in memory order, as `[w0, w1, c]`, 4 lanes each.
#[target_feature(enable = "avx2")]
#[inline]
fn spread3(a: __m256d, b: __m256d, c: __m256d) -> [__m256d; 3] {
    // a = [w0a w1a ca w0b], b = [w1b cb w0c w1c], c = [cc w0d w1d cd]: the halves
    // paired as `load_spread3` reads them (one permute each), then one blend or
    // shuffle per field.
    let m0 = _mm256_permute2f128_pd::<0x30>(a, b); // w0a w1a | w0c w1c
    let m1 = _mm256_permute2f128_pd::<0x21>(a, c); // ca  w0b | cc  w0d
    let m2 = _mm256_permute2f128_pd::<0x30>(b, c); // w1b cb  | w1d cd
    gather3(m0, m1, m2)
}

/// `[w0, w1, c]` of 4 pieces from their halves paired as [`spread3`] pairs them.
#[target_feature(enable = "avx2")]
#[inline]
fn gather3(m0: __m256d, m1: __m256d, m2: __m256d) -> [__m256d; 3] {
    [
        _mm256_blend_pd::<0b1010>(m0, m1),
        _mm256_shuffle_pd::<0b0101>(m0, m2),
        _mm256_blend_pd::<0b1010>(m1, m2),
    ]
}

/// [`spread3`] of the 4 pieces' weights at `w` (12 `f64`s), read as halves: each half
/// vector holds two pieces' values in the lanes they go to, so one blend or shuffle
/// per field gathers them (no cross-lane permute): the same lanes, fewer instructions.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn load_spread3(w: *const f64) -> [__m256d; 3] {
    // SAFETY (all loads): the caller has 12 `f64`s at `w`.
    let (m0, m1, m2) = unsafe {
        (
            _mm256_loadu2_m128d(w.add(6), w),         // w0a w1a | w0c w1c
            _mm256_loadu2_m128d(w.add(8), w.add(2)),  // ca  w0b | cc  w0d
            _mm256_loadu2_m128d(w.add(10), w.add(4)), // w1b cb  | w1d cd
        )
    };
    gather3(m0, m1, m2)
}

/// `x < 0 ? neg : pos`, lane by lane, for the two corners `neg`, `pos` of a checked
/// function's box (zero or more), chosen by `x`'s sign bit (one blend, no
/// comparison): that differs from `x < 0` only where `x` is -0.0 or a NaN with its
/// sign set, and then `x` times either corner has the same bits (a zero of `x`'s
/// sign, `x`'s NaN). Only for `x · by_sign(x, ..)` of such corners, then.
#[target_feature(enable = "avx2")]
#[inline]
fn by_sign(x: __m256d, neg: __m256d, pos: __m256d) -> __m256d {
    _mm256_blendv_pd(pos, neg, x)
}

/// The boxes of the whole groups of four 2-D pieces `boxes` (`[lo0, hi0, lo1, hi1]`
/// each) as `f64`s, per group `[lo0; 4]`, `[hi0; 4]`, `[lo1; 4]`, `[hi1; 4]` (the
/// lanes [`bounds4`] makes), into `out`: the boxes of a tiling stay from one solve to
/// the next, so the passes read them so instead of spreading and converting them each
/// time. The boxes are a checked function's (`0 <= lo <= hi`), which the passes
/// reading the corners rely on (see [`lo_hi`], [`by_sign`]).
#[target_feature(enable = "avx2")]
pub(crate) fn corners2(boxes: &[i32], out: &mut Vec<f64>) {
    let groups = boxes.len() / 16;
    out.clear();
    out.resize(16 * groups, 0.0);
    for g in 0..groups {
        // SAFETY: group g < groups reads boxes[16g..16g+16], writes out[16g..16g+16].
        unsafe {
            let v = bounds4(boxes.as_ptr().add(16 * g));
            for (k, v) in v.iter().enumerate() {
                _mm256_storeu_pd(out.as_mut_ptr().add(16 * g + 4 * k), *v);
            }
        }
    }
}

/// Where [`extremes2`] reads the boxes of its groups of four: `Ints` the pieces' own,
/// `Corners` as [`corners2`] made them from the pieces' boxes in the problem's order,
/// `swap` when the function has its two dimensions the other way round.
#[derive(Clone, Copy)]
pub(crate) enum Boxes2<'a> {
    Ints(&'a [i32]),
    Corners(&'a [f64], bool),
}

/// The extremes of the first `4·k` pieces (as many whole groups as both slices hold):
/// `(k·4, least lo, greatest hi)`, each the value of the FIRST piece reaching it, as
/// the scalar `if lo < mn` keeps. Each lane keeps its own first (`min`/`max` keep the
/// held value on a tie or a NaN, as the scalar test does); equal values have equal bits
/// but for -0.0 and +0.0, so only when lanes hold zeros of both signs is the first
/// piece at zero looked up (see [`first_zero`]). NaN values are skipped, as the scalar
/// loop does once it holds a number: the caller must not come here when the first
/// piece's extremes are NaN.
#[target_feature(enable = "avx2")]
pub(crate) fn extremes2(boxes: Boxes2, weights: &[f64]) -> (usize, f64, f64) {
    match boxes {
        Boxes2::Ints(b) => extremes2_from::<0>(b, &[], weights),
        Boxes2::Corners(c, false) => extremes2_from::<1>(&[], c, weights),
        Boxes2::Corners(c, true) => extremes2_from::<2>(&[], c, weights),
    }
}

/// The bounds of group `g` in the function's order, as `[lo0, hi0, lo1, hi1]` lanes:
/// from `ints` (`FROM` 0) or `corners` (1; 2 with the dimensions swapped).
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn group_bounds<const FROM: u8>(ints: &[i32], corners: &[f64], g: usize) -> [__m256d; 4] {
    // SAFETY (all loads): the caller's group is whole in the slice read.
    unsafe {
        if FROM == 0 {
            return bounds4(ints.as_ptr().add(16 * g));
        }
        let c = corners.as_ptr().add(16 * g);
        let [l0, h0, l1, h1] = [0, 4, 8, 12].map(|k| _mm256_loadu_pd(c.add(k)));
        if FROM == 2 {
            [l1, h1, l0, h0]
        } else {
            [l0, h0, l1, h1]
        }
    }
}

/// [`extremes2`] from the bounds of [`group_bounds`].
#[target_feature(enable = "avx2")]
#[inline]
fn extremes2_from<const FROM: u8>(
    ints: &[i32],
    corners: &[f64],
    weights: &[f64],
) -> (usize, f64, f64) {
    let held = if FROM == 0 { ints.len() } else { corners.len() };
    let groups = (held / 16).min(weights.len() / 12);
    let (mut mn, mut mx) = (
        _mm256_set1_pd(f64::INFINITY),
        _mm256_set1_pd(f64::NEG_INFINITY),
    );
    macro_rules! group {
        ($g:expr) => {{
            let g = $g;
            // SAFETY: group g < groups is whole in the bounds and in `weights`.
            let (lo, hi) = unsafe {
                lo_hi::<FROM>(
                    group_bounds::<FROM>(ints, corners, g),
                    weights.as_ptr().add(12 * g),
                )
            };
            // `lo < mn ? lo : mn`, `hi > mx ? hi : mx`.
            mn = _mm256_min_pd(lo, mn);
            mx = _mm256_max_pd(hi, mx);
        }};
    }
    // Two groups a step (half the loop's own instructions), in order.
    for p in 0..groups / 2 {
        group!(2 * p);
        group!(2 * p + 1);
    }
    if groups % 2 == 1 {
        group!(groups - 1);
    }
    let lo = first_best(mn, |a, b| a < b);
    let hi = first_best(mx, |a, b| a > b);
    let (lo, hi) = match (lo, hi) {
        (Some(lo), Some(hi)) => (lo, hi),
        // SAFETY: as the loop above, over the same groups.
        _ => unsafe {
            (
                lo.unwrap_or_else(|| first_zero::<FROM>(ints, corners, weights, groups, false)),
                hi.unwrap_or_else(|| first_zero::<FROM>(ints, corners, weights, groups, true)),
            )
        },
    };
    (4 * groups, lo, hi)
}

/// The lo and hi extremes of 4 pieces with bounds `[l0, h0, l1, h1]` and weights at
/// `w` (12 `f64`s), by the scalar loop's operations: `(c + w0·x0) + w1·x1`, `x_d` the
/// corner by `w_d`'s sign.
///
/// From the corners (`FROM` not 0: boxes of a checked function, `0 <= lo <= hi`) the
/// corner products are ordered by the weight's sign (`w·lo <= w·hi` for `w >= 0`, the
/// other way below, each product rounded monotonely; zeros of one sign), so the hi
/// one is the greater product and the lo one the lesser: `max`/`min` of the two
/// instead of a test and two blends. Only where a product is NaN (an infinite weight
/// on a zero bound) can a lane differ from the test's, and then it holds an infinity
/// no extreme takes, where the test's holds a NaN none takes either.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn lo_hi<const FROM: u8>(
    [l0, h0, l1, h1]: [__m256d; 4],
    w: *const f64,
) -> (__m256d, __m256d) {
    // SAFETY: the caller has 12 `f64`s at `w`.
    let [w0, w1, cc] = unsafe { load_spread3(w) };
    if FROM != 0 {
        // `max(a, b)` is `a > b ? a : b`: a NaN `w·lo` gives `w·hi`, as the test would
        // for a weight that is not negative.
        let (p0, q0) = (_mm256_mul_pd(w0, l0), _mm256_mul_pd(w0, h0));
        let (p1, q1) = (_mm256_mul_pd(w1, l1), _mm256_mul_pd(w1, h1));
        let hi = _mm256_add_pd(cc, _mm256_max_pd(p0, q0));
        let lo = _mm256_add_pd(cc, _mm256_min_pd(p0, q0));
        let hi = _mm256_add_pd(hi, _mm256_max_pd(p1, q1));
        let lo = _mm256_add_pd(lo, _mm256_min_pd(p1, q1));
        return (lo, hi);
    }
    let hi = _mm256_add_pd(cc, _mm256_mul_pd(w0, by_sign(w0, l0, h0)));
    let lo = _mm256_add_pd(cc, _mm256_mul_pd(w0, by_sign(w0, h0, l0)));
    let hi = _mm256_add_pd(hi, _mm256_mul_pd(w1, by_sign(w1, l1, h1)));
    let lo = _mm256_add_pd(lo, _mm256_mul_pd(w1, by_sign(w1, h1, l1)));
    (lo, hi)
}

/// The best of the 4 lanes `v` by `better`, `None` when the lanes at the best value
/// differ in their bits (zeros of both signs: which came first is not known).
#[target_feature(enable = "avx2")]
#[inline]
fn first_best(v: __m256d, better: fn(f64, f64) -> bool) -> Option<f64> {
    let mut x = [0.0f64; 4];
    // SAFETY: 4 doubles into an array of 4.
    unsafe { _mm256_storeu_pd(x.as_mut_ptr(), v) };
    let best = x[1..]
        .iter()
        .fold(x[0], |b, &y| if better(y, b) { y } else { b });
    let at_best = x.iter().filter(|&&y| y == best);
    at_best
        .clone()
        .all(|y| y.to_bits() == best.to_bits())
        .then_some(best)
}

/// The lo (with `hi`, the hi) extreme of the first of the `4·groups` pieces whose is
/// a zero: the first to reach the best value when that is a zero of either sign.
#[target_feature(enable = "avx2")]
unsafe fn first_zero<const FROM: u8>(
    ints: &[i32],
    corners: &[f64],
    weights: &[f64],
    groups: usize,
    hi: bool,
) -> f64 {
    let zero = _mm256_setzero_pd();
    for g in 0..groups {
        // SAFETY: the caller's groups, whole in the bounds and in `weights`.
        let (lo, h) = unsafe {
            lo_hi::<FROM>(
                group_bounds::<FROM>(ints, corners, g),
                weights.as_ptr().add(12 * g),
            )
        };
        let v = if hi { h } else { lo };
        let at = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(v, zero));
        if at != 0 {
            let mut x = [0.0f64; 4];
            // SAFETY: 4 doubles into an array of 4.
            unsafe { _mm256_storeu_pd(x.as_mut_ptr(), v) };
            return x[at.trailing_zeros() as usize];
        }
    }
    // Not reached: the lanes held a zero.
    0.0
}

/// How [`weigh2`] makes the weights: `Some((shift, scale))` normalizes.
pub(crate) struct Scale2 {
    pub(crate) norm: Option<(f64, f64)>,
    pub(crate) pwt: f64,
    /// `f64::from((pts_d - 1).max(0))` of the two problem dimensions.
    pub(crate) span: [f64; 2],
}

/// 4 pieces' weights in memory order (`[a0 b0 c0 a1]`, `[b1 c1 a2 b2]`, `[c2 a3 b3 c3]`,
/// slopes `a`, `b`, intercept `c`) with each piece's two slopes swapped.
#[target_feature(enable = "avx2")]
#[inline]
fn swap_slopes(v: [__m256d; 3]) -> [__m256d; 3] {
    let low = _mm256_permute2f128_pd::<0x20>(v[0], v[1]); // a0 b0 b1 c1
    let high = _mm256_permute2f128_pd::<0x31>(v[0], v[1]); // c0 a1 a2 b2
    [
        _mm256_shuffle_pd::<0b0001>(v[0], low),       // b0 a0 c0 b1
        _mm256_shuffle_pd::<0b0111>(high, v[1]),      // a1 c1 b2 a2
        _mm256_permute4x64_pd::<0b11_01_10_00>(v[2]), // c2 b3 a3 c3
    ]
}

/// The first `4·k` pieces (whole groups that `src`, `weights`, `ub` and, if given,
/// `boxes` all hold) of `weigh` for two dimensions, the function's in problem order
/// or, with `swap`, the other way round (map `[1, 0]`): weights from `src` into
/// `weights`, each piece's `maxVal` over its box into `ub`, the boxes in the problem's
/// order (as `i32`s or their corners; a corners' `swap` flag is not read). Returns
/// `(4·k, the largest term scale, whether any term was NaN)`; with a NaN the largest
/// is not the scalar's (which keeps the last NaN): the caller recomputes it.
#[target_feature(enable = "avx2")]
pub(crate) fn weigh2(
    sc: &Scale2,
    swap: bool,
    src: &[f64],
    weights: &mut [f64],
    boxes: Option<Boxes2>,
    ub: &mut [f64],
) -> (usize, f64, bool) {
    let (ints, corners, from): (&[i32], &[f64], u8) = match boxes {
        None => (&[], &[], 0),
        Some(Boxes2::Ints(b)) => (b, &[], 1),
        Some(Boxes2::Corners(c, _)) => (&[], c, 2),
    };
    let b = (ints, corners);
    macro_rules! body {
        ($($s:literal $n:literal $f:literal),*) => {
            match (swap, sc.norm.is_some(), from) {
                $(($s, $n, $f) => weigh2_body::<$s, $n, $f>(sc, src, weights, b, ub),)*
                _ => unreachable!("from is 0, 1 or 2"),
            }
        };
    }
    body!(
        false false 0, false false 1, false false 2, false true 0, false true 1, false true 2,
        true false 0, true false 1, true false 2, true true 0, true true 1, true true 2
    )
}

/// [`weigh2`] for a constant `SWAP`, `NORM` (`sc.norm` is some) and `FROM`: 0 no
/// boxes, 1 the `i32` boxes, 2 their corners.
#[target_feature(enable = "avx2")]
#[inline]
fn weigh2_body<const SWAP: bool, const NORM: bool, const FROM: u8>(
    sc: &Scale2,
    src: &[f64],
    weights: &mut [f64],
    (ints, corners): (&[i32], &[f64]),
    ub: &mut [f64],
) -> (usize, f64, bool) {
    let mut groups = (src.len() / 12).min(weights.len() / 12);
    if FROM > 0 {
        let held = if FROM == 1 { ints.len() } else { corners.len() };
        groups = groups.min(held / 16).min(ub.len() / 4);
    }
    let pwt = _mm256_set1_pd(sc.pwt);
    let (k0, k1) = (_mm256_set1_pd(sc.span[0]), _mm256_set1_pd(sc.span[1]));
    let sign = _mm256_set1_pd(-0.0);
    // In memory order, adding -0.0 leaves every slope as it is (-0.0 too); the
    // intercepts get `shift`.
    let (shift, scale) = sc.norm.unwrap_or((0.0, 1.0));
    let z = -0.0;
    let shifts = [
        _mm256_setr_pd(z, z, shift, z),
        _mm256_setr_pd(z, shift, z, z),
        _mm256_setr_pd(shift, z, z, shift),
    ];
    let scale = _mm256_set1_pd(scale);
    // The terms added up: NaN if and only if one is (they are sums of magnitudes).
    let (mut most, mut sum) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    macro_rules! group {
        ($g:expr) => {{
            let g = $g;
            let mut v = [_mm256_setzero_pd(); 3];
            for (k, v) in v.iter_mut().enumerate() {
                // SAFETY: group g < groups reads src[12g..12g+12].
                *v = unsafe { _mm256_loadu_pd(src.as_ptr().add(12 * g + 4 * k)) };
                *v = match NORM {
                    true => _mm256_mul_pd(_mm256_mul_pd(_mm256_add_pd(*v, shifts[k]), scale), pwt),
                    false => _mm256_mul_pd(*v, pwt),
                };
            }
            // The function's order; the problem's is the other way round with `SWAP`.
            let [s0, s1, c] = spread3(v[0], v[1], v[2]);
            let (w0, w1) = if SWAP { (s1, s0) } else { (s0, s1) };
            if SWAP {
                v = swap_slopes(v);
            }
            for (k, v) in v.iter().enumerate() {
                // SAFETY: group g < groups writes weights[12g..12g+12].
                unsafe { _mm256_storeu_pd(weights.as_mut_ptr().add(12 * g + 4 * k), *v) };
            }
            let t = _mm256_andnot_pd(sign, c);
            let t = _mm256_add_pd(t, _mm256_mul_pd(_mm256_andnot_pd(sign, w0), k0));
            let t = _mm256_add_pd(t, _mm256_mul_pd(_mm256_andnot_pd(sign, w1), k1));
            most = _mm256_max_pd(t, most);
            sum = _mm256_add_pd(sum, t);
            if FROM > 0 {
                // SAFETY: group g < groups reads its bounds, writes ub[4g..4g+4].
                let [l0, h0, l1, h1] = unsafe {
                    match FROM {
                        1 => group_bounds::<0>(ints, &[], g),
                        _ => group_bounds::<1>(&[], corners, g),
                    }
                };
                let top = _mm256_add_pd(c, _mm256_mul_pd(w0, by_sign(w0, l0, h0)));
                let top = _mm256_add_pd(top, _mm256_mul_pd(w1, by_sign(w1, l1, h1)));
                unsafe { _mm256_storeu_pd(ub.as_mut_ptr().add(4 * g), top) };
            }
        }};
    }
    // Two groups a step (half the loop's own instructions), in order.
    for p in 0..groups / 2 {
        group!(2 * p);
        group!(2 * p + 1);
    }
    if groups % 2 == 1 {
        group!(groups - 1);
    }
    let nan = _mm256_cmp_pd::<_CMP_UNORD_Q>(sum, sum);
    let mut x = [0.0f64; 4];
    // SAFETY: 4 doubles into an array of 4.
    unsafe { _mm256_storeu_pd(x.as_mut_ptr(), most) };
    // No lane holds NaN or -0.0 (terms are sums of magnitudes): `max` is exact.
    let top = x.iter().fold(0.0f64, |m, &t| if t > m { t } else { m });
    (4 * groups, top, _mm256_movemask_pd(nan) != 0)
}
