//! Problem set-up (spec §5 steps 4-5): each function normalized, weighted and
//! translated into the problem domain, with its grid of cell lists and cell bounds.

use super::*;
use crate::coords::same_small;
use crate::prepared::{walk_cells, ODO_DIMS};
use crate::weigh::{min_max_wt_with, weigh, Weighing};

impl Solver {
    /// addOF (normalize if range > 100, apply pwt), alignment and grid build.
    ///
    /// One pass over the pieces for the extremes (normalization), then one that makes
    /// every piece's weights, its term scale and its `maxVal`. The problem-order boxes
    /// and the cell lists are kept from the last solve when they were made from the
    /// same boxes the same way (the contacts' tilings are the same every iteration):
    /// only the weights and the cell bounds are new.
    ///
    /// A function the slot was prepared from last time, unchanged (same domain, boxes,
    /// weight bits, gel box, grid bits, pwt bits and level) in the same problem (see
    /// [`Solver::same_problem`], `same` its answer in this solve once asked), is kept
    /// as it is: prepared again it would be the same (the helm's depth functions, a
    /// waypoint while ownship holds still).
    pub(super) fn prepare(
        &mut self,
        fi: usize,
        f: &FunctionView<'_>,
        helm: &Domain,
        dim: usize,
        first: bool,
        same: &mut Option<bool>,
    ) -> Result<(), IvpError> {
        if self.funcs[fi].key.on
            && self.same_problem(helm, same)
            && self.funcs[fi]
                .key
                .matches(&self.funcs[fi].src_bounds, f, first)
        {
            self.funcs[fi].key.misses = 0;
            #[cfg(test)]
            {
                self.kept += 1;
            }
            return Ok(());
        }
        let key = &mut self.funcs[fi].key;
        key.on = false;
        key.misses = key.misses.saturating_add(1);
        self.prepare_fresh::<false>(fi, f, helm, dim, first)?;
        // Large functions (the contacts' tilings) change every iteration: keying them
        // would copy and compare thousands of weights for nothing. A slot whose
        // function keeps changing (a moving waypoint) is keyed now and then only.
        let misses = self.funcs[fi].key.misses;
        if keys_now(misses, f.piece_count()) {
            self.same_problem(helm, same);
            self.funcs[fi].key.set(f, first);
        }
        Ok(())
    }

    /// Whether the problem (helm domain, `prob_to_helm`) is the one the slots' keys
    /// were made in, asked once per solve (`same`). When it is not, every key is
    /// dropped and this problem recorded: keys made from here on are this problem's.
    pub(super) fn same_problem(&mut self, helm: &Domain, same: &mut Option<bool>) -> bool {
        if let Some(s) = *same {
            return s;
        }
        let s = self.key_helm == *helm && self.key_prob == self.prob_to_helm;
        if !s {
            for p in &mut self.funcs {
                p.key.on = false;
            }
            self.key_helm.clone_from(helm);
            self.key_prob.clone_from(&self.prob_to_helm);
        }
        *same = Some(s);
        s
    }

    /// [`Solver::prepare`] from scratch (but for the kept boxes and cell lists).
    ///
    /// `LONE`: for the lone function of `lone.rs` (`first`), only its boxes, weights and
    /// pieces' `maxVal`s, made as here for any first function; its grid is left as it
    /// was, and its key off, so the slot is prepared afresh before anything reads it.
    pub(super) fn prepare_fresh<const LONE: bool>(
        &mut self,
        fi: usize,
        f: &FunctionView<'_>,
        helm: &Domain,
        dim: usize,
        first: bool,
    ) -> Result<(), IvpError> {
        let p = &mut self.funcs[fi];
        p.gen = p.gen.wrapping_add(1);
        let od = f.dim();
        // The variables' helm indices when `solve_views_into` found them by name: a
        // variable's problem dimension is where its index is (the same one as found by
        // name: the indices are the first of each name, the only ones `prob_to_helm`
        // holds of it), without comparing names again.
        let helm_of = self
            .var_at
            .get(fi)
            .and_then(|&a| self.var_helm.get(a..a + od));
        p.map.clear();
        for (i, v) in f.domain().vars().iter().enumerate() {
            let pos = match helm_of {
                Some(h) => self.prob_to_helm.iter().position(|&x| x == h[i]),
                None => self
                    .prob_to_helm
                    .iter()
                    .position(|&h| helm.var(h).name == v.name),
            };
            p.map
                .push(pos.ok_or_else(|| IvpError::UnknownVar(v.name.clone()))?);
        }
        let pwt = f.pwt();
        let n = f.piece_count();
        p.n = n;
        let wl = dim + 1;
        let (fb, fw) = (f.bounds(), f.weights());
        let identity = od == dim && p.map.iter().enumerate().all(|(d, &t)| d == t);
        p.borrowed = identity;
        let boxes_gen = p.boxes_gen;
        translate_boxes(p, fb, &self.pts);
        let boxes_kept = p.boxes_gen == boxes_gen;
        let boxes: &[i32] = if identity { fb } else { &p.bounds };
        let corners = p.corners.of(boxes, (od, dim, &p.map), p.boxes_gen);
        let swapped = p.map.first() == Some(&1);
        let (mn, mx) = min_max_wt_with(f, corners.map(|c| (c, swapped)));
        let norm = mx - mn > 100.0;
        let r = mx - mn;
        let (shift, scale) = (0.0 - mn, 100.0 / r);
        // Grid (its shape depends on the boxes' domain only). The lone function's is
        // not read (see `LONE`).
        let mut total = 1usize;
        let mut keep_grid = false;
        let g = f.grid_bounds();
        if !LONE {
            p.ppg.clear();
            p.ncells.clear();
            p.stride.clear();
            let gel = f.gelbox();
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
            // A builder-made grid is kept (its bounds transformed like the weights)
            // when no translation is needed; otherwise the bounds come from the pieces.
            // The first function's pieces are enumerated in array order and never
            // bounded (bounds start at level 1): it needs neither.
            // (With the helm indices, `identity` already says the names are the same.)
            let same = identity
                && (0..dim).all(|d| {
                    let (a, b) = (f.domain().var(d), helm.var(self.prob_to_helm[d]));
                    a.points == b.points
                        && a.low == b.low
                        && a.high == b.high
                        && (helm_of.is_some() || a.name == b.name)
                });
            keep_grid = same && g.len() == total;
        }
        // The first function's `maxVal`s are its first-level node values (see
        // `Search::run`).
        let piece_bounds = first || !keep_grid;
        // Weights: slope x -> (x*scale)*pwt, intercept x -> ((x+shift)*scale)*pwt when
        // normalizing, x*pwt otherwise; dimensions the function lacks get slope 0.
        // With them each piece's term scale and, if needed, its `maxVal`.
        // Every weight of every piece is written below but for the slopes of dimensions
        // the function lacks: only then are the old ones cleared.
        if od < dim {
            p.weights.clear();
        }
        p.weights.resize(n * wl, 0.0);
        p.weights.truncate(n * wl);
        let wg = Weighing {
            map: &p.map,
            identity,
            norm,
            shift,
            scale,
            pwt,
            pts: &self.pts,
        };
        let most = weigh(
            &wg,
            fw,
            od,
            &mut p.weights,
            (piece_bounds.then_some(boxes), corners),
            &mut p.piece_ub,
        );
        p.term_scale = most;
        if LONE {
            return Ok(());
        }
        if first {
            // Its cell size is still known (`ppg`), for the geometry sharing and the
            // last index. A large tiling whose boxes stay gets its cell lists too (on
            // the second solve with the same boxes, kept while they stay): the seed
            // looks the previous decision up there instead of scanning every piece.
            if !p.single && n >= SEED_LISTS_MIN && (boxes_kept || p.lists_ppg == p.ppg) {
                p.make_coord_table(&self.pts);
                if p.lists_ppg != p.ppg {
                    self.make_lists(fi, identity.then_some(fb), dim, total);
                }
            }
            return Ok(());
        }
        let tg = |x: f64| {
            let mut x = x;
            if norm {
                x = (x + shift) * scale;
            }
            x * pwt
        };
        if keep_grid && p.single {
            let v = tg(g[0]);
            p.global_ub = if v == f64::NEG_INFINITY { NO_BOUND } else { v };
        } else if p.single {
            p.global_ub = NO_BOUND;
            for (k, &v) in p.piece_ub.iter().enumerate() {
                if k == 0 || v > p.global_ub {
                    p.global_ub = v;
                }
            }
        }
        if p.single {
            return Ok(());
        }
        p.make_coord_table(&self.pts);
        if p.lists_ppg != p.ppg {
            self.make_lists(fi, identity.then_some(fb), dim, total);
        }
        let p = &mut self.funcs[fi];
        if keep_grid {
            p.cell_ub.clear();
            p.cell_ub.resize(total, NO_BOUND);
            p.cell_filled.clear();
            p.cell_filled.resize(total, false);
            for (c, &x) in g.iter().enumerate() {
                let v = tg(x);
                p.cell_filled[c] = v != f64::NEG_INFINITY && !v.is_nan();
                p.cell_ub[c] = if p.cell_filled[c] { v } else { NO_BOUND };
            }
        } else {
            cell_bounds(p, total);
        }
        Ok(())
    }

    /// The cell lists of function `fi` (boxes `own` when borrowed, else its
    /// translated ones): copied from an earlier function with the same boxes and
    /// cells (the contacts' uniform tilings, translated alike), else built.
    fn make_lists(&mut self, fi: usize, own: Option<&[i32]>, dim: usize, total: usize) {
        let twin = if own.is_some() {
            None
        } else {
            let me = &self.funcs[fi];
            self.active.iter().skip(1).copied().find(|&j| {
                let q = &self.funcs[j];
                !q.borrowed && !q.single && q.ppg == me.ppg && q.bounds == me.bounds
            })
        };
        let (p, twin) = match twin {
            // `fi` is not active yet, so `j != fi`.
            Some(j) if j < fi => {
                let (a, b) = self.funcs.split_at_mut(fi);
                (&mut b[0], Some(&a[j]))
            }
            Some(j) => {
                let (a, b) = self.funcs.split_at_mut(j);
                (&mut a[fi], Some(&b[0]))
            }
            None => (&mut self.funcs[fi], None),
        };
        if let Some(t) = twin {
            p.cell_start.clone_from(&t.cell_start);
            p.cell_items.clone_from(&t.cell_items);
        } else {
            let translated = std::mem::take(&mut p.bounds);
            build_lists(p, own.unwrap_or(&translated), dim, total);
            p.bounds = translated;
        }
        p.lists_ppg.clone_from(&p.ppg);
        if p.seen.len() < p.n {
            p.seen.resize_with(p.n, || Cell::new(0));
        }
        for s in &p.seen {
            s.set(0);
        }
        p.stamp.set(0);
    }
}

/// The problem-order boxes of `p` from the function's boxes `fb` (`p.map` and the
/// problem's points `pts` set), unless made from the same boxes the same way last
/// time: then they, and the cell lists made from them, are kept.
#[inline(always)]
fn translate_boxes(p: &mut Prepared, fb: &[i32], pts: &[i32]) {
    if same_small(&p.src_map, &p.map) && same_small(&p.src_pts, pts) && p.src_bounds == fb {
        return;
    }
    remake_boxes(p, fb, pts);
}

/// [`translate_boxes`] when they are new: kept out of line, the set-up's common path
/// keeps its registers.
#[inline(never)]
fn remake_boxes(p: &mut Prepared, fb: &[i32], pts: &[i32]) {
    p.boxes_gen = p.boxes_gen.wrapping_add(1);
    p.src_map.clone_from(&p.map);
    p.src_pts.clear();
    p.src_pts.extend_from_slice(pts);
    p.src_bounds.clear();
    p.src_bounds.extend_from_slice(fb);
    p.lists_ppg.clear();
    p.bounds.clear();
    if p.borrowed {
        return;
    }
    let (dim, od) = (pts.len(), p.map.len());
    p.bounds.resize(p.n * 2 * dim, 0);
    // The helm's shapes with the dimensions constants (boxes as `[lo, hi]` pairs, the
    // map's indices checked once per box): the same boxes as the loop for any.
    let (out, fb, map) = (&mut p.bounds[..], fb, &p.map[..]);
    if dim == 2 && matches!(map, [1, 0]) {
        // Two dimensions the other way round (a function over speed × course): each
        // box's halves swapped.
        let (out, _) = out.as_chunks_mut::<4>();
        for (b, &[l1, h1, l0, h0]) in out.iter_mut().zip(fb.as_chunks::<4>().0) {
            *b = [l0, h0, l1, h1];
        }
        return;
    }
    match (od, dim) {
        (1, 1) => translate_dims::<1, 1>(out, fb, map, pts),
        (2, 2) => translate_dims::<2, 2>(out, fb, map, pts),
        (3, 3) => translate_dims::<3, 3>(out, fb, map, pts),
        (1, 2) => translate_dims::<1, 2>(out, fb, map, pts),
        (1, 3) => translate_dims::<1, 3>(out, fb, map, pts),
        (2, 3) => translate_dims::<2, 3>(out, fb, map, pts),
        _ => translate_any(out, fb, map, pts),
    }
}

/// The problem-order boxes `out` of the function's `fb` (`OD` dimensions, mapped by
/// `map` into the problem's `DIM`), whole in the dimensions the function lacks.
#[inline(always)]
fn translate_dims<const OD: usize, const DIM: usize>(
    out: &mut [i32],
    fb: &[i32],
    map: &[usize],
    pts: &[i32],
) {
    let (Ok(map), Ok(pts)) = (<&[usize; OD]>::try_from(map), <&[i32; DIM]>::try_from(pts)) else {
        return translate_any(out, fb, map, pts);
    };
    let whole: [[i32; 2]; DIM] = std::array::from_fn(|d| [0, pts[d] - 1]);
    let (out, _) = out.as_chunks_mut::<2>();
    let (src, _) = fb.as_chunks::<2>();
    for (b, s) in out.chunks_exact_mut(DIM).zip(src.chunks_exact(OD)) {
        b.copy_from_slice(&whole);
        for i in 0..OD {
            b[map[i]] = s[i];
        }
    }
}

/// [`translate_dims`] for any dimensions.
fn translate_any(out: &mut [i32], fb: &[i32], map: &[usize], pts: &[i32]) {
    let (dim, od) = (pts.len(), map.len());
    let whole = od < dim;
    for (b, src) in out.chunks_exact_mut(2 * dim).zip(fb.chunks_exact(2 * od)) {
        if whole {
            for d in 0..dim {
                b[2 * d] = 0;
                b[2 * d + 1] = pts[d] - 1;
            }
        }
        for (s, &t) in src.chunks_exact(2).zip(map) {
            b[2 * t] = s[0];
            b[2 * t + 1] = s[1];
        }
    }
}

/// Cell bounds from the pieces' `maxVal`s: per cell over its list, which holds the
/// cell's pieces in array order, so every cell sees the comparisons of the
/// piece-by-piece build in the same order (the first piece taken as it is, each next
/// one if greater); an empty cell is `NO_BOUND`, not filled.
fn cell_bounds(p: &mut Prepared, total: usize) {
    let (start, items, piece_ub) = (&p.cell_start[..=total], &p.cell_items, &p.piece_ub);
    p.cell_ub.clear();
    p.cell_ub.resize(total, NO_BOUND);
    p.cell_filled.clear();
    p.cell_filled.resize(total, false);
    let out = (&mut p.cell_ub[..], &mut p.cell_filled[..]);
    // Whether every piece the lists name has a `maxVal`: checked once over the lists
    // (a vectorized max), not at every item of every list (a tiling's thousands).
    let sure = items.is_empty() || (max_item(items) as usize) < piece_ub.len();
    if sure {
        fill_cells::<true>(start, items, piece_ub, out);
    } else {
        fill_cells::<false>(start, items, piece_ub, out);
    }
}

/// The largest of `items` (0 for none), eight a step with AVX2 when the CPU has it.
fn max_item(items: &[u32]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2.
        return unsafe { max_item_avx2(items) };
    }
    items.iter().fold(0, |m, &k| m.max(k))
}

/// [`max_item`] compiled for AVX2 (the fold vectorized with `vpmaxud`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn max_item_avx2(items: &[u32]) -> u32 {
    items.iter().fold(0, |m, &k| m.max(k))
}

/// [`cell_bounds`] into `ub` and `filled` (sized, `NO_BOUND` and not filled);
/// `SURE`: every item of `items` is below `piece_ub.len()`.
#[inline(always)]
fn fill_cells<const SURE: bool>(
    start: &[u32],
    items: &[u32],
    piece_ub: &[f64],
    (ub, filled): (&mut [f64], &mut [bool]),
) {
    let at = |k: u32| {
        if SURE {
            // SAFETY: with `SURE` the caller found every item below `piece_ub.len()`.
            unsafe { *piece_ub.get_unchecked(k as usize) }
        } else {
            piece_ub[k as usize]
        }
    };
    // The lists lie one after the other in `items` (`start` their prefix sums): each
    // split off the front of what remains, no index checks per cell.
    let mut rest = &items[start[0] as usize..];
    for (w, (ub, filled)) in start.windows(2).zip(ub.iter_mut().zip(filled)) {
        let (list, tail) = rest.split_at(w[1].saturating_sub(w[0]) as usize);
        rest = tail;
        let Some((&k0, list)) = list.split_first() else {
            continue;
        };
        let mut top = at(k0);
        for &k in list {
            let v = at(k);
            if v > top {
                top = v;
            }
        }
        (*ub, *filled) = (top, true);
    }
}

/// Cell lists of a multi-cell grid: every cell's pieces in array order.
fn build_lists(p: &mut Prepared, boxes: &[i32], dim: usize, total: usize) {
    // The helm's dimensions made constants (a tiling's thousands of pieces, most in one
    // cell each, are placed without the odometer's loops).
    match dim {
        1 => build_lists_dim::<1>(p, boxes, dim, total),
        2 => build_lists_dim::<2>(p, boxes, dim, total),
        3 => build_lists_dim::<3>(p, boxes, dim, total),
        _ => build_lists_dim::<0>(p, boxes, dim, total),
    }
}

/// [`build_lists`] with `D == dim` (0: any dimension).
fn build_lists_dim<const D: usize>(p: &mut Prepared, boxes: &[i32], dim: usize, total: usize) {
    let dim = if D == 0 { dim } else { D };
    let bl = 2 * dim;
    p.cell_start.clear();
    p.cell_start.resize(total + 1, 0);
    let mut cell_start = std::mem::take(&mut p.cell_start);
    for b in boxes.chunks_exact(bl).take(p.n) {
        piece_cells::<D>(p, b, dim, |c| cell_start[c + 1] += 1);
    }
    let mut at = 0;
    for s in cell_start.iter_mut() {
        at += *s;
        *s = at;
    }
    p.cell_items.clear();
    p.cell_items.resize(cell_start[total] as usize, 0);
    p.cursor.clear();
    p.cursor.extend_from_slice(&cell_start[..total]);
    p.cell_start = cell_start;
    let mut items = std::mem::take(&mut p.cell_items);
    let mut cursor = std::mem::take(&mut p.cursor);
    for (k, b) in boxes.chunks_exact(bl).take(p.n).enumerate() {
        piece_cells::<D>(p, b, dim, |c| {
            items[cursor[c] as usize] = k as u32;
            cursor[c] += 1;
        });
    }
    (p.cell_items, p.cursor) = (items, cursor);
}

/// Every cell of piece `b` (`dim` dimensions, `D` when not 0), in the odometer's order
/// (any order would do for the lists: each cell's gets the piece once).
#[inline(always)]
fn piece_cells<const D: usize>(p: &Prepared, b: &[i32], dim: usize, mut f: impl FnMut(usize)) {
    if D == 0 && dim > ODO_DIMS {
        return p.for_each_cell(b, dim, |c| {
            f(c);
            true
        });
    }
    let r = p.range(b, dim);
    if r.one {
        return f(r.top);
    }
    walk_cells(&r, &p.stride, dim, |c| {
        f(c);
        true
    });
}

/// Smallest first function given cell lists for the seed (see `Solver::prepare_fresh`).
const SEED_LISTS_MIN: usize = 64;

/// Largest function kept from one solve to the next (see [`Solver::prepare`]).
const KEEP_MAX_PIECES: usize = 128;

/// Whether [`Solver::prepare`] keys a slot prepared afresh `misses` times in a row,
/// its function of `pieces` pieces.
#[inline(always)]
pub(crate) fn keys_now(misses: u32, pieces: usize) -> bool {
    (misses <= 2 || misses.is_multiple_of(16)) && pieces <= KEEP_MAX_PIECES
}
