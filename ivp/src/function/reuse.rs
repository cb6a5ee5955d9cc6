//! Functions rebuilt every iteration live in the buffers of the ones dropped before
//! them (issue 19: a helm iteration allocates nothing in steady state), kept per
//! thread in `mbutil::spare` (domains in `crate::domain`).

use super::{check_buffers, grid_total, IvpFunction};
use crate::domain::Domain;
use crate::error::IvpError;
use mbutil::spare;

impl IvpFunction {
    /// Give this function's buffers to the builders of later functions on this thread
    /// (the helm does this with every function once it has solved).
    pub fn recycle(self) {
        // One visit to the thread's storage for the four piece buffers.
        spare::give_function_buffers(self.bounds, self.weights, self.gelbox, self.grid);
        spare::give_string(self.context);
        crate::domain::give_domain(self.domain);
    }

    /// Move out the piece buffers (bounds, weights, gel box, grid), leaving them empty:
    /// the rest of the function can then be recycled apart.
    pub fn take_buffers(&mut self) -> (Vec<i32>, Vec<f64>, Vec<u32>, Vec<f64>) {
        (
            std::mem::take(&mut self.bounds),
            std::mem::take(&mut self.weights),
            std::mem::take(&mut self.gelbox),
            std::mem::take(&mut self.grid),
        )
    }

    /// [`IvpFunction::from_raw_parts`] over a domain built apart (e.g. by
    /// [`Domain::from_var_refs`]), checked the same way; the context string is a spare.
    pub fn from_buffers(
        domain: Domain,
        bounds: Vec<i32>,
        weights: Vec<f64>,
        gelbox: Vec<u32>,
        grid: Vec<f64>,
        pwt: f64,
    ) -> Result<IvpFunction, IvpError> {
        check_buffers(&domain, &bounds, &weights, &gelbox, &grid)?;
        let context = spare::string();
        let f = Self::of_parts(domain, bounds, weights, gelbox, grid);
        Ok(IvpFunction { pwt, context, ..f })
    }

    /// Unchecked constructor for builders of this crate (layout is correct by
    /// construction), with the gel box (the whole domain) in a spare buffer.
    pub(crate) fn assemble(domain: Domain, bounds: Vec<i32>, weights: Vec<f64>) -> IvpFunction {
        let mut gelbox = spare::uints();
        gelbox.extend(domain.vars().iter().map(|v| v.points.saturating_sub(1)));
        IvpFunction::of_parts(domain, bounds, weights, gelbox, Vec::new())
    }

    /// [`IvpFunction::build_grid`] for a builder's function, in a spare buffer: with the
    /// whole domain as gel box there is one cell, the max over the pieces (the same
    /// rule as there); any other gel box goes to `build_grid`.
    pub(crate) fn build_whole_grid(&mut self) {
        let dim = self.dim();
        if dim == 0 || grid_total(&self.domain, &self.gelbox) != 1 {
            self.build_grid();
            return;
        }
        let mut g = std::mem::take(&mut self.grid);
        if g.capacity() == 0 {
            g = spare::floats();
        }
        g.clear();
        g.push(self.whole_domain_max());
        self.grid = g;
    }
}
