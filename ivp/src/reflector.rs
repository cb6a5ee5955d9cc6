//! OF_Reflector (spec §8): approximate an analytical objective function (AOF)
//! by linear pieces on a uniform tiling.
//!
//! Implemented: the uniform stage (`uniform_piece`, `uniform_grid`,
//! `uniform_amount` via the genUnifBox rule), the degree-1 fit with strict
//! range, and normalized extraction. **Not implemented:** directed refinement
//! (`refine_region`/`refine_piece`), smart refinement (`smart_amount`,
//! `smart_percent`: the reference picks random leaves, so it is not
//! reproducible anyway) and auto-peak; `create`'s smart amount is ignored.

use crate::domain::Domain;
use crate::function::IvpFunction;
pub use crate::regions::{box_subtract, intersects, IndexBox};

/// An analytical objective function over a domain's grid.
pub trait Aof {
    /// Utility at grid point `index` (one index per variable of `domain`).
    fn eval(&self, domain: &Domain, index: &[u32]) -> f64;
    /// Whether the utility ignores dimension `dim` entirely (BHV_AvoidObstacleV24's
    /// speed, say): tiles that differ only there then share one fit, which is the same
    /// fit bit for bit (that dimension's slope is exactly 0). Default: no.
    fn ignores(&self, _dim: usize) -> bool {
        false
    }
    /// Utilities at every point of the grid `axes[0] × axes[1] × …` (one list of indices
    /// per variable of `domain`) into `out`, dimension 0 fastest: the point
    /// `(axes[0][i0], axes[1][i1], …)` goes to `out[i0 + len0·(i1 + len1·(…))]`, and
    /// `out` holds the product of the axes' lengths. The reflector asks for its tiles'
    /// corners and centres this way. An AOF may override it to do per-course work once
    /// for all speeds, but must give exactly what [`Aof::eval`] gives at each point (the
    /// pieces are the same bit for bit either way). Default: [`eval_grid_pointwise`].
    fn eval_grid(&self, domain: &Domain, axes: &[&[u32]], out: &mut [f64]) {
        eval_grid_pointwise(self, domain, axes, out);
    }
    /// Whether [`Aof::eval_grid`] writes every slot of `out`, whatever it was given.
    /// The reflector then hands it a buffer left from the last build instead of a
    /// zeroed one (an AOF that may skip slots gets zeros there, as always). Default:
    /// no; the default `eval_grid` does fill every slot, but an override may not.
    fn eval_grid_fills(&self) -> bool {
        false
    }
}

/// [`Aof::eval_grid`] by one [`Aof::eval`] per point (the default, and a fallback for
/// AOFs whose batched form covers only some domains).
pub fn eval_grid_pointwise<A: Aof + ?Sized>(
    aof: &A,
    domain: &Domain,
    axes: &[&[u32]],
    out: &mut [f64],
) {
    let n = axes.len();
    if n == 0 || axes.iter().any(|a| a.is_empty()) {
        return;
    }
    let mut at = vec![0usize; n];
    let mut index: Vec<u32> = axes.iter().map(|a| a[0]).collect();
    for slot in out.iter_mut() {
        *slot = aof.eval(domain, &index);
        // Next point, dimension 0 fastest.
        for d in 0..n {
            at[d] += 1;
            if at[d] < axes[d].len() {
                index[d] = axes[d][at[d]];
                break;
            }
            at[d] = 0;
            index[d] = axes[d][0];
        }
    }
}

/// [`Aof::eval_grid`] for an AOF of the first two variables whose work splits in two:
/// `prep` of the first variable's value (once per index of `axes[0]`), then `point` of
/// that and the second variable's value, per grid point. `point(&prep(x), y)` must be
/// what [`Aof::eval`] gives at (x, y). Grids of other than two axes go point by point.
pub fn eval_grid_2d<A: Aof + ?Sized, T>(
    aof: &A,
    domain: &Domain,
    axes: &[&[u32]],
    out: &mut [f64],
    prep: impl Fn(f64) -> T,
    point: impl Fn(&T, f64) -> f64,
) {
    let [xs, ys] = axes else {
        return eval_grid_pointwise(aof, domain, axes, out);
    };
    if xs.is_empty() {
        return;
    }
    let prepared: Vec<T> = xs.iter().map(|&i| prep(domain.value(0, i))).collect();
    for (row, &j) in out.chunks_exact_mut(xs.len()).zip(ys.iter()) {
        let y = domain.value(1, j);
        for (o, p) in row.iter_mut().zip(&prepared) {
            *o = point(p, y);
        }
    }
}

/// The OF_Reflector builder.
pub struct Reflector<'a> {
    domain: Domain,
    aof: &'a dyn Aof,
    uniform_piece: Option<Vec<u32>>,
    uniform_grid: Option<Vec<u32>>,
    uniform_amount: usize,
    strict_range: bool,
    bounds: Vec<i32>,
    weights: Vec<f64>,
    gelbox: Vec<u32>,
    warnings: String,
    /// Plateau then basin boxes with their constant utility (see [`Reflector::add_region`]).
    regions: Vec<(IndexBox, f64)>,
    /// The search grid and value range of the pieces, when the fit gave them.
    summary: Option<crate::tiling::Summary>,
    /// Fit the uniform tiling from grid evaluations ([`crate::tiling`]); off only in
    /// tests, which compare it with fitting tile by tile.
    grid_eval: bool,
}

/// Boxes of up to this many dimensions are fitted without heap allocation.
pub(crate) const FIT_DIMS: usize = 4;

impl<'a> Reflector<'a> {
    pub fn new(domain: &Domain, aof: &'a dyn Aof) -> Self {
        Reflector {
            domain: domain.clone(),
            aof,
            uniform_piece: None,
            uniform_grid: None,
            uniform_amount: 1,
            strict_range: true,
            bounds: vec![],
            weights: vec![],
            gelbox: vec![],
            warnings: String::new(),
            regions: vec![],
            summary: None,
            grid_eval: true,
        }
    }

    /// This reflector fitting its uniform tiling tile by tile, one AOF call per point
    /// (the reference for the grid evaluation's tests).
    #[cfg(test)]
    pub(crate) fn tile_by_tile(mut self) -> Self {
        self.grid_eval = false;
        self
    }

    /// A region of known constant utility `value` (a plateau at the AOF's maximum or a
    /// basin at its minimum): the uniform tiling is cut around it and the region becomes
    /// one constant piece. Regions must be disjoint; add plateaus before basins, the
    /// pieces come in that order after the uniform ones. Ignored if the box does not fit
    /// the domain.
    pub fn add_region(&mut self, region: IndexBox, value: f64) {
        let fits = region.len() == self.domain.size()
            && region
                .iter()
                .zip(self.domain.vars())
                .all(|(&(lo, hi), v)| lo <= hi && hi < v.points);
        if fits {
            self.regions.push((region, value));
        }
    }

    /// Box sizes from `"discrete @ course:10,speed:5"` (unnamed variables: 1).
    fn parse_box(&self, s: &str) -> Option<Vec<u32>> {
        let body = s.trim();
        let body = body
            .strip_prefix("discrete")
            .map(str::trim_start)
            .and_then(|b| b.strip_prefix('@'))
            .unwrap_or(body);
        let mut sizes = vec![1u32; self.domain.size()];
        for part in body.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (name, val) = part.split_once(':')?;
            let d = self.domain.index_of(name.trim())?;
            let v: u32 = val.trim().parse().ok()?;
            if v == 0 {
                return None;
            }
            sizes[d] = v;
        }
        Some(sizes)
    }

    /// Parameters: `uniform_piece`, `uniform_grid` (box strings), `uniform_amount`
    /// (integer ≥ 1), `strict_range` (`true`/`false`). Unknown names return false.
    pub fn set_param(&mut self, name: &str, value: &str) -> bool {
        match name.trim().to_ascii_lowercase().as_str() {
            "uniform_piece" => self
                .parse_box(value)
                .map(|b| self.uniform_piece = Some(b))
                .is_some(),
            "uniform_grid" => self
                .parse_box(value)
                .map(|b| self.uniform_grid = Some(b))
                .is_some(),
            "uniform_amount" => match value.trim().parse::<usize>() {
                Ok(a) if a >= 1 => {
                    self.uniform_amount = a;
                    true
                }
                _ => false,
            },
            "strict_range" => match value.trim().to_ascii_lowercase().as_str() {
                "true" => {
                    self.strict_range = true;
                    true
                }
                "false" => {
                    self.strict_range = false;
                    true
                }
                _ => false,
            },
            _ => {
                self.warnings.push_str(&format!("unhandled param: {name}"));
                false
            }
        }
    }

    pub fn warnings(&self) -> &str {
        &self.warnings
    }

    /// genUnifBox: piece edge lengths for about `amount` pieces.
    fn unif_box(&self, amount: usize) -> Vec<u32> {
        let n = self.domain.size();
        let pts: Vec<u64> = self
            .domain
            .vars()
            .iter()
            .map(|v| u64::from(v.points))
            .collect();
        let mut splits = vec![1u64; n];
        let mut maxed: Vec<bool> = (0..n).map(|d| splits[d] >= pts[d]).collect();
        loop {
            let mut pick: Option<usize> = None;
            for d in 0..n {
                if maxed[d] {
                    continue;
                }
                let r = pts[d] as f64 / splits[d] as f64;
                if pick.is_none_or(|p| r > pts[p] as f64 / splits[p] as f64) {
                    pick = Some(d);
                }
            }
            let Some(d) = pick else { break };
            splits[d] += 1;
            let prod: u64 = splits.iter().product();
            if prod > amount as u64 {
                splits[d] -= 1;
                maxed[d] = true;
            } else if splits[d] >= pts[d] {
                maxed[d] = true;
            }
        }
        (0..n).map(|d| pts[d].div_ceil(splits[d]) as u32).collect()
    }

    /// Build the pieces (uniform stage + fit). `unif_amount` is used when no
    /// `uniform_piece` was set; `_smart_amount` is ignored (see module docs).
    /// Returns the number of pieces.
    pub fn create(&mut self, unif_amount: Option<usize>, _smart_amount: Option<usize>) -> usize {
        let n = self.domain.size();
        if n == 0 {
            return 0;
        }
        let size = match &self.uniform_piece {
            Some(s) => s.clone(),
            None => self.unif_box(unif_amount.unwrap_or(self.uniform_amount).max(1)),
        };
        self.gelbox = self
            .uniform_grid
            .clone()
            .unwrap_or_else(|| size.clone())
            .iter()
            .map(|s| s.saturating_sub(1))
            .collect();
        let pts: Vec<u32> = self.domain.vars().iter().map(|v| v.points).collect();
        let counts: Vec<u32> = (0..n).map(|d| pts[d].div_ceil(size[d])).collect();
        let total: usize = counts.iter().map(|&c| c as usize).product();
        self.summary = None;
        if !self.regions.is_empty() {
            return self.create_with_regions(&size, &counts, total);
        }
        // Tiles with dimension 0 varying fastest; the reference stores them reversed, so
        // tile i (dimension 0 fastest) is visited from the last to the first. Each tile is
        // computed in place: no per-tile allocation (this runs for thousands of pieces per
        // behavior per iteration).
        self.bounds.clear();
        self.weights.clear();
        self.bounds.reserve(total * 2 * n);
        self.weights.reserve(total * (n + 1));
        let mut tile = vec![(0u32, 0u32); n];
        let mut w = vec![0.0; n + 1];
        // Fits shared by tiles equal in every dimension the AOF uses (and in whether the
        // fit takes the centre point), when it ignores some dimension: slot = the tile's
        // coordinates in the used dimensions (mixed radix) × 2 + centre.
        let used: Vec<bool> = (0..n).map(|d| !self.aof.ignores(d)).collect();
        let sharing = used.iter().any(|u| !u);
        let slots: usize = if sharing {
            2 * (0..n)
                .filter(|&d| used[d])
                .map(|d| counts[d] as usize)
                .product::<usize>()
        } else {
            0
        };
        if self.grid_eval && !sharing && n <= FIT_DIMS {
            let mut summary = crate::tiling::Summary::default();
            crate::tiling::fit_uniform(
                self.aof,
                &self.domain,
                &size,
                &counts,
                self.strict_range,
                &self.gelbox,
                &mut self.bounds,
                &mut self.weights,
                &mut summary,
            );
            self.summary = Some(summary);
            return total;
        }
        let mut shared: Vec<Option<usize>> = vec![None; slots];
        for i in (0..total).rev() {
            let mut rest = i;
            let mut slot = 0usize;
            for d in 0..n {
                let c = (rest % counts[d] as usize) as u32;
                rest /= counts[d] as usize;
                tile[d] = (c * size[d], ((c + 1) * size[d]).min(pts[d]) - 1);
                if used[d] {
                    slot = slot * counts[d] as usize + c as usize;
                }
            }
            for &(lo, hi) in &tile {
                self.bounds.push(lo as i32);
                self.bounds.push(hi as i32);
            }
            if sharing {
                let centre = tile.iter().any(|&(lo, hi)| hi - lo + 1 > 2);
                let slot = 2 * slot + usize::from(centre);
                if let Some(at) = shared[slot] {
                    self.weights.extend_from_within(at..at + n + 1);
                    continue;
                }
                shared[slot] = Some(self.weights.len());
            }
            self.fit_into(&tile, &mut w);
            self.weights.extend_from_slice(&w);
        }
        total
    }

    /// The uniform stage cut around the regions, then the regions as constant pieces.
    fn create_with_regions(&mut self, size: &[u32], counts: &[u32], total: usize) -> usize {
        let n = size.len();
        let pts: Vec<u32> = self.domain.vars().iter().map(|v| v.points).collect();
        let tiles: Vec<IndexBox> = (0..total)
            .rev()
            .map(|i| {
                let mut rest = i;
                (0..n)
                    .map(|d| {
                        let c = (rest % counts[d] as usize) as u32;
                        rest /= counts[d] as usize;
                        (c * size[d], ((c + 1) * size[d]).min(pts[d]) - 1)
                    })
                    .collect()
            })
            .collect();
        let tiles = crate::regions::cut_around(tiles, &self.regions);
        self.bounds.clear();
        self.weights.clear();
        let mut w = vec![0.0; n + 1];
        for t in &tiles {
            for &(lo, hi) in t {
                self.bounds.push(lo as i32);
                self.bounds.push(hi as i32);
            }
            self.fit_into(t, &mut w);
            self.weights.extend_from_slice(&w);
        }
        for (r, value) in &self.regions {
            for &(lo, hi) in r {
                self.bounds.push(lo as i32);
                self.bounds.push(hi as i32);
            }
            self.weights.extend(std::iter::repeat_n(0.0, n));
            self.weights.push(*value);
        }
        tiles.len() + self.regions.len()
    }

    /// Degree-1 fit of one box (spec §8 step 3) into `w` (n slopes, then the intercept),
    /// from its corners and centre evaluated one by one. Up to [`FIT_DIMS`] dimensions
    /// the corners live on the stack.
    pub(crate) fn fit_into(&self, b: &[(u32, u32)], w: &mut [f64]) {
        let n = b.len();
        if n > FIT_DIMS || n == 0 {
            w.copy_from_slice(&self.fit(b));
            return;
        }
        let mut vals = [0.0f64; (1 << FIT_DIMS) + 1];
        let mut point = [0u32; FIT_DIMS];
        for mask in 0..1usize << n {
            for d in 0..n {
                point[d] = if mask & (1 << d) != 0 { b[d].1 } else { b[d].0 };
            }
            vals[mask] = self.aof.eval(&self.domain, &point[..n]);
        }
        let mut m = 1 << n;
        if takes_centre(b) {
            for d in 0..n {
                point[d] = b[d].0 + (b[d].1 - b[d].0) / 2;
            }
            vals[m] = self.aof.eval(&self.domain, &point[..n]);
            m += 1;
        }
        fit_values(b, &vals[..m], self.strict_range, w);
    }

    /// Degree-1 fit of one box of any dimension (spec §8 step 3); [`Self::fit_into`] is
    /// the same arithmetic with the corners on the stack.
    pub(crate) fn fit(&self, b: &[(u32, u32)]) -> Vec<f64> {
        let n = b.len();
        let ncorner = 1usize << n;
        let mut pt = vec![0u32; n];
        let mut vals = Vec::with_capacity(ncorner + 1);
        let mut points: Vec<Vec<u32>> = Vec::with_capacity(ncorner + 1);
        for mask in 0..ncorner {
            for d in 0..n {
                pt[d] = if mask & (1 << d) != 0 { b[d].1 } else { b[d].0 };
            }
            vals.push(self.aof.eval(&self.domain, &pt));
            points.push(pt.clone());
        }
        let mut w = vec![0.0; n + 1];
        for d in 0..n {
            let width = f64::from(b[d].1 - b[d].0);
            if width == 0.0 {
                continue;
            }
            let mut sum = 0.0;
            let mut cnt = 0.0;
            for mask in 0..ncorner {
                if mask & (1 << d) == 0 {
                    sum += vals[mask | (1 << d)] - vals[mask];
                    cnt += 1.0;
                }
            }
            w[d] = (sum / cnt) / width;
        }
        if b.iter().any(|&(lo, hi)| hi - lo + 1 > 2) {
            let c: Vec<u32> = b.iter().map(|&(lo, hi)| lo + (hi - lo) / 2).collect();
            vals.push(self.aof.eval(&self.domain, &c));
            points.push(c);
        }
        let plane = |w: &[f64], p: &[u32]| -> f64 {
            let mut acc = 0.0;
            for d in 0..n {
                acc += w[d] * f64::from(p[d]);
            }
            acc
        };
        let mut isum = 0.0;
        for (v, p) in vals.iter().zip(&points) {
            isum += v - plane(&w, p);
        }
        let mut icpt = isum / vals.len() as f64;
        if self.strict_range {
            let vmin = vals.iter().copied().fold(f64::INFINITY, f64::min);
            let vmax = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let pvals: Vec<f64> = points.iter().map(|p| plane(&w, p) + icpt).collect();
            let pmin = pvals.iter().copied().fold(f64::INFINITY, f64::min);
            let pmax = pvals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if pmax > vmax {
                icpt -= pmax - vmax;
            } else if pmin < vmin {
                icpt += vmin - pmin;
            }
        }
        w[n] = icpt;
        w
    }

    /// The function (normalized to `[0,100]` if `normalize`); `None` before `create`.
    pub fn extract(&self, normalize: bool) -> Option<IvpFunction> {
        if self.weights.is_empty() {
            return None;
        }
        let summary = self.summary.as_ref().map(|s| crate::tiling::Summary {
            grid: s.grid.clone(),
            min_max: s.min_max,
        });
        Self::function(
            self.domain.clone(),
            self.bounds.clone(),
            self.weights.clone(),
            self.gelbox.clone(),
            summary,
            normalize,
            false,
        )
    }

    /// [`Reflector::extract`] for a reflector used once: the pieces move into the
    /// function instead of being copied.
    pub fn into_function(self, normalize: bool) -> Option<IvpFunction> {
        if self.weights.is_empty() {
            return None;
        }
        Self::function(
            self.domain,
            self.bounds,
            self.weights,
            self.gelbox,
            self.summary,
            normalize,
            false,
        )
    }

    /// [`Reflector::into_function`]`(true)` then [`IvpFunction::normalize`]`(0, 100)` on
    /// the result, bit for bit (the contact behaviors normalize the reflector's
    /// normalized function once more): the second normalization's value range is taken
    /// while the first one writes the weights, instead of in a pass of its own.
    pub fn into_function_normalized_twice(self) -> Option<IvpFunction> {
        if self.weights.is_empty() {
            return None;
        }
        Self::function(
            self.domain,
            self.bounds,
            self.weights,
            self.gelbox,
            self.summary,
            true,
            true,
        )
    }

    /// The function of these pieces with its search grid, normalized if asked. The
    /// uniform fit hands over the grid and value range it took while fitting (what
    /// build_grid and min_max_wt would compute again from the pieces). `again`:
    /// normalized a second time (only with `normalize`).
    fn function(
        domain: Domain,
        bounds: Vec<i32>,
        weights: Vec<f64>,
        gelbox: Vec<u32>,
        summary: Option<crate::tiling::Summary>,
        normalize: bool,
        again: bool,
    ) -> Option<IvpFunction> {
        let Some(s) = summary else {
            let mut f = IvpFunction::from_flat(domain, bounds, weights, gelbox).ok()?;
            f.build_grid();
            if normalize {
                f.normalize(0.0, 100.0);
                if again {
                    f.normalize(0.0, 100.0);
                }
            }
            return Some(f);
        };
        let mut f = IvpFunction::with_grid_unchecked(domain, bounds, weights, gelbox, s.grid);
        let min_max = s.min_max.unwrap_or((0.0, 0.0));
        if normalize && again {
            let min_max = f.normalize_from_and_min_max(min_max, 0.0, 100.0);
            f.normalize_from(min_max, 0.0, 100.0);
        } else if normalize {
            f.normalize_from(min_max, 0.0, 100.0);
        }
        Some(f)
    }
}

/// Whether the fit of box `b` takes its centre point too (some edge spans more than 2
/// grid points).
fn takes_centre(b: &[(u32, u32)]) -> bool {
    b.iter().any(|&(lo, hi)| hi - lo + 1 > 2)
}

/// The degree-1 fit of box `b` (1 to [`FIT_DIMS`] dimensions) from its values: `vals`
/// holds the corners (`vals[mask]`, bit d of `mask` set = dimension d at its high end)
/// and, when [`takes_centre`], the centre last. The n slopes then the intercept go to
/// `w`. Spec §8 step 3: slopes from the mean corner differences, intercept from the mean
/// residual, shifted into the values' range when `strict`.
pub(crate) fn fit_values(b: &[(u32, u32)], vals: &[f64], strict: bool, w: &mut [f64]) {
    match b.len() {
        1 => fit_values_n::<1>(b, vals, strict, w),
        2 => fit_values_n::<2>(b, vals, strict, w),
        3 => fit_values_n::<3>(b, vals, strict, w),
        _ => fit_values_n::<FIT_DIMS>(b, vals, strict, w),
    }
}

/// [`fit_values`] for `N` dimensions: [`fit_box`] on the box and values copied into
/// fixed-size arrays.
pub(crate) fn fit_values_n<const N: usize>(
    b: &[(u32, u32)],
    vals: &[f64],
    strict: bool,
    w: &mut [f64],
) {
    let ncorner = 1usize << N;
    let lo: [u32; N] = std::array::from_fn(|d| b[d].0);
    let hi: [u32; N] = std::array::from_fn(|d| b[d].1);
    let mut v = [0.0f64; (1 << FIT_DIMS) + 1];
    v[..vals.len()].copy_from_slice(vals);
    let mut out = [0.0f64; FIT_DIMS + 1];
    if vals.len() > ncorner {
        fit_box::<N, true>(&lo, &hi, &v, strict, &mut out);
    } else {
        fit_box::<N, false>(&lo, &hi, &v, strict, &mut out);
    }
    w[..=N].copy_from_slice(&out[..=N]);
}

/// `q / width` as an `f64` division, by a multiplication when `width` is a power of two:
/// `q · 2⁻ᵏ` and `q / 2ᵏ` are the same exact real number, rounded once the same way
/// (subnormal results included), so the same bits; the multiplication does not wait on
/// the divider. `width` is not 0 (a zero-width dimension has slope 0, not divided).
#[inline(always)]
pub(crate) fn div_by_width(q: f64, width: u32) -> f64 {
    if width.is_power_of_two() {
        // Exact: 1 / 2^k for k < 32.
        q * (1.0 / f64::from(width))
    } else {
        q / f64::from(width)
    }
}

/// The degree-1 fit of the box `lo..=hi` from `vals`: the corners (`vals[mask]`, bit d
/// of `mask` set = dimension d at its high end), then, when `CENTRE`, the centre at
/// `vals[2^N]`. The n slopes then the intercept go to `w[..=N]`. `N` and `CENTRE` are
/// constants, so every loop unrolls and the values stay in registers.
///
/// The arithmetic is [`Reflector::fit`]'s, with two exact shortcuts: each point's plane
/// value is computed once and used for both the mean residual and the range check, and
/// the minima and maxima are taken by comparison. Those skip NaNs as `f64::min`/`max`
/// do (the running value starts infinite, never NaN) and may differ from them only in
/// the sign of a zero, which the shift (a difference of two values known to be unequal)
/// never shows.
#[inline(always)]
pub(crate) fn fit_box<const N: usize, const CENTRE: bool>(
    lo: &[u32; N],
    hi: &[u32; N],
    vals: &[f64; (1 << FIT_DIMS) + 1],
    strict: bool,
    w: &mut [f64; FIT_DIMS + 1],
) {
    let ncorner = 1usize << N;
    let m = ncorner + usize::from(CENTRE);
    let lof: [f64; N] = std::array::from_fn(|d| f64::from(lo[d]));
    let hif: [f64; N] = std::array::from_fn(|d| f64::from(hi[d]));
    for d in 0..N {
        let width = f64::from(hi[d] - lo[d]);
        if width == 0.0 {
            w[d] = 0.0;
            continue;
        }
        let mut sum = 0.0;
        let mut cnt = 0.0;
        for mask in 0..ncorner {
            if mask & (1 << d) == 0 {
                sum += vals[mask | (1 << d)] - vals[mask];
                cnt += 1.0;
            }
        }
        w[d] = div_by_width(sum / cnt, hi[d] - lo[d]);
    }
    // The plane (without intercept) at each corner, then at the centre.
    let mut plane = [0.0f64; (1 << FIT_DIMS) + 1];
    for (mask, p) in plane.iter_mut().enumerate().take(ncorner) {
        let mut acc = 0.0;
        for d in 0..N {
            acc += w[d] * if mask & (1 << d) != 0 { hif[d] } else { lof[d] };
        }
        *p = acc;
    }
    if CENTRE {
        let mut acc = 0.0;
        for d in 0..N {
            acc += w[d] * f64::from(lo[d] + (hi[d] - lo[d]) / 2);
        }
        plane[ncorner] = acc;
    }
    let mut isum = 0.0;
    for k in 0..m {
        isum += vals[k] - plane[k];
    }
    let mut icpt = isum / m as f64;
    if strict {
        let (mut vmin, mut vmax) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut pmin, mut pmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..m {
            let (v, p) = (vals[k], plane[k] + icpt);
            vmin = if v < vmin { v } else { vmin };
            vmax = if v > vmax { v } else { vmax };
            pmin = if p < pmin { p } else { pmin };
            pmax = if p > pmax { p } else { pmax };
        }
        if pmax > vmax {
            icpt -= pmax - vmax;
        } else if pmin < vmin {
            icpt += vmin - pmin;
        }
    }
    w[N] = icpt;
}
