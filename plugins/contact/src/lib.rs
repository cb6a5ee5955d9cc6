//! The contact behaviors of MOOS-IvP as one plugin library: BHV_AvoidCollision
//! (contacts-appcast.md §3), BHV_CutRange, BHV_Trail and BHV_Shadow
//! (behaviors-contacts.md §2–§4). Each holds the SDK's contact base
//! (`behavior_api::contact::ContactBase`) for what contact behaviors share; CutRange and
//! Trail also share one objective function ([`aof::CutRangeAof`]), which is why the four
//! are one library.
//!
//! Depends on `behavior-api` alone (the SDK), like a third party's plugin; nothing of
//! the helm.
//!
//! Parameters are those of the specs' tables. Where the spec is silent we chose to
//! refuse, as an unknown parameter with file and line: the blocks of the
//! distribution's current example missions that we could read pass unchanged, but
//! older example files kept in its history (`missions_multi`, `missions_misc2`,
//! `bhv_colregs`) set parameters of an older interface (`them`, `max_range`,
//! `active_distance`, `collision_distance`, `all_clear_distance`, `unifbox`,
//! `dist_priority_interval`, `cpa_utility_interval`) that the documented parameters of
//! today's behaviors do not have, and whose meaning we would have to guess.
//!
//! ```
//! use behavior_api::sdk::{HelmDomain, IvpBehavior};
//! use behavior_api::testing::MockHelm;
//! let mut b = bhv_contact::AvoidCollision::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
//! let mut helm = MockHelm::new("avd_bob");
//! helm.nav(0.0, 0.0, 0.0, 2.0);
//! helm.contact("bob", 0.0, 100.0, 180.0, 2.0, "kayak");
//! assert!(helm.with(|ctx| b.set_param(ctx, "contact", "bob")));
//! helm.with(|ctx| b.on_every_state(ctx));
//! let f = helm.with(|ctx| b.on_run(ctx)).unwrap(); // head-on at 100 m: inside 200 m
//! assert_eq!(f.piece_count(), Some(120 * 14));
//! ```

pub mod aof;
mod avoid_collision;
mod cutrange;
mod shadow;
mod trail;

pub use avoid_collision::AvoidCollision;
pub use cutrange::CutRange;
pub use shadow::Shadow;
pub use trail::Trail;

behavior_api::export_behaviors! {
    "BHV_AvoidCollision" => AvoidCollision::new,
    "BHV_CutRange" => CutRange::new,
    "BHV_Trail" => Trail::new,
    "BHV_Shadow" => Shadow::new,
}
