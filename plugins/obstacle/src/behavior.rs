//! BHV_AvoidObstacleV24 (obstacles.md §1): the hooks, flags, postings and visuals around
//! the model of [`crate::model`].

use behavior_api::geometry::rel_ang;
use behavior_api::ivp::{Domain, Reflector};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{compact, push_compact, FunctionData, PostValue};

use crate::model::{
    all_aft, derive, range_relevance, update_side_lock, CourseTable, Derived, ObstacleAof, Pose,
    Side,
};
use crate::params::{Params, Set};
use crate::visuals;

/// Per-encounter closest-approach detector state (§1.5 step 5).
#[derive(Clone, Copy, Debug)]
struct CpaEvent {
    closing: bool,
    cpa_sofar: f64,
    fpa_sofar: f64,
}

/// One obstacle avoided by course; one instance per obstacle, spawned from a template.
pub struct AvoidObstacleV24 {
    pub params: Params,
    domain: Option<Domain>,
    domain_spec: String,
    /// The template's facts, given by the helm (`helm_templating`, `helm_updates`).
    templating: bool,
    updates_var: String,
    pose: Option<Pose>,
    derived: Option<Derived>,
    valid: bool,
    resolved_pending: bool,
    cpa_ever: f64,
    cpa_reported: f64,
    event: CpaEvent,
    side_lock: Option<Side>,
    disabled: bool,
    visuals: visuals::Kept,
    /// The course utilities' list, kept from build to build.
    course_list: Vec<f64>,
    /// The flags' macro expansion buffers, kept so that posting flags allocates nothing.
    macro_bufs: MacroBufs,
}

/// Kept buffers of [`AvoidObstacleV24::expand_into`]: the expanded text, the text it is
/// rebuilt into at each replacement (the two swap), and a formatted number.
#[derive(Default)]
struct MacroBufs {
    text: String,
    spare: String,
    num: String,
}

impl AvoidObstacleV24 {
    pub fn new(helm: &HelmDomain) -> Self {
        AvoidObstacleV24 {
            params: Params::default(),
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            templating: false,
            updates_var: String::new(),
            pose: None,
            derived: None,
            valid: false,
            resolved_pending: false,
            cpa_ever: -1.0,
            cpa_reported: -1.0,
            event: CpaEvent {
                closing: false,
                cpa_sofar: -1.0,
                fpa_sofar: -1.0,
            },
            side_lock: None,
            disabled: false,
            visuals: visuals::Kept::default(),
            course_list: Vec::new(),
            macro_bufs: MacroBufs::default(),
        }
    }

    /// The helm's platform model: ownship from the NAV values, once all four are known.
    fn read_pose(&mut self, ctx: &mut Ctx<'_>) {
        let x = ctx.get_buffer_double_val_quiet("NAV_X");
        let y = ctx.get_buffer_double_val_quiet("NAV_Y");
        let h = ctx.get_buffer_double_val_quiet("NAV_HEADING");
        let v = ctx.get_buffer_double_val_quiet("NAV_SPEED");
        if let (Some(x), Some(y), Some(h), Some(_)) = (x, y, h, v) {
            self.pose = Some(Pose {
                x,
                y,
                heading: behavior_api::geometry::angle360(h),
            });
        }
    }

    /// Recompute the derived values and the model's validity (§1.4.1, §1.5 step 2).
    fn refresh(&mut self) {
        let gut = &self.params.obstacle;
        let Some(os) = self.pose else {
            self.valid = false;
            return;
        };
        if !gut.is_convex() {
            self.valid = false;
            return;
        }
        let d = derive(
            gut,
            os,
            self.params.min_util_cpa,
            self.params.max_util_cpa,
            self.derived.take(),
        );
        self.valid = self.params.distances_ordered() && d.mid.is_convex() && d.rim.is_convex();
        self.derived = Some(d);
    }

    fn range(&self) -> f64 {
        self.derived.as_ref().map_or(-1.0, |d| d.range)
    }

    /// Relevance with the side lock update (§1.7).
    fn relevance(&mut self) -> f64 {
        let (Some(os), Some(d)) = (self.pose, self.derived.as_ref()) else {
            return 0.0;
        };
        let p = &self.params;
        let rr = range_relevance(&p.obstacle, os, d.range, p.pwt_inner, p.pwt_outer);
        self.side_lock = update_side_lock(self.side_lock, rr, d.passing_side);
        rr.max(0.0)
    }

    /// `Unable to init AOF_AvoidObstacleV24:<reason>` (§1.6 step 5), first failing check.
    fn init_failure(&self, os: Pose) -> Option<&'static str> {
        let p = &self.params;
        if !p.min_set {
            Some("min_util_cpa is not set")
        } else if !p.max_set {
            Some("max_util_cpa is not set")
        } else if !p.ttc_set {
            Some("allowable_ttc is not set")
        } else if !p.obstacle.is_convex() {
            Some("m_obstacle is not convex")
        } else if p.obstacle.contains(os.x, os.y) {
            Some("m_obstacle contains osx,osy")
        } else {
            None
        }
    }

    fn build(&mut self, ctx: &mut Ctx<'_>) -> Option<behavior_api::ivp::IvpFunction> {
        let os = self.pose?;
        let d = self.derived.as_ref()?;
        let Some(domain) = self.domain.as_ref() else {
            ctx.post_wmessage("Unable to init AOF_AvoidObstacleV24:crs_ix is not set");
            return None;
        };
        if let Some(reason) = self.init_failure(os) {
            ctx.post_wmessage(&format!("Unable to init AOF_AvoidObstacleV24:{reason}"));
            return None;
        }
        let aof = ObstacleAof {
            gut: &self.params.obstacle,
            os,
            min_cpa: self.params.min_util_cpa,
            max_cpa: self.params.max_util_cpa,
            locked: self.side_lock.is_some(),
            passing_side: d.passing_side,
            centre: d.centre,
            course_ix: domain.index_of("course")?,
        };
        let table = CourseTable::new(&aof, domain, std::mem::take(&mut self.course_list));
        let mut refl = Reflector::new(domain, &table);
        refl.set_param("uniform_piece", "discrete@course:3,speed:3");
        refl.set_param("uniform_grid", "discrete@course:9,speed:9");
        if self.params.use_refinery {
            let r =
                crate::refinery::regions(&self.params.obstacle, &d.rim, os, self.side_lock, domain);
            // The AOF's known range is [0, 100]: plateaus at the top, basins at the bottom.
            for b in r.plateaus {
                refl.add_region(b, 100.0);
            }
            for b in r.basins {
                refl.add_region(b, 0.0);
            }
        }
        refl.create(None, None);
        let warnings = refl.warnings().to_string();
        let f = refl.into_function(true);
        self.course_list = table.into_list();
        if f.is_none() && !warnings.is_empty() {
            ctx.post_wmessage(&warnings);
        }
        f
    }

    fn post_bad_config(&self, ctx: &mut Ctx<'_>, text: &str) {
        let msg = format!("{}: {text}", ctx.name());
        ctx.post_repeatable_message("BHV_BAD_CONFIG", PostValue::from(msg.as_str()));
    }

    fn post_settings(&self, ctx: &mut Ctx<'_>) {
        let s = self.params.settings(&ctx.name());
        ctx.post_repeatable_message("BHV_SETTINGS", PostValue::from(s.as_str()));
    }

    fn post_visuals(&mut self, ctx: &mut Ctx<'_>) {
        let Some(d) = self.derived.as_ref() else {
            return;
        };
        let fill = if self.side_lock.is_some() {
            "pink"
        } else {
            "gray60"
        };
        self.params.set_hint("gut_fill_color", fill);
        self.params.set_hint("mid_fill_color", "gray70");
        self.params.set_hint("rim_fill_color", "gray70");
        let sources = [&self.params.obstacle, &d.mid, &d.rim];
        let texts = self.visuals.texts(&self.params, sources);
        for (s, key) in texts.iter().zip(visuals::KEYS) {
            ctx.post_message_key("VIEW_POLYGON", PostValue::from(s.as_str()), key);
        }
    }

    fn erase_visuals(&self, ctx: &mut Ctx<'_>) {
        let label = &self.params.obstacle.attrs.label;
        for (suffix, key) in [("", "gut"), ("_mid_poly", "mid"), ("_rim_poly", "rim")] {
            let s = format!("pts={{0,0:9,0:0,9}},active=false,label={label}{suffix}");
            ctx.post_message_key("VIEW_POLYGON", PostValue::from(s.as_str()), key);
        }
    }

    /// The CPA event detector (§1.5 step 5): true once per pass of a closest point.
    fn cpa_event(&mut self, rng: f64) -> bool {
        let e = &mut self.event;
        if e.cpa_sofar < 0.0 || e.fpa_sofar < 0.0 {
            e.cpa_sofar = rng;
            e.fpa_sofar = rng;
        }
        if e.closing {
            e.cpa_sofar = e.cpa_sofar.min(rng);
            if rng > e.cpa_sofar + 1.0 {
                e.closing = false;
                e.fpa_sofar = rng;
                return true;
            }
        } else {
            e.fpa_sofar = e.fpa_sofar.max(rng);
            if rng < e.fpa_sofar - 1.0 {
                e.closing = true;
                e.cpa_sofar = rng;
            }
        }
        false
    }

    /// The able filter (§1.12): `true` when an `expunge` applied.
    fn able_filter(&mut self, ctx: &mut Ctx<'_>) -> bool {
        if !self.params.can_disable {
            return false;
        }
        let mut expunge = false;
        for s in ctx.get_buffer_string_vector("BHV_ABLE_FILTER") {
            match able_action(&s, &self.params.id, &self.params.obstacle.attrs.vsource) {
                Ok(Some(a)) => {
                    self.disabled = a == "disable";
                    expunge |= a == "expunge";
                }
                Ok(None) => {}
                Err(()) => ctx.post_wmessage(&format!("Unhandled BHV_ABLE_FILTER: {s}")),
            }
        }
        expunge
    }
}

/// Read one able-filter string: `Ok(Some(action))` when it applies to this obstacle,
/// `Ok(None)` when it is about another, `Err` when malformed.
fn able_action(s: &str, id: &str, vsource: &str) -> Result<Option<String>, ()> {
    let (mut action, mut obid, mut vsrc) = (None, None, None);
    for elem in s.split(',') {
        let (k, v) = elem.split_once('=').ok_or(())?;
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim().to_ascii_lowercase());
        let slot = match k.as_str() {
            "action" => &mut action,
            "obstacle_id" => &mut obid,
            "vsource" => &mut vsrc,
            _ => return Err(()),
        };
        if slot.is_some() {
            return Err(());
        }
        *slot = Some(v);
    }
    let action = action.ok_or(())?;
    if !matches!(action.as_str(), "disable" | "enable" | "expunge") {
        return Err(());
    }
    match (obid, vsrc) {
        (None, None) => Err(()),
        (Some(o), _) => Ok((o == id.to_ascii_lowercase()).then_some(action)),
        (None, Some(v)) => Ok((v == vsource.to_ascii_lowercase()).then_some(action)),
    }
}

impl IvpBehavior for AvoidObstacleV24 {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    /// The reference's constructor never manages to set its own name.
    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        match param.as_str() {
            "helm_templating" => {
                let v = value.trim();
                self.templating = !v.is_empty() && !v.eq_ignore_ascii_case("disallow");
                return true;
            }
            "helm_updates" => {
                self.updates_var = value.trim().to_string();
                return true;
            }
            _ => {}
        }
        match self.params.set(&param, value) {
            None | Some(Set::Refused) => false,
            Some(Set::Ok) => true,
            Some(Set::BadConfig(text)) => {
                self.post_bad_config(ctx, &text);
                false
            }
        }
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_X,NAV_Y,NAV_HEADING");
        ctx.add_info_vars_no_warning("OBM_RESOLVED");
        if self.params.can_disable {
            ctx.add_info_vars_no_warning("BHV_ABLE_FILTER");
        }
        self.read_pose(ctx);
        self.refresh();
        // The template itself posts no settings (run R1); its spawned instances do.
        if !self.templating {
            self.post_settings(ctx);
        }
    }

    fn on_helm_start(&mut self, ctx: &mut Ctx<'_>) {
        if self.templating && !self.updates_var.is_empty() {
            let req = format!(
                "name={},update_var={},alert_range={}",
                ctx.name(),
                self.updates_var,
                compact(self.params.pwt_outer, 1)
            );
            ctx.post_message("OBM_ALERT_REQUEST", &req);
        }
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        for v in ctx.get_buffer_string_vector("OBM_RESOLVED") {
            ctx.post_message("NOTED_RESOLVED", &v);
            if v == self.params.id {
                self.resolved_pending = true;
            }
        }
        self.read_pose(ctx);
        self.refresh();
        if !self.valid {
            ctx.post_wmessage("Invalid update of ownship/obship model");
        }
        if let Some(text) = self.derived.as_mut().and_then(|d| d.failed_expand.take()) {
            ctx.post_wmessage(&text);
        }
        if !self.valid {
            return;
        }
        let rng = self.range();
        if self.cpa_ever < 0.0 || rng < self.cpa_ever {
            self.cpa_ever = rng;
        }
        self.cpa_reported = self.cpa_ever;
        // Taken out while `expand_into` reads `self`; put back below.
        let mut bufs = std::mem::take(&mut self.macro_bufs);
        let MacroBufs { text, spare, num } = &mut bufs;
        for f in &self.params.rng_flags {
            if f.below <= 0.0 || rng < f.below {
                self.expand_into(&f.flag, text, spare, num);
                ctx.post_flag(text, false);
            }
        }
        if self.cpa_event(rng) && rng < self.params.pwt_outer {
            self.cpa_reported = self.event.cpa_sofar;
            for f in &self.params.cpa_flags {
                self.expand_into(f, text, spare, num);
                ctx.post_flag(text, false);
            }
            self.cpa_reported = self.cpa_ever;
        }
        self.macro_bufs = bufs;
        if rng > self.params.completed {
            self.resolved_pending = true;
        }
        // The helm's default platform model is holonomic; a plugin cannot see pmgen.
        if !self.params.holonomic_ok {
            ctx.post_wmessage("holo plat_model not best. Set holonomic_ok=true to silence");
        }
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
        if self.resolved_pending {
            ctx.set_complete();
        }
    }

    fn on_idle_to_run(&mut self, ctx: &mut Ctx<'_>) {
        self.post_settings(ctx);
    }

    fn on_inactive(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_visuals(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if self.able_filter(ctx) {
            ctx.set_complete();
            return None;
        }
        if self.resolved_pending {
            ctx.set_complete();
            return None;
        }
        if !self.valid || self.disabled {
            return None;
        }
        let os = self.pose?;
        if all_aft(&self.params.obstacle, os, 20.0) {
            return None;
        }
        let relevance = self.relevance();
        if relevance <= 0.0 {
            return None;
        }
        let Some(mut f) = self.build(ctx) else {
            if self.params.allstop_on_breach {
                ctx.post_emessage("Allstop: Obstacle Breached");
            } else {
                ctx.post_wmessage("Obstacle Breached");
            }
            return None;
        };
        if f.max_wt() == 0.0 {
            ctx.post_emessage("Allstop: obstacle unavoidable");
            return None;
        }
        f.set_pwt(relevance * ctx.priority());
        self.post_visuals(ctx);
        Some(function_data(f))
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        Some(self.expand(text))
    }
}

impl AvoidObstacleV24 {
    /// The type's macros (§1.13); `$[RBNG]` is never expanded, as in the reference.
    pub fn expand(&self, text: &str) -> String {
        let mut out = String::new();
        self.expand_into(text, &mut out, &mut String::new(), &mut String::new());
        out
    }

    /// [`Self::expand`] into `out`, with `spare` and `num` as scratch: nothing is
    /// allocated once the buffers have grown. The macros are replaced one after another
    /// in the reference's order, each in the text the previous one left (so a value
    /// holding a later macro, a label with `$[CPA]`, is expanded too).
    fn expand_into(&self, text: &str, out: &mut String, spare: &mut String, num: &mut String) {
        out.clear();
        out.push_str(text);
        if !text.contains("$[") {
            return;
        }
        let label = self.params.obstacle.attrs.label.as_str();
        let oidx = label.rsplit_once('_').map_or("", |(_, t)| t);
        let (bng, side) = match (self.pose, self.derived.as_ref()) {
            (Some(os), Some(d)) => (
                rel_ang(os.x, os.y, d.centre.0, d.centre.1),
                d.passing_side.as_str(),
            ),
            _ => (0.0, "n/a"),
        };
        let slock = self.side_lock.map_or("", Side::as_str);
        let p = &self.params;
        let steps = [
            ("$[RNG]", Value::Num(self.range())),
            ("$[BNG]", Value::Num(bng)),
            ("$[SIDE]", Value::Text(side)),
            ("$[OIDX]", Value::Text(oidx)),
            ("$[OID]", Value::Text(label)),
            ("$[CPA]", Value::Num(self.cpa_reported)),
            ("$[SLOCK]", Value::Text(slock)),
            ("$[MINU_CPA]", Value::Num(p.min_util_cpa)),
            ("$[MAXU_CPA]", Value::Num(p.max_util_cpa)),
        ];
        for (token, value) in steps {
            // A replacement without the token would copy the text unchanged.
            if !out.contains(token) {
                continue;
            }
            let value = match value {
                Value::Text(s) => s,
                Value::Num(v) => {
                    num.clear();
                    push_compact(num, v, 3);
                    num.as_str()
                }
            };
            replace_into(out, token, value, spare);
        }
    }
}

/// A macro's value: numbers are formatted only when their macro is present.
enum Value<'a> {
    Text(&'a str),
    Num(f64),
}

/// `*text = text.replace(token, value)`, built in `spare` (the two are swapped).
fn replace_into(text: &mut String, token: &str, value: &str, spare: &mut String) {
    spare.clear();
    let mut last = 0;
    for (at, _) in text.match_indices(token) {
        spare.push_str(&text[last..at]);
        spare.push_str(value);
        last = at + token.len();
    }
    spare.push_str(&text[last..]);
    std::mem::swap(text, spare);
}

#[cfg(test)]
mod tests;
