//! The standard behaviors of the ivp-helm: BHV_Waypoint, BHV_Loiter and BHV_Timer
//! (behaviors-std.md), written against the behavior SDK.

pub mod common;
pub mod kept;
pub mod loiter;
pub mod timer;
pub mod waypoint;

use behavior_api::sdk::{boxed, HelmDomain};
use behavior_api::BehaviorBox;

pub use loiter::BhvLoiter;
pub use timer::BhvTimer;
pub use waypoint::BhvWaypoint;

/// Constructor of a built-in behavior type.
pub type Constructor = fn(&HelmDomain) -> BehaviorBox;

fn make_waypoint(d: &HelmDomain) -> BehaviorBox {
    boxed(BhvWaypoint::new(d))
}
fn make_loiter(d: &HelmDomain) -> BehaviorBox {
    boxed(BhvLoiter::new(d))
}
fn make_timer(d: &HelmDomain) -> BehaviorBox {
    boxed(BhvTimer::new(d))
}

/// The built-in types, by their (case-sensitive) type names.
pub fn builtin_types() -> Vec<(&'static str, Constructor)> {
    vec![
        ("BHV_Waypoint", make_waypoint as Constructor),
        ("BHV_Loiter", make_loiter as Constructor),
        ("BHV_Timer", make_timer as Constructor),
    ]
}
