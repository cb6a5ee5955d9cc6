//! `ivp-solver`: the IvP solver, HelmEngine problem set-up (spec §5) and branch and
//! bound (spec §6), over `ivp`'s domains and functions. It depends on `ivp` alone (and
//! nothing of the helm: no behaviors, no MOOS); the helm engine calls it once per
//! iteration.
//!
//! ```
//! use ivp::{Domain, IvpFunction};
//! use ivp_solver::Solver;
//! let dom = Domain::parse("x:0:10:11").unwrap();
//! let f = IvpFunction::from_pieces(dom.clone(), &[(vec![(0, 10)], vec![1.0, 0.0])]).unwrap();
//! let mut solver = Solver::new();
//! let d = solver.solve(&dom, &[&f]).unwrap().unwrap();
//! assert_eq!(d.indices[0], Some(10));
//! ```
//!
//! All working memory lives in [`Solver`] and is reused, so once a solver has
//! seen a problem of a given size, further solves do not allocate (use
//! [`Solver::solve_into`] to also reuse the [`Decision`]).

// Index loops over dimensions read closest to the spec's formulas.
#![allow(clippy::needless_range_loop)]

use coords::CoordTable;
use ivp::function::max_val;
use ivp::{Domain, IvpError, IvpFunction};
use last_bits::LastBits;
use last_index::LastIndex;
use std::cell::Cell;

mod coords;
mod last_bits;
mod last_index;
mod setup;
#[cfg(test)]
use setup::min_max_wt;

/// The solver's answer, one entry per *helm* domain variable.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Decision {
    /// Decision value (`low + delta*index`), `None` = no decision for that variable.
    pub values: Vec<Option<f64>>,
    /// Decision index, `None` = no decision.
    pub indices: Vec<Option<u32>>,
    /// Objective value of the winning piece combination.
    pub utility: f64,
}

/// One function, normalized, weighted and translated into the problem domain.
#[derive(Debug, Default)]
struct Prepared {
    /// The boxes in the problem domain, unless `borrowed` (the function's own boxes
    /// already are: same dimensions in the same order).
    bounds: Vec<i32>,
    borrowed: bool,
    weights: Vec<f64>,
    n: usize,
    map: Vec<usize>,
    // Grid (spec §2.4).
    single: bool,
    global_ub: f64,
    ppg: Vec<i32>,
    ncells: Vec<i32>,
    stride: Vec<usize>,
    /// Cell coordinate of every index (no division per piece bound).
    coords: CoordTable,
    /// Position in `active` of the first function with the same grid geometry: boxes
    /// cover the same cells of both.
    geom: usize,
    cell_start: Vec<u32>,
    cell_items: Vec<u32>,
    /// Cell bound, `NO_BOUND` for an empty cell.
    cell_ub: Vec<f64>,
    cell_filled: Vec<bool>,
    cursor: Vec<u32>,
    seen: Vec<Cell<u32>>,
    stamp: Cell<u32>,
    /// Largest `|intercept| + Σ |slope_d|·(points_d - 1)` over the pieces: no partial
    /// sum of a value or bound of this function exceeds it (sizes the rounding slack).
    term_scale: f64,
    /// `maxVal` of every piece (scratch of the set-up, for the cell bounds).
    piece_ub: Vec<f64>,
    /// The function's own boxes, dimension map and problem points that `bounds` were
    /// made from (see `setup.rs`).
    src_bounds: Vec<i32>,
    src_map: Vec<usize>,
    src_pts: Vec<i32>,
    /// The cell size the cell lists were made for (from the boxes of `src_*`), empty
    /// for none.
    lists_ppg: Vec<i32>,
}

const NO_BOUND: f64 = -99999.0;

/// The grid cells a box overlaps: per dimension the lowest and highest cell
/// coordinate, and the number of the cell at the highest corner (where the odometer
/// starts).
#[derive(Clone, Copy)]
struct CellRange {
    lo: [usize; ODO_DIMS],
    hi: [usize; ODO_DIMS],
    top: usize,
    one: bool,
}

impl Prepared {
    /// Cell coordinate of index `i` in dimension `d` (`i / ppg`).
    #[inline(always)]
    fn coord(&self, d: usize, i: i32) -> usize {
        let line = self.coords.line(d);
        // Indices are inside the problem domain; anything else divides as before.
        match line.get(i as usize) {
            Some(&c) => c as usize,
            None => (i / self.ppg[d]) as usize,
        }
    }

    /// The cells box `b` overlaps (`dim <= ODO_DIMS`).
    #[inline(always)]
    fn range(&self, b: &[i32], dim: usize) -> CellRange {
        let mut r = CellRange {
            lo: [0; ODO_DIMS],
            hi: [0; ODO_DIMS],
            top: 0,
            one: true,
        };
        for d in 0..dim {
            r.lo[d] = self.coord(d, b[2 * d]);
            r.hi[d] = self.coord(d, b[2 * d + 1]);
            r.top += r.hi[d] * self.stride[d];
            r.one &= r.lo[d] == r.hi[d];
        }
        r
    }

    /// (Re)make the coordinate table when points or cell sizes changed.
    fn make_coord_table(&mut self, pts: &[i32]) {
        self.coords.make(pts, &self.ppg);
    }

    #[inline]
    fn for_each_cell(&self, b: &[i32], dim: usize, f: impl FnMut(usize) -> bool) {
        if dim > ODO_DIMS {
            return for_each_cell_any(&self.ppg, &self.stride, b, dim, f);
        }
        walk_cells(&self.range(b, dim), &self.stride, dim, f)
    }

    /// Cheap bound over the cells of `r` (spec §2.4).
    #[inline]
    fn bound_over(&self, r: &CellRange, dim: usize) -> f64 {
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
    fn cheap_bound(&self, b: &[i32], dim: usize) -> f64 {
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
fn for_each_cell(
    ppg: &[i32],
    stride: &[usize],
    b: &[i32],
    dim: usize,
    f: impl FnMut(usize) -> bool,
) {
    if dim > ODO_DIMS {
        return for_each_cell_any(ppg, stride, b, dim, f);
    }
    let mut r = CellRange {
        lo: [0; ODO_DIMS],
        hi: [0; ODO_DIMS],
        top: 0,
        one: true,
    };
    for d in 0..dim {
        r.lo[d] = (b[2 * d] / ppg[d]) as usize;
        r.hi[d] = (b[2 * d + 1] / ppg[d]) as usize;
        r.top += r.hi[d] * stride[d];
    }
    walk_cells(&r, stride, dim, f)
}

/// The odometer of [`for_each_cell`] over a computed range (`dim <= ODO_DIMS`).
#[inline]
fn walk_cells(r: &CellRange, stride: &[usize], dim: usize, mut f: impl FnMut(usize) -> bool) {
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
const BITS_AFTER: u32 = 3;

/// Dimensions the stack odometer of [`for_each_cell`] handles.
const ODO_DIMS: usize = 4;

/// [`for_each_cell`] for any number of dimensions (same order).
fn for_each_cell_any(
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
fn intersects(a: &[i32], b: &[i32], dim: usize) -> bool {
    (0..dim).all(|d| a[2 * d] <= b[2 * d + 1] && b[2 * d] <= a[2 * d + 1])
}

/// Reusable solver (see the module docs).
#[derive(Debug, Default)]
pub struct Solver {
    funcs: Vec<Prepared>,
    active: Vec<usize>,
    used: Vec<usize>,
    prob_to_helm: Vec<usize>,
    pts: Vec<i32>,
    node_b: Vec<i32>,
    node_w: Vec<f64>,
    best_b: Vec<i32>,
    best_w: Vec<f64>,
    last: LastIndex,
    /// Bit sets over the last function when it has no [`LastIndex`] (see `last_bits.rs`).
    bits: LastBits,
    /// The previous decision point (problem indices), to seed the next search. Any
    /// point of the domain is a valid seed (see [`seed_value`]); a stale one only
    /// prunes less.
    prev: Vec<i32>,
    seed_b: Vec<i32>,
    seed_w: Vec<f64>,
    /// The allocation of each solve's list of box slices, kept empty between solves.
    boxes_buf: Vec<&'static [i32]>,
    /// Last solve: (seeded, searched again unseeded, last bit sets on), for the tests.
    #[cfg(test)]
    stats: (usize, usize, usize),
}

/// An empty list in `v`'s allocation, of any lifetime: the emptied list is collected
/// in place, so the buffer is kept and nothing of the old borrows remains.
fn recycle_slices<'b>(mut v: Vec<&[i32]>) -> Vec<&'b [i32]> {
    v.clear();
    v.into_iter().map(|_| unreachable!("cleared")).collect()
}

/// `acc + Σ_{k >= level} cheapBound(F[k], b)`, accumulated left to right.
///
/// Functions with the same grid geometry share the box's cell range (computed once),
/// and a box inside one cell reads that cell's bound directly.
#[inline]
fn bound_rest(
    funcs: &[Prepared],
    active: &[usize],
    dim: usize,
    level: usize,
    b: &[i32],
    acc: f64,
) -> f64 {
    bound_upto(funcs, active, dim, level, active.len(), b, acc)
}

/// The reference bound [`bound_rest`] and a tighter one: with a [`LastIndex`] cell
/// holding the box, the last function's term (its global bound, a one-cell function)
/// is replaced by the cell's bound. The first is bit for bit [`bound_rest`]: the same
/// sum, the last term added last.
#[inline]
fn bound_pair(
    funcs: &[Prepared],
    active: &[usize],
    dim: usize,
    level: usize,
    b: &[i32],
    acc: f64,
    last: Option<&LastIndex>,
) -> (f64, f64) {
    let m = active.len();
    if let Some(ix) = last {
        if let Some(c) = ix.cell_of(b) {
            let prefix = if level + 1 == m {
                acc
            } else {
                bound_upto(funcs, active, dim, level, m - 1, b, acc)
            };
            return (
                prefix + funcs[active[m - 1]].global_ub,
                prefix + ix.bound(c),
            );
        }
    }
    let r = bound_rest(funcs, active, dim, level, b, acc);
    (r, r)
}

/// `acc + Σ_{level <= k < upto} cheapBound(F[k], b)`, accumulated left to right.
#[inline]
fn bound_upto(
    funcs: &[Prepared],
    active: &[usize],
    dim: usize,
    level: usize,
    upto: usize,
    b: &[i32],
    mut acc: f64,
) -> f64 {
    if dim > ODO_DIMS {
        for &fi in &active[level..upto] {
            acc += funcs[fi].cheap_bound(b, dim);
        }
        return acc;
    }
    let mut range_of = usize::MAX;
    let mut range = CellRange {
        lo: [0; ODO_DIMS],
        hi: [0; ODO_DIMS],
        top: 0,
        one: true,
    };
    for &fi in &active[level..upto] {
        let f = &funcs[fi];
        if f.single {
            acc += f.global_ub;
            continue;
        }
        if f.geom != range_of {
            range = f.range(b, dim);
            range_of = f.geom;
        }
        acc += f.bound_over(&range, dim);
    }
    acc
}

struct Search<'a> {
    funcs: &'a [Prepared],
    /// The boxes of function `fi` (see [`Prepared::bounds`]).
    boxes: &'a [&'a [i32]],
    active: &'a [usize],
    dim: usize,
    node_b: &'a mut [i32],
    node_w: &'a mut [f64],
    best_b: &'a mut [i32],
    best_w: &'a mut [f64],
    /// The incumbent's value once `found`; before that, when `seeded`, the floor
    /// `B` (see [`Search::prune`]).
    best: f64,
    found: bool,
    seeded: bool,
    /// Rounding tolerance: a bound or leaf value is within `tol` of its exact value.
    tol: f64,
    /// Set when a seeded search came too close to its floor to be sure it follows the
    /// reference (see [`Search::prune`]); the caller then searches again unseeded.
    doubt: Cell<bool>,
    last: Option<&'a LastIndex>,
    /// The last function's bit sets when it may use them, made once `scans` reaches
    /// [`BITS_AFTER`] (`bits_ready`).
    bits: Option<&'a mut LastBits>,
    bits_ready: bool,
    scans: u32,
    pts: &'a [i32],
}

impl Search<'_> {
    #[inline]
    fn bounds(&self, level: usize, b: &[i32], acc: f64) -> (f64, f64) {
        bound_pair(self.funcs, self.active, self.dim, level, b, acc, self.last)
    }

    /// Whether to skip a subtree with reference bound `rb` (spec §6.1, computed
    /// exactly as the reference does) and tighter bound `tb` (see `last_index.rs`).
    ///
    /// The answer must be the reference branch and bound's, bit for bit, including
    /// its rare rounding prunes (a bound a few ulps below a leaf under it: the golden
    /// `plugin_constant_depth` depends on one). So:
    ///
    /// * `rb <= best` prunes exactly as the reference does;
    /// * `tb <= best - 2 tol` prunes a subtree whose every leaf is below `best`: the
    ///   reference, exploring it, would take none of them, so skipping it changes no
    ///   incumbent and no later decision;
    /// * seeded (no leaf taken yet): `best` holds the floor `B = S - 16 tol`, `S` the
    ///   value of a leaf holding the previous decision point. The reference's final
    ///   value is at least `S - tol > B`; let `L` be the first leaf it takes above `B`.
    ///   Before `L` the reference takes only leaves at most `B`, and the seeded search
    ///   prunes at least what the reference prunes, taking nothing (a leaf above `B`
    ///   visited by it but not by the reference would sit under a reference prune with
    ///   `rb <= B`, which the seeded search makes too). `L` itself is reached and taken
    ///   unless its value or a bound above it is within `2 tol` of `B` -- flagged as
    ///   `doubt`, for an unseeded rerun. From `L` on both searches hold the same
    ///   incumbent and decide alike.
    #[inline]
    fn prune(&self, rb: f64, tb: f64) -> bool {
        if !(self.found || self.seeded) {
            return false;
        }
        if rb <= self.best {
            if !self.found && rb > self.best - 2.0 * self.tol {
                self.doubt.set(true);
            }
            return true;
        }
        tb <= self.best - 2.0 * self.tol
    }

    /// Whether a leaf of value `v` becomes the incumbent (`v > best`, or the very
    /// first leaf of an unseeded search).
    #[inline]
    fn takes(&self, v: f64) -> bool {
        if self.found || self.seeded {
            if !self.found && v > self.best && v <= self.best + 2.0 * self.tol {
                self.doubt.set(true);
            }
            v > self.best
        } else {
            true
        }
    }

    #[inline]
    fn set_best(&mut self, v: f64) {
        self.best = v;
        self.found = true;
    }

    fn run(&mut self) {
        let (dim, m) = (self.dim, self.active.len());
        let (bl, wl) = (2 * dim, dim + 1);
        let f0 = &self.funcs[self.active[0]];
        let pieces = self.boxes[self.active[0]]
            .chunks_exact(bl)
            .zip(f0.weights.chunks_exact(wl))
            .take(f0.n);
        if m == 1 {
            // The pieces are the leaves: copied only when one becomes the incumbent.
            for (pb, pw) in pieces {
                let mv = max_val(pb, pw);
                if self.takes(mv) {
                    self.set_best(mv);
                    self.best_b.copy_from_slice(pb);
                    self.best_w.copy_from_slice(pw);
                }
            }
            return;
        }
        for (pb, pw) in pieces {
            let mv = max_val(pb, pw);
            let (rb, tb) = self.bounds(1, pb, mv);
            if !self.prune(rb, tb) {
                self.node_b[..bl].copy_from_slice(pb);
                self.node_w[..wl].copy_from_slice(pw);
                self.recurse(1);
            }
        }
    }

    #[inline]
    fn leaf(&mut self, slot: usize, v: f64) {
        if self.takes(v) {
            let (bl, wl) = (2 * self.dim, self.dim + 1);
            self.set_best(v);
            self.best_b
                .copy_from_slice(&self.node_b[slot * bl..(slot + 1) * bl]);
            self.best_w
                .copy_from_slice(&self.node_w[slot * wl..(slot + 1) * wl]);
        }
    }

    /// Fast path for the deepest level with a single-cell grid: leaf values are
    /// computed on the fly with exactly the operations of `maxVal(node ∩ q)`
    /// (summed weights, intercept first, then dimensions in order); the leaf is
    /// only materialized when it becomes the incumbent. A node inside one cell of the
    /// [`LastIndex`] meets only that cell's pieces (array order, as here).
    fn last_level_single(&mut self, level: usize, f: &Prepared, fb: &[i32]) {
        let bl = 2 * self.dim;
        let cell = {
            let node_b = &self.node_b[(level - 1) * bl..level * bl];
            self.last
                .and_then(|ix| ix.cell_of(node_b).map(|c| ix.pieces(c)))
        };
        let wl = self.dim + 1;
        match cell {
            Some(list) => {
                for &q in list {
                    let q = q as usize;
                    let qb = &fb[q * bl..(q + 1) * bl];
                    self.last_leaf(level, qb, &f.weights[q * wl..(q + 1) * wl]);
                }
            }
            None => {
                let mut meet = [0u64; 4];
                if let Some(words) = self.bits_meeting(level, f, fb, &mut meet) {
                    // The pieces meeting the node, in array order.
                    for (w, &word) in meet.iter().enumerate().take(words) {
                        let mut word = word;
                        while word != 0 {
                            let q = w * 64 + word.trailing_zeros() as usize;
                            word &= word - 1;
                            let qb = &fb[q * bl..(q + 1) * bl];
                            self.last_leaf(level, qb, &f.weights[q * wl..(q + 1) * wl]);
                        }
                    }
                    return;
                }
                let pieces = fb.chunks_exact(bl).zip(f.weights.chunks_exact(wl));
                for (qb, qw) in pieces.take(f.n) {
                    self.last_leaf(level, qb, qw);
                }
            }
        }
    }

    /// The pieces of the last function meeting the node at `level` into `meet`, and the
    /// words used, from its bit sets; `None`: scan them all. The sets are made at the
    /// [`BITS_AFTER`]th scan of a solve (fewer scans cost less than making them).
    fn bits_meeting(
        &mut self,
        level: usize,
        f: &Prepared,
        fb: &[i32],
        meet: &mut [u64; 4],
    ) -> Option<usize> {
        if !self.bits_ready {
            let bits = self.bits.as_deref_mut()?;
            self.scans += 1;
            if self.scans < BITS_AFTER {
                return None;
            }
            if !bits.make(fb, f.n, self.pts) {
                self.bits = None;
                return None;
            }
            self.bits_ready = true;
        }
        let bits = self.bits.as_deref()?;
        let bl = 2 * self.dim;
        let node_b = &self.node_b[(level - 1) * bl..level * bl];
        bits.meeting(node_b, meet).then(|| bits.words())
    }

    /// The leaf `node ∩ q` of [`Search::last_level_single`] (`q` = box `qb`, weights
    /// `qw`), if they meet.
    #[inline(always)]
    fn last_leaf(&mut self, level: usize, qb: &[i32], qw: &[f64]) {
        let dim = self.dim;
        let (bl, wl) = (2 * dim, dim + 1);
        let node_b = &self.node_b[(level - 1) * bl..level * bl];
        let node_w = &self.node_w[(level - 1) * wl..level * wl];
        {
            if !intersects(node_b, qb, dim) {
                return;
            }
            let mut acc = node_w[dim] + qw[dim];
            for d in 0..dim {
                let w = node_w[d] + qw[d];
                let c = if w < 0.0 {
                    node_b[2 * d].max(qb[2 * d])
                } else {
                    node_b[2 * d + 1].min(qb[2 * d + 1])
                };
                acc += w * f64::from(c);
            }
            if self.takes(acc) {
                // `set_best`, field by field (the node is borrowed).
                self.best = acc;
                self.found = true;
                for d in 0..dim {
                    self.best_b[2 * d] = node_b[2 * d].max(qb[2 * d]);
                    self.best_b[2 * d + 1] = node_b[2 * d + 1].min(qb[2 * d + 1]);
                }
                for i in 0..wl {
                    self.best_w[i] = node_w[i] + qw[i];
                }
            }
        }
    }

    /// `level` = index of the function to intersect with; node is in slot `level-1`.
    fn recurse(&mut self, level: usize) {
        let dim = self.dim;
        let (bl, wl) = (2 * dim, dim + 1);
        let funcs = self.funcs;
        let f = &funcs[self.active[level]];
        let fb = self.boxes[self.active[level]];
        let last = level + 1 == self.active.len();
        if last && f.single {
            self.last_level_single(level, f, fb);
            return;
        }
        let visit = |s: &mut Self, q: usize| {
            let (nb, cb) = s.node_b.split_at_mut(level * bl);
            let (nw, cw) = s.node_w.split_at_mut(level * wl);
            let node_b = &nb[(level - 1) * bl..];
            let node_w = &nw[(level - 1) * wl..];
            let qb = &fb[q * bl..(q + 1) * bl];
            let qw = &f.weights[q * wl..(q + 1) * wl];
            let child_b = &mut cb[..bl];
            let child_w = &mut cw[..wl];
            for d in 0..dim {
                child_b[2 * d] = node_b[2 * d].max(qb[2 * d]);
                child_b[2 * d + 1] = node_b[2 * d + 1].min(qb[2 * d + 1]);
            }
            for i in 0..wl {
                child_w[i] = node_w[i] + qw[i];
            }
            let mv = max_val(child_b, child_w);
            if last {
                s.leaf(level, mv);
            } else {
                let (rb, tb) = bound_pair(s.funcs, s.active, dim, level + 1, &cb[..bl], mv, s.last);
                if !s.prune(rb, tb) {
                    s.recurse(level + 1);
                }
            }
        };
        if f.single {
            for q in 0..f.n {
                let hit = {
                    let node_b = &self.node_b[(level - 1) * bl..level * bl];
                    intersects(node_b, &fb[q * bl..(q + 1) * bl], dim)
                };
                if hit {
                    visit(self, q);
                }
            }
        } else {
            let stamp = f.stamp.get().wrapping_add(1);
            f.stamp.set(stamp);
            if stamp == 0 {
                for s in &f.seen {
                    s.set(u32::MAX);
                }
            }
            let mut qbox = [0i32; 16];
            let big;
            let node_copy: &[i32] = if bl <= 16 {
                qbox[..bl].copy_from_slice(&self.node_b[(level - 1) * bl..level * bl]);
                &qbox[..bl]
            } else {
                big = self.node_b[(level - 1) * bl..level * bl].to_vec();
                &big
            };
            f.for_each_cell(node_copy, dim, |c| {
                for &q in &f.cell_items[f.cell_start[c] as usize..f.cell_start[c + 1] as usize] {
                    let q = q as usize;
                    if f.seen[q].get() == stamp
                        || !intersects(node_copy, &fb[q * bl..(q + 1) * bl], dim)
                    {
                        continue;
                    }
                    f.seen[q].set(stamp);
                    visit(self, q);
                }
                true
            });
        }
    }
}

impl Solver {
    pub fn new() -> Self {
        Self::default()
    }

    /// HelmEngine procedure (spec §5 steps 2–6, §6). `functions` in problem
    /// order (the helm sorts by behavior name). The inputs are not modified.
    /// `Ok(None)` when there is nothing to solve (no function, or no leaf).
    pub fn solve(
        &mut self,
        helm_domain: &Domain,
        functions: &[&IvpFunction],
    ) -> Result<Option<Decision>, IvpError> {
        let mut d = Decision::default();
        Ok(if self.solve_into(helm_domain, functions, &mut d)? {
            Some(d)
        } else {
            None
        })
    }

    /// As [`Solver::solve`], writing into `out` (reused, no allocation once warm).
    /// Returns whether a decision was found.
    pub fn solve_into(
        &mut self,
        helm_domain: &Domain,
        functions: &[&IvpFunction],
        out: &mut Decision,
    ) -> Result<bool, IvpError> {
        self.used.clear();
        for f in functions {
            for v in f.domain().vars() {
                let i = helm_domain
                    .index_of(&v.name)
                    .ok_or_else(|| IvpError::UnknownVar(v.name.clone()))?;
                if !self.used.contains(&i) {
                    self.used.push(i);
                }
            }
        }
        self.prob_to_helm.clear();
        if self.used.len() == helm_domain.size() {
            self.prob_to_helm.extend(0..helm_domain.size());
        } else {
            self.prob_to_helm.extend_from_slice(&self.used);
        }
        self.run(helm_domain, functions, out)
    }

    /// IvPProblem with an explicit problem domain (every variable of `problem`
    /// is decided, used or not). Values/indices are per `problem` variable.
    pub fn solve_problem(
        &mut self,
        problem: &Domain,
        functions: &[&IvpFunction],
    ) -> Result<Option<Decision>, IvpError> {
        self.prob_to_helm.clear();
        self.prob_to_helm.extend(0..problem.size());
        let mut d = Decision::default();
        Ok(if self.run(problem, functions, &mut d)? {
            Some(d)
        } else {
            None
        })
    }

    fn run(
        &mut self,
        helm: &Domain,
        functions: &[&IvpFunction],
        out: &mut Decision,
    ) -> Result<bool, IvpError> {
        out.values.clear();
        out.values.resize(helm.size(), None);
        out.indices.clear();
        out.indices.resize(helm.size(), None);
        out.utility = 0.0;
        let dim = self.prob_to_helm.len();
        self.pts.clear();
        self.pts
            .extend(self.prob_to_helm.iter().map(|&h| helm.var(h).points as i32));
        if self.funcs.len() < functions.len() {
            self.funcs.resize_with(functions.len(), Prepared::default);
        }
        self.active.clear();
        for (fi, f) in functions.iter().enumerate() {
            if f.pwt() <= 0.0 {
                continue;
            }
            let first = self.active.is_empty();
            self.prepare(fi, f, helm, dim, first)?;
            self.active.push(fi);
        }
        if self.active.is_empty() || dim == 0 {
            return Ok(false);
        }
        for k in 0..self.active.len() {
            let fk = &self.funcs[self.active[k]];
            let first = (0..k)
                .find(|&j| self.funcs[self.active[j]].ppg == fk.ppg)
                .unwrap_or(k);
            self.funcs[self.active[k]].geom = first;
        }
        let m = self.active.len();
        let (bl, wl) = (2 * dim, dim + 1);
        self.node_b.resize(m * bl, 0);
        self.node_w.resize(m * wl, 0.0);
        self.best_b.resize(bl, 0);
        self.best_w.resize(wl, 0.0);
        let mut boxes = recycle_slices(std::mem::take(&mut self.boxes_buf));
        boxes.extend(functions.iter().zip(&self.funcs).map(|(f, p)| {
            if p.borrowed {
                f.bounds()
            } else {
                &p.bounds[..]
            }
        }));
        index_last(&mut self.last, &self.funcs, &self.active, &self.pts, &boxes);
        let fl = self.active[self.active.len() - 1];
        let bits_on = self.active.len() > 1 && !self.last.on && self.funcs[fl].single;
        // Rounding tolerance: a leaf value or a bound is a sum of fewer than
        // `4(m + dim + 2)` rounded operations (builder grids: a few more, once) on
        // terms no larger than `scale`, so within `tol` of its exact value. A
        // non-finite or NaN scale turns the seed and the tighter bound off.
        let scale: f64 = self
            .active
            .iter()
            .map(|&fi| self.funcs[fi].term_scale)
            .sum();
        let tol = scale * f64::EPSILON * 16.0 * (m + dim + 8) as f64;
        let sure = tol.is_finite();
        // One function: its pieces are the leaves, a plain scan is cheaper than a seed.
        let seed = if m > 1 {
            seed_value(
                &self.funcs,
                &self.active,
                &self.pts,
                &self.prev,
                &boxes,
                (&mut self.seed_b, &mut self.seed_w),
            )
        } else {
            None
        };
        let seed = seed.filter(|s| sure && s.is_finite());
        let last = (sure && self.last.on).then_some(&self.last);
        let mut s = Search {
            funcs: &self.funcs,
            boxes: &boxes,
            active: &self.active,
            dim,
            node_b: &mut self.node_b,
            node_w: &mut self.node_w,
            best_b: &mut self.best_b,
            best_w: &mut self.best_w,
            best: seed.map_or(0.0, |s| s - 16.0 * tol),
            found: false,
            seeded: seed.is_some(),
            tol,
            doubt: Cell::new(false),
            last,
            bits: bits_on.then_some(&mut self.bits),
            bits_ready: false,
            scans: 0,
            pts: &self.pts,
        };
        s.run();
        #[cfg(test)]
        let (seeded, bits_on) = (s.seeded, s.bits_ready);
        let rerun = s.seeded && (s.doubt.get() || !s.found);
        #[cfg(test)]
        {
            self.stats = (
                usize::from(seeded),
                usize::from(rerun),
                usize::from(bits_on),
            );
        }
        if rerun {
            // Too close to the floor to be sure (see `Search::prune`): the reference
            // search, unseeded. (`!found` cannot happen: the seed is a leaf's value.)
            s.seeded = false;
            s.found = false;
            s.run();
        }
        let (found, best) = (s.found, s.best);
        self.boxes_buf = recycle_slices(boxes);
        if !found {
            return Ok(false);
        }
        self.prev.clear();
        for (d, &h) in self.prob_to_helm.iter().enumerate() {
            let ix = if self.best_w[d] < 0.0 {
                self.best_b[2 * d]
            } else {
                self.best_b[2 * d + 1]
            };
            self.prev.push(ix);
            let ix = ix.max(0) as u32;
            out.indices[h] = Some(ix);
            out.values[h] = Some(helm.value(h, ix));
        }
        out.utility = best;
        Ok(true)
    }
}

/// Build the [`LastIndex`] when the last function has a one-cell grid and several
/// pieces, on the cell size of the function above it (see `last_index.rs`).
fn index_last(
    last: &mut LastIndex,
    funcs: &[Prepared],
    active: &[usize],
    pts: &[i32],
    boxes: &[&[i32]],
) {
    last.on = false;
    let m = active.len();
    if m < 2 {
        return;
    }
    let (above, fl) = (active[m - 2], active[m - 1]);
    let f = &funcs[fl];
    if !f.single || f.n < 2 || funcs[above].single {
        return;
    }
    last.build(&funcs[above].ppg, pts, boxes[fl], &f.weights, f.n);
}

/// The seed for the search: the value of a leaf holding the previous decision
/// point, computed with exactly the operations the search uses for that leaf
/// (per function in problem order the first piece holding the point; boxes
/// intersected; weights summed left to right; `maxVal`). Any leaf would do, the
/// previous optimum's is usually close to the new one. `None` when the point is
/// not in the domain or some function has no piece there.
fn seed_value(
    funcs: &[Prepared],
    active: &[usize],
    pts: &[i32],
    x: &[i32],
    boxes: &[&[i32]],
    (seed_b, seed_w): (&mut Vec<i32>, &mut Vec<f64>),
) -> Option<f64> {
    let dim = pts.len();
    if x.len() != dim || (0..dim).any(|d| x[d] < 0 || x[d] >= pts[d]) {
        return None;
    }
    let (bl, wl) = (2 * dim, dim + 1);
    seed_b.resize(bl, 0);
    seed_w.resize(wl, 0.0);
    for (k, &fi) in active.iter().enumerate() {
        let f = &funcs[fi];
        let fb = boxes[fi];
        let holds = |q: usize| {
            let b = &fb[q * bl..(q + 1) * bl];
            (0..dim).all(|d| b[2 * d] <= x[d] && x[d] <= b[2 * d + 1])
        };
        // Functions below the first have cell lists: only the point's cell's.
        let q = if k > 0 && !f.single {
            let c: usize = (0..dim).map(|d| f.coord(d, x[d]) * f.stride[d]).sum();
            f.cell_items[f.cell_start[c] as usize..f.cell_start[c + 1] as usize]
                .iter()
                .map(|&q| q as usize)
                .find(|&q| holds(q))
        } else {
            (0..f.n).find(|&q| holds(q))
        }?;
        let (qb, qw) = (&fb[q * bl..(q + 1) * bl], &f.weights[q * wl..(q + 1) * wl]);
        if k == 0 {
            seed_b.copy_from_slice(qb);
            seed_w.copy_from_slice(qw);
        } else {
            for d in 0..dim {
                seed_b[2 * d] = seed_b[2 * d].max(qb[2 * d]);
                seed_b[2 * d + 1] = seed_b[2 * d + 1].min(qb[2 * d + 1]);
            }
            for i in 0..wl {
                seed_w[i] += qw[i];
            }
        }
    }
    Some(max_val(seed_b, seed_w))
}

#[cfg(test)]
mod equivalence_tests {
    // Unit tests only, in a `tests.rs` like every test module.
    mod tests;
}
#[cfg(test)]
mod tests;
