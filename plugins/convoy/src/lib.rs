//! BHV_Convoy (behaviors-more.md §10) as a plugin library: follow a named contact along
//! its own track. It drops marks (breadcrumbs) on the contact's path, steers to the
//! oldest, and sets its speed from the contact's recent speed and the range to it. A
//! contact behavior on the SDK's `behavior_api::contact::ContactBase`, in its own crate
//! so it ships apart from the collision-avoidance family.
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_convoy::Convoy::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! let mut helm = MockHelm::new("convoy");
//! assert!(helm.with(|ctx| b.set_param(ctx, "contact", "abe")));
//! assert!(!helm.with(|ctx| b.set_param(ctx, "inter_mark_range", "0")));
//! helm.nav(0.0, 0.0, 0.0, 1.0);
//! helm.contact("abe", 0.0, 50.0, 0.0, 1.5, "kayak");
//! helm.with(|ctx| b.on_every_state(ctx));
//! let f = helm.with(|ctx| b.on_run(ctx)).unwrap(); // one mark, 50 m ahead
//! assert_eq!(f.pwt, 10.0); // the reference never applies pwt
//! assert_eq!(helm.last("WPTY").as_deref(), Some("50"));
//! ```

mod convoy;
mod marks;

pub use convoy::Convoy;
pub use marks::Marks;

behavior_api::export_behaviors! {
    "BHV_Convoy" => Convoy::new,
}
