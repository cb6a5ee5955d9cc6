//! The reflector's uniform stage fitted from two grid evaluations (ivp-solver.md §8):
//! every tile's corners lie on the grid of the tiles' low and high edges, and its centre
//! on the grid of their midpoints, so the AOF is asked for those two grids at once
//! ([`Aof::eval_grid`]) instead of point by point, and each tile's fit reads its values
//! from them. The pieces are those of the point-by-point fit bit for bit: the same
//! points, the same fit arithmetic ([`crate::reflector::fit_values`]).

use crate::domain::Domain;
use crate::reflector::{fit_values_n, Aof, FIT_DIMS};

/// The uniform tiling of `domain` by boxes of edge `size` (`counts` of them per
/// dimension, the last one clipped), fitted and appended to `bounds` and `weights` in the
/// reflector's order: tile `i` numbered with dimension 0 fastest, from the last tile to
/// the first. At most [`FIT_DIMS`] dimensions.
pub(crate) fn fit_uniform(
    aof: &dyn Aof,
    domain: &Domain,
    size: &[u32],
    counts: &[u32],
    strict: bool,
    bounds: &mut Vec<i32>,
    weights: &mut Vec<f64>,
) {
    let out = (bounds, weights);
    match size.len() {
        1 => fit_uniform_n::<1>(aof, domain, size, counts, strict, out),
        2 => fit_uniform_n::<2>(aof, domain, size, counts, strict, out),
        3 => fit_uniform_n::<3>(aof, domain, size, counts, strict, out),
        _ => fit_uniform_n::<FIT_DIMS>(aof, domain, size, counts, strict, out),
    }
}

/// [`fit_uniform`] for `N` dimensions (a constant, so the per-tile loops unroll).
fn fit_uniform_n<const N: usize>(
    aof: &dyn Aof,
    domain: &Domain,
    size: &[u32],
    counts: &[u32],
    strict: bool,
    (bounds, weights): (&mut Vec<i32>, &mut Vec<f64>),
) {
    let pts: Vec<u32> = domain.vars().iter().map(|v| v.points).collect();
    // Per dimension: the tiles' (low, high) edges side by side, and their midpoints.
    let edges: Vec<Vec<(u32, u32)>> = (0..N)
        .map(|d| {
            (0..counts[d])
                .map(|c| (c * size[d], ((c + 1) * size[d]).min(pts[d]) - 1))
                .collect()
        })
        .collect();
    let corner_axes: Vec<Vec<u32>> = edges
        .iter()
        .map(|e| e.iter().flat_map(|&(lo, hi)| [lo, hi]).collect())
        .collect();
    let mid_axes: Vec<Vec<u32>> = edges
        .iter()
        .map(|e| e.iter().map(|&(lo, hi)| lo + (hi - lo) / 2).collect())
        .collect();
    let mut corners = Scratch::take();
    evaluate(aof, domain, &corner_axes, &mut corners.0);
    // Some tile takes its centre exactly when some dimension has a tile wider than 2.
    let any_centre = (0..N).any(|d| size[d].min(pts[d]) > 2);
    let mut mids = Scratch::take();
    if any_centre {
        evaluate(aof, domain, &mid_axes, &mut mids.0);
    }
    // Strides of the two grids (dimension 0 fastest).
    let mut corner_stride = [0usize; N];
    let mut mid_stride = [0usize; N];
    let (mut cs, mut ms) = (1usize, 1usize);
    for d in 0..N {
        corner_stride[d] = cs;
        mid_stride[d] = ms;
        cs *= 2 * counts[d] as usize;
        ms *= counts[d] as usize;
    }
    // Where each corner (bit d of the mask = high end in dimension d) lies from the
    // tile's low corner in the corner grid.
    let corner_offset: [usize; 1 << FIT_DIMS] = std::array::from_fn(|mask| {
        (0..N)
            .filter(|&d| mask & (1 << d) != 0)
            .map(|d| corner_stride[d])
            .sum()
    });
    let total: usize = counts.iter().map(|&c| c as usize).product();
    bounds.reserve(total * 2 * N);
    weights.reserve(total * (N + 1));
    let mut coord: [usize; N] = std::array::from_fn(|d| counts[d] as usize - 1);
    let mut vals = [0.0f64; (1 << FIT_DIMS) + 1];
    let mut w = [0.0f64; FIT_DIMS + 1];
    let ncorner = 1usize << N;
    for _ in 0..total {
        let b: [(u32, u32); N] = std::array::from_fn(|d| edges[d][coord[d]]);
        let (mut corner_at, mut mid_at) = (0usize, 0usize);
        for d in 0..N {
            bounds.push(b[d].0 as i32);
            bounds.push(b[d].1 as i32);
            corner_at += 2 * coord[d] * corner_stride[d];
            mid_at += coord[d] * mid_stride[d];
        }
        for mask in 0..ncorner {
            vals[mask] = corners.0[corner_at + corner_offset[mask]];
        }
        let mut m = ncorner;
        if b.iter().any(|&(lo, hi)| hi - lo + 1 > 2) {
            vals[m] = mids.0[mid_at];
            m += 1;
        }
        fit_values_n::<N>(&b, &vals[..m], strict, &mut w[..=N]);
        weights.extend_from_slice(&w[..=N]);
        // The previous tile: dimension 0 counts down first.
        for d in 0..N {
            if coord[d] > 0 {
                coord[d] -= 1;
                break;
            }
            coord[d] = counts[d] as usize - 1;
        }
    }
}

/// A grid-values buffer kept per thread between builds (a behavior builds every
/// iteration; the buffer is taken out while in use, so a nested build gets its own).
struct Scratch(Vec<f64>);

thread_local! {
    static SCRATCH: std::cell::Cell<Vec<Vec<f64>>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Scratch {
    fn take() -> Scratch {
        Scratch(SCRATCH.with(|s| {
            let mut pool = s.take();
            let v = pool.pop().unwrap_or_default();
            s.set(pool);
            v
        }))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let v = std::mem::take(&mut self.0);
        SCRATCH.with(|s| {
            let mut pool = s.take();
            if pool.len() < 4 {
                pool.push(v);
            }
            s.set(pool);
        });
    }
}

/// The AOF's values on the grid `axes[0] × axes[1] × …` into `out` (resized to fit).
fn evaluate(aof: &dyn Aof, domain: &Domain, axes: &[Vec<u32>], out: &mut Vec<f64>) {
    let len: usize = axes.iter().map(Vec::len).product();
    // Zeroed, not left from the last build: an AOF's eval_grid should fill every slot.
    out.clear();
    out.resize(len, 0.0);
    let mut refs: [&[u32]; FIT_DIMS] = [&[]; FIT_DIMS];
    for (r, a) in refs.iter_mut().zip(axes) {
        *r = a;
    }
    aof.eval_grid(domain, &refs[..axes.len()], &mut out[..len]);
}

#[cfg(test)]
mod tests {
    use crate::{Aof, Domain, Reflector};

    fn rng(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A bumpy surface with flat clipped stretches (ties in the strict-range shift).
    struct Bumps {
        k: Vec<f64>,
        clip: f64,
    }

    impl Aof for Bumps {
        fn eval(&self, domain: &Domain, index: &[u32]) -> f64 {
            let mut u = 0.0;
            for (d, &i) in index.iter().enumerate() {
                let x = domain.value(d, i);
                u += (x * self.k[d]).sin() * 40.0 + x * self.k[d + 3];
            }
            u.clamp(-self.clip, self.clip)
        }
    }

    /// Fitting from the two grid evaluations gives the pieces of fitting tile by tile,
    /// bit for bit, over random domains (1 to 3 dimensions, clipped last tiles, edges of
    /// 1 to 6 points) and random surfaces, plain and normalized.
    #[test]
    fn grid_evaluation_equals_tile_by_tile() {
        let mut seed = 7u64;
        for case in 0..600 {
            let dims = 1 + case % 3;
            let mut spec = Vec::new();
            let mut piece = Vec::new();
            for d in 0..dims {
                let points = 1 + (rng(&mut seed) * 60.0) as u32;
                let low = (rng(&mut seed) * 20.0).floor() - 10.0;
                let high = low + (points.max(2) - 1) as f64 * (0.1 + rng(&mut seed));
                let points = if points == 1 { 1 } else { points };
                let high = if points == 1 { low } else { high };
                spec.push(format!("x{d}:{low}:{high}:{points}"));
                piece.push(format!("x{d}:{}", 1 + (rng(&mut seed) * 6.0) as u32));
            }
            let Ok(domain) = Domain::parse(&spec.join(",")) else {
                continue;
            };
            let aof = Bumps {
                k: (0..6).map(|_| rng(&mut seed) * 2.0 - 1.0).collect(),
                clip: 10.0 + rng(&mut seed) * 60.0,
            };
            let strict = case % 4 != 3;
            let build = |r: Reflector<'_>| {
                let mut r = r;
                r.set_param("uniform_piece", &format!("discrete@{}", piece.join(",")));
                r.set_param("strict_range", if strict { "true" } else { "false" });
                let n = r.create(None, None);
                let f = r.extract(case % 2 == 0).expect("pieces");
                let bits: Vec<u64> = f.weights().iter().map(|w| w.to_bits()).collect();
                (n, f.bounds().to_vec(), bits)
            };
            let grid = build(Reflector::new(&domain, &aof));
            let tiles = build(Reflector::new(&domain, &aof).tile_by_tile());
            assert_eq!(grid, tiles, "case {case}: {spec:?} {piece:?}");
        }
    }

    /// Values with ties, signed zeros, NaNs and infinities, from a hash of the point.
    struct Awkward(u64);

    impl Aof for Awkward {
        fn eval(&self, _: &Domain, index: &[u32]) -> f64 {
            let mut h = self.0;
            for &i in index {
                h = (h ^ u64::from(i)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            }
            match (h >> 59) % 16 {
                0 => 0.0,
                1 => -0.0,
                2 => f64::NAN,
                3 => f64::INFINITY,
                4 => 7.0,
                5 => -7.0,
                _ => ((h >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 200.0,
            }
        }
    }

    /// The fit of 1 to 4 dimensions ([`Reflector::fit_into`], with its shortcuts) is the
    /// general fit ([`Reflector::fit`], the spec's arithmetic) bit for bit, awkward
    /// values included, strict range or not.
    #[test]
    fn fit_shortcuts_equal_the_general_fit() {
        let mut seed = 3u64;
        for case in 0..20000u64 {
            let n = 1 + (case % 4) as usize;
            let d = Domain::parse(
                &["a:0:99:100", "b:0:99:100", "c:0:99:100", "d:0:99:100"][..n].join(","),
            )
            .unwrap();
            let aof = Awkward(case);
            let mut r = Reflector::new(&d, &aof);
            if case % 3 == 0 {
                r.set_param("strict_range", "false");
            }
            let b: Vec<(u32, u32)> = (0..n)
                .map(|_| {
                    let lo = (rng(&mut seed) * 90.0) as u32;
                    (lo, lo + (rng(&mut seed) * 5.0) as u32)
                })
                .collect();
            let mut w = vec![0.0; n + 1];
            r.fit_into(&b, &mut w);
            let want = r.fit(&b);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&w), bits(&want), "case {case}: {b:?}");
        }
    }
}
