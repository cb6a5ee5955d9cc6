//! The reflector's uniform stage fitted from two grid evaluations (ivp-solver.md §8):
//! every tile's corners lie on the grid of the tiles' low and high edges, and its centre
//! on the grid of their midpoints, so the AOF is asked for those two grids at once
//! ([`Aof::eval_grid`]) instead of point by point, and each tile's fit reads its values
//! from them. The pieces are those of the point-by-point fit bit for bit: the same
//! points, the same fit arithmetic ([`crate::fit::fit_box`]). The same pass folds
//! each piece into the function's search grid and value range, which the reflector hands
//! over instead of having them computed again from the pieces.

use crate::aof::Aof;
use crate::fit::{fit_box, FIT_DIMS};
use ivp::domain::Domain;
use ivp::function::grid_dim;
use mbutil::spare;

/// What the fitting pass gives besides the pieces: what the function's
/// [`IvpFunction::build_grid`](ivp::IvpFunction::build_grid) and
/// [`IvpFunction::min_max_wt`](ivp::IvpFunction::min_max_wt) would compute from them,
/// taken while each piece is at hand.
#[derive(Debug, Default)]
pub(crate) struct Summary {
    /// The search grid of the pieces under the reflector's gel box.
    pub grid: Vec<f64>,
    /// The least piece minimum and the greatest piece maximum (`None`: no pieces).
    pub min_max: Option<(f64, f64)>,
    /// The pieces of a 2-dimensional fit in lists, for normalizing them several at a
    /// time ([`rows::Pieces::normalize`]).
    pub pieces: Option<rows::Pieces>,
    /// The 2-dimensional fit's weights are only in `pieces`, not yet in the reflector's
    /// ([`rows::Pieces::write_weights`]; normalize writes them normalized).
    pub weights_pending: bool,
}

/// The uniform tiling of `domain` by boxes of edge `size` (`counts` of them per
/// dimension, the last one clipped), fitted and appended to `bounds` and `weights` in the
/// reflector's order: tile `i` numbered with dimension 0 fastest, from the last tile to
/// the first. At most [`FIT_DIMS`] dimensions. The pieces' grid under `gelbox` and their
/// value range go to `summary`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_uniform(
    aof: &dyn Aof,
    domain: &Domain,
    size: &[u32],
    counts: &[u32],
    strict: bool,
    gelbox: &[u32],
    bounds: &mut Vec<i32>,
    weights: &mut Vec<f64>,
    summary: &mut Summary,
) {
    let out = (bounds, weights, summary);
    let shape = (size, counts, gelbox);
    // The axes in the buffers of an earlier fit on this thread, of this shape if kept
    // (then they need no recomputing).
    let keys: [AxisKey; FIT_DIMS] = std::array::from_fn(|d| axis_key(domain, shape, d));
    let n = size.len().min(FIT_DIMS);
    let same = |a: &[Axis; FIT_DIMS]| (0..n).all(|d| a[d].key == Some(keys[d]));
    let mut axes: [Axis; FIT_DIMS] = pop_where(&SPARE_AXES, same).unwrap_or_default();
    if !same(&axes) {
        let mut stride = 1;
        for (d, a) in axes.iter_mut().enumerate().take(n) {
            a.set(keys[d], d, stride);
            stride *= keys[d][5];
        }
    }
    let a = &mut axes;
    match size.len() {
        1 => fit_uniform_n::<1>(aof, domain, shape, strict, a, out),
        2 => fit_uniform_n::<2>(aof, domain, shape, strict, a, out),
        3 => fit_uniform_n::<3>(aof, domain, shape, strict, a, out),
        _ => fit_uniform_n::<FIT_DIMS>(aof, domain, shape, strict, a, out),
    }
    push(&SPARE_AXES, axes);
}

/// What an [`Axis`] is computed from: the number of dimensions, then the dimension's
/// tile size, tile count, points, and search grid cell size and count (all 0 past the
/// domain's dimensions).
type AxisKey = [usize; 6];

/// The [`AxisKey`] of dimension `d` of a tiling.
fn axis_key(
    domain: &Domain,
    (size, counts, gelbox): (&[u32], &[u32], &[u32]),
    d: usize,
) -> AxisKey {
    if d >= size.len() {
        return [size.len(), 0, 0, 0, 0, 0];
    }
    let (ppg, ncells) = grid_dim(domain.var(d), gelbox.get(d));
    let at = |x: u32| x as usize;
    let (pts, edge, count) = (at(domain.var(d).points), at(size[d]), at(counts[d]));
    [size.len(), edge, count, pts, ppg as usize, ncells as usize]
}

/// Tiles of the tiling per dimension: their edges, where they lie in the search grid,
/// and the coordinates of the two grids the AOF is evaluated on.
#[derive(Default)]
struct Axis {
    /// What the lists below were computed from (`None`: nothing yet).
    key: Option<AxisKey>,
    /// Dimension 0 of a 2-dimensional tiling: the tiles' bounds as the reflector lists
    /// them, kept for the next fit of the same shape (empty: not computed).
    bounds: Vec<i32>,
    /// (low, high) edge of each tile.
    edges: Vec<(u32, u32)>,
    /// Per tile: its first grid cell's offset in the grid (cell × stride) and how many
    /// cells it spans.
    cells: Vec<(usize, usize)>,
    /// The search grid's stride of this dimension (cells, dimension 0 fastest).
    stride: usize,
    /// The corner grid's coordinates: each tile's low and high edge side by side,
    /// except dimension 0 of a 2-dimensional tiling, where all the low edges come
    /// first, then all the high ones (the row fit reads each corner's values as one
    /// list; see fit_rows_2).
    corners: Vec<u32>,
    /// The midpoint grid's coordinates: each tile's centre.
    mids: Vec<u32>,
    /// Runs of consecutive tiles of equal width: (first tile, end, width `hi − lo`).
    runs: Vec<(usize, usize, u32)>,
    /// How many tiles lie in each grid cell when each cell holds that many consecutive
    /// tiles (the last maybe fewer) and no tile spans two cells; else 0.
    per_cell: usize,
}

impl Axis {
    /// The lists of dimension `d` of the tiling of `key`, whose search grid stride is
    /// `stride` (cells, dimension 0 fastest); the kept bounds let go.
    fn set(&mut self, key: AxisKey, d: usize, stride: usize) {
        let [n, size, count, pts, ppg, _] = key.map(|x| x as u32);
        self.key = Some(key);
        self.bounds.clear();
        let edges = (0..count).map(|c| (c * size, ((c + 1) * size).min(pts) - 1));
        self.edges.clear();
        self.edges.extend(edges);
        let ppg = ppg as i32;
        self.cells.clear();
        self.cells.extend(self.edges.iter().map(|&(lo, hi)| {
            let (a, b) = ((lo as i32 / ppg) as usize, (hi as i32 / ppg) as usize);
            (a * stride, b - a + 1)
        }));
        self.stride = stride;
        self.corners.clear();
        if n == 2 && d == 0 {
            self.corners.extend(self.edges.iter().map(|&(lo, _)| lo));
            self.corners.extend(self.edges.iter().map(|&(_, hi)| hi));
        } else {
            self.corners
                .extend(self.edges.iter().flat_map(|&(lo, hi)| [lo, hi]));
        }
        self.mids.clear();
        self.mids
            .extend(self.edges.iter().map(|&(lo, hi)| lo + (hi - lo) / 2));
        self.runs.clear();
        for (k, &(lo, hi)) in self.edges.iter().enumerate() {
            match self.runs.last_mut() {
                Some((_, end, width)) if *width == hi - lo => *end = k + 1,
                _ => self.runs.push((k, k + 1, hi - lo)),
            }
        }
        // Tile k in cell k / per_cell, for the per_cell that the first cell's tiles give.
        let per_cell = self.cells.iter().take_while(|c| c.0 == 0).count();
        let in_cells = |(k, &(cell, span)): (usize, &(usize, usize))| {
            span == 1 && cell == k / per_cell * stride
        };
        let uniform = per_cell > 0 && self.cells.iter().enumerate().all(in_cells);
        self.per_cell = if uniform { per_cell } else { 0 };
    }
}

/// [`fit_uniform`] for `N` dimensions (a constant, so the per-tile loops unroll).
fn fit_uniform_n<const N: usize>(
    aof: &dyn Aof,
    domain: &Domain,
    (size, counts, _): (&[u32], &[u32], &[u32]),
    strict: bool,
    axes: &mut [Axis],
    (bounds, weights, summary): (&mut Vec<i32>, &mut Vec<f64>, &mut Summary),
) {
    // Arrays, not vectors, where the length is N (a build runs every iteration).
    let pts: [u32; N] = std::array::from_fn(|d| domain.var(d).points);
    let grid_stride: usize = axes[..N]
        .iter()
        .map(|a| a.key.map_or(1, |k| k[5]))
        .product();
    if N == 2 {
        // The bounds depend on the shape alone: written once, then copied, or found in
        // a buffer of an earlier function of this shape that came back holding them.
        let mut kept = std::mem::take(&mut axes[0].bounds);
        if kept.is_empty() {
            write_bounds_2(&axes[0].edges, &axes[1].edges, &mut kept);
        }
        debug_assert!(bounds.is_empty());
        spare::give_ints(std::mem::replace(bounds, spare::ints_holding(&kept)));
        axes[0].bounds = kept;
    }
    let axes = &axes[..N];
    let grid_strides: [usize; N] = std::array::from_fn(|d| axes[d].stride);
    let grid = &mut summary.grid;
    grid.clear();
    grid.resize(grid_stride, f64::NEG_INFINITY);
    let mut corners = Scratch::take();
    evaluate(aof, domain, axes, false, &mut corners.0);
    // Some tile takes its centre exactly when some dimension has a tile wider than 2.
    let any_centre = (0..N).any(|d| size[d].min(pts[d]) > 2);
    let mut mids = Scratch::take();
    if any_centre {
        evaluate(aof, domain, axes, true, &mut mids.0);
    }
    // Strides of the two grids (dimension 0 fastest).
    let mut corner_stride = [0usize; N];
    let mut mid_stride = [0usize; N];
    let (mut cs, mut ms) = (1usize, 1usize);
    for d in 0..N {
        corner_stride[d] = cs;
        mid_stride[d] = ms;
        cs *= 2 * counts[d] as usize;
        ms *= counts[d] as usize;
    }
    // Where each corner (bit d of the mask = high end in dimension d) lies from the
    // tile's low corner in the corner grid.
    let corner_offset: [usize; 1 << FIT_DIMS] = std::array::from_fn(|mask| {
        (0..N)
            .filter(|&d| mask & (1 << d) != 0)
            .map(|d| corner_stride[d])
            .sum()
    });
    if N == 2 {
        // The contact behaviors' course × speed: rows of tiles, no per-corner offsets.
        let mids = if any_centre { &mids.0[..] } else { &[] };
        let (pieces, min_max) = fit_rows_2(axes, (&corners.0, mids), strict, grid);
        (summary.min_max, summary.pieces) = (min_max, Some(pieces));
        summary.weights_pending = min_max.is_some();
        return;
    }
    let total: usize = counts.iter().map(|&c| c as usize).product();
    bounds.reserve(total * 2 * N);
    weights.reserve(total * (N + 1));
    let mut folds = Folds {
        grid,
        min_max: None,
    };
    let mut coord: [usize; N] = std::array::from_fn(|d| counts[d] as usize - 1);
    let mut vals = [0.0f64; (1 << FIT_DIMS) + 1];
    let mut w = [0.0f64; FIT_DIMS + 1];
    let ncorner = 1usize << N;
    for _ in 0..total {
        let lo: [u32; N] = std::array::from_fn(|d| axes[d].edges[coord[d]].0);
        let hi: [u32; N] = std::array::from_fn(|d| axes[d].edges[coord[d]].1);
        let (mut corner_at, mut mid_at) = (0usize, 0usize);
        for d in 0..N {
            bounds.push(lo[d] as i32);
            bounds.push(hi[d] as i32);
            corner_at += 2 * coord[d] * corner_stride[d];
            mid_at += coord[d] * mid_stride[d];
        }
        for mask in 0..ncorner {
            vals[mask] = corners.0[corner_at + corner_offset[mask]];
        }
        if (0..N).any(|d| hi[d] - lo[d] + 1 > 2) {
            vals[ncorner] = mids.0[mid_at];
            fit_box::<N, true>(&lo, &hi, &vals, strict, &mut w);
        } else {
            fit_box::<N, false>(&lo, &hi, &vals, strict, &mut w);
        }
        weights.extend_from_slice(&w[..=N]);
        let pmax = folds.add::<N>(&lo, &hi, &w);
        raise_cells::<N>(folds.grid, axes, &grid_strides, &coord, pmax);
        // The previous tile: dimension 0 counts down first.
        for d in 0..N {
            if coord[d] > 0 {
                coord[d] -= 1;
                break;
            }
            coord[d] = counts[d] as usize - 1;
        }
    }
    summary.min_max = folds.min_max;
}

/// The running value range of the pieces fitted so far, and their grid.
struct Folds<'a> {
    grid: &'a mut Vec<f64>,
    min_max: Option<(f64, f64)>,
}

impl Folds<'_> {
    /// Fold in the piece `lo..=hi` with weights `w`: its least and greatest value
    /// (function.rs's min_val and max_val, the same operations in the same order),
    /// folded as min_max_wt folds them. Returns the greatest.
    #[inline(always)]
    fn add<const N: usize>(
        &mut self,
        lo: &[u32; N],
        hi: &[u32; N],
        w: &[f64; FIT_DIMS + 1],
    ) -> f64 {
        let (mut pmin, mut pmax) = (w[N], w[N]);
        for d in 0..N {
            let (l, h) = (f64::from(lo[d] as i32), f64::from(hi[d] as i32));
            pmax += w[d] * if w[d] < 0.0 { l } else { h };
            pmin += w[d] * if w[d] < 0.0 { h } else { l };
        }
        self.min_max = Some(match self.min_max {
            None => (pmin, pmax),
            Some((mn, mx)) => (
                if pmin < mn { pmin } else { mn },
                if pmax > mx { pmax } else { mx },
            ),
        });
        pmax
    }
}

/// The tiles of a 2-dimensional tiling fitted in the reflector's order (the last tile
/// first, dimension 0 fastest); what the general loop of [`fit_uniform_n`] does, tile
/// for tile. Each row's tiles are fitted a run of equal widths at a time
/// ([`rows::fit_run`], several tiles per instruction), from the corner grid's rows (all
/// low-edge corners of a row, then all high-edge ones) and the grid of midpoints; then
/// the pieces are written out and folded in the reflector's order.
fn fit_rows_2(
    axes: &[Axis],
    (corners, mids): (&[f64], &[f64]),
    strict: bool,
    grid: &mut [f64],
) -> (rows::Pieces, Option<(f64, f64)>) {
    let (xs, ys) = (&axes[0], &axes[1]);
    let (nx, ny) = (xs.edges.len(), ys.edges.len());
    let row = 2 * nx;
    let mut pieces = rows::Pieces::new(&xs.edges, &ys.edges);
    let mut lists = pieces.lists_mut();
    for (cy, &(ylo, yhi)) in ys.edges.iter().enumerate() {
        let low_row = &corners[2 * cy * row..][..row];
        let high_row = &corners[(2 * cy + 1) * row..][..row];
        // Empty when no tile takes its centre (the midpoints were not asked then).
        let mid_row = if mids.is_empty() {
            &[][..]
        } else {
            &mids[cy * nx..][..nx]
        };
        let y_centre = yhi - ylo + 1 > 2;
        let y = [
            f64::from(ylo),
            f64::from(yhi),
            f64::from(ylo + (yhi - ylo) / 2),
        ];
        let at = cy * nx;
        for &(a, b, width) in &xs.runs {
            let centre = y_centre || width + 1 > 2;
            let run = rows::Run {
                x: [&lists.xl[a..b], &lists.xh[a..b], &lists.xm[a..b]],
                y,
                widths: (width, yhi - ylo),
                vals: [
                    &low_row[a..b],
                    &low_row[nx + a..nx + b],
                    &high_row[a..b],
                    &high_row[nx + a..nx + b],
                    if centre { &mid_row[a..b] } else { &[] },
                ],
                strict,
                centre,
            };
            let (i, j) = (at + a, at + b);
            let [w0, w1, w2, lo, hi] = &mut lists.pieces;
            let mut out = rows::RunOut {
                w: [&mut w0[i..j], &mut w1[i..j], &mut w2[i..j]],
                min: &mut lo[i..j],
                max: &mut hi[i..j],
            };
            rows::fit_run(&run, &mut out);
        }
    }
    let total = nx * ny;
    let [_, _, _, lo, hi] = &lists.pieces;
    let (lo, hi) = (&lo[..total], &hi[..total]);
    // In the reflector's order (the last tile first), each in a pass of its own (tight
    // loops): ranges folded, grid cells raised (the weights stay in the lists:
    // Summary::weights_pending; the bounds are fit_uniform_n's).
    let min_max = (total > 0).then(|| rows::fold_range(lo, hi));
    for (cy, &(ycell, yspan)) in ys.cells.iter().enumerate().rev() {
        let row = &hi[cy * nx..][..nx];
        if xs.per_cell == 0 || yspan != 1 {
            let raise = |cx| raise_cells::<2>(grid, axes, &[1, ys.stride], &[cx, cy], row[cx]);
            (0..nx).rev().for_each(raise);
            continue;
        }
        // The row's tiles in consecutive cells, xs.per_cell to a cell.
        let cells = &mut grid[ycell..][..nx.div_ceil(xs.per_cell)];
        rows::raise_cells_of_row(cells, row, xs.per_cell);
    }
    (pieces, min_max)
}

/// The bounds of the tiles of a 2-dimensional tiling with edges `xs` × `ys`, appended
/// to `bounds` in the reflector's order (the last tile first, dimension 0 fastest).
fn write_bounds_2(xs: &[(u32, u32)], ys: &[(u32, u32)], bounds: &mut Vec<i32>) {
    bounds.reserve(4 * xs.len() * ys.len());
    for &(ylo, yhi) in ys.iter().rev() {
        for &(xlo, xhi) in xs.iter().rev() {
            bounds.extend([xlo, xhi, ylo, yhi].map(|x| x as i32));
        }
    }
}

#[path = "tiling_rows.rs"]
mod rows;

/// Raise the grid cells of the tile at `coord` to the piece maximum `v`, as
/// build_grid does (a cell still at -inf takes `v` whatever it is).
#[inline(always)]
fn raise_cells<const N: usize>(
    grid: &mut [f64],
    axes: &[Axis],
    strides: &[usize; N],
    coord: &[usize; N],
    v: f64,
) {
    let mut first = 0usize;
    let mut span = [1usize; N];
    for d in 0..N {
        let (at, n) = axes[d].cells[coord[d]];
        first += at;
        span[d] = n;
    }
    let mut off = [0usize; N];
    let mut c = first;
    'cells: loop {
        let g = &mut grid[c];
        if *g == f64::NEG_INFINITY || v > *g {
            *g = v;
        }
        for d in 0..N {
            if off[d] + 1 < span[d] {
                off[d] += 1;
                c += strides[d];
                continue 'cells;
            }
            c -= off[d] * strides[d];
            off[d] = 0;
        }
        break;
    }
}

/// A grid-values buffer kept per thread between builds (a behavior builds every
/// iteration; the buffer is taken out while in use, so a nested build gets its own).
#[derive(Debug)]
struct Scratch(Vec<f64>);

/// Values kept per thread between builds: grid-values buffers and fits' axes.
type Pool<T> = std::thread::LocalKey<std::cell::RefCell<Vec<T>>>;

thread_local! {
    static SCRATCH: std::cell::RefCell<Vec<Vec<f64>>> = const { std::cell::RefCell::new(Vec::new()) };
    static SPARE_AXES: std::cell::RefCell<Vec<[Axis; FIT_DIMS]>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The last value kept in `pool`, if any (none once the thread is ending).
fn pop<T>(pool: &'static Pool<T>) -> Option<T> {
    pool.try_with(|p| p.borrow_mut().pop()).ok().flatten()
}

/// The last value kept in `pool` that is `wanted`, else the last one, if any.
fn pop_where<T>(pool: &'static Pool<T>, wanted: impl Fn(&T) -> bool) -> Option<T> {
    let take = |p: &std::cell::RefCell<Vec<T>>| {
        let mut kept = p.borrow_mut();
        match kept.iter().rposition(wanted) {
            Some(i) => Some(kept.remove(i)),
            None => kept.pop(),
        }
    };
    pool.try_with(take).ok().flatten()
}

/// Keep `v` in `pool` (up to 8 values) for a later [`pop`].
fn push<T>(pool: &'static Pool<T>, v: T) {
    let _ = pool.try_with(|p| {
        let mut kept = p.borrow_mut();
        if kept.len() < 8 {
            kept.push(v);
        }
    });
}

impl Scratch {
    fn take() -> Scratch {
        Scratch(pop(&SCRATCH).unwrap_or_default())
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        push(&SCRATCH, std::mem::take(&mut self.0));
    }
}

/// The AOF's values on the grid of the axes' corner coordinates (or their `mids`) into
/// `out` (resized to fit).
fn evaluate(aof: &dyn Aof, domain: &Domain, axes: &[Axis], mids: bool, out: &mut Vec<f64>) {
    let mut refs: [&[u32]; FIT_DIMS] = [&[]; FIT_DIMS];
    for (r, a) in refs.iter_mut().zip(axes) {
        *r = if mids { &a.mids } else { &a.corners };
    }
    let len: usize = refs[..axes.len()].iter().map(|r| r.len()).product();
    if aof.eval_grid_fills() {
        // Every slot is written: what the last build left there does not matter.
        if out.len() < len {
            out.resize(len, 0.0);
        }
    } else {
        // Zeroed, not left from the last build: a slot the AOF skips reads 0.
        out.clear();
        out.resize(len, 0.0);
    }
    aof.eval_grid(domain, &refs[..axes.len()], &mut out[..len]);
}

#[cfg(test)]
mod tests {
    use crate::{Aof, Reflector};
    use ivp::Domain;

    fn rng(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The bits of `x`, every NaN as the one canonical NaN: Rust leaves the sign and
    /// payload of an arithmetic NaN unspecified (the compiler may swap the operands of
    /// a sum, and x86 then passes on the other NaN), so those bits are no property of
    /// the code; all else (signed zeros, infinities, every finite value) must match.
    pub(crate) fn bits_of(x: f64) -> u64 {
        if x.is_nan() {
            f64::NAN.to_bits()
        } else {
            x.to_bits()
        }
    }

    /// A bumpy surface with flat clipped stretches (ties in the strict-range shift).
    struct Bumps {
        k: Vec<f64>,
        clip: f64,
    }

    impl Aof for Bumps {
        fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
            let mut u = 0.0;
            for (d, &i) in index.iter().enumerate() {
                let x = domain.value(d, i);
                u += (x * self.k[d]).sin() * 40.0 + x * self.k[d + 3];
            }
            u.clamp(-self.clip, self.clip)
        }
    }

    /// Fitting from the two grid evaluations gives the pieces of fitting tile by tile,
    /// bit for bit, over random domains (1 to 3 dimensions, clipped last tiles, edges of
    /// 1 to 6 points), random surfaces (smooth, or with ties, signed zeros, NaNs and
    /// infinities) and random search grids, plain and normalized; so do the search grid
    /// and the value range the fit takes along (against build_grid and min_max_wt).
    #[test]
    fn grid_evaluation_equals_tile_by_tile() {
        let mut seed = 7u64;
        for case in 0..2400 {
            let dims = 1 + case % 3;
            let mut spec = Vec::new();
            let mut piece = Vec::new();
            let mut gel = Vec::new();
            for d in 0..dims {
                let points = 1 + (rng(&mut seed) * 60.0) as u32;
                let low = (rng(&mut seed) * 20.0).floor() - 10.0;
                let high = low + (points.max(2) - 1) as f64 * (0.1 + rng(&mut seed));
                let points = if points == 1 { 1 } else { points };
                let high = if points == 1 { low } else { high };
                spec.push(format!("x{d}:{low}:{high}:{points}"));
                piece.push(format!("x{d}:{}", 1 + (rng(&mut seed) * 6.0) as u32));
                gel.push(format!("x{d}:{}", 1 + (rng(&mut seed) * 12.0) as u32));
            }
            let Ok(domain) = Domain::parse(&spec.join(",")) else {
                continue;
            };
            let bumps = Bumps {
                k: (0..6).map(|_| rng(&mut seed) * 2.0 - 1.0).collect(),
                clip: 10.0 + rng(&mut seed) * 60.0,
            };
            let awkward = Awkward(case as u64);
            let aof: &dyn Aof = if case % 5 == 4 { &awkward } else { &bumps };
            let strict = case % 4 != 3;
            let with_grid = case % 3 != 0;
            let build = |r: Reflector<'_>| {
                let mut r = r;
                r.set_param("uniform_piece", &format!("discrete@{}", piece.join(",")));
                if with_grid {
                    r.set_param("uniform_grid", &format!("discrete@{}", gel.join(",")));
                }
                r.set_param("strict_range", if strict { "true" } else { "false" });
                let n = r.create(None, None);
                let f = r.extract(case % 2 == 0).expect("pieces");
                let bits = |v: &[f64]| v.iter().map(|&w| bits_of(w)).collect::<Vec<u64>>();
                let (mn, mx) = f.min_max_wt();
                (
                    n,
                    f.bounds().to_vec(),
                    bits(f.weights()),
                    bits(f.grid_bounds()),
                    bits(&[mn, mx]),
                )
            };
            let grid = build(Reflector::new(&domain, aof));
            let tiles = build(Reflector::new(&domain, aof).tile_by_tile());
            assert_eq!(grid, tiles, "case {case}: {spec:?} {piece:?}");
        }
    }

    /// A build in the buffers of earlier ones (the reflector's, the fit's axes, bounds
    /// and grid values, recycled functions' buffers, all kept per thread) gives what a
    /// build on a fresh thread, with no spares, gives: bit for bit, over rounds of builds
    /// of different shapes and of one shape, through every way out of the reflector,
    /// created twice or once.
    #[test]
    fn builds_in_reused_buffers_equal_fresh_ones() {
        let cases = [
            ("x:0:359:360,y:0:4:41", "x:3,y:3", "x:9,y:6", 0),
            ("x:0:99:100", "x:7", "x:4", 1),
            (
                "x:-5:5:11,y:0:9:10,z:0:2:3",
                "x:2,y:4,z:1",
                "x:5,y:3,z:2",
                2,
            ),
            ("x:0:359:360,y:0:4:41", "x:5,y:2", "x:5,y:2", 3),
            ("x:0:20:21,y:0:30:31", "x:4,y:6", "x:3,y:3", 4),
            // Case 0's shape on other values: its kept axes and bounds serve.
            ("x:-10:349:360,y:0:8:41", "x:3,y:3", "x:9,y:6", 5),
            // Case 0's tiles under another search grid: the axes are made again.
            ("x:0:359:360,y:0:4:41", "x:3,y:3", "x:6,y:9", 6),
        ];
        let build = |(spec, piece, grid, k): (&str, &str, &str, usize), twice: bool| {
            let domain = Domain::parse(spec).expect("domain");
            let awkward = Awkward(k as u64);
            let bumps = Bumps {
                k: vec![0.3, -0.7, 0.11, 0.5, -0.2, 0.9],
                clip: 35.0,
            };
            let aof: &dyn Aof = if k == 4 { &awkward } else { &bumps };
            let mut r = Reflector::new(&domain, aof);
            r.set_param("uniform_piece", &format!("discrete@{piece}"));
            r.set_param("uniform_grid", &format!("discrete@{grid}"));
            r.set_param("strict_range", if k == 1 { "FALSE" } else { "true" });
            r.create(None, None);
            if twice {
                // Created again: the same pieces, not twice as many.
                r.create(None, None);
            }
            let f = match k % 3 {
                0 => r.into_function_normalized_twice(),
                1 => r.into_function(true),
                _ => r.extract(false),
            }
            .expect("pieces");
            let bits = |v: &[f64]| v.iter().map(|&w| bits_of(w)).collect::<Vec<u64>>();
            let got = (
                f.domain().clone(),
                f.bounds().to_vec(),
                bits(f.weights()),
                bits(f.grid_bounds()),
                f.gelbox().to_vec(),
            );
            f.recycle();
            got
        };
        let fresh: Vec<_> = cases
            .iter()
            .map(|&c| {
                std::thread::spawn(move || build(c, false))
                    .join()
                    .expect("build")
            })
            .collect();
        for round in 0..4 {
            for (k, (&c, want)) in cases.iter().zip(&fresh).enumerate().rev() {
                assert_eq!(&build(c, k == 3), want, "round {round} case {k}");
            }
        }
    }

    /// A function's bounds buffer that comes back holding its shape's bounds serves the
    /// next build of that shape as it is; one changed while out is written again.
    #[test]
    fn a_returned_bounds_buffer_serves_only_while_it_holds_the_bounds() {
        let domain = Domain::parse("x:0:359:360,y:0:4:41").expect("domain");
        let aof = Bumps {
            k: vec![0.3, -0.7, 0.11, 0.5, -0.2, 0.9],
            clip: 35.0,
        };
        let build = || {
            let mut r = Reflector::new(&domain, &aof);
            r.set_param("uniform_piece", "discrete@x:3,y:3");
            r.create(None, None);
            r.into_function(true).expect("pieces")
        };
        let want = std::thread::scope(|s| s.spawn(|| build().bounds().to_vec()).join());
        let want = want.expect("build");
        let mut f = build();
        assert_eq!(f.bounds(), want);
        let at = f.bounds().as_ptr();
        f.recycle();
        f = build();
        assert!(f.bounds().as_ptr() == at && f.bounds() == want);
        // Changed in place while out (its weights and all): the bounds are written again.
        let (mut bounds, weights, gelbox, grid) = f.take_buffers();
        bounds[5] += 1;
        mbutil::spare::give_function_buffers(bounds, weights, gelbox, grid);
        f = build();
        assert!(f.bounds().as_ptr() == at && f.bounds() == want);
        f.recycle();
    }

    /// The boxes given as pairs are those of the same boxes given as text, and a box
    /// with an unknown variable or a size 0 is refused and left as it was, as there.
    #[test]
    fn uniform_boxes_as_pairs_equal_them_as_text() {
        let domain = Domain::parse("course:0:359:360,speed:0:4:41").expect("domain");
        let aof = Bumps {
            k: vec![0.3, -0.7, 0.11, 0.5, -0.2, 0.9],
            clip: 35.0,
        };
        let build = |pairs: bool, piece: &'static str, grid: &'static str| {
            let mut r = Reflector::new(&domain, &aof);
            let ok = if pairs {
                let box_of = |t: &'static str| -> Vec<(&'static str, u32)> {
                    let parts = t.split(',').filter_map(|p| p.split_once(':'));
                    parts.map(|(n, v)| (n, v.parse().expect("size"))).collect()
                };
                r.set_uniform(&box_of(piece), &box_of(grid))
            } else {
                let a = r.set_param("uniform_piece", &format!("discrete @ {piece}"));
                let b = r.set_param("uniform_grid", &format!("discrete @ {grid}"));
                a && b
            };
            r.create(None, None);
            let f = r.into_function_normalized_twice().expect("pieces");
            let bits = |v: &[f64]| v.iter().map(|&w| bits_of(w)).collect::<Vec<u64>>();
            let got = (
                ok,
                f.bounds().to_vec(),
                bits(f.weights()),
                bits(f.grid_bounds()),
            );
            (got, f.gelbox().to_vec())
        };
        for (piece, grid) in [
            ("course:3,speed:3", "course:9,speed:6"),
            ("speed:2", "course:8"),
            ("course:3,heading:3", "course:9,speed:6"),
            ("course:3,speed:0", "course:0,speed:6"),
        ] {
            assert_eq!(
                build(true, piece, grid),
                build(false, piece, grid),
                "{piece} {grid}"
            );
        }
    }

    /// Values with ties, signed zeros, NaNs and infinities, from a hash of the point.
    struct Awkward(u64);

    impl Aof for Awkward {
        fn eval(&self, _: &Domain, index: &[u32]) -> f64 {
            let mut h = self.0;
            for &i in index {
                h = (h ^ u64::from(i)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            }
            match (h >> 59) % 16 {
                0 => 0.0,
                1 => -0.0,
                2 => f64::NAN,
                3 => f64::INFINITY,
                4 => 7.0,
                5 => -7.0,
                _ => ((h >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 200.0,
            }
        }
    }

    /// The fit of 1 to 4 dimensions ([`Reflector::fit_into`], with its shortcuts) is the
    /// general fit ([`Reflector::fit`], the spec's arithmetic) bit for bit, awkward
    /// values included, strict range or not.
    #[test]
    fn fit_shortcuts_equal_the_general_fit() {
        let mut seed = 3u64;
        for case in 0..20000u64 {
            let n = 1 + (case % 4) as usize;
            let d = Domain::parse(
                &["a:0:99:100", "b:0:99:100", "c:0:99:100", "d:0:99:100"][..n].join(","),
            )
            .unwrap();
            let aof = Awkward(case);
            let mut r = Reflector::new(&d, &aof);
            if case % 3 == 0 {
                r.set_param("strict_range", "false");
            }
            let b: Vec<(u32, u32)> = (0..n)
                .map(|_| {
                    let lo = (rng(&mut seed) * 90.0) as u32;
                    (lo, lo + (rng(&mut seed) * 5.0) as u32)
                })
                .collect();
            let mut w = vec![0.0; n + 1];
            r.fit_into(&b, &mut w);
            let want = r.fit(&b);
            let bits = |v: &[f64]| v.iter().map(|&x| bits_of(x)).collect::<Vec<_>>();
            assert_eq!(bits(&w), bits(&want), "case {case}: {b:?}");
        }
    }

    /// Random awkward values: signed zeros, infinities, NaN, subnormals, huge and tiny
    /// normals, ordinary values.
    fn awkward_value(seed: &mut u64) -> f64 {
        let r = rng(seed);
        let k = (rng(seed) * 14.0) as u32;
        let sign = if rng(seed) < 0.5 { -1.0 } else { 1.0 };
        sign * match k {
            0 => 0.0,
            1 => f64::INFINITY,
            2 => f64::NAN,
            3 => f64::MIN_POSITIVE * r,               // subnormal
            4 => f64::from_bits((r * 4.0e15) as u64), // subnormal, any bits
            5 => f64::MIN_POSITIVE * (1.0 + r),       // smallest normals
            6 => f64::MAX * r,
            7 => 2.5,
            _ => (r - 0.5) * 250.0,
        }
    }

    /// Dividing by a power of two as [`crate::fit::div_by_width`] does (a
    /// multiplication by the exact reciprocal) gives the division's bits, subnormal
    /// results, signed zeros and infinities included; other widths are divided.
    #[test]
    fn division_by_a_power_of_two_width_is_the_division() {
        let mut seed = 5u64;
        for _ in 0..200_000 {
            let q = awkward_value(&mut seed);
            let width = match (rng(&mut seed) * 3.0) as u32 {
                0 => 1u32 << (rng(&mut seed) * 32.0) as u32,
                1 => 1 + (rng(&mut seed) * 10.0) as u32,
                _ => (rng(&mut seed) * 4.0e9) as u32 | 1,
            };
            let got = crate::fit::div_by_width(q, width);
            let want = q / f64::from(width);
            assert_eq!(bits_of(got), bits_of(want), "{q:e} / {width}");
        }
    }

    /// Normalizing while folding the new pieces' range gives what normalizing then
    /// asking min_max_wt gives (weights, grid and range, bit for bit), over random
    /// functions of 1 to 5 dimensions with awkward weights and ranges.
    #[test]
    fn normalize_with_range_equals_normalize_then_range() {
        let mut seed = 13u64;
        let specs = [
            "a:0:9:10",
            "a:0:9:10,b:0:40:41",
            "a:0:9:10,b:0:4:5,c:0:20:21",
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3",
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3,e:0:7:8",
        ];
        for round in 0..4000 {
            let dom = Domain::parse(specs[round % specs.len()]).unwrap();
            let dim = dom.size();
            let n = (rng(&mut seed) * 40.0) as usize;
            let (mut bounds, mut weights) = (vec![], vec![]);
            for _ in 0..n {
                for v in dom.vars() {
                    let lo = (rng(&mut seed) * f64::from(v.points)) as i32;
                    let hi = lo + (rng(&mut seed) * f64::from(v.points as i32 - lo)) as i32;
                    bounds.extend([lo, hi]);
                }
                for _ in 0..=dim {
                    let w = if rng(&mut seed) < 0.7 {
                        (rng(&mut seed) - 0.5) * 300.0
                    } else {
                        awkward_value(&mut seed)
                    };
                    weights.push(w);
                }
            }
            let gel = vec![1 + (rng(&mut seed) * 3.0) as u32; dim];
            let Ok(mut f) = ivp::IvpFunction::from_flat(dom, bounds, weights, gel) else {
                continue;
            };
            f.build_grid();
            let (base, range) = [(0.0, 100.0), (-3.0, 0.5), (7.0, -1.0)][round % 3];
            let min_max = match round % 4 {
                0 => (awkward_value(&mut seed), awkward_value(&mut seed)),
                1 => (-1.0, 1.0),
                _ => f.min_max_wt(),
            };
            let mut want = f.clone();
            want.normalize_from(min_max, base, range);
            let want_range = want.min_max_wt();
            let got_range = f.normalize_from_and_min_max(min_max, base, range);
            let bits = |v: &[f64]| v.iter().map(|&x| bits_of(x)).collect::<Vec<_>>();
            assert_eq!(bits(f.weights()), bits(want.weights()), "round {round}");
            assert_eq!(
                bits(f.grid_bounds()),
                bits(want.grid_bounds()),
                "round {round}"
            );
            assert_eq!(
                bits(&[got_range.0, got_range.1]),
                bits(&[want_range.0, want_range.1]),
                "round {round}"
            );
        }
    }

    /// The reflector's function normalized twice in one step is its normalized function
    /// normalized once more (the previous way), bit for bit, from the grid fit and from
    /// the tile-by-tile fit, over random domains and surfaces; normalized once, the grid
    /// fit's function is the tile-by-tile one's.
    #[test]
    fn normalized_twice_equals_normalize_after_into_function() {
        let mut seed = 21u64;
        for case in 0..900 {
            let dims = 1 + case % 3;
            let (mut spec, mut piece) = (vec![], vec![]);
            for d in 0..dims {
                let points = 2 + (rng(&mut seed) * 60.0) as u32;
                let low = (rng(&mut seed) * 20.0).floor() - 10.0;
                let high = low + (points - 1) as f64 * (0.1 + rng(&mut seed));
                spec.push(format!("x{d}:{low}:{high}:{points}"));
                piece.push(format!("x{d}:{}", 1 + (rng(&mut seed) * 6.0) as u32));
            }
            let Ok(domain) = Domain::parse(&spec.join(",")) else {
                continue;
            };
            let bumps = Bumps {
                k: (0..6).map(|_| rng(&mut seed) * 2.0 - 1.0).collect(),
                clip: 10.0 + rng(&mut seed) * 60.0,
            };
            let awkward = Awkward(case as u64);
            let aof: &dyn Aof = if case % 5 == 4 { &awkward } else { &bumps };
            let mut once = vec![];
            for tiles in [false, true] {
                let make = || {
                    let r = Reflector::new(&domain, aof);
                    let mut r = if tiles { r.tile_by_tile() } else { r };
                    r.set_param("uniform_piece", &format!("discrete@{}", piece.join(",")));
                    r.create(None, None);
                    r
                };
                // Normalized once: the grid fit's weights written normalized are the
                // tile-by-tile function's, normalized in a pass of its own.
                let f = make().into_function(true).expect("pieces");
                let bits = |v: &[f64]| v.iter().map(|&x| bits_of(x)).collect::<Vec<_>>();
                once.push((
                    bits(f.weights()),
                    bits(f.grid_bounds()),
                    f.bounds().to_vec(),
                ));
                let got = make().into_function_normalized_twice().expect("pieces");
                let mut want = make().into_function(true).expect("pieces");
                want.normalize(0.0, 100.0);
                assert_eq!(bits(got.weights()), bits(want.weights()), "case {case}");
                assert_eq!(got.bounds(), want.bounds(), "case {case}");
                assert_eq!(
                    bits(got.grid_bounds()),
                    bits(want.grid_bounds()),
                    "case {case}"
                );
            }
            assert_eq!(once[0], once[1], "case {case}");
        }
    }
}
