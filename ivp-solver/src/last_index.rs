//! A finer index over the problem's last function when its own grid is one cell.
//!
//! The helm's last function is typically a Waypoint coupled function (tens of pieces,
//! one grid cell), searched below every piece of a contact function's uniform tiling.
//! With one cell, every node would test every piece for intersection and be bounded by
//! the function's global maximum. This index lays the grid of the level above it (the
//! cell size of the function at level `m-2`) over the last function and keeps, per
//! cell, its pieces overlapping the cell **in array order** and a bound
//! `max maxVal(piece ∩ cell)`.
//!
//! Neither changes the result:
//! * a node inside one cell meets only pieces of that cell's list, and the list keeps
//!   array order, which is the one-cell grid order: the same leaves in the same order;
//! * a leaf below such a node lies in `node ∩ q ⊆ q ∩ cell`, so its value is at most
//!   `maxVal(node) + maxVal(q ∩ cell)`: a valid bound (up to rounding, which the
//!   search's slack covers).
//!
//! Nodes spanning several cells use the function's own (global) bound and scan all
//! pieces, as before.

use super::coords::CoordTable;
use crate::made_from::same_bits;
use crate::prepared::ODO_DIMS;
#[cfg(test)]
use ivp::function::max_val;

#[derive(Debug, Default)]
pub(super) struct LastIndex {
    /// Whether the index was built for the current problem.
    pub(super) on: bool,
    dim: usize,
    ppg: Vec<i32>,
    stride: Vec<usize>,
    /// Cell coordinate of every index (the points of each dimension).
    coords: CoordTable,
    /// Per dimension: its coordinates' start in `coords.all()`, their count, its stride.
    lines: [(usize, usize, usize); ODO_DIMS],
    start: Vec<u32>,
    items: Vec<u32>,
    cursor: Vec<u32>,
    /// Per cell: the largest `maxVal(piece ∩ cell)`, `-inf` for a cell no piece meets;
    /// then the bound outside every cell (see [`LastIndex::set_outside`]).
    ub: Vec<f64>,
    /// Scratch of the build: one piece's `w_d·c_d` per dimension and cell coordinate.
    terms: Vec<f64>,
    /// The pieces (boxes, weight bits) the index in memory was made from, when it was
    /// made (`made`): the same pieces on the same cells make the same index, the same
    /// boxes the same lists.
    made: bool,
    key_boxes: Vec<i32>,
    /// Every piece's lowest and highest cell coordinates (kept with the lists).
    spans: Vec<([usize; ODO_DIMS], [usize; ODO_DIMS])>,
    key_weights: Vec<u64>,
}

impl LastIndex {
    /// Index pieces `boxes`/`weights` (problem order, `n` pieces) on cells of `ppg`
    /// points over a domain of `pts` points. Leaves the index off when a box leaves
    /// the domain or the dimension is beyond the stack odometer.
    pub(super) fn build(
        &mut self,
        ppg: &[i32],
        pts: &[i32],
        boxes: &[i32],
        weights: &[f64],
        n: usize,
    ) {
        let dim = pts.len();
        self.on = false;
        if dim == 0 || dim > ODO_DIMS || ppg.len() != dim || ppg.iter().any(|&p| p < 1) {
            return;
        }
        let (bl, wl) = (2 * dim, dim + 1);
        let (boxes, weights) = (&boxes[..n * bl], &weights[..n * wl]);
        // The waypoint's boxes often stay the same from one iteration to the next (its
        // weights less often): the same boxes on the same cells make the same lists.
        let same_boxes = self.made
            && self.dim == dim
            && self.ppg == ppg
            && self.coords.is_for(pts, ppg)
            && self.key_boxes == boxes;
        if same_boxes && same_bits(&self.key_weights, weights) {
            self.on = true;
            return;
        }
        if !same_boxes && !self.make_lists(ppg, pts, boxes, n) {
            self.made = false;
            return;
        }
        self.key_weights.clear();
        self.key_weights.extend(weights.iter().map(|w| w.to_bits()));
        self.make_bounds(boxes, weights, n);
        self.on = true;
        self.made = true;
    }

    /// The cells and the cell lists of the `n` boxes `boxes` (keyed as made, with
    /// each box's cell span); false when a box leaves the domain.
    fn make_lists(&mut self, ppg: &[i32], pts: &[i32], boxes: &[i32], n: usize) -> bool {
        let dim = pts.len();
        let bl = 2 * dim;
        self.made = false;
        self.key_boxes.clear();
        self.key_boxes.extend_from_slice(boxes);
        self.dim = dim;
        self.ppg.clear();
        self.ppg.extend_from_slice(ppg);
        self.stride.clear();
        let mut total = 1usize;
        for d in 0..dim {
            self.stride.push(total);
            total *= ((pts[d] + ppg[d] - 1) / ppg[d]).max(1) as usize;
        }
        self.make_coord_table(pts);
        for d in 0..dim {
            let (at, len) = self.coords.span(d);
            self.lines[d] = (at, len, self.stride[d]);
        }
        self.spans.clear();
        for k in 0..n {
            let Some(span) = self.cell_span(&boxes[k * bl..(k + 1) * bl]) else {
                return false;
            };
            self.spans.push(span);
        }
        self.start.clear();
        self.start.resize(total + 1, 0);
        // (The passes over plain slices: the vectors' fields are not read per cell.)
        let (start, stride) = (&mut self.start[..], &self.stride[..]);
        // Pass 1: count the pieces per cell.
        for (lo, hi) in &self.spans {
            walk(lo, hi, stride, dim, |c| start[c + 1] += 1);
        }
        // The counts summed into the lists' starts (`start[0]` is 0).
        let mut at = 0;
        for s in start.iter_mut() {
            at += *s;
            *s = at;
        }
        self.items.clear();
        self.items.resize(self.start[total] as usize, 0);
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.start[..total]);
        // Pass 2: pieces in array order into every cell they meet.
        let (items, cursor) = (&mut self.items[..], &mut self.cursor[..]);
        for (k, (lo, hi)) in self.spans.iter().enumerate() {
            walk(lo, hi, stride, dim, |c| {
                items[cursor[c] as usize] = k as u32;
                cursor[c] += 1;
            });
        }
        true
    }

    /// The cell bounds of the pieces (the boxes the lists and spans were made from,
    /// `weights` theirs), each cell's from its pieces in array order.
    fn make_bounds(&mut self, boxes: &[i32], weights: &[f64], n: usize) {
        let dim = self.dim;
        let (bl, wl) = (2 * dim, dim + 1);
        self.ub.clear();
        // One more: the bound outside every cell (see `LastIndex::set_outside`).
        self.ub.resize(self.start.len(), f64::NEG_INFINITY);
        if dim == 2 {
            return self.make_bounds2(boxes, weights, n);
        }
        for k in 0..n {
            let b = &boxes[k * bl..(k + 1) * bl];
            let w = &weights[k * wl..(k + 1) * wl];
            let (lo, hi) = self.spans[k];
            // `maxVal(piece ∩ cell)` (spec §2.1) is `w_n + Σ_d w_d·c_d`, the corner
            // `c_d` of the clipped box depending on the cell's coordinate in `d`
            // alone: each product made once per coordinate, the sum in the same
            // order, so the same value bit for bit (see `clip_max_val`). The first
            // add (intercept and dimension 0) is made once per coordinate too.
            let mut off = [0usize; ODO_DIMS];
            self.terms.clear();
            for d in 0..dim {
                off[d] = self.terms.len();
                let (bl_d, bh_d, ppg_d) = (b[2 * d], b[2 * d + 1], self.ppg[d]);
                let first = (d == 0).then_some(w[dim]);
                self.terms.extend((lo[d]..=hi[d]).map(|x| {
                    let cell_lo = x as i32 * ppg_d;
                    let c = if w[d] < 0.0 {
                        bl_d.max(cell_lo)
                    } else {
                        bh_d.min(cell_lo + ppg_d - 1)
                    };
                    let t = w[d] * f64::from(c);
                    first.map_or(t, |a| a + t)
                }));
            }
            let (ub, terms) = (&mut self.ub, &self.terms);
            // Rows along dimension 0 (stride 1): the other dimensions' terms per row.
            let row = &terms[..=hi[0] - lo[0]];
            walk_rows(&lo, &hi, &self.stride, dim, |c0, cur| {
                let mut rest = [0.0; ODO_DIMS];
                for d in 1..dim {
                    rest[d] = terms[off[d] + (cur[d] - lo[d])];
                }
                for (x, &a) in row.iter().enumerate() {
                    let mut v = a;
                    for &t in &rest[1..dim] {
                        v += t;
                    }
                    let u = &mut ub[c0 + x];
                    if v > *u || v.is_nan() {
                        *u = v;
                    }
                }
            });
        }
    }

    /// [`LastIndex::make_bounds`] in two dimensions (the helm's course × speed): the
    /// same terms and sums over a piece's cells without the walk, the cell sizes and
    /// strides held in locals.
    fn make_bounds2(&mut self, boxes: &[i32], weights: &[f64], n: usize) {
        let (p0, p1, s1) = (self.ppg[0], self.ppg[1], self.stride[1]);
        let (ub, terms) = (&mut self.ub[..], &mut self.terms);
        let pieces = boxes.chunks_exact(4).zip(weights.chunks_exact(3));
        for ((b, w), (lo, hi)) in pieces.zip(&self.spans).take(n) {
            // `(w_2 + w_0·c_0) + w_1·c_1`, each corner by its weight's sign.
            let corner = |x: usize, p: i32, (l, h): (i32, i32), w: f64| {
                let cell_lo = x as i32 * p;
                if w < 0.0 {
                    l.max(cell_lo)
                } else {
                    h.min(cell_lo + p - 1)
                }
            };
            terms.clear();
            terms.extend(
                (lo[0]..=hi[0]).map(|x| w[2] + w[0] * f64::from(corner(x, p0, (b[0], b[1]), w[0]))),
            );
            let len = terms.len();
            terms.extend(
                (lo[1]..=hi[1]).map(|y| w[1] * f64::from(corner(y, p1, (b[2], b[3]), w[1]))),
            );
            // Column by column: a piece spans a cell or two along dimension 0 and many
            // along dimension 1 (each cell's value is the same sum either way).
            let (row, col) = terms.split_at(len);
            let c0 = lo[0] + lo[1] * s1;
            for (x, &a) in row.iter().enumerate() {
                let mut c = c0 + x;
                for &t in col {
                    let v = a + t;
                    let u = &mut ub[c];
                    if v > *u || v.is_nan() {
                        *u = v;
                    }
                    c += s1;
                }
            }
        }
    }

    fn make_coord_table(&mut self, pts: &[i32]) {
        self.coords.make(pts, &self.ppg);
    }

    /// Cell coordinate of index `i` in dimension `d`, `None` outside the domain.
    #[inline(always)]
    fn coord(&self, d: usize, i: i32) -> Option<usize> {
        let i = usize::try_from(i).ok()?;
        self.coords.line(d).get(i).map(|&c| c as usize)
    }

    /// Lowest and highest cell coordinates box `b` meets.
    fn cell_span(&self, b: &[i32]) -> Option<([usize; ODO_DIMS], [usize; ODO_DIMS])> {
        let (mut lo, mut hi) = ([0; ODO_DIMS], [0; ODO_DIMS]);
        for d in 0..self.dim {
            lo[d] = self.coord(d, b[2 * d])?;
            hi[d] = self.coord(d, b[2 * d + 1])?;
            if lo[d] > hi[d] {
                return None;
            }
        }
        Some((lo, hi))
    }

    /// The one cell holding all of box `b`, if there is one.
    #[inline(always)]
    pub(super) fn cell_of(&self, b: &[i32]) -> Option<usize> {
        let coord = self.coords.all();
        let mut c = 0;
        for (d, &(at, len, stride)) in self.lines.iter().enumerate().take(self.dim) {
            // A negative index turns huge and fails the range test.
            let (lo, hi) = (b[2 * d] as usize, b[2 * d + 1] as usize);
            if lo >= len || hi >= len {
                return None;
            }
            let k = coord[at + lo];
            if coord[at + hi] != k {
                return None;
            }
            c += k as usize * stride;
        }
        Some(c)
    }

    /// The bound of cell `c` (`-inf`: no piece meets it).
    #[inline]
    pub(super) fn bound(&self, c: usize) -> f64 {
        self.ub[c]
    }

    /// Every cell's bound (see [`LastIndex::bound`]), then the one outside every cell
    /// (see [`LastIndex::set_outside`]).
    #[inline]
    pub(super) fn bounds(&self) -> &[f64] {
        &self.ub
    }

    /// Set the bound after the cells' (see [`LastIndex::bounds`]): the last function's
    /// global bound, the term of a node no cell holds.
    pub(super) fn set_outside(&mut self, v: f64) {
        if let Some(u) = self.ub.last_mut() {
            *u = v;
        }
    }

    /// [`LastIndex::cell_of`] of every one of `n` boxes into `out` ([`NO_CELL`] for
    /// none).
    pub(super) fn cells_of(&self, boxes: &[i32], n: usize, out: &mut Vec<u32>) {
        let bl = 2 * self.dim;
        out.clear();
        out.extend(
            boxes
                .chunks_exact(bl)
                .take(n)
                .map(|b| self.cell_of(b).map_or(NO_CELL, |c| c as u32)),
        );
    }

    /// The pieces meeting cell `c`, in array order.
    #[inline]
    pub(super) fn pieces(&self, c: usize) -> &[u32] {
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }
}

/// The plain bound of cell `cur` (coordinates) for piece `b`, `w` on cells of `ppg`:
/// `maxVal` of the piece clipped to the cell (the build's reference).
#[cfg(test)]
pub(super) fn clip_max_val(b: &[i32], w: &[f64], ppg: &[i32], cur: &[usize]) -> f64 {
    let mut clip = b.to_vec();
    for d in 0..ppg.len() {
        let cell_lo = cur[d] as i32 * ppg[d];
        clip[2 * d] = b[2 * d].max(cell_lo);
        clip[2 * d + 1] = b[2 * d + 1].min(cell_lo + ppg[d] - 1);
    }
    max_val(&clip, w)
}

/// "No cell holds the box", in [`FirstCells`].
pub(super) const NO_CELL: u32 = u32::MAX;

/// The [`LastIndex`] cell of every piece of the first function, which the search
/// bounds one by one at its first level (thousands for a contact's tiling). The cell
/// depends only on the piece's box and the index's cells, which stay the same from one
/// iteration to the next: kept while they do.
#[derive(Debug, Default)]
pub(super) struct FirstCells {
    cells: Vec<u32>,
    /// What `cells` were made for: the first function's slot and its boxes'
    /// generation (see [`Prepared::boxes_gen`](crate::prepared::Prepared)), the
    /// index's cell size and the problem's points.
    key: Option<(usize, u64)>,
    key_ppg: Vec<i32>,
    key_pts: Vec<i32>,
}

impl FirstCells {
    /// The cells of the `n` boxes `boxes` of the first function (slot `fi`, boxes
    /// generation `gen`) in index `ix` (on, over `pts`), made unless kept.
    pub(super) fn refresh(
        &mut self,
        ix: &LastIndex,
        (fi, gen): (usize, u64),
        pts: &[i32],
        boxes: &[i32],
        n: usize,
    ) -> &[u32] {
        let kept = self.key == Some((fi, gen))
            && self.key_ppg == ix.ppg
            && self.key_pts == pts
            && self.cells.len() == n;
        if !kept {
            ix.cells_of(boxes, n, &mut self.cells);
            self.key = Some((fi, gen));
            self.key_ppg.clone_from(&ix.ppg);
            self.key_pts.clear();
            self.key_pts.extend_from_slice(pts);
        }
        &self.cells
    }
}

/// Visit the cells from `lo` to `hi` (any order will do: callers only append per cell).
fn walk(
    lo: &[usize; ODO_DIMS],
    hi: &[usize; ODO_DIMS],
    stride: &[usize],
    dim: usize,
    mut f: impl FnMut(usize),
) {
    let mut c: usize = (0..dim).map(|d| lo[d] * stride[d]).sum();
    if dim == 2 {
        // Two dimensions: rows along dimension 0 (stride 1), no odometer.
        for _ in lo[1]..=hi[1] {
            for x in 0..=hi[0] - lo[0] {
                f(c + x);
            }
            c += stride[1];
        }
        return;
    }
    let mut cur = *lo;
    loop {
        f(c);
        let mut d = 0;
        loop {
            if d == dim {
                return;
            }
            if cur[d] < hi[d] {
                cur[d] += 1;
                c += stride[d];
                break;
            }
            c -= (cur[d] - lo[d]) * stride[d];
            cur[d] = lo[d];
            d += 1;
        }
    }
}

/// [`walk`] by rows along dimension 0 (stride 1): `f` gets the cell number of the row's
/// first cell (coordinate `lo[0]`) and the row's coordinates (dimension 0 left at
/// `lo[0]`).
fn walk_rows(
    lo: &[usize; ODO_DIMS],
    hi: &[usize; ODO_DIMS],
    stride: &[usize],
    dim: usize,
    mut f: impl FnMut(usize, &[usize; ODO_DIMS]),
) {
    let mut cur = *lo;
    let mut c: usize = (0..dim).map(|d| lo[d] * stride[d]).sum();
    loop {
        f(c, &cur);
        let mut d = 1;
        loop {
            if d >= dim {
                return;
            }
            if cur[d] < hi[d] {
                cur[d] += 1;
                c += stride[d];
                break;
            }
            c -= (cur[d] - lo[d]) * stride[d];
            cur[d] = lo[d];
            d += 1;
        }
    }
}
