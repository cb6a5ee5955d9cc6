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
    // As unsigned numbers `lo <= hi <= top` says it all (a negative `lo` or `hi` is
    // above any top up to i32::MAX), in two compares the compiler vectorizes when a
    // loop turn holds 8 bounds (or more): one 256-bit register.
    fn all_in<const N: usize, const K: usize>(bounds: &[i32], tops: &[u32]) -> bool {
        let (tops, mut bad) = (std::array::from_fn::<u32, N, _>(|d| tops[d]), false);
        let mut turns = bounds.chunks_exact(2 * N * K);
        let mut piece = |b: &[i32]| {
            for (d, &top) in tops.iter().enumerate() {
                let (lo, hi) = (b[2 * d] as u32, b[2 * d + 1] as u32);
                bad |= (lo > hi) | (hi > top);
            }
        };
        for b in &mut turns {
            b.chunks_exact(2 * N).for_each(&mut piece);
        }
        turns.remainder().chunks_exact(2 * N).for_each(piece);
        !bad
    }
    let n = domain.size();
    let mut tops = [0u32; 4];
    for (d, t) in tops.iter_mut().enumerate().take(n) {
        // A top of -1 (no points) holds no bound.
        match u32::try_from(i64::from(domain.var(d).points) - 1) {
            Ok(top) => *t = top.min(i32::MAX as u32),
            Err(_) => return bounds.is_empty(),
        }
    }
    match n {
        1 => all_in::<1, 4>(bounds, &tops),
        2 => all_in::<2, 2>(bounds, &tops),
        3 => all_in::<3, 2>(bounds, &tops),
        4 => all_in::<4, 1>(bounds, &tops),
        n => bounds.chunks_exact(2 * n).all(|b| {
            (0..n).all(|d| {
                let (lo, hi) = (b[2 * d], b[2 * d + 1]);
                lo >= 0 && lo <= hi && i64::from(hi) < i64::from(domain.var(d).points)
            })
        }),
    }
}
