//! BHV_Waypoint (behaviors-std.md §2): traverse a list of waypoints, optionally along
//! the track lines with a lead point.

pub mod engine;
pub mod ipf;
mod macros;
pub mod params;
mod report;

use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{FunctionData, PostValue};
use geometry::{dist, fmt_x, perp_seg_int_pt, project_point, rel_ang, Vertex};

use crate::common::{platform_update, Platform};
use engine::{Advance, WaypointEngine};
use params::WptHints;

/// The BHV_Waypoint behavior.
pub struct BhvWaypoint {
    domain: String,
    /// The path spec and the points version it shows: formatted again only when the
    /// points change (parameters, which set its look and tags, clear it).
    seg_view: Option<(u64, String)>,
    /// Edge tags of the loaded path (a lawnmower's lanes), posted in VIEW_SEGLIST.
    path_tags: Vec<geometry::EdgeTag>,
    /// The next-point spec and the trackpt erase spec, by the point they show: both stay
    /// the same for as long as the vehicle heads to one waypoint (parameters clear them).
    nextpt_spec: Option<((u64, u64), String)>,
    trk_erase_spec: Option<String>,
    /// Ownship and this behavior's name, read once per configuration (they do not
    /// change while the behavior runs), and what is built from them every iteration:
    /// the trackpt's attribute fields, and a text buffer.
    own: String,
    me: String,
    trk_attrs: String,
    text: String,
    /// The status report, its text up to `dist=` kept with the counters it shows and
    /// its length (only the distance and the eta change every iteration).
    stat: String,
    stat_head: Option<((usize, u32, u32, u32), usize)>,
    ivp_domain: Option<ivp::Domain>,
    ipf: ipf::Builder,
    speed_high: Option<f64>,
    pub(crate) engine: WaypointEngine,
    cruise_speed: f64,
    speed_alt: f64,
    use_alt_speed: bool,
    greedy_tour: bool,
    draw_path_loop: bool,
    var_report: String,
    var_index: String,
    var_cyindex: String,
    var_dist_to_prev: String,
    var_dist_to_next: String,
    post_suffix: String,
    wptflags: Vec<String>,
    cycleflags: Vec<String>,
    wptflag_on_start: bool,
    wptflag_on_start_posted: bool,
    reset_on_idle: bool,
    eager_prev_index: bool,
    ipf_type: String,
    lead: f64,
    lead_damper: f64,
    lead_to_start: bool,
    lead_conditions: Vec<String>,
    capture_line_absolute: bool,
    efficiency_all: bool,
    crs_ratio: f64,
    hints: WptHints,
    end_spd: Option<(f64, f64)>,
    start_intent: bool,
    // run-time state
    plat: Platform,
    prev_pt: Option<(f64, f64)>,
    prev_waypt_index: i64,
    prev_cycle_index: u32,
    nextpt: Option<(f64, f64)>,
    trackpt: (f64, f64),
    mark: Option<(f64, f64)>,
    odo_prev: Option<(f64, f64)>,
    odo_leg: f64,
    odo_total: f64,
    eff: Efficiency,
}

/// Odometry-based efficiency bookkeeping (`efficiency_measure=all`).
#[derive(Clone, Debug, Default)]
struct Efficiency {
    baselined: bool,
    leg_start: (f64, f64),
    leg_time: f64,
    all_linear: f64,
    all_odo: f64,
    all_linear_time: f64,
    all_odo_time: f64,
}

impl BhvWaypoint {
    pub fn new(helm: &HelmDomain) -> Self {
        BhvWaypoint {
            seg_view: None,
            path_tags: Vec::new(),
            nextpt_spec: None,
            trk_erase_spec: None,
            own: String::new(),
            me: String::new(),
            trk_attrs: String::new(),
            text: String::new(),
            stat: String::new(),
            stat_head: None,
            domain: helm.sub_domain(&["course", "speed"]),
            ivp_domain: helm.ivp_domain(&["course", "speed"]),
            ipf: ipf::Builder::default(),
            speed_high: helm.var("speed").map(|v| v.high),
            engine: WaypointEngine::new(),
            cruise_speed: 0.0,
            speed_alt: -1.0,
            use_alt_speed: false,
            greedy_tour: false,
            draw_path_loop: false,
            var_report: "WPT_STAT".into(),
            var_index: "WPT_INDEX".into(),
            var_cyindex: "CYCLE_INDEX".into(),
            var_dist_to_prev: String::new(),
            var_dist_to_next: String::new(),
            post_suffix: String::new(),
            wptflags: Vec::new(),
            cycleflags: Vec::new(),
            wptflag_on_start: false,
            wptflag_on_start_posted: false,
            reset_on_idle: false,
            eager_prev_index: false,
            ipf_type: "zaic".into(),
            lead: -1.0,
            lead_damper: -1.0,
            lead_to_start: false,
            lead_conditions: Vec::new(),
            capture_line_absolute: false,
            efficiency_all: false,
            crs_ratio: 50.0,
            hints: WptHints::default(),
            end_spd: None,
            start_intent: false,
            plat: Platform::default(),
            prev_pt: None,
            prev_waypt_index: -1,
            prev_cycle_index: 0,
            nextpt: None,
            trackpt: (0.0, 0.0),
            mark: None,
            odo_prev: None,
            odo_leg: 0.0,
            odo_total: 0.0,
            eff: Efficiency::default(),
        }
    }

    /// `var` with the post suffix (borrowed as it is without one).
    fn sfx<'a>(&self, var: &'a str) -> std::borrow::Cow<'a, str> {
        if self.post_suffix.is_empty() {
            var.into()
        } else {
            format!("{var}{}", self.post_suffix).into()
        }
    }

    /// Read ownship and the behavior's name again, and forget what was built from them.
    fn refresh_names(&mut self, ctx: &Ctx<'_>) {
        self.own = ctx.ownship();
        self.me = ctx.name();
        self.seg_view = None;
        self.stat_head = None;
        self.trk_attrs.clear();
    }

    fn silent(v: &str) -> bool {
        v == "silent"
    }

    fn cruise(&self) -> f64 {
        if self.use_alt_speed && self.speed_alt >= 0.0 {
            self.speed_alt
        } else {
            self.cruise_speed
        }
    }

    fn post_flags(&self, ctx: &mut Ctx<'_>, flags: &[String], repeatable: bool) {
        for f in flags {
            let text = self.expand_type_macros(f);
            ctx.post_flag(&text, repeatable);
        }
    }

    fn lead_allowed(&self, ctx: &mut Ctx<'_>) -> bool {
        self.lead_conditions
            .iter()
            .all(|c| ctx.eval_condition(c).unwrap_or(false))
    }

    fn odometry(&mut self) {
        let (x, y) = (self.plat.x, self.plat.y);
        if let Some((px, py)) = self.odo_prev {
            let d = dist(px, py, x, y);
            self.odo_leg += d;
            self.odo_total += d;
        }
        self.odo_prev = Some((x, y));
    }

    /// Leg mark: efficiency reporting and a new leg for the odometry.
    fn leg_mark(&mut self, ctx: &mut Ctx<'_>) {
        let now = ctx.get_buffer_curr_time();
        let (x, y) = (self.plat.x, self.plat.y);
        if self.efficiency_all {
            if self.eff.baselined {
                let linear = dist(self.eff.leg_start.0, self.eff.leg_start.1, x, y);
                let odo = self.odo_leg;
                let odo_time = now - self.eff.leg_time;
                let cruise = self.cruise();
                let linear_time = if cruise > 0.0 { linear / cruise } else { 0.0 };
                self.eff.all_linear += linear;
                self.eff.all_odo += odo;
                self.eff.all_linear_time += linear_time;
                self.eff.all_odo_time += odo_time;
                let ratio = |a: f64, b: f64| if b > 0.0 { 100.0 * a / b } else { 0.0 };
                let summ = |ctx: &Ctx<'_>, l: f64, o: f64, lt: f64, ot: f64| {
                    format!(
                        "vname={},bhv_name={},linear_dist={},odo_dist={},efficiency_dist={},linear_time={},odo_time={},efficiency_time={}",
                        ctx.ownship(),
                        ctx.name(),
                        fmt_x(l, 2),
                        fmt_x(o, 2),
                        fmt_x(ratio(l, o), 2),
                        fmt_x(lt, 2),
                        fmt_x(ot, 2),
                        fmt_x(ratio(lt, ot), 2)
                    )
                };
                let leg = summ(ctx, linear, odo, linear_time, odo_time);
                let e = self.eff.clone();
                let all = summ(
                    ctx,
                    e.all_linear,
                    e.all_odo,
                    e.all_linear_time,
                    e.all_odo_time,
                );
                ctx.post_message(&self.sfx("WPT_EFF_SUMM_LEG"), &leg);
                ctx.post_message(&self.sfx("WPT_EFF_SUMM_ALL"), &all);
                ctx.post_message_num(
                    &self.sfx("WPT_EFF_DIST_ALL"),
                    ratio(e.all_linear, e.all_odo),
                );
                ctx.post_message_num(
                    &self.sfx("WPT_EFF_TIME_ALL"),
                    ratio(e.all_linear_time, e.all_odo_time),
                );
                ctx.post_message_num(&self.sfx("WPT_EFF_DIST_LEG"), ratio(linear, odo));
                ctx.post_message_num(&self.sfx("WPT_EFF_TIME_LEG"), ratio(linear_time, odo_time));
            }
            self.eff.baselined = true;
            self.eff.leg_start = (x, y);
            self.eff.leg_time = now;
        }
        self.odo_leg = 0.0;
    }

    /// Behavior-level advance (§2.3): true when there is a next point.
    fn set_next_waypoint(&mut self, ctx: &mut Ctx<'_>, lead_ok: bool) -> (bool, Advance) {
        if self.engine.size() == 0 {
            return (false, Advance::EmptySeglist);
        }
        self.engine.set_prev_point(self.prev_pt);
        let res = self.engine.advance(self.plat.x, self.plat.y);
        if res == Advance::EmptySeglist {
            return (false, res);
        }
        if res != Advance::InTransit {
            self.leg_mark(ctx);
        }
        ctx.post_message_num(&self.sfx("WPT_ODO"), self.odo_leg);
        if matches!(res, Advance::Completed | Advance::Cycled) {
            if !Self::silent(&self.var_report) {
                let word = if res == Advance::Completed {
                    "completed"
                } else {
                    "cycled"
                };
                let v = format!("behavior-name={},{word}", ctx.name());
                ctx.post_message(&self.sfx(&self.var_report), &v);
            }
            let flags = std::mem::take(&mut self.cycleflags);
            self.post_flags(ctx, &flags, true);
            self.cycleflags = flags;
        }
        if res == Advance::Completed {
            ctx.set_complete();
            self.mark = None;
            if ctx.perpetual() {
                self.engine.reset_for_new_traversal();
            }
            return (false, res);
        }
        let Some(next) = self.engine.current() else {
            return (false, res);
        };
        self.nextpt = Some((next.x, next.y));
        self.trackpt = (next.x, next.y);
        if lead_ok && self.lead >= 0.0 {
            let ix = self.engine.index();
            let anchor = if ix > 0 {
                self.engine.point(ix - 1).map(|p| (p.x, p.y))
            } else if self.engine.cycles() > 0 {
                self.engine
                    .point(self.engine.size() - 1)
                    .map(|p| (p.x, p.y))
            } else if self.lead_to_start {
                if self.mark.is_none() {
                    self.mark = Some((self.plat.x, self.plat.y));
                }
                self.mark
            } else {
                None
            };
            if let Some((ax, ay)) = anchor {
                let (os_x, os_y) = (self.plat.x, self.plat.y);
                let (px, py) = perp_seg_int_pt(ax, ay, next.x, next.y, os_x, os_y);
                let mut f = 1.0;
                let dp = dist(px, py, os_x, os_y);
                if self.lead_damper > 0.0 && dp < self.lead_damper {
                    f = 1.0 + 2.0 * (1.0 - dp / self.lead_damper);
                }
                let l = dist(px, py, next.x, next.y).min(self.lead * f);
                self.trackpt = project_point(rel_ang(ax, ay, next.x, next.y), l, px, py);
            }
        }
        (true, res)
    }

    /// Cruise speed after the `end_spd` ramp.
    fn ramped_cruise(&self) -> f64 {
        let mut cruise = self.cruise();
        if let Some((slow, stop)) = self.end_spd {
            let d = self.engine.dist_to_go_all(self.plat.x, self.plat.y);
            if d >= 0.0 {
                if d <= stop {
                    cruise = 0.0;
                } else if d < slow {
                    cruise *= if slow == stop {
                        0.0
                    } else {
                        (d - stop) / (slow - stop)
                    };
                }
            }
        }
        cruise
    }

    fn build_function(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let dom = self.ivp_domain.as_ref()?;
        let o = ipf::WptObjective {
            ipf_type: &self.ipf_type,
            cruise: self.ramped_cruise(),
            bearing: rel_ang(self.plat.x, self.plat.y, self.trackpt.0, self.trackpt.1),
            heading: self.plat.heading,
            crs_pct: self.crs_ratio,
        };
        match self.ipf.build(dom, &o) {
            Ok(mut f) => {
                f.set_pwt(ctx.priority());
                Some(function_data(f))
            }
            Err(msg) => {
                ctx.post_wmessage(msg);
                None
            }
        }
    }
}

impl IvpBehavior for BhvWaypoint {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_waypoint".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        // Hints and names may change what the cached point specs say.
        self.nextpt_spec = None;
        self.trk_erase_spec = None;
        self.seg_view = None;
        self.trk_attrs.clear();
        self.set_wpt_param(ctx, param, value)
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.refresh_names(ctx);
        ctx.add_info_vars("NAV_X, NAV_Y, NAV_SPEED, NAV_HEADING");
        let settings = self.settings(&ctx.name());
        ctx.post_repeatable_message("BHV_SETTINGS", PostValue::from(settings.as_str()));
        if self.engine.size() == 1 && (self.engine.repeats() > 0 || self.engine.repeats_endless()) {
            ctx.post_wmessage("cycles/repeats not supported with single waypt");
        }
        let msg = "No waypts given. Set val to empty if intentional";
        if self.engine.size() == 0 && !self.start_intent {
            ctx.post_wmessage(msg);
        } else {
            ctx.post_retract_wmessage(msg);
        }
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        if !self.start_intent || self.engine.size() != 0 {
            return;
        }
        if !ctx.get_buffer_is_known("NAV_X") || !ctx.get_buffer_is_known("NAV_Y") {
            return;
        }
        let x = ctx.get_buffer_double_val_quiet("NAV_X");
        let y = ctx.get_buffer_double_val_quiet("NAV_Y");
        if let (Some(x), Some(y)) = (x, y) {
            let parse = |v: f64| fmt_x(v, 3).parse::<f64>().unwrap_or(v);
            self.engine
                .set_points(vec![Vertex::new(parse(x), parse(y))]);
        }
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(p) = platform_update(ctx) {
            self.plat = p;
        }
    }

    fn on_idle_to_run(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(p) = platform_update(ctx) {
            self.plat = p;
        }
        self.odo_prev = Some((self.plat.x, self.plat.y));
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
        if self.reset_on_idle {
            self.engine.reset_for_new_traversal();
        }
        self.engine.reset_cpa();
        self.odo_prev = None;
        self.odo_leg = 0.0;
        self.eff.baselined = false;
        if !self.var_dist_to_prev.is_empty() {
            ctx.post_message_num(&self.var_dist_to_prev, -1.0);
        }
        if !self.var_dist_to_next.is_empty() {
            ctx.post_message_num(&self.var_dist_to_next, -1.0);
        }
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if self.engine.size() == 0 {
            return None;
        }
        self.engine.set_perpetual(ctx.perpetual());
        if self.own.is_empty() && self.me.is_empty() {
            self.refresh_names(ctx);
        }
        let Some(p) = platform_update(ctx) else {
            self.post_nextpt_inactive(ctx);
            return None;
        };
        self.plat = p;
        self.odometry();
        let lead_ok = self.lead_allowed(ctx);

        let this = self.engine.current();
        let this_ix = self.engine.index();
        if self.prev_pt.is_none() {
            self.prev_pt = Some((self.plat.x, self.plat.y));
        }
        let (have_next, res) = self.set_next_waypoint(ctx, lead_ok);
        let captured = matches!(
            res,
            Advance::Completed | Advance::Cycled | Advance::Advanced
        );
        let now = self.engine.current();
        let changed = match (this, now) {
            (Some(a), Some(b)) => a.x != b.x || a.y != b.y,
            _ => false,
        };
        let on_start = self.wptflag_on_start && !self.wptflag_on_start_posted;
        if changed || on_start || res == Advance::Completed || captured {
            if let Some(t) = this {
                self.prev_pt = Some((t.x, t.y));
            }
            if self.eager_prev_index {
                self.prev_waypt_index = this_ix as i64;
            }
            let flags = std::mem::take(&mut self.wptflags);
            self.post_flags(ctx, &flags, false);
            self.wptflags = flags;
            self.wptflag_on_start_posted = true;
        }
        if !Self::silent(&self.var_cyindex) && self.engine.cycles() != self.prev_cycle_index {
            ctx.post_message_num(
                &self.sfx(&self.var_cyindex),
                f64::from(self.engine.cycles()),
            );
            self.prev_cycle_index = self.engine.cycles();
        }
        if !have_next {
            self.post_nextpt_inactive(ctx);
            return None;
        }
        self.post_status_report(ctx);
        self.post_views(ctx);
        self.post_distances(ctx);
        self.build_function(ctx)
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        Some(self.expand_type_macros(text))
    }
}

#[cfg(test)]
mod tests;
