//! `behavior-api`: the stable ABI between the ivp-helm host and its behaviors, and the
//! SDK to write one.
//!
//! A behavior is a [`behavior::Behavior`] trait object (abi_stable `#[sabi_trait]`), the
//! same for behaviors compiled into the helm and for those loaded from a `cdylib`: the
//! engine cannot tell them apart. During each call the behavior talks to the helm through
//! a [`context::HelmContext`] (the info buffer and postings). Authors implement the plain
//! Rust trait [`sdk::IvpBehavior`] and export it with [`export_behaviors!`].
//!
//! ```
//! use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
//! use behavior_api::FunctionData;
//!
//! struct Quiet { domain: String }
//! impl IvpBehavior for Quiet {
//!     fn domain(&self) -> String { self.domain.clone() }
//!     fn default_name(&self) -> String { "bhv_quiet".into() }
//!     fn set_param(&mut self, _: &mut Ctx<'_>, _: &str, _: &str) -> bool { false }
//!     fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
//!         ctx.post_message("QUIET", "yes");
//!         None
//!     }
//! }
//! let helm = HelmDomain::new("course,0,359,360:speed,0,4,41");
//! let b = behavior_api::sdk::boxed(Quiet { domain: helm.sub_domain(&["speed"]) });
//! assert_eq!(b.domain().as_str(), "speed,0,4,41");
//! ```
//!
//! Everything a behavior needs comes through this crate, so a third party depends on
//! `behavior-api` (and `abi_stable`) alone:
//! - [`ivp`]: domains, ZAIC builders, coupler, reflector (the objective functions);
//!   [`zaic`]: the ZAIC_PEAK and ZAIC_SPD shapes as named parameter structs;
//! - [`geometry`]: angles, points and segments, convex polygons, the point / seglist /
//!   polygon strings, and the VIEW_* spec strings ([`geometry::spec`]: `point_spec`,
//!   `seglist_spec`, `Attrs`, ...);
//! - MOOS-IvP's number and colour rules from [`mbutil`], also at the top level:
//!   [`is_number`], [`atof`], [`parse_number`], [`compact`] (the `%.Nf` formatter with
//!   trailing zeros removed), [`parse_color`] / [`is_color`] (the helm's colour parser);
//! - [`platform`]: the common platform update (NAV_X/Y/HEADING required, NAV_SPEED optional);
//! - [`params`]: shared parameter-value rules (`parse_bool` with `toggle`, `positive`,
//!   `non_negative`, `no_white`);
//! - [`flag`]: the `.bhv` flag syntax (`[#dest ]VAR = VALUE [if CONDITION]`), to check a
//!   behavior's own flag parameters (e.g. BHV_Waypoint's `wptflag`) the way the helm
//!   checks `endflag`.
//!
//! ```
//! assert_eq!(behavior_api::parse_number(" 1.5 "), Some(1.5));
//! assert!(behavior_api::is_color("gray70"));
//! assert_eq!(behavior_api::geometry::angle360(-90.0), 270.0);
//! let attrs = behavior_api::geometry::spec::Attrs::default();
//! assert_eq!(behavior_api::geometry::spec::point_spec(1.0, 2.5, None, &attrs), "x=1,y=2.5");
//! ```
//!
//! Versioning: the root module carries this crate's version; abi_stable refuses a library
//! built against an incompatible version and checks every type layout when loading.

// abi_stable's sabi_trait macro expands to impls inside a const block.
#![allow(non_local_definitions)]

pub mod abi_v1;
pub mod abi_v2;
pub mod abi_v3;
pub mod behavior;
pub mod contact;
pub mod context;
pub mod flag;
pub mod format;
pub mod function;
pub mod kept;
pub mod module;
pub mod params;
pub mod platform;
pub mod sdk;
pub mod testing;
pub mod value;
pub mod zaic;

/// Domains, functions, ZAIC builders and coupler (the crate `ivp`) with the
/// OF_Reflector (the crate `ivp-reflector`), at the paths behaviors have always used:
/// `ivp::Reflector`, `ivp::Aof`, `ivp::reflector::…` beside `ivp::Domain` and the rest.
pub mod ivp {
    pub use ::ivp::*;
    pub use ivp_reflector::{reflector, Aof, Reflector};
}

// The tutorial's files are shown whole, their `#[cfg(test)]` tests included: rustdoc
// compiles them, and helm/tests/plugin_copy.rs builds them as crates and runs the tests.
#[allow(clippy::test_attr_in_doctest)]
#[doc = include_str!("../TUTORIAL.md")]
pub mod tutorial {}

pub use abi_stable;
pub use behavior::{BehaviorBox, CallResult};
pub use contacts;
pub use context::HelmCtx;
pub use format::{push_compact, push_fixed, push_i64, push_u64};
pub use function::FunctionData;
pub use geometry;
pub use mbutil;
pub use mbutil::{atof, compact, is_color, is_number, parse_color, parse_number, Color};
pub use module::{BehaviorLibRef, FunctionRecycler, API_VERSION};
pub use value::{ContactState, PostValue};
