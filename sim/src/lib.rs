//! `helm-sim`: `helm sim`, a mission in deterministic fast time, in one process.
//!
//! The helm (driven by the same [`helm_engine::cycle::HelmCycle`] as `helm run`), the
//! vehicle simulator ([`vehicle_model`]) and an in-process MOOS bus ([`bus`]) run on a
//! simulated clock ([`run`]); a [`scenario`] file adds pokes, end conditions and start
//! overrides; [`output`] writes the summary and [`picture`] the SVG; [`montecarlo`]
//! runs the mission many times with perturbed starts; [`cli`] is the command line
//! ([`args`] its arguments).
//! [`fleet`] runs several vehicles on one clock, with node reports between them, a
//! contact manager each and collision statistics.
//!
//! It may depend on `helm-engine`, `vehicle-model`, `moos` (for the `.alog` and mission
//! files; never a socket), `geometry`, `contact-manager` and `contacts`, and `mbutil`; it must not depend on `helm-app`, and nothing
//! but the `helm` binary depends on it.
//!
//! The repo's alpha mission, start to end, on a simulated clock:
//!
//! ```
//! use helm_sim::{Prepared, RunOptions, StartShift};
//! let mission = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha");
//! let prepared = Prepared::load(&mission, &[], None).unwrap();
//! let run = prepared.run(StartShift::default(), &RunOptions::default()).unwrap();
//! assert_eq!(run.end_reason, "mission-over");
//! ```

pub mod args;
pub mod bus;
pub(crate) mod canvas;
pub mod cli;
pub(crate) mod decor;
pub mod depth_strip;
pub mod fleet;
pub mod interrupt;
pub mod montecarlo;
pub mod observe;
pub mod output;
pub mod picture;
pub mod run;
pub mod scenario;

pub use run::{find_mission, Outcome, Prepared, RunOptions, SimError, StartShift};
