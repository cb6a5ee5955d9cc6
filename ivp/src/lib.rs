//! # ivp — IvP domains, functions and builders
//!
//! An **IvP function** is a piecewise-linear utility function over a discrete
//! decision domain (e.g. `course × speed`). Each piece is a box of grid indices
//! with a linear interior function `w_0*x_0 + … + w_{n-1}*x_{n-1} + w_n` on the
//! indices. The solver, which picks the grid point maximizing the sum of several
//! weighted IvP functions with the reference helm's exact tie-breaking, is its own
//! crate (`ivp-solver`, built on this one). This crate depends on no helm, MOOS or
//! ABI crate: only `mbutil` (the number formatter, and the spare buffers that let
//! builders reuse their storage).
//!
//! ```
//! use ivp::{Domain, ZaicPeak, couple};
//!
//! let dom = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
//! let mut crs = ZaicPeak::new(&dom, "course").unwrap();
//! crs.set_value_wrap(true);
//! crs.set_params(63.4, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
//! let mut spd = ZaicPeak::new(&dom, "speed").unwrap();
//! spd.set_params(2.0, 1.0, 1.6, 20.0, 0.0, 100.0, 0);
//! let mut f = couple(crs.extract(true).unwrap(), spd.extract(true).unwrap(), 50.0, 50.0, true).unwrap();
//! f.set_pwt(100.0);
//! assert_eq!(f.domain().size(), 2);
//! ```
//!
//! ## Storage and the plugin ABI boundary
//!
//! [`IvpFunction`] is plain data: its [`Domain`], and its pieces stored
//! contiguously in two flat buffers, `bounds: Vec<i32>` (`lo, hi` per dimension
//! per piece) and `weights: Vec<f64>` (slopes then intercept per piece), plus
//! `pwt`, `context` and `gelbox`. To hand a function across the behavior-plugin
//! ABI, call [`IvpFunction::into_raw_parts`] and **move** each `Vec` into an
//! `abi_stable::std_types::RVec` (`RVec::from(vec)` reuses the allocation: no
//! per-iteration deep copy); on the other side turn the `RVec`s back into
//! `Vec`s (`into_vec`) and rebuild with [`IvpFunction::from_raw_parts`], which
//! validates the layout. [`RawFunction::grid`] (the builder-made grid bounds,
//! possibly empty) must travel with the other buffers: the solver prunes with
//! it exactly as the reference does, which settles rare floating-point
//! near-ties.
//!
//! Modules: [`domain`], [`function`], [`zaic`], [`coupler`], [`values_key`]. The OF_Reflector is the
//! crate `ivp-reflector` (a few hidden items here are public for it alone); the
//! BHV_IPF text of a function is the crate `ivp-ipf`.

// Index loops over dimensions read closest to the spec's formulas.
#![allow(clippy::needless_range_loop)]

pub mod coupler;
pub mod domain;
pub mod error;
pub mod function;
pub mod values_key;
pub mod zaic;

pub use coupler::{couple, try_couple, try_couple_normalized};
pub use domain::{Domain, DomainVar, Snap};
pub use error::IvpError;
pub use function::{IvpFunction, Piece, PieceSpec, RawFunction};
pub use values_key::ValuesKey;
pub use zaic::{ZaicHeq, ZaicLeq, ZaicPeak, ZaicSpd, ZaicVector};
