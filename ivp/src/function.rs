//! Piecewise-linear IvP functions stored as flat arrays (spec §2).

use crate::domain::{Domain, DomainVar};
use crate::error::{bad_piece, invalid, IvpError};

/// An IvP function: an ordered list of linear pieces over its own [`Domain`].
///
/// Storage is contiguous: piece `k` owns `bounds[2*dim*k .. 2*dim*(k+1)]`
/// (`lo, hi` per dimension, inclusive grid indices) and
/// `weights[(dim+1)*k .. (dim+1)*(k+1)]` (one slope per dimension, then the
/// intercept). Values are evaluated on grid *indices*, not domain values.
#[derive(Debug, Clone, PartialEq)]
pub struct IvpFunction {
    domain: Domain,
    bounds: Vec<i32>,
    weights: Vec<f64>,
    pwt: f64,
    context: String,
    gelbox: Vec<u32>,
    /// Grid cell upper bounds (empty = no grid); see [`IvpFunction::build_grid`].
    grid: Vec<f64>,
}

/// One piece for [`IvpFunction::from_pieces`]: `(lo, hi)` per dimension, then
/// the weights (slopes in dimension order, then the intercept).
pub type PieceSpec = (Vec<(i32, i32)>, Vec<f64>);

/// A borrowed view of one piece.
#[derive(Debug, Clone, Copy)]
pub struct Piece<'a> {
    bounds: &'a [i32],
    weights: &'a [f64],
}

impl<'a> Piece<'a> {
    /// Lowest index (inclusive) in dimension `d`.
    pub fn lo(&self, d: usize) -> i32 {
        self.bounds[2 * d]
    }
    /// Highest index (inclusive) in dimension `d`.
    pub fn hi(&self, d: usize) -> i32 {
        self.bounds[2 * d + 1]
    }
    /// Slopes (one per dimension) followed by the intercept.
    pub fn weights(&self) -> &'a [f64] {
        self.weights
    }
    /// Maximum over the box: intercept first, then dimension 0, 1, ...
    pub fn max_val(&self) -> f64 {
        max_val(self.bounds, self.weights)
    }
    /// Minimum over the box (opposite corner).
    pub fn min_val(&self) -> f64 {
        min_val(self.bounds, self.weights)
    }
}

/// `maxVal` of a linear box (spec §2.1): `w_n + Σ_d w_d * (w_d < 0 ? lo_d : hi_d)`.
/// Public for the solver crate (`ivp-solver`), which bounds cells with it.
#[inline]
pub fn max_val(bounds: &[i32], w: &[f64]) -> f64 {
    let n = w.len() - 1;
    let mut acc = w[n];
    for d in 0..n {
        let c = if w[d] < 0.0 {
            bounds[2 * d]
        } else {
            bounds[2 * d + 1]
        };
        acc += w[d] * f64::from(c);
    }
    acc
}

#[inline]
pub(crate) fn min_val(bounds: &[i32], w: &[f64]) -> f64 {
    let n = w.len() - 1;
    let mut acc = w[n];
    for d in 0..n {
        let c = if w[d] < 0.0 {
            bounds[2 * d + 1]
        } else {
            bounds[2 * d]
        };
        acc += w[d] * f64::from(c);
    }
    acc
}

/// The lowest and highest value over every piece, any dimension (the unrolled
/// `min_max_n` gives the same for 1 to 3).
fn min_max_any_dim(bounds: &[i32], weights: &[f64], dim: usize) -> (f64, f64) {
    let mut pieces = bounds
        .chunks_exact(2 * dim)
        .zip(weights.chunks_exact(dim + 1));
    let Some((b, w)) = pieces.next() else {
        return (0.0, 0.0);
    };
    let (mut mn, mut mx) = (min_val(b, w), max_val(b, w));
    for (b, w) in pieces {
        let (lo, hi) = (min_val(b, w), max_val(b, w));
        if lo < mn {
            mn = lo;
        }
        if hi > mx {
            mx = hi;
        }
    }
    (mn, mx)
}

/// [`IvpFunction::min_max_wt`] of the pieces in `bounds`/`weights` for `N` dimensions
/// (a constant): [`min_val`] and [`max_val`] with the same operations in the same order,
/// folded the same way.
fn min_max_n<const N: usize>(bounds: &[i32], weights: &[f64]) -> (f64, f64) {
    let piece = |b: &[i32], w: &[f64]| -> (f64, f64) {
        let (b, w) = (&b[..2 * N], &w[..=N]);
        let (mut lo, mut hi) = (w[N], w[N]);
        for d in 0..N {
            let (l, h) = (f64::from(b[2 * d]), f64::from(b[2 * d + 1]));
            hi += w[d] * if w[d] < 0.0 { l } else { h };
            lo += w[d] * if w[d] < 0.0 { h } else { l };
        }
        (lo, hi)
    };
    let mut pieces = bounds.chunks_exact(2 * N).zip(weights.chunks_exact(N + 1));
    let Some((b, w)) = pieces.next() else {
        return (0.0, 0.0);
    };
    let (mut mn, mut mx) = piece(b, w);
    for (b, w) in pieces {
        let (lo, hi) = piece(b, w);
        if lo < mn {
            mn = lo;
        }
        if hi > mx {
            mx = hi;
        }
    }
    (mn, mx)
}

/// [`IvpFunction::normalize_from`] of the weights (`wl` per piece): the intercepts
/// shifted, then every weight scaled, so `[mn, mx]` becomes `[base, base + range]`; the
/// shift and scale, `None` (nothing done) for a range that is not positive.
fn shift_scale(
    weights: &mut [f64],
    wl: usize,
    (mn, mx): (f64, f64),
    base: f64,
    range: f64,
) -> Option<(f64, f64)> {
    let r = mx - mn;
    if r.is_nan() || r <= 0.0 {
        return None;
    }
    let (shift, scale) = (base - mn, range / r);
    // Each weight gets its own operations in the same order (intercepts shifted, then
    // scaled), in two passes over the weights: the scaling one runs vectorized.
    for w in weights.chunks_exact_mut(wl) {
        w[wl - 1] += shift;
    }
    for x in weights.iter_mut() {
        *x *= scale;
    }
    Some((shift, scale))
}

/// [`IvpFunction::normalize`] of a one-variable function's pieces, not yet a function
/// (it has no grid): the same weights, bit for bit.
pub(crate) fn normalize_line_pieces(bounds: &[i32], weights: &mut [f64], base: f64, range: f64) {
    let min_max = min_max_n::<1>(bounds, weights);
    shift_scale(weights, 2, min_max, base, range);
}

/// [`IvpFunction::normalize_from`]'s pass over the weights for `N` dimensions (a
/// constant; at least one piece), each piece then folded as [`min_max_n`] folds it.
fn normalize_min_max_n<const N: usize>(
    bounds: &[i32],
    weights: &mut [f64],
    shift: f64,
    scale: f64,
) -> (f64, f64) {
    let (mut mn, mut mx) = (f64::NAN, f64::NAN);
    let pieces = bounds
        .chunks_exact(2 * N)
        .zip(weights.chunks_exact_mut(N + 1));
    for (k, (b, w)) in pieces.enumerate() {
        let (b, w) = (&b[..2 * N], &mut w[..=N]);
        w[N] += shift;
        for x in w.iter_mut() {
            *x *= scale;
        }
        let (mut lo, mut hi) = (w[N], w[N]);
        for d in 0..N {
            let (l, h) = (f64::from(b[2 * d]), f64::from(b[2 * d + 1]));
            hi += w[d] * if w[d] < 0.0 { l } else { h };
            lo += w[d] * if w[d] < 0.0 { h } else { l };
        }
        if k == 0 {
            (mn, mx) = (lo, hi);
            continue;
        }
        if lo < mn {
            mn = lo;
        }
        if hi > mx {
            mx = hi;
        }
    }
    (mn, mx)
}

/// The raw parts of an [`IvpFunction`], all fields public so the buffers can be
/// moved (not copied) into another container, e.g. `abi_stable::std_types::RVec`.
#[derive(Debug, Clone, PartialEq)]
pub struct RawFunction {
    pub vars: Vec<DomainVar>,
    pub bounds: Vec<i32>,
    pub weights: Vec<f64>,
    pub pwt: f64,
    pub context: String,
    pub gelbox: Vec<u32>,
    /// Grid cell upper bounds as built by the builder (empty = no grid). Must be
    /// carried across the ABI too: the solver's pruning (and so exact ties in
    /// rare near-tie cases) depends on it.
    pub grid: Vec<f64>,
}

impl IvpFunction {
    /// Build from `(per-dimension (lo,hi), weights)` pieces; weights are the
    /// slopes in dimension order then the intercept. Gel box = whole domain, pwt 10.
    pub fn from_pieces(domain: Domain, pieces: &[PieceSpec]) -> Result<IvpFunction, IvpError> {
        let dim = domain.size();
        let mut bounds = Vec::with_capacity(pieces.len() * 2 * dim);
        let mut weights = Vec::with_capacity(pieces.len() * (dim + 1));
        for (k, (b, w)) in pieces.iter().enumerate() {
            if b.len() != dim || w.len() != dim + 1 {
                return Err(bad_piece(
                    k,
                    format!("needs {dim} intervals and {} weights", dim + 1),
                ));
            }
            for &(lo, hi) in b {
                bounds.push(lo);
                bounds.push(hi);
            }
            weights.extend_from_slice(w);
        }
        let gelbox = domain
            .vars()
            .iter()
            .map(|v| v.points.saturating_sub(1))
            .collect();
        Self::from_flat(domain, bounds, weights, gelbox)
    }

    /// Build from flat buffers (layout documented on the type); validated.
    pub fn from_flat(
        domain: Domain,
        bounds: Vec<i32>,
        weights: Vec<f64>,
        gelbox: Vec<u32>,
    ) -> Result<IvpFunction, IvpError> {
        check_layout(&domain, &bounds, &weights, &gelbox)?;
        Ok(Self::of_parts(domain, bounds, weights, gelbox, Vec::new()))
    }

    /// The one place a function is put together: the given buffers, the default
    /// priority weight (10) and no context.
    pub(crate) fn of_parts(
        domain: Domain,
        bounds: Vec<i32>,
        weights: Vec<f64>,
        gelbox: Vec<u32>,
        grid: Vec<f64>,
    ) -> IvpFunction {
        IvpFunction {
            domain,
            bounds,
            weights,
            pwt: 10.0,
            context: String::new(),
            gelbox,
            grid,
        }
    }

    /// A builder's function whose search grid it computed along with the pieces (what
    /// [`IvpFunction::build_grid`] gives for them); the layout is correct by
    /// construction (checked in debug builds).
    // Public but hidden: for ivp-reflector only, not part of ivp's API.
    #[doc(hidden)]
    pub fn with_grid_unchecked(
        domain: Domain,
        bounds: Vec<i32>,
        weights: Vec<f64>,
        gelbox: Vec<u32>,
        grid: Vec<f64>,
    ) -> IvpFunction {
        debug_assert!(check_layout(&domain, &bounds, &weights, &gelbox).is_ok());
        debug_assert_eq!(grid.len(), grid_total(&domain, &gelbox));
        Self::of_parts(domain, bounds, weights, gelbox, grid)
    }

    /// Give the buffers away (no copy).
    pub fn into_raw_parts(self) -> RawFunction {
        RawFunction {
            vars: self.domain.into_vars(),
            bounds: self.bounds,
            weights: self.weights,
            pwt: self.pwt,
            context: self.context,
            gelbox: self.gelbox,
            grid: self.grid,
        }
    }

    /// Rebuild from raw parts (validated; the buffers are moved in, not copied).
    pub fn from_raw_parts(raw: RawFunction) -> Result<IvpFunction, IvpError> {
        let domain = Domain::from_vars(raw.vars)?;
        let (b, w, g) = (raw.bounds, raw.weights, raw.gelbox);
        let mut f = Self::from_buffers(domain, b, w, g, raw.grid, raw.pwt)?;
        f.context = raw.context;
        Ok(f)
    }

    /// Move the domain out, leaving an empty one (for a builder that is done with the
    /// function's variables and only reads its pieces afterwards).
    pub(crate) fn take_domain(&mut self) -> Domain {
        std::mem::take(&mut self.domain)
    }

    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    pub fn dim(&self) -> usize {
        self.domain.size()
    }
    pub fn piece_count(&self) -> usize {
        self.weights.len() / (self.dim() + 1)
    }
    /// Piece `k` (panics if out of range).
    pub fn piece(&self, k: usize) -> Piece<'_> {
        let (bl, wl) = (2 * self.dim(), self.dim() + 1);
        Piece {
            bounds: &self.bounds[k * bl..(k + 1) * bl],
            weights: &self.weights[k * wl..(k + 1) * wl],
        }
    }
    /// Iterate the pieces in order.
    pub fn pieces(&self) -> impl Iterator<Item = Piece<'_>> {
        (0..self.piece_count()).map(move |k| self.piece(k))
    }
    /// Flat bounds buffer.
    pub fn bounds(&self) -> &[i32] {
        &self.bounds
    }
    /// Flat weights buffer.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }
    /// Gel box high corner per dimension (grid cell size minus 1).
    pub fn gelbox(&self) -> &[u32] {
        &self.gelbox
    }
    /// Set the gel box (one entry per dimension).
    pub fn set_gelbox(&mut self, gelbox: Vec<u32>) -> Result<(), IvpError> {
        if gelbox.len() != self.dim() {
            return Err(invalid("gelbox", format!("needs {} entries", self.dim())));
        }
        self.gelbox = gelbox;
        if !self.grid.is_empty() {
            self.build_grid();
        }
        Ok(())
    }

    /// Whether the function carries a builder-made grid.
    pub fn has_grid(&self) -> bool {
        !self.grid.is_empty()
    }

    /// Grid cell upper bounds (cells numbered with dimension 0 fastest).
    pub fn grid_bounds(&self) -> &[f64] {
        &self.grid
    }

    /// Value at a grid point: the first piece containing it, evaluated
    /// intercept first, then `+ slope_d * index_d` in dimension order.
    pub fn eval(&self, index: &[u32]) -> Option<f64> {
        if index.len() != self.dim() {
            return None;
        }
        self.pieces()
            .find(|p| {
                index.iter().enumerate().all(|(d, &i)| {
                    i64::from(p.lo(d)) <= i64::from(i) && i64::from(i) <= i64::from(p.hi(d))
                })
            })
            .map(|p| {
                let w = p.weights();
                let mut acc = w[self.dim()];
                for (d, &i) in index.iter().enumerate() {
                    acc += w[d] * f64::from(i);
                }
                acc
            })
    }

    /// Max over pieces of the piece maximum (0 with no pieces).
    pub fn max_wt(&self) -> f64 {
        self.pieces()
            .map(|p| p.max_val())
            .reduce(|a, b| if b > a { b } else { a })
            .unwrap_or(0.0)
    }
    /// Min over pieces of the piece minimum (0 with no pieces).
    pub fn min_wt(&self) -> f64 {
        self.pieces()
            .map(|p| p.min_val())
            .reduce(|a, b| if b < a { b } else { a })
            .unwrap_or(0.0)
    }

    /// `(min_wt(), max_wt())` in one pass over the pieces, with the same comparisons
    /// in the same order (so the same values, bit for bit).
    pub fn min_max_wt(&self) -> (f64, f64) {
        let dim = self.dim();
        if dim == 0 {
            return (self.min_wt(), self.max_wt());
        }
        // The usual dimensions with the per-piece loops unrolled (the solver and the
        // behaviors' normalization ask this of every function, every iteration).
        match dim {
            1 => return min_max_n::<1>(&self.bounds, &self.weights),
            2 => return min_max_n::<2>(&self.bounds, &self.weights),
            3 => return min_max_n::<3>(&self.bounds, &self.weights),
            _ => {}
        }
        min_max_any_dim(&self.bounds, &self.weights, dim)
    }

    /// Shift then scale so the range becomes `[base, base+range]`; flat functions untouched.
    pub fn normalize(&mut self, base: f64, range: f64) {
        let min_max = self.min_max_wt();
        self.normalize_from(min_max, base, range);
    }

    /// [`IvpFunction::normalize`] given what [`IvpFunction::min_max_wt`] returns (a
    /// builder that has it already).
    // Public but hidden: for ivp-reflector only, not part of ivp's API.
    #[doc(hidden)]
    pub fn normalize_from(&mut self, min_max: (f64, f64), base: f64, range: f64) {
        let wl = self.dim() + 1;
        if let Some((shift, scale)) = shift_scale(&mut self.weights, wl, min_max, base, range) {
            for g in &mut self.grid {
                *g = (*g + shift) * scale;
            }
        }
    }

    /// [`IvpFunction::normalize_from`], returning what [`IvpFunction::min_max_wt`] gives
    /// afterwards: for 1 to 3 dimensions each piece's new least and greatest value are
    /// taken as its weights are written (the same operations on the same values, folded
    /// in the same order), saving a pass over the pieces when normalizing again.
    // Public but hidden: for ivp-reflector only, not part of ivp's API.
    #[doc(hidden)]
    pub fn normalize_from_and_min_max(
        &mut self,
        (mn, mx): (f64, f64),
        base: f64,
        range: f64,
    ) -> (f64, f64) {
        let r = mx - mn;
        if r.is_nan() || r <= 0.0 {
            return self.min_max_wt();
        }
        if self.weights.is_empty() {
            self.normalize_from((mn, mx), base, range);
            return self.min_max_wt();
        }
        let (shift, scale) = (base - mn, range / r);
        let folded = match self.dim() {
            1 => normalize_min_max_n::<1>(&self.bounds, &mut self.weights, shift, scale),
            2 => normalize_min_max_n::<2>(&self.bounds, &mut self.weights, shift, scale),
            3 => normalize_min_max_n::<3>(&self.bounds, &mut self.weights, shift, scale),
            _ => {
                self.normalize_from((mn, mx), base, range);
                return self.min_max_wt();
            }
        };
        for g in &mut self.grid {
            *g = (*g + shift) * scale;
        }
        folded
    }

    /// Multiply every weight (slopes and intercepts) by `w`.
    pub fn apply_weight(&mut self, w: f64) {
        for x in &mut self.weights {
            *x *= w;
        }
        for g in &mut self.grid {
            *g *= w;
        }
    }

    pub fn pwt(&self) -> f64 {
        self.pwt
    }
    pub fn set_pwt(&mut self, pwt: f64) {
        self.pwt = pwt;
    }
    pub fn context(&self) -> &str {
        &self.context
    }
    pub fn set_context(&mut self, s: &str) {
        self.context = s.to_string();
    }
    /// The context string to write in place (e.g. with `write!`, no temporary string).
    pub fn context_mut(&mut self) -> &mut String {
        &mut self.context
    }

    /// Translate into `target` (spec §2.3): dimensions move to the same-named
    /// target variable; new dimensions get the full interval and slope 0.
    pub fn translate(&self, target: &Domain) -> Result<IvpFunction, IvpError> {
        let map = dim_map(&self.domain, target)?;
        let (od, td) = (self.dim(), target.size());
        let n = self.piece_count();
        let mut bounds = Vec::with_capacity(n * 2 * td);
        let mut weights = Vec::with_capacity(n * (td + 1));
        let mut gelbox: Vec<u32> = target
            .vars()
            .iter()
            .map(|v| v.points.saturating_sub(1))
            .collect();
        for (d, &t) in map.iter().enumerate() {
            gelbox[t] = self.gelbox[d];
        }
        translate_into(
            &self.bounds,
            &self.weights,
            od,
            &map,
            target,
            &mut bounds,
            &mut weights,
        );
        let mut f = IvpFunction {
            domain: target.clone(),
            bounds,
            weights,
            pwt: self.pwt,
            context: self.context.clone(),
            gelbox,
            grid: Vec::new(),
        };
        if self.has_grid() {
            f.build_grid();
        }
        Ok(f)
    }
}

/// For each own dimension, the target dimension of the same name.
pub(crate) fn dim_map(own: &Domain, target: &Domain) -> Result<Vec<usize>, IvpError> {
    own.vars()
        .iter()
        .map(|v| {
            target
                .index_of(&v.name)
                .ok_or_else(|| IvpError::UnknownVar(v.name.clone()))
        })
        .collect()
}

/// Append the translated pieces to `bounds`/`weights` (cleared by the caller if needed).
pub(crate) fn translate_into(
    src_b: &[i32],
    src_w: &[f64],
    od: usize,
    map: &[usize],
    target: &Domain,
    bounds: &mut Vec<i32>,
    weights: &mut Vec<f64>,
) {
    let td = target.size();
    let n = src_w.len() / (od + 1);
    // Sized once: these run for every coupled function of every iteration.
    bounds.reserve(n * 2 * td);
    weights.reserve(n * (td + 1));
    for k in 0..n {
        let b0 = bounds.len();
        let w0 = weights.len();
        for v in target.vars() {
            bounds.push(0);
            bounds.push(v.points as i32 - 1);
            weights.push(0.0);
        }
        weights.push(src_w[k * (od + 1) + od]);
        for (d, &t) in map.iter().enumerate() {
            bounds[b0 + 2 * t] = src_b[k * 2 * od + 2 * d];
            bounds[b0 + 2 * t + 1] = src_b[k * 2 * od + 2 * d + 1];
            weights[w0 + t] = src_w[k * (od + 1) + d];
        }
        debug_assert_eq!(weights.len() - w0, td + 1);
    }
}

// Building functions in recycled storage (issue 19).
mod grid;
mod layout;
mod reuse;

// Public but hidden: for ivp-reflector only, not part of ivp's API.
#[doc(hidden)]
pub use grid::grid_dim;
use grid::grid_total;
pub use layout::check_buffers;
use layout::check_layout;

#[cfg(test)]
mod tests {
    use super::*;

    /// The grid as spec §2.4 states it: every cell of every piece found by dividing,
    /// the cell's bound the max `maxVal` of its pieces (first piece taken as is).
    fn grid_by_division(f: &IvpFunction) -> Vec<f64> {
        let dim = f.dim();
        let dims: Vec<(i32, i32)> = (0..dim)
            .map(|d| grid_dim(f.domain().var(d), f.gelbox().get(d)))
            .collect();
        let total: usize = dims.iter().map(|&(_, n)| n as usize).product();
        let mut g = vec![f64::NEG_INFINITY; total];
        for p in f.pieces() {
            let v = p.max_val();
            // Every cell whose coordinates lie between the piece's corner cells.
            let (lo, hi): (Vec<usize>, Vec<usize>) = dims
                .iter()
                .enumerate()
                .map(|(d, &(ppg, _))| ((p.lo(d) / ppg) as usize, (p.hi(d) / ppg) as usize))
                .unzip();
            let count: usize = (0..dim).map(|d| hi[d] - lo[d] + 1).product();
            for k in 0..count {
                let (mut rem, mut c, mut stride) = (k, 0usize, 1usize);
                for d in 0..dim {
                    let span = hi[d] - lo[d] + 1;
                    c += (lo[d] + rem % span) * stride;
                    rem /= span;
                    stride *= dims[d].1 as usize;
                }
                if g[c] == f64::NEG_INFINITY || v > g[c] {
                    g[c] = v;
                }
            }
        }
        g
    }

    /// The single-cell shortcut and the coordinate table give the divided grid, bit for
    /// bit, for few and many pieces (uniform tilings and random overlapping boxes).
    #[test]
    fn build_grid_equals_the_grid_by_division() {
        let doms = [
            Domain::parse("speed:0:4:41,course:0:359:360").unwrap(),
            Domain::parse("x:0:9:10,y:0:6:7,z:0:2:3").unwrap(),
            Domain::parse("x:0:20:21").unwrap(),
        ];
        let mut seed = 3u64;
        let mut rng = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 33
        };
        for round in 0..240 {
            let dom = &doms[round % doms.len()];
            let dim = dom.size();
            let pts: Vec<u32> = dom.vars().iter().map(|v| v.points).collect();
            let mut pieces = vec![];
            if round.is_multiple_of(3) {
                // A uniform tiling, tile sizes = the gel box + 1.
                let tile: Vec<u32> = pts.iter().map(|&p| 1 + (rng() as u32 % p.min(5))).collect();
                let mut corner = vec![0u32; dim];
                'tiles: loop {
                    let b = (0..dim)
                        .map(|d| {
                            let lo = corner[d];
                            (lo as i32, (lo + tile[d] - 1).min(pts[d] - 1) as i32)
                        })
                        .collect();
                    let mut w: Vec<f64> =
                        (0..dim).map(|_| (rng() % 41) as f64 / 4.0 - 5.0).collect();
                    w.push((rng() % 1001) as f64 / 8.0);
                    pieces.push((b, w));
                    for d in 0..dim {
                        corner[d] += tile[d];
                        if corner[d] < pts[d] {
                            continue 'tiles;
                        }
                        corner[d] = 0;
                    }
                    break;
                }
                let mut f = IvpFunction::from_pieces(dom.clone(), &pieces).unwrap();
                f.set_gelbox(tile.iter().map(|t| t - 1).collect()).unwrap();
                f.build_grid();
                assert_eq!(bits(f.grid_bounds()), bits(&grid_by_division(&f)));
                continue;
            }
            let n = 1 + rng() as usize % if round % 3 == 1 { 6 } else { 400 };
            for _ in 0..n {
                let b = (0..dim)
                    .map(|d| {
                        let lo = rng() as u32 % pts[d];
                        (lo as i32, (lo + rng() as u32 % (pts[d] - lo)) as i32)
                    })
                    .collect();
                let mut w: Vec<f64> = (0..dim).map(|_| (rng() % 41) as f64 / 4.0 - 5.0).collect();
                w.push((rng() % 1001) as f64 / 8.0);
                pieces.push((b, w));
            }
            let mut f = IvpFunction::from_pieces(dom.clone(), &pieces).unwrap();
            let gel = pts.iter().map(|&p| rng() as u32 % (p + 2)).collect();
            f.set_gelbox(gel).unwrap();
            f.build_grid();
            assert_eq!(bits(f.grid_bounds()), bits(&grid_by_division(&f)));
        }
    }

    /// `min_max_wt` as it was before the unrolled dimensions (the reference).
    fn min_max_wt_reference(f: &IvpFunction) -> (f64, f64) {
        min_max_any_dim(&f.bounds, &f.weights, f.dim())
    }

    /// `check_layout`'s piece loop as it was (the reference for `bounds_in_range`).
    fn in_range_reference(domain: &Domain, bounds: &[i32]) -> bool {
        let tops: Vec<i64> = domain
            .vars()
            .iter()
            .map(|v| i64::from(v.points) - 1)
            .collect();
        bounds.chunks_exact(2 * tops.len()).all(|b| {
            tops.iter().enumerate().all(|(d, &top)| {
                let (lo, hi) = (b[2 * d], b[2 * d + 1]);
                !(lo < 0 || lo > hi || i64::from(hi) > top)
            })
        })
    }

    /// The unrolled `min_max_wt` and the branch-free range check give what the plain
    /// loops give, over random pieces of 1 to 5 dimensions with awkward weights (signed
    /// zeros, ties, NaNs, infinities) and bounds (negative, crossed, past the top).
    #[test]
    fn unrolled_piece_loops_equal_the_plain_ones() {
        let mut seed = 11u64;
        let mut rng = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            seed >> 33
        };
        let specs = [
            "a:0:9:10",
            "a:0:9:10,b:0:40:41",
            "a:0:9:10,b:0:4:5,c:0:20:21",
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3",
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3,e:0:7:8",
        ];
        for round in 0..4000 {
            let dom = Domain::parse(specs[round % specs.len()]).unwrap();
            let dim = dom.size();
            let n = rng() as usize % 40;
            let mut bounds = vec![];
            let mut weights = vec![];
            for _ in 0..n {
                for v in dom.vars() {
                    let lo = rng() as i32 % v.points as i32;
                    let hi = lo + rng() as i32 % (v.points as i32 - lo);
                    bounds.push(lo);
                    bounds.push(hi);
                }
                for _ in 0..=dim {
                    weights.push(match rng() % 12 {
                        0 => 0.0,
                        1 => -0.0,
                        2 => f64::NAN,
                        3 => f64::INFINITY,
                        4 => f64::NEG_INFINITY,
                        5 => 2.5,
                        _ => (rng() % 2001) as f64 / 8.0 - 125.0,
                    });
                }
            }
            let f =
                IvpFunction::from_flat(dom.clone(), bounds.clone(), weights, vec![0; dim]).unwrap();
            let (a, b) = (f.min_max_wt(), min_max_wt_reference(&f));
            assert_eq!(
                bits(&[a.0, a.1]),
                bits(&[b.0, b.1]),
                "round {round}: {a:?} {b:?}"
            );
            // Normalizing in two passes gives each weight what the per-piece loop gives.
            let mut g = f.clone();
            g.normalize_from((-3.0, 17.5), 1.0, 100.0);
            let (shift, scale) = (1.0 - -3.0, 100.0 / (17.5 - -3.0));
            let mut want = f.weights().to_vec();
            for w in want.chunks_exact_mut(dim + 1) {
                w[dim] += shift;
                for x in w.iter_mut() {
                    *x *= scale;
                }
            }
            assert_eq!(bits(g.weights()), bits(&want), "round {round}");
            // Spoil one bound now and then.
            if n > 0 && round % 2 == 0 {
                let k = rng() as usize % bounds.len();
                bounds[k] = match rng() % 3 {
                    0 => -1,
                    1 => bounds[k] + 1 + rng() as i32 % 50,
                    _ => i32::MAX,
                };
            }
            assert_eq!(
                layout::bounds_in_range(&dom, &bounds),
                in_range_reference(&dom, &bounds),
                "round {round}: {bounds:?}"
            );
        }
    }

    /// The bits of each value, every NaN as the canonical NaN (Rust leaves an arithmetic
    /// NaN's sign and payload unspecified; see tiling's tests).
    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter()
            .map(|x| {
                if x.is_nan() {
                    f64::NAN.to_bits()
                } else {
                    x.to_bits()
                }
            })
            .collect()
    }
}
