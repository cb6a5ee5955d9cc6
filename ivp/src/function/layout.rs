//! The layout check of a function's pieces (every function that crosses the plugin ABI
//! goes through it).

use super::grid_total;
use crate::domain::Domain;
use crate::error::{bad_piece, invalid, IvpError};

/// [`crate::IvpFunction::from_buffers`]'s check, for buffers read in place (a plugin's).
pub fn check_buffers(
    domain: &Domain,
    bounds: &[i32],
    weights: &[f64],
    gelbox: &[u32],
    grid: &[f64],
) -> Result<(), IvpError> {
    check_layout(domain, bounds, weights, gelbox)?;
    let cells = if grid.is_empty() {
        0
    } else {
        grid_total(domain, gelbox)
    };
    if grid.len() != cells {
        return Err(invalid("grid", format!("needs {cells} cell bounds")));
    }
    Ok(())
}

pub(super) fn check_layout(
    domain: &Domain,
    bounds: &[i32],
    weights: &[f64],
    gelbox: &[u32],
) -> Result<(), IvpError> {
    let dim = domain.size();
    if dim == 0 {
        if bounds.is_empty() && weights.is_empty() {
            return Ok(());
        }
        return Err(bad_piece(0, "pieces over an empty domain"));
    }
    let bl = 2 * dim;
    let wl = dim + 1;
    if bounds.len() / bl * bl != bounds.len()
        || weights.len() / wl * wl != weights.len()
        || bounds.len() / bl != weights.len() / wl
    {
        return Err(bad_piece(
            0,
            "bounds/weights lengths do not match the dimension",
        ));
    }
    if gelbox.len() != dim {
        return Err(invalid("gelbox", format!("needs {dim} entries")));
    }
    // Every function crossing the ABI is checked piece by piece: first whether all
    // pieces are in range (no branch per piece), and only when one is not, which one.
    if bounds_in_range(domain, bounds) {
        return Ok(());
    }
    // Highest index per dimension, looked up once.
    let tops: Vec<i64> = domain
        .vars()
        .iter()
        .map(|v| i64::from(v.points) - 1)
        .collect();
    for (k, b) in bounds.chunks_exact(bl).enumerate() {
        for (d, &top) in tops.iter().enumerate() {
            let (lo, hi) = (b[2 * d], b[2 * d + 1]);
            if lo < 0 || lo > hi || i64::from(hi) > top {
                return Err(IvpError::BadPiece {
                    piece: k,
                    reason: format!(
                        "bounds [{lo},{hi}] outside 0..={top} of `{}`",
                        domain.var(d).name
                    ),
                });
            }
        }
    }
    Ok(())
}

/// Whether every piece's `lo, hi` satisfy `0 <= lo <= hi <= points - 1` in every
/// dimension (`bounds` holds whole pieces of `domain`'s dimension, at least 1).
pub(super) fn bounds_in_range(domain: &Domain, bounds: &[i32]) -> bool {
    #[cfg(target_arch = "x86_64")]
    let simd = std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let simd = false;
    in_range_with(domain, bounds, simd)
}

/// Bounds checked in one pass: 24 is a whole number of pieces for 1 to 4 dimensions.
const RUN: usize = 24;

/// [`bounds_in_range`], with the AVX2 body if `simd`.
fn in_range_with(domain: &Domain, bounds: &[i32], simd: bool) -> bool {
    let n = domain.size();
    let mut tops = [0i32; 4];
    for (d, t) in tops.iter_mut().enumerate().take(n) {
        // A top of -1 (no points) holds no bound.
        match u32::try_from(i64::from(domain.var(d).points) - 1) {
            Ok(top) => *t = top.min(i32::MAX as u32) as i32,
            Err(_) => return bounds.is_empty(),
        }
    }
    if n > 4 {
        return bounds.chunks_exact(2 * n).all(|b| {
            (0..n).all(|d| {
                let (lo, hi) = (b[2 * d], b[2 * d + 1]);
                lo >= 0 && lo <= hi && i64::from(hi) < i64::from(domain.var(d).points)
            })
        });
    }
    let tops = &tops[..n];
    if bounds.len() < RUN {
        // Most functions are a few pieces.
        return signs_of(bounds, tops) >= 0;
    }
    // Each bound's top, for a run of bounds starting on a piece.
    let mut pattern = [0i32; RUN];
    let mut d = 0;
    for pair in pattern.chunks_exact_mut(2) {
        pair.fill(tops[d]);
        d = if d + 1 == n { 0 } else { d + 1 };
    }
    let mut runs = bounds.chunks_exact(RUN);
    let mut signs = 0;
    #[cfg(target_arch = "x86_64")]
    if simd {
        // SAFETY: the caller found AVX2.
        signs = unsafe { signs_avx2(&mut runs, &pattern) };
    }
    for run in runs.by_ref() {
        signs |= signs_of(run, tops);
    }
    signs |= signs_of(runs.remainder(), tops);
    signs >= 0
}

/// The or of `lo`, `hi - lo`, `top - lo` and `top - hi` (wrapping) over the pairs of
/// `bounds` (whole pieces, `tops` per dimension): its sign is clear exactly when every
/// pair has `0 <= lo <= hi <= top` (for `0 <= top <= i32::MAX`). A `lo` in `0..=top`
/// leaves no wrap in the others except `hi - lo` for a very negative `hi`, and then
/// `top - hi` wraps negative. One rule for every bound, without a branch: it vectorizes.
fn signs_of(bounds: &[i32], tops: &[i32]) -> i32 {
    let (mut acc, mut d) = (0, 0);
    for b in bounds.chunks_exact(2) {
        let (lo, hi, top) = (b[0], b[1], tops[d]);
        acc |= lo | hi.wrapping_sub(lo) | top.wrapping_sub(lo) | top.wrapping_sub(hi);
        d = if d + 1 == tops.len() { 0 } else { d + 1 };
    }
    acc
}

/// [`signs_of`]'s answer over the whole runs left in `runs`, eight bounds a register:
/// a bound minus the one before it in its 64-bit lane gives `lo` and `hi - lo` in one
/// subtraction (their signs or-ed), and each lane's unsigned maximum, compared with its
/// top once at the end, holds every bound in `0..=top` (for `top <= i32::MAX`): then
/// `hi - lo` cannot wrap and its sign is `hi < lo`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn signs_avx2(runs: &mut std::slice::ChunksExact<'_, i32>, tops: &[i32; RUN]) -> i32 {
    use std::arch::x86_64::*;
    // SAFETY (all loads here): `tops` and every run hold 24 readable `i32`s.
    let (tp, mut acc) = (tops.as_ptr(), _mm256_setzero_si256());
    let t = unsafe { [0, 8, 16].map(|k| _mm256_loadu_si256(tp.add(k).cast())) };
    let mut most = [_mm256_setzero_si256(); 3];
    for run in runs.by_ref() {
        for (k, most) in most.iter_mut().enumerate() {
            let b = unsafe { _mm256_loadu_si256(run.as_ptr().add(8 * k).cast()) };
            let pairs = _mm256_sub_epi32(b, _mm256_slli_epi64::<32>(b));
            acc = _mm256_or_si256(acc, pairs);
            *most = _mm256_max_epu32(*most, b);
        }
    }
    // A lane above its top: `max(most, top) != top`.
    let mut over = _mm256_setzero_si256();
    for (most, &top) in most.iter().zip(&t) {
        let within = _mm256_cmpeq_epi32(_mm256_max_epu32(*most, top), top);
        over = _mm256_or_si256(over, _mm256_xor_si256(within, _mm256_set1_epi32(-1)));
    }
    // Any lane's sign set: a negative result.
    let any = _mm256_or_si256(acc, over);
    -i32::from(_mm256_movemask_ps(_mm256_castsi256_ps(any)) != 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain per-piece rule.
    fn reference(domain: &Domain, bounds: &[i32]) -> bool {
        bounds.chunks_exact(2 * domain.size()).all(|b| {
            domain.vars().iter().enumerate().all(|(d, v)| {
                let (lo, hi) = (b[2 * d], b[2 * d + 1]);
                lo >= 0 && lo <= hi && i64::from(hi) < i64::from(v.points)
            })
        })
    }

    /// Every bound of functions of 1 to 6 dimensions and 0 to 30 pieces (whole runs
    /// and remainders) spoiled in turn, in every way, with and without AVX2: the
    /// answer is the plain rule's.
    #[test]
    fn a_bad_bound_anywhere_is_found_as_the_plain_rule_finds_it() {
        let simd = [false, std::arch::is_x86_feature_detected!("avx2")];
        let specs = ["a:0:9:10", "a:0:9:10,b:0:0:1", "a:0:9:10,b:0:4:5,c:0:20:21"];
        let more = [
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3",
            "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3,e:0:7:8",
        ];
        let six = "a:0:9:10,b:0:4:5,c:0:20:21,d:0:2:3,e:0:7:8,f:0:1:2";
        let mut seed = 7u64;
        let mut rng = move |n: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) % n
        };
        for spec in specs.iter().chain(&more).chain([&six]) {
            let dom = Domain::parse(spec).unwrap();
            let dim = dom.size();
            for pieces in 0..=30 {
                let mut good = Vec::new();
                for _ in 0..pieces {
                    for v in dom.vars() {
                        let lo = rng(u64::from(v.points)) as i32;
                        good.extend([lo, lo + rng(u64::from(v.points) - lo as u64) as i32]);
                    }
                }
                for &on in &simd {
                    assert!(in_range_with(&dom, &good, on), "{spec} {good:?}");
                }
                for k in 0..good.len() {
                    let top = dom.var((k / 2) % dim).points as i32 - 1;
                    let other = good[k ^ 1];
                    for v in [-1, i32::MIN, top, top + 1, i32::MAX, other - 1, other + 1] {
                        let mut b = good.clone();
                        b[k] = v;
                        for &on in &simd {
                            let want = reference(&dom, &b);
                            assert_eq!(in_range_with(&dom, &b, on), want, "{spec} {k} {b:?}");
                        }
                    }
                }
            }
        }
        // A variable with a top of i32::MAX or more, and none with no points.
        let wide = Domain::parse("a:0:1:4294967295,b:0:9:10").unwrap();
        for b in [
            [0, i32::MAX, 0, 9],
            [-1, 5, 0, 9],
            [3, 2, 0, 9],
            [0, 0, 0, 10],
        ] {
            for &on in &simd {
                assert_eq!(in_range_with(&wide, &b, on), reference(&wide, &b), "{b:?}");
            }
        }
    }
}
