//! OF_Coupler (spec §4): two functions over disjoint variables → one function.

use crate::error::IvpError;
use crate::function::{dim_map, translate_into, IvpFunction};

/// `couple(f1, f2, w1, w2)`: normalize f1 to `[0,w1]` and f2 to `[0,w2]`,
/// then every `p ∩ q` (f1 outer, f2 inner) with summed weights over
/// `union(dom f1, dom f2)`; if `normalize`, the result is normalized to `[0,100]`.
/// `None` if `w1 <= 0`, `w2 <= 0`, or the variable sets overlap.
pub fn couple(
    f1: IvpFunction,
    f2: IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Option<IvpFunction> {
    try_couple(f1, f2, w1, w2, normalize).ok()
}

/// As [`couple`] with a typed error.
pub fn try_couple(
    mut f1: IvpFunction,
    mut f2: IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Result<IvpFunction, IvpError> {
    if w1.is_nan() || w1 <= 0.0 {
        return Err(IvpError::Invalid {
            param: "w1".into(),
            reason: format!("must be > 0 (got {w1})"),
        });
    }
    if w2.is_nan() || w2 <= 0.0 {
        return Err(IvpError::Invalid {
            param: "w2".into(),
            reason: format!("must be > 0 (got {w2})"),
        });
    }
    if f2
        .domain()
        .vars()
        .iter()
        .any(|v| f1.domain().index_of(&v.name).is_some())
    {
        return Err(IvpError::Couple("the functions share a variable".into()));
    }
    f1.normalize(0.0, w1);
    f2.normalize(0.0, w2);
    let dom = f1.domain().union(f2.domain());
    let td = dom.size();
    let (mut b1, mut ww1, mut b2, mut ww2) = (vec![], vec![], vec![], vec![]);
    translate_into(
        f1.bounds(),
        f1.weights(),
        f1.dim(),
        &dim_map(f1.domain(), &dom)?,
        &dom,
        &mut b1,
        &mut ww1,
    );
    translate_into(
        f2.bounds(),
        f2.weights(),
        f2.dim(),
        &dim_map(f2.domain(), &dom)?,
        &dom,
        &mut b2,
        &mut ww2,
    );
    let (n1, n2) = (f1.piece_count(), f2.piece_count());
    let (bl, wl) = (2 * td, td + 1);
    let mut bounds = Vec::with_capacity(n1 * n2 * bl);
    let mut weights = Vec::with_capacity(n1 * n2 * wl);
    for p in 0..n1 {
        let (pb, pw) = (&b1[p * bl..(p + 1) * bl], &ww1[p * wl..(p + 1) * wl]);
        for q in 0..n2 {
            let (qb, qw) = (&b2[q * bl..(q + 1) * bl], &ww2[q * wl..(q + 1) * wl]);
            let disjoint =
                (0..td).any(|d| pb[2 * d].max(qb[2 * d]) > pb[2 * d + 1].min(qb[2 * d + 1]));
            if disjoint {
                continue;
            }
            for d in 0..td {
                bounds.push(pb[2 * d].max(qb[2 * d]));
                bounds.push(pb[2 * d + 1].min(qb[2 * d + 1]));
            }
            weights.extend(pw.iter().zip(qw).map(|(a, b)| a + b));
        }
    }
    let mut out = IvpFunction::new_unchecked(dom, bounds, weights);
    if normalize {
        out.normalize(0.0, 100.0);
    }
    Ok(out)
}
