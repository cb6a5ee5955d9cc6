//! The depth and limit behaviors of MOOS-IvP as one plugin library (behaviors-more.md
//! §4–§7): BHV_MaxSpeed and BHV_MaxDepth (constraints: a ZAIC_LEQ cap, one shared body
//! in [`limit`]), BHV_GoToDepth (a list of depth levels held in turn) and
//! BHV_PeriodicSurface (a UUV's surfacing cycle). They share the ZAIC_LEQ limit and the
//! depth variable, so they ship as one library.
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let helm_domain = HelmDomain::new("course,0,359,360:speed,0,4,41:depth,0,100,101");
//! let mut b = bhv_depth::MaxDepth::new(&helm_domain);
//! assert_eq!(b.domain(), "depth,0,100,101");
//! let mut helm = MockHelm::new("cap");
//! helm.set("NAV_DEPTH", 4.0);
//! assert!(helm.with(|ctx| b.set_param(ctx, "max_depth", "6.3")));
//! assert!(helm.with(|ctx| b.set_param(ctx, "tolerance", "1")));
//! assert!(helm.with(|ctx| b.set_param(ctx, "depth_slack_var", "SLACK")));
//! let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
//! assert_eq!(f.piece_count(), Some(3));
//! assert_eq!(helm.last("SLACK").as_deref(), Some("2.3"));
//! ```

pub mod goto_depth;
pub mod limit;
pub mod periodic_surface;

pub use goto_depth::GoToDepth;
pub use limit::{MaxDepth, MaxSpeed};
pub use periodic_surface::PeriodicSurface;

behavior_api::export_behaviors! {
    "BHV_MaxDepth" => MaxDepth::new,
    "BHV_MaxSpeed" => MaxSpeed::new,
    "BHV_GoToDepth" => GoToDepth::new,
    "BHV_PeriodicSurface" => PeriodicSurface::new,
}
