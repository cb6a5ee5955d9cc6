//! The fit of a run of tiles of one row of a 2-dimensional uniform tiling (tiles of
//! equal widths) in structure-of-arrays form: the values of each corner, the slopes,
//! intercepts and piece ranges each in a list of their own, so that each step is one
//! loop over the run that the compiler does several tiles at a time (four on a CPU with
//! AVX2, which gets a copy of the loops compiled for it). Per tile these are
//! [`crate::fit::fit_box`]'s operations for 2 dimensions, in its order, and the piece
//! range of the tiling's fold, so the bits are the same at any width.

/// One run of tiles: equal widths, one row.
pub(super) struct Run<'a> {
    /// Per tile, in dimension 0: low edge, high edge, centre (`lo + (hi − lo) / 2`).
    pub x: [&'a [f64]; 3],
    /// The row's low edge, high edge and centre in dimension 1.
    pub y: [f64; 3],
    /// The tiles' widths (`hi − lo`) in dimensions 0 and 1.
    pub widths: (u32, u32),
    /// Per tile, the values at the corners by mask (bit 0: high in dimension 0, bit 1:
    /// high in dimension 1), then at the centre (read only when the fit takes it).
    pub vals: [&'a [f64]; 5],
    /// Shift each intercept into its values' range (spec §8 strict range).
    pub strict: bool,
    /// The fit takes the centre (some width spans more than 2 points).
    pub centre: bool,
}

/// What the fit of a run gives per tile.
pub(super) struct RunOut<'a> {
    /// Slopes in dimensions 0 and 1, then the intercept.
    pub w: [&'a mut [f64]; 3],
    /// The piece's least and greatest value over its box.
    pub min: &'a mut [f64],
    pub max: &'a mut [f64],
}

/// Fit the run's tiles into `out` (as many as `out.min` holds).
pub(super) fn fit_run(run: &Run<'_>, out: &mut RunOut<'_>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { fit_run_avx2(run, out) };
    }
    fit_run_plain(run, out);
}

/// [`fit_run`] compiled for AVX2: four tiles per step written out when the widths allow
/// ([`avx2::fit_steps`]), the rest (or all) by the loops compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn fit_run_avx2(run: &Run<'_>, out: &mut RunOut<'_>) {
    let done = avx2::fit_steps(run, out);
    if done < out.min.len() {
        fit_run_body(&run.from(done), &mut out.from(done));
    }
}

#[cfg(target_arch = "x86_64")]
#[path = "tiling_rows_avx2.rs"]
mod avx2;

/// Raise the search grid's `cells` of a row of tiles to the tiles' greatest values
/// `row`, as build_grid does (a cell still at -inf takes the value whatever it is):
/// tiles `per_cell·c ..` (`per_cell` of them, the last cell maybe fewer) lie in cell `c`,
/// each cell's from the last to the first (the reflector's order).
pub(super) fn raise_cells_of_row(cells: &mut [f64], row: &[f64], per_cell: usize) {
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        done = unsafe { avx2::raise_cells(cells, row, per_cell) };
    }
    for (c, g) in cells.iter_mut().enumerate().skip(done) {
        let tiles = row.get(c * per_cell..).unwrap_or(&[]);
        *g = tiles.iter().take(per_cell).rev().fold(*g, raise);
    }
}

/// A grid cell at `g` raised by a piece of greatest value `v` (build_grid's step).
#[inline(always)]
fn raise(g: f64, &v: &f64) -> f64 {
    if g == f64::NEG_INFINITY || v > g {
        v
    } else {
        g
    }
}

impl<'a> Run<'a> {
    /// The run's tiles from the `k`-th on (an empty list, the centres when not read,
    /// stays empty).
    fn from(&self, k: usize) -> Run<'a> {
        let tail = |s: &'a [f64]| s.get(k..).unwrap_or(&[]);
        Run {
            x: self.x.map(tail),
            vals: self.vals.map(tail),
            ..*self
        }
    }
}

impl RunOut<'_> {
    /// The outputs of the tiles from the `k`-th on (`k` at most each list's length).
    fn from(&mut self, k: usize) -> RunOut<'_> {
        let [w0, w1, w2] = &mut self.w;
        RunOut {
            w: [&mut w0[k..], &mut w1[k..], &mut w2[k..]],
            min: &mut self.min[k..],
            max: &mut self.max[k..],
        }
    }
}

/// [`fit_run`] for the target's baseline instructions.
pub(super) fn fit_run_plain(run: &Run<'_>, out: &mut RunOut<'_>) {
    fit_run_body(run, out);
}

#[inline(always)]
fn fit_run_body(run: &Run<'_>, out: &mut RunOut<'_>) {
    let n = out.min.len();
    let [v0, v1, v2, v3, v4] = run.vals;
    let (v0, v1, v2, v3) = (&v0[..n], &v1[..n], &v2[..n], &v3[..n]);
    let [w0, w1, w2] = &mut out.w;
    let (w0, w1) = (&mut w0[..n], &mut w1[..n]);
    // Slopes: the mean of the two corner differences along the dimension, divided by
    // the width (0 for a zero width), as fit_box sums them (from 0, mask order).
    slopes(w0, run.widths.0, |k| {
        let mut sum = 0.0;
        sum += v1[k] - v0[k];
        sum += v3[k] - v2[k];
        sum / 2.0
    });
    slopes(w1, run.widths.1, |k| {
        let mut sum = 0.0;
        sum += v2[k] - v0[k];
        sum += v3[k] - v1[k];
        sum / 2.0
    });
    let planes = Planes {
        x: run.x.map(|s| &s[..n]),
        y: run.y,
        w0,
        w1,
        vals: [v0, v1, v2, v3],
    };
    let out = (&mut w2[..n], &mut out.min[..n], &mut out.max[..n]);
    // Each case compiled on its own: no test of `strict` mixed into the lanes.
    match (run.centre, run.strict) {
        (true, true) => intercepts::<true, true>(&planes, &v4[..n], out),
        (true, false) => intercepts::<true, false>(&planes, &v4[..n], out),
        (false, true) => intercepts::<false, true>(&planes, &[], out),
        (false, false) => intercepts::<false, false>(&planes, &[], out),
    }
}

/// `w[k] = div_by_width(numer(k), width)` for every tile (0 when `width` is 0), the
/// width's case decided once for the run.
#[inline(always)]
fn slopes(w: &mut [f64], width: u32, numer: impl Fn(usize) -> f64) {
    if width == 0 {
        w.fill(0.0);
    } else if width.is_power_of_two() {
        // Exact: see crate::fit::div_by_width.
        let r = 1.0 / f64::from(width);
        for (k, x) in w.iter_mut().enumerate() {
            *x = numer(k) * r;
        }
    } else {
        let d = f64::from(width);
        for (k, x) in w.iter_mut().enumerate() {
            *x = numer(k) / d;
        }
    }
}

/// The run's slopes with what the intercepts need.
struct Planes<'a> {
    x: [&'a [f64]; 3],
    y: [f64; 3],
    w0: &'a [f64],
    w1: &'a [f64],
    vals: [&'a [f64]; 4],
}

/// Intercepts (the mean residual, shifted into the values' range when strict) and the
/// pieces' least and greatest values, with fit_box's and the fold's operations.
#[inline(always)]
fn intercepts<const CENTRE: bool, const STRICT: bool>(
    p: &Planes<'_>,
    centres: &[f64],
    (w2, min, max): (&mut [f64], &mut [f64], &mut [f64]),
) {
    let n = w2.len();
    let [xl, xh, xm] = p.x;
    let [yl, yh, ym] = p.y;
    let [v0, v1, v2, v3] = p.vals;
    let (xl, xh, xm, w0, w1) = (&xl[..n], &xh[..n], &xm[..n], &p.w0[..n], &p.w1[..n]);
    let (v0, v1, v2, v3) = (&v0[..n], &v1[..n], &v2[..n], &v3[..n]);
    let (min, max) = (&mut min[..n], &mut max[..n]);
    let m = if CENTRE { 5.0 } else { 4.0 };
    for k in 0..n {
        let (a, b) = (w0[k], w1[k]);
        // The products once, for the planes and the range.
        let (axl, axh, byl, byh) = (a * xl[k], a * xh[k], b * yl, b * yh);
        let plane = |ax: f64, by: f64| {
            let mut acc = 0.0;
            acc += ax;
            acc += by;
            acc
        };
        let vals = [
            v0[k],
            v1[k],
            v2[k],
            v3[k],
            if CENTRE { centres[k] } else { 0.0 },
        ];
        let planes = [
            plane(axl, byl),
            plane(axh, byl),
            plane(axl, byh),
            plane(axh, byh),
            if CENTRE {
                plane(a * xm[k], b * ym)
            } else {
                0.0
            },
        ];
        let cnt = if CENTRE { 5 } else { 4 };
        let mut isum = 0.0;
        for j in 0..cnt {
            isum += vals[j] - planes[j];
        }
        let icpt = isum / m;
        let (mut vmin, mut vmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut pmin, mut pmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for j in 0..cnt {
            let (v, q) = (vals[j], planes[j] + icpt);
            vmin = if v < vmin { v } else { vmin };
            vmax = if v > vmax { v } else { vmax };
            pmin = if q < pmin { q } else { pmin };
            pmax = if q > pmax { q } else { pmax };
        }
        let down = icpt - (pmax - vmax);
        let up = icpt + (vmin - pmin);
        let icpt = if STRICT & (pmax > vmax) {
            down
        } else if STRICT & (pmin < vmin) {
            up
        } else {
            icpt
        };
        w2[k] = icpt;
        // The piece's range over its box (the tiling's Folds::add: `a · x` picked is the
        // pick of the products).
        let (mut lo, mut hi) = (icpt, icpt);
        hi += if a < 0.0 { axl } else { axh };
        lo += if a < 0.0 { axh } else { axl };
        hi += if b < 0.0 { byl } else { byh };
        lo += if b < 0.0 { byh } else { byl };
        min[k] = lo;
        max[k] = hi;
    }
}

/// The pieces of a 2-dimensional uniform fit as lists (tile `cx + nx·cy` at index
/// `cx + nx·cy`, the grid's order, not the reflector's): the tiles' edges as numbers
/// and, per tile, the slopes, intercept and range of its piece. One buffer kept per
/// thread between builds.
#[derive(Debug)]
pub(crate) struct Pieces {
    buf: super::Scratch,
    nx: usize,
    ny: usize,
}

/// [`Pieces`]' lists, borrowed.
pub(super) struct Lists<'a> {
    /// Per tile of dimension 0: low edge, high edge, centre; of dimension 1: low, high.
    pub xl: &'a mut [f64],
    pub xh: &'a mut [f64],
    pub xm: &'a mut [f64],
    pub yl: &'a mut [f64],
    pub yh: &'a mut [f64],
    /// Per tile: slope 0, slope 1, intercept, least value, greatest value.
    pub pieces: [&'a mut [f64]; 5],
}

impl Pieces {
    /// Lists for the tiles with these edges (per dimension, `(lo, hi)` per tile).
    pub(super) fn new(xs: &[(u32, u32)], ys: &[(u32, u32)]) -> Pieces {
        let (nx, ny) = (xs.len(), ys.len());
        let mut buf = super::Scratch::take();
        // Every list is written before it is read (the edges here, the pieces by the
        // fit): what the last build left needs no clearing.
        let len = 3 * nx + 2 * ny + 5 * nx * ny;
        if buf.0.len() < len {
            buf.0.resize(len, 0.0);
        }
        let mut p = Pieces { buf, nx, ny };
        let l = p.lists_mut();
        for (k, &(lo, hi)) in xs.iter().enumerate() {
            (l.xl[k], l.xh[k]) = (f64::from(lo), f64::from(hi));
            l.xm[k] = f64::from(lo + (hi - lo) / 2);
        }
        for (k, &(lo, hi)) in ys.iter().enumerate() {
            (l.yl[k], l.yh[k]) = (f64::from(lo), f64::from(hi));
        }
        p
    }

    /// Append the pieces' weights to `weights` in the reflector's order, normalized on
    /// the way if asked (see [`write_reversed`]).
    pub(crate) fn write_weights(&self, weights: &mut Vec<f64>, scale: Option<(f64, f64)>) {
        let n = self.nx * self.ny;
        let w = &self.buf.0[3 * self.nx + 2 * self.ny..][..3 * n];
        write_reversed([&w[..n], &w[n..2 * n], &w[2 * n..]], [scale, None], weights);
    }

    pub(super) fn lists_mut(&mut self) -> Lists<'_> {
        let (nx, ny, n) = (self.nx, self.ny, self.nx * self.ny);
        let (xl, rest) = self.buf.0.split_at_mut(nx);
        let (xh, rest) = rest.split_at_mut(nx);
        let (xm, rest) = rest.split_at_mut(nx);
        let (yl, rest) = rest.split_at_mut(ny);
        let (yh, rest) = rest.split_at_mut(ny);
        let (w0, rest) = rest.split_at_mut(n);
        let (w1, rest) = rest.split_at_mut(n);
        let (w2, rest) = rest.split_at_mut(n);
        let (lo, hi) = rest.split_at_mut(n);
        Lists {
            xl,
            xh,
            xm,
            yl,
            yh,
            pieces: [w0, w1, w2, lo, hi],
        }
    }

    /// What [`ivp::IvpFunction::normalize_from`]`(min_max, base, range)` does to the
    /// function of these pieces (its search `grid`, and its weights, appended to the
    /// empty `weights` in the reflector's order), bit for bit; if `twice`, what
    /// [`ivp::IvpFunction::normalize_from_and_min_max`] then normalize_from of the
    /// range it returns do: each piece's operations are theirs, and the ranges are folded
    /// in the reflector's order. `false` (nothing changed) when the first range is empty
    /// or `weights` is not empty: the function's own methods then do it.
    pub(crate) fn normalize(
        &mut self,
        (mn, mx): (f64, f64),
        (base, range): (f64, f64),
        twice: bool,
        (weights, grid): (&mut Vec<f64>, &mut [f64]),
    ) -> bool {
        let r = mx - mn;
        let n = self.nx * self.ny;
        if r.is_nan() || r <= 0.0 || !weights.is_empty() || n == 0 {
            return false;
        }
        let (shift, scale) = (base - mn, range / r);
        grid.iter_mut().for_each(|g| *g = (*g + shift) * scale);
        if !twice {
            // Written out normalized: no pass of its own over the function's weights.
            self.write_weights(weights, Some((shift, scale)));
            return true;
        }
        let nx = self.nx;
        let l = self.lists_mut();
        let [w0, w1, w2, lo, hi] = l.pieces;
        let once = Some((shift, scale));
        // The once-normalized range from the weights as they are (no normalized list
        // written, no fold of its own), unless zeros make it depend on the order.
        let lists = (&*l.xl, &*l.xh, &*l.yl, &*l.yh, [&*w0, &*w1, &*w2]);
        if let Some((mn2, mx2)) = normalized_range(lists, shift, scale) {
            let r2 = mx2 - mn2;
            let again = !(r2.is_nan() || r2 <= 0.0);
            let (shift2, scale2) = (base - mn2, range / r2);
            if again {
                grid.iter_mut().for_each(|g| *g = (*g + shift2) * scale2);
            }
            let scales = [once, again.then_some((shift2, scale2))];
            write_reversed([w0, w1, w2], scales, weights);
            return true;
        }
        for cy in 0..l.yl.len() {
            let (i, j) = (cy * nx, (cy + 1) * nx);
            let row = NormRow {
                x: [&*l.xl, &*l.xh],
                y: [l.yl[cy], l.yh[cy]],
                w: [&mut w0[i..j], &mut w1[i..j], &mut w2[i..j]],
                min: &mut lo[i..j],
                max: &mut hi[i..j],
            };
            normalize_row(row, shift, scale);
        }
        let (mn2, mx2) = fold_range(&lo[..n], &hi[..n]);
        let r2 = mx2 - mn2;
        let again = !(r2.is_nan() || r2 <= 0.0);
        let (shift2, scale2) = (base - mn2, range / r2);
        if again {
            grid.iter_mut().for_each(|g| *g = (*g + shift2) * scale2);
        }
        write_reversed(
            [w0, w1, w2],
            [again.then_some((shift2, scale2)), None],
            weights,
        );
        true
    }
}

/// The least of `lo` and the greatest of `hi` (not empty) as min_max_wt folds them: in
/// the reflector's order (the last piece first), from the last piece's, each replaced
/// only by a strictly lesser (greater) value. So: the last piece's when it is NaN, else
/// the extreme of the values that are not NaN, and of equal extremes the first in that
/// order, which only zeros (+0 and −0) tell apart. Found four lanes at a time, with the
/// fold in order only for an extreme of zeros of both signs.
pub(super) fn fold_range(lo: &[f64], hi: &[f64]) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { fold_range_avx2(lo, hi) };
    }
    fold_range_lanes(lo, hi)
}

/// [`fold_range_lanes`] with its lanes' loop written in AVX2 instructions (the
/// compiler's own loop reverses every vector twice per step).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn fold_range_avx2(lo: &[f64], hi: &[f64]) -> (f64, f64) {
    use std::arch::x86_64::*;
    let n = lo.len().min(hi.len());
    let (lo, hi) = (&lo[..n], &hi[..n]);
    let (lc, hc) = (lo.as_chunks::<4>().0, hi.as_chunks::<4>().0);
    let mut mn = _mm256_set1_pd(f64::INFINITY);
    let mut mx = _mm256_set1_pd(f64::NEG_INFINITY);
    for (l, h) in lc.iter().zip(hc) {
        // min(x, m) is `x < m ? x : m`, max(x, m) `x > m ? x : m`: the lanes' picks.
        mn = _mm256_min_pd(_mm256_loadu_pd(l.as_ptr()), mn);
        mx = _mm256_max_pd(_mm256_loadu_pd(h.as_ptr()), mx);
    }
    let (mut lmn, mut lmx) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(lmn.as_mut_ptr(), mn);
    _mm256_storeu_pd(lmx.as_mut_ptr(), mx);
    fold_range_from(lo, hi, n / 4 * 4, (lmn, lmx))
}

#[inline(always)]
fn fold_range_lanes(lo: &[f64], hi: &[f64]) -> (f64, f64) {
    let n = lo.len().min(hi.len());
    let (lo, hi) = (&lo[..n], &hi[..n]);
    // Lanes from ±inf: a NaN never replaces (as in the fold), and the last piece's value
    // (not NaN) is among those folded, so the lanes' extreme is the fold's value.
    let (mut mn, mut mx) = ([f64::INFINITY; 4], [f64::NEG_INFINITY; 4]);
    let (lc, hc) = (lo.chunks_exact(4), hi.chunks_exact(4));
    for (l, h) in lc.zip(hc) {
        for j in 0..4 {
            mn[j] = if l[j] < mn[j] { l[j] } else { mn[j] };
            mx[j] = if h[j] > mx[j] { h[j] } else { mx[j] };
        }
    }
    fold_range_from(lo, hi, n / 4 * 4, (mn, mx))
}

/// [`fold_range`] given the lanes' extremes `(mn, mx)` of the first `done` pieces (a
/// multiple of 4): the rest folded in, then the answer picked.
#[inline(always)]
fn fold_range_from(
    lo: &[f64],
    hi: &[f64],
    done: usize,
    (mut mn, mut mx): ([f64; 4], [f64; 4]),
) -> (f64, f64) {
    let n = lo.len().min(hi.len());
    let (lo, hi) = (&lo[..n], &hi[..n]);
    let (lr, hr) = (&lo[done..], &hi[done..]);
    for (j, (&l, &h)) in lr.iter().zip(hr).enumerate() {
        mn[j] = if l < mn[j] { l } else { mn[j] };
        mx[j] = if h > mx[j] { h } else { mx[j] };
    }
    let mn = mn
        .into_iter()
        .fold(f64::INFINITY, |a, x| if x < a { x } else { a });
    let mx = mx
        .into_iter()
        .fold(f64::NEG_INFINITY, |a, x| if x > a { x } else { a });
    let first = (lo[n - 1], hi[n - 1]);
    let pick = |first: f64, ext: f64, list: &[f64], less: bool| {
        if first.is_nan() {
            return first;
        }
        if ext != 0.0 {
            // Values equal to a non-zero one have its bits.
            return ext;
        }
        // Zeros: the sign of the first in order, one sign only unless both occur.
        let (pos, neg) = zero_signs(list);
        if pos != neg {
            return if pos { 0.0 } else { -0.0 };
        }
        let mut e = first;
        for &x in list.iter().rev() {
            let better = if less { x < e } else { x > e };
            e = if better { x } else { e };
        }
        e
    };
    (pick(first.0, mn, lo, true), pick(first.1, mx, hi, false))
}

/// Whether `list` holds a +0 and whether it holds a −0.
#[inline(always)]
fn zero_signs(list: &[f64]) -> (bool, bool) {
    let (mut pos, mut neg) = (false, false);
    for &x in list {
        pos |= x.to_bits() == 0;
        neg |= x.to_bits() == 1 << 63;
    }
    (pos, neg)
}

#[path = "tiling_norm.rs"]
mod norm;
use norm::*;

#[cfg(test)]
#[path = "tiling_rows_tests.rs"]
mod tests;
