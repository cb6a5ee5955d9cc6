//! ZigZag's parameters (behaviors-more.md §8.1).

use behavior_api::geometry::{angle360, text::split_q};
use behavior_api::params::{non_negative, parse_bool, positive};
use behavior_api::{is_color, parse_number};

use super::{Side, ZigZag};

impl ZigZag {
    pub(super) fn set_zig_param(&mut self, param: &str, value: &str) -> bool {
        let v = value.trim();
        match param {
            "speed" => non_negative(v).map(|s| self.speed = s).is_some(),
            "mod_speed" => {
                if v.eq_ignore_ascii_case("reset") {
                    self.speed = self.orig_speed;
                    return true;
                }
                parse_number(v)
                    .map(|d| self.speed = (self.speed + d).clamp(0.0, self.speed_max.max(0.0)))
                    .is_some()
            }
            "speed_on_active" | "spd_on_active" => parse_bool(v, self.speed_on_active)
                .map(|b| self.speed_on_active = b)
                .is_some(),
            "stem_hdg" => parse_number(v)
                .map(|h| self.stem_hdg = angle360(h))
                .is_some(),
            "stem_on_active" => parse_bool(v, self.stem_on_active)
                .map(|b| self.stem_on_active = b)
                .is_some(),
            "hdg_thresh" => non_negative(v).map(|t| self.hdg_thresh = t).is_some(),
            "fierce_zigging" => parse_bool(v, self.fierce)
                .map(|b| self.fierce = b)
                .is_some(),
            "zig_angle" => in_zig_range(v).map(|a| self.zig_angle = a).is_some(),
            "zig_angle_fierce" | "delta_heading" => {
                in_zig_range(v).map(|a| self.zig_angle_fierce = a).is_some()
            }
            "zig_first" => match v.to_ascii_lowercase().as_str() {
                "port" | "left" => {
                    self.zig_first = Side::Port;
                    true
                }
                "star" | "starboard" | "right" => {
                    self.zig_first = Side::Star;
                    true
                }
                _ => false,
            },
            "max_zig_legs" => non_negative(v)
                .map(|n| self.max_zig_legs = n.trunc().min(u64::MAX as f64) as u64)
                .is_some(),
            "max_zig_zags" => parse_number(v)
                .filter(|n| *n >= 1.0)
                .map(|n| self.max_zig_legs = (2.0 * n.trunc()).min(u64::MAX as f64) as u64)
                .is_some(),
            "max_stem_odo" => positive(v).map(|d| self.max_stem_odo = d).is_some(),
            "zigflag" => self.zigflags.set(v),
            "zagflag" => self.zagflags.set(v),
            "portflag" => self.portflags.set(v),
            "starflag" => self.starflags.set(v),
            "portflagx" => self.portflagx.set(v),
            "starflagx" => self.starflagx.set(v),
            "visual_hints" => self.set_visual_hints(v),
            _ => false,
        }
    }

    /// Applied in order; the first bad hint refuses the line and stops there.
    fn set_visual_hints(&mut self, value: &str) -> bool {
        for hint in split_q(value, ',') {
            let (key, val) = match hint.split_once('=') {
                Some((k, v)) => (k.trim().to_ascii_lowercase(), v.trim()),
                None => return false,
            };
            let ok = match key.as_str() {
                "draw_set_hdg" => parse_bool(val, self.draw_set)
                    .map(|b| self.draw_set = b)
                    .is_some(),
                "draw_req_hdg" => parse_bool(val, self.draw_req)
                    .map(|b| self.draw_req = b)
                    .is_some(),
                "set_hdg_color" if is_color(val) || val.eq_ignore_ascii_case("off") => {
                    self.set_color = val.to_string();
                    true
                }
                "req_hdg_color" if is_color(val) || val.eq_ignore_ascii_case("off") => {
                    self.req_color = val.to_string();
                    true
                }
                _ => false,
            };
            if !ok {
                return false;
            }
        }
        true
    }
}

/// A zig angle: a number in [1, 75].
fn in_zig_range(v: &str) -> Option<f64> {
    parse_number(v).filter(|a| (1.0..=75.0).contains(a))
}
