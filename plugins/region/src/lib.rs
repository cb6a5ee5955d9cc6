//! The operating-region behaviors of MOOS-IvP as one plugin library: BHV_OpRegion (a
//! safety envelope that halts the helm on a breach, [`opregion`]) and BHV_OpRegionV24
//! (nested core / save / halt regions with a recovery objective, [`v24`]). They share
//! the perimeter geometry ([`geom`]) and the entry/exit debouncing ([`watch`]).
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin; nothing of
//! the helm.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_region::OpRegion::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! let mut helm = MockHelm::new("opreg");
//! assert!(helm.with(|ctx| b.set_param(ctx, "polygon", "0,0 : 100,0 : 100,-100 : 0,-100")));
//! assert!(!helm.with(|ctx| b.set_param(ctx, "max_time", "-1")));
//! helm.nav(50.0, -50.0, 90.0, 2.0);
//! assert!(helm.with(|ctx| b.on_run(ctx)).is_none()); // a monitor: no objective function
//! assert_eq!(helm.last("OPREG_ABSOLUTE_PERIM_DIST").as_deref(), Some("50"));
//! assert_eq!(helm.last("OPREG_TRAJECTORY_PERIM_ETA").as_deref(), Some("25"));
//! ```

pub mod geom;
pub mod opregion;
pub mod v24;
pub mod watch;

#[cfg(test)]
mod tests;

pub use opregion::{Breach, OpRegion};
pub use v24::OpRegionV24;

behavior_api::export_behaviors! {
    "BHV_OpRegion" => OpRegion::new,
    "BHV_OpRegionV24" => OpRegionV24::new,
}
