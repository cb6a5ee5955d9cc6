//! The first level of the search with the last index on ([`Search::run_indexed`]),
//! and its quick bound when functions sit between the first and the last (several
//! contacts' tilings above a waypoint's function, the helm's avoidance problems with
//! two or more contacts).
//!
//! The reference bound of a first-level piece adds, left to right, the cheap bound of
//! every function below it: one cell bound per middle function when the piece lies in
//! one of their cells (the tilings share one grid, the piece is a tile). That sum is
//! made per piece, thousands of times a solve. Here it is made per cell instead, once
//! per solve, in another order: `(maxVal + sum of the cell) + last bound` is then the
//! same bound up to rounding, which the search's slack covers (see `Search::prune`:
//! a bound at most `best - 2 tol` leaves every leaf under it below the incumbent, so
//! skipping the piece skips no leaf the reference would take). A middle cell no piece
//! meets holds `NO_BOUND`: no leaf lies under such a piece at all.

#[cfg(target_arch = "x86_64")]
use crate::first_simd;
use crate::last_index::{LastIndex, NO_CELL};
use crate::prepared::{Prepared, ODO_DIMS};
use crate::search::Search;

#[derive(Debug, Default)]
pub(crate) struct Mid {
    /// Per piece of the first function: its cell in the middle functions' grid,
    /// [`NO_CELL`] when it meets several.
    tops: Vec<u32>,
    /// What `tops` were made for: the first function's slot and boxes generation (see
    /// [`Prepared::boxes_gen`]), the grid's cell size and the problem's points.
    key: Option<(usize, u64)>,
    key_ppg: Vec<i32>,
    key_pts: Vec<i32>,
    /// Per cell of the middle grid: the sum of the middle functions' bounds there; then
    /// NaN, for `first_simd.rs`.
    sums: Vec<f64>,
}

impl Mid {
    /// Make the cell sums of this solve (and the pieces' cells unless kept) for the
    /// middle functions `active[1..m-1]`, when they are all one cell or all grids of
    /// one geometry, at least one a grid; `None` otherwise. `boxes` are the `n` boxes
    /// of the first function (slot `active[0]`).
    pub(crate) fn refresh(
        &mut self,
        funcs: &[Prepared],
        active: &[usize],
        pts: &[i32],
        boxes: &[i32],
    ) -> Option<(&[u32], &[f64])> {
        let (m, dim) = (active.len(), pts.len());
        if m < 3 || dim > ODO_DIMS {
            return None;
        }
        let mid = &active[1..m - 1];
        let &g = mid.iter().find(|&&fi| !funcs[fi].single)?;
        let grid = &funcs[g];
        if mid
            .iter()
            .any(|&fi| !funcs[fi].single && funcs[fi].geom != grid.geom)
        {
            return None;
        }
        let (f0, total) = (active[0], grid.cell_ub.len());
        let f = &funcs[f0];
        let key = Some((f0, f.boxes_gen));
        if self.key != key
            || self.key_ppg != grid.ppg
            || self.key_pts != pts
            || self.tops.len() != f.n
        {
            let top = |b: &[i32], dim: usize| {
                let r = grid.range(b, dim);
                if r.one && r.top < total {
                    r.top as u32
                } else {
                    NO_CELL
                }
            };
            let boxes = boxes.chunks_exact(2 * dim).take(f.n);
            self.tops.clear();
            // (Two dimensions, the helm's course × speed, a constant: unrolled.)
            match dim {
                2 => self.tops.extend(boxes.map(|b| top(b, 2))),
                _ => self.tops.extend(boxes.map(|b| top(b, dim))),
            }
            self.key = key;
            self.key_ppg.clone_from(&grid.ppg);
            self.key_pts.clear();
            self.key_pts.extend_from_slice(pts);
        }
        self.sums.clear();
        self.sums.resize(total, 0.0);
        for &fi in mid {
            let p = &funcs[fi];
            if p.single {
                self.sums.iter_mut().for_each(|s| *s += p.global_ub);
            } else {
                for (s, &u) in self.sums.iter_mut().zip(&p.cell_ub) {
                    *s += u;
                }
            }
        }
        // (Read past the cells by the AVX2 loop for a piece without one: no bound.)
        self.sums.push(f64::NAN);
        Some((&self.tops, &self.sums))
    }
}

impl Search<'_> {
    /// The first level of [`Search::run`] with the index on, `mvs` the first
    /// function's `maxVal`s and `cells` their index cells: [`Search::skip_first`]
    /// inlined, with the pieces it prunes passed over in a tight loop when there are
    /// two functions (raising `doubt` as it does): the same prunes, the same flag.
    // Once per solve: kept out of `Search::run`, whose other loops it would crowd.
    #[inline(never)]
    pub(crate) fn run_indexed(&mut self, ix: &LastIndex, cells: &[u32], mvs: &[f64]) {
        let (dim, m) = (self.dim, self.active.len());
        let (bl, wl) = (2 * dim, dim + 1);
        let f0 = &self.funcs[self.active[0]];
        let (fb, fw) = (self.boxes[self.active[0]], &f0.weights[..]);
        let n = f0.n.min(mvs.len()).min(cells.len());
        let last_ub = self.last_ub;
        // Held in locals: the loop tests them once per piece the tight loops stop at.
        let (two, mid) = (m == 2, self.mid.filter(|_| m > 2));
        // The second function the last and one cell: its leaves read the piece in place.
        let direct = two && self.funcs[self.active[1]].single;
        // The tight loops four pieces a step when the CPU has AVX2 (`first_simd.rs`),
        // the scalar loops then going on from where they stop.
        #[cfg(target_arch = "x86_64")]
        let simd = std::arch::is_x86_feature_detected!("avx2");
        let mut q = 0;
        while q < n {
            // The two-function loop stopped at `q`: `skip_indexed`'s tests made on it,
            // with the same `best`, and it was not skipped.
            let tested = two && (self.found || self.seeded);
            if tested {
                // `skip_indexed`: the reference bound `rb = mv + last_ub` (pruning, and
                // before the first leaf raising `doubt` above `best - 2 tol`, as
                // `prune(rb, rb)` does), then the index's.
                let (best, floor) = (self.best, self.best - 2.0 * self.tol);
                #[cfg(target_arch = "x86_64")]
                if simd {
                    let t = first_simd::Two {
                        mvs,
                        cells,
                        ub: ix.bounds(),
                        last_ub,
                        best,
                        floor,
                    };
                    // SAFETY: `simd` only when the CPU has AVX2.
                    let (at, doubt) = unsafe { first_simd::pass_two(&t, q, n, !self.found) };
                    if doubt {
                        self.doubt.set(true);
                    }
                    q = at;
                }
                while q < n {
                    let rb = mvs[q] + last_ub;
                    if rb <= best {
                        if !self.found && rb > floor {
                            self.doubt.set(true);
                        }
                        q += 1;
                        continue;
                    }
                    let c = cells[q];
                    let tb = if c != NO_CELL {
                        mvs[q] + ix.bound(c as usize)
                    } else {
                        rb
                    };
                    // (A NaN bound prunes nothing, as in `prune`.)
                    if tb <= floor {
                        q += 1;
                        continue;
                    }
                    break;
                }
                if q == n {
                    return;
                }
            }
            // Seeded, `best` is the floor `B`: a piece the quick bound puts at most
            // `B - 2 tol` holds no leaf above `B` (the first the reference takes there
            // is not under it), so it is passed over with no `doubt`, as `prune` passes
            // over a tighter bound's prunes.
            if let (Some((tops, sums)), true) = (mid, self.found || self.seeded) {
                // The quick bound (see the module docs), the rest exactly as below.
                let lim = self.best - 2.0 * self.tol;
                #[cfg(target_arch = "x86_64")]
                if simd {
                    let t = first_simd::Mid {
                        mvs,
                        cells,
                        ub: ix.bounds(),
                        tops,
                        sums,
                        lim,
                    };
                    // SAFETY: `simd` only when the CPU has AVX2.
                    q = unsafe { first_simd::pass_mid(&t, q, n) };
                }
                while q < n && tops[q] != NO_CELL {
                    let c = cells[q];
                    let lb = if c != NO_CELL {
                        ix.bound(c as usize)
                    } else {
                        last_ub
                    };
                    // (A NaN bound prunes nothing, as in `prune`.)
                    if (mvs[q] + sums[tops[q] as usize]) + lb <= lim {
                        q += 1;
                    } else {
                        break;
                    }
                }
                if q == n {
                    return;
                }
            }
            let (pb, mv) = (&fb[q * bl..(q + 1) * bl], mvs[q]);
            let skip = !tested
                && (self.found || self.seeded)
                && self.skip_indexed(1, pb, mv, ix, || {
                    let c = cells[q];
                    (c != NO_CELL).then_some(c as usize)
                });
            if !skip {
                self.descend(pb, &fw[q * wl..(q + 1) * wl], mv, direct);
            }
            q += 1;
        }
    }
}
