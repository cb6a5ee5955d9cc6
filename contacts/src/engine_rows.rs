//! A row of CPA distances: one speed, every candidate course of a grid row, the
//! distance (or a function of it) per course. The baseline loop and its AVX2
//! compilation give the same bits (engine_tests.rs checks both against the formula).

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

/// What a row of CPA distances needs of the engine and the speed.
#[derive(Clone, Copy)]
pub(crate) struct CpaRow {
    /// Ownship's speed (negative counted as 0).
    pub v: f64,
    /// Ownship − contact.
    pub px: f64,
    pub py: f64,
    /// The contact's velocity.
    pub cn_vx: f64,
    pub cn_vy: f64,
    /// The current range (the CPA when not closing).
    pub now: f64,
    /// The horizon.
    pub tol: f64,
}

/// Where a row's `f` is flat: `f(x)` is `f(0.0)` for every `x` in `[0, below)` and
/// `f(f64::MAX)` for every `x > above` (both finite, `below <= above`). An objective
/// function's utility of the CPA usually is (worst below one distance, best above
/// another): a candidate whose CPA is surely in a flat end is given that end's value
/// without the division and square root of its distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatEnds {
    pub below: f64,
    pub above: f64,
}

/// AOF_AvoidCollision's utility of a CPA distance (contacts-appcast.md §3.5): 0 below
/// the collision distance `cd`, 100 above the all-clear distance `acd`, else
/// `25 + 75·(d − cd)/(acd − cd)` (the jump from 0 to 25 at `cd` is the reference's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AvoidRamp {
    pub cd: f64,
    pub acd: f64,
}

impl AvoidRamp {
    /// The utility of `d`: the ramp computed and the answer picked, without jumps, so
    /// that a row's loop does several entries per instruction.
    #[inline(always)]
    pub fn at(self, d: f64) -> f64 {
        let AvoidRamp { cd, acd } = self;
        let mid = 25.0 + 75.0 * (d - cd) / (acd - cd);
        let high = if d > acd { 100.0 } else { mid };
        if d < cd {
            0.0
        } else {
            high
        }
    }

    /// Where [`AvoidRamp::at`] is flat: 0 below `cd` (for any `d < cd`), 100 above both
    /// (`d ≥ cd` and `d > acd`); none unless both are finite.
    pub fn flat_ends(self) -> Option<FlatEnds> {
        let AvoidRamp { cd, acd } = self;
        (cd.is_finite() && acd.is_finite()).then(|| FlatEnds {
            below: cd.min(acd),
            above: cd.max(acd),
        })
    }
}

/// A row's tests for [`FlatEnds`], from [`Ends::of`]. A candidate's CPA is read off the
/// distance of the contact's track to ownship's line, `|p × u| / |u|`, without a
/// division: `(p × u)² ≥ k_hi·|u|²` says the distance at any time is above `above`, and
/// `(p × u)² ≤ k_lo·|u|²` with the time of the CPA within the horizon
/// (`p·u ≤ tol_lo·|u|²`) that it is below `below`. The thresholds are `above` and
/// `below` moved out by `slack`, far more than the rounding of either formula: the
/// computed distance differs from the geometric one by a few units of the last place of
/// the range, `|p|`, and the tests' products by a few of their own (engine_rows_tests.rs
/// checks the answers against the formula on borderline rows, engine_tests.rs on
/// random and awkward ones).
#[derive(Clone, Copy)]
pub(crate) struct Ends {
    pub on: bool,
    pub k_hi: f64,
    pub k_lo: f64,
    pub tol_lo: f64,
    pub lo: f64,
    pub hi: f64,
}

/// The numbers the tests are kept within, so that no product overflows or underflows
/// and every time and distance is finite: `|px| + |py|` and `above` at most `BIG`,
/// `|u|²` within `[1/BIG², BIG²]` and `p·u ≥ |u|²/BIG²` (the time of the CPA surely
/// positive); other rows and candidates take the formula.
const BIG: f64 = 1e50;

impl Ends {
    pub(crate) const OFF: Ends = Ends {
        on: false,
        k_hi: f64::INFINITY,
        k_lo: -1.0,
        tol_lo: -1.0,
        lo: 0.0,
        hi: 0.0,
    };

    #[inline(always)]
    pub(crate) fn of<F: Fn(f64) -> f64>(row: &CpaRow, flat: Option<FlatEnds>, f: &F) -> Ends {
        let Some(FlatEnds { below, above }) = flat else {
            return Ends::OFF;
        };
        let pn = row.px.abs() + row.py.abs();
        let finite = [row.v, row.cn_vx, row.cn_vy, row.tol, below, above]
            .iter()
            .all(|x| x.is_finite());
        if !(finite
            && pn <= BIG
            && row.tol >= 0.0
            && (0.0..=BIG).contains(&above)
            && below <= above)
        {
            return Ends::OFF;
        }
        let slack = 1e-9 * (pn + above + 1.0);
        let lo_edge = below - slack;
        Ends {
            on: true,
            k_hi: (above + slack) * (above + slack),
            k_lo: if lo_edge > 0.0 {
                lo_edge * lo_edge
            } else {
                -1.0
            },
            tol_lo: row.tol * (1.0 - 1e-12),
            lo: f(0.0),
            hi: f(f64::MAX),
        }
    }
}

/// A row's numbers in AVX2 registers, with [`cpa_entry`]'s two halves on four
/// candidates at a time: one definition for both AVX2 row kernels ([`cpa_row_avx2`] and
/// engine_zip.rs's), so that they give the same distances.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(crate) struct Lanes {
    v: __m256d,
    px: __m256d,
    py: __m256d,
    cn_vx: __m256d,
    cn_vy: __m256d,
    now: __m256d,
    tol: __m256d,
    zero: __m256d,
}

/// `(ux, uy, p·u)` of four candidates ([`cpa_closing_num`] per lane).
#[cfg(target_arch = "x86_64")]
pub(crate) type Closing = (__m256d, __m256d, __m256d);

#[cfg(target_arch = "x86_64")]
impl Lanes {
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) fn of(row: &CpaRow) -> Lanes {
        let set = _mm256_set1_pd;
        Lanes {
            v: set(row.v),
            px: set(row.px),
            py: set(row.py),
            cn_vx: set(row.cn_vx),
            cn_vy: set(row.cn_vy),
            now: set(row.now),
            tol: set(row.tol),
            zero: _mm256_setzero_pd(),
        }
    }

    /// [`cpa_closing_num`] per vector of a chunk, and whether any lane's p·u is above 0.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) fn closing(&self, s: &[f64; WIDE], c: &[f64; WIDE]) -> ([Closing; VECS], bool) {
        let Lanes {
            v,
            px,
            py,
            cn_vx,
            cn_vy,
            zero,
            ..
        } = *self;
        let mut u = [(zero, zero, zero); VECS];
        let mut any = zero;
        for (h, u) in u.iter_mut().enumerate() {
            // SAFETY: a chunk holds VECS vectors of 4.
            let (s, c) = unsafe {
                let at = |x: &[f64; WIDE]| _mm256_loadu_pd(x.as_ptr().add(4 * h));
                (at(s), at(c))
            };
            let ux = _mm256_sub_pd(cn_vx, _mm256_mul_pd(v, s));
            let uy = _mm256_sub_pd(cn_vy, _mm256_mul_pd(v, c));
            let num = _mm256_add_pd(_mm256_mul_pd(px, ux), _mm256_mul_pd(py, uy));
            any = _mm256_or_pd(any, _mm256_cmp_pd::<_CMP_GT_OQ>(num, zero));
            *u = (ux, uy, num);
        }
        (u, _mm256_testz_pd(any, any) == 0)
    }

    /// `|u|²` of four candidates.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) fn ww((ux, uy, _): Closing) -> __m256d {
        _mm256_add_pd(_mm256_mul_pd(ux, ux), _mm256_mul_pd(uy, uy))
    }

    /// [`cpa_finish`]'s distance of four candidates (`ww` their [`Lanes::ww`]):
    /// `closing` is `!(ww == 0) & (t > 0)`; min(tol, t) is `tol` when `tol < t`, else
    /// `t`; max(r, 0) is `r` when `r > 0`, else 0.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(crate) fn dist(&self, (ux, uy, num): Closing, ww: __m256d) -> __m256d {
        let Lanes {
            px,
            py,
            now,
            tol,
            zero,
            ..
        } = *self;
        let t = _mm256_div_pd(num, ww);
        let closing = _mm256_and_pd(
            _mm256_cmp_pd::<_CMP_NEQ_UQ>(ww, zero),
            _mm256_cmp_pd::<_CMP_GT_OQ>(t, zero),
        );
        let t = _mm256_min_pd(tol, t);
        let dx = _mm256_sub_pd(px, _mm256_mul_pd(ux, t));
        let dy = _mm256_sub_pd(py, _mm256_mul_pd(uy, t));
        let r = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
        _mm256_blendv_pd(now, _mm256_max_pd(r, zero), closing)
    }
}

/// [`CpaEngine::cpa_dists`]'s loop compiled for AVX2: [`cpa_row`]'s chunks, with
/// [`cpa_entry`]'s operations written as AVX2 instructions on four candidates at a time
/// (left to itself, the compiler does a chunk's candidates two at a time or one by one).
/// Each instruction is the IEEE operation of the scalar formula on each lane, so the
/// bits are the same (engine_tests.rs checks it). With `ends` on, a vector of four
/// candidates each either not closing or surely in a flat end is written without the
/// formula's division and square root.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn cpa_row_avx2<F: Fn(f64) -> f64>(
    row: &CpaRow,
    units: (&[f64], &[f64]),
    out: &mut [f64],
    f: F,
    ends: Ends,
) {
    let ((sins, coss), out) = row_slices(units, out);
    if still_row(row, (sins, coss), out, &f) {
        return;
    }
    let lanes = Lanes::of(row);
    let (px, py, zero) = (lanes.px, lanes.py, lanes.zero);
    let set = _mm256_set1_pd;
    let far = set(f(row.now));
    let (k_hi, k_lo, tol_lo) = (set(ends.k_hi), set(ends.k_lo), set(ends.tol_lo));
    let (lo_val, hi_val) = (set(ends.lo), set(ends.hi));
    let (ww_min, ww_max) = (set(1.0 / (BIG * BIG)), set(BIG * BIG));
    let (sc, s_rest) = sins.as_chunks::<WIDE>();
    let (cc, c_rest) = coss.as_chunks::<WIDE>();
    let (oc, o_rest) = out.as_chunks_mut::<WIDE>();
    for ((o, s), c) in oc.iter_mut().zip(sc).zip(cc) {
        let (u, any) = lanes.closing(s, c);
        if !any {
            // SAFETY: a chunk holds VECS vectors of 4.
            unsafe {
                for h in 0..VECS {
                    _mm256_storeu_pd(o.as_mut_ptr().add(4 * h), far);
                }
            }
            continue;
        }
        let mut d = [0.0; WIDE];
        let mut formula = [true; VECS];
        for (h, &u) in u.iter().enumerate() {
            let (ux, uy, num) = u;
            let ww = Lanes::ww(u);
            if ends.on {
                // Ends::of's tests; a lane not closing (p·u ≤ 0) is `far` as below.
                let cross = _mm256_sub_pd(_mm256_mul_pd(px, uy), _mm256_mul_pd(py, ux));
                let c2 = _mm256_mul_pd(cross, cross);
                let sure = _mm256_and_pd(
                    _mm256_and_pd(
                        _mm256_cmp_pd::<_CMP_GE_OQ>(ww, ww_min),
                        _mm256_cmp_pd::<_CMP_LE_OQ>(ww, ww_max),
                    ),
                    _mm256_cmp_pd::<_CMP_GE_OQ>(num, _mm256_mul_pd(ww, ww_min)),
                );
                let hi = _mm256_cmp_pd::<_CMP_GE_OQ>(c2, _mm256_mul_pd(k_hi, ww));
                let lo = _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_LE_OQ>(c2, _mm256_mul_pd(k_lo, ww)),
                    _mm256_cmp_pd::<_CMP_LE_OQ>(num, _mm256_mul_pd(tol_lo, ww)),
                );
                let not_closing = _mm256_cmp_pd::<_CMP_LE_OQ>(num, zero);
                let known = _mm256_or_pd(not_closing, _mm256_and_pd(sure, _mm256_or_pd(hi, lo)));
                if _mm256_movemask_pd(known) == 0b1111 {
                    let end = _mm256_blendv_pd(lo_val, hi_val, hi);
                    // SAFETY: a chunk holds VECS vectors of 4.
                    unsafe {
                        _mm256_storeu_pd(
                            o.as_mut_ptr().add(4 * h),
                            _mm256_blendv_pd(end, far, not_closing),
                        )
                    };
                    formula[h] = false;
                    continue;
                }
            }
            // SAFETY: `d` holds VECS vectors of 4.
            unsafe { _mm256_storeu_pd(d.as_mut_ptr().add(4 * h), lanes.dist(u, ww)) };
        }
        // `f` per lane: the compiler does these at vector width too.
        if formula == [true; VECS] {
            for (o, &d) in o.iter_mut().zip(&d) {
                *o = f(d);
            }
        } else {
            for h in (0..VECS).filter(|&h| formula[h]) {
                for i in 4 * h..4 * h + 4 {
                    o[i] = f(d[i]);
                }
            }
        }
    }
    for ((o, &s), &c) in o_rest.iter_mut().zip(s_rest).zip(c_rest) {
        *o = cpa_entry(row, (s, c), &f);
    }
}

/// [`CpaEngine::cpa_dists`]'s loop, for the target's baseline instructions: by chunks of
/// [`LANES`] candidates, a chunk none of whose candidates is closing (about half of an
/// avoidance grid's) written as `f` of the range now without the rest of the formula
/// (the division and the square root).
#[inline(always)]
pub(crate) fn cpa_row<F: Fn(f64) -> f64>(
    row: &CpaRow,
    units: (&[f64], &[f64]),
    out: &mut [f64],
    f: F,
) {
    let ((sins, coss), out) = row_slices(units, out);
    if still_row(row, (sins, coss), out, &f) {
        return;
    }
    let far = f(row.now);
    let (sc, s_rest) = sins.as_chunks::<LANES>();
    let (cc, c_rest) = coss.as_chunks::<LANES>();
    let (oc, o_rest) = out.as_chunks_mut::<LANES>();
    for ((o, s), c) in oc.iter_mut().zip(sc).zip(cc) {
        let u: [[f64; 3]; LANES] = std::array::from_fn(|i| cpa_closing_num(row, (s[i], c[i])));
        if u.iter().any(|u| u[2] > 0.0) {
            for (o, &u) in o.iter_mut().zip(&u) {
                *o = cpa_finish(row, u, &f);
            }
        } else {
            *o = [far; LANES];
        }
    }
    for ((o, &s), &c) in o_rest.iter_mut().zip(s_rest).zip(c_rest) {
        *o = cpa_entry(row, (s, c), &f);
    }
}

/// The units and `out` cut to their common length.
#[inline(always)]
fn row_slices<'a>(
    (sins, coss): (&'a [f64], &'a [f64]),
    out: &'a mut [f64],
) -> ((&'a [f64], &'a [f64]), &'a mut [f64]) {
    let n = out.len().min(sins.len()).min(coss.len());
    ((&sins[..n], &coss[..n]), &mut out[..n])
}

/// Writes the row and says true if ownship is still and every number finite: v·sin is
/// then ±0 for every unit, so the candidates differ at most in the sign of zeros, which
/// no result shows (a zero closing speed or time is "not closing", a zero offset is
/// squared): the row is its first entry.
#[inline(always)]
pub(crate) fn still_row<F: Fn(f64) -> f64>(
    row: &CpaRow,
    (sins, coss): (&[f64], &[f64]),
    out: &mut [f64],
    f: &F,
) -> bool {
    let &CpaRow {
        v,
        px,
        py,
        cn_vx,
        cn_vy,
        ..
    } = row;
    if !(v == 0.0 && all_finite(&[sins, coss, &[px, py, cn_vx, cn_vy]])) {
        return false;
    }
    if let Some((first, rest)) = out.split_first_mut() {
        *first = cpa_entry(row, (sins[0], coss[0]), f);
        rest.fill(*first);
    }
    true
}

/// Candidates per chunk of [`cpa_row`]: a chunk is skipped only when none of its
/// candidates is closing, so smaller chunks skip more candidates and larger ones test
/// fewer times (the sizes here took the fewest instructions on avoidance grids).
const LANES: usize = 4;

/// AVX2 vectors (of four candidates) per chunk of [`cpa_row_avx2`], and its candidates.
pub(crate) const VECS: usize = 2;
pub(crate) const WIDE: usize = 4 * VECS;

/// One entry of [`cpa_row`]: `cpa_of_ranged`'s formula with the relative velocity
/// negated, `u = contact − ownship` (so `t = p·u / |u|²` needs no sign flip and
/// `p + w·t` is `p − u·t`): `u` is `−w` exactly but for the sign of a zero, which
/// changes only zero or non-closing values (`t` ≤ 0 or NaN: the range now) and the sign
/// of a zero offset (squared). The branches are all computed and the answer picked.
#[inline(always)]
pub(crate) fn cpa_entry<F: Fn(f64) -> f64>(row: &CpaRow, unit: (f64, f64), f: &F) -> f64 {
    cpa_finish(row, cpa_closing_num(row, unit), f)
}

/// The first half of [`cpa_entry`]: `[ux, uy, p·u]`. The candidate is not closing when
/// `p·u` is not above 0: `t = p·u / |u|²` with `|u|²` ≥ 0 or NaN is then ≤ 0 (±0 / +inf
/// included) or NaN, and [`cpa_finish`] gives `f(now)`.
#[inline(always)]
fn cpa_closing_num(row: &CpaRow, (s, c): (f64, f64)) -> [f64; 3] {
    let (ux, uy) = (row.cn_vx - row.v * s, row.cn_vy - row.v * c);
    [ux, uy, row.px * ux + row.py * uy]
}

/// The rest of [`cpa_entry`] from [`cpa_closing_num`]'s numbers.
#[inline(always)]
fn cpa_finish<F: Fn(f64) -> f64>(row: &CpaRow, [ux, uy, num]: [f64; 3], f: &F) -> f64 {
    let CpaRow {
        px, py, now, tol, ..
    } = *row;
    let ww = ux * ux + uy * uy;
    let t = num / ww;
    let closing = !(ww == 0.0) & !(t.is_nan() | (t <= 0.0));
    let t = if t > tol { tol } else { t };
    let (dx, dy) = (px - ux * t, py - uy * t);
    // √d2 > 0 exactly when d2 > 0 (NaN and ±0 give 0): one max instruction.
    let r = (dx * dx + dy * dy).sqrt();
    let d = if r > 0.0 { r } else { 0.0 };
    f(if closing { d } else { now })
}

/// True if no number in `lists` is infinite or NaN (bit tests OR-ed, no early exit: the
/// loop runs several numbers per instruction).
#[inline(always)]
fn all_finite(lists: &[&[f64]]) -> bool {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let odd = lists.iter().fold(0u64, |a, l| {
        a | l
            .iter()
            .fold(0u64, |b, x| b | u64::from(x.to_bits() & EXP == EXP))
    });
    odd == 0
}

#[cfg(all(test, target_arch = "x86_64"))]
#[path = "engine_rows_tests.rs"]
mod tests;
