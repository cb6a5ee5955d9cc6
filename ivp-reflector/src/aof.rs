//! Analytical objective functions (AOFs): what the OF_Reflector (spec §8) approximates,
//! and the helpers that evaluate one over a whole grid.

use ivp::domain::Domain;

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
