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

use ivp::function::max_val;
use ivp::{Domain, IvpError, IvpFunction};
use last_bits::LastBits;
use last_index::{FirstCells, LastIndex};
use prepared::{Prepared, NO_BOUND};
use search::{Clip, Search, Term};
use std::cell::Cell;

mod clip;
mod coords;
mod first_level;
#[cfg(target_arch = "x86_64")]
mod first_simd;
mod last_bits;
mod last_index;
mod last_level;
mod lone;
mod made_from;
mod nan_scan;
mod prepared;
mod search;
mod separate;
mod setup;
mod view;
mod weigh;
#[cfg(target_arch = "x86_64")]
mod weigh_simd;

pub use nan_scan::any_nan;
pub use view::{CheckedFunction, FunctionView, PieceBuffers};
#[cfg(test)]
use {
    last_index::NO_CELL,
    prepared::{for_each_cell, for_each_cell_any, intersects},
    search::{bound_pair, bound_rest, bound_terms, bound_upto},
    weigh::min_max_wt,
};

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
    /// The index's cell of every piece of the first function (see `last_index.rs`).
    first_cells: FirstCells,
    /// Bit sets over the last function when it has no [`LastIndex`] (see `last_bits.rs`).
    bits: LastBits,
    /// The first level's quick bound over the functions between (see `first_level.rs`).
    mid: first_level::Mid,
    /// The bound terms of independent groups of functions (see `separate.rs`).
    sep: separate::Separate,
    /// The previous decision point (problem indices), to seed the next search. Any
    /// point of the domain is a valid seed (see [`seed_value`]); a stale one only
    /// prunes less.
    prev: Vec<i32>,
    seed_b: Vec<i32>,
    seed_w: Vec<f64>,
    /// The helm domain and problem variables the slots' keys were made in (see
    /// `setup.rs`).
    key_helm: Domain,
    key_prob: Vec<usize>,
    /// Per function of this solve, where its variables' helm indices start in
    /// `var_helm` (found by name once, in `solve_views_into`); empty when not found so.
    var_at: Vec<usize>,
    var_helm: Vec<usize>,
    /// The allocation of each solve's list of box slices, kept empty between solves.
    boxes_buf: Vec<&'static [i32]>,
    /// The allocation of each solve's list of bound terms, kept empty between solves.
    terms_buf: Vec<Term<'static>>,
    /// The allocation of the views the `&[&IvpFunction]` entry points solve.
    views_buf: Vec<FunctionView<'static>>,
    /// Last solve: (seeded, searched again unseeded, last bit sets on, clipped bound
    /// on, last index on), for the tests.
    #[cfg(test)]
    stats: (usize, usize, usize, usize, usize),
    /// Functions kept from an earlier solve, over the solver's life, for the tests.
    #[cfg(test)]
    kept: usize,
    /// Solves with the bound of independent groups on, over the solver's life.
    #[cfg(test)]
    sep_solves: usize,
    /// Bit sets over the last function however few its pieces (tests).
    #[cfg(test)]
    all_bits: bool,
    /// Every problem through the search, none through `lone.rs` (tests).
    #[cfg(test)]
    no_lone: bool,
    /// Solves through `lone.rs`, over the solver's life (tests).
    #[cfg(test)]
    lone_solves: usize,
}

/// An empty list in `v`'s allocation, of any lifetime: the emptied list is collected
/// in place, so the buffer is kept and nothing of the old borrows remains.
fn recycle_slices<'b>(mut v: Vec<&[i32]>) -> Vec<&'b [i32]> {
    v.clear();
    v.into_iter().map(|_| unreachable!("cleared")).collect()
}

/// [`recycle_slices`] for a list of function views.
fn recycle_views<'b>(mut v: Vec<FunctionView<'_>>) -> Vec<FunctionView<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!("cleared")).collect()
}

/// [`recycle_slices`] for the list of bound terms.
fn recycle_terms<'b>(mut v: Vec<Term<'_>>) -> Vec<Term<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!("cleared")).collect()
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
        let mut views = recycle_views(std::mem::take(&mut self.views_buf));
        views.extend(functions.iter().map(|&f| FunctionView::from(f)));
        let found = self.solve_views_into(helm_domain, &views, out);
        self.views_buf = recycle_views(views);
        found
    }

    /// As [`Solver::solve_into`] over functions read in place (e.g. a plugin's
    /// buffers, see [`CheckedFunction`]).
    pub fn solve_views_into(
        &mut self,
        helm_domain: &Domain,
        functions: &[FunctionView<'_>],
        out: &mut Decision,
    ) -> Result<bool, IvpError> {
        self.used.clear();
        self.var_at.clear();
        self.var_helm.clear();
        for f in functions {
            self.var_at.push(self.var_helm.len());
            for v in f.domain().vars() {
                let i = helm_domain
                    .index_of(&v.name)
                    .ok_or_else(|| IvpError::UnknownVar(v.name.clone()))?;
                self.var_helm.push(i);
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
        // The functions' variables are found by name in the set-up.
        self.var_at.clear();
        let mut d = Decision::default();
        let views: Vec<FunctionView<'_>> = functions.iter().map(|&f| f.into()).collect();
        Ok(if self.run(problem, &views, &mut d)? {
            Some(d)
        } else {
            None
        })
    }

    fn run(
        &mut self,
        helm: &Domain,
        functions: &[FunctionView<'_>],
        out: &mut Decision,
    ) -> Result<bool, IvpError> {
        out.values.clear();
        out.values.resize(helm.size(), None);
        out.indices.clear();
        out.indices.resize(helm.size(), None);
        out.utility = 0.0;
        let dim = self.prob_to_helm.len();
        let few = self.few_pieces();
        self.pts.clear();
        self.pts
            .extend(self.prob_to_helm.iter().map(|&h| helm.var(h).points as i32));
        if self.funcs.len() < functions.len() {
            self.funcs.resize_with(functions.len(), Prepared::default);
        }
        if let Some(lone) = self.lone(helm, functions) {
            return self.run_lone(helm, lone, functions, out);
        }
        // Whether the problem is the one the slots' keys were made in: checked when a
        // key is first used or made (see `Solver::same_problem`).
        let mut same_problem = None;
        self.active.clear();
        for (fi, f) in functions.iter().enumerate() {
            if f.pwt() <= 0.0 {
                continue;
            }
            let first = self.active.is_empty();
            self.prepare(fi, f, helm, dim, first, &mut same_problem)?;
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
        let mut terms = recycle_terms(std::mem::take(&mut self.terms_buf));
        terms.extend(self.active.iter().map(|&fi| {
            let f = &self.funcs[fi];
            Term {
                grid: (!f.single).then_some(f),
                ub: f.global_ub,
                geom: f.geom,
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
        // The functions from `singles_from` on are all one cell (their bounds are
        // their global ones).
        let singles_from = (0..m)
            .rev()
            .find(|&k| !self.funcs[self.active[k]].single)
            .map_or(0, |k| k + 1);
        // The last function's clipped bound, from the first level whose nodes may be
        // narrower than the domain in one of its dimensions (a function above fixes
        // one of them), if that is two or more levels above it and all below are one
        // cell.
        // (Dimensions past 31 are left out: the bound is valid whatever the mask.)
        let dims = |fi: usize| {
            let bit = |d: usize| 1u32.checked_shl(d as u32).unwrap_or(0);
            self.funcs[fi].map.iter().fold(0, |a, &d| a | bit(d))
        };
        let clip_from = (m >= 3 && sure && last.is_none() && singles_from < m)
            .then(|| {
                let mut above = 0;
                (1..m).find(|&k| {
                    above |= dims(self.active[k - 1]);
                    above & dims(fl) != 0
                })
            })
            .flatten()
            .map(|from| from.max(singles_from))
            .filter(|&from| from + 1 < m);
        let clip = clip_from.map(|from| {
            let f = &self.funcs[fl];
            Clip {
                boxes: boxes[fl],
                weights: &f.weights,
                ubs: &f.piece_ub,
                n: f.n,
                dims: dims(fl),
                from,
            }
        });
        let f0 = self.active[0];
        let first_cells = last.map(|ix| {
            let key = (f0, self.funcs[f0].boxes_gen);
            let n = self.funcs[f0].n;
            self.first_cells.refresh(ix, key, &self.pts, boxes[f0], n)
        });
        let mid = last.and_then(|_| {
            self.mid
                .refresh(&self.funcs, &self.active, &self.pts, boxes[f0])
        });
        let sep = self
            .sep
            .refresh(&self.funcs, &self.active, &boxes, &self.pts);
        #[cfg(test)]
        {
            self.sep_solves += usize::from(sep.is_some());
        }
        let mut s = Search {
            sep,
            funcs: &self.funcs,
            boxes: &boxes,
            active: &self.active,
            terms: &terms,
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
            first_cells,
            mid,
            clip,
            singles_from,
            last_ub: self.funcs[fl].global_ub,
            bits: bits_on.then_some(&mut self.bits),
            bits_ready: false,
            few,
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
                usize::from(s.clip.is_some()),
                usize::from(s.last.is_some()) + usize::from(s.mid.is_some()),
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
        self.terms_buf = recycle_terms(terms);
        if !found {
            return Ok(false);
        }
        let leaf = (&self.best_b[..], &self.best_w[..]);
        decide_at(&self.prob_to_helm, &mut self.prev, helm, leaf, out);
        out.utility = best;
        Ok(true)
    }
}

/// The decision in the winning piece (`bounds`, `weights`, in problem order): each
/// variable at the edge its weight points to (the low one for a negative weight, else
/// the high one), into `out` at its helm index and kept in `prev` (the next solve's seed).
#[inline(always)]
fn decide_at(
    prob_to_helm: &[usize],
    prev: &mut Vec<i32>,
    helm: &Domain,
    (bounds, weights): (&[i32], &[f64]),
    out: &mut Decision,
) {
    prev.clear();
    for (d, &h) in prob_to_helm.iter().enumerate() {
        let ix = if weights[d] < 0.0 {
            bounds[2 * d]
        } else {
            bounds[2 * d + 1]
        };
        prev.push(ix);
        let ix = ix.max(0) as u32;
        out.indices[h] = Some(ix);
        out.values[h] = Some(helm.value(h, ix));
    }
}

impl Solver {
    /// [`search::FEW_PIECES`], 0 when a test asks for bit sets however few the pieces.
    fn few_pieces(&self) -> usize {
        #[cfg(test)]
        if self.all_bits {
            return 0;
        }
        search::FEW_PIECES
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
    if last.on {
        last.set_outside(f.global_ub);
    }
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
    seed: (&mut Vec<i32>, &mut Vec<f64>),
) -> Option<f64> {
    // The helm's dimensions made constants: the point tests unrolled.
    match pts.len() {
        1 => seed_value_dim::<1>(funcs, active, pts, x, boxes, seed),
        2 => seed_value_dim::<2>(funcs, active, pts, x, boxes, seed),
        3 => seed_value_dim::<3>(funcs, active, pts, x, boxes, seed),
        _ => seed_value_dim::<0>(funcs, active, pts, x, boxes, seed),
    }
}

/// [`seed_value`] with `D == pts.len()` (`D == 0`: any dimension).
fn seed_value_dim<const D: usize>(
    funcs: &[Prepared],
    active: &[usize],
    pts: &[i32],
    x: &[i32],
    boxes: &[&[i32]],
    (seed_b, seed_w): (&mut Vec<i32>, &mut Vec<f64>),
) -> Option<f64> {
    let dim = if D == 0 { pts.len() } else { D };
    if x.len() != dim || (0..dim).any(|d| x[d] < 0 || x[d] >= pts[d]) {
        return None;
    }
    let (bl, wl) = (2 * dim, dim + 1);
    seed_b.resize(bl, 0);
    seed_w.resize(wl, 0.0);
    for (k, &fi) in active.iter().enumerate() {
        let f = &funcs[fi];
        let fb = boxes[fi];
        let x = &x[..dim];
        let holds = |q: usize| {
            let b = &fb[q * bl..(q + 1) * bl];
            (0..dim).all(|d| b[2 * d] <= x[d] && x[d] <= b[2 * d + 1])
        };
        // Functions below the first have cell lists, a large first one may have them
        // (see `Solver::prepare_fresh`): only the point's cell's.
        let q = if !f.single && (k > 0 || f.lists_ppg == f.ppg) {
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
