//! The normalization of a 2-dimensional uniform fit's pieces held in lists
//! ([`super::Pieces::normalize`]): rows of pieces normalized with their new ranges, the
//! range of the normalized pieces folded without writing them, and the weights written
//! out in the reflector's order, scaled on the way.

/// One row of pieces to normalize: the tiles' edges and the pieces' lists.
pub(super) struct NormRow<'a> {
    pub x: [&'a [f64]; 2],
    pub y: [f64; 2],
    pub w: [&'a mut [f64]; 3],
    pub min: &'a mut [f64],
    pub max: &'a mut [f64],
}

/// Normalize a row's pieces (`w[2] += shift`, then every weight `*= scale`) and take
/// each one's new range, as normalize_from_and_min_max does per piece.
pub(super) fn normalize_row(row: NormRow<'_>, shift: f64, scale: f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { normalize_row_avx2(row, shift, scale) };
    }
    normalize_row_body(row, shift, scale);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn normalize_row_avx2(row: NormRow<'_>, shift: f64, scale: f64) {
    normalize_row_body(row, shift, scale);
}

#[inline(always)]
pub(super) fn normalize_row_body(row: NormRow<'_>, shift: f64, scale: f64) {
    let NormRow { x, y, w, min, max } = row;
    let n = min.len();
    let [w0, w1, w2] = w;
    let (w0, w1, w2, max) = (&mut w0[..n], &mut w1[..n], &mut w2[..n], &mut max[..n]);
    let (xl, xh) = (&x[0][..n], &x[1][..n]);
    for k in 0..n {
        let w = [w0[k], w1[k], w2[k]];
        let ([a, b, c], lo, hi) = normalized_piece(w, (xl[k], xh[k]), y, (shift, scale));
        (w0[k], w1[k], w2[k]) = (a, b, c);
        min[k] = lo;
        max[k] = hi;
    }
}

/// One piece's weights `[a, b, c]` normalized (`c += shift`, then every weight
/// `*= scale`), with its new least and greatest value over the box `x` × `y`, as
/// normalize_from_and_min_max computes them.
#[inline(always)]
pub(super) fn normalized_piece(
    [a, b, c]: [f64; 3],
    (l, h): (f64, f64),
    [yl, yh]: [f64; 2],
    (shift, scale): (f64, f64),
) -> ([f64; 3], f64, f64) {
    let (a, b) = (a * scale, b * scale);
    let c = (c + shift) * scale;
    let (mut lo, mut hi) = (c, c);
    // The edges picked as l + 0 or l + (h − l), exact (integers): a pick between the
    // loaded edges would be compiled as a pick between lists, a lane at a time.
    let up = if a < 0.0 { 0.0 } else { h - l };
    hi += a * (l + up);
    lo += a * (h - up);
    hi += b * if b < 0.0 { yl } else { yh };
    lo += b * if b < 0.0 { yh } else { yl };
    ([a, b, c], lo, hi)
}

/// The tiles' edges (low and high per tile of dimension 0, per row of dimension 1) and
/// the pieces' slope and intercept lists, row after row.
pub(super) type RangeLists<'a> = (&'a [f64], &'a [f64], &'a [f64], &'a [f64], [&'a [f64]; 3]);

/// What [`fold_range`] gives over the ranges of the pieces normalized by
/// [`normalized_piece`], computed without writing them, or `None` (nothing to fold, or
/// an extreme of zeros: which zero comes first in order is only in the lists).
pub(super) fn normalized_range(
    lists: RangeLists<'_>,
    shift: f64,
    scale: f64,
) -> Option<(f64, f64)> {
    let (xl, xh, yl, yh, [w0, w1, w2]) = lists;
    let (nx, ny) = (xl.len().min(xh.len()), yl.len().min(yh.len()));
    let n = nx * ny;
    if n == 0 || w0.len() < n || w1.len() < n || w2.len() < n {
        return None;
    }
    let lists = (&xl[..nx], &xh[..nx], &yl[..ny], &yh[..ny], [w0, w1, w2]);
    let mut done = false;
    // Folded from ±inf, as fold_range_lanes: a NaN never replaces, and the values are
    // folded in any order (only zeros of both signs would tell it, and they give None).
    let (mut mn, mut mx) = (f64::INFINITY, f64::NEG_INFINITY);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        let flat = scale.is_finite() && scale.is_sign_positive();
        // SAFETY: the CPU has AVX2 (checked just above).
        (mn, mx) = unsafe { normalized_range_avx2(lists, (shift, scale), flat) };
        done = true;
    }
    if !done {
        for k in 0..n {
            let (_, lo, hi) = piece_of(lists, k, (shift, scale));
            mn = if lo < mn { lo } else { mn };
            mx = if hi > mx { hi } else { mx };
        }
    }
    // The last piece comes first in the reflector's order: a NaN there is the answer.
    let (_, lo, hi) = piece_of(lists, n - 1, (shift, scale));
    let pick = |first: f64, ext: f64| match (first.is_nan(), ext != 0.0) {
        (true, _) => Some(first),
        (false, true) => Some(ext),
        (false, false) => None,
    };
    Some((pick(lo, mn)?, pick(hi, mx)?))
}

/// [`normalized_piece`] of piece `k` (tile `k mod nx` of row `k / nx`) of `lists`.
#[inline(always)]
pub(super) fn piece_of(lists: RangeLists<'_>, k: usize, s: (f64, f64)) -> ([f64; 3], f64, f64) {
    let (xl, xh, yl, yh, [w0, w1, w2]) = lists;
    let (cx, cy) = (k % xl.len(), k / xl.len());
    let w = [w0[k], w1[k], w2[k]];
    normalized_piece(w, (xl[cx], xh[cx]), [yl[cy], yh[cy]], s)
}

/// [`normalized_range`]'s fold, four pieces per instruction ([`normalized_piece`]'s
/// operations on four lanes; the minimum and maximum instructions pick as its
/// comparisons do), the rows' last n mod 4 pieces one at a time. Every list holds its
/// pieces (checked by the caller).
///
/// If `flat` (the scale finite and not negative), four pieces of slopes +0 (the fit's
/// flat pieces) take a shorter way to the same values: their slopes normalize to +0,
/// the products of +0 and the edges (finite, not negative) are +0, so each range is
/// the normalized intercept `(c + shift)·scale` plus +0 (twice, which is once).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn normalized_range_avx2(
    lists: RangeLists<'_>,
    s: (f64, f64),
    flat: bool,
) -> (f64, f64) {
    if flat {
        normalized_range_lanes::<true>(lists, s)
    } else {
        normalized_range_lanes::<false>(lists, s)
    }
}

/// [`normalized_range_avx2`] for a case of `flat`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn normalized_range_lanes<const FLAT: bool>(
    lists: RangeLists<'_>,
    (shift, scale): (f64, f64),
) -> (f64, f64) {
    use std::arch::x86_64::*;
    let (xl, xh, yl, yh, [w0, w1, w2]) = lists;
    let nx = xl.len();
    let (mut mn, mut mx) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut vmn, mut vmx) = (_mm256_set1_pd(mn), _mm256_set1_pd(mx));
    let (sh, sc, zero) = (
        _mm256_set1_pd(shift),
        _mm256_set1_pd(scale),
        _mm256_setzero_pd(),
    );
    for (cy, (&y0, &y1)) in yl.iter().zip(yh).enumerate() {
        let (ylo, yhi) = (_mm256_set1_pd(y0), _mm256_set1_pd(y1));
        let at = cy * nx;
        for k in (0..nx / 4).map(|q| 4 * q) {
            // SAFETY: k + 4 <= nx, within xl and xh, and at + k + 4 <= n, within the
            // weight lists (checked by the caller).
            let ld = |l: &[f64], i: usize| _mm256_loadu_pd(l.as_ptr().add(i));
            let (a, b) = (ld(w0, at + k), ld(w1, at + k));
            let zeros = _mm256_castpd_si256(_mm256_or_pd(a, b));
            if FLAT && _mm256_testz_si256(zeros, zeros) != 0 {
                let c = _mm256_mul_pd(_mm256_add_pd(ld(w2, at + k), sh), sc);
                let c = _mm256_add_pd(c, zero);
                (vmn, vmx) = (_mm256_min_pd(c, vmn), _mm256_max_pd(c, vmx));
                continue;
            }
            let (a, b) = (_mm256_mul_pd(a, sc), _mm256_mul_pd(b, sc));
            let c = _mm256_mul_pd(_mm256_add_pd(ld(w2, at + k), sh), sc);
            let (l, h) = (ld(xl, k), ld(xh, k));
            // up = if a < 0 { 0 } else { h − l }.
            let up = _mm256_blendv_pd(
                _mm256_sub_pd(h, l),
                zero,
                _mm256_cmp_pd::<_CMP_LT_OQ>(a, zero),
            );
            let hi = _mm256_add_pd(c, _mm256_mul_pd(a, _mm256_add_pd(l, up)));
            let lo = _mm256_add_pd(c, _mm256_mul_pd(a, _mm256_sub_pd(h, up)));
            let neg = _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero);
            let hi = _mm256_add_pd(hi, _mm256_mul_pd(b, _mm256_blendv_pd(yhi, ylo, neg)));
            let lo = _mm256_add_pd(lo, _mm256_mul_pd(b, _mm256_blendv_pd(ylo, yhi, neg)));
            // min(x, m) is `x < m ? x : m`, max(x, m) `x > m ? x : m`.
            vmn = _mm256_min_pd(lo, vmn);
            vmx = _mm256_max_pd(hi, vmx);
        }
        for k in nx / 4 * 4..nx {
            let (_, lo, hi) = piece_of(lists, at + k, (shift, scale));
            mn = if lo < mn { lo } else { mn };
            mx = if hi > mx { hi } else { mx };
        }
    }
    let (mut lmn, mut lmx) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(lmn.as_mut_ptr(), vmn);
    _mm256_storeu_pd(lmx.as_mut_ptr(), vmx);
    let mn = lmn.into_iter().fold(mn, |a, x| if x < a { x } else { a });
    let mx = lmx.into_iter().fold(mx, |a, x| if x > a { x } else { a });
    (mn, mx)
}

/// Append the pieces' weights (slope 0, slope 1, intercept lists) to `weights`, the
/// last piece first; normalized on the way (`w[2] += shift`, then `*= scale`) by each
/// of `scales` given, in turn.
pub(super) fn write_reversed(
    w: [&[f64]; 3],
    scales: [Option<(f64, f64)>; 2],
    weights: &mut Vec<f64>,
) {
    let (n, at) = (w[0].len().min(w[1].len()).min(w[2].len()), weights.len());
    weights.reserve(3 * n);
    let out = &mut weights.spare_capacity_mut()[..3 * n];
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        done = unsafe { write_reversed_avx2(w, scales, out) };
    }
    for (o, k) in out[3 * done..].chunks_exact_mut(3).zip((0..n - done).rev()) {
        let mut p = [w[0][k], w[1][k], w[2][k]];
        for (shift, s) in scales.into_iter().flatten() {
            p = [p[0] * s, p[1] * s, (p[2] + shift) * s];
        }
        o.iter_mut().zip(p).for_each(|(o, x)| _ = o.write(x));
    }
    // SAFETY: the loops above wrote each of the first 3·n spare slots (n chunks of 3).
    unsafe { weights.set_len(at + 3 * n) };
}

/// [`write_reversed`]'s loop four pieces at a time, reversed and interleaved by shuffles;
/// returns how many it wrote (from the last; the first n mod 4 are left to the caller).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn write_reversed_avx2(
    w: [&[f64]; 3],
    scales: [Option<(f64, f64)>; 2],
    out: &mut [std::mem::MaybeUninit<f64>],
) -> usize {
    // Each case compiled on its own: no test of the scalings inside the loop.
    match scales.map(|s| s.is_some()) {
        [false, false] => write_reversed_lanes::<false, false>(w, scales, out),
        [true, false] => write_reversed_lanes::<true, false>(w, scales, out),
        [false, true] => write_reversed_lanes::<false, true>(w, scales, out),
        [true, true] => write_reversed_lanes::<true, true>(w, scales, out),
    }
}

/// [`write_reversed_avx2`] with the first (second) scaling applied if `S1` (`S2`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(super) unsafe fn write_reversed_lanes<const S1: bool, const S2: bool>(
    [w0, w1, w2]: [&[f64]; 3],
    scales: [Option<(f64, f64)>; 2],
    out: &mut [std::mem::MaybeUninit<f64>],
) -> usize {
    use std::arch::x86_64::*;
    let n = w0.len().min(w1.len()).min(w2.len()).min(out.len() / 3);
    let [(shift, s), (shift2, s2)] = scales.map(|scale| {
        let (shift, s) = scale.unwrap_or((0.0, 1.0));
        (_mm256_set1_pd(shift), _mm256_set1_pd(s))
    });
    let o = out.as_mut_ptr().cast::<f64>();
    for done in (0..n / 4).map(|q| 4 * q) {
        // Pieces j..j+4 (in bounds: j + 4 <= n), written j+3 first; scaled if asked.
        let j = n - done - 4;
        // SAFETY: j + 4 <= n, at most each list's length (no bounds checks in the loop).
        let [mut x, mut y, mut z] = [w0, w1, w2].map(|w| _mm256_loadu_pd(w.as_ptr().add(j)));
        if S1 {
            (x, y) = (_mm256_mul_pd(x, s), _mm256_mul_pd(y, s));
            z = _mm256_mul_pd(_mm256_add_pd(z, shift), s);
        }
        if S2 {
            (x, y) = (_mm256_mul_pd(x, s2), _mm256_mul_pd(y, s2));
            z = _mm256_mul_pd(_mm256_add_pd(z, shift2), s2);
        }
        // Reversed: x0 = piece j+3.
        let [x, y, z] = [x, y, z].map(|v| _mm256_permute4x64_pd::<0x1B>(v));
        let t = _mm256_unpacklo_pd(x, y); // x0 y0 x2 y2
        let u = _mm256_shuffle_pd::<0b1010>(z, x); // z0 x1 z2 x3
        let v = _mm256_unpackhi_pd(y, z); // y1 z1 y3 z3
                                          // SAFETY: 3·done + 12 <= 3·n, at most out's length.
        let o = o.add(3 * done);
        _mm256_storeu_pd(o, _mm256_permute2f128_pd::<0x20>(t, u));
        _mm256_storeu_pd(o.add(4), _mm256_blend_pd::<0b1100>(v, t));
        _mm256_storeu_pd(o.add(8), _mm256_permute2f128_pd::<0x31>(u, v));
    }
    n / 4 * 4
}
