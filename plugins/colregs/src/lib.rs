//! BHV_AvdColregsV22, with BHV_AvdColregsV19 and BHV_AvdColregsV17, as one plugin
//! library (behaviors-contacts.md §5): avoid one contact by the collision regulations.
//! A mode machine ([`modes`]) names the rule situation each iteration — overtaking
//! (rule 13), head-on (14), give-way crossing (16), stand-on crossing or stand-on while
//! overtaken (17), or a plain CPA catch-all — and each mode has its own objective
//! function ([`aof`], [`standon`]). One implementation serves the three types; a
//! [`params::Version`] switch holds what V19 and V17 do differently (§5.8).
//!
//! Depends on `behavior-api` alone (the contact SDK and the CPA engine it re-exports),
//! like a third party's plugin; nothing of the helm.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_colregs::Colregs::v22(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! let mut helm = MockHelm::new("col_bob");
//! for (p, v) in [("contact", "bob"), ("pwt_outer_dist", "80"), ("pwt_inner_dist", "50")] {
//!     assert!(helm.with(|ctx| b.set_param(ctx, p, v)));
//! }
//! helm.nav(0.0, 0.0, 0.0, 2.0);
//! helm.contact("bob", 0.0, 60.0, 180.0, 2.0, "kayak"); // dead ahead, coming at us
//! helm.with(|ctx| b.on_every_state(ctx));
//! let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
//! assert_eq!(f.piece_count(), Some(1680));
//! assert_eq!(b.expand_macros("$[FULL_MODE]").as_deref(), Some("headon:none"));
//! ```

pub mod aof;
pub mod build;
mod colregs;
pub mod modes;
pub mod params;
pub mod standon;

pub use colregs::Colregs;

behavior_api::export_behaviors! {
    "BHV_AvdColregsV22" => Colregs::v22,
    "BHV_AvdColregsV19" => Colregs::v19,
    "BHV_AvdColregsV17" => Colregs::v17,
}
