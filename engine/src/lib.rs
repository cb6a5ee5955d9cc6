//! `helm-engine`: the IvP Helm itself, as a library driven from outside.
//!
//! A caller hands it mail and a time and takes its postings; it never reads a socket, a
//! wall clock or a thread of its own, and knows nothing of simulation. The MOOS app
//! (`helm-app`), the simulator (`helm-sim`) and the conformance runner ([`conform`]) all
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
//!   remembers for its terminal and its end;
//! - conformance cases are replayed by [`conform`].
//!
//! A golden case recorded from the C++ helm, replayed through the engine (mail and
//! times in, postings out, compared step by step):
//!
//! ```
//! use helm_engine::conform::{run_file, Outcome};
//! use helm_engine::factory::BehaviorFactory;
//! let case = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
//!     .join("../conformance/helm/two_wpt_weighted.toml");
//! let result = run_file(&case, &BehaviorFactory::with_builtins());
//! assert_eq!(result.outcome(), Outcome::Passed, "{:?}", result.mismatches);
//! ```

pub mod config;
pub mod conform;
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
