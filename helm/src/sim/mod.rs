//! `helm sim`: a mission in deterministic fast time, in one process.
//!
//! The helm (driven by the same [`crate::app::cycle::HelmCycle`] as `helm run`), the
//! vehicle simulator ([`crate::vehicle`]) and an in-process MOOS bus ([`bus`]) run on a
//! simulated clock ([`run`]); a [`scenario`] file adds pokes, end conditions and start
//! overrides; [`output`] writes the summary and [`picture`] the SVG; [`montecarlo`]
//! runs the mission many times with perturbed starts; [`cli`] is the command line.

pub mod bus;
pub mod cli;
pub mod montecarlo;
pub mod observe;
pub mod output;
pub mod picture;
pub mod run;
pub mod scenario;

pub use run::{find_mission, Outcome, Prepared, RunOptions, SimError, StartShift};
