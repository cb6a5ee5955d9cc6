//! The branch and bound (spec §6): the cheap bounds of a box over the functions not
//! yet fixed, and the depth-first search over the functions' pieces.

pub(crate) use crate::clip::Clip;
use crate::last_bits::LastBits;
use crate::last_index::{LastIndex, NO_CELL};
use crate::prepared::{intersects, CellRange, Prepared, ODO_DIMS};
use ivp::function::max_val;
use std::cell::Cell;

/// `acc + Σ_{k >= level} cheapBound(F[k], b)`, accumulated left to right.
///
/// Functions with the same grid geometry share the box's cell range (computed once),
/// and a box inside one cell reads that cell's bound directly.
#[inline]
pub(crate) fn bound_rest(
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
/// sum, the last term added last. ([`Search::skip`] computes them lazily; this is its
/// reference.)
#[cfg(test)]
pub(crate) fn bound_pair(
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
pub(crate) fn bound_upto(
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
    let mut range = CellRange::NONE;
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

/// One active function as the search's bounds read it: its global bound when it is
/// one cell, else its cells (and the position of its grid geometry, see
/// [`Prepared::geom`]). Kept in active order, side by side.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Term<'a> {
    pub(crate) grid: Option<&'a Prepared>,
    pub(crate) ub: f64,
    pub(crate) geom: usize,
}

/// [`bound_upto`] over the terms of the functions `level..upto` (`dim <= ODO_DIMS`):
/// the same terms added in the same order.
#[inline]
pub(crate) fn bound_terms(terms: &[Term], dim: usize, b: &[i32], mut acc: f64) -> f64 {
    let mut range_of = usize::MAX;
    let mut range = CellRange::NONE;
    for t in terms {
        let Some(f) = t.grid else {
            acc += t.ub;
            continue;
        };
        if t.geom != range_of {
            range = f.range(b, dim);
            range_of = t.geom;
        }
        acc += f.bound_over(&range, dim);
    }
    acc
}

/// Last functions of at most this many pieces are scanned whole at the last level
/// (when their `maxVal`s cut), without bit sets (see [`Search::last_level_dim`]).
pub(crate) const FEW_PIECES: usize = 16;

pub(crate) struct Search<'a> {
    pub(crate) funcs: &'a [Prepared],
    /// The boxes of function `fi` (see [`Prepared::bounds`]).
    pub(crate) boxes: &'a [&'a [i32]],
    pub(crate) active: &'a [usize],
    /// The active functions' bound terms (see [`Term`]).
    pub(crate) terms: &'a [Term<'a>],
    pub(crate) dim: usize,
    pub(crate) node_b: &'a mut [i32],
    pub(crate) node_w: &'a mut [f64],
    pub(crate) best_b: &'a mut [i32],
    pub(crate) best_w: &'a mut [f64],
    /// The incumbent's value once `found`; before that, when `seeded`, the floor
    /// `B` (see [`Search::prune`]).
    pub(crate) best: f64,
    pub(crate) found: bool,
    pub(crate) seeded: bool,
    /// Rounding tolerance: a bound or leaf value is within `tol` of its exact value.
    pub(crate) tol: f64,
    /// Set when a seeded search came too close to its floor to be sure it follows the
    /// reference (see [`Search::prune`]); the caller then searches again unseeded.
    pub(crate) doubt: Cell<bool>,
    pub(crate) last: Option<&'a LastIndex>,
    /// Without `last`: the last function's clipped bound, for nodes two or more levels
    /// above it when the functions from there on are all one cell.
    pub(crate) clip: Option<Clip<'a>>,
    /// The first level from which every function is one cell (`active.len()`: none).
    pub(crate) singles_from: usize,
    /// With `last`: the index's cell of every piece of the first function
    /// ([`NO_CELL`] for none), so that its pieces are bounded without looking it up.
    pub(crate) first_cells: Option<&'a [u32]>,
    /// With `last` and functions between the first and the last: the first pieces'
    /// middle cells and the cells' sums (see `first_level.rs`).
    pub(crate) mid: Option<(&'a [u32], &'a [f64])>,
    /// The last function's global bound (its term when `last` is on).
    pub(crate) last_ub: f64,
    /// The last function's bit sets when it may use them, made once `scans` reaches
    /// [`BITS_AFTER`](crate::prepared::BITS_AFTER) (`bits_ready`).
    pub(crate) bits: Option<&'a mut LastBits>,
    pub(crate) bits_ready: bool,
    /// [`FEW_PIECES`] (0 in tests of the bit sets).
    pub(crate) few: usize,
    pub(crate) scans: u32,
    pub(crate) pts: &'a [i32],
    /// Per level, the terms of the functions from there on with independent groups
    /// counted by their own maximum, NaN for none (see `separate.rs`).
    pub(crate) sep: Option<&'a [f64]>,
}

impl Search<'_> {
    /// [`Search::prune`] of the node `b` at `level` (functions `level..` not yet
    /// fixed) worth `acc`, with its bounds [`bound_pair`] computed only as far as
    /// the answer needs them: none before the first leaf of an unseeded search
    /// (nothing is pruned then), and the tighter bound only when the reference bound
    /// does not prune. The bounds computed are [`bound_pair`]'s, with the same
    /// operations in the same order.
    #[inline]
    pub(crate) fn skip(&self, level: usize, b: &[i32], acc: f64) -> bool {
        if !(self.found || self.seeded) {
            return false;
        }
        let (m, dim) = (self.active.len(), self.dim);
        let Some(ix) = self.last else {
            if level >= self.singles_from {
                return self.skip_singles(level, b, acc);
            }
            let r = if dim <= ODO_DIMS {
                bound_terms(&self.terms[level..m], dim, b, acc)
            } else {
                bound_rest(self.funcs, self.active, dim, level, b, acc)
            };
            return self.prune(r, r);
        };
        self.skip_indexed(level, b, acc, ix, || ix.cell_of(b))
    }

    /// Whether [`Search::skip`] at `level` reduces, once a leaf is found, to the
    /// reference bound of one-cell functions: no index, no clipped bound (or the last
    /// function's level, where [`Search::skip_singles`] does not clip), the
    /// functions `level..` all one cell (see [`Search::skip_found_singles`]).
    #[inline(always)]
    fn singles_at(&self, level: usize) -> bool {
        let unclipped = self.clip.is_none() || level + 1 >= self.active.len();
        self.last.is_none() && unclipped && level >= self.singles_from
    }

    /// [`Search::skip`] at a `level` where [`Search::singles_at`] holds, once `found`,
    /// inlined into the search's loops: the same sum as [`Search::skip_singles`], the
    /// same answer (`prune(rb, rb)` is `rb <= best` once found: `best - 2 tol` is not
    /// above `best`, and nothing raises `doubt`).
    #[inline(always)]
    fn skip_found_singles(&self, level: usize, acc: f64) -> bool {
        let m = self.active.len();
        let mut prefix = acc;
        for t in &self.terms[level..m - 1] {
            prefix += t.ub;
        }
        prefix + self.last_ub <= self.best || self.sep_prunes(level, acc)
    }

    /// Whether the bound of `separate.rs` prunes the node at `level` worth `acc` (a
    /// tighter bound: `prune(rb, tb)` once `rb` does not prune).
    #[inline(always)]
    fn sep_prunes(&self, level: usize, acc: f64) -> bool {
        self.sep
            .is_some_and(|r| acc + r[level] <= self.best - 2.0 * self.tol)
    }

    /// [`Search::skip`] without the index when the functions `level..` are all one
    /// cell: their terms are their global bounds, added in order as [`bound_terms`]
    /// adds them, the last one last; the tighter bound is the [`Clip`] one, when on.
    #[inline(always)]
    fn skip_singles(&self, level: usize, b: &[i32], acc: f64) -> bool {
        let m = self.active.len();
        let mut prefix = acc;
        for t in &self.terms[level..m - 1] {
            prefix += t.ub;
        }
        let rb = prefix + self.last_ub;
        if rb <= self.best {
            return self.prune(rb, rb);
        }
        if self.sep_prunes(level, acc) {
            return self.prune(rb, f64::NEG_INFINITY);
        }
        match &self.clip {
            // Next to the last function its leaves cost about what this bound does.
            // (`prune(rb, tb)` with `rb > best` is `tb <= best - 2 tol`.)
            Some(clip) if clip.from <= level && level + 1 < m && clip.narrows(b, self.pts) => {
                clip.within(b, prefix, self.best - 2.0 * self.tol, self.dim)
            }
            _ => self.prune(rb, rb),
        }
    }

    /// [`Search::skip`] with the index on (`found || seeded`), `cell` giving the
    /// index's cell holding `b` (if any) when it is needed.
    #[inline(always)]
    pub(crate) fn skip_indexed(
        &self,
        level: usize,
        b: &[i32],
        acc: f64,
        ix: &LastIndex,
        cell: impl FnOnce() -> Option<usize>,
    ) -> bool {
        let (m, dim) = (self.active.len(), self.dim);
        // The last function is one cell (the index is on, so `dim <= ODO_DIMS`): its
        // term is its global bound, added last; the same sum whether or not a cell
        // holds `b`.
        let prefix = if level + 1 == m {
            acc
        } else {
            bound_terms(&self.terms[level..m - 1], dim, b, acc)
        };
        let rb = prefix + self.last_ub;
        if rb <= self.best {
            // Pruned whatever the tighter bound.
            return self.prune(rb, rb);
        }
        let tb = match cell() {
            Some(c) => prefix + ix.bound(c),
            None => rb,
        };
        self.prune(rb, tb)
    }

    /// [`Search::skip`] of piece `q` (box `b`, value `acc`) of the first function,
    /// its index cell read from `first_cells` (the one [`LastIndex::cell_of`] gives).
    #[inline(always)]
    pub(crate) fn skip_first(&self, q: usize, b: &[i32], acc: f64) -> bool {
        let (Some(ix), Some(cells)) = (self.last, self.first_cells) else {
            return self.skip(1, b, acc);
        };
        if !(self.found || self.seeded) {
            return false;
        }
        self.skip_indexed(1, b, acc, ix, || {
            let c = cells[q];
            (c != NO_CELL).then_some(c as usize)
        })
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
    pub(crate) fn prune(&self, rb: f64, tb: f64) -> bool {
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
    pub(crate) fn takes(&self, v: f64) -> bool {
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
    pub(crate) fn set_best(&mut self, v: f64) {
        self.best = v;
        self.found = true;
    }

    pub(crate) fn run(&mut self) {
        let (dim, m) = (self.dim, self.active.len());
        let (bl, wl) = (2 * dim, dim + 1);
        let f0 = &self.funcs[self.active[0]];
        let pieces = self.boxes[self.active[0]]
            .chunks_exact(bl)
            .zip(f0.weights.chunks_exact(wl))
            .take(f0.n);
        // The set-up made every piece's `maxVal` (`piece_ub`, the same operations).
        let mvs = &f0.piece_ub[..];
        let known = mvs.len() == f0.n;
        if m > 1 && known {
            if let (Some(ix), Some(cells)) = (self.last, self.first_cells) {
                return self.run_indexed(ix, cells, mvs);
            }
        }
        let mv_of = |q: usize, pb: &[i32], pw: &[f64]| {
            if known {
                mvs[q]
            } else {
                max_val(pb, pw)
            }
        };
        if m == 1 {
            // The pieces are the leaves (as many as the zip holds): with their
            // `maxVal`s known only those read, the incumbent's copied once, at the end.
            let (f0b, mut at) = (self.boxes[self.active[0]], None);
            for q in 0..pieces.len() {
                let mv = match known {
                    true => mvs[q],
                    false => max_val(&f0b[q * bl..][..bl], &f0.weights[q * wl..][..wl]),
                };
                if self.takes(mv) {
                    self.set_best(mv);
                    at = Some(q);
                }
            }
            if let Some(q) = at {
                self.best_b.copy_from_slice(&f0b[q * bl..(q + 1) * bl]);
                self.best_w
                    .copy_from_slice(&f0.weights[q * wl..(q + 1) * wl]);
            }
            return;
        }
        let singles = self.singles_at(1);
        // Without the index, the functions below all one cell: `skip`'s own path
        // (`skip_singles`, the clipped bound's), inlined here.
        let direct = self.last.is_none() && self.singles_from <= 1;
        // The second function the last and one cell: its leaves read the piece in place.
        let two = m == 2 && self.funcs[self.active[1]].single;
        for (q, (pb, pw)) in pieces.enumerate() {
            let mv = mv_of(q, pb, pw);
            let skip = if singles && self.found {
                self.skip_found_singles(1, mv)
            } else if direct {
                (self.found || self.seeded) && self.skip_singles(1, pb, mv)
            } else {
                self.skip_first(q, pb, mv)
            };
            if !skip {
                self.descend(pb, pw, mv, two);
            }
        }
    }

    /// Below the first function's piece `pb`/`pw` (its best value `mv`): read in place
    /// by [`Search::last_of_two`] when the second function is the last one (`two`), else
    /// copied into the node for the levels below.
    #[inline(always)]
    pub(crate) fn descend(&mut self, pb: &[i32], pw: &[f64], mv: f64, two: bool) {
        if two {
            self.last_of_two(pb, pw, mv);
        } else {
            self.node_b[..pb.len()].copy_from_slice(pb);
            self.node_w[..pw.len()].copy_from_slice(pw);
            self.recurse(1, mv);
        }
    }

    #[inline]
    pub(crate) fn leaf(&mut self, slot: usize, v: f64) {
        if self.takes(v) {
            let (bl, wl) = (2 * self.dim, self.dim + 1);
            self.set_best(v);
            self.best_b
                .copy_from_slice(&self.node_b[slot * bl..(slot + 1) * bl]);
            self.best_w
                .copy_from_slice(&self.node_w[slot * wl..(slot + 1) * wl]);
        }
    }

    /// `level` = index of the function to intersect with; node is in slot `level-1`,
    /// `mv` its `maxVal`.
    pub(crate) fn recurse(&mut self, level: usize, mv: f64) {
        // The helm's dimensions made constants: the per-piece loops here and the
        // per-leaf ones of `last_level_dim` unrolled, the slices' lengths known.
        match self.dim {
            1 => self.recurse_dim::<1>(level, mv),
            2 => self.recurse_dim::<2>(level, mv),
            3 => self.recurse_dim::<3>(level, mv),
            _ => self.recurse_dim::<0>(level, mv),
        }
    }

    /// [`Search::recurse`] with `D == self.dim` (`D == 0`: any dimension).
    fn recurse_dim<const D: usize>(&mut self, level: usize, node_mv: f64) {
        let dim = if D == 0 { self.dim } else { D };
        let bl = 2 * dim;
        let funcs = self.funcs;
        let f = &funcs[self.active[level]];
        let fb = self.boxes[self.active[level]];
        let last = level + 1 == self.active.len();
        if last && f.single {
            // The node held apart from `self` while the leaves update the incumbent.
            let (all_b, all_w) = (
                std::mem::take(&mut self.node_b),
                std::mem::take(&mut self.node_w),
            );
            let nb = &all_b[(level - 1) * bl..level * bl];
            let nw = &all_w[(level - 1) * (dim + 1)..level * (dim + 1)];
            self.last_level_dim(nb, nw, f, fb, dim, node_mv);
            (self.node_b, self.node_w) = (all_b, all_w);
            return;
        }
        let singles = self.singles_at(level + 1);
        let visit = |s: &mut Self, q: usize| {
            // The sizes made again here, constants when `D` is (captured, they are read
            // from the closure's state: the loops below were not unrolled).
            let dim = if D == 0 { s.dim } else { D };
            let (bl, wl) = (2 * dim, dim + 1);
            let (nb, cb) = s.node_b.split_at_mut(level * bl);
            let (nw, cw) = s.node_w.split_at_mut(level * wl);
            let node_b = &nb[(level - 1) * bl..];
            let node_w = &nw[(level - 1) * wl..];
            let (node_b, node_w) = (&node_b[..bl], &node_w[..wl]);
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
                let skip = if singles && s.found {
                    s.skip_found_singles(level + 1, mv)
                } else {
                    s.skip(level + 1, &s.node_b[level * bl..(level + 1) * bl], mv)
                };
                if !skip {
                    s.recurse_dim::<D>(level + 1, mv);
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
