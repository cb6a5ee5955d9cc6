//! Functions read in place: borrowed buffers checked like an owned function's, so a
//! host can solve a plugin's function without copying it.

use std::sync::Arc;

use ivp::{Domain, IvpError, IvpFunction};

/// The read-only side of an [`IvpFunction`] over borrowed buffers (same layout).
#[derive(Clone, Copy, Debug)]
pub struct FunctionView<'a> {
    domain: &'a Domain,
    bounds: &'a [i32],
    weights: &'a [f64],
    gelbox: &'a [u32],
    grid: &'a [f64],
    pwt: f64,
}

impl<'a> FunctionView<'a> {
    /// The pieces `bounds`/`weights` over `domain` with their gel box and grid, checked
    /// as [`IvpFunction::from_buffers`] checks its own (the same errors): they may come
    /// from a plugin, so nothing about them is trusted.
    pub fn checked(
        domain: &'a Domain,
        bounds: &'a [i32],
        weights: &'a [f64],
        gelbox: &'a [u32],
        grid: &'a [f64],
        pwt: f64,
    ) -> Result<FunctionView<'a>, IvpError> {
        ivp::function::check_buffers(domain, bounds, weights, gelbox, grid)?;
        Ok(FunctionView {
            domain,
            bounds,
            weights,
            gelbox,
            grid,
            pwt,
        })
    }

    pub fn domain(&self) -> &'a Domain {
        self.domain
    }
    pub fn dim(&self) -> usize {
        self.domain.size()
    }
    pub fn piece_count(&self) -> usize {
        self.weights.len() / (self.dim() + 1)
    }
    pub fn bounds(&self) -> &'a [i32] {
        self.bounds
    }
    pub fn weights(&self) -> &'a [f64] {
        self.weights
    }
    pub fn gelbox(&self) -> &'a [u32] {
        self.gelbox
    }
    /// Grid cell upper bounds (empty = no grid).
    pub fn grid_bounds(&self) -> &'a [f64] {
        self.grid
    }
    pub fn pwt(&self) -> f64 {
        self.pwt
    }
}

/// An owned function is valid by construction: its view needs no check.
impl<'a> From<&'a IvpFunction> for FunctionView<'a> {
    fn from(f: &'a IvpFunction) -> Self {
        FunctionView {
            domain: f.domain(),
            bounds: f.bounds(),
            weights: f.weights(),
            gelbox: f.gelbox(),
            grid: f.grid_bounds(),
            pwt: f.pwt(),
        }
    }
}

/// A function's buffers kept where they were made (e.g. a plugin's ABI form). Each
/// method returns the same every time (plain fields).
pub trait PieceBuffers {
    fn bounds(&self) -> &[i32];
    fn weights(&self) -> &[f64];
    fn gelbox(&self) -> &[u32];
    fn grid(&self) -> &[f64];
    fn pwt(&self) -> f64;
}

/// Buffers checked once over a domain, then viewed without checking again: only `&P`
/// is ever lent out, so they cannot change after the check.
#[derive(Debug)]
pub struct CheckedFunction<P> {
    parts: P,
    domain: Arc<Domain>,
}

impl<P: PieceBuffers> CheckedFunction<P> {
    /// `parts` over `domain`, checked as [`FunctionView::checked`] does; the parts come
    /// back with the error when they are rejected.
    pub fn new(parts: P, domain: Arc<Domain>) -> Result<CheckedFunction<P>, (P, IvpError)> {
        let (b, w, g, grid) = (
            parts.bounds(),
            parts.weights(),
            parts.gelbox(),
            parts.grid(),
        );
        match ivp::function::check_buffers(&domain, b, w, g, grid) {
            Ok(()) => Ok(CheckedFunction { parts, domain }),
            Err(e) => Err((parts, e)),
        }
    }

    /// The checked function, read in place.
    pub fn view(&self) -> FunctionView<'_> {
        FunctionView {
            domain: &self.domain,
            bounds: self.parts.bounds(),
            weights: self.parts.weights(),
            gelbox: self.parts.gelbox(),
            grid: self.parts.grid(),
            pwt: self.parts.pwt(),
        }
    }

    /// The parts themselves (read only).
    pub fn parts(&self) -> &P {
        &self.parts
    }

    /// The buffers, e.g. to hand back to their maker.
    pub fn into_parts(self) -> P {
        self.parts
    }
}
