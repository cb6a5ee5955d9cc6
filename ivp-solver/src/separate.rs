//! A tighter bound from functions independent of the rest: the helm's depth
//! functions (GoToDepth, ConstantDepth, all over depth alone) below a waypoint's
//! course × speed.
//!
//! Split the active functions into groups that share no problem dimension with one
//! another (connected by shared dimensions). While a group of two or more functions is
//! wholly below a node (none of its functions fixed), the node's box is the whole
//! domain in the group's dimensions and its slopes there are 0, so every leaf below is
//! `node ∩ (pieces of the others) ∩ g`, `g` a leaf of the group alone, and its value is
//! the sum of the two parts'. Its exact value is at most the reference bound with the
//! group's cheap bounds replaced by `max_G`, the largest leaf value of the group alone.
//! Computed, that sum is within the search's slack of its exact value (the same kind of
//! sum as any bound), so it serves as a tighter bound (see `Search::prune`): a subtree
//! it puts at most `best - 2 tol` holds no leaf the reference would take.
//!
//! Only made when every function from a level on is one cell (their terms are their
//! global bounds, constant per level) and a group's leaves are few (`MAX_VISITS`).

use crate::prepared::{intersects, Prepared};
use ivp::function::max_val;

/// Most nodes visited making one group's `max_G`.
const MAX_VISITS: usize = 4096;

#[derive(Debug, Default)]
pub(crate) struct Separate {
    /// Per level `k`: the sum of the terms of the functions `k..` with every group
    /// wholly below `k` counted by its `max_G`; NaN where no such group (or not all
    /// one cell).
    rest: Vec<f64>,
    /// Per group: (its dimensions, its functions as a bit set of positions).
    groups: Vec<(u32, u64)>,
    /// Per group: `max_G` (`None`: too many leaves, or NaN).
    maxes: Vec<Option<f64>>,
    /// Scratch of [`Separate::group_max`]: its nodes and its functions' slots.
    node_b: Vec<i32>,
    node_w: Vec<f64>,
    order: Vec<usize>,
    /// What `maxes` were made from: the problem's points, then per group its
    /// functions' (slot, generation) (see [`Prepared::gen`]): kept functions (the
    /// depth ones, mostly) keep their groups' maxima.
    key: Vec<u64>,
    new_key: Vec<u64>,
}

impl Separate {
    /// The bound terms per level (see the module docs) of the active functions, or
    /// `None` when no level gains from them.
    pub(crate) fn refresh(
        &mut self,
        funcs: &[Prepared],
        active: &[usize],
        boxes: &[&[i32]],
        pts: &[i32],
    ) -> Option<&[f64]> {
        let (m, dim) = (active.len(), pts.len());
        if !(3..=64).contains(&m) || dim > 32 {
            return None;
        }
        self.groups.clear();
        for (k, &fi) in active.iter().enumerate() {
            let mut mask = funcs[fi].map.iter().fold(0u32, |a, &d| a | (1 << d));
            let mut members = 1u64 << k;
            // Merge every group sharing a dimension with this function.
            let mut i = 0;
            while i < self.groups.len() {
                if self.groups[i].0 & mask != 0 {
                    let (gm, gs) = self.groups.swap_remove(i);
                    mask |= gm;
                    members |= gs;
                } else {
                    i += 1;
                }
            }
            self.groups.push((mask, members));
        }
        // Groups of two or more functions, none of them the first (it is fixed at
        // every level).
        self.groups
            .retain(|&(_, s)| s.count_ones() >= 2 && s & 1 == 0);
        if self.groups.is_empty() {
            return None;
        }
        self.new_key.clear();
        self.new_key.extend(pts.iter().map(|&p| p as u64));
        for &(_, members) in &self.groups {
            self.new_key.push(u64::MAX);
            for (k, &fi) in active.iter().enumerate() {
                if members & (1 << k) != 0 {
                    self.new_key.extend([fi as u64, funcs[fi].gen]);
                }
            }
        }
        if self.new_key != self.key || self.maxes.len() != self.groups.len() {
            self.maxes.clear();
            for gi in 0..self.groups.len() {
                let members = self.groups[gi].1;
                let v = self.group_max(funcs, active, boxes, pts, members);
                self.maxes.push(v.filter(|v| !v.is_nan()));
            }
            std::mem::swap(&mut self.key, &mut self.new_key);
        }
        self.rest.clear();
        self.rest.resize(m + 1, f64::NAN);
        let mut any = false;
        for k in 1..m {
            if active[k..].iter().any(|&fi| !funcs[fi].single) {
                continue;
            }
            // Groups wholly below level k, with their `max_G`.
            let mut below = 0u64;
            let mut sum = 0.0;
            for (&(_, s), &v) in self.groups.iter().zip(&self.maxes) {
                if let (Some(v), true) = (v, s.trailing_zeros() as usize >= k) {
                    below |= s;
                    sum += v;
                }
            }
            if below == 0 {
                continue;
            }
            for j in k..m {
                if below & (1 << j) == 0 {
                    sum += funcs[active[j]].global_ub;
                }
            }
            self.rest[k] = sum;
            any = true;
        }
        any.then_some(&self.rest[..])
    }

    /// The largest leaf value of the functions at positions `members` alone (leaves
    /// in the problem's dimensions: the others whole with slope 0).
    fn group_max(
        &mut self,
        funcs: &[Prepared],
        active: &[usize],
        boxes: &[&[i32]],
        pts: &[i32],
        members: u64,
    ) -> Option<f64> {
        let dim = pts.len();
        let (bl, wl) = (2 * dim, dim + 1);
        let depth = members.count_ones() as usize;
        self.node_b.clear();
        self.node_b.resize((depth + 1) * bl, 0);
        self.node_w.clear();
        self.node_w.resize((depth + 1) * wl, 0.0);
        for d in 0..dim {
            self.node_b[2 * d + 1] = pts[d] - 1;
        }
        self.order.clear();
        self.order.extend(
            (0..active.len())
                .filter(|&k| members & (1 << k) != 0)
                .map(|k| active[k]),
        );
        let mut visits = 0;
        let mut best = f64::NEG_INFINITY;
        let mut walk = Walk {
            funcs,
            boxes,
            order: &self.order,
            dim,
            node_b: &mut self.node_b,
            node_w: &mut self.node_w,
            visits: &mut visits,
            best: &mut best,
        };
        walk.go(0).then_some(best)
    }
}

/// The enumeration of [`Separate::group_max`].
struct Walk<'a> {
    funcs: &'a [Prepared],
    boxes: &'a [&'a [i32]],
    /// The group's function slots in problem order.
    order: &'a [usize],
    dim: usize,
    node_b: &'a mut [i32],
    node_w: &'a mut [f64],
    visits: &'a mut usize,
    best: &'a mut f64,
}

impl Walk<'_> {
    /// Every leaf below the node in slot `depth` into `best`; false when the visits
    /// run out or a value is NaN.
    fn go(&mut self, depth: usize) -> bool {
        let (bl, wl) = (2 * self.dim, self.dim + 1);
        if depth == self.order.len() {
            let v = max_val(
                &self.node_b[depth * bl..(depth + 1) * bl],
                &self.node_w[depth * wl..(depth + 1) * wl],
            );
            if v.is_nan() {
                return false;
            }
            *self.best = self.best.max(v);
            return true;
        }
        let fi = self.order[depth];
        let f = &self.funcs[fi];
        let fb = self.boxes[fi];
        for q in 0..f.n {
            *self.visits += 1;
            if *self.visits > MAX_VISITS {
                return false;
            }
            let qb = &fb[q * bl..(q + 1) * bl];
            let (nb, cb) = self.node_b.split_at_mut((depth + 1) * bl);
            let nb = &nb[depth * bl..];
            if !intersects(nb, qb, self.dim) {
                continue;
            }
            for d in 0..self.dim {
                cb[2 * d] = nb[2 * d].max(qb[2 * d]);
                cb[2 * d + 1] = nb[2 * d + 1].min(qb[2 * d + 1]);
            }
            let (nw, cw) = self.node_w.split_at_mut((depth + 1) * wl);
            let nw = &nw[depth * wl..];
            let qw = &f.weights[q * wl..(q + 1) * wl];
            for i in 0..wl {
                cw[i] = nw[i] + qw[i];
            }
            if !self.go(depth + 1) {
                return false;
            }
        }
        true
    }
}
