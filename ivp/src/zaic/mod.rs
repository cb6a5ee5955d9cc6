//! ZAIC builders: one-dimensional IvP functions from a few parameters (spec §3).
//!
//! Setters mirror the C++ names in snake_case and return `bool` like the C++
//! ones (the `call_ok` of the conformance cases). `extract` returns `None` when
//! the builder state is bad; `try_extract` returns the typed reason instead.

mod heq;
mod peak;
mod peak_scan;
mod shape;
pub use mbutil::spare;
mod spd;
mod vector;

pub use heq::{ZaicHeq, ZaicLeq};
pub use peak::ZaicPeak;
pub use spd::ZaicSpd;
pub use vector::ZaicVector;

use crate::domain::Domain;
use crate::error::{invalid, IvpError};
use crate::function::IvpFunction;

/// The one-variable domain of a builder.
pub(crate) fn one_var(domain: &Domain, var: &str) -> Result<Domain, IvpError> {
    match domain.index_of(var) {
        // In a spare domain's storage (every builder is made again every iteration).
        Some(i) => Ok(crate::domain::domain_of(&domain.vars()[i..=i])),
        None => Err(IvpError::UnknownVar(var.to_string())),
    }
}

/// Accumulates 1-D pieces in order.
#[derive(Default, Clone, Debug)]
pub(crate) struct Pieces1 {
    pub(crate) bounds: Vec<i32>,
    pub(crate) weights: Vec<f64>,
}

impl Pieces1 {
    /// Empty, in spare buffers with room for the usual few pieces, so the pushes do not
    /// regrow them step by step on every build.
    pub(crate) fn spare() -> Pieces1 {
        let (mut bounds, mut weights) = (spare::ints(), spare::floats());
        bounds.reserve(2 * SAMPLE_PIECES);
        weights.reserve(2 * SAMPLE_PIECES);
        Pieces1 { bounds, weights }
    }

    /// Emptied for new pieces, in spare buffers if it has none.
    pub(crate) fn reset(&mut self) {
        if self.bounds.capacity() == 0 {
            *self = Pieces1::spare();
        }
        self.bounds.clear();
        self.weights.clear();
    }

    /// Its buffers to the spares.
    pub(crate) fn give_back(self) {
        spare::give_ints(self.bounds);
        spare::give_floats(self.weights);
    }

    /// One piece (a capacity check per buffer, not per number).
    pub(crate) fn push(&mut self, lo: i32, hi: i32, slope: f64, intercept: f64) {
        self.bounds.extend_from_slice(&[lo, hi]);
        self.weights.extend_from_slice(&[slope, intercept]);
    }

    /// "Box(a, ra, b, rb)": slope `(rb-ra)/(b-a)` (0 if a == b), intercept `ra - slope*a`;
    /// the piece covers `[lo, b]`.
    pub(crate) fn push_anchor(&mut self, lo: i32, a: i32, ra: f64, b: i32, rb: f64) {
        let slope = if a == b {
            0.0
        } else {
            (rb - ra) / f64::from(b - a)
        };
        self.push(lo, b, slope, ra - slope * f64::from(a));
    }

    /// The function, with its (single-cell) grid built as the reference builders do.
    pub(crate) fn finish(self, domain: Domain) -> IvpFunction {
        let mut f = IvpFunction::assemble(domain, self.bounds, self.weights);
        f.build_whole_grid();
        f
    }
}

/// Pieces a sampled ZAIC usually has (a peak with wrap: under a dozen).
const SAMPLE_PIECES: usize = 16;

/// Piece construction from sampled values (spec §3.1, tolerance 0.001). The skipping
/// scan (`peak_scan`) follows it step for step: a change here is a change there.
pub(crate) fn pieces_from_samples(v: &[f64]) -> Pieces1 {
    let mut out = Pieces1::spare();
    let n = v.len();
    if n < 2 {
        return out;
    }
    let tol = 0.001;
    let (mut first, mut fv) = (0usize, v[0]);
    let (mut trend, mut m, mut b) = (false, 0.0f64, 0.0f64);
    let chord = |first: usize, fv: f64, end: usize, ve: f64| {
        if end == first {
            0.0
        } else {
            (ve - fv) / (end - first) as f64
        }
    };
    for i in 1..n {
        let (vp, vi) = (v[i - 1], v[i]);
        let fi = i as f64;
        if !trend {
            m = (vi - fv) / (i - first) as f64;
            b = vi - m * fi;
            trend = true;
        }
        let mut brk = ((m * fi + b) - vi).abs() > tol;
        let lm = vi - vp;
        if (lm < 0.0 && m > 0.0) || (lm > 0.0 && m < 0.0) {
            brk = true;
        }
        if i == n - 1 {
            if brk {
                out.push(i as i32, i as i32, 0.0, vi);
            } else {
                let s = chord(first, fv, i, vi);
                out.push(first as i32, i as i32, s, fv - s * first as f64);
            }
        }
        if brk {
            let s = chord(first, fv, i - 1, vp);
            out.push(first as i32, (i - 1) as i32, s, fv - s * first as f64);
            trend = false;
            first = i;
            fv = vi;
        }
    }
    out
}

/// PDMapBuilder (spec §3.3): strictly increasing anchors from 0 to N-1.
pub(crate) fn pieces_from_anchors(d: &[i32], r: &[f64], n: i32) -> Option<Pieces1> {
    let k = d.len();
    if k == 0
        || k != r.len()
        || d[0] != 0
        || d[k - 1] != n - 1
        || d.windows(2).any(|w| w[0] >= w[1])
    {
        return None;
    }
    let mut out = Pieces1::spare();
    if k == 1 {
        out.push_anchor(d[0], d[0], r[0], d[0], r[0]);
        return Some(out);
    }
    if k == 2 {
        out.push_anchor(d[0], d[0], r[0], d[1], r[1]);
        return Some(out);
    }
    for i in 0..k - 1 {
        if i == 0 {
            out.push_anchor(d[0], d[0], r[0], d[1], r[1]);
        } else if d[i] + 1 == d[i + 1] {
            if i + 1 == k - 1 {
                out.push_anchor(d[i + 1], d[i + 1], r[i + 1], d[i + 1], r[i + 1]);
            } else {
                out.push_anchor(d[i], d[i], r[i], d[i + 1], r[i + 1]);
            }
        } else {
            out.push_anchor(d[i] + 1, d[i], r[i], d[i + 1], r[i + 1]);
        }
    }
    Some(out)
}

/// A one-variable function from one utility per domain point of `var`, pieced exactly
/// as ZAIC_PEAK pieces its samples (spec §3.1, tolerance 0.001). For builders outside
/// this crate whose shape is not one of the ZAICs (the heading ZAIC of the COLREGS
/// behaviors).
///
/// ```
/// use ivp::{zaic::from_samples, Domain};
/// let d = Domain::parse("course:0:3:4").unwrap();
/// let f = from_samples(&d, "course", &[0.0, 50.0, 100.0, 100.0]).unwrap();
/// assert_eq!(f.piece_count(), 2);
/// assert!(from_samples(&d, "course", &[0.0]).is_err());
/// ```
pub fn from_samples(domain: &Domain, var: &str, values: &[f64]) -> Result<IvpFunction, IvpError> {
    let d = one_var(domain, var)?;
    if values.len() != d.var(0).points as usize || values.len() < 2 {
        return Err(invalid(
            "values",
            format!("{} values for {} points", values.len(), d.var(0).points),
        ));
    }
    for (k, &v) in values.iter().enumerate() {
        crate::error::finite(&format!("values[{k}]"), v)?;
    }
    Ok(pieces_from_samples(values).finish(d))
}
