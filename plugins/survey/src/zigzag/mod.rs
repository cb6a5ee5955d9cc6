//! BHV_ZigZag (behaviors-more.md §8): from a stem heading, steer `zig_angle` to one side,
//! then the other, counting turns; complete after `max_zig_legs` turns or a distance
//! along the stem.

use behavior_api::flag::{expand_macros, has_macro, FlagList};
use behavior_api::geometry::{
    angle360, angle_diff, dist, fmt_x, perp_seg_int_pt, project_point, push_pts_props_spec,
    seglist_erase_spec, Attrs, Vertex,
};
use behavior_api::ivp;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::objective::{Objective, Shape};
use crate::odometer::Odometer;

mod params;
#[cfg(test)]
mod tests;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Stem,
    Port,
    Star,
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Stem => "stem",
            Side::Port => "port",
            Side::Star => "star",
        }
    }
}

/// NAV data older than this is stale.
const STALE: f64 = 5.0;

/// `containsAngle(a, b, q)` (behaviors-more.md §0.1): is q inside the arc a..b (the
/// shorter way)? q is not normalised.
pub fn contains_angle(a: f64, b: f64, q: f64) -> bool {
    let (mut a, mut b) = (angle360(a), angle360(b));
    if a == b {
        return q == b;
    }
    if (b - a).abs() == 180.0 {
        return true;
    }
    if a > b {
        std::mem::swap(&mut a, &mut b);
    }
    if b - a > 180.0 {
        q >= b || q <= a
    } else {
        a <= q && q <= b
    }
}

/// `distToLine(p; a, b)`: distance from p to the infinite line through a and b.
pub fn dist_to_line(px: f64, py: f64, ax: f64, ay: f64, bx: f64, by: f64) -> f64 {
    let (fx, fy) = if (ax - bx).abs() < 0.0001 {
        (ax, py)
    } else if (ay - by).abs() < 0.0001 {
        (px, ay)
    } else {
        let m = (by - ay) / (bx - ax);
        let c = ay - m * ax;
        let m2 = -1.0 / m;
        let c2 = py - m2 * px;
        let fx = (c2 - c) / (m - m2);
        (fx, m2 * fx + c2)
    };
    dist(px, py, fx, fy)
}

pub struct ZigZag {
    /// The function's builders, kept between iterations.
    objective: Objective,
    /// The set and requested heading lines' attributes and text, kept.
    line_attrs: [Attrs; 2],
    line_text: String,
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    speed_max: f64,
    // Parameters.
    speed: f64,
    orig_speed: f64,
    speed_on_active: bool,
    stem_hdg: f64,
    stem_on_active: bool,
    hdg_thresh: f64,
    fierce: bool,
    zig_angle: f64,
    zig_angle_fierce: f64,
    zig_first: Side,
    max_zig_legs: u64,
    max_stem_odo: f64,
    zigflags: FlagList,
    zagflags: FlagList,
    portflags: FlagList,
    starflags: FlagList,
    portflagx: FlagList,
    starflagx: FlagList,
    draw_set: bool,
    draw_req: bool,
    set_color: String,
    req_color: String,
    // State.
    os: (f64, f64, f64, f64),
    side: Side,
    set_hdg: f64,
    req_hdg: f64,
    n: u64,
    n_ever: u64,
    odo: Odometer,
    zig_odo: Odometer,
    zag_odo: Odometer,
    stem: Option<((f64, f64), (f64, f64))>,
    stem_dist: f64,
    stem_odo: f64,
    z_start: f64,
    z_min: f64,
    z_delta: f64,
}

impl ZigZag {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        ZigZag {
            objective: Objective::default(),
            line_attrs: Default::default(),
            line_text: String::new(),
            domain: helm_domain.sub_domain(&["course", "speed"]),
            ivp_domain: helm_domain.ivp_domain(&["course", "speed"]),
            speed_max: helm_domain.var("speed").map_or(0.0, |v| v.high),
            speed: 0.0,
            orig_speed: 0.0,
            speed_on_active: false,
            stem_hdg: 0.0,
            stem_on_active: false,
            hdg_thresh: 0.0,
            fierce: false,
            zig_angle: 0.0,
            zig_angle_fierce: -1.0,
            zig_first: Side::Port,
            max_zig_legs: 2,
            max_stem_odo: -1.0,
            zigflags: FlagList::default(),
            zagflags: FlagList::default(),
            portflags: FlagList::default(),
            starflags: FlagList::default(),
            portflagx: FlagList::default(),
            starflagx: FlagList::default(),
            draw_set: true,
            draw_req: true,
            set_color: "white".into(),
            req_color: "yellow".into(),
            os: (0.0, 0.0, 0.0, 0.0),
            side: Side::Stem,
            set_hdg: 0.0,
            req_hdg: 0.0,
            n: 0,
            n_ever: 0,
            odo: Odometer::default(),
            zig_odo: Odometer::default(),
            zag_odo: Odometer::default(),
            stem: None,
            stem_dist: 0.0,
            stem_odo: 0.0,
            z_start: 0.0,
            z_min: -1.0,
            z_delta: 0.0,
        }
    }

    fn legs_complete(&self) -> bool {
        self.n > self.max_zig_legs
    }

    /// A NAV read with the error severity: found and not stale.
    fn read_fresh(ctx: &mut Ctx<'_>, var: &str) -> Option<f64> {
        let v = ctx.get_buffer_double_val(var)?;
        (ctx.get_buffer_time_val(var) <= STALE).then_some(v)
    }

    fn read_position(&mut self, ctx: &mut Ctx<'_>) -> bool {
        let x = ctx.get_buffer_double_val("NAV_X");
        let y = ctx.get_buffer_double_val("NAV_Y");
        let stale =
            ctx.get_buffer_time_val("NAV_X") > STALE || ctx.get_buffer_time_val("NAV_Y") > STALE;
        match y {
            Some(y) if !stale => {
                self.os.0 = x.unwrap_or(0.0);
                self.os.1 = y;
                true
            }
            _ => {
                ctx.post_emessage("ownship NAV_X/Y not found or stale.");
                false
            }
        }
    }

    fn read_heading(&mut self, ctx: &mut Ctx<'_>) -> bool {
        match Self::read_fresh(ctx, "NAV_HEADING") {
            Some(h) => {
                self.os.2 = h;
                true
            }
            None => {
                ctx.post_emessage("ownship NAV_HEADING not found or stale.");
                false
            }
        }
    }

    fn read_speed(&mut self, ctx: &mut Ctx<'_>) -> bool {
        match Self::read_fresh(ctx, "NAV_SPEED") {
            Some(v) => {
                self.os.3 = v;
                true
            }
            None => {
                ctx.post_emessage("ownship NAV_SPEED not found or stale.");
                false
            }
        }
    }

    fn post(&self, ctx: &mut Ctx<'_>, flags: &FlagList) {
        flags.post(ctx, false, |f| self.expand(f));
    }

    fn set_side(&mut self, ctx: &mut Ctx<'_>, new: Side) {
        if new == self.side {
            return;
        }
        if !self.legs_complete() {
            match new {
                Side::Star => self.post(ctx, &self.starflags),
                Side::Port => self.post(ctx, &self.portflags),
                Side::Stem => {}
            }
        }
        self.side = new;
    }

    fn reset_odometry(&mut self) {
        self.odo.reset();
        self.zig_odo.reset();
        self.zag_odo.reset();
        self.stem_dist = 0.0;
        self.stem_odo = 0.0;
    }

    fn update_set_heading(&mut self, ctx: &mut Ctx<'_>) {
        let (stem, zig) = (self.stem_hdg, self.zig_angle);
        if self.side == Side::Stem {
            let first = self.zig_first;
            self.set_side(ctx, first);
            self.set_hdg = angle360(if first == Side::Port {
                stem - zig
            } else {
                stem + zig
            });
            return;
        }
        let osh = self.os.2;
        let diff = angle_diff(osh, self.set_hdg);
        let done = diff < self.hdg_thresh
            || match self.side {
                Side::Port => !contains_angle(osh, osh - 170.0, self.set_hdg),
                _ => !contains_angle(osh, osh + 170.0, self.set_hdg),
            };
        let osv = self.os.3;
        if self.z_min < 0.0 || osv < self.z_min {
            self.z_min = osv;
        }
        self.z_delta = self.z_start - self.z_min;
        if !done {
            return;
        }
        self.n += 1;
        self.n_ever += 1;
        self.post(ctx, &self.zigflags);
        if self.n & 1 == 0 {
            self.post(ctx, &self.zagflags);
        }
        if self.side == Side::Port {
            self.post(ctx, &self.portflagx);
            self.set_side(ctx, Side::Star);
            self.set_hdg = angle360(stem + zig);
        } else {
            self.post(ctx, &self.starflagx);
            self.set_side(ctx, Side::Port);
            self.set_hdg = angle360(stem - zig);
        }
        self.zig_odo.reset();
        if self.n & 1 == 0 {
            self.zag_odo.reset();
        }
        self.z_start = osh;
        self.z_min = -1.0;
        self.z_delta = 0.0;
    }

    fn post_visuals(&mut self, ctx: &mut Ctx<'_>) {
        let (x, y) = (self.os.0, self.os.1);
        for k in 0..2 {
            let (draw, hdg, label, color) = if k == 0 {
                (self.draw_set, self.set_hdg, "zig_set_", &self.set_color)
            } else {
                (self.draw_req, self.req_hdg, "zig_req_", &self.req_color)
            };
            if !draw {
                continue;
            }
            let (ex, ey) = project_point(hdg, 20.0, x, y);
            let color = if color == "off" {
                "invisible"
            } else {
                color.as_str()
            };
            // The attributes are kept (made again only when a colour changed): the
            // lines are posted every iteration.
            let attrs = &mut self.line_attrs[k];
            if attrs.label.is_empty() || attrs.edge_color != color {
                *attrs = Attrs {
                    label: format!("{label}{}", ctx.ownship()),
                    label_color: "invisible".into(),
                    edge_color: color.into(),
                    vertex_color: color.into(),
                    duration: Some(5.0),
                    vertex_size: Some(2.0),
                    edge_size: Some(1.0),
                    ..Attrs::default()
                };
            }
            let pts = [Vertex::new(x, y), Vertex::new(ex, ey)];
            self.line_text.clear();
            push_pts_props_spec(&mut self.line_text, &pts, &[], 1);
            attrs.push_spec(&mut self.line_text);
            ctx.post_message("VIEW_SEGLIST", &self.line_text);
        }
    }

    fn function(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let dom = self.ivp_domain.as_ref()?;
        let shape = Shape {
            spd_high_util: 85.0,
            peak_width: Some(0.0),
        };
        let mut f = self
            .objective
            .build(dom, self.speed, self.req_hdg, 50.0, shape)?;
        f.normalize(0.0, 100.0);
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }

    /// The type's macros (§8.6).
    pub fn expand(&self, text: &str) -> String {
        if !has_macro(text) {
            return text.to_string();
        }
        let f3 = |v: f64| fmt_x(v, 3);
        let togo = self.max_zig_legs.saturating_sub(self.n).to_string();
        let subs: Vec<(&str, String)> = vec![
            ("ODO", f3(self.odo.total())),
            ("ZIG_ODO", f3(self.zig_odo.total())),
            ("ZAG_ODO", f3(self.zag_odo.total())),
            ("STEM_DIST", fmt_x(self.stem_dist, 2)),
            ("STEM_ODO", fmt_x(self.stem_odo, 2)),
            ("ZIGS_EVER", self.n_ever.to_string()),
            ("ZAGS_EVER", (self.n_ever / 2).to_string()),
            ("ZIGS_TOGO", togo.clone()),
            ("ZAGS_TOGO", togo),
            ("ZIGS", self.n.to_string()),
            ("ZAGS", (self.n / 2).to_string()),
            ("STEM_HDG", f3(self.stem_hdg)),
            ("STEM_SPD", f3(self.orig_speed)),
            ("ZIG_START_SPD", f3(self.z_start)),
            ("ZIG_MIN_SPD", f3(self.z_min)),
            ("ZIG_SPD_DELTA", f3(self.z_delta)),
            ("ZIG_PORT", (self.side == Side::Port).to_string()),
            ("ZIG_STAR", (self.side == Side::Star).to_string()),
            ("ZIG_SIDE", self.side.name().to_string()),
        ];
        expand_macros(text, &subs)
    }
}

impl IvpBehavior for ZigZag {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        self.set_zig_param(param, value)
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_SPEED, NAV_HEADING");
    }

    fn on_idle_to_run(&mut self, ctx: &mut Ctx<'_>) {
        if self.stem_on_active && self.read_heading(ctx) {
            self.stem_hdg = self.os.2;
        }
        if self.speed_on_active && self.read_speed(ctx) {
            self.speed = self.os.3;
            self.orig_speed = self.os.3;
        }
        self.read_position(ctx);
        self.n = 0;
        self.reset_odometry();
        let s1 = (self.os.0, self.os.1);
        self.stem = Some((s1, project_point(self.stem_hdg, 5000.0, s1.0, s1.1)));
        self.side = Side::Stem;
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        let own = ctx.ownship();
        ctx.post_message(
            "VIEW_SEGLIST",
            &seglist_erase_spec(&format!("zig_set_{own}")),
        );
        ctx.post_message(
            "VIEW_SEGLIST",
            &seglist_erase_spec(&format!("zig_req_{own}")),
        );
        self.reset_odometry();
        self.n = 0;
        self.side = Side::Stem;
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !(self.read_position(ctx) && self.read_heading(ctx) && self.read_speed(ctx)) {
            return None;
        }
        let (x, y, h, v) = self.os;
        ctx.set_platform(x, y, h, v);
        for o in [&mut self.odo, &mut self.zig_odo, &mut self.zag_odo] {
            o.update(x, y);
        }
        if let Some(((ax, ay), (bx, by))) = self.stem {
            self.stem_dist = dist_to_line(x, y, ax, ay, bx, by);
            let (px, py) = perp_seg_int_pt(ax, ay, bx, by, x, y);
            self.stem_odo = dist(ax, ay, px, py);
        }
        self.update_set_heading(ctx);
        self.req_hdg = if self.fierce {
            let dh = if self.zig_angle_fierce > 0.0 {
                self.zig_angle_fierce
            } else {
                self.zig_angle
            };
            match self.side {
                Side::Port => h - dh,
                Side::Star => h + dh,
                Side::Stem => self.stem_hdg,
            }
        } else {
            self.set_hdg
        };
        self.req_hdg = angle360(self.req_hdg);
        self.post_visuals(ctx);
        if self.legs_complete() || (self.max_stem_odo > 0.0 && self.stem_odo >= self.max_stem_odo) {
            ctx.set_complete();
            return None;
        }
        self.function(ctx)
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        Some(self.expand(text))
    }
}
