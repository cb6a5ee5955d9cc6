//! MOOS clocks (spec §6.1): MOOSLocalTime = wall × warp; MOOSTime = local + skew.

use std::time::{SystemTime, UNIX_EPOCH};

/// UNIX wall-clock time in seconds.
pub fn wall_time() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0)
}

/// Whether a time-warp factor is acceptable (0 < warp ≤ 400).
pub fn warp_ok(warp: f64) -> bool {
    warp > 0.0 && warp <= 400.0
}

/// MOOSLocalTime for a warp factor.
pub fn local_time(warp: f64) -> f64 {
    wall_time() * warp
}
