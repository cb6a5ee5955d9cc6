//! `helm sim` on a fleet (`helm_sim::fleet` runs it): the command ([`cli`]), the
//! summary ([`output`]), the Monte Carlo with shards and merge ([`montecarlo`]) and the
//! picture ([`picture`]).

pub mod cli;
pub mod montecarlo;
pub mod obstacle_layer;
pub mod output;
pub mod picture;
pub mod stats;
