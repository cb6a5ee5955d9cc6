//! BHV_Waypoint parameters (behaviors-std.md §2.1) and its BHV_SETTINGS report.

use behavior_api::sdk::Ctx;
use geometry::{dist, fmt_x, is_color, parse_point, parse_polygon, parse_seglist, EdgeTag, Vertex};

use super::BhvWaypoint;
use crate::common::{no_white, parse_bool, parse_nonneg, parse_number};

/// Visual hints for the VIEW_* postings.
#[derive(Clone, Debug, PartialEq)]
pub struct WptHints {
    pub vertex_size: f64,
    pub edge_size: f64,
    pub vertex_color: String,
    pub edge_color: String,
    pub label_color: String,
    pub nextpt_color: String,
    pub nextpt_label_color: String,
    pub nextpt_vertex_size: f64,
}

impl Default for WptHints {
    fn default() -> Self {
        WptHints {
            vertex_size: 3.0,
            edge_size: 1.0,
            vertex_color: "dodger_blue".into(),
            edge_color: "white".into(),
            label_color: "white".into(),
            nextpt_color: "yellow".into(),
            nextpt_label_color: "aqua".into(),
            nextpt_vertex_size: 5.0,
        }
    }
}

impl WptHints {
    /// Apply `key=value,key=value`; all-or-nothing validation: a key containing `color`
    /// needs a colour (`mbutil::color`), any other key a number (behaviors-std.md §2.1).
    pub fn apply(&mut self, spec: &str) -> bool {
        let mut next = self.clone();
        for part in spec.split(',') {
            let part = part.trim();
            if part.is_empty() {
                continue;
            }
            let Some((k, v)) = part.split_once('=') else {
                return false;
            };
            let key = k
                .trim()
                .to_ascii_lowercase()
                .replace("lcolor", "label_color");
            let v = v.trim();
            if key.contains("color") {
                let edge_off = key == "edge_color"
                    && matches!(v.to_ascii_lowercase().as_str(), "off" | "inactive");
                if !is_color(v) && !edge_off {
                    return false;
                }
                let v = v.to_string();
                // Any key holding a valid colour is a hint (the distribution's own
                // missions write `line_color=white`); the ones not drawn are kept nowhere.
                match key.as_str() {
                    "vertex_color" => next.vertex_color = v,
                    "edge_color" => next.edge_color = v,
                    "label_color" => next.label_color = v,
                    "nextpt_color" => next.nextpt_color = v,
                    "nextpt_label_color" => next.nextpt_label_color = v,
                    _ => {}
                }
            } else {
                let Some(n) = parse_number(v) else {
                    return false;
                };
                match key.as_str() {
                    "vertex_size" => next.vertex_size = n,
                    "edge_size" => next.edge_size = n,
                    "nextpt_vertex_size" => next.nextpt_vertex_size = n,
                    _ => {}
                }
            }
        }
        *self = next;
        true
    }
}

/// A seglist string, or a polygon converted to a seglist starting at the vertex nearest
/// (x, y) and continuing in polygon order.
pub fn points_from_string(s: &str, x: f64, y: f64) -> Option<Vec<Vertex>> {
    path_from_string(s, x, y).map(|(pts, _)| pts)
}

/// [`points_from_string`] with the seglist's edge tags (a lawnmower's `lane` tags; a
/// polygon has none). The tags are posted back in VIEW_SEGLIST.
pub fn path_from_string(s: &str, x: f64, y: f64) -> Option<(Vec<Vertex>, Vec<EdgeTag>)> {
    if let Some(sl) = parse_seglist(s) {
        if !sl.pts.is_empty() {
            return Some((sl.pts, sl.tags));
        }
    }
    let poly = parse_polygon(s)?;
    let v = poly.vertices();
    if v.is_empty() {
        return None;
    }
    let mut best = 0;
    let mut best_d = f64::INFINITY;
    for (i, p) in v.iter().enumerate() {
        let d = dist(x, y, p.x, p.y);
        if d < best_d {
            best_d = d;
            best = i;
        }
    }
    let pts = (0..v.len()).map(|k| v[(best + k) % v.len()]).collect();
    Some((pts, Vec::new()))
}

/// `slow_dist=..,stop_dist=..`.
fn parse_end_spd(s: &str) -> Option<(f64, f64)> {
    let (mut slow, mut stop) = (None, None);
    for part in s.split(',') {
        let (k, v) = part.split_once('=')?;
        let v = parse_number(v)?;
        match k.trim().to_ascii_lowercase().as_str() {
            "slow_dist" => slow = Some(v),
            "stop_dist" => stop = Some(v),
            _ => return None,
        }
    }
    let (slow, stop) = (slow?, stop.unwrap_or(0.0));
    (slow > 0.0 && stop >= 0.0 && stop <= slow).then_some((slow, stop))
}

fn status_var(v: &str) -> Option<String> {
    let t = no_white(v)?;
    Some(if t.eq_ignore_ascii_case("silent") {
        "silent".to_string()
    } else {
        t.to_string()
    })
}

/// A flag in the `.bhv` flag syntax (the same check as the common flags).
fn flag_ok(v: &str) -> bool {
    behavior_api::flag::parse_flag(v).is_ok()
}

impl BhvWaypoint {
    /// Load a point list (from `points`, `polygon` or `point`).
    fn load_points(&mut self, pts: Vec<Vertex>, reset_prev: bool) {
        self.engine.set_points(pts);
        self.mark = None;
        if reset_prev {
            self.prev_cycle_index = 0;
            self.prev_waypt_index = -1;
            self.prev_pt = None;
        }
    }

    fn set_flag(list: &mut Vec<String>, v: &str) -> bool {
        if !flag_ok(v) {
            return false;
        }
        if v.trim().eq_ignore_ascii_case("clearall") {
            list.clear();
        } else {
            list.push(v.trim().to_string());
        }
        true
    }

    /// The type-specific parameter handler.
    pub(super) fn set_wpt_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let v = value.trim();
        let lower = v.to_ascii_lowercase();
        match param {
            "points" | "polygon" => {
                if lower == "empty" || lower == "start" {
                    self.start_intent = lower == "start";
                    return true;
                }
                let Some((pts, tags)) = path_from_string(v, self.plat.x, self.plat.y) else {
                    return false;
                };
                self.start_intent = false;
                self.load_points(pts, true);
                self.path_tags = tags;
                true
            }
            "xpoints" => {
                let Some(pts) = points_from_string(v, self.plat.x, self.plat.y) else {
                    return false;
                };
                if pts.len() != self.engine.size() {
                    return false;
                }
                self.engine.replace_points_keep_state(pts);
                true
            }
            "point" => {
                if lower == "empty" || lower == "start" {
                    self.start_intent = lower == "start";
                    return true;
                }
                let Some(p) = parse_point(v) else {
                    return false;
                };
                self.start_intent = false;
                self.load_points(vec![Vertex::new(p.x, p.y)], false);
                self.path_tags.clear();
                true
            }
            "newpt" => {
                let Some(p) = parse_point(v) else {
                    return false;
                };
                self.engine.add_point(Vertex::new(p.x, p.y));
                true
            }
            "speed" => match parse_nonneg(v) {
                Some(s) => {
                    self.cruise_speed = match self.speed_high {
                        Some(h) if s > h => h,
                        _ => s,
                    };
                    true
                }
                None => false,
            },
            "speed_alt" => match parse_nonneg(v) {
                Some(s) => {
                    self.speed_alt = s;
                    true
                }
                None => false,
            },
            "use_alt_speed" => {
                if let Some(b) = parse_bool(v) {
                    self.use_alt_speed = b;
                }
                true
            }
            "currix" => {
                let n = parse_number(v).unwrap_or(0.0);
                if n < 0.0 {
                    return false;
                }
                self.engine.set_index(n.trunc() as usize);
                true
            }
            "greedy_tour" | "shortest_tour" => self.set_bool(v, |s, b| s.greedy_tour = b),
            "draw_path_loop" => self.set_bool(v, |s, b| s.draw_path_loop = b),
            "wptflag_on_start" => self.set_bool(v, |s, b| s.wptflag_on_start = b),
            "reset_on_idle" => self.set_bool(v, |s, b| s.reset_on_idle = b),
            "eager_prev_index_flag" => self.set_bool(v, |s, b| s.eager_prev_index = b),
            "lead_to_start" => self.set_bool(v, |s, b| s.lead_to_start = b),
            "wpt_status" | "wpt_status_var" => self.set_var(v, |s, x| s.var_report = x),
            "wpt_index" | "wpt_index_var" => self.set_var(v, |s, x| s.var_index = x),
            "cycle_index_var" => self.set_var(v, |s, x| s.var_cyindex = x),
            "wpt_dist_to_prev" | "wpt_dist_to_next" => {
                let t = if v.is_empty() {
                    ""
                } else {
                    match no_white(v) {
                        Some(t) => t,
                        None => return false,
                    }
                };
                let t = if t.eq_ignore_ascii_case("silent") {
                    ""
                } else {
                    t
                };
                if param == "wpt_dist_to_prev" {
                    self.var_dist_to_prev = t.to_string();
                } else {
                    self.var_dist_to_next = t.to_string();
                }
                true
            }
            "post_suffix" => {
                if v.is_empty() {
                    self.post_suffix.clear();
                    return true;
                }
                let Some(t) = no_white(v) else {
                    return false;
                };
                self.post_suffix = if t.starts_with('_') {
                    t.to_string()
                } else {
                    format!("_{t}")
                };
                true
            }
            "cycleflag" => Self::set_flag(&mut self.cycleflags, v),
            "wptflag" => Self::set_flag(&mut self.wptflags, v),
            "ipf_type" | "ipf-type" => {
                if matches!(
                    lower.as_str(),
                    "zaic" | "zaic_spd" | "roc" | "rate_of_closure"
                ) {
                    self.ipf_type = lower;
                }
                true
            }
            "lead" => match parse_number(v) {
                Some(l) => {
                    self.lead = if l <= 0.0 { -1.0 } else { l };
                    true
                }
                None => false,
            },
            "lead_damper" => match parse_number(v) {
                Some(d) if d > 0.0 => {
                    self.lead_damper = d;
                    true
                }
                _ => false,
            },
            "lead_condition" => {
                let cond = v.replace(',', "=");
                if cond.trim().is_empty() || ctx.eval_condition(&cond).is_err() {
                    return false;
                }
                for var in crate::common::condition_vars(&cond) {
                    ctx.add_info_vars_no_warning(&var);
                }
                self.lead_conditions.push(cond);
                true
            }
            "order" => {
                let rev = match v {
                    "normal" => false,
                    "reverse" | "reversed" => true,
                    "toggle" => !self.engine.reverse(),
                    _ => return false,
                };
                self.engine.set_reverse(rev);
                true
            }
            "repeat" => {
                if lower == "forever" {
                    self.engine.set_repeats_endless(true);
                    ctx.set_perpetual(true);
                    return true;
                }
                match parse_nonneg(v) {
                    Some(n) => {
                        let n = n.trunc().min(f64::from(u32::MAX)) as u32;
                        self.engine.set_repeats(n);
                        self.engine.set_repeats_endless(false);
                        if n > 0 {
                            ctx.set_perpetual(true);
                        }
                        true
                    }
                    None => false,
                }
            }
            "radius" | "capture_radius" => match parse_number(v) {
                Some(r) if r > 0.0 => {
                    self.engine.set_capture_radius(r);
                    true
                }
                _ => false,
            },
            "nm_radius" | "slip_radius" => match parse_nonneg(v) {
                Some(r) => {
                    self.engine.set_slip_radius(r);
                    true
                }
                None => false,
            },
            "capture_line" => {
                match lower.as_str() {
                    "absolute" => {
                        self.engine.set_capture_line(true);
                        self.engine.set_capture_radius(0.0);
                        self.engine.set_slip_radius(0.0);
                        self.capture_line_absolute = true;
                    }
                    _ => match parse_bool(v) {
                        Some(b) => {
                            self.engine.set_capture_line(b);
                            self.capture_line_absolute = false;
                        }
                        None => return false,
                    },
                }
                true
            }
            "efficiency_measure" => match lower.as_str() {
                "all" | "off" => {
                    self.efficiency_all = lower == "all";
                    true
                }
                _ => false,
            },
            "crs_spd_zaic_ratio" | "patience" => match parse_number(v) {
                Some(r) if (1.0..=99.0).contains(&r) => {
                    self.crs_ratio = r;
                    true
                }
                _ => false,
            },
            "visual_hints" => self.hints.apply(v),
            "end_spd" => match parse_end_spd(v) {
                Some(e) => {
                    self.end_spd = Some(e);
                    true
                }
                None => false,
            },
            _ => false,
        }
    }

    fn set_bool(&mut self, v: &str, f: impl FnOnce(&mut Self, bool)) -> bool {
        match parse_bool(v) {
            Some(b) => {
                f(self, b);
                true
            }
            None => false,
        }
    }

    fn set_var(&mut self, v: &str, f: impl FnOnce(&mut Self, String)) -> bool {
        match status_var(v) {
            Some(x) => {
                f(self, x);
                true
            }
            None => false,
        }
    }

    /// The BHV_SETTINGS value.
    pub(super) fn settings(&self, name: &str) -> String {
        let b = |v: bool| if v { "true" } else { "false" };
        let mut s = format!("type=BHV_Waypoint,name={name}");
        s += &format!(",points={}", geometry::pts_spec(self.engine.points(), 1));
        s += &format!(",speed={}", fmt_x(self.cruise_speed, 2));
        s += &format!(",speed_alt={}", fmt_x(self.speed_alt, 2));
        s += &format!(",currix={}", self.engine.index());
        s += &format!(",greedy_tour={}", b(self.greedy_tour));
        s += &format!(",use_alt_speed={}", b(self.use_alt_speed));
        s += &format!(",wpt_status={}", self.var_report);
        s += &format!(",wpt_dist_to_prev={}", self.var_dist_to_prev);
        s += &format!(",wpt_dist_to_next={}", self.var_dist_to_next);
        s += &format!(",wpt_index={}", self.var_index);
        s += &format!(",cycle_index_var={}", self.var_cyindex);
        s += &format!(",post_suffix={}", self.post_suffix);
        s += &format!(",post_suffix={}", self.post_suffix);
        s += &format!(",ipf_type={}", self.ipf_type);
        s += &format!(",lead={}", fmt_x(self.lead, 2));
        s += &format!(",lead_damper={}", fmt_x(self.lead_damper, 2));
        s += &format!(",lead_to_start={}", b(self.lead_to_start));
        s += &format!(
            ",order={}",
            if self.engine.reverse() {
                "reverse"
            } else {
                "normal"
            }
        );
        if self.engine.repeats_endless() {
            s += ",repeats=forever";
        } else {
            s += &format!(",repeats={}", self.engine.repeats());
        }
        s += &format!(
            ",efficiency_measure={}",
            if self.efficiency_all { "all" } else { "off" }
        );
        s += &format!(",capture_radius={}", fmt_x(self.engine.capture_radius(), 2));
        s += &format!(",slip_radius={}", fmt_x(self.engine.slip_radius(), 2));
        if self.capture_line_absolute {
            s += ",capture_line=absolute";
        } else if self.engine.capture_line() {
            s += ",capture_line=true";
        }
        s += &format!(",crs_spd_zaic_ratio={}", fmt_x(self.crs_ratio, 2));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hints() {
        let mut h = WptHints::default();
        assert!(h.apply("nextpt_lcolor=red, vertex_size=4"));
        assert_eq!(h.nextpt_label_color, "red");
        assert_eq!(h.vertex_size, 4.0);
        assert!(!h.apply("vertex_size=4,edge_color=nocolor"));
        assert_eq!(h.edge_color, "white");
        // Any key is a hint: a colour when its name says `color`, else a number.
        assert!(h.apply("bogus=3"));
        assert!(!h.apply("bogus=x"));
        assert!(h.apply("edge_color=off"));
    }

    #[test]
    fn point_strings() {
        let p = points_from_string("0,-40 : 60,-40", 0.0, 0.0).unwrap();
        assert_eq!(p.len(), 2);
        // radial polygon: converted starting at the vertex nearest (0,0)
        let p = points_from_string(
            "format=radial, x=50, y=-80, radius=20, pts=8, snap=1",
            0.0,
            0.0,
        )
        .unwrap();
        assert_eq!(p.len(), 8);
        assert_eq!((p[0].x, p[0].y), (42.0, -62.0));
        assert_eq!((p[1].x, p[1].y), (58.0, -62.0));
        assert!(points_from_string("hello", 0.0, 0.0).is_none());
        assert!(points_from_string("", 0.0, 0.0).is_none());
        assert_eq!(parse_end_spd("slow_dist=20,stop_dist=5"), Some((20.0, 5.0)));
        assert_eq!(parse_end_spd("slow_dist=5,stop_dist=20"), None);
        assert_eq!(parse_end_spd("slow_dist=0"), None);
    }

    #[test]
    fn visual_hints_take_every_colour_form_and_any_hint_key() {
        let mut h = WptHints::default();
        // The alpha mission's hints, the misspelt and `_`/case forms, triples.
        for spec in [
            "nextpt_color=yellow",
            "nextpt_vertex_size=8",
            "nextpt_lcolor=gray70",
            "vertex_color=dodger_blue, edge_color=white",
            "vertex_size=5, edge_size=1",
            "vertex_color=yellow, line_color=white",
            "label_color=Dark_Khaki, edge_color=tomatao",
            "vertex_color=0.5$0.25$1",
            "edge_color=off",
        ] {
            assert!(h.apply(spec), "{spec}");
        }
        assert_eq!(h.nextpt_label_color, "gray70");
        assert_eq!(h.nextpt_vertex_size, 8.0);
        assert_eq!(h.label_color, "Dark_Khaki");
        assert_eq!(h.vertex_color, "0.5$0.25$1");
        assert_eq!(h.edge_color, "off");
        // All or nothing: one bad entry refuses the line and changes nothing.
        let before = h.clone();
        for spec in [
            "vertex_color=red, edge_color=gray71",
            "vertex_size=2, edge_color=0,0,0",
            "line_color=hex:00,00,00",
            "label=tour",
            "vertex_size=big",
            "nextpt_color",
        ] {
            assert!(!h.apply(spec), "{spec}");
            assert_eq!(h, before, "{spec}");
        }
    }

    #[test]
    fn flags_are_checked_like_the_common_flags() {
        for ok in ["HIT = $[NI]", "#all+ X = 1", "clearall", "X = 1 [if] A = 2"] {
            assert!(flag_ok(ok), "{ok}");
        }
        for bad in ["NOEQUALS", "X = ", " = 3", "X = 1 [if] ((A"] {
            assert!(!flag_ok(bad), "{bad}");
        }
    }
}
