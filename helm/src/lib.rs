//! `helm`: the IvP Helm host.
//!
//! Where things are:
//! - a `.bhv` line is parsed in the `bhv` crate (`bhv::reader`), the pHelmIvP block in
//!   [`config`];
//! - a behavior is called in [`runtime`] (`runtime::step`, one behavior's part in one
//!   iteration), built-in and plugin alike through `behavior-api`;
//! - a decision is solved in [`engine`] (`Helm::iterate` → `decide` → `ivp::Solver`);
//! - conformance cases are replayed by [`conform`].

pub mod app;
pub mod appcast;
pub mod config;
pub mod conform;
pub mod engine;
pub mod factory;
pub mod info_buffer;
pub mod loader;
pub mod mission;
pub mod phelmivp;
pub mod posting;
pub mod runtime;
pub mod sim;
pub mod vehicle;

pub use engine::{Helm, HelmState, Mail};
