//! BHV_OpRegion: the operating-region safety envelope. It builds no objective function;
//! each running iteration it watches ownship against a convex polygon, a mission time,
//! a maximum depth and a minimum altitude, and on a breach posts its breach flag and a
//! `BHV_ERROR`, which halts the helm (`IVPHELM_ALLSTOP = BehaviorError`). The breach is
//! latched: the error repeats every iteration until `reset_var` is written `true`.
//!
//! What the golden case `opregion_breach` pins down (and this reproduces): the entry /
//! exit debouncing (`trigger_entry_time`, `trigger_exit_time`), the error text
//! `BHV_OpRegion Polygon containment failure:  x=%.1f y=%.1f`, and the perimeter postings
//! `SECS_IN_POLY`, `OPREG_TRAJECTORY_PERIM_DIST/ETA` (along the heading),
//! `OPREG_ABSOLUTE_PERIM_DIST/ETA` (to the nearest edge), `OPREG_TIME_REMAINING`, the
//! `time_remaining_var` (a whole number) and the `opregion_poly_var` (`pts={..}`, once).
//!
//! Chosen where nothing says (MOOS-IvP's documentation names the parameters only):
//! * `trigger_on_poly_entry` (default true): the polygon is enforced only once ownship
//!   has been inside it for `trigger_entry_time`; false enforces it from the start;
//! * the mission clock starts at the behavior's first running iteration;
//! * `OPREG_TIME_REMAINING` and the `time_remaining_var` are posted only with a
//!   `max_time` (> 0); the absolute-perimeter ETA assumes the helm domain's top speed
//!   and is not posted without a `speed` variable;
//! * the time, depth and altitude errors read `BHV_OpRegion Max Time failure: ...`,
//!   `BHV_OpRegion Max Depth failure: ...`, `BHV_OpRegion Min Altitude failure: ...`;
//! * without a `polygon` only time, depth and altitude are watched;
//! * the polygon is drawn once (`VIEW_POLYGON`, label `<ownship>_<name>`, styled by
//!   `visual_hints`).

use behavior_api::geometry::{parse_polygon, Attrs, Polygon};
use behavior_api::params::{no_white, non_negative, parse_bool};
use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::geom::{dist_post, int_post, ray_dist_to_poly};
use crate::watch::Watch;

/// What was breached, in the order they are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Breach {
    Poly,
    Time,
    Depth,
    Altitude,
}

pub struct OpRegion {
    domain: String,
    /// Top speed of the helm domain (for the absolute-perimeter ETA).
    top_speed: Option<f64>,
    polygon: Option<Polygon>,
    max_time: f64,
    max_depth: f64,
    min_altitude: f64,
    watch: Watch,
    poly_flags: Vec<String>,
    time_flags: Vec<String>,
    depth_flags: Vec<String>,
    altitude_flags: Vec<String>,
    reset_var: String,
    time_remaining_var: String,
    opregion_poly_var: String,
    hints: Attrs,
    start_time: Option<f64>,
    breach: Option<Breach>,
}

impl OpRegion {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        let names: Vec<&str> = helm_domain.vars().iter().map(|v| v.name.as_str()).collect();
        OpRegion {
            domain: helm_domain.sub_domain(&names),
            top_speed: helm_domain.var("speed").map(|v| v.high),
            polygon: None,
            max_time: 0.0,
            max_depth: 0.0,
            min_altitude: 0.0,
            watch: Watch::new(1.0, 1.0),
            poly_flags: Vec::new(),
            time_flags: Vec::new(),
            depth_flags: Vec::new(),
            altitude_flags: Vec::new(),
            reset_var: String::new(),
            time_remaining_var: String::new(),
            opregion_poly_var: String::new(),
            hints: Attrs {
                edge_color: "aqua".into(),
                vertex_color: "white".into(),
                ..Attrs::default()
            },
            start_time: None,
            breach: None,
        }
    }

    /// The breach latched so far, if any.
    pub fn breach(&self) -> Option<Breach> {
        self.breach
    }

    fn reset(&mut self, now: f64) {
        self.watch.reset();
        self.breach = None;
        self.start_time = Some(now);
    }

    fn draw(&self, ctx: &mut Ctx<'_>) {
        let Some(poly) = &self.polygon else { return };
        let mut p = poly.clone();
        p.attrs = Attrs {
            label: format!("{}_{}", ctx.ownship(), ctx.name()),
            ..self.hints.clone()
        };
        ctx.post_message("VIEW_POLYGON", &p.spec(1));
    }

    fn declare(&mut self, ctx: &mut Ctx<'_>, kind: Breach) {
        if self.breach.is_some() {
            return;
        }
        self.breach = Some(kind);
        let flags = match kind {
            Breach::Poly => &self.poly_flags,
            Breach::Time => &self.time_flags,
            Breach::Depth => &self.depth_flags,
            Breach::Altitude => &self.altitude_flags,
        };
        for f in flags.clone() {
            ctx.post_flag(&f, false);
        }
    }

    /// The perimeter postings and the polygon watch; true on a polygon breach.
    fn watch_polygon(
        &mut self,
        ctx: &mut Ctx<'_>,
        now: f64,
        pos: (f64, f64),
        hdg: f64,
        spd: f64,
    ) -> bool {
        let Some(poly) = &self.polygon else {
            return false;
        };
        let inside = poly.contains(pos.0, pos.1);
        let breached = self.watch.observe(now, inside);
        ctx.post_message_num("SECS_IN_POLY", self.watch.secs_inside(now));
        let traj = ray_dist_to_poly(poly, pos, hdg);
        ctx.post_message_num("OPREG_TRAJECTORY_PERIM_DIST", dist_post(traj));
        let traj_eta = if spd > 0.0 { int_post(traj / spd) } else { 0.0 };
        ctx.post_message_num("OPREG_TRAJECTORY_PERIM_ETA", traj_eta);
        let abs = poly.dist_to_poly(pos.0, pos.1);
        ctx.post_message_num("OPREG_ABSOLUTE_PERIM_DIST", dist_post(abs));
        if let Some(top) = self.top_speed.filter(|v| *v > 0.0) {
            ctx.post_message_num("OPREG_ABSOLUTE_PERIM_ETA", int_post(abs / top));
        }
        breached
    }
}

/// A flag in `.bhv` flag syntax needs a `VAR = value`.
fn flag(value: &str) -> Option<String> {
    let v = value.trim();
    let (var, _) = v.split_once('=')?;
    (!var.trim().is_empty()).then(|| v.to_string())
}

fn var_name(value: &str) -> Option<String> {
    let v = value.trim();
    no_white(v).filter(|v| !v.is_empty()).map(str::to_string)
}

/// `visual_hints = key=value, key=value` onto `attrs`; false on any unknown key.
pub(crate) fn set_hints(attrs: &mut Attrs, value: &str) -> bool {
    let mut next = attrs.clone();
    for field in value.split(',').filter(|f| !f.trim().is_empty()) {
        let Some((k, v)) = field.split_once('=') else {
            return false;
        };
        let key = k.trim().to_ascii_lowercase();
        let ok = matches!(
            key.as_str(),
            "edge_color"
                | "vertex_color"
                | "label_color"
                | "fill_color"
                | "edge_size"
                | "vertex_size"
                | "fill_transparency"
        ) && next.set(&key, v);
        if !ok {
            return false;
        }
    }
    *attrs = next;
    true
}

impl IvpBehavior for OpRegion {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_opregion".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let set = |slot: &mut f64| non_negative(value).map(|v| *slot = v).is_some();
        match param {
            "polygon" => match parse_polygon(value).filter(Polygon::is_convex) {
                Some(p) => {
                    self.polygon = Some(p);
                    true
                }
                None => false,
            },
            "max_time" => set(&mut self.max_time),
            "max_depth" => set(&mut self.max_depth),
            "min_altitude" => set(&mut self.min_altitude),
            "trigger_entry_time" => set(&mut self.watch.entry_time),
            "trigger_exit_time" => set(&mut self.watch.exit_time),
            "trigger_on_poly_entry" => parse_bool(value, !self.watch.armed_from_start)
                .map(|b| self.watch.armed_from_start = !b)
                .is_some(),
            "breached_poly_flag" => flag(value).map(|f| self.poly_flags.push(f)).is_some(),
            "breached_time_flag" => flag(value).map(|f| self.time_flags.push(f)).is_some(),
            "breached_depth_flag" => flag(value).map(|f| self.depth_flags.push(f)).is_some(),
            "breached_altitude_flag" => flag(value).map(|f| self.altitude_flags.push(f)).is_some(),
            "reset_var" => match var_name(value) {
                Some(v) => {
                    ctx.add_info_vars_no_warning(&v);
                    self.reset_var = v;
                    true
                }
                None => false,
            },
            "time_remaining_var" => var_name(value)
                .map(|v| self.time_remaining_var = v)
                .is_some(),
            "opregion_poly_var" => var_name(value)
                .map(|v| self.opregion_poly_var = v)
                .is_some(),
            "visual_hints" => set_hints(&mut self.hints, value),
            _ => false,
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED");
        if self.max_depth > 0.0 {
            ctx.add_info_vars("NAV_DEPTH");
        }
        if self.min_altitude > 0.0 {
            ctx.add_info_vars("NAV_ALTITUDE");
        }
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let now = ctx.get_buffer_curr_time();
        if !self.reset_var.is_empty()
            && ctx
                .get_buffer_string_vector(&self.reset_var)
                .iter()
                .any(|v| v.trim().eq_ignore_ascii_case("true"))
        {
            self.reset(now);
        }
        let start = match self.start_time {
            Some(s) => s,
            None => {
                self.start_time = Some(now);
                if let Some(p) = &self.polygon {
                    if !self.opregion_poly_var.is_empty() {
                        let pts = p.spec(2);
                        ctx.post_message(&self.opregion_poly_var, &pts);
                    }
                }
                self.draw(ctx);
                now
            }
        };
        let (Some(x), Some(y)) = (
            ctx.get_buffer_double_val("NAV_X"),
            ctx.get_buffer_double_val("NAV_Y"),
        ) else {
            ctx.post_emessage("No ownship X/Y info in info_buffer.");
            return None;
        };
        let hdg = ctx.get_buffer_double_val("NAV_HEADING").unwrap_or(0.0);
        let spd = ctx.get_buffer_double_val("NAV_SPEED").unwrap_or(0.0);

        if self.watch_polygon(ctx, now, (x, y), hdg, spd) {
            self.declare(ctx, Breach::Poly);
        }
        let elapsed = now - start;
        if self.max_time > 0.0 {
            let remaining = self.max_time - elapsed;
            ctx.post_message_num("OPREG_TIME_REMAINING", remaining);
            if !self.time_remaining_var.is_empty() {
                ctx.post_int_message(&self.time_remaining_var, remaining);
            }
            if remaining < 0.0 {
                self.declare(ctx, Breach::Time);
            }
        }
        let mut depth = 0.0;
        if self.max_depth > 0.0 {
            depth = ctx.get_buffer_double_val("NAV_DEPTH").unwrap_or(0.0);
            if depth > self.max_depth {
                self.declare(ctx, Breach::Depth);
            }
        }
        let mut altitude = 0.0;
        if self.min_altitude > 0.0 {
            if let Some(a) = ctx.get_buffer_double_val("NAV_ALTITUDE") {
                altitude = a;
                if a < self.min_altitude {
                    self.declare(ctx, Breach::Altitude);
                }
            }
        }
        match self.breach {
            None => {}
            Some(Breach::Poly) => ctx.post_emessage(&format!(
                "BHV_OpRegion Polygon containment failure:  x={x:.1} y={y:.1}"
            )),
            Some(Breach::Time) => ctx.post_emessage(&format!(
                "BHV_OpRegion Max Time failure: elapsed={elapsed:.1} max_time={}",
                self.max_time
            )),
            Some(Breach::Depth) => ctx.post_emessage(&format!(
                "BHV_OpRegion Max Depth failure: depth={depth:.1} max_depth={}",
                self.max_depth
            )),
            Some(Breach::Altitude) => ctx.post_emessage(&format!(
                "BHV_OpRegion Min Altitude failure: altitude={altitude:.1} min_altitude={}",
                self.min_altitude
            )),
        }
        None
    }
}
