//! The ABI-safe form of an IvP function.
//!
//! A behavior's objective function crosses from plugin to host as plain buffers: pieces
//! are stored contiguously (`bounds`: lo,hi per dimension per piece; `weights`: one slope
//! per dimension then the intercept, per piece). `RVec` carries its own deallocator, so the
//! host can take ownership of the plugin's buffers without copying them.

use abi_stable::std_types::{RString, RVec};
use abi_stable::StableAbi;

/// An IvP function of degree 1 as plain data.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, Default, PartialEq)]
pub struct FunctionData {
    /// The function's own domain, `name,low,high,points` per variable joined by `:`
    /// (the helm's `domainToString` form), in the function's dimension order.
    pub domain: RString,
    /// `2 * dim` integers per piece: `lo_0, hi_0, lo_1, hi_1, ...` (inclusive indices).
    pub bounds: RVec<i32>,
    /// `dim + 1` numbers per piece: slopes in dimension order, then the intercept.
    pub weights: RVec<f64>,
    /// Priority weight.
    pub pwt: f64,
    /// Grid cell size minus one per dimension (`points - 1` for a single cell).
    pub gelbox: RVec<u32>,
    /// Grid cell upper bounds as the builder left them (empty = none): the solver's
    /// pruning, and so exact ties in rare near-tie cases, depend on them.
    pub grid: RVec<f64>,
}

impl FunctionData {
    /// Number of dimensions, from the domain string.
    pub fn dim(&self) -> usize {
        if self.domain.is_empty() {
            0
        } else {
            self.domain.as_str().split(':').count()
        }
    }

    /// Number of pieces, or `None` when the buffers disagree with each other.
    pub fn piece_count(&self) -> Option<usize> {
        let dim = self.dim();
        if dim == 0 || !self.bounds.len().is_multiple_of(2 * dim) {
            return None;
        }
        let n = self.bounds.len() / (2 * dim);
        (self.weights.len() == n * (dim + 1)).then_some(n)
    }
}

impl FunctionData {
    /// Move an `ivp` function into the ABI form: the piece buffers are moved, not copied.
    pub fn from_ivp(f: ivp::IvpFunction) -> FunctionData {
        // One string of about the right size, written in place (not grown step by step).
        let mut domain = String::with_capacity(32 * f.dim());
        let _ = std::fmt::Write::write_fmt(&mut domain, format_args!("{}", f.domain()));
        let raw = f.into_raw_parts();
        FunctionData {
            domain: domain.into(),
            bounds: raw.bounds.into(),
            weights: raw.weights.into(),
            pwt: raw.pwt,
            gelbox: raw.gelbox.into(),
            grid: raw.grid.into(),
        }
    }

    /// Variable names of the function's domain, in dimension order.
    pub fn var_names(&self) -> impl Iterator<Item = &str> {
        self.domain
            .as_str()
            .split(':')
            .filter(|s| !s.is_empty())
            .map(|v| v.split(',').next().unwrap_or(""))
    }
}

impl From<ivp::IvpFunction> for FunctionData {
    fn from(f: ivp::IvpFunction) -> Self {
        FunctionData::from_ivp(f)
    }
}
