//! What a solver slot was last prepared from, so that an unchanged function is not
//! prepared again (see `Solver::prepare`).

use crate::view::FunctionView;
use ivp::Domain;

/// What a slot was last prepared from; the slot's boxes are its `src_bounds`.
#[derive(Debug, Default)]
pub(crate) struct MadeFrom {
    pub(crate) on: bool,
    domain: Domain,
    weights: Vec<u64>,
    gelbox: Vec<u32>,
    grid: Vec<u64>,
    pwt: u64,
    first: bool,
    /// Fresh preparations of the slot in a row.
    pub(crate) misses: u32,
}

/// The bits of `x` equal `key`, element by element (NaN and signed zeros told apart).
pub(crate) fn same_bits(key: &[u64], x: &[f64]) -> bool {
    key.len() == x.len() && key.iter().zip(x).all(|(&k, v)| k == v.to_bits())
}

impl MadeFrom {
    pub(crate) fn set(&mut self, f: &FunctionView<'_>, first: bool) {
        // (A domain's names would be allocated anew by `clone_from`.)
        if self.domain != *f.domain() {
            self.domain.clone_from(f.domain());
        }
        self.weights.clear();
        self.weights.extend(f.weights().iter().map(|w| w.to_bits()));
        self.gelbox.clear();
        self.gelbox.extend_from_slice(f.gelbox());
        self.grid.clear();
        self.grid
            .extend(f.grid_bounds().iter().map(|w| w.to_bits()));
        self.pwt = f.pwt().to_bits();
        self.first = first;
        self.on = true;
    }

    /// Whether the slot (its boxes `src_bounds`) was last prepared from `f` at the
    /// same level (`first`).
    pub(crate) fn matches(&self, src_bounds: &[i32], f: &FunctionView<'_>, first: bool) -> bool {
        // The weights first: what changes when anything does.
        self.on
            && same_bits(&self.weights, f.weights())
            && self.first == first
            && self.pwt == f.pwt().to_bits()
            && src_bounds == f.bounds()
            && self.gelbox == f.gelbox()
            && same_bits(&self.grid, f.grid_bounds())
            && self.domain == *f.domain()
    }
}
