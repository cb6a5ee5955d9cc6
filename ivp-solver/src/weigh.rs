//! The set-up's passes over every piece (spec §5 step 4): the weight extremes that
//! decide normalization, then each piece's weights in the problem domain, its term
//! scale and its `maxVal`. They run over every piece of every function each iteration
//! (thousands per contact), so each is made for 1 to 3 dimensions by inlining one
//! loop with a constant dimension (unrolled, indices checked once per piece): the
//! same operations in the same order as the loop for any dimension. Two-dimensional
//! functions (the contacts' course × speed pieces, most of the work) go four pieces a
//! step through the AVX2 bodies of `weigh_simd` when the CPU has AVX2, to the same
//! bits; the scalar loops finish the last pieces and do everything else.

#[cfg(target_arch = "x86_64")]
use crate::weigh_simd::{corners2, extremes2, weigh2, Boxes2, Scale2};
use crate::FunctionView;
use ivp::function::max_val;

/// How a function's weights become the problem's (see [`weigh`]).
pub(crate) struct Weighing<'a> {
    /// Problem dimension of each of the function's dimensions.
    pub(crate) map: &'a [usize],
    /// `map` is `0..` and the function has every problem dimension.
    pub(crate) identity: bool,
    /// Normalize: slope `x -> (x*scale)*pwt`, intercept `x -> ((x+shift)*scale)*pwt`;
    /// otherwise `x -> x*pwt`.
    pub(crate) norm: bool,
    pub(crate) shift: f64,
    pub(crate) scale: f64,
    pub(crate) pwt: f64,
    /// The problem's points per dimension.
    pub(crate) pts: &'a [i32],
}

/// Every piece's weights from the function's `src` (`od` dimensions) into `weights`
/// (problem order; the slopes of dimensions the function lacks are left as they are),
/// and, with the pieces' problem-order `boxes` (a checked function's: `0 <= lo <=
/// hi`), each piece's `maxVal` into `piece_ub` (cleared first). Returns the largest
/// term scale (`term`), NaN kept. `corners`: the boxes' [`Corners`], when made.
pub(crate) fn weigh(
    wg: &Weighing,
    src: &[f64],
    od: usize,
    weights: &mut [f64],
    (boxes, corners): (Option<&[i32]>, Option<&[f64]>),
    piece_ub: &mut Vec<f64>,
) -> f64 {
    weigh_with(wg, src, od, weights, (boxes, corners), piece_ub, avx2())
}

/// Fewest pieces given [`Corners`]: a small function's boxes (a waypoint's) change more
/// often than not, and making its corners costs about what they save.
const CORNERS_MIN: usize = 64;

/// The problem-order boxes of a two-dimensional function (both dimensions the
/// problem's, either way round) as the AVX2 passes read them (see
/// `weigh_simd::corners2`), kept while the boxes stay (a tiling's do, solve after
/// solve): made for one slot's boxes generation (see `Prepared::boxes_gen`).
#[derive(Debug, Default)]
pub(crate) struct Corners {
    data: Vec<f64>,
    of: Option<u64>,
}

impl Corners {
    /// The corners of the boxes `boxes` (problem order) of generation `gen` of a
    /// function with `od` dimensions mapped by `map` into the problem's `dim`, made
    /// unless they are these; `None` when the AVX2 passes would not read them.
    pub(crate) fn of(
        &mut self,
        boxes: &[i32],
        (od, dim, map): (usize, usize, &[usize]),
        gen: u64,
    ) -> Option<&[f64]> {
        let n = boxes.len() / 4;
        if !(od == 2 && dim == 2 && n >= CORNERS_MIN && matches!(map, [0, 1] | [1, 0]) && avx2()) {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        if self.of != Some(gen) {
            // SAFETY: `avx2()` said the CPU has AVX2.
            unsafe { corners2(boxes, &mut self.data) };
            self.of = Some(gen);
        }
        let _ = (boxes, gen);
        Some(&self.data)
    }
}

/// Whether the AVX2 bodies of `weigh_simd` may run.
fn avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    return false;
}

/// [`weigh`], with the AVX2 body for two dimensions (either order) if `simd` (reading
/// the boxes' corners when given).
fn weigh_with(
    wg: &Weighing,
    src: &[f64],
    od: usize,
    weights: &mut [f64],
    (boxes, corners): (Option<&[i32]>, Option<&[f64]>),
    piece_ub: &mut Vec<f64>,
    simd: bool,
) -> f64 {
    let id = wg.identity;
    if let Some(b) = boxes {
        // Every entry is written below, but for pieces without a box (none, in a
        // checked function): no zeroing pass over the rest.
        let wl = wg.pts.len() + 1;
        let n = (weights.len() / wl).min(src.len() / (od + 1));
        piece_ub.resize(n, 0.0);
        let boxed = b.len() / (2 * wg.pts.len()).max(1);
        piece_ub[boxed.min(n)..].fill(0.0);
    } else {
        piece_ub.clear();
    }
    #[cfg(target_arch = "x86_64")]
    // Two dimensions, the function's in problem order or the other way round.
    if simd && od == 2 && wg.pts.len() == 2 && matches!(wg.map, [0, 1] | [1, 0]) {
        let sc = Scale2 {
            norm: wg.norm.then_some((wg.shift, wg.scale)),
            pwt: wg.pwt,
            span: [0, 1].map(|d| f64::from((wg.pts[d] - 1).max(0))),
        };
        let swap = wg.map[0] == 1;
        // SAFETY: `simd` is only true when the CPU has AVX2 (see `avx2`).
        let read = boxes.map(|b| match corners {
            Some(c) => Boxes2::Corners(c, false),
            None => Boxes2::Ints(b),
        });
        let (done, most, nan) = unsafe { weigh2(&sc, swap, src, weights, read, piece_ub) };
        let most = if nan {
            // The scalar keeps the last NaN: its terms again, from the weights made.
            let made = weights[..3 * done].chunks_exact(3);
            made.fold(0.0, |m, w| most_of(m, term(w, &wg.pts[..2])))
        } else {
            most
        };
        let rest = (&src[3 * done..], &mut weights[3 * done..]);
        let boxes = boxes.map(|b| &b[4 * done..]);
        let at = done.min(piece_ub.len());
        let ub = &mut piece_ub[at..];
        return weigh_dims(wg, rest.0, 2, 2, !swap, rest.1, boxes, ub, most);
    }
    let _ = simd;
    let piece_ub = &mut piece_ub[..];
    match (od, wg.pts.len()) {
        (1, 1) => weigh_dims(wg, src, 1, 1, id, weights, boxes, piece_ub, 0.0),
        (2, 2) => weigh_dims(wg, src, 2, 2, id, weights, boxes, piece_ub, 0.0),
        (3, 3) => weigh_dims(wg, src, 3, 3, id, weights, boxes, piece_ub, 0.0),
        (1, 2) => weigh_dims(wg, src, 1, 2, id, weights, boxes, piece_ub, 0.0),
        (1, 3) => weigh_dims(wg, src, 1, 3, id, weights, boxes, piece_ub, 0.0),
        (2, 3) => weigh_dims(wg, src, 2, 3, id, weights, boxes, piece_ub, 0.0),
        (od, dim) => weigh_dims(wg, src, od, dim, id, weights, boxes, piece_ub, 0.0),
    }
}

/// [`weigh`] for `od` function and `dim` problem dimensions (`identity`: `map` is
/// `0..dim`, written directly), `most` the largest term scale so far, `piece_ub`
/// already sized (with boxes).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn weigh_dims(
    wg: &Weighing,
    src: &[f64],
    od: usize,
    dim: usize,
    identity: bool,
    weights: &mut [f64],
    boxes: Option<&[i32]>,
    piece_ub: &mut [f64],
    most: f64,
) -> f64 {
    let (bl, wl) = (2 * dim, dim + 1);
    let mut most = most;
    // The terms' spans, converted once (up to 4 dimensions, else per piece).
    let mut span = [0.0; 4];
    let spans = (dim <= span.len()).then(|| {
        for d in 0..dim {
            span[d] = f64::from((wg.pts[d] - 1).max(0));
        }
        &span[..dim]
    });
    match boxes {
        Some(b) => {
            let pieces = weights.chunks_exact_mut(wl).zip(src.chunks_exact(od + 1));
            for (((w, s), b), ub) in pieces.zip(b.chunks_exact(bl)).zip(piece_ub.iter_mut()) {
                most = most_of(most, piece_weights(wg, w, s, od, dim, identity, spans));
                *ub = max_val(&b[..bl], &w[..wl]);
            }
        }
        None => {
            for (w, s) in weights.chunks_exact_mut(wl).zip(src.chunks_exact(od + 1)) {
                most = most_of(most, piece_weights(wg, w, s, od, dim, identity, spans));
            }
        }
    }
    most
}

/// The running largest term scale after term `t` (NaN must not be lost by `max`).
#[inline(always)]
fn most_of(most: f64, t: f64) -> f64 {
    if t > most || t.is_nan() {
        t
    } else {
        most
    }
}

/// One piece's weights `w` (problem order) from the function's `s`; its term scale
/// (with the spans of [`term_spans`] when given).
#[inline(always)]
fn piece_weights(
    wg: &Weighing,
    w: &mut [f64],
    s: &[f64],
    od: usize,
    dim: usize,
    identity: bool,
    spans: Option<&[f64]>,
) -> f64 {
    let (shift, scale, pwt) = (wg.shift, wg.scale, wg.pwt);
    let (w, s) = (&mut w[..dim + 1], &s[..od + 1]);
    let map = &wg.map[..od];
    if wg.norm {
        w[dim] = ((s[od] + shift) * scale) * pwt;
        if identity {
            for d in 0..dim {
                w[d] = (s[d] * scale) * pwt;
            }
        } else {
            for i in 0..od {
                w[map[i]] = (s[i] * scale) * pwt;
            }
        }
    } else {
        w[dim] = s[od] * pwt;
        if identity {
            for d in 0..dim {
                w[d] = s[d] * pwt;
            }
        } else {
            for i in 0..od {
                w[map[i]] = s[i] * pwt;
            }
        }
    }
    match spans {
        Some(spans) => term_spans(w, &spans[..dim]),
        None => term(w, &wg.pts[..dim]),
    }
}

/// [`term`] with the spans `f64::from((pts_d - 1).max(0))` given: the same value.
#[inline(always)]
fn term_spans(w: &[f64], spans: &[f64]) -> f64 {
    let dim = spans.len();
    let mut t = w[dim].abs();
    for d in 0..dim {
        t += w[d].abs() * spans[d];
    }
    t
}

/// `|intercept| + Σ_d |slope_d|·(pts_d - 1)` of one piece's weights (problem order).
#[inline(always)]
pub(crate) fn term(w: &[f64], pts: &[i32]) -> f64 {
    let dim = pts.len();
    let mut t = w[dim].abs();
    for d in 0..dim {
        t += w[d].abs() * f64::from((pts[d] - 1).max(0));
    }
    t
}

/// [`ivp::IvpFunction::min_max_wt`] with both extremes of a piece in one loop over its
/// dimensions: each accumulates the same terms in the same order, and the pieces are
/// compared in the same order, so the values are the same bit for bit.
#[cfg(test)]
pub(crate) fn min_max_wt(f: &FunctionView<'_>) -> (f64, f64) {
    min_max_wt_with(f, None)
}

/// [`min_max_wt`], the AVX2 pass reading the function's boxes from their
/// [`Corners`] (problem order; `swap`: the function's two dimensions the other way
/// round) when given. Inlined: called once per set-up, in both of its forms.
#[inline(always)]
pub(crate) fn min_max_wt_with(f: &FunctionView<'_>, corners: Option<(&[f64], bool)>) -> (f64, f64) {
    let (od, b, w) = (f.dim(), f.bounds(), f.weights());
    if od == 0 || f.piece_count() == 0 || b.len() < 2 * od || w.len() < od + 1 {
        // No piece (a checked function over no variable has none): what
        // `IvpFunction::min_max_wt` gives then.
        return (0.0, 0.0);
    }
    let simd = avx2();
    match od {
        1 => extremes::<1>(b, w, 1, simd, None),
        2 => extremes::<2>(b, w, 2, simd, corners),
        3 => extremes::<3>(b, w, 3, simd, None),
        _ => extremes::<0>(b, w, od, simd, None),
    }
}

/// One piece's `(lo, hi)` extremes over its box `b` (weights `w`, `od` dimensions,
/// `OD` when not 0): inlined with the dimension a constant, the loop unrolled.
#[inline(always)]
fn piece_extremes<const OD: usize>(b: &[i32], w: &[f64], od: usize) -> (f64, f64) {
    let od = if OD == 0 { od } else { OD };
    let (b, w) = (&b[..2 * od], &w[..od + 1]);
    let (mut lo, mut hi) = (w[od], w[od]);
    for d in 0..od {
        let x = w[d];
        let (l, h) = (f64::from(b[2 * d]), f64::from(b[2 * d + 1]));
        if x < 0.0 {
            hi += x * l;
            lo += x * h;
        } else {
            hi += x * h;
            lo += x * l;
        }
    }
    (lo, hi)
}

/// The least and greatest piece extremes over boxes `bounds` and weights `weights` of
/// `od` dimensions (at least one piece); the AVX2 body for two dimensions if `simd`
/// (reading the boxes' `corners` when given, see [`min_max_wt_with`]).
#[inline(always)]
fn extremes<const OD: usize>(
    bounds: &[i32],
    weights: &[f64],
    od: usize,
    simd: bool,
    corners: Option<(&[f64], bool)>,
) -> (f64, f64) {
    let (mut mn, mut mx) = piece_extremes::<OD>(bounds, weights, od);
    let mut done = 1;
    // Once the first piece's values are numbers, NaN pieces change nothing (`<` is
    // false), which the lanes do too; a NaN first value is kept: scalar then.
    #[cfg(target_arch = "x86_64")]
    if simd && od == 2 && !mn.is_nan() && !mx.is_nan() {
        // SAFETY: `simd` is only true when the CPU has AVX2 (see `avx2`).
        let boxes = match corners {
            Some((c, swap)) => Boxes2::Corners(c, swap),
            None => Boxes2::Ints(bounds),
        };
        let (n, lo, hi) = unsafe { extremes2(boxes, weights) };
        if n > 0 {
            (done, mn, mx) = (n, lo, hi);
        }
    }
    let _ = (simd, corners);
    let rest = (&bounds[2 * od * done..], &weights[(od + 1) * done..]);
    for (b, w) in rest.0.chunks_exact(2 * od).zip(rest.1.chunks_exact(od + 1)) {
        let (lo, hi) = piece_extremes::<OD>(b, w, od);
        if lo < mn {
            mn = lo;
        }
        if hi > mx {
            mx = hi;
        }
    }
    (mn, mx)
}

#[cfg(test)]
#[path = "weigh_tests.rs"]
mod tests;
