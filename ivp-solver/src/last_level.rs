//! The last level of the search when the last function is one cell: its leaves made
//! on the fly, from the node's box and weights wherever they are held (the search's
//! node slots, or the first function's piece itself when the second function is the
//! last, see [`Search::last_of_two`]).

use crate::prepared::{intersects, Prepared, BITS_AFTER};
use crate::search::Search;

impl Search<'_> {
    /// The last level under piece `q` of the first function (box `pb`, weights `pw`,
    /// `maxVal` `mv`) when the second function is the last and one cell: what
    /// [`Search::recurse`] at level 1 does with the piece copied into the node's slot,
    /// here read in place (no copies, no dispatch per level).
    // Kept out of `run_indexed`, whose loops it would crowd.
    #[inline(never)]
    pub(crate) fn last_of_two(&mut self, pb: &[i32], pw: &[f64], mv: f64) {
        let (funcs, boxes) = (self.funcs, self.boxes);
        let (f, fb) = (&funcs[self.active[1]], boxes[self.active[1]]);
        // The helm's dimensions made constants, as in `Search::recurse`.
        match self.dim {
            1 => self.last_level_dim(pb, pw, f, fb, 1, mv),
            2 => self.last_level_dim(pb, pw, f, fb, 2, mv),
            3 => self.last_level_dim(pb, pw, f, fb, 3, mv),
            dim => self.last_level_dim(pb, pw, f, fb, dim, mv),
        }
    }

    /// Fast path for the deepest level with a single-cell grid (`dim == self.dim`, a
    /// constant in [`Search::recurse_dim`]): leaf values are computed on the fly with
    /// exactly the operations of `maxVal(node ∩ q)` (summed weights, intercept first,
    /// then dimensions in order); the leaf is only materialized when it becomes the
    /// incumbent. A node inside one cell of the [`LastIndex`] meets only that cell's
    /// pieces (array order, as here).
    ///
    /// Once a leaf is found or the search is seeded, a piece `q` with
    /// `mv + maxVal(q) <= best - 2 tol` (`mv` the node's `maxVal`) is passed over: that
    /// sum bounds its leaf `node ∩ q`, so the leaf is at most `best` (see
    /// [`Search::prune`]): never taken and raising no `doubt`, the same answer.
    #[inline(always)]
    pub(crate) fn last_level_dim(
        &mut self,
        nb: &[i32],
        nw: &[f64],
        f: &Prepared,
        fb: &[i32],
        dim: usize,
        mv: f64,
    ) {
        let (bl, wl) = (2 * dim, dim + 1);
        let (nb, nw) = (&nb[..bl], &nw[..wl]);
        let cell = self
            .last
            .and_then(|ix| ix.cell_of(nb).map(|c| ix.pieces(c)));
        // The pieces' `maxVal`s when the set-up made them (a NaN `mv` passes all).
        let ubs = &f.piece_ub[..];
        let (ubs, mv) = if ubs.len() == f.n && (self.found || self.seeded) {
            (ubs, mv)
        } else {
            (&[][..], f64::NAN)
        };
        let mut meet = [0u64; 4];
        let words = match cell {
            Some(_) => None,
            // A few pieces are passed over by their `maxVal` for less than the sets cost.
            None if f.n <= self.few && !ubs.is_empty() => None,
            None => self.bits_meeting(nb, f, fb, &mut meet),
        };
        let weights = &f.weights;
        let cut = |s: &Self, q: usize| ubs.get(q).is_some_and(|&u| mv + u <= s.best - 2.0 * s.tol);
        match (cell, words) {
            // (The index's cell bound already pruned the node when no piece of the cell
            // could beat the incumbent: the cut would cost more than it saves.)
            (Some(list), _) => {
                for &q in list {
                    let q = q as usize;
                    // Most of a cell's pieces miss the node: tested before their
                    // weights are sliced.
                    let qb = &fb[q * bl..(q + 1) * bl];
                    if !intersects(nb, qb, dim) {
                        continue;
                    }
                    let qw = &weights[q * wl..(q + 1) * wl];
                    self.last_leaf(nb, nw, qb, qw, dim);
                }
            }
            (None, Some(words)) => {
                // The pieces meeting the node, in array order.
                for (w, &word) in meet.iter().enumerate().take(words) {
                    let mut word = word;
                    while word != 0 {
                        let q = w * 64 + word.trailing_zeros() as usize;
                        word &= word - 1;
                        if cut(self, q) {
                            continue;
                        }
                        let (qb, qw) = (&fb[q * bl..(q + 1) * bl], &weights[q * wl..(q + 1) * wl]);
                        self.last_leaf(nb, nw, qb, qw, dim);
                    }
                }
            }
            (None, None) => {
                let n = f.n.min(fb.len() / bl).min(weights.len() / wl);
                // Most pieces are cut: they are passed over in a tight loop, `cut`'s
                // test with `best - 2 tol` held in a local (made again after a leaf,
                // which may raise `best`).
                let m = n.min(ubs.len());
                let mut lim = self.best - 2.0 * self.tol;
                let mut q = 0;
                while q < n {
                    while q < m && mv + ubs[q] <= lim {
                        q += 1;
                    }
                    if q == n {
                        break;
                    }
                    let qb = &fb[q * bl..(q + 1) * bl];
                    if intersects(nb, qb, dim) {
                        let qw = &weights[q * wl..(q + 1) * wl];
                        self.last_leaf(nb, nw, qb, qw, dim);
                        lim = self.best - 2.0 * self.tol;
                    }
                    q += 1;
                }
            }
        }
    }

    /// The pieces of the last function meeting the node `node_b` into `meet`, and the
    /// words used, from its bit sets; `None`: scan them all. The sets are made at the
    /// [`BITS_AFTER`]th scan of a solve (fewer scans cost less than making them).
    pub(crate) fn bits_meeting(
        &mut self,
        node_b: &[i32],
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
        bits.meeting(node_b, meet).then(|| bits.words())
    }

    /// The leaf `node ∩ q` of [`Search::last_level_dim`] (the node's box and weights
    /// `node_b`, `node_w`; `q`'s `qb`, `qw`; `dim == self.dim`), which meet (the
    /// callers test it, or know it from the bit sets, which give exactly the pieces
    /// meeting the node).
    #[inline(always)]
    pub(crate) fn last_leaf(
        &mut self,
        node_b: &[i32],
        node_w: &[f64],
        qb: &[i32],
        qw: &[f64],
        dim: usize,
    ) {
        let (bl, wl) = (2 * dim, dim + 1);
        let (node_b, node_w, qb, qw) = (&node_b[..bl], &node_w[..wl], &qb[..bl], &qw[..wl]);
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
            self.set_best(acc);
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
