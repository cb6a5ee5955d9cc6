//! The visual-only behaviors of MOOS-IvP as one plugin library: BHV_HSLine (the helm's
//! desired heading and speed as a line, behaviors-more.md §1), BHV_BearingLine (a
//! line toward a fixed point, §2) and BHV_PModelView (the helm's platform-model turn
//! path toward the desired heading, §3). None of them ever produces an objective function:
//! they only post VIEW_* strings, so they share one library (one file to ship, one
//! build unit).
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin; nothing of
//! the helm.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_visuals::HsLine::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! let mut helm = MockHelm::new("hsline");
//! helm.nav(0.0, 0.0, 0.0, 0.0);
//! helm.set("DESIRED_HEADING", 0.0);
//! helm.set("DESIRED_SPEED", 2.2);
//! assert!(helm.with(|ctx| b.set_param(ctx, "time_on_leg", "10")));
//! assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
//! assert_eq!(
//!     helm.last("VIEW_SEGLIST").as_deref(),
//!     Some("pts={0,0:0,22},active=true,label=abe_hsline")
//! );
//! ```

mod bearing_line;
mod hsline;
mod pmodel_view;

pub use bearing_line::BearingLine;
pub use hsline::HsLine;
pub use pmodel_view::PModelView;

behavior_api::export_behaviors! {
    "BHV_HSLine" => HsLine::new,
    "BHV_BearingLine" => BearingLine::new,
    "BHV_PModelView" => PModelView::new,
}
