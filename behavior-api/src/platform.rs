//! The common platform update (`updatePlatformInfo`, behavior-common.md §7) that many
//! behaviors start their run with: NAV_X, NAV_Y and NAV_HEADING are required (BHV_ERROR
//! otherwise, which halts the helm's decision), NAV_SPEED is optional (warning only, 0).

use crate::geometry::angle360;
use crate::sdk::Ctx;

/// Ownship as read by the platform update.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Platform {
    pub x: f64,
    pub y: f64,
    /// Put through `angle360`.
    pub heading: f64,
    pub speed: f64,
}

/// Read ownship; `None` after posting the reference's BHV_ERROR. Records the values for
/// the common `$[OSX]`, `$[OSY]`, `$[OSH]`, `$[OSV]` macros.
///
/// ```
/// use behavior_api::platform::platform_update;
/// use behavior_api::testing::MockHelm;
/// let mut helm = MockHelm::new("b");
/// helm.nav(1.0, 2.0, -90.0, 1.5);
/// let p = helm.with(|ctx| platform_update(ctx)).unwrap();
/// assert_eq!((p.x, p.y, p.heading, p.speed), (1.0, 2.0, 270.0, 1.5));
/// helm.unset("NAV_HEADING");
/// assert!(helm.with(|ctx| platform_update(ctx)).is_none());
/// assert_eq!(helm.last("BHV_ERROR").as_deref(), Some("b: No ownship heading info in info_buffer."));
/// ```
pub fn platform_update(ctx: &mut Ctx<'_>) -> Option<Platform> {
    let x = ctx.get_buffer_double_val("NAV_X");
    let y = ctx.get_buffer_double_val("NAV_Y");
    let (Some(x), Some(y)) = (x, y) else {
        ctx.post_emessage("No ownship X/Y info in info_buffer.");
        return None;
    };
    let Some(h) = ctx.get_buffer_double_val("NAV_HEADING") else {
        ctx.post_emessage("No ownship heading info in info_buffer.");
        return None;
    };
    let heading = angle360(h);
    let speed = ctx.get_buffer_double_val("NAV_SPEED").unwrap_or(0.0);
    ctx.set_platform(x, y, heading, speed);
    Some(Platform {
        x,
        y,
        heading,
        speed,
    })
}
