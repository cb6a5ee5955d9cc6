//! The contact-behavior base (the reference's IvPContactBehavior, contacts-appcast.md §3
//! and behaviors-contacts.md §1): what every behavior about one other vessel shares.
//!
//! A contact behavior holds one [`ContactBase`] and forwards to it:
//! * `set_param`: [`ContactBase::set_param`] first (`contact`, `on_no_contact_ok`,
//!   `extrapolate`, `decay`, `time_on_leg`, the match/ignore filters, `exit_on_filter_*`,
//!   `cnflag`, `bearing_line_*`, `post_per_contact_info`, ...); `None` means "not mine";
//! * `on_every_state`: [`ContactBase::every_state`] (the spawned-contact-gone rule, then
//!   the refresh: ownship, the contact from the ledger snapshot, range, bearings, CPA);
//! * `on_run`: [`ContactBase::handle_cnflags`] and [`ContactBase::able_filter`] first;
//! * `on_spawn`: [`ContactBase::spawned`];
//! * `expand_macros`: [`ContactBase::expand_macros`] (`$[CONTACT]`, `$[CN_*]`, `$[RANGE]`,
//!   ... and the life-event post-mortem, [`POST_MORTEM_MACRO`]);
//! * `on_helm_start`: [`ContactBase::alert_request`] builds `BCM_ALERT_REQUEST`.
//!
//! The helm tells a behavior built from a `templating` block its template facts before
//! its helm-start hook, as two type parameters: `helm_templating = spawn|clone` and
//! `helm_updates = <VAR>` (the base takes both).
//!
//! ```
//! use behavior_api::contact::ContactBase;
//! use behavior_api::testing::MockHelm;
//! let mut base = ContactBase::new(60.0);
//! assert_eq!(base.set_param("contact", "bob"), Some(true));
//! assert_eq!(base.set_param("speed", "2"), None); // not a base parameter
//! let mut helm = MockHelm::new("avd_bob");
//! helm.nav(0.0, 0.0, 0.0, 2.0);
//! helm.contact("bob", 0.0, 100.0, 180.0, 3.0, "kayak");
//! assert!(helm.with(|ctx| base.every_state(ctx)));
//! assert_eq!(base.range(), 100.0);
//! // Head-on: they meet in 100 / (2 + 3) = 20 s, well inside the 120 s look-ahead.
//! assert!(base.relation().unwrap().os_curr_cpa_dist < 1e-9);
//! assert_eq!(base.expand_macros("$[CONTACT] at $[RANGE]").as_deref(), Some("bob at 100"));
//! ```

mod able;
mod lazy;
mod macros;

use contacts::{CnFlag, CnTag, ContactFilter, ContactRelation, Decay, Pose};
use lazy::LazyRelation;

use crate::geometry::angle360;
use crate::params::parse_bool;
use crate::platform::{platform_update, Platform};
use crate::sdk::Ctx;
use crate::{parse_number, push_compact, PostValue};

pub use able::AbleOutcome;
pub use macros::POST_MORTEM_MACRO;

/// What a contact behavior's bearing line is coloured by (`info:relevance|range`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BearingInfo {
    Relevance,
    Range,
}

/// The shared state and parameters of a contact behavior.
#[derive(Clone, Debug)]
pub struct ContactBase {
    pub contact: String,
    pub on_no_contact_ok: bool,
    /// Accepted, inert in the reference's version (behaviors-contacts.md §1.1).
    pub extrapolate: bool,
    pub decay: Decay,
    pub time_on_leg: f64,
    pub post_per_contact_info: bool,
    pub filter: ContactFilter,
    pub exit_on_filter_vtype: bool,
    pub exit_on_filter_group: bool,
    pub exit_on_filter_region: bool,
    pub cnflags: Vec<CnFlag>,
    /// `(color, threshold)` pairs, in the order given.
    pub bearing_lines: Vec<(String, f64)>,
    pub bearing_info: BearingInfo,
    pub bearing_line_show: bool,
    pub bearing_line_label_show: bool,
    pub no_alert_request: bool,
    /// Obey `BHV_ABLE_FILTER` (`can_disable`; only types that offer it set it).
    pub can_disable: bool,
    /// Set by the helm for a template's instance (`helm_templating`).
    pub templating: bool,
    /// The template's `updates` variable (`helm_updates`).
    pub updates_var: String,
    /// This instance was spawned from a template.
    pub is_spawned: bool,
    /// Disabled by a `BHV_ABLE_FILTER` (`action=disable`).
    pub disabled: bool,

    // The picture of the last refresh.
    pub os: Platform,
    pub cn: Pose,
    pub cn_type: String,
    pub cn_group: String,
    pub cn_vsource: String,
    pub cn_utc: f64,
    /// The relations of the last and the previous refresh (computed when asked).
    rel: Option<LazyRelation>,
    prev: Option<LazyRelation>,
    /// The refresh of this iteration succeeded.
    pub update_ok: bool,
    warned: bool,
    /// The picture before this iteration's refresh, and whether the behavior itself
    /// asked to complete (see [`ContactBase::on_complete`]).
    before: Option<(Platform, Pose, Option<LazyRelation>)>,
    self_completed: bool,
    /// `<ownship>_<name>`, the bearing lines' label: neither changes once the behavior
    /// exists (an update may not rename it), so it is asked of the helm once.
    line_label: LabelCache,
    /// The bearing line's text, written again each iteration into this kept string.
    line_text: std::cell::RefCell<String>,
    /// `CLSG_SPD_AVD_<CN>` and `RANGE_AVD_<CN>`, made when the contact changes, and the
    /// contact name they were made for.
    per_contact_vars: (String, [String; 2]),
}

/// The bearing-line label, once asked. A copy of a base starts without it: the copy
/// may belong to another behavior (another name).
#[derive(Debug, Default)]
struct LabelCache(std::cell::OnceCell<String>);

impl Clone for LabelCache {
    fn clone(&self) -> Self {
        LabelCache::default()
    }
}

impl ContactBase {
    /// A base with the reference's defaults; `time_on_leg` differs per type (60 in the
    /// base, 120 AvoidCollision, 15 CutRange).
    pub fn new(time_on_leg: f64) -> Self {
        ContactBase {
            contact: String::new(),
            on_no_contact_ok: true,
            extrapolate: true,
            decay: Decay::default(),
            time_on_leg,
            post_per_contact_info: false,
            filter: ContactFilter::default(),
            exit_on_filter_vtype: false,
            exit_on_filter_group: false,
            exit_on_filter_region: false,
            cnflags: Vec::new(),
            bearing_lines: Vec::new(),
            bearing_info: BearingInfo::Relevance,
            bearing_line_show: false,
            // Uninitialised in the reference, seen on (contacts-appcast.md §6).
            bearing_line_label_show: true,
            no_alert_request: false,
            can_disable: false,
            templating: false,
            updates_var: String::new(),
            is_spawned: false,
            disabled: false,
            os: Platform::default(),
            cn: Pose::default(),
            cn_type: String::new(),
            cn_group: String::new(),
            cn_vsource: String::new(),
            cn_utc: 0.0,
            rel: None,
            prev: None,
            update_ok: false,
            warned: false,
            before: None,
            self_completed: false,
            line_label: LabelCache::default(),
            line_text: std::cell::RefCell::new(String::new()),
            per_contact_vars: Default::default(),
        }
    }

    /// [`ContactBase::set_param`] from a behavior's `set_param`: when the contact was
    /// set, the helm is told (`Ctx::set_contact`, for `IVPHELM_CONTACT_SUMMARY`), so a
    /// contact behavior cannot forget it.
    pub fn set_param_with(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> Option<bool> {
        let ok = self.set_param(param, value)?;
        if ok && param == "contact" {
            ctx.set_contact(&self.contact);
        }
        Some(ok)
    }

    /// A base parameter (name lower-cased): `None` when `param` is not one, else
    /// whether the value was accepted.
    pub fn set_param(&mut self, param: &str, value: &str) -> Option<bool> {
        let v = value.trim();
        let ok = match param {
            "contact" => {
                self.contact = v.to_string();
                true
            }
            "on_no_contact_ok" => set_bool(&mut self.on_no_contact_ok, v),
            "extrapolate" => set_bool(&mut self.extrapolate, v),
            "decay" => match Decay::parse(v) {
                Ok(d) => {
                    self.decay = d;
                    true
                }
                Err(_) => false,
            },
            "decay_end" => match parse_number(v) {
                Some(e) if e >= self.decay.start => {
                    self.decay.end = e;
                    true
                }
                _ => false,
            },
            "time_on_leg" => set_non_neg(&mut self.time_on_leg, v),
            "post_per_contact_info" => set_bool(&mut self.post_per_contact_info, v),
            "exit_on_filter_vtype" => set_bool(&mut self.exit_on_filter_vtype, v),
            "exit_on_filter_group" => set_bool(&mut self.exit_on_filter_group, v),
            "exit_on_filter_region" => set_bool(&mut self.exit_on_filter_region, v),
            "cnflag" => match CnFlag::parse(v) {
                Ok(f) => {
                    self.cnflags.push(f);
                    true
                }
                Err(_) => false,
            },
            "bearing_line_config" | "bearing_lines" => self.set_bearing_lines(v),
            "bearing_line_show" => set_bool(&mut self.bearing_line_show, v),
            "bearing_line_label_show" => set_bool(&mut self.bearing_line_label_show, v),
            "use_plat_model" => parse_bool(v, false).is_some(),
            "helm_templating" => {
                self.templating = !v.is_empty() && !v.eq_ignore_ascii_case("disallow");
                true
            }
            "helm_updates" => {
                self.updates_var = v.to_string();
                true
            }
            _ => {
                // An empty `contact_type_required` is refused (contacts-appcast.md §3.2).
                if param == "contact_type_required" && v.is_empty() {
                    return Some(false);
                }
                return match self.filter.set_param(param, v) {
                    Ok(true) => Some(true),
                    Ok(false) => None,
                    Err(_) => Some(false),
                };
            }
        };
        Some(ok)
    }

    /// `bearing_line_config = white:0, green:0.65, info:range`: colour thresholds.
    fn set_bearing_lines(&mut self, v: &str) -> bool {
        let mut lines = Vec::new();
        let mut info = self.bearing_info;
        for item in v.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let Some((a, b)) = item.split_once(':') else {
                return false;
            };
            let (a, b) = (a.trim(), b.trim());
            if a.eq_ignore_ascii_case("info") {
                info = match b.to_ascii_lowercase().as_str() {
                    "range" => BearingInfo::Range,
                    "relevance" => BearingInfo::Relevance,
                    _ => return false,
                };
                continue;
            }
            let Some(t) = parse_number(b) else {
                return false;
            };
            if !crate::is_color(a) {
                return false;
            }
            lines.push((a.to_string(), t));
        }
        self.bearing_lines = lines;
        self.bearing_info = info;
        self.bearing_line_show = true;
        true
    }

    /// The `on_spawn` hook: this instance came from a template.
    pub fn spawned(&mut self) {
        self.is_spawned = true;
    }

    /// Range to the contact at the last refresh (0 before the first).
    pub fn range(&self) -> f64 {
        self.rel.as_ref().map_or(0.0, LazyRelation::range)
    }

    /// The contact-state quantities of the last successful refresh.
    pub fn relation(&self) -> Option<&ContactRelation> {
        self.rel.as_ref().map(LazyRelation::get)
    }

    /// Whether a refresh has succeeded (so [`ContactBase::relation`] is `Some`), without
    /// computing the relation.
    pub fn has_relation(&self) -> bool {
        self.rel.is_some()
    }

    /// Whether the contact passes the filters whose `exit_on_filter_*` is set.
    pub fn exit_filter_fails(&self) -> bool {
        let c = self.filter.check(
            &self.contact,
            &self.cn_group,
            &self.cn_type,
            self.cn.x,
            self.cn.y,
        );
        (self.exit_on_filter_vtype && !c.vtype)
            || (self.exit_on_filter_group && !c.group)
            || (self.exit_on_filter_region && !c.region)
    }

    /// The "every state" hook: a spawned behavior whose contact left the ledger
    /// completes (contacts-appcast.md §3.6); otherwise the contact picture is refreshed.
    /// Returns whether the refresh succeeded.
    pub fn every_state(&mut self, ctx: &mut Ctx<'_>) -> bool {
        self.before = Some((self.os, self.cn, self.rel.clone()));
        if self.is_spawned && !self.contact.is_empty() && ctx.contact(&self.contact).is_none() {
            self.update_ok = false;
            self.complete(ctx);
            return false;
        }
        self.update(ctx)
    }

    /// Ask the helm to complete this behavior (endflags, removal).
    pub fn complete(&mut self, ctx: &mut Ctx<'_>) {
        self.self_completed = true;
        ctx.set_complete();
    }

    /// The `on_complete` hook. When the helm completed the behavior before its
    /// every-state hook (duration, ...), the reference skips that iteration's contact
    /// read: the picture (and so the post-mortem) goes back to the previous one.
    pub fn on_complete(&mut self) {
        if !self.self_completed {
            if let Some((os, cn, rel)) = self.before.take() {
                self.os = os;
                self.cn = cn;
                self.rel = rel;
            }
        }
    }

    /// Refresh the contact picture (behaviors-contacts.md §1.1–§1.2): ownship from the
    /// info buffer, the contact from the ledger snapshot, then range, bearings, CPA.
    pub fn update(&mut self, ctx: &mut Ctx<'_>) -> bool {
        self.update_ok = self.refresh(ctx);
        self.update_ok
    }

    fn refresh(&mut self, ctx: &mut Ctx<'_>) -> bool {
        let Some(os) = platform_update(ctx) else {
            return false;
        };
        self.os = os;
        if self.contact.is_empty() {
            if !self.on_no_contact_ok {
                ctx.post_emessage("contact IDX not set.");
            }
            return false;
        }
        if self.contact.eq_ignore_ascii_case("unset_ok") {
            return true;
        }
        ctx.set_contact(&self.contact);
        let msg = || format!("{} x/y/heading/speed info not found", self.contact);
        let Some(c) = ctx.contact(&self.contact) else {
            let msg = msg();
            if self.on_no_contact_ok {
                ctx.post_wmessage(&msg);
                self.warned = true;
            } else {
                ctx.post_emessage(&msg);
            }
            return false;
        };
        if self.warned {
            ctx.post_retract_wmessage(&msg());
            self.warned = false;
        }
        self.cn = Pose {
            x: c.x,
            y: c.y,
            hdg: angle360(c.hdg),
            spd: c.spd.max(0.0),
        };
        self.cn_utc = c.utc;
        // Written into the kept strings: nothing allocated in steady state.
        ctx.contact_text_into(&self.contact, "type", &mut self.cn_type);
        // The reference asks for the group under a field name the snapshot does not
        // know, so a contact behavior's contact group is always empty (§2.5).
        self.cn_group.clear();
        ctx.contact_text_into(&self.contact, "vsource", &mut self.cn_vsource);
        let os_pose = Pose {
            x: os.x,
            y: os.y,
            hdg: os.heading,
            spd: os.speed,
        };
        let rel = LazyRelation::new(os_pose, self.cn);
        self.prev = self.rel.replace(rel);
        if self.post_per_contact_info {
            self.post_per_contact(ctx);
        }
        true
    }

    fn post_per_contact(&mut self, ctx: &mut Ctx<'_>) {
        // The field, not relation(): per_contact_vars is borrowed mutably beside it.
        let Some(r) = self.rel.as_ref().map(LazyRelation::get) else {
            return;
        };
        let (made_for, [clsg_var, range_var]) = &mut self.per_contact_vars;
        if *made_for != self.contact || clsg_var.is_empty() {
            made_for.clone_from(&self.contact);
            let up = self.contact.to_ascii_uppercase();
            *clsg_var = format!("CLSG_SPD_AVD_{up}");
            *range_var = format!("RANGE_AVD_{up}");
        }
        let clsg = (r.rate_of_closure * 10.0).round() / 10.0;
        ctx.post_message_num(clsg_var, clsg);
        let rng = if r.range > 10.0 {
            r.range.round()
        } else {
            r.range
        };
        ctx.post_message_num(range_var, rng);
    }

    /// Contact flags (`cnflag`) of the running state, decided from the previous and
    /// current refresh (contacts-appcast.md §3.7); posted repeatable.
    pub fn handle_cnflags(&self, ctx: &mut Ctx<'_>) {
        // Without flags neither relation is asked for (nor computed).
        if self.cnflags.is_empty() {
            return;
        }
        let Some(cur) = self.relation() else { return };
        let prev = self.prev.as_ref().map(LazyRelation::get);
        for f in &self.cnflags {
            let fire = match f.tag {
                CnTag::Cpa => {
                    prev.is_some_and(|p| p.rate_of_closure > 0.0) && cur.rate_of_closure <= 0.0
                }
                CnTag::OsPassedCn => passed(prev, cur, |r| r.os_fore_of_cn, |r| r.os_aft_of_cn),
                CnTag::OsPassedCnPort => {
                    passed(prev, cur, |r| r.os_fore_of_cn, |r| r.os_aft_of_cn) && cur.os_port_of_cn
                }
                CnTag::OsPassedCnStar => {
                    passed(prev, cur, |r| r.os_fore_of_cn, |r| r.os_aft_of_cn) && cur.os_star_of_cn
                }
                CnTag::CnPassedOs => passed(prev, cur, |r| r.cn_fore_of_os, |r| r.cn_aft_of_os),
                CnTag::CnPassedOsPort => {
                    passed(prev, cur, |r| r.cn_fore_of_os, |r| r.cn_aft_of_os) && cur.cn_port_of_os
                }
                CnTag::CnPassedOsStar => {
                    passed(prev, cur, |r| r.cn_fore_of_os, |r| r.cn_aft_of_os) && cur.cn_star_of_os
                }
                CnTag::Crossed => false,
                tag => tag.fires_on_range(prev.map(|p| p.range), cur.range),
            };
            if !fire {
                continue;
            }
            match self.numeric_macro(&f.value) {
                Some(n) => ctx.post_repeatable_message(&f.var, PostValue::Num(n)),
                None => {
                    let s = self
                        .expand_macros(&f.value)
                        .unwrap_or_else(|| f.value.clone());
                    let s = ctx.expand_common_macros(&s);
                    ctx.post_repeatable_message(&f.var, PostValue::from(s.as_str()));
                }
            }
        }
    }

    /// A cnflag value that is exactly one of the numeric macros.
    fn numeric_macro(&self, v: &str) -> Option<f64> {
        let r = self.relation()?;
        Some(match v {
            // No CPA macro exists: the reference posts 0 (quirk).
            "$[CPA]" => 0.0,
            "$[RANGE]" => r.range,
            "$[OS_CN_REL_BNG]" => r.os_cn_rel_bng,
            "$[CN_OS_REL_BNG]" => r.cn_os_rel_bng,
            "$[BNG_RATE]" => r.bearing_rate,
            _ => return None,
        })
    }

    /// `BCM_ALERT_REQUEST` for a template instance (contacts-appcast.md §3.4): `None`
    /// when `no_alert_request`, without an `updates` variable or without templating.
    pub fn alert_request(&self, prefix: &str, alert_range: f64, cpa_range: f64) -> Option<String> {
        if self.no_alert_request || self.updates_var.is_empty() || !self.templating {
            return None;
        }
        Some(contacts::alert_request(
            prefix,
            &self.updates_var,
            alert_range,
            cpa_range,
            &self.filter,
        ))
    }

    /// The active bearing line (`VIEW_SEGLIST`), coloured by `index` (relevance or
    /// range, per `info:`); nothing without a configuration.
    pub fn post_bearing_line(&self, ctx: &mut Ctx<'_>, relevance: f64) {
        if !self.bearing_line_show || self.bearing_lines.is_empty() {
            return;
        }
        let index = match self.bearing_info {
            BearingInfo::Relevance => relevance,
            BearingInfo::Range => self.range(),
        };
        let color = self
            .bearing_lines
            .iter()
            .find(|(_, t)| index <= *t)
            .map_or("blank", |(c, _)| c.as_str());
        let label_color = if self.bearing_line_label_show {
            "white"
        } else {
            "off"
        };
        let label = self.line_label(ctx);
        let Ok(mut s) = self.line_text.try_borrow_mut() else {
            return;
        };
        s.clear();
        s.push_str("pts={");
        for (k, v) in [self.os.x, self.os.y, self.cn.x, self.cn.y]
            .into_iter()
            .enumerate()
        {
            if k > 0 {
                s.push(if k == 2 { ':' } else { ',' });
            }
            push_compact(&mut s, v, 2);
        }
        s.push_str("},label=");
        s.push_str(label);
        s.push_str(",label_color=");
        s.push_str(label_color);
        s.push_str(",edge_color=");
        s.push_str(color);
        s.push_str(",time=");
        push_compact(&mut s, ctx.get_buffer_curr_time(), 2);
        s.push_str(",duration=100");
        ctx.post_message("VIEW_SEGLIST", &s);
    }

    /// `<ownship>_<name>`, asked of the helm the first time only.
    fn line_label(&self, ctx: &Ctx<'_>) -> &str {
        self.line_label
            .0
            .get_or_init(|| format!("{}_{}", ctx.ownship(), ctx.name()))
    }

    /// The inactive bearing line (inactive hook, disabled state, completion).
    pub fn post_inactive_bearing_line(&self, ctx: &mut Ctx<'_>) {
        if !self.bearing_line_show || self.bearing_lines.is_empty() {
            return;
        }
        const HEAD: &str = "pts={0,0:9,0:0,9},active=false,label=";
        let label = self.line_label(ctx);
        // The active line's kept text: an idle contact behavior posts this every
        // iteration, and a new string each time was its only steady allocation.
        let Ok(mut s) = self.line_text.try_borrow_mut() else {
            return;
        };
        s.clear();
        s.push_str(HEAD);
        s.push_str(label);
        ctx.post_message("VIEW_SEGLIST", &s);
    }
}

/// An event tag fired when the "fore" relation turned into "aft" since the previous
/// refresh.
fn passed(
    prev: Option<&ContactRelation>,
    cur: &ContactRelation,
    fore: impl Fn(&ContactRelation) -> bool,
    aft: impl Fn(&ContactRelation) -> bool,
) -> bool {
    prev.is_some_and(|p| fore(p) && !aft(p)) && aft(cur) && !fore(cur)
}

fn set_bool(field: &mut bool, v: &str) -> bool {
    match parse_bool(v, *field) {
        Some(b) => {
            *field = b;
            true
        }
        None => false,
    }
}

fn set_non_neg(field: &mut f64, v: &str) -> bool {
    match parse_number(v) {
        Some(n) if n >= 0.0 => {
            *field = n;
            true
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests;
