//! `helm-sim-cli`: the `helm sim` command on top of the simulator (`helm-sim`).
//!
//! [`cli`] is the command line ([`args`] its arguments); [`montecarlo`] runs a mission
//! many times from perturbed starts ([`interrupt`]: Ctrl-C keeps the finished runs);
//! [`output`] writes `summary.json` and `runs.csv`, [`picture`] the SVG ([`canvas`],
//! [`decor`] and [`depth_strip`] its parts, [`labels`] placing its texts and the fleet
//! picture's); [`fleet`] does the same for fleets, with
//! shards and `helm sim merge`.
//!
//! It may depend on `helm-sim`, `helm-engine` (posted values), `geometry` and `mbutil`;
//! it must not depend on `helm-app`, the MOOS crates' sockets or the `helm` binary; only
//! the `helm` binary depends on it. The simulation itself (clock, bus, vehicles, fleet,
//! statistics) stays in `helm-sim`: this crate decides what to run and what to write.
//!
//! One alpha run drawn:
//!
//! ```
//! use helm_sim::{Prepared, RunOptions, StartShift};
//! let mission = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha");
//! let prepared = Prepared::load(&mission, &[], None).unwrap();
//! let run = prepared.run(StartShift::default(), &RunOptions::default()).unwrap();
//! let svg = helm_sim_cli::picture::svg(&run.observer, "alpha", "one run");
//! assert!(svg.starts_with("<svg") && svg.contains("alpha"));
//! ```

pub mod args;
pub(crate) mod canvas;
pub mod cli;
pub(crate) mod decor;
pub mod depth_strip;
pub mod fleet;
pub mod interrupt;
pub(crate) mod labels;
pub mod montecarlo;
pub mod output;
pub mod picture;
