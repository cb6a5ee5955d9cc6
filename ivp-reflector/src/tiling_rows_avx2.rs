//! [`super::fit_run`]'s loops written out for AVX2 when the run's widths are 0 or powers
//! of two (the contact behaviors' tiles of 2 or 3 points): four tiles per step, slopes,
//! intercepts and ranges in one pass, with [`super::fit_run_body`]'s operations in its
//! order. A step whose four tiles each have one value at all their points is filled in
//! (most of a contact's tiles lie where the utility is flat), with the general fit's
//! bits, as follows.
//!
//! Every value `v` of a tile (corners and centre) compare equal, `v` finite. Each
//! corner difference is then +0 (or ±0 for zeros of both signs), each slope sum
//! `(0 + d) + d'` is +0, and so is every slope (+0 · ½ · 2⁻ᵏ, or the zero width's 0).
//! The tiles' edges are integers ≥ 0, so every product `slope · edge` and every plane
//! value `(0 + ax) + by` is +0 and every residual `v − 0` is `v`.
//! - Zeros only: the residual sum `0 + (±0) + …` is +0, so is the intercept, and no
//!   plane value (+0) exceeds or undercuts the values (zeros): intercept +0, strict or
//!   not.
//! - `v` not zero, `|v| < 2¹⁰²⁰`, strict: the sum of 4 or 5 `v` does not overflow and
//!   the intercept `c` (sum / count) is within a few units in the last place of `v`,
//!   of its sign: within a factor 2 of it. If `c > v` the plane's greatest value `c`
//!   exceeds the values' `v` and the intercept becomes `c − (c − v)`, where `c − v` is
//!   exact (Sterbenz) and so the result `v`; if `c < v` likewise `c + (v − c) = v`.
//!   The intercept is `v` (without strict range it would be the rounded mean).
//!
//! Either way the weights are `(+0, +0, v + 0)` (`v + 0` is +0 for −0, else `v`) and
//! the piece's least and greatest value are `v + 0` too (`v + 0 + 0`).
//!
//! The other steps add the plane values as `a·x + b·y`, not `(0 + a·x) + b·y` as the
//! fit does: the two differ only when both products are −0, and then only in the sign of
//! a zero, which no result shows. The residual sum starts from +0, so it is never −0: a
//! zero residual adds nothing, and `v − (±0)` is `v` for any other `v`. In the strict
//! range, the plane value plus the intercept is the intercept, or a zero again; the
//! range compares it with the values (signs do not count), subtracts it from an extreme
//! that is not zero (giving exactly that extreme), or from a zero extreme only in a shift
//! it never picks (`±0 > ±0` is false).

//!
//! The strict range's plane extremes are taken before the intercept is added, once
//! (`min(q) + c`, not `min(q + c)`): rounding never reverses an order, so the two are
//! equal but for the sign of a zero or where `q + c` is NaN for some `q` (an infinite
//! `c`, or a NaN one), and there both sides compare false with the values' extremes
//! (then neither shift is taken), or the shift taken subtracts them from a value that
//! is not zero, which the zero's sign does not change.

use super::{Run, RunOut};
use std::arch::x86_64::*;

/// Below this magnitude five equal values sum without overflow (see the module docs).
const FLAT_LIMIT: f64 = f64::from_bits(0x7fb0_0000_0000_0000); // 2^1020

/// Fit the run's tiles four at a time while four remain; returns how many were fitted
/// (0 when some width is neither 0 nor a power of two: then the caller fits them all).
///
/// # Safety
/// The CPU must have AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn fit_steps(run: &Run<'_>, out: &mut RunOut<'_>) -> usize {
    let (wx, wy) = run.widths;
    let scalable = |w: u32| w == 0 || w.is_power_of_two();
    if !(scalable(wx) && scalable(wy)) {
        return 0;
    }
    match (run.centre, run.strict) {
        (true, true) => steps::<true, true>(run, out),
        (true, false) => steps::<true, false>(run, out),
        (false, true) => steps::<false, true>(run, out),
        (false, false) => steps::<false, false>(run, out),
    }
}

/// A slope's factors for width `w` (0 or a power of two): `1 / w` (exact), and the mask
/// that keeps the product (all bits) or makes it +0 (no bits: the zero width's 0).
#[inline(always)]
unsafe fn slope_factors(w: u32) -> (__m256d, __m256d) {
    if w == 0 {
        (_mm256_set1_pd(1.0), _mm256_setzero_pd())
    } else {
        let ones = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
        (_mm256_set1_pd(1.0 / f64::from(w)), ones)
    }
}

/// Per lane, whether tiles of the one value `v` are filled in: `|v| < 2^1020` if
/// strict, else `v` zero (see the module docs).
#[inline(always)]
unsafe fn fills<const STRICT: bool>(v: __m256d) -> __m256d {
    if STRICT {
        let magnitude = _mm256_and_pd(v, _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX)));
        _mm256_cmp_pd::<_CMP_LT_OQ>(magnitude, _mm256_set1_pd(FLAT_LIMIT))
    } else {
        _mm256_cmp_pd::<_CMP_EQ_OQ>(v, _mm256_setzero_pd())
    }
}

/// [`fit_steps`] for the run's case of centre and strict range.
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn steps<const CENTRE: bool, const STRICT: bool>(
    run: &Run<'_>,
    out: &mut RunOut<'_>,
) -> usize {
    let n = out.min.len().min(out.max.len());
    let n = out.w.iter().fold(n, |n, w| n.min(w.len()));
    let n = run.x.iter().fold(n, |n, x| n.min(x.len()));
    let cnt = if CENTRE { 5 } else { 4 };
    let n = run.vals[..cnt].iter().fold(n, |n, v| n.min(v.len()));
    let zero = _mm256_setzero_pd();
    let ones = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    let half = _mm256_set1_pd(0.5);
    let (rx, mx) = slope_factors(run.widths.0);
    let (ry, my) = slope_factors(run.widths.1);
    // Opaque masks: known, the compiler tests each width in the loop (branches per
    // step) instead of one AND per slope.
    let (mx, my) = std::hint::black_box((mx, my));
    let [yl, yh, ym] = run.y.map(|y| _mm256_set1_pd(y));
    let count = _mm256_set1_pd(if CENTRE { 5.0 } else { 4.0 });
    let (inf, ninf) = (
        _mm256_set1_pd(f64::INFINITY),
        _mm256_set1_pd(f64::NEG_INFINITY),
    );
    let [p0, p1, p2, p3, p4] = run.vals.map(|v| v.as_ptr());
    let [px, ph, pm] = run.x.map(|x| x.as_ptr());
    let [o0, o1, o2] = [0, 1, 2].map(|i| out.w[i].as_mut_ptr());
    let (omin, omax) = (out.min.as_mut_ptr(), out.max.as_mut_ptr());
    // A step's values (the centres' only when CENTRE).
    // SAFETY (every load and store below): k + 4 <= n, at most each list's length (the
    // centres' only read when CENTRE, and then counted in n).
    macro_rules! load {
        ($k:expr) => {{
            let ld = |p: *const f64| _mm256_loadu_pd(p.add($k));
            let v4 = if CENTRE { ld(p4) } else { zero };
            (ld(p0), ld(p1), ld(p2), ld(p3), v4)
        }};
    }
    // Whether every tile of a step has one value (module docs), given `same`, the
    // lanes where the first two corners agree.
    macro_rules! flat {
        ($same:expr, $v0:expr, $v2:expr, $v3:expr, $v4:expr) => {{
            let mut flat = _mm256_and_pd($same, _mm256_cmp_pd::<_CMP_EQ_OQ>($v2, $v0));
            flat = _mm256_and_pd(flat, _mm256_cmp_pd::<_CMP_EQ_OQ>($v3, $v0));
            if CENTRE {
                flat = _mm256_and_pd(flat, _mm256_cmp_pd::<_CMP_EQ_OQ>($v4, $v0));
            }
            flat = _mm256_and_pd(flat, fills::<STRICT>($v0));
            _mm256_testc_pd(flat, ones) != 0
        }};
    }
    // The filled step.
    macro_rules! fill {
        ($k:expr, $v0:expr) => {{
            let k = $k;
            let c = _mm256_add_pd($v0, zero);
            _mm256_storeu_pd(o0.add(k), zero);
            _mm256_storeu_pd(o1.add(k), zero);
            _mm256_storeu_pd(o2.add(k), c);
            _mm256_storeu_pd(omin.add(k), c);
            _mm256_storeu_pd(omax.add(k), c);
        }};
    }
    // The general fit of a step.
    macro_rules! general {
        ($k:expr, ($v0:expr, $v1:expr, $v2:expr, $v3:expr, $v4:expr)) => {{
            let k = $k;
            let (v0, v1, v2, v3, v4) = ($v0, $v1, $v2, $v3, $v4);
            let ld = |p: *const f64| _mm256_loadu_pd(p.add(k));
            // Slopes: (0 + (v1 − v0)) + (v3 − v2), halved, scaled by 1 / width.
            let sum = |d: __m256d, e: __m256d| _mm256_add_pd(_mm256_add_pd(zero, d), e);
            let sx = sum(_mm256_sub_pd(v1, v0), _mm256_sub_pd(v3, v2));
            let sy = sum(_mm256_sub_pd(v2, v0), _mm256_sub_pd(v3, v1));
            let a = _mm256_and_pd(_mm256_mul_pd(_mm256_mul_pd(sx, half), rx), mx);
            let b = _mm256_and_pd(_mm256_mul_pd(_mm256_mul_pd(sy, half), ry), my);
            // Plane values a·x + b·y at the corners, then the centre: the fit's (0 + a·x) + b·y
            // but for the sign of a zero, which no result shows (module docs).
            let (axl, axh) = (_mm256_mul_pd(a, ld(px)), _mm256_mul_pd(a, ld(ph)));
            let (byl, byh) = (_mm256_mul_pd(b, yl), _mm256_mul_pd(b, yh));
            let q0 = _mm256_add_pd(axl, byl);
            let q1 = _mm256_add_pd(axh, byl);
            let q2 = _mm256_add_pd(axl, byh);
            let q3 = _mm256_add_pd(axh, byh);
            let q4 = if CENTRE {
                _mm256_add_pd(_mm256_mul_pd(a, ld(pm)), _mm256_mul_pd(b, ym))
            } else {
                zero
            };
            let mut isum = _mm256_add_pd(zero, _mm256_sub_pd(v0, q0));
            isum = _mm256_add_pd(isum, _mm256_sub_pd(v1, q1));
            isum = _mm256_add_pd(isum, _mm256_sub_pd(v2, q2));
            isum = _mm256_add_pd(isum, _mm256_sub_pd(v3, q3));
            if CENTRE {
                isum = _mm256_add_pd(isum, _mm256_sub_pd(v4, q4));
            }
            let mut icpt = _mm256_div_pd(isum, count);
            if STRICT {
                // min(x, m) is `x < m ? x : m`, max(x, m) `x > m ? x : m`: the fit's picks.
                // The plane's extremes shifted once, not each value (module docs).
                let (mut vmin, mut vmax, mut qmin, mut qmax) = (inf, ninf, inf, ninf);
                let pairs = [(v0, q0), (v1, q1), (v2, q2), (v3, q3), (v4, q4)];
                for &(v, q) in &pairs[..cnt] {
                    vmin = _mm256_min_pd(v, vmin);
                    vmax = _mm256_max_pd(v, vmax);
                    qmin = _mm256_min_pd(q, qmin);
                    qmax = _mm256_max_pd(q, qmax);
                }
                let (pmin, pmax) = (_mm256_add_pd(qmin, icpt), _mm256_add_pd(qmax, icpt));
                let down = _mm256_sub_pd(icpt, _mm256_sub_pd(pmax, vmax));
                let up = _mm256_add_pd(icpt, _mm256_sub_pd(vmin, pmin));
                icpt = _mm256_blendv_pd(icpt, up, _mm256_cmp_pd::<_CMP_LT_OQ>(pmin, vmin));
                icpt = _mm256_blendv_pd(icpt, down, _mm256_cmp_pd::<_CMP_GT_OQ>(pmax, vmax));
            }
            // The piece's range: the intercept plus each product picked by its slope's sign.
            let na = _mm256_cmp_pd::<_CMP_LT_OQ>(a, zero);
            let nb = _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero);
            let hi = _mm256_add_pd(icpt, _mm256_blendv_pd(axh, axl, na));
            let lo = _mm256_add_pd(icpt, _mm256_blendv_pd(axl, axh, na));
            let hi = _mm256_add_pd(hi, _mm256_blendv_pd(byh, byl, nb));
            let lo = _mm256_add_pd(lo, _mm256_blendv_pd(byl, byh, nb));
            _mm256_storeu_pd(o0.add(k), a);
            _mm256_storeu_pd(o1.add(k), b);
            _mm256_storeu_pd(o2.add(k), icpt);
            _mm256_storeu_pd(omin.add(k), lo);
            _mm256_storeu_pd(omax.add(k), hi);
        }};
    }
    let end = n / 4 * 4;
    let mut k = 0;
    // Two loops, one per expectation, so that no step tests which one it is in: while
    // steps are flat (a contact's utility mostly is) each tests all its values at once;
    // after one that is not, the first two corners are tested alone first (on a
    // surface that varies most steps end there).
    while k < end {
        while k < end {
            let (v0, v1, v2, v3, v4) = load!(k);
            let same = _mm256_cmp_pd::<_CMP_EQ_OQ>(v1, v0);
            if flat!(same, v0, v2, v3, v4) {
                fill!(k, v0);
                k += 4;
                continue;
            }
            general!(k, (v0, v1, v2, v3, v4));
            k += 4;
            break;
        }
        while k < end {
            let (v0, v1, v2, v3, v4) = load!(k);
            let same = _mm256_cmp_pd::<_CMP_EQ_OQ>(v1, v0);
            if _mm256_testc_pd(same, ones) != 0 && flat!(same, v0, v2, v3, v4) {
                fill!(k, v0);
                k += 4;
                break;
            }
            general!(k, (v0, v1, v2, v3, v4));
            k += 4;
        }
    }
    end
}

/// [`super::raise_cells_of_row`] four cells at a time while four cells' tiles remain, each
/// lane a cell raised by its tiles in its order (gathered from the row, `per_cell` apart);
/// returns how many cells it raised (from the first).
///
/// # Safety
/// The CPU must have AVX2.
#[target_feature(enable = "avx2")]
pub(super) unsafe fn raise_cells(cells: &mut [f64], row: &[f64], per_cell: usize) -> usize {
    let k = per_cell as i64;
    if k == 0 {
        return 0;
    }
    let blocks = (row.len() / per_cell).min(cells.len()) / 4;
    let ninf = _mm256_set1_pd(f64::NEG_INFINITY);
    let (one, step) = (_mm256_set1_epi64x(1), _mm256_set1_epi64x(4 * k));
    // The last tile of each of the block's cells.
    let mut last = _mm256_setr_epi64x(k - 1, 2 * k - 1, 3 * k - 1, 4 * k - 1);
    let (g, v) = (cells.as_mut_ptr(), row.as_ptr());
    for at in (0..blocks).map(|b| 4 * b) {
        // SAFETY: at + 4 <= cells.len(), and every index gathered is below
        // 4·blocks·per_cell <= row.len().
        let mut x = _mm256_loadu_pd(g.add(at));
        let mut tile = last;
        for _ in 0..per_cell {
            let y = _mm256_i64gather_pd::<8>(v, tile);
            let take = _mm256_or_pd(
                _mm256_cmp_pd::<_CMP_EQ_OQ>(x, ninf),
                _mm256_cmp_pd::<_CMP_GT_OQ>(y, x),
            );
            x = _mm256_blendv_pd(x, y, take);
            tile = _mm256_sub_epi64(tile, one);
        }
        _mm256_storeu_pd(g.add(at), x);
        last = _mm256_add_epi64(last, step);
    }
    4 * blocks
}
