//! The IvP solver: HelmEngine problem set-up (spec §5) and branch and bound (spec §6).
//!
//! All working memory lives in [`Solver`] and is reused, so once a solver has
//! seen a problem of a given size, further solves do not allocate (use
//! [`Solver::solve_into`] to also reuse the [`Decision`]).

use crate::domain::Domain;
use crate::error::IvpError;
use crate::function::{max_val, IvpFunction};
use std::cell::Cell;

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
    bounds: Vec<i32>,
    weights: Vec<f64>,
    n: usize,
    map: Vec<usize>,
    // Grid (spec §2.4).
    single: bool,
    global_ub: f64,
    ppg: Vec<i32>,
    ncells: Vec<i32>,
    stride: Vec<usize>,
    cell_start: Vec<u32>,
    cell_items: Vec<u32>,
    cell_ub: Vec<f64>,
    cell_filled: Vec<bool>,
    /// `maxVal` of each piece (the global bound and the cell bounds both need it).
    maxv: Vec<f64>,
    cursor: Vec<u32>,
    seen: Vec<Cell<u32>>,
    stamp: Cell<u32>,
}

const NO_BOUND: f64 = -99999.0;

impl Prepared {
    #[inline]
    fn for_each_cell(&self, b: &[i32], dim: usize, f: impl FnMut(usize) -> bool) {
        for_each_cell(&self.ppg, &self.stride, b, dim, f)
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
#[inline]
fn for_each_cell(
    ppg: &[i32],
    stride: &[usize],
    b: &[i32],
    dim: usize,
    mut f: impl FnMut(usize) -> bool,
) {
    if dim > ODO_DIMS {
        return for_each_cell_any(ppg, stride, b, dim, f);
    }
    let mut lo = [0usize; ODO_DIMS];
    let mut hi = [0usize; ODO_DIMS];
    let mut cur = [0usize; ODO_DIMS];
    let mut idx = 0usize;
    for d in 0..dim {
        lo[d] = (b[2 * d] / ppg[d]) as usize;
        hi[d] = (b[2 * d + 1] / ppg[d]) as usize;
        cur[d] = hi[d];
        idx += hi[d] * stride[d];
    }
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

/// Dimensions the stack odometer of [`for_each_cell`] handles.
const ODO_DIMS: usize = 8;

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
}

/// `acc + Σ_{k >= level} cheapBound(F[k], b)`, accumulated left to right.
#[inline]
fn bound_rest(
    funcs: &[Prepared],
    active: &[usize],
    dim: usize,
    level: usize,
    b: &[i32],
    mut acc: f64,
) -> f64 {
    for &fi in &active[level..] {
        acc += funcs[fi].cheap_bound(b, dim);
    }
    acc
}

struct Search<'a> {
    funcs: &'a [Prepared],
    active: &'a [usize],
    dim: usize,
    node_b: &'a mut [i32],
    node_w: &'a mut [f64],
    best_b: &'a mut [i32],
    best_w: &'a mut [f64],
    best: f64,
    found: bool,
}

impl Search<'_> {
    #[inline]
    fn bound_rest(&self, level: usize, b: &[i32], acc: f64) -> f64 {
        bound_rest(self.funcs, self.active, self.dim, level, b, acc)
    }

    fn run(&mut self) {
        let (dim, m) = (self.dim, self.active.len());
        let (bl, wl) = (2 * dim, dim + 1);
        let f0 = &self.funcs[self.active[0]];
        for k in 0..f0.n {
            let pb = &f0.bounds[k * bl..(k + 1) * bl];
            let pw = &f0.weights[k * wl..(k + 1) * wl];
            self.node_b[..bl].copy_from_slice(pb);
            self.node_w[..wl].copy_from_slice(pw);
            let mv = max_val(pb, pw);
            if m == 1 {
                self.leaf(0, mv);
                continue;
            }
            let bound = self.bound_rest(1, pb, mv);
            if !self.found || bound > self.best {
                self.recurse(1);
            }
        }
    }

    #[inline]
    fn leaf(&mut self, slot: usize, v: f64) {
        if !self.found || v > self.best {
            let (bl, wl) = (2 * self.dim, self.dim + 1);
            self.best = v;
            self.found = true;
            self.best_b
                .copy_from_slice(&self.node_b[slot * bl..(slot + 1) * bl]);
            self.best_w
                .copy_from_slice(&self.node_w[slot * wl..(slot + 1) * wl]);
        }
    }

    /// Fast path for the deepest level with a single-cell grid: leaf values are
    /// computed on the fly with exactly the operations of `maxVal(node ∩ q)`
    /// (summed weights, intercept first, then dimensions in order); the leaf is
    /// only materialized when it becomes the incumbent.
    fn last_level_single(&mut self, level: usize, f: &Prepared) {
        let dim = self.dim;
        let (bl, wl) = (2 * dim, dim + 1);
        let node_b = &self.node_b[(level - 1) * bl..level * bl];
        let node_w = &self.node_w[(level - 1) * wl..level * wl];
        for (qb, qw) in f
            .bounds
            .chunks_exact(bl)
            .zip(f.weights.chunks_exact(wl))
            .take(f.n)
        {
            if !intersects(node_b, qb, dim) {
                continue;
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
            if !self.found || acc > self.best {
                self.found = true;
                self.best = acc;
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
        let last = level + 1 == self.active.len();
        if last && f.single {
            self.last_level_single(level, f);
            return;
        }
        let visit = |s: &mut Self, q: usize| {
            let (nb, cb) = s.node_b.split_at_mut(level * bl);
            let (nw, cw) = s.node_w.split_at_mut(level * wl);
            let node_b = &nb[(level - 1) * bl..];
            let node_w = &nw[(level - 1) * wl..];
            let qb = &f.bounds[q * bl..(q + 1) * bl];
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
                let bound = bound_rest(s.funcs, s.active, dim, level + 1, &cb[..bl], mv);
                if !s.found || bound > s.best {
                    s.recurse(level + 1);
                }
            }
        };
        if f.single {
            for q in 0..f.n {
                let hit = {
                    let node_b = &self.node_b[(level - 1) * bl..level * bl];
                    intersects(node_b, &f.bounds[q * bl..(q + 1) * bl], dim)
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
                        || !intersects(node_copy, &f.bounds[q * bl..(q + 1) * bl], dim)
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
            self.prepare(fi, f, helm, dim)?;
            self.active.push(fi);
        }
        if self.active.is_empty() || dim == 0 {
            return Ok(false);
        }
        let m = self.active.len();
        let (bl, wl) = (2 * dim, dim + 1);
        self.node_b.resize(m * bl, 0);
        self.node_w.resize(m * wl, 0.0);
        self.best_b.resize(bl, 0);
        self.best_w.resize(wl, 0.0);
        let mut s = Search {
            funcs: &self.funcs,
            active: &self.active,
            dim,
            node_b: &mut self.node_b,
            node_w: &mut self.node_w,
            best_b: &mut self.best_b,
            best_w: &mut self.best_w,
            best: 0.0,
            found: false,
        };
        s.run();
        let (found, best) = (s.found, s.best);
        if !found {
            return Ok(false);
        }
        for (d, &h) in self.prob_to_helm.iter().enumerate() {
            let ix = if self.best_w[d] < 0.0 {
                self.best_b[2 * d]
            } else {
                self.best_b[2 * d + 1]
            };
            let ix = ix.max(0) as u32;
            out.indices[h] = Some(ix);
            out.values[h] = Some(helm.value(h, ix));
        }
        out.utility = best;
        Ok(true)
    }

    /// addOF (normalize if range > 100, apply pwt), alignment and grid build.
    fn prepare(
        &mut self,
        fi: usize,
        f: &IvpFunction,
        helm: &Domain,
        dim: usize,
    ) -> Result<(), IvpError> {
        let p = &mut self.funcs[fi];
        let od = f.dim();
        p.map.clear();
        for v in f.domain().vars() {
            let pos = self
                .prob_to_helm
                .iter()
                .position(|&h| helm.var(h).name == v.name);
            p.map
                .push(pos.ok_or_else(|| IvpError::UnknownVar(v.name.clone()))?);
        }
        let (mn, mx) = (f.min_wt(), f.max_wt());
        let norm = mx - mn > 100.0;
        let r = mx - mn;
        let (shift, scale) = (0.0 - mn, 100.0 / r);
        let pwt = f.pwt();
        let n = f.piece_count();
        p.n = n;
        let (bl, wl) = (2 * dim, dim + 1);
        p.bounds.clear();
        p.weights.clear();
        p.bounds.resize(n * bl, 0);
        p.weights.resize(n * wl, 0.0);
        let (fb, fw) = (f.bounds(), f.weights());
        for k in 0..n {
            let b = &mut p.bounds[k * bl..(k + 1) * bl];
            let w = &mut p.weights[k * wl..(k + 1) * wl];
            for d in 0..dim {
                b[2 * d] = 0;
                b[2 * d + 1] = self.pts[d] - 1;
                w[d] = 0.0;
            }
            let src = &fw[k * (od + 1)..(k + 1) * (od + 1)];
            let tf = |x: f64, is_int: bool| {
                let mut x = x;
                if norm {
                    if is_int {
                        x += shift;
                    }
                    x *= scale;
                }
                x * pwt
            };
            w[dim] = tf(src[od], true);
            for (d, &t) in p.map.iter().enumerate() {
                b[2 * t] = fb[k * 2 * od + 2 * d];
                b[2 * t + 1] = fb[k * 2 * od + 2 * d + 1];
                w[t] = tf(src[d], false);
            }
        }
        // Grid.
        p.ppg.clear();
        p.ncells.clear();
        p.stride.clear();
        let gel = f.gelbox();
        let mut total = 1usize;
        for d in 0..dim {
            let g = p
                .map
                .iter()
                .position(|&t| t == d)
                .map_or(self.pts[d] - 1, |od_i| gel[od_i] as i32);
            let ppg = g.saturating_add(1).max(2).min(self.pts[d]).max(1);
            let nc = (self.pts[d] + ppg - 1) / ppg;
            p.ppg.push(ppg);
            p.ncells.push(nc);
            p.stride.push(total);
            total *= nc as usize;
        }
        p.single = total == 1;
        p.global_ub = NO_BOUND;
        p.maxv.clear();
        for k in 0..n {
            let v = max_val(
                &p.bounds[k * bl..(k + 1) * bl],
                &p.weights[k * wl..(k + 1) * wl],
            );
            p.maxv.push(v);
            if k == 0 || v > p.global_ub {
                p.global_ub = v;
            }
        }
        if !p.single {
            build_cells(p, dim, total);
        }
        // A builder-made grid is kept (its bounds transformed like the weights)
        // when no translation is needed; otherwise the grid is rebuilt above.
        let same = od == dim
            && p.map.iter().enumerate().all(|(d, &t)| d == t)
            && (0..dim).all(|d| *f.domain().var(d) == *helm.var(self.prob_to_helm[d]));
        let g = f.grid_bounds();
        if same && g.len() == total {
            let tg = |x: f64| {
                let mut x = x;
                if norm {
                    x = (x + shift) * scale;
                }
                x * pwt
            };
            if p.single {
                let v = tg(g[0]);
                p.global_ub = if v == f64::NEG_INFINITY { NO_BOUND } else { v };
            } else {
                for (c, &x) in g.iter().enumerate() {
                    let v = tg(x);
                    p.cell_filled[c] = v != f64::NEG_INFINITY && !v.is_nan();
                    p.cell_ub[c] = if p.cell_filled[c] { v } else { NO_BOUND };
                }
            }
        }
        Ok(())
    }
}

fn build_cells(p: &mut Prepared, dim: usize, total: usize) {
    let bl = 2 * dim;
    let (ppg, stride) = (&p.ppg, &p.stride);
    p.cell_start.clear();
    p.cell_start.resize(total + 1, 0);
    p.cell_ub.clear();
    p.cell_ub.resize(total, NO_BOUND);
    p.cell_filled.clear();
    p.cell_filled.resize(total, false);
    for k in 0..p.n {
        for_each_cell(ppg, stride, &p.bounds[k * bl..(k + 1) * bl], dim, |c| {
            p.cell_start[c + 1] += 1;
            true
        });
    }
    for c in 0..total {
        p.cell_start[c + 1] += p.cell_start[c];
    }
    p.cell_items.clear();
    p.cell_items.resize(p.cell_start[total] as usize, 0);
    p.cursor.clear();
    p.cursor.extend_from_slice(&p.cell_start[..total]);
    // Pieces in array order inside every cell; cell bound = max piece maxVal.
    for k in 0..p.n {
        let b = &p.bounds[k * bl..(k + 1) * bl];
        let v = p.maxv[k];
        for_each_cell(ppg, stride, b, dim, |c| {
            p.cell_items[p.cursor[c] as usize] = k as u32;
            p.cursor[c] += 1;
            if !p.cell_filled[c] || v > p.cell_ub[c] {
                p.cell_ub[c] = v;
            }
            p.cell_filled[c] = true;
            true
        });
    }
    if p.seen.len() < p.n {
        p.seen.resize_with(p.n, || Cell::new(0));
    }
    for s in &p.seen {
        s.set(0);
    }
    p.stamp.set(0);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stack odometer visits exactly the cells, in exactly the order, of the
    /// reference's divide-per-cell count (the order fixes the search's tie-breaks).
    #[test]
    fn odometer_matches_the_divide_per_cell_order() {
        let cases: [(&[i32], &[i32]); 4] = [
            (&[9, 6], &[0, 359, 0, 40]),
            (&[9, 6], &[17, 19, 5, 12]),
            (&[4, 3, 2], &[3, 9, 0, 0, 1, 5]),
            (&[2], &[7, 7]),
        ];
        for (ppg, b) in cases {
            let mut stride = vec![];
            let mut total = 1usize;
            for &p in ppg {
                stride.push(total);
                total *= (400 / p as usize) + 1;
            }
            let dim = ppg.len();
            let (mut fast, mut slow) = (vec![], vec![]);
            for_each_cell(ppg, &stride, b, dim, |c| {
                fast.push(c);
                true
            });
            for_each_cell_any(ppg, &stride, b, dim, |c| {
                slow.push(c);
                true
            });
            assert!(!fast.is_empty());
            assert_eq!(fast, slow, "{ppg:?} {b:?}");
            let mut first = vec![];
            for_each_cell(ppg, &stride, b, dim, |c| {
                first.push(c);
                false
            });
            assert_eq!(first, slow[..1]);
        }
    }
}
