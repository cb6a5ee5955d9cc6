//! BHV_AvdColregsV22, V19 and V17 (behaviors-contacts.md §5): the per-iteration flow,
//! completion and postings around the mode machine ([`crate::modes`]) and the
//! functions of each mode ([`crate::build`]).

use std::collections::VecDeque;

use behavior_api::contact::{ContactBase, POST_MORTEM_MACRO};
use behavior_api::flag::{expand_macros, has_macro};
use behavior_api::ivp::Domain;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{compact, push_compact, FunctionData, PostValue};

use crate::build::{build_function, grid_box, Built};
use crate::modes::{mode_index, Debug, Inputs, Machine, Mode, Submode};
use crate::params::{Params, Version};

/// The contact's headings and bearings are kept this long (s) for its turn rate.
const HISTORY_SECS: f64 = 5.0;

pub struct Colregs {
    pub(crate) base: ContactBase,
    pub(crate) p: Params,
    domain: Option<Domain>,
    domain_spec: String,
    /// The native `uniform_grid` as box sizes (`discrete@course:9,speed:40`).
    grid: String,
    pub(crate) machine: Machine,
    iterations: u64,
    crossed: bool,
    /// (contact heading, time) and (ownship→contact relative bearing, time).
    hdg_hist: VecDeque<(f64, f64)>,
    bng_hist: VecDeque<(f64, f64)>,
    hdg0: f64,
    spd0: f64,
    /// The last non-zero-relevance weight actually given (`$[APWT]`).
    actual_pwt: f64,
    mode_ix: u32,
    /// Why the behavior completed (the post-mortem's prefix, V22 only).
    reason: &'static str,
    dbg: Vec<Debug>,
    /// The names and texts posted every iteration.
    texts: Texts,
}

/// The variable names and texts this behavior posts every iteration, kept so that an
/// iteration builds no string: the per-contact names are made again only when the
/// contact changes, the ownship's once; each text is written into `text`.
#[derive(Default)]
struct Texts {
    /// The contact the names below were made for (`None` before the first).
    contact: Option<String>,
    fore: String,
    port: String,
    crossed: String,
    range: String,
    hdg: String,
    avoid_mode: String,
    summary: String,
    avoid_ix: String,
    avoid_pwt: String,
    relevance: String,
    col22_mode: String,
    bow_dist: String,
    bow_turn_gap: String,
    /// `HEADON_DEBUG_<OWNSHIP>` and the status seglist's label `<ownship><name>`,
    /// read once (`None` before).
    own: Option<(String, String)>,
    /// The text being posted.
    text: String,
}

impl Colregs {
    pub fn new(helm: &HelmDomain, version: Version) -> Self {
        let domain = helm.ivp_domain(&["course", "speed"]);
        let grid = domain.as_ref().map(grid_box).unwrap_or_default();
        Colregs {
            base: ContactBase::new(120.0),
            p: Params::new(version),
            domain,
            domain_spec: helm.sub_domain(&["course", "speed"]),
            grid,
            machine: Machine::default(),
            iterations: 0,
            crossed: false,
            hdg_hist: VecDeque::with_capacity(16),
            bng_hist: VecDeque::with_capacity(16),
            hdg0: 0.0,
            spd0: 0.0,
            actual_pwt: 0.0,
            mode_ix: 0,
            reason: "",
            dbg: Vec::with_capacity(4),
            texts: Texts::default(),
        }
    }

    pub fn v22(helm: &HelmDomain) -> Self {
        Colregs::new(helm, Version::V22)
    }
    pub fn v19(helm: &HelmDomain) -> Self {
        Colregs::new(helm, Version::V19)
    }
    pub fn v17(helm: &HelmDomain) -> Self {
        Colregs::new(helm, Version::V17)
    }

    fn v22_only(&self) -> bool {
        self.p.version == Version::V22
    }

    fn complete(&mut self, ctx: &mut Ctx<'_>, reason: &'static str) {
        self.reason = reason;
        self.base.complete(ctx);
    }

    /// The completion range test: 1.1 × completed_dist (V17: completed_dist).
    fn out_of_range(&self) -> bool {
        let f = if self.p.version == Version::V17 {
            1.0
        } else {
            1.1
        };
        self.base.range() >= f * self.p.completed_dist
    }

    /// Filter and range completion of the idle/disabled/running states (`x` is the
    /// state's letter of the reason). Returns whether it completed.
    fn completion(&mut self, ctx: &mut Ctx<'_>, filt: &'static str, rng: &'static str) -> bool {
        let mut done = false;
        if self.base.exit_filter_fails() {
            self.complete(ctx, filt);
            done = true;
        }
        if self.out_of_range() {
            self.complete(ctx, rng);
            done = true;
        }
        done
    }

    /// The mode as `mode` or `mode:submode` appended to `out`.
    fn push_mode_text(m: Machine, out: &mut String) {
        out.push_str(m.mode.as_str());
        if m.submode != Submode::None {
            out.push(':');
            out.push_str(m.submode.as_str());
        }
    }

    /// Makes the per-contact names when the contact is not the one they were made for.
    fn ready_names(&mut self) {
        if self.texts.contact.as_deref() == Some(self.base.contact.as_str()) {
            return;
        }
        let relevance = self.relevance_var();
        let up = self.base.contact.to_ascii_uppercase();
        let sep = if self.p.version == Version::V17 {
            "__"
        } else {
            "_"
        };
        let t = &mut self.texts;
        t.fore = format!("CN_FORE_OF_OS{sep}{up}");
        t.port = format!("CN_PORT_OF_OS__{up}");
        t.crossed = format!("CN_CROSSED_OS_PORT_STAR{sep}{up}");
        t.range = format!("AVDCOL_RANGE_{up}");
        t.hdg = format!("COLREGS_CONTACT_HDG_{up}");
        t.avoid_mode = format!("COLREGS_AVOID_MODE_{up}");
        t.summary = format!("COLREGS_SUMMARY_{up}");
        t.avoid_ix = format!("COLREGS_AVOID_IX_{up}");
        t.avoid_pwt = format!("COLREGS_AVOID_PWT_{up}");
        t.relevance = relevance;
        t.col22_mode = format!("COL22_AVOID_MODE_{up}");
        t.bow_dist = format!("XCN_BOW_DIST_{up}");
        t.bow_turn_gap = format!("XCN_BOW_TURN_GAP_{up}");
        t.contact = Some(self.base.contact.clone());
        // Room for the longest text (the status seglist) at once.
        t.text.reserve(160);
    }

    /// Reads the ownship's name and the behavior's (neither changes) the first time.
    fn ready_own(&mut self, ctx: &Ctx<'_>) {
        self.texts.own.get_or_insert_with(|| {
            let own = ctx.ownship();
            let headon = format!("HEADON_DEBUG_{}", own.to_ascii_uppercase());
            (headon, own + &ctx.name())
        });
    }

    /// The status info (§5.7), and for V19/V17 the status seglist.
    fn post_status(&mut self, ctx: &mut Ctx<'_>) {
        if self.p.version != Version::V22 {
            self.post_status_seglist(ctx);
        }
        if !self.base.post_per_contact_info {
            return;
        }
        self.ready_names();
        let Some(r) = self.base.relation() else {
            return;
        };
        let t = &mut self.texts;
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        ctx.post_message_num(&t.fore, b(r.cn_fore_of_os));
        ctx.post_message_num(&t.port, b(r.cn_port_of_os));
        ctx.post_message_num(&t.crossed, b(self.crossed));
        ctx.post_message_num(&t.range, r.range);
        ctx.post_message_num(&t.hdg, self.base.cn.hdg);
        t.text.clear();
        Self::push_mode_text(self.machine, &mut t.text);
        ctx.post_message(&t.avoid_mode, &t.text);
        t.text.clear();
        t.text.push_str("mode=");
        t.text.push_str(self.machine.mode.as_str());
        t.text.push(':');
        t.text.push_str(self.machine.submode.as_str());
        ctx.post_message(&t.summary, &t.text);
        ctx.post_repeatable_message(&t.avoid_ix, PostValue::Num(f64::from(self.mode_ix)));
        ctx.post_repeatable_message(&t.avoid_pwt, PostValue::Num(self.actual_pwt));
    }

    /// V19/V17: a seglist ownship → contact with the mode as its message.
    fn post_status_seglist(&mut self, ctx: &mut Ctx<'_>) {
        let (os, cn) = (self.base.os, self.base.cn);
        let active = !matches!(self.machine.mode, Mode::None | Mode::Complete);
        self.ready_own(ctx);
        let t = &mut self.texts;
        let label = t.own.as_ref().map_or("", |o| o.1.as_str());
        let s = &mut t.text;
        s.clear();
        s.push_str("pts={");
        for (i, v) in [os.x, os.y, cn.x, cn.y].into_iter().enumerate() {
            if i > 0 {
                s.push(if i == 2 { ':' } else { ',' });
            }
            push_compact(s, v, 2);
        }
        s.push_str("},label=");
        s.push_str(label);
        s.push_str(",msg=");
        Self::push_mode_text(self.machine, s);
        if !active {
            s.push_str(",active=false");
        }
        ctx.post_message("VIEW_SEGLIST", s);
    }

    fn post_debug(&mut self, ctx: &mut Ctx<'_>) {
        let always = !self.v22_only();
        if !(always || self.base.post_per_contact_info) {
            self.dbg.clear();
            return;
        }
        if self.dbg.is_empty() {
            return;
        }
        self.ready_names();
        self.ready_own(ctx);
        let t = &mut self.texts;
        for d in self.dbg.drain(..) {
            match d {
                Debug::HeadOn(why) => {
                    let var = t.own.as_ref().map_or("", |o| o.0.as_str());
                    t.text.clear();
                    t.text.push_str("contact=");
                    t.text.push_str(&self.base.contact);
                    t.text.push(',');
                    t.text.push_str(why);
                    ctx.post_message(var, &t.text);
                }
                Debug::BowDist(x) => ctx.post_message_num(&t.bow_dist, x),
                Debug::BowTurnGap(g) => ctx.post_message_num(&t.bow_turn_gap, g),
            }
        }
    }

    /// The contact's turn rate (deg/s) from the heading history: valid with two or
    /// more entries spanning at least 4 s.
    fn turn_rate(&self) -> Option<f64> {
        let (first, last) = (self.hdg_hist.front()?, self.hdg_hist.back()?);
        let span = last.1 - first.1;
        if self.hdg_hist.len() < 2 || span < 4.0 {
            return None;
        }
        let mut sum = 0.0;
        for (a, b) in self.hdg_hist.iter().zip(self.hdg_hist.iter().skip(1)) {
            let mut d = b.0 - a.0;
            while d > 180.0 {
                d -= 360.0;
            }
            while d <= -180.0 {
                d += 360.0;
            }
            sum += d;
        }
        Some(sum / span)
    }

    fn push_history(&mut self, now: f64) {
        let (cnh, bng) = (
            self.base.cn.hdg,
            self.base.relation().map_or(0.0, |r| r.os_cn_rel_bng),
        );
        for (q, v) in [(&mut self.hdg_hist, cnh), (&mut self.bng_hist, bng)] {
            q.push_back((v, now));
            while q.front().is_some_and(|f| now - f.1 >= HISTORY_SECS) {
                q.pop_front();
            }
        }
    }

    fn update_mode(&mut self, ctx: &mut Ctx<'_>) {
        let before = self.machine.mode;
        if let Some(m) = self.p.forced_mode {
            self.machine.mode = m;
            self.machine.submode = self.p.forced_submode.unwrap_or(Submode::None);
        } else if let Some(r) = self.base.relation() {
            let (os, cn) = (self.base.os, self.base.cn);
            let inputs = Inputs {
                rel: r,
                os: (os.x, os.y, os.heading, os.speed),
                cn: (cn.x, cn.y, cn.hdg),
                outer: self.p.pwt_outer_dist,
                min_util: self.p.min_util_cpa_dist,
                max_util: self.p.max_util_cpa_dist,
                giveway_bow_dist: self.p.giveway_bow_dist,
                turn_radius: self.p.turn_radius,
                crossed: self.crossed,
                turn_rate: self.turn_rate(),
            };
            let mut m = self.machine;
            m.update(&inputs, &mut self.dbg);
            self.machine = m;
        }
        self.post_debug(ctx);
        if Machine::entered_standon(before, self.machine.mode) {
            self.hdg0 = self.base.os.heading;
            self.spd0 = self.base.os.speed;
        }
        if self.p.headon_only
            && matches!(
                self.machine.mode,
                Mode::Overtaking | Mode::GiveWay | Mode::StandOn | Mode::StandOnOt
            )
        {
            self.machine.mode = Mode::Cpa;
            self.machine.submode = Submode::None;
        }
        self.mode_ix = mode_index(self.machine.mode, self.machine.submode);
        if !self.v22_only() {
            let v = if self.p.version == Version::V19 {
                "V19"
            } else {
                "V17"
            };
            let info = &mut self.texts.text;
            info.clear();
            info.push_str(v);
            info.push_str(" CN:");
            info.push_str(&self.base.contact);
            info.push_str("  Mode:");
            info.push_str(self.machine.mode.as_str());
            info.push(':');
            info.push_str(self.machine.submode.as_str());
            ctx.post_message("AVD_INFO", info);
        }
    }

    fn relevance_var(&self) -> String {
        match self.p.version {
            Version::V22 => format!("COL22_RELEVANCE_{}", self.base.contact.to_ascii_uppercase()),
            Version::V19 => "COL19_RELEVANCE".into(),
            Version::V17 => "COL17_RELEVANCE".into(),
        }
    }

    /// The type macros of V22 (`$[AVD_MODE]`, ...).
    fn own_macros(&self, text: &str) -> String {
        if !self.v22_only() {
            return text.to_string();
        }
        let m = self.machine;
        let subs = [
            ("AVD_MODE", m.mode.as_str().to_string()),
            ("AVD_SMODE", m.submode.as_str().to_string()),
            ("APWT", compact(self.actual_pwt, 3)),
            ("MODE_ID", self.mode_ix.to_string()),
            (
                "FULL_MODE",
                format!("{}:{}", m.mode.as_str(), m.submode.as_str()),
            ),
        ];
        expand_macros(text, &subs)
    }
}

impl IvpBehavior for Colregs {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "colregs".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        let mut tol = self.base.time_on_leg;
        if let Some(ok) = self.p.set(&param, value, &mut tol) {
            self.base.time_on_leg = tol;
            return ok;
        }
        let v = value.trim();
        match param.as_str() {
            "no_alert_request" => return bool_into(&mut self.base.no_alert_request, v),
            "can_disable" if self.p.version != Version::V17 => {
                return bool_into(&mut self.base.can_disable, v)
            }
            "can_disable" => return false,
            _ => {}
        }
        self.base
            .set_param_with(ctx, &param, value)
            .unwrap_or(false)
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        // V19 and V22 register the able filter whatever `can_disable` says; V17 not.
        if self.p.version != Version::V17 {
            ctx.add_info_vars_no_warning("BHV_ABLE_FILTER");
        }
    }

    fn on_helm_start(&mut self, ctx: &mut Ctx<'_>) {
        let name = ctx.name();
        let (outer, done) = (self.p.pwt_outer_dist, self.p.completed_dist);
        if let Some(req) = self.base.alert_request(&name, outer, done) {
            ctx.post_message("BCM_ALERT_REQUEST", &req);
        }
    }

    fn on_spawn(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.spawned();
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        self.base.every_state(ctx);
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        if !self.base.update_ok {
            return;
        }
        if !self.v22_only() || self.p.post_status_info_on_idle {
            self.post_status(ctx);
        }
        self.completion(ctx, "filtera", "rng1p1a");
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        if self.v22_only() {
            self.base.post_inactive_bearing_line(ctx);
        }
    }

    fn on_inactive(&mut self, ctx: &mut Ctx<'_>) {
        self.base.post_inactive_bearing_line(ctx);
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.base.on_complete();
        self.machine.mode = Mode::Complete;
        self.post_status(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        let able = self.base.able_filter(ctx, self.p.version.type_name());
        if able.expunge {
            self.base.complete(ctx);
            return None;
        }
        self.base.handle_cnflags(ctx);
        if self.base.disabled {
            self.base.post_inactive_bearing_line(ctx);
            self.completion(ctx, "filterb", "rng1p1b");
            return None;
        }
        self.iterations += 1;
        let prev = self.base.relation().is_some_and(|r| r.cn_port_of_os);
        // The reference refreshes a second time at the start of its run hook.
        if !self.base.update(ctx) {
            return None;
        }
        let now = ctx.get_buffer_curr_time();
        let port = self.base.relation().is_some_and(|r| r.cn_port_of_os);
        self.crossed = self.iterations > 1 && port != prev;
        if self.completion(ctx, "filterc", "rng1p1c") {
            return None;
        }
        self.push_history(now);
        self.update_mode(ctx);

        let range = self.base.range();
        let relevance = self.p.relevance(range);
        if !self.v22_only() || self.base.post_per_contact_info {
            self.ready_names();
            ctx.post_message_num(&self.texts.relevance, relevance);
        }

        let mut f = None;
        if relevance > 0.0 {
            let factor = match self.p.velocity_filter {
                Some(vf) if self.v22_only() => vf.factor(self.base.os.speed, self.base.cn.spd),
                _ => 1.0,
            };
            let built = self.domain.as_ref().map(|d| {
                build_function(
                    d,
                    &self.grid,
                    &self.base,
                    &self.p,
                    self.machine,
                    (self.hdg0, self.spd0),
                    factor,
                )
            });
            match built {
                Some(Built::Function(g)) => f = Some(g),
                Some(Built::Error(e)) => ctx.post_emessage(&e),
                Some(Built::Warning(w)) => ctx.post_wmessage(w),
                Some(Built::Nothing) | None => {}
            }
        }
        if self.v22_only() && self.base.post_per_contact_info {
            self.ready_names();
            ctx.post_message(&self.texts.col22_mode, self.machine.mode.as_str());
        }
        if let Some(g) = f.as_mut() {
            self.actual_pwt = relevance * ctx.priority();
            g.set_pwt(self.actual_pwt);
        }
        self.post_status(ctx);
        let g = f?;
        if self.v22_only() {
            // The base's relevance field this behavior never sets: always 0.
            self.base.post_bearing_line(ctx, 0.0);
        }
        Some(function_data(g))
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        if !has_macro(text) {
            return None;
        }
        if text == POST_MORTEM_MACRO {
            let pm = self.base.post_mortem();
            return Some(if self.v22_only() && !self.reason.is_empty() {
                format!("{}#{pm}", self.reason)
            } else {
                pm
            });
        }
        let own = self.own_macros(text);
        match self.base.expand_macros(&own) {
            Some(s) => Some(s),
            None => (own != text).then_some(own),
        }
    }
}

fn bool_into(field: &mut bool, v: &str) -> bool {
    match behavior_api::params::parse_bool(v, *field) {
        Some(b) => {
            *field = b;
            true
        }
        None => false,
    }
}

#[cfg(test)]
#[path = "colregs_tests.rs"]
mod tests;
