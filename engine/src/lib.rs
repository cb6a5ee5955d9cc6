//! `helm-engine`: the IvP Helm itself, as a library driven from outside.
//!
//! A caller hands it mail and a time and takes its postings; it never reads a socket, a
//! wall clock or a thread of its own, and knows nothing of simulation. The MOOS app
//! (`helm-app`), the simulator (`helm-sim`) and the conformance runner (`helm-conform`) all
//! drive it the same way, through [`cycle::HelmCycle`] or [`Helm`] directly.
//!
//! It may depend on `behavior-api`, `behaviors-std`, `bhv`, `ivp` and `moos-mission` (the
//! `.moos` file reader). It must not depend on the MOOS client or the DB (`moos`), the
//! app, or the simulator; a test in `helm/tests/layout.rs` checks that.
//!
//! Where things are:
//! - the pHelmIvP block is read in [`config`], a whole mission (`.moos` + `.bhv` files +
//!   behavior libraries) in [`mission`]; a `.bhv` line is parsed in the `bhv` crate;
//! - behaviors come from [`factory`] (built-in) and [`loader`] (shared libraries);
//! - a behavior is called in [`runtime`] (`runtime::step`, one behavior's part in one
//!   iteration), built-in and plugin alike through `behavior-api`;
//! - a decision is made in [`engine`]: `Helm::handle_mail` → `Helm::iterate` (modes,
//!   behaviors, `decide` with `ivp::Solver`, postings), with spawning and reports;
//! - [`cycle`] is one helm cycle as every driver runs it; [`status`] what a run
//!   remembers for its terminal and its end.
//! - conformance cases are replayed by the `helm-conform` crate.
//!
//! The repo's alpha mission read as pHelmIvP reads it (block, `.bhv` files, libraries):
//!
//! ```
//! let moos = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha/alpha.moos");
//! let loaded = helm_engine::mission::load(&moos, &[], "pHelmIvP").unwrap();
//! let (helm, _mission) = loaded.into_helm();
//! assert!(helm.config_warnings().is_empty());
//! assert!(helm.behavior_names().contains(&"waypt_survey".to_string()));
//! ```

pub mod config;
pub mod cycle;
pub mod engine;
pub mod factory;
pub mod info_buffer;
pub mod loader;
pub mod mission;
pub mod posting;
pub mod run_warnings;
pub mod runtime;
pub mod status;

pub use engine::{Helm, HelmState, Mail};
