//! BHV_Loiter (behaviors-std.md §3): circle a convex polygon, acquiring it from outside
//! or inside.

pub mod engine;
pub mod ipf;
mod posts;

use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{FunctionData, PostValue};
use geometry::{
    angle_diff, dist, fmt_x, is_color, parse_point, parse_polygon, rel_ang, Attrs, Polygon,
};

use crate::common::Platform;
use crate::common::{no_white, parse_bool, parse_nonneg, parse_number, platform_update, subst};
use crate::waypoint::engine::{Advance, WaypointEngine};

/// Loiter visual hints.
#[derive(Clone, Debug)]
struct Hints {
    vertex_size: f64,
    edge_size: f64,
    vertex_color: String,
    edge_color: String,
    nextpt_color: String,
    nextpt_lcolor: String,
    nextpt_vertex_size: f64,
    label: String,
    label_color: String,
}

impl Default for Hints {
    fn default() -> Self {
        Hints {
            vertex_size: 1.0,
            edge_size: 1.0,
            vertex_color: "dodger_blue".into(),
            edge_color: "white".into(),
            nextpt_color: "yellow".into(),
            nextpt_lcolor: "aqua".into(),
            nextpt_vertex_size: 5.0,
            label: String::new(),
            label_color: String::new(),
        }
    }
}

impl Hints {
    /// Apply `key=value,...`; invalid entries are silently ignored.
    fn apply(&mut self, spec: &str) {
        for part in spec.split(',') {
            let Some((k, v)) = part.split_once('=') else {
                continue;
            };
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            let color = || is_color(v).then(|| v.to_string());
            let num = || parse_number(v);
            match k.as_str() {
                "vertex_size" => self.vertex_size = num().unwrap_or(self.vertex_size),
                "edge_size" => self.edge_size = num().unwrap_or(self.edge_size),
                "nextpt_vertex_size" => {
                    self.nextpt_vertex_size = num().unwrap_or(self.nextpt_vertex_size)
                }
                "vertex_color" => self.vertex_color = color().unwrap_or(self.vertex_color.clone()),
                "edge_color" => self.edge_color = color().unwrap_or(self.edge_color.clone()),
                "nextpt_color" => self.nextpt_color = color().unwrap_or(self.nextpt_color.clone()),
                "nextpt_lcolor" | "nextpt_label_color" => {
                    self.nextpt_lcolor = color().unwrap_or(self.nextpt_lcolor.clone())
                }
                "lcolor" | "label_color" => {
                    self.label_color = color().unwrap_or(self.label_color.clone())
                }
                "label" => self.label = v.to_string(),
                _ => {}
            }
        }
    }
}

/// The BHV_Loiter behavior.
pub struct BhvLoiter {
    domain: String,
    /// The path spec, formatted again only when the path or its look changes.
    view_cache: geometry::SeglistSpecCache,
    ivp_domain: Option<ivp::Domain>,
    ipf: ipf::Builder,
    speed_high: Option<f64>,
    poly: Polygon,
    engine: WaypointEngine,
    clockwise: bool,
    dynamic_clockwise: bool,
    speed: f64,
    speed_alt: f64,
    use_alt_speed: bool,
    acquire_dist: f64,
    patience: f64,
    center_pending: String,
    center_activate: bool,
    slingshot: f64,
    spiral: f64,
    ipf_type: String,
    suffix: String,
    hints: Hints,
    posts: posts::Posts,
    // run-time state
    plat: Platform,
    acquire_mode: bool,
    mode: String,
    dist_to_poly: f64,
    eta_to_poly: f64,
    nextpt: (f64, f64),
    bng_last: Option<f64>,
    bng_total: f64,
}

impl BhvLoiter {
    pub fn new(helm: &HelmDomain) -> Self {
        let mut engine = WaypointEngine::new();
        engine.set_perpetual(true);
        engine.set_repeats_endless(true);
        BhvLoiter {
            view_cache: Default::default(),
            domain: helm.sub_domain(&["course", "speed"]),
            ivp_domain: helm.ivp_domain(&["course", "speed"]),
            ipf: ipf::Builder::default(),
            speed_high: helm.var("speed").map(|v| v.high),
            poly: Polygon::default(),
            engine,
            clockwise: true,
            dynamic_clockwise: false,
            speed: 0.0,
            speed_alt: -1.0,
            use_alt_speed: false,
            acquire_dist: 10.0,
            patience: 50.0,
            center_pending: String::new(),
            center_activate: false,
            slingshot: -1.0,
            spiral: engine::DEFAULT_SPIRAL,
            ipf_type: "zaic".into(),
            suffix: String::new(),
            hints: Hints::default(),
            posts: posts::Posts::default(),
            plat: Platform::default(),
            acquire_mode: true,
            mode: "idle".into(),
            dist_to_poly: 0.0,
            eta_to_poly: 0.0,
            nextpt: (0.0, 0.0),
            bng_last: None,
            bng_total: 0.0,
        }
    }

    /// Orient the polygon to `clockwise` and (re)load it as the waypoint list.
    fn orient_and_load(&mut self) {
        if self.poly.size() >= 3 && self.poly.is_clockwise() != self.clockwise {
            self.poly.reverse();
        }
        self.engine.set_points(self.poly.vertices().to_vec());
        self.acquire_mode = true;
    }

    fn desired_speed(&self) -> f64 {
        if self.use_alt_speed && self.speed_alt >= 0.0 {
            self.speed_alt
        } else {
            self.speed
        }
    }

    /// Apply a center assignment (`present_position`, `x,y`, `x=..,y=..`, `,x=V`).
    fn apply_center(&mut self, spec: &str) -> bool {
        let s = spec.trim().to_ascii_lowercase();
        let (cx, cy) = self.poly.center();
        let target = if s == "present_position" {
            Some((self.plat.x, self.plat.y))
        } else if let Some(p) = parse_point(&s) {
            Some((p.x, p.y))
        } else {
            let (mut x, mut y) = (None, None);
            for part in s.split(',') {
                if let Some((k, v)) = part.split_once('=') {
                    match k.trim() {
                        "x" => x = parse_number(v),
                        "y" => y = parse_number(v),
                        _ => {}
                    }
                }
            }
            (x.is_some() || y.is_some()).then(|| (x.unwrap_or(cx), y.unwrap_or(cy)))
        };
        let Some((x, y)) = target else {
            return false;
        };
        self.poly.new_center(x, y);
        self.engine
            .replace_points_keep_state(self.poly.vertices().to_vec());
        true
    }

    /// `updateInfoIn`: ownship and the distance/ETA to the polygon.
    fn update_info(&mut self, ctx: &mut Ctx<'_>) -> bool {
        if self.poly.is_empty() {
            ctx.post_wmessage("Empty/NULL Loiter Specification.");
            return false;
        }
        let Some(p) = platform_update(ctx) else {
            return false;
        };
        self.plat = p;
        let mut d = self.poly.dist_to_poly(p.x, p.y);
        if self.poly.contains(p.x, p.y) {
            d = -d;
        }
        self.dist_to_poly = d;
        self.eta_to_poly = if d > 0.0 && p.heading > 0.001 {
            d / p.speed
        } else {
            0.0
        };
        true
    }

    fn set_acquire_index(&mut self) {
        if let Some(i) = engine::acquire_vertex(
            &self.poly,
            self.clockwise,
            self.spiral,
            self.plat.x,
            self.plat.y,
            self.plat.heading,
        ) {
            self.engine.set_index(i);
        }
    }

    fn poly_label(&self, ctx: &Ctx<'_>, strip: bool) -> String {
        if !self.hints.label.is_empty() {
            return self.hints.label.clone();
        }
        let mut name = ctx.name().to_ascii_lowercase();
        if strip {
            name = name.replace("(d)", "");
        }
        format!("{}_{name}", ctx.ownship())
    }

    fn erase_visuals(&self, ctx: &mut Ctx<'_>) {
        let (x, y) = self.nextpt;
        let pt = format!(
            "x={},y={},active=false,label={}_waypoint",
            fmt_x(x, 2),
            fmt_x(y, 2),
            ctx.ownship()
        );
        ctx.post_message("VIEW_POINT", &pt);
        let attrs = Attrs {
            active: Some(false),
            label: self.poly_label(ctx, true),
            ..Attrs::default()
        };
        let poly = geometry::seglist_spec(self.engine.points(), 1, &attrs);
        ctx.post_message("VIEW_POLYGON", &poly);
    }

    /// The polygon's and the next point's view attributes.
    fn view_attrs(&self, ctx: &Ctx<'_>) -> (Attrs, Attrs) {
        let poly = Attrs {
            label: self.poly_label(ctx, false),
            label_color: self.hints.label_color.clone(),
            edge_color: self.hints.edge_color.clone(),
            vertex_color: self.hints.vertex_color.clone(),
            vertex_size: Some(self.hints.vertex_size),
            edge_size: Some(self.hints.edge_size),
            ..Attrs::default()
        };
        let pt = Attrs {
            label: format!("{}_waypoint", ctx.ownship()),
            label_color: self.hints.nextpt_lcolor.clone(),
            vertex_color: self.hints.nextpt_color.clone(),
            vertex_size: Some(self.hints.nextpt_vertex_size),
            ..Attrs::default()
        };
        (poly, pt)
    }

    fn post_views(&mut self, ctx: &mut Ctx<'_>) {
        if self.posts.views.is_none() {
            self.posts.views = Some(self.view_attrs(ctx));
        }
        let Some((poly_attrs, pt_attrs)) = &self.posts.views else {
            return;
        };
        let poly = self.view_cache.get(self.engine.points(), 1, poly_attrs);
        ctx.post_message("VIEW_POLYGON", poly);
        let pt = &mut self.posts.point;
        pt.clear();
        geometry::push_point_spec(pt, self.nextpt.0, self.nextpt.1, None, pt_attrs);
        ctx.post_message("VIEW_POINT", pt);
    }

    fn post_status(&mut self, ctx: &mut Ctx<'_>) {
        use posts::{ACQUIRE, DIST_TO_POLY, ETA_TO_POLY, INDEX, MODE, REPORT};
        let ix = self.engine.index();
        let mut report = std::mem::take(&mut self.posts.report);
        report.clear();
        report.push_str("index=");
        behavior_api::push_u64(&mut report, ix as u64);
        report.push_str(",capture_hits=");
        behavior_api::push_u64(&mut report, u64::from(self.engine.capture_hits()));
        report.push_str(",nonmono_hits=");
        behavior_api::push_u64(&mut report, u64::from(self.engine.slip_hits()));
        report.push_str(",acquire_mode=");
        report.push_str(if self.acquire_mode { "true" } else { "false" });
        let names = self.posts.names(&self.suffix);
        ctx.post_message(&names[REPORT], &report);
        ctx.post_message_num(&names[INDEX], ix as f64);
        ctx.post_message(&names[MODE], &self.mode);
        ctx.post_message_num(&names[ACQUIRE], if self.acquire_mode { 1.0 } else { 0.0 });
        let d = self.dist_to_poly;
        let d = if d > 10.0 { (d + 0.5).trunc() } else { d };
        ctx.post_message_num(&names[DIST_TO_POLY], d);
        let e = self.eta_to_poly;
        let e = if e > 10.0 || e == 0.0 {
            (e + 0.5).trunc()
        } else {
            e
        };
        ctx.post_message_num(&names[ETA_TO_POLY], e);
        self.posts.report = report;
    }

    fn settings(&self, name: &str) -> String {
        let (cx, cy) = self.poly.center();
        format!(
            "type=BHV_Loiter,name={name},x={cx:.2},y={cy:.2},clockwise={},dynamic_clockwise={},center_activate={},desired_speed={:.1},polygon=\"{}\"",
            self.clockwise,
            self.dynamic_clockwise,
            self.center_activate,
            self.desired_speed(),
            self.poly.spec(1)
        )
    }

    fn build_function(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let dom = self.ivp_domain.as_ref()?;
        let o = ipf::LoiterObjective {
            ipf_type: &self.ipf_type,
            speed: self.desired_speed(),
            bearing: rel_ang(self.plat.x, self.plat.y, self.nextpt.0, self.nextpt.1),
            patience: self.patience,
        };
        match self.ipf.build(dom, &o) {
            Ok(mut f) => {
                f.set_pwt(ctx.priority());
                Some(function_data(f))
            }
            Err(msg) => {
                if let Some(msg) = msg {
                    ctx.post_wmessage(msg);
                }
                None
            }
        }
    }

    fn reset_slingshot(&mut self) {
        self.bng_last = None;
        self.bng_total = 0.0;
    }

    /// `clockwise=best`: the direction whose entry vertex needs the smaller turn.
    fn choose_direction(&mut self) {
        let mut cw = self.poly.clone();
        if !cw.is_clockwise() {
            cw.reverse();
        }
        let mut ccw = cw.clone();
        ccw.reverse();
        let (x, y, h) = (self.plat.x, self.plat.y, self.plat.heading);
        let turn = |p: &Polygon, c: bool| {
            engine::acquire_vertex(p, c, self.spiral, x, y, h)
                .map(|i| angle_diff(h, rel_ang(x, y, p.vx(i), p.vy(i))))
        };
        if let (Some(a), Some(b)) = (turn(&cw, true), turn(&ccw, false)) {
            self.clockwise = a <= b;
        }
    }
}

impl IvpBehavior for BhvLoiter {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_loiter".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        // Names and view attributes follow the parameters.
        self.posts.forget();
        let v = value.trim();
        let lower = v.to_ascii_lowercase();
        match param {
            "polygon" => {
                let Some(mut p) = parse_polygon(v) else {
                    return false;
                };
                if !p.is_convex() {
                    return false;
                }
                p.apply_snap(0.1);
                self.poly = p;
                self.orient_and_load();
            }
            "clockwise" => {
                if lower == "best" {
                    self.dynamic_clockwise = true;
                    return true;
                }
                let b = if lower == "toggle" {
                    !self.clockwise
                } else {
                    match parse_bool(v) {
                        Some(b) => b,
                        None => return false,
                    }
                };
                self.dynamic_clockwise = false;
                self.clockwise = b;
                self.orient_and_load();
            }
            "speed" => match parse_nonneg(v) {
                Some(s) => {
                    self.speed = match self.speed_high {
                        Some(h) if s > h => h,
                        _ => s,
                    }
                }
                None => return false,
            },
            "speed_alt" => match parse_number(v) {
                Some(s) => self.speed_alt = s,
                None => return false,
            },
            "use_alt_speed" => match parse_bool(v) {
                Some(b) => self.use_alt_speed = b,
                None => return false,
            },
            "radius" | "capture_radius" => match parse_nonneg(v) {
                Some(r) => self.engine.set_capture_radius(r),
                None => return false,
            },
            "nm_radius" | "slip_radius" => match parse_nonneg(v) {
                Some(r) => self.engine.set_slip_radius(r),
                None => return false,
            },
            "acquire_dist" | "acquire_distance" => match parse_nonneg(v) {
                Some(d) => self.acquire_dist = d,
                None => return false,
            },
            "patience" => match parse_number(v) {
                Some(p) if (1.0..=99.0).contains(&p) => self.patience = p,
                _ => return false,
            },
            "center_assign" => {
                if !self.apply_center(&lower) {
                    return false;
                }
            }
            "xcenter_assign" | "ycenter_assign" => {
                let Some(n) = parse_number(v) else {
                    return false;
                };
                let k = if param == "xcenter_assign" { "x" } else { "y" };
                self.center_pending.push_str(&format!(",{k}={n}"));
            }
            "center_activate" => match lower.as_str() {
                "true" => self.center_activate = true,
                "false" => self.center_activate = false,
                _ => return false,
            },
            "mod_poly_rad" => {
                let Some(n) = parse_number(v) else {
                    return false;
                };
                self.poly.grow_radius(n);
                self.engine
                    .replace_points_keep_state(self.poly.vertices().to_vec());
            }
            "slingshot" => match parse_nonneg(v) {
                Some(s) => self.slingshot = s,
                None => return false,
            },
            "spiral_factor" => match parse_number(v) {
                Some(s) => self.spiral = engine::spiral_from_param(s),
                None => return false,
            },
            "ipf_type" | "ipf-type" => {
                if lower == "zaic" || lower == "zaic_spd" {
                    self.ipf_type = lower;
                }
            }
            "post_suffix" => match no_white(v) {
                Some(s) => self.suffix = format!("_{}", s.to_ascii_uppercase()),
                None => return false,
            },
            "visual_hints" => self.hints.apply(v),
            _ => return false,
        }
        let _ = ctx;
        true
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED");
        let s = self.settings(&ctx.name());
        ctx.post_repeatable_message("BHV_SETTINGS", PostValue::from(s.as_str()));
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
        self.mode = "idle".into();
        self.post_status(ctx);
        self.reset_slingshot();
        if self.center_activate {
            self.center_pending = "present_position".into();
        }
    }

    fn on_idle_to_run(&mut self, ctx: &mut Ctx<'_>) {
        let s = self.settings(&ctx.name());
        ctx.post_repeatable_message("BHV_SETTINGS", PostValue::from(s.as_str()));
        if !self.update_info(ctx) {
            return;
        }
        if self.dynamic_clockwise {
            self.choose_direction();
            self.orient_and_load();
        }
        self.set_acquire_index();
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
        ctx.post_message("LOITER_COMPLETE", "true");
        self.reset_slingshot();
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.update_info(ctx) {
            self.erase_visuals(ctx);
            return None;
        }
        let mode = engine::loiter_mode(&self.mode, self.dist_to_poly, self.acquire_dist);
        if self.mode != mode {
            self.mode.clear();
            self.mode.push_str(mode);
        }
        if !self.center_pending.is_empty() {
            let pending = std::mem::take(&mut self.center_pending);
            self.apply_center(pending.trim_start_matches(','));
        }
        self.acquire_mode = self.dist_to_poly > self.acquire_dist;
        if self.acquire_mode {
            self.set_acquire_index();
        }
        let mut sling_done = false;
        if !self.acquire_mode && self.slingshot >= 0.0 {
            let (cx, cy) = self.poly.center();
            let bng = rel_ang(self.plat.x, self.plat.y, cx, cy);
            if let Some(last) = self.bng_last {
                let delta = angle_diff(bng, last);
                self.bng_total += delta;
                ctx.post_message_num("LOITER_BNG_TOTAL", self.bng_total);
                ctx.post_message_num("LOITER_BNG_DELTA", delta);
                sling_done = self.bng_total > self.slingshot;
            }
            self.bng_last = Some(bng);
        }
        self.engine.set_perpetual(true);
        let res = self.engine.advance(self.plat.x, self.plat.y);
        if matches!(res, Advance::Advanced | Advance::Cycled) {
            self.acquire_mode = false;
        }
        let next = self.engine.current()?;
        self.nextpt = (next.x, next.y);
        ctx.post_message_num(
            "LOITER_DIST_TO_VERT",
            dist(self.plat.x, self.plat.y, next.x, next.y),
        );
        let f = self.build_function(ctx);
        self.post_views(ctx);
        self.post_status(ctx);
        if sling_done {
            ctx.set_complete();
        }
        f
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        let mut s = text.to_string();
        if !s.contains("$[") && !s.contains("$(") {
            return Some(s);
        }
        let (cx, cy) = self.poly.center();
        subst(&mut s, "PTS", &self.poly.size().to_string());
        subst(&mut s, "CX", &fmt_x(cx, 2));
        subst(&mut s, "CY", &fmt_x(cy, 2));
        subst(
            &mut s,
            "CENTER",
            &format!("x={},y={}", fmt_x(cx, 2), fmt_x(cy, 2)),
        );
        subst(
            &mut s,
            "CWISE",
            if self.clockwise { "true" } else { "false" },
        );
        subst(&mut s, "RAD", &fmt_x(self.poly.max_radius(), 2));
        Some(s)
    }
}

#[cfg(test)]
mod tests;
