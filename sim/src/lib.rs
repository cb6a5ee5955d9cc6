//! `helm-sim`: `helm sim`, a mission in deterministic fast time, in one process.
//!
//! The helm (driven by the same [`helm_cycle::HelmCycle`] as `helm run`), the
//! vehicle simulator ([`vehicle_model`]) and an in-process MOOS bus ([`bus`]) run on a
//! simulated clock ([`run`]); a [`scenario`] file adds pokes, end conditions and start
//! overrides; [`observe`] keeps what the run shows (track, VIEW_* shapes, all-stops,
//! [`depth`]). [`fleet`] runs several vehicles on one clock, with node reports between
//! them, a contact manager each and collision statistics. The `helm sim` command, its
//! Monte Carlo, output files and pictures are the `helm-sim-cli` crate's.
//!
//! It may depend on `helm-engine` and `helm-cycle` (the cycle that drives it), `vehicle-model`, `moos` (for the `.alog` and mission
//! files; never a socket), `geometry`, `contact-manager` and `contacts`, and `mbutil`; it must not depend on `helm-app`; only `helm-sim-cli` and the `helm`
//! binary depend on it.
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

pub mod bus;
pub mod depth;
pub mod fleet;
pub mod observe;
pub mod run;
pub mod scenario;
pub mod seed;

pub use run::{find_mission, Outcome, Prepared, RunOptions, SimError, StartShift};
