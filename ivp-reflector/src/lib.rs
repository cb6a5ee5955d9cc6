//! # ivp-reflector — the OF_Reflector
//!
//! An **analytical objective function** ([`Aof`]) gives a utility at any grid point
//! of an `ivp` domain; the [`Reflector`] (spec §8) approximates it by the linear
//! pieces of an [`ivp::IvpFunction`] on a uniform tiling, optionally with constant
//! plateau and basin regions cut out. It depends on `ivp` and `mbutil` alone: no
//! helm, MOOS or ABI crate. Behaviors reach it as `behavior_api::ivp::Reflector`
//! (behavior-api re-exports it beside `ivp`'s items).
//!
//! ```
//! use ivp::Domain;
//! use ivp_reflector::{Aof, Reflector};
//!
//! /// Utility falls off with the distance of the course from 90.
//! struct East;
//! impl Aof for East {
//!     fn eval(&self, dom: &Domain, index: &[u32]) -> f64 {
//!         100.0 - (dom.value(0, index[0]) - 90.0).abs() / 1.8
//!     }
//! }
//!
//! let dom = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
//! let mut r = Reflector::new(&dom, &East);
//! assert!(r.set_param("uniform_piece", "discrete@course:10,speed:41"));
//! r.create(None, None);
//! let f = r.extract(true).unwrap();
//! assert_eq!(f.domain().size(), 2);
//! ```
//!
//! Modules: [`reflector`] (the builder, and the AOF trait and region helpers that
//! behaviors use through `reflector::…`).

// Index loops over dimensions read closest to the spec's formulas.
#![allow(clippy::needless_range_loop)]

mod aof;
mod fit;
pub mod reflector;
mod regions;
mod tiling;

pub use reflector::{Aof, Reflector};
