//! [`super::r14_row`]'s loop written in AVX2 instructions, four candidates per step:
//! the scalar loop's operations in its order on each lane (IEEE operations give the
//! same bits at any width), each `if` a compare (ordered, false on NaN, as Rust's) and
//! a blend. Left to itself the compiler narrows the compares' truth values to 32 bits
//! and widens them again for every blend.

use std::arch::x86_64::*;

use super::R14Row;

/// The courses' per-degree cosines a row reads (gam, cnh, tan).
pub(super) type Cosines<'a> = (&'a [f64], &'a [f64], &'a [f64]);

/// The first `4·⌊n/4⌋` candidates of a row (`n` the shortest list's length) as
/// [`super::r14_row_sides`]' loop computes them, with its rules decided: `BOW` the
/// bow rule (to port and moving), `AFT` and `BEAM` ownship's side facts, `EQUAL` the
/// metric's kind and `REWARD` the bearing-rate reward (`!(b0 >= 0)`). Returns how many
/// it wrote.
///
/// # Safety
/// The CPU must have AVX2.
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn r14_lanes<
    const EQUAL: bool,
    const BOW: bool,
    const AFT: bool,
    const BEAM: bool,
    const REWARD: bool,
>(
    r: &R14Row,
    (gams, cnhs, tans): Cosines<'_>,
    row: &mut [f64],
) -> usize {
    let n = row.len().min(gams.len()).min(cnhs.len()).min(tans.len());
    let R14Row {
        consts,
        metric: m,
        b0,
        v,
        ..
    } = *r;
    let (cn_tan, tn_const, cnv) = consts.parts();
    let set = _mm256_set1_pd;
    let zero = _mm256_setzero_pd();
    let (negv, vv, cn_tan, tn_const, cnv) = (set(-v), set(v), set(cn_tan), set(tn_const), set(cnv));
    let (mu, big, hundred, b0) = (set(m.mu), set(m.big), set(100.0), set(b0));
    // Metric::eval_row's `between`: the constant of a metric of equal bounds, else the
    // formula's factors.
    let equal = set(if m.zero_when_equal { 0.0 } else { m.floor });
    let (floor, span, width) = (set(m.floor), set(100.0 - m.floor), set(m.big - m.mu));
    let out = row.as_mut_ptr();
    for k in (0..n / 4).map(|q| 4 * q) {
        // SAFETY (every load and store): k + 4 <= n, at most each list's length.
        let ld = |s: &[f64]| _mm256_loadu_pd(s.as_ptr().add(k));
        let p = _mm256_loadu_pd(out.add(k));
        // RowConsts::bearing_rate: (-v · tan + cn_tan) · tn_const.
        let br = _mm256_mul_pd(
            _mm256_add_pd(_mm256_mul_pd(negv, ld(tans)), cn_tan),
            tn_const,
        );
        let between = if EQUAL {
            equal
        } else {
            let q = _mm256_div_pd(_mm256_mul_pd(span, _mm256_sub_pd(p, mu)), width);
            _mm256_add_pd(floor, q)
        };
        let above_low = _mm256_blendv_pd(between, hundred, _mm256_cmp_pd::<_CMP_GT_OQ>(p, big));
        let m1 = _mm256_blendv_pd(above_low, zero, _mm256_cmp_pd::<_CMP_LT_OQ>(p, mu));
        let m3 = if REWARD {
            let scaled = _mm256_div_pd(_mm256_mul_pd(hundred, br), b0);
            let beyond = _mm256_blendv_pd(scaled, hundred, _mm256_cmp_pd::<_CMP_LE_OQ>(br, b0));
            _mm256_blendv_pd(beyond, zero, _mm256_cmp_pd::<_CMP_GE_OQ>(br, zero))
        } else {
            zero
        };
        let mut u = _mm256_add_pd(m1, m3);
        if BOW {
            let crossing = _mm256_blendv_pd(u, zero, _mm256_cmp_pd::<_CMP_GE_OQ>(br, zero));
            let flat = _mm256_cmp_pd::<_CMP_LE_OQ>(ld(gams), zero);
            u = _mm256_blendv_pd(crossing, u, flat);
        }
        if !BEAM {
            // RowConsts::beam_closing.
            let w = _mm256_mul_pd(ld(cnhs), vv);
            let (e, port) = if AFT {
                (_mm256_sub_pd(w, cnv), _mm256_cmp_pd::<_CMP_GT_OQ>(br, zero))
            } else {
                (_mm256_sub_pd(cnv, w), _mm256_cmp_pd::<_CMP_LT_OQ>(br, zero))
            };
            let star = _mm256_blendv_pd(zero, u, port);
            u = _mm256_blendv_pd(u, star, _mm256_cmp_pd::<_CMP_GT_OQ>(e, zero));
        }
        _mm256_storeu_pd(out.add(k), u);
    }
    n / 4 * 4
}
