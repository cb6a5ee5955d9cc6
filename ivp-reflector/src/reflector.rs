//! OF_Reflector (spec §8): approximate an analytical objective function (AOF)
//! by linear pieces on a uniform tiling.
//!
//! Implemented: the uniform stage (`uniform_piece`, `uniform_grid`,
//! `uniform_amount` via the genUnifBox rule), the degree-1 fit with strict
//! range, and normalized extraction. **Not implemented:** directed refinement
//! (`refine_region`/`refine_piece`), smart refinement (`smart_amount`,
//! `smart_percent`: the reference picks random leaves, so it is not
//! reproducible anyway) and auto-peak; `create`'s smart amount is ignored.

pub use crate::aof::{eval_grid_2d, eval_grid_pointwise, Aof};
use crate::fit::{fit_values, takes_centre, FIT_DIMS};
pub use crate::regions::{box_subtract, intersects, IndexBox};
use ivp::domain::Domain;
use ivp::function::IvpFunction;
use mbutil::spare;
use std::mem::take;

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

impl<'a> Reflector<'a> {
    /// A reflector over a copy of `domain`, built in this thread's spare storage (see
    /// `mbutil::spare`; a behavior builds one every iteration).
    pub fn new(domain: &Domain, aof: &'a dyn Aof) -> Self {
        Reflector {
            domain: ivp::domain::domain_of(domain.vars()),
            aof,
            uniform_piece: None,
            uniform_grid: None,
            uniform_amount: 1,
            strict_range: true,
            bounds: spare::ints(),
            weights: spare::floats(),
            gelbox: spare::uints(),
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
        let parts = body.split(',').map(str::trim).filter(|p| !p.is_empty());
        self.box_of(parts.map(|part| {
            let (name, val) = part.split_once(':')?;
            Some((name.trim(), val.trim().parse().ok()?))
        }))
    }

    /// Box sizes from (variable, size) pairs (unnamed variables: 1); `None` for a pair
    /// that is `None`, names no variable or has size 0.
    fn box_of<'s>(&self, parts: impl Iterator<Item = Option<(&'s str, u32)>>) -> Option<Vec<u32>> {
        let mut sizes = spare::uints();
        sizes.resize(self.domain.size(), 1);
        for part in parts {
            let (name, v) = part?;
            let d = self.domain.index_of(name)?;
            if v == 0 {
                return None;
            }
            sizes[d] = v;
        }
        Some(sizes)
    }

    /// `uniform_piece` and `uniform_grid` from (variable, size) pairs, as
    /// [`Reflector::set_param`] takes `"discrete @ course:3,speed:3"` but without reading
    /// the text (a behavior sets them every build). False, and that one left unset,
    /// for a box with an unknown variable or a size 0.
    pub fn set_uniform(&mut self, piece: &[(&str, u32)], grid: &[(&str, u32)]) -> bool {
        let piece = self.box_of(piece.iter().map(|&p| Some(p)));
        let grid = self.box_of(grid.iter().map(|&p| Some(p)));
        let ok = piece.is_some() && grid.is_some();
        self.uniform_piece = piece.or(self.uniform_piece.take());
        self.uniform_grid = grid.or(self.uniform_grid.take());
        ok
    }

    /// Parameters: `uniform_piece`, `uniform_grid` (box strings), `uniform_amount`
    /// (integer ≥ 1), `strict_range` (`true`/`false`). Unknown names return false.
    pub fn set_param(&mut self, name: &str, value: &str) -> bool {
        // Names in any case, compared without a lowered copy (set every build).
        let known = [
            "uniform_piece",
            "uniform_grid",
            "uniform_amount",
            "strict_range",
        ];
        let key = known
            .into_iter()
            .find(|k| name.trim().eq_ignore_ascii_case(k))
            .unwrap_or("");
        match key {
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
            "strict_range" => {
                let v = value.trim();
                let yes = v.eq_ignore_ascii_case("true");
                let known = yes || v.eq_ignore_ascii_case("false");
                self.strict_range = if known { yes } else { self.strict_range };
                known
            }
            _ => {
                self.warnings.push_str("unhandled param: ");
                self.warnings.push_str(name);
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
        if self.domain.size() == 0 {
            return 0;
        }
        // Tile sizes and counts in spare buffers (this runs every iteration).
        let (mut size, mut counts) = (spare::uints(), spare::uints());
        match &self.uniform_piece {
            Some(s) => size.extend_from_slice(s),
            None => size.extend(self.unif_box(unif_amount.unwrap_or(self.uniform_amount).max(1))),
        }
        self.gelbox.clear();
        let gel = self.uniform_grid.as_deref().unwrap_or(&size);
        self.gelbox.extend(gel.iter().map(|s| s.saturating_sub(1)));
        let vars = self.domain.vars().iter().zip(&size);
        counts.extend(vars.map(|(v, &s)| v.points.div_ceil(s)));
        let pieces = self.create_tiles(&size, &counts);
        spare::give_uints(size);
        spare::give_uints(counts);
        pieces
    }

    /// [`Reflector::create`] with tiles of edge `size`, `counts` of them per dimension.
    fn create_tiles(&mut self, size: &[u32], counts: &[u32]) -> usize {
        let n = size.len();
        let total: usize = counts.iter().map(|&c| c as usize).product();
        self.summary = None;
        if !self.regions.is_empty() {
            return self.create_with_regions(size, counts, total);
        }
        // Tiles with dimension 0 varying fastest; the reference stores them reversed, so
        // tile i (dimension 0 fastest) is visited from the last to the first. Each tile is
        // computed in place: no per-tile allocation (this runs for thousands of pieces per
        // behavior per iteration).
        self.bounds.clear();
        self.weights.clear();
        // Fits shared by tiles equal in every dimension the AOF uses (and in whether the
        // fit takes the centre point), when it ignores some dimension: slot = the tile's
        // coordinates in the used dimensions (mixed radix) × 2 + centre.
        let sharing = (0..n).any(|d| self.aof.ignores(d));
        if self.grid_eval && !sharing && n <= FIT_DIMS {
            let grid = spare::floats();
            let mut summary = crate::tiling::Summary {
                grid,
                ..Default::default()
            };
            crate::tiling::fit_uniform(
                self.aof,
                &self.domain,
                size,
                counts,
                self.strict_range,
                &self.gelbox,
                &mut self.bounds,
                &mut self.weights,
                &mut summary,
            );
            self.summary = Some(summary);
            return total;
        }
        // Tile by tile (allocated only here: the grid fit above needs none of these).
        self.bounds.reserve(total * 2 * n);
        self.weights.reserve(total * (n + 1));
        let mut tile = vec![(0u32, 0u32); n];
        let mut w = vec![0.0; n + 1];
        let used: Vec<bool> = (0..n).map(|d| !self.aof.ignores(d)).collect();
        let slots: usize = if sharing {
            2 * (0..n)
                .filter(|&d| used[d])
                .map(|d| counts[d] as usize)
                .product::<usize>()
        } else {
            0
        };
        let mut shared: Vec<Option<usize>> = vec![None; slots];
        for i in (0..total).rev() {
            let mut rest = i;
            let mut slot = 0usize;
            for d in 0..n {
                let c = (rest % counts[d] as usize) as u32;
                rest /= counts[d] as usize;
                let points = self.domain.var(d).points;
                tile[d] = (c * size[d], ((c + 1) * size[d]).min(points) - 1);
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
        if !self.has_pieces() {
            return None;
        }
        let summary = self.summary.as_ref().map(|s| crate::tiling::Summary {
            grid: s.grid.clone(),
            min_max: s.min_max,
            pieces: None,
            weights_pending: false,
        });
        let (domain, bounds) = (self.domain.clone(), self.bounds.clone());
        let (mut weights, gelbox) = (self.weights.clone(), self.gelbox.clone());
        let pending = self.summary.iter().filter(|s| s.weights_pending);
        pending
            .flat_map(|s| &s.pieces)
            .for_each(|p| p.write_weights(&mut weights, None));
        Self::function(domain, bounds, weights, gelbox, summary, normalize, false)
    }

    /// [`Reflector::extract`] for a reflector used once: the pieces move into the
    /// function instead of being copied.
    pub fn into_function(mut self, normalize: bool) -> Option<IvpFunction> {
        self.take_function(normalize, false)
    }

    /// [`Reflector::into_function`]`(true)` then [`IvpFunction::normalize`]`(0, 100)` on
    /// the result, bit for bit (the contact behaviors normalize the reflector's
    /// normalized function once more): the second normalization's value range is taken
    /// while the first one writes the weights, instead of in a pass of its own.
    pub fn into_function_normalized_twice(mut self) -> Option<IvpFunction> {
        self.take_function(true, true)
    }

    /// The function of these pieces, moved out of the reflector (see [`Self::function`]).
    fn take_function(&mut self, normalize: bool, again: bool) -> Option<IvpFunction> {
        if !self.has_pieces() {
            return None;
        }
        let (domain, bounds) = (take(&mut self.domain), take(&mut self.bounds));
        let (weights, gelbox) = (take(&mut self.weights), take(&mut self.gelbox));
        let summary = self.summary.take();
        Self::function(domain, bounds, weights, gelbox, summary, normalize, again)
    }

    /// Whether `create` made pieces (their weights maybe only in the summary's lists).
    fn has_pieces(&self) -> bool {
        !self.weights.is_empty() || self.summary.as_ref().is_some_and(|s| s.weights_pending)
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
        let (mut weights, mut grid) = (weights, s.grid);
        let min_max = s.min_max.unwrap_or((0.0, 0.0));
        if let (true, Some(mut pieces)) = (s.weights_pending, s.pieces) {
            // Normalized several at a time as their weights are written out, or just written.
            let out = (&mut weights, &mut grid[..]);
            if normalize && pieces.normalize(min_max, (0.0, 100.0), again, out) {
                let f = IvpFunction::with_grid_unchecked(domain, bounds, weights, gelbox, grid);
                return Some(f);
            }
            pieces.write_weights(&mut weights, None);
        }
        let mut f = IvpFunction::with_grid_unchecked(domain, bounds, weights, gelbox, grid);
        if normalize && again {
            let min_max = f.normalize_from_and_min_max(min_max, 0.0, 100.0);
            f.normalize_from(min_max, 0.0, 100.0);
        } else if normalize {
            f.normalize_from(min_max, 0.0, 100.0);
        }
        Some(f)
    }
}

/// The storage a reflector still holds goes back to this thread's spares for the next
/// build (the pieces' buffers when no function took them).
impl Drop for Reflector<'_> {
    fn drop(&mut self) {
        ivp::domain::give_domain(take(&mut self.domain));
        spare::give_ints(take(&mut self.bounds));
        let grid = self.summary.take().map(|s| s.grid);
        let floats = [Some(take(&mut self.weights)), grid];
        floats.into_iter().flatten().for_each(spare::give_floats);
        let (piece, gel) = (self.uniform_piece.take(), self.uniform_grid.take());
        let uints = [piece, gel, Some(take(&mut self.gelbox))];
        uints.into_iter().flatten().for_each(spare::give_uints);
    }
}
