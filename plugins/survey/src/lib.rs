//! The survey-pattern behaviors of MOOS-IvP as one plugin library: BHV_ZigZag (alternate
//! legs off a stem heading, behaviors-more.md §8) and BHV_LegRun (back and forth along a
//! leg with generated turns, §9). They share the odometer, the flag lists and the
//! course/speed function shape, so they ship as one library.
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut z = bhv_survey::ZigZag::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! assert_eq!(z.domain(), "course,0,359,360:speed,0,4,41");
//! let mut helm = MockHelm::new("zig");
//! helm.nav(0.0, 0.0, 0.0, 1.0);
//! for (p, v) in [("speed", "2"), ("zig_angle", "45"), ("zig_first", "star")] {
//!     assert!(helm.with(|ctx| z.set_param(ctx, p, v)));
//! }
//! let f = helm.with(|ctx| z.on_run(ctx)).unwrap();
//! assert_eq!(f.var_names().collect::<Vec<_>>(), vec!["course", "speed"]);
//! ```

pub mod legrun;
mod objective;
pub mod odometer;
pub mod zigzag;

pub use legrun::LegRun;
pub use zigzag::ZigZag;

behavior_api::export_behaviors! {
    "BHV_ZigZag" => ZigZag::new,
    "BHV_LegRun" => LegRun::new,
}
