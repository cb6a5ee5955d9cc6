//! One function as the solver holds it (spec §5): its boxes and weights in the problem
//! domain, its grid of cells with their bounds (spec §2.4), and the walks over the
//! cells a box overlaps.

use crate::coords::CoordTable;
use std::cell::Cell;

/// One function, normalized, weighted and translated into the problem domain.
#[derive(Debug, Default)]
pub(crate) struct Prepared {
    /// The boxes in the problem domain, unless `borrowed` (the function's own boxes
    /// already are: same dimensions in the same order).
    pub(crate) bounds: Vec<i32>,
    pub(crate) borrowed: bool,
    /// Bumped whenever the boxes are made anew (kept boxes keep it): equal
    /// generations of one slot mean equal boxes.
    pub(crate) boxes_gen: u64,
    /// Bumped whenever the slot is prepared afresh (a kept slot keeps it).
    pub(crate) gen: u64,
    pub(crate) weights: Vec<f64>,
    pub(crate) n: usize,
    pub(crate) map: Vec<usize>,
    // Grid (spec §2.4).
    pub(crate) single: bool,
    pub(crate) global_ub: f64,
    pub(crate) ppg: Vec<i32>,
    pub(crate) ncells: Vec<i32>,
    pub(crate) stride: Vec<usize>,
    /// Cell coordinate of every index (no division per piece bound).
    pub(crate) coords: CoordTable,
    /// Position in `active` of the first function with the same grid geometry: boxes
    /// cover the same cells of both.
    pub(crate) geom: usize,
    pub(crate) cell_start: Vec<u32>,
    pub(crate) cell_items: Vec<u32>,
    /// Cell bound, `NO_BOUND` for an empty cell.
    pub(crate) cell_ub: Vec<f64>,
    pub(crate) cell_filled: Vec<bool>,
    pub(crate) cursor: Vec<u32>,
    pub(crate) seen: Vec<Cell<u32>>,
    pub(crate) stamp: Cell<u32>,
    /// Largest `|intercept| + Σ |slope_d|·(points_d - 1)` over the pieces: no partial
    /// sum of a value or bound of this function exceeds it (sizes the rounding slack).
    pub(crate) term_scale: f64,
    /// `maxVal` of every piece (scratch of the set-up, for the cell bounds).
    pub(crate) piece_ub: Vec<f64>,
    /// The function's own boxes, dimension map and problem points that `bounds` were
    /// made from (see `setup.rs`).
    pub(crate) src_bounds: Vec<i32>,
    pub(crate) src_map: Vec<usize>,
    pub(crate) src_pts: Vec<i32>,
    /// The cell size the cell lists were made for (from the boxes of `src_*`), empty
    /// for none.
    pub(crate) lists_ppg: Vec<i32>,
    /// The boxes as the set-up's AVX2 passes read them (see `weigh.rs`).
    pub(crate) corners: crate::weigh::Corners,
    /// What the slot was last prepared from (see `setup.rs`).
    pub(crate) key: crate::made_from::MadeFrom,
}

pub(crate) const NO_BOUND: f64 = -99999.0;

/// The grid cells a box overlaps: per dimension the lowest and highest cell
/// coordinate, and the number of the cell at the highest corner (where the odometer
/// starts).
#[derive(Clone, Copy)]
pub(crate) struct CellRange {
    pub(crate) lo: [usize; ODO_DIMS],
    pub(crate) hi: [usize; ODO_DIMS],
    pub(crate) top: usize,
    pub(crate) one: bool,
}

impl CellRange {
    /// No cells yet: the start of a range being filled in.
    pub(crate) const NONE: CellRange = CellRange {
        lo: [0; ODO_DIMS],
        hi: [0; ODO_DIMS],
        top: 0,
        one: true,
    };
}

impl Prepared {
    /// Cell coordinate of index `i` in dimension `d` (`i / ppg`).
    #[inline(always)]
    pub(crate) fn coord(&self, d: usize, i: i32) -> usize {
        let line = self.coords.line(d);
        // Indices are inside the problem domain; anything else divides as before.
        match line.get(i as usize) {
            Some(&c) => c as usize,
            None => (i / self.ppg[d]) as usize,
        }
    }

    /// The cells box `b` overlaps (`dim <= ODO_DIMS`).
    #[inline(always)]
    pub(crate) fn range(&self, b: &[i32], dim: usize) -> CellRange {
        let mut r = CellRange::NONE;
        for d in 0..dim {
            r.lo[d] = self.coord(d, b[2 * d]);
            r.hi[d] = self.coord(d, b[2 * d + 1]);
            r.top += r.hi[d] * self.stride[d];
            r.one &= r.lo[d] == r.hi[d];
        }
        r
    }

    /// (Re)make the coordinate table when points or cell sizes changed.
    pub(crate) fn make_coord_table(&mut self, pts: &[i32]) {
        self.coords.make(pts, &self.ppg);
    }

    #[inline]
    pub(crate) fn for_each_cell(&self, b: &[i32], dim: usize, f: impl FnMut(usize) -> bool) {
        if dim > ODO_DIMS {
            return for_each_cell_any(&self.ppg, &self.stride, b, dim, f);
        }
        walk_cells(&self.range(b, dim), &self.stride, dim, f)
    }

    /// Cheap bound over the cells of `r` (spec §2.4).
    #[inline]
    pub(crate) fn bound_over(&self, r: &CellRange, dim: usize) -> f64 {
        if r.one {
            // An empty cell holds NO_BOUND, the bound of no filled cell.
            return self.cell_ub[r.top];
        }
        let mut best = NO_BOUND;
        let mut any = false;
        walk_cells(r, &self.stride, dim, |c| {
            if self.cell_filled[c] && (!any || self.cell_ub[c] > best) {
                best = self.cell_ub[c];
                any = true;
            }
            true
        });
        best
    }

    #[inline]
    pub(crate) fn cheap_bound(&self, b: &[i32], dim: usize) -> f64 {
        if self.single {
            return self.global_ub;
        }
        let mut best = NO_BOUND;
        let mut any = false;
        self.for_each_cell(b, dim, |c| {
            if self.cell_filled[c] && (!any || self.cell_ub[c] > best) {
                best = self.cell_ub[c];
                any = true;
            }
            true
        });
        best
    }
}

/// Visit the grid cells overlapping box `b` like an odometer counting down,
/// last dimension first (spec §2.4). `f` returns false to stop.
///
/// Runs for every piece of every function each iteration (cell lists, cheap bounds), so
/// the odometer steps by strides on the stack instead of dividing per cell.
#[cfg(test)]
pub(crate) fn for_each_cell(
    ppg: &[i32],
    stride: &[usize],
    b: &[i32],
    dim: usize,
    f: impl FnMut(usize) -> bool,
) {
    if dim > ODO_DIMS {
        return for_each_cell_any(ppg, stride, b, dim, f);
    }
    let mut r = CellRange::NONE;
    for d in 0..dim {
        r.lo[d] = (b[2 * d] / ppg[d]) as usize;
        r.hi[d] = (b[2 * d + 1] / ppg[d]) as usize;
        r.top += r.hi[d] * stride[d];
    }
    walk_cells(&r, stride, dim, f)
}

/// The odometer of [`for_each_cell`] over a computed range (`dim <= ODO_DIMS`).
#[inline]
pub(crate) fn walk_cells(
    r: &CellRange,
    stride: &[usize],
    dim: usize,
    mut f: impl FnMut(usize) -> bool,
) {
    let (lo, hi) = (&r.lo, &r.hi);
    let mut cur = *hi;
    let mut idx = r.top;
    loop {
        if !f(idx) {
            return;
        }
        // Count down, last dimension fastest; wrap to `hi` and carry.
        let mut d = dim;
        loop {
            if d == 0 {
                return;
            }
            d -= 1;
            if cur[d] > lo[d] {
                cur[d] -= 1;
                idx -= stride[d];
                break;
            }
            idx += (hi[d] - lo[d]) * stride[d];
            cur[d] = hi[d];
        }
    }
}

/// The scan of the last level (in a solve) at which its bit sets are made.
pub(crate) const BITS_AFTER: u32 = 3;

/// Dimensions the stack odometer of [`for_each_cell`] handles.
pub(crate) const ODO_DIMS: usize = 4;

/// [`for_each_cell`] for any number of dimensions (same order).
pub(crate) fn for_each_cell_any(
    ppg: &[i32],
    stride: &[usize],
    b: &[i32],
    dim: usize,
    mut f: impl FnMut(usize) -> bool,
) {
    let mut total = 1usize;
    for d in 0..dim {
        total *= (b[2 * d + 1] / ppg[d] - b[2 * d] / ppg[d] + 1) as usize;
    }
    for t in 0..total {
        let mut rem = t;
        let mut idx = 0usize;
        for d in (0..dim).rev() {
            let (lo, hi) = (b[2 * d] / ppg[d], b[2 * d + 1] / ppg[d]);
            let span = (hi - lo + 1) as usize;
            let digit = rem % span;
            rem /= span;
            idx += (hi as usize - digit) * stride[d];
        }
        if !f(idx) {
            return;
        }
    }
}

#[inline]
pub(crate) fn intersects(a: &[i32], b: &[i32], dim: usize) -> bool {
    (0..dim).all(|d| a[2 * d] <= b[2 * d + 1] && b[2 * d] <= a[2 * d + 1])
}
