//! The search grid of a function (spec §2.4): cell geometry and the per-cell bounds.

use super::{max_val, IvpFunction};
use crate::domain::Domain;

impl IvpFunction {
    /// The one cell bound of a whole-domain gel box: the max over the pieces (-inf for
    /// none), folded in piece order.
    pub(crate) fn whole_domain_max(&self) -> f64 {
        let dim = self.dim();
        let mut m = f64::NEG_INFINITY;
        for (b, w) in self
            .bounds
            .chunks_exact(2 * dim)
            .zip(self.weights.chunks_exact(dim + 1))
        {
            let v = max_val(b, w);
            if m == f64::NEG_INFINITY || v > m {
                m = v;
            }
        }
        m
    }

    /// Build the search grid (spec §2.4): per cell of `gelbox+1` points, the max
    /// `maxVal` of the pieces overlapping it (`-inf` for an empty cell). Builders
    /// call this when they extract, as the reference does. Afterwards
    /// [`normalize`](Self::normalize) and [`apply_weight`](Self::apply_weight)
    /// transform the stored bounds arithmetically instead of rebuilding them —
    /// the reference solver prunes with these bounds, which decides rare exact
    /// near-ties. Functions without a grid (e.g. coupled ones) get a fresh grid
    /// in the solver.
    pub fn build_grid(&mut self) {
        let dim = self.dim();
        // Cell sizes, strides (dimension 0 fastest) and, per piece, the corner cell and
        // spans live on the stack up to `GRID_DIMS` dimensions (this runs for every
        // piece of every function built, every iteration).
        const GRID_DIMS: usize = 8;
        let (mut ppg_st, mut stride_st) = ([0i32; GRID_DIMS], [0usize; GRID_DIMS]);
        let (mut ppg_heap, mut stride_heap) = (vec![], vec![]);
        let (ppg, stride): (&mut [i32], &mut [usize]) = if dim <= GRID_DIMS {
            (&mut ppg_st[..dim], &mut stride_st[..dim])
        } else {
            ppg_heap.resize(dim, 0);
            stride_heap.resize(dim, 0);
            (&mut ppg_heap, &mut stride_heap)
        };
        let mut total = 1usize;
        for (d, v) in self.domain.vars().iter().enumerate() {
            let (p, n) = grid_dim(v, self.gelbox.get(d));
            ppg[d] = p;
            stride[d] = total;
            total *= n as usize;
        }
        let mut g = vec![f64::NEG_INFINITY; total];
        if total == 1 && dim > 0 {
            // One cell (the builders' whole-domain gel box): the max over the pieces.
            g[0] = self.whole_domain_max();
            self.grid = g;
            return;
        }
        // Cell coordinate of every index, per dimension, when the pieces are many
        // (uniform tilings): a table read instead of two divisions per piece and
        // dimension.
        let points: usize = self.domain.vars().iter().map(|v| v.points as usize).sum();
        let mut coord: Vec<u32> = vec![];
        let mut coord_at = [0usize; GRID_DIMS + 1];
        if dim <= GRID_DIMS && self.piece_count() * 2 * dim > points {
            coord.reserve(points);
            for (d, v) in self.domain.vars().iter().enumerate() {
                coord_at[d] = coord.len();
                let (p, mut c, mut left) = (ppg[d] as u32, 0u32, ppg[d] as u32);
                for _ in 0..v.points {
                    coord.push(c);
                    left -= 1;
                    if left == 0 {
                        c += 1;
                        left = p;
                    }
                }
            }
            coord_at[dim] = coord.len();
        }
        let cell_of = |d: usize, i: i32| -> usize {
            let at = coord_at[d];
            match coord.get(at.wrapping_add(i as usize)) {
                Some(&c) if !coord.is_empty() && (i as usize) < coord_at[d + 1] - at => c as usize,
                _ => (i / ppg[d]) as usize,
            }
        };
        let (mut lo_st, mut span_st) = ([0usize; GRID_DIMS], [0usize; GRID_DIMS]);
        let (mut lo_heap, mut span_heap) = (vec![], vec![]);
        let (idx_lo, span): (&mut [usize], &mut [usize]) = if dim <= GRID_DIMS {
            (&mut lo_st[..dim], &mut span_st[..dim])
        } else {
            lo_heap.resize(dim, 0);
            span_heap.resize(dim, 0);
            (&mut lo_heap, &mut span_heap)
        };
        for p in self.pieces() {
            let v = p.max_val();
            for d in 0..dim {
                idx_lo[d] = cell_of(d, p.lo(d));
                span[d] = cell_of(d, p.hi(d)) - idx_lo[d] + 1;
            }
            // Cells in counting order, dimension 0 fastest, stepped by strides (no
            // division per cell); `off[d]` is the digit of dimension d.
            let mut off = [0usize; GRID_DIMS];
            let mut off_heap = vec![];
            let off: &mut [usize] = if dim <= GRID_DIMS {
                &mut off[..dim]
            } else {
                off_heap.resize(dim, 0);
                &mut off_heap
            };
            let mut c: usize = (0..dim).map(|d| idx_lo[d] * stride[d]).sum();
            'cells: loop {
                if g[c] == f64::NEG_INFINITY || v > g[c] {
                    g[c] = v;
                }
                for d in 0..dim {
                    if off[d] + 1 < span[d] {
                        off[d] += 1;
                        c += stride[d];
                        continue 'cells;
                    }
                    c -= off[d] * stride[d];
                    off[d] = 0;
                }
                break;
            }
        }
        self.grid = g;
    }
}

/// Grid geometry: (points per cell, cells, stride (dim 0 fastest), total cells).
/// Points per cell = `gelbox+1` clamped to `[2, points]`.
/// Points per grid cell and number of cells of variable `v` under gel-box entry `g`
/// (none: one cell across the variable).
pub fn grid_dim(v: &crate::domain::DomainVar, g: Option<&u32>) -> (i32, i32) {
    let pts = v.points as i32;
    let g = g.map_or(pts - 1, |&g| g.min(i32::MAX as u32 - 1) as i32);
    let p = (g + 1).max(2).min(pts).max(1);
    (p, (pts + p - 1) / p)
}

/// Number of grid cells of `domain` under `gelbox`.
pub(super) fn grid_total(domain: &Domain, gelbox: &[u32]) -> usize {
    let mut total = 1usize;
    for (d, v) in domain.vars().iter().enumerate() {
        total *= grid_dim(v, gelbox.get(d)).1 as usize;
    }
    total
}
