//! BHV_AvoidObstacleV24 (obstacles.md §1) as a plugin library: keep ownship's course
//! clear of one convex polygon obstacle, one instance per obstacle, spawned from a
//! template when the obstacle manager (pObstacleMgr) alerts about it, completed when the
//! manager resolves it or ownship is past `completed_dist`.
//!
//! Depends on `behavior-api` alone (the SDK, with `geometry` for the buffer polygon, the
//! tangent bearings and the ray CPA), like a third party's plugin; nothing of the helm.
//! The older types (V21, X and the original) are refused by the helm itself as the real
//! helm refuses them, so they are not here.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_obstacle::AvoidObstacleV24::new(&HelmDomain::new("course,0,359,360:speed,0,4,21"));
//! let mut helm = MockHelm::new("avd_ob_oba");
//! let params = [("poly", "pts={60,-12:60,6:80,6:80,-12},label=oba"), ("id", "oba"),
//!               ("allowable_ttc", "5"), ("min_util_cpa_dist", "3"), ("max_util_cpa_dist", "7"),
//!               ("pwt_outer_dist", "15"), ("pwt_inner_dist", "5"), ("completed_dist", "15")];
//! # assert_eq!(params, bhv_obstacle::EXAMPLE_PARAMS);
//! for (p, v) in params {
//!     assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}");
//! }
//! helm.nav(50.0, 0.0, 90.0, 2.0);
//! helm.with(|ctx| b.on_every_state(ctx));
//! let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
//! assert_eq!(f.piece_count(), Some(120 * 7));
//! ```

mod behavior;
pub mod model;
pub mod params;
pub mod refinery;
mod visuals;

pub use behavior::AvoidObstacleV24;

/// The parameters of the example above (m34_bo_alpha's, spawned for obstacle `oba`),
/// from which the crate's tests build their behavior.
#[doc(hidden)]
pub const EXAMPLE_PARAMS: [(&str, &str); 8] = [
    ("poly", "pts={60,-12:60,6:80,6:80,-12},label=oba"),
    ("id", "oba"),
    ("allowable_ttc", "5"),
    ("min_util_cpa_dist", "3"),
    ("max_util_cpa_dist", "7"),
    ("pwt_outer_dist", "15"),
    ("pwt_inner_dist", "5"),
    ("completed_dist", "15"),
];

behavior_api::export_behaviors! {
    "BHV_AvoidObstacleV24" => AvoidObstacleV24::new,
}
