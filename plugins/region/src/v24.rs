//! BHV_OpRegionV24: nested regions around a convex `core_poly`. The *save* region
//! (`save_poly`, else the core grown by `save_dist`) is where the vehicle should stay:
//! outside it the behavior steers back toward the core's center at `recover_spd`
//! (a coupled course × speed function) and posts its `save_flag`s once per excursion,
//! its `save_clear_flag`s when back in. The *halt* region (`halt_poly`, else the save
//! region grown by `halt_dist`) is the hard limit: leaving it (debounced like
//! BHV_OpRegion), exceeding `max_time`, `max_depth` or going under `min_altitude`
//! posts the `halt_flag`s and a `BHV_ERROR` every iteration, which halts the helm.
//!
//! Nothing in our specs describes this type beyond its name, default name (`opregx`),
//! domain (`course,speed`) and its three polygon parameters (convex, posted at
//! precision 3). Everything else is chosen here, after the parameters the MOOS-IvP
//! missions and test harnesses set: `core_poly`, `save_poly`, `halt_poly`, `save_dist`
//! and `halt_dist` (>= 0, default 0 and 10), `recover_spd` (> 0, default 1),
//! `trigger_on_poly_entry` (default true: a vehicle that starts outside the halt region
//! is not in breach until it has been inside), `trigger_entry_time` /
//! `trigger_exit_time` (>= 0, default 1 / 1), `max_time`, `max_depth`, `min_altitude`
//! (>= 0, 0 = none), `save_flag` (on leaving the save region), `savex_flag` (alias
//! `save_clear_flag`: on being back inside it), `halt_flag` and `breached_poly_flag`,
//! `breached_time_flag`, `breached_depth_flag`, `breached_altitude_flag` (on the halt
//! of that kind; `halt_flag` on any), `draw_save_status` / `draw_halt_status`
//! (booleans, default true: draw those regions), `core_poly_var` (a
//! variable whose new polygon replaces the core at run time, the regions regrown),
//! `reset` (`true`, from an `updates` string: forget the entry state and the breach),
//! and `visual_hints`. The regions are drawn as `VIEW_POLYGON`s labelled
//! `<name>_core`, `<name>_save`, `<name>_halt` whenever they change.

use behavior_api::geometry::{parse_polygon, rel_ang, Attrs, Polygon};
use behavior_api::ivp::{self, couple, ZaicPeak};
use behavior_api::params::{no_white, non_negative, parse_bool, positive};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::opregion::set_hints;
use crate::watch::Watch;

pub struct OpRegionV24 {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    core: Option<Polygon>,
    save_given: Option<Polygon>,
    halt_given: Option<Polygon>,
    save: Option<Polygon>,
    halt: Option<Polygon>,
    save_dist: f64,
    halt_dist: f64,
    recover_spd: f64,
    max_time: f64,
    max_depth: f64,
    min_altitude: f64,
    watch: Watch,
    save_flags: Vec<String>,
    save_clear_flags: Vec<String>,
    halt_flags: Vec<String>,
    /// Flags of one kind of halt: polygon, time, depth, altitude.
    kind_flags: [Vec<String>; 4],
    draw_save: bool,
    draw_halt: bool,
    core_poly_var: String,
    hints: Attrs,
    start_time: Option<f64>,
    recovering: bool,
    halted: Option<String>,
    redraw: bool,
}

/// The convex polygon grown outward by `d` (each edge moved out by `d`, neighbouring
/// edges meeting at their new lines). `d <= 0` gives a copy.
pub fn grow(poly: &Polygon, d: f64) -> Polygon {
    let v = poly.vertices();
    let n = v.len();
    if d <= 0.0 || n < 3 {
        return poly.clone();
    }
    // Outward normal of edge i: with clockwise order the outside is on the left.
    let sign = if poly.is_clockwise() { 1.0 } else { -1.0 };
    let lines: Vec<((f64, f64), (f64, f64))> = (0..n)
        .map(|i| {
            let a = v[i];
            let b = v[(i + 1) % n];
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let len = dx.hypot(dy).max(f64::MIN_POSITIVE);
            let (nx, ny) = (-dy / len * sign, dx / len * sign);
            ((a.x + nx * d, a.y + ny * d), (dx, dy))
        })
        .collect();
    let mut pts = Vec::with_capacity(n);
    for i in 0..n {
        let (p, r) = lines[(i + n - 1) % n];
        let (q, s) = lines[i];
        let den = r.0 * s.1 - r.1 * s.0;
        if den.abs() < 1e-12 {
            pts.push(q);
            continue;
        }
        let t = ((q.0 - p.0) * s.1 - (q.1 - p.1) * s.0) / den;
        pts.push((p.0 + t * r.0, p.1 + t * r.1));
    }
    Polygon::from_xy(&pts)
}

fn convex(value: &str) -> Option<Polygon> {
    parse_polygon(value).filter(Polygon::is_convex)
}

fn flag(value: &str) -> Option<String> {
    let v = value.trim();
    let (var, _) = v.split_once('=')?;
    (!var.trim().is_empty()).then(|| v.to_string())
}

impl OpRegionV24 {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        OpRegionV24 {
            domain: helm_domain.sub_domain(&["course", "speed"]),
            ivp_domain: helm_domain.ivp_domain(&["course", "speed"]),
            core: None,
            save_given: None,
            halt_given: None,
            save: None,
            halt: None,
            save_dist: 0.0,
            halt_dist: 10.0,
            recover_spd: 1.0,
            max_time: 0.0,
            max_depth: 0.0,
            min_altitude: 0.0,
            watch: Watch::new(1.0, 1.0),
            save_flags: Vec::new(),
            save_clear_flags: Vec::new(),
            halt_flags: Vec::new(),
            kind_flags: Default::default(),
            draw_save: true,
            draw_halt: true,
            core_poly_var: String::new(),
            hints: Attrs {
                edge_color: "gray50".into(),
                vertex_color: "white".into(),
                ..Attrs::default()
            },
            start_time: None,
            recovering: false,
            halted: None,
            redraw: true,
        }
    }

    /// The save and halt regions as they are now (after generation).
    pub fn regions(&self) -> (Option<&Polygon>, Option<&Polygon>) {
        (self.save.as_ref(), self.halt.as_ref())
    }

    /// Rebuild the save and halt regions from the core and the given polygons.
    fn regrow(&mut self) {
        self.save = self
            .save_given
            .clone()
            .or_else(|| self.core.as_ref().map(|c| grow(c, self.save_dist)));
        self.halt = self
            .halt_given
            .clone()
            .or_else(|| self.save.as_ref().map(|s| grow(s, self.halt_dist)));
        self.redraw = true;
    }

    fn draw(&mut self, ctx: &mut Ctx<'_>) {
        if !self.redraw {
            return;
        }
        self.redraw = false;
        let name = ctx.name();
        for (poly, tag, on) in [
            (&self.core, "core", true),
            (&self.save, "save", self.draw_save),
            (&self.halt, "halt", self.draw_halt),
        ] {
            if let Some(p) = poly.as_ref().filter(|_| on) {
                let mut p = p.clone();
                p.attrs = Attrs {
                    label: format!("{name}_{tag}"),
                    ..self.hints.clone()
                };
                ctx.post_message_key(
                    "VIEW_POLYGON",
                    behavior_api::PostValue::from(p.spec(3).as_str()),
                    tag,
                );
            }
        }
    }

    /// Declare a halt of `kind` (0 polygon, 1 time, 2 depth, 3 altitude).
    fn halt(&mut self, ctx: &mut Ctx<'_>, kind: usize, why: String) {
        if self.halted.is_none() {
            let flags = self.halt_flags.iter().chain(self.kind_flags[kind].iter());
            for f in flags.cloned().collect::<Vec<_>>() {
                ctx.post_flag(&f, false);
            }
        }
        self.halted.get_or_insert(why);
    }

    /// Course to the core's center at the recovery speed.
    fn recover(&self, ctx: &mut Ctx<'_>, pos: (f64, f64)) -> Option<FunctionData> {
        let core = self.core.as_ref().or(self.save.as_ref())?;
        let (cx, cy) = core.center();
        let course = rel_ang(pos.0, pos.1, cx, cy);
        let dom = self.ivp_domain.as_ref()?;
        let mut zc = ZaicPeak::new(dom, "course").ok()?;
        zc.set_params(course, 0.0, 180.0, 0.0, 0.0, 100.0, 0);
        zc.set_value_wrap(true);
        let mut zs = ZaicPeak::new(dom, "speed").ok()?;
        zs.set_params(self.recover_spd, 0.0, 2.0, 0.0, 0.0, 100.0, 0);
        let mut f = couple(zc.extract(true)?, zs.extract(true)?, 50.0, 50.0, true)?;
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }
}

impl IvpBehavior for OpRegionV24 {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "opregx".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let set = |slot: &mut f64| non_negative(value).map(|v| *slot = v).is_some();
        let ok = match param {
            "core_poly" => convex(value).map(|p| self.core = Some(p)).is_some(),
            "save_poly" => convex(value).map(|p| self.save_given = Some(p)).is_some(),
            "halt_poly" => convex(value).map(|p| self.halt_given = Some(p)).is_some(),
            "save_dist" => set(&mut self.save_dist),
            "halt_dist" => set(&mut self.halt_dist),
            "recover_spd" => positive(value).map(|v| self.recover_spd = v).is_some(),
            "max_time" => set(&mut self.max_time),
            "max_depth" => set(&mut self.max_depth),
            "min_altitude" => set(&mut self.min_altitude),
            "trigger_entry_time" => set(&mut self.watch.entry_time),
            "trigger_exit_time" => set(&mut self.watch.exit_time),
            "trigger_on_poly_entry" => parse_bool(value, !self.watch.armed_from_start)
                .map(|b| self.watch.armed_from_start = !b)
                .is_some(),
            "save_flag" => flag(value).map(|f| self.save_flags.push(f)).is_some(),
            "savex_flag" | "save_clear_flag" => {
                flag(value).map(|f| self.save_clear_flags.push(f)).is_some()
            }
            "halt_flag" => flag(value).map(|f| self.halt_flags.push(f)).is_some(),
            "breached_poly_flag" => flag(value).map(|f| self.kind_flags[0].push(f)).is_some(),
            "breached_time_flag" => flag(value).map(|f| self.kind_flags[1].push(f)).is_some(),
            "breached_depth_flag" => flag(value).map(|f| self.kind_flags[2].push(f)).is_some(),
            "breached_altitude_flag" => flag(value).map(|f| self.kind_flags[3].push(f)).is_some(),
            "draw_save_status" => parse_bool(value, self.draw_save)
                .map(|b| self.draw_save = b)
                .is_some(),
            "draw_halt_status" => parse_bool(value, self.draw_halt)
                .map(|b| self.draw_halt = b)
                .is_some(),
            "core_poly_var" => match no_white(value.trim()).filter(|v| !v.is_empty()) {
                Some(v) => {
                    ctx.add_info_vars_no_warning(v);
                    self.core_poly_var = v.to_string();
                    true
                }
                None => false,
            },
            "reset" => match parse_bool(value, false) {
                Some(true) => {
                    self.watch.reset();
                    self.halted = None;
                    self.start_time = None;
                    true
                }
                Some(false) => true,
                None => false,
            },
            "visual_hints" => set_hints(&mut self.hints, value),
            _ => false,
        };
        if ok
            && matches!(
                param,
                "core_poly" | "save_poly" | "halt_poly" | "save_dist" | "halt_dist"
            )
        {
            self.regrow();
        }
        ok
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X, NAV_Y");
        if self.max_depth > 0.0 {
            ctx.add_info_vars("NAV_DEPTH");
        }
        if self.min_altitude > 0.0 {
            ctx.add_info_vars("NAV_ALTITUDE");
        }
    }

    fn collective_check(&mut self) -> String {
        if self.core.is_none() && self.save_given.is_none() && self.halt_given.is_none() {
            return "no core_poly, save_poly or halt_poly given".into();
        }
        String::new()
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let now = ctx.get_buffer_curr_time();
        let start = *self.start_time.get_or_insert(now);
        if !self.core_poly_var.is_empty() {
            let var = self.core_poly_var.clone();
            if let Some(p) = ctx
                .get_buffer_string_vector(&var)
                .iter()
                .rev()
                .find_map(|s| convex(s))
            {
                self.core = Some(p);
                self.regrow();
            }
        }
        self.draw(ctx);
        let (Some(x), Some(y)) = (
            ctx.get_buffer_double_val("NAV_X"),
            ctx.get_buffer_double_val("NAV_Y"),
        ) else {
            ctx.post_emessage("No ownship X/Y info in info_buffer.");
            return None;
        };
        if let Some(h) = &self.halt {
            let inside = h.contains(x, y);
            if self.watch.observe(now, inside) {
                self.halt(
                    ctx,
                    0,
                    format!("BHV_OpRegionV24 Halt region breach: x={x:.1} y={y:.1}"),
                );
            }
        }
        if self.max_time > 0.0 && now - start > self.max_time {
            self.halt(
                ctx,
                1,
                format!(
                    "BHV_OpRegionV24 Max Time failure: max_time={}",
                    self.max_time
                ),
            );
        }
        if self.max_depth > 0.0 {
            let d = ctx.get_buffer_double_val("NAV_DEPTH").unwrap_or(0.0);
            if d > self.max_depth {
                self.halt(
                    ctx,
                    2,
                    format!("BHV_OpRegionV24 Max Depth failure: depth={d:.1}"),
                );
            }
        }
        if self.min_altitude > 0.0 {
            if let Some(a) = ctx
                .get_buffer_double_val("NAV_ALTITUDE")
                .filter(|a| *a < self.min_altitude)
            {
                self.halt(
                    ctx,
                    3,
                    format!("BHV_OpRegionV24 Min Altitude failure: altitude={a:.1}"),
                );
            }
        }
        if let Some(why) = self.halted.clone() {
            ctx.post_emessage(&why);
            return None;
        }
        let outside_save = self.save.as_ref().is_some_and(|s| !s.contains(x, y));
        if outside_save != self.recovering {
            self.recovering = outside_save;
            let flags = if outside_save {
                &self.save_flags
            } else {
                &self.save_clear_flags
            };
            for f in flags.clone() {
                ctx.post_flag(&f, false);
            }
        }
        if !outside_save {
            return None;
        }
        let f = self.recover(ctx, (x, y));
        if f.is_none() {
            ctx.post_emessage("Unable to build the recovery IvP function");
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grow_moves_every_edge_out() {
        let sq = Polygon::from_xy(&[(0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0)]);
        for p in [sq.clone(), {
            let mut r = sq.clone();
            r.reverse();
            r
        }] {
            let g = grow(&p, 5.0);
            assert!(g.is_convex());
            assert!(g.contains(-4.9, -4.9) && g.contains(14.9, 14.9));
            assert!(!g.contains(-5.1, 5.0) && !g.contains(5.0, 15.1));
        }
        assert_eq!(grow(&sq, 0.0), sq);
    }
}
