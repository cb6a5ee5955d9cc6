//! The manager: mail in, an iteration, postings out (the helm engine's shape).

use contacts::{Decay, NodeReport};
use mbutil::short_str;

use crate::alert::{Alert, AlertSet};
use crate::config::Config;
use crate::macros::flag_posting;
use crate::requests::{able_postings, Able, ReportRequest, ReportRequests};
use crate::status::Status;
use crate::table::{Contact, Table};
pub use crate::value::Ownship;
use crate::value::{MailValue, Posting};
use crate::warnings::Warnings;

/// The CPA horizon of the alert test (s).
pub const CPA_HORIZON: f64 = 36000.0;

/// Geometry of one contact at one iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry {
    /// Ownship to the last reported position.
    pub range: f64,
    /// Ownship to the extrapolated position.
    pub range_extrap: f64,
    /// Closest approach from the extrapolated position.
    pub cpa: f64,
    pub age: f64,
}

/// pContactMgrV20 as a library. Per iteration: [`ContactManager::handle_mail`] with the
/// batch, then [`ContactManager::iterate`], then post what it returns.
#[derive(Debug)]
pub struct ContactManager {
    cfg: Config,
    ownship_name: String,
    os: Ownship,
    table: Table,
    /// Alerted (contact, alert id) pairs, sorted.
    alerted: Vec<(String, String)>,
    reports: ReportRequests,
    helm_drive_seen: bool,
    display_radii: bool,
    postings: Vec<Posting>,
    /// The postings were handed out: clear before adding more.
    handed_out: bool,
    retired_now: Vec<Contact>,
    scratch: String,
    status: Status,
    warnings: Warnings,
    alert_requests: u64,
    reports_received: u64,
    /// Text `NODE_REPORT`s that name no vehicle or give no time or position.
    malformed_reports: u64,
    iterations: u64,
}

fn geometry(os: &Ownship, c: &Contact, decay: &Decay, now: f64) -> Geometry {
    *Lazy::new(os, c, decay, now).full(os, c)
}

/// [`geometry`] with the closest approach worked out only when asked: most alert
/// checks decide on the range alone, and a range report reads only the range.
struct Lazy {
    /// Its `cpa` is NaN until [`Lazy::full`].
    g: Geometry,
    /// The contact's extrapolated position.
    ex: f64,
    ey: f64,
    known: bool,
}

impl Lazy {
    fn new(os: &Ownship, c: &Contact, decay: &Decay, now: f64) -> Lazy {
        let (ex, ey) = decay.extrapolate(c.x, c.y, c.hdg, c.spd, c.utc, now);
        Lazy {
            g: Geometry {
                range: contacts::range(os.x, os.y, c.x, c.y),
                range_extrap: contacts::range(os.x, os.y, ex, ey),
                cpa: f64::NAN,
                age: now - c.utc,
            },
            ex,
            ey,
            known: false,
        }
    }

    /// The whole geometry (the same `os` and `c` as [`Lazy::new`]).
    fn full(&mut self, os: &Ownship, c: &Contact) -> &Geometry {
        if !self.known {
            let cpa = contacts::cpa(
                os.x,
                os.y,
                os.hdg,
                os.spd,
                self.ex,
                self.ey,
                c.hdg,
                c.spd,
                CPA_HORIZON,
            );
            self.g.cpa = cpa.dist;
            self.known = true;
        }
        &self.g
    }
}

/// Whether `a` applies to contact `c` with geometry `l` (§4.3; `os` the ownship `l`
/// was made with).
fn applies(a: &Alert, c: &Contact, os: &Ownship, l: &mut Lazy, max_age: f64) -> bool {
    // A NaN age (hostile TIME) is not fresh.
    let fresh = l.g.age <= max_age;
    if !(a.valid() && a.enabled && fresh) {
        return false;
    }
    if !a.filter.check(&c.name, &c.group, &c.vtype, c.x, c.y).all() {
        return false;
    }
    let ar = a.alert_range.unwrap_or(0.0);
    if ar > 0.0 {
        let range = l.g.range;
        return range <= a.cpa_range() && (range <= ar || l.full(os, c).cpa <= ar);
    }
    true
}

impl ContactManager {
    /// A manager for the vehicle `ownship` (the community name; its own reports are
    /// ignored, case-insensitively), with the mission's LatOrigin/LongOrigin if any.
    ///
    /// ```
    /// use contact_manager::{Config, ContactManager, MailValue::*};
    /// let mut cfg = Config::default();
    /// cfg.set("alert", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME], alert_range=50, cpa_range=75").unwrap();
    /// let mut m = ContactManager::new("alpha", cfg, None);
    /// m.handle_mail(10.0, &[("NAV_X", Num(0.0)), ("NAV_Y", Num(0.0)),
    ///     ("NODE_REPORT", Str("NAME=bob,X=0,Y=40,SPD=0,HDG=0,TIME=10"))]);
    /// let p = m.iterate(10.0);
    /// assert!(p.iter().any(|p| p.var == "CONTACT_INFO" && p.val.as_str() == Some("name=bob # contact=bob")));
    /// ```
    pub fn new(ownship: &str, cfg: Config, origin: Option<(f64, f64)>) -> ContactManager {
        ContactManager {
            table: Table::new(origin, cfg.local_coords, cfg.max_contacts),
            display_radii: cfg.display_radii,
            cfg,
            ownship_name: ownship.to_string(),
            os: Ownship::default(),
            alerted: Vec::new(),
            reports: ReportRequests::default(),
            helm_drive_seen: false,
            postings: Vec::new(),
            handed_out: false,
            retired_now: Vec::new(),
            scratch: String::new(),
            status: Status::default(),
            warnings: Warnings::default(),
            alert_requests: 0,
            reports_received: 0,
            malformed_reports: 0,
            iterations: 0,
        }
    }

    pub fn config(&self) -> &Config {
        &self.cfg
    }
    pub fn alerts(&self) -> &AlertSet {
        &self.cfg.alerts
    }
    pub fn ownship(&self) -> &Ownship {
        &self.os
    }
    pub fn ownship_name(&self) -> &str {
        &self.ownship_name
    }
    pub fn table(&self) -> &Table {
        &self.table
    }
    /// The alerted (contact, alert id) pairs.
    pub fn alerted(&self) -> impl Iterator<Item = (&str, &str)> {
        self.alerted.iter().map(|(n, i)| (n.as_str(), i.as_str()))
    }
    pub fn warnings(&self) -> &Warnings {
        &self.warnings
    }
    pub fn warnings_mut(&mut self) -> &mut Warnings {
        &mut self.warnings
    }
    pub fn report_requests(&self) -> &[ReportRequest] {
        &self.reports.list
    }
    /// (alert requests, node reports) received.
    pub fn received(&self) -> (u64, u64) {
        (self.alert_requests, self.reports_received)
    }
    /// Text `NODE_REPORT`s received that name no vehicle or give no time or position
    /// (neither X and Y nor LON).
    pub fn malformed_reports(&self) -> u64 {
        self.malformed_reports
    }
    pub fn iterations(&self) -> u64 {
        self.iterations
    }
    pub fn helm_drive_seen(&self) -> bool {
        self.helm_drive_seen
    }
    pub fn retired(&self) -> &std::collections::VecDeque<String> {
        &self.status.retired
    }

    /// The geometry of contact `c` now, as the alert test sees it.
    pub fn geometry(&self, c: &Contact, now: f64) -> Geometry {
        geometry(&self.os, c, &self.cfg.decay, now)
    }

    /// The variables the manager reads (the configured able variables included).
    pub fn subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "NAV_X",
            "NAV_Y",
            "NAV_HEADING",
            "NAV_SPEED",
            "NODE_REPORT",
            "BCM_ALERT_REQUEST",
            "BCM_REPORT_REQUEST",
            "BCM_DISPLAY_RADII",
            "IVPHELM_STATE",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for s in [
            &self.cfg.disable_var,
            &self.cfg.enable_var,
            &self.cfg.expunge_var,
        ] {
            if !s.is_empty() && !v.contains(s) {
                v.push(s.clone());
            }
        }
        v
    }

    fn fresh_postings(&mut self) {
        if self.handed_out {
            self.postings.clear();
            self.handed_out = false;
        }
    }

    /// Take one batch of mail received by time `now`.
    pub fn handle_mail(&mut self, now: f64, mail: &[(&str, MailValue<'_>)]) {
        self.handle_mail_parsed(now, mail, &());
    }

    /// [`Self::handle_mail`] with some `NODE_REPORT`s already read: `parsed.read(k)`,
    /// when given, is `NodeReport::parse` of `mail[k]`'s text (a fleet simulator reads
    /// each report once for all its receivers); the others are read here.
    pub fn handle_mail_parsed(
        &mut self,
        now: f64,
        mail: &[(&str, MailValue<'_>)],
        parsed: &dyn contacts::report::ReadReports,
    ) {
        self.fresh_postings();
        for (k, (var, val)) in mail.iter().enumerate() {
            self.one_mail(now, var, val, || parsed.read(k));
        }
    }

    fn one_mail<'r>(
        &mut self,
        now: f64,
        var: &str,
        val: &MailValue<'_>,
        parsed: impl FnOnce() -> Option<NodeReport<'r>>,
    ) {
        let num = |slot: &mut f64| {
            if let Some(v) = val.num().filter(|v| v.is_finite()) {
                *slot = v;
            }
        };
        match var {
            "NAV_X" => num(&mut self.os.x),
            "NAV_Y" => num(&mut self.os.y),
            "NAV_HEADING" => num(&mut self.os.hdg),
            "NAV_SPEED" => num(&mut self.os.spd),
            "NODE_REPORT" => match val {
                MailValue::Str(s) => self.node_report(s, true, parsed().as_ref()),
                MailValue::Num(_) => self.node_report(&val.text(), false, None),
            },
            "BCM_ALERT_REQUEST" => {
                self.alert_requests += 1;
                let text = val.text();
                if let Err(e) = self.cfg.alerts.apply(&text) {
                    tracing::warn!(request = %text, error = %e, "alert request refused");
                    self.warnings
                        .run_warning(&format!("Unhandled Alert Request: {text}"));
                }
            }
            "BCM_REPORT_REQUEST" => {
                let text = val.text();
                match ReportRequest::parse(&text, now) {
                    Ok(r) => self.reports.add(
                        r,
                        now,
                        self.cfg.range_report_timeout,
                        self.cfg.range_report_maxsize,
                    ),
                    Err(e) => self
                        .warnings
                        .run_warning(&format!("Unhandled Report Request: {text} ({e})")),
                }
            }
            "BCM_DISPLAY_RADII" => match val.text().trim().to_ascii_lowercase().as_str() {
                "true" => self.display_radii = true,
                "false" => self.display_radii = false,
                other => self
                    .warnings
                    .run_warning(&format!("Unhandled BCM_DISPLAY_RADII: {other}")),
            },
            "IVPHELM_STATE" => {
                if val.text().trim().eq_ignore_ascii_case("drive") {
                    self.helm_drive_seen = true;
                }
            }
            _ => self.able_mail(var, val),
        }
    }

    fn able_mail(&mut self, var: &str, val: &MailValue<'_>) {
        let action = if var == self.cfg.disable_var {
            Able::Disable
        } else if var == self.cfg.enable_var {
            Able::Enable
        } else if var == self.cfg.expunge_var {
            Able::Expunge
        } else {
            return;
        };
        let c = &self.cfg;
        match able_postings(
            action,
            &val.text(),
            &c.able_flags,
            &c.disable_flags,
            &c.enable_flags,
        ) {
            Ok(p) => self.postings.extend(p),
            Err(e) => self
                .warnings
                .run_warning(&format!("Unhandled {var}: {} ({e})", val.text())),
        }
    }

    /// One `NODE_REPORT` (`text`: it came as a string, so it counts toward
    /// [`Self::malformed_reports`]).
    fn node_report(&mut self, report: &str, text: bool, parsed: Option<&NodeReport<'_>>) {
        self.reports_received += 1;
        let read;
        let r = match parsed {
            Some(r) => r,
            None => {
                read = NodeReport::parse(report);
                &read
            }
        };
        if text && (r.name.is_empty() || r.time.is_none() || !(r.has_xy() || r.has_latlon())) {
            self.malformed_reports += 1;
        }
        match self
            .table
            .ingest_parsed(r, &self.cfg.filter, &self.ownship_name)
        {
            Ok((name, new)) => {
                if new && self.cfg.alert_verbose {
                    let p = Posting::str("ALERT_VERBOSE", format!("new_contact={name}"));
                    self.postings.push(p);
                }
            }
            Err(e) if e.warns() => {
                self.warnings
                    .run_warning(&format!("Bad Mail: NODE_REPORT:{e}"));
            }
            Err(_) => {}
        }
    }

    /// One iteration at time `now`: alerts, retirement, range reports and the status
    /// postings. Returns everything to post since the last call (mail postings too).
    pub fn iterate(&mut self, now: f64) -> &[Posting] {
        self.fresh_postings();
        self.iterations += 1;
        if !self.cfg.hold_alerts_for_helm || self.helm_drive_seen {
            self.check_alerts(now);
        }
        self.retire(now);
        self.range_reports(now);
        self.status.post(
            &mut self.postings,
            now,
            &self.cfg,
            &self.ownship_name,
            &self.os,
            &self.table,
            &self.alerted,
            self.display_radii,
        );
        self.handed_out = true;
        &self.postings
    }

    fn check_alerts(&mut self, now: f64) {
        let max_age = self.cfg.contact_max_age;
        for c in self.table.contacts() {
            let mut l = Lazy::new(&self.os, c, &self.cfg.decay, now);
            for a in self.cfg.alerts.alerts() {
                let on = applies(a, c, &self.os, &mut l, max_age);
                let key = (c.name.as_str(), a.id.as_str());
                let pos = self.alerted.binary_search_by(|(n, i)| {
                    short_str::order(n, key.0).then_with(|| short_str::order(i, key.1))
                });
                match (pos, on) {
                    (Err(i), true) => {
                        self.alerted.insert(i, (c.name.clone(), a.id.clone()));
                        for f in &a.on_flags {
                            self.postings.push(flag_posting(f, c, now));
                        }
                        if self.cfg.alert_verbose {
                            self.postings.push(verbose(c, a, l.full(&self.os, c), true));
                        }
                    }
                    (Ok(i), false) => {
                        self.alerted.remove(i);
                        for f in &a.off_flags {
                            self.postings.push(flag_posting(f, c, now));
                        }
                        if self.cfg.alert_verbose {
                            self.postings
                                .push(verbose(c, a, l.full(&self.os, c), false));
                        }
                    }
                    _ => {}
                }
            }
        }
    }

    /// Retire old and far contacts; a retired contact still alerted gets its off-flags.
    fn retire(&mut self, now: f64) {
        self.retired_now.clear();
        self.table.retire(
            now,
            self.cfg.contact_max_age,
            (self.os.x, self.os.y),
            self.cfg.reject_range,
            &mut self.retired_now,
        );
        for c in &self.retired_now {
            let g = geometry(&self.os, c, &self.cfg.decay, now);
            for a in self.cfg.alerts.alerts() {
                let key = (c.name.as_str(), a.id.as_str());
                if let Ok(i) = self
                    .alerted
                    .binary_search_by(|(n, i)| (n.as_str(), i.as_str()).cmp(&key))
                {
                    self.alerted.remove(i);
                    for f in &a.off_flags {
                        self.postings.push(flag_posting(f, c, now));
                    }
                    if self.cfg.alert_verbose {
                        self.postings.push(verbose(c, a, &g, false));
                    }
                }
            }
            self.status
                .note_retired(&c.name, self.cfg.max_retired_history);
        }
    }

    fn range_reports(&mut self, now: f64) {
        // One reused buffer: a steady report allocates nothing.
        let mut val = std::mem::take(&mut self.scratch);
        for r in &mut self.reports.list {
            val.clear();
            for c in self.table.contacts() {
                if !r.group.is_empty() && !r.group.eq_ignore_ascii_case(&c.group) {
                    continue;
                }
                if !r.vtype.is_empty() && !r.vtype.eq_ignore_ascii_case(&c.vtype) {
                    continue;
                }
                let g = Lazy::new(&self.os, c, &self.cfg.decay, now).g;
                if g.range_extrap < r.range {
                    if !val.is_empty() {
                        val.push(',');
                    }
                    val.push_str(&c.name);
                }
            }
            if r.refresh || r.last.as_deref() != Some(val.as_str()) {
                self.postings.push(Posting::str(&r.var, val.clone()));
                r.last = Some(val.clone());
                r.refresh = false;
            }
        }
        self.scratch = val;
    }
}

/// The `ALERT_VERBOSE` line of a transition.
fn verbose(c: &Contact, a: &Alert, g: &Geometry, on: bool) -> Posting {
    let ar = mbutil::compact(a.alert_range.unwrap_or(0.0), 1);
    let cr = mbutil::compact(a.cpa_range(), 1);
    let head = format!(
        "contact={},alert_id={},{},alert_range={ar},alert_range_cpa={cr},range_actual={:.1}",
        c.name,
        a.id,
        if on { "off-->alerted" } else { "alerted-->off" },
        g.range
    );
    let val = if on {
        format!("{head},range_cpa={:.1}", g.cpa)
    } else {
        head
    };
    Posting::str("ALERT_VERBOSE", val)
}

#[cfg(test)]
#[path = "manager_tests.rs"]
mod tests;
