//! Fleets: several vehicles in one deterministic run (issue 23).
//!
//! A `scenario.toml` with `[[vehicle]]` entries ([`spec`]) makes a fleet: each vehicle
//! has its own helm, bus, simulator, pNodeReporter and contact manager ([`vehicle`]),
//! all on one simulated clock ([`run`]); node reports travel between vehicles through
//! the comms model ([`comms`], after uFldNodeComms) and every pair's closest approach,
//! encounters, near misses and collisions are kept ([`collide`], after
//! uFldCollisionDetect). Its summary, Monte Carlo, shards and picture are in
//! `helm-sim-cli` (`fleet`).

pub mod collide;
pub mod colregs;
pub mod comms;
pub mod obstacles;
pub mod relay;
pub mod reporter;
pub mod run;
pub mod spec;
pub mod vehicle;

pub use run::{FleetOptions, FleetOutcome, FleetPlan, VehicleOutcome};
pub use spec::{is_fleet, FleetScenario};
