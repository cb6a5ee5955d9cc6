//! Mail processing before each iteration (helm.md §4.2).

use super::{Helm, HelmState};
use crate::posting::Value;
use contacts::ledger::nav_var;

/// One incoming MOOS message.
#[derive(Clone, Debug, PartialEq)]
pub struct Mail {
    pub var: String,
    pub value: Value,
    /// The message's own timestamp.
    pub time: f64,
    pub source: String,
    pub source_aux: String,
}

/// The run warning while `hold_on_apps` are missing (retracted once they are seen).
pub(crate) const HOLD_WAIT: &str = "Not all HoldOnApps have been detected";

impl Helm {
    /// Take one batch of mail into the info buffer.
    pub fn handle_mail(&mut self, now: f64, batch: &[Mail]) {
        self.handle_mail_parsed(now, batch, &());
    }

    /// [`Helm::handle_mail`] with some reports already read: `parsed.read(k)`, when
    /// given, is `NodeReport::parse` of `batch[k]`'s text (a fleet simulator reads each
    /// report once for all its receivers); the others are read here.
    pub fn handle_mail_parsed(
        &mut self,
        now: f64,
        batch: &[Mail],
        parsed: &dyn contacts::report::ReadReports,
    ) {
        self.fresh_outbox();
        if self.state == HelmState::Disabled {
            return;
        }
        self.ib.set_curr_time(now);
        self.mail_this_cycle = true;
        for (k, m) in batch.iter().enumerate() {
            self.handle_one(now, m, || parsed.read(k));
        }
        self.ib.set_string("COMMS_POLICY", "open", now);
        if self.state == HelmState::Standby {
            // A standby helm takes over once the primary has gone quiet.
            if let (Some(t), Some(last)) = (self.config.standby, self.last_heartbeat) {
                if now - last > t {
                    self.state = if self.has_control {
                        HelmState::Drive
                    } else {
                        HelmState::Park
                    };
                }
            }
        }
    }

    /// Every app named by `hold_on_apps` has appeared in DB_CLIENTS (helm.md §11).
    pub(crate) fn hold_apps_seen(&self) -> bool {
        self.config
            .hold_on_apps
            .iter()
            .all(|h| self.apps_seen.iter().any(|a| a == h))
    }

    fn is_own_posting(&self, m: &Mail) -> bool {
        m.source == self.app_name
    }

    /// One message; `parsed` reads it when it is a report (see
    /// [`Helm::handle_mail_parsed`]).
    fn handle_one<'r>(
        &mut self,
        now: f64,
        m: &Mail,
        parsed: impl FnOnce() -> Option<contacts::NodeReport<'r>>,
    ) {
        if let Some(ok_skew) = self.config.ok_skew {
            let skew = (now - m.time).abs();
            if skew > ok_skew && !self.is_own_posting(m) && m.var != "HELM_MAP_CLEAR" {
                let text = format!(
                    "Helm ignores MOOS msg due to skew: {} Source={} Skew={:.2}",
                    m.var, m.source, skew
                );
                self.run_warning(&text);
                self.post_str("IVPHELM_SKEW", &format!("{text} curr_time: {now:.3}"));
                return;
            }
        }
        let var = m.var.as_str();
        let is_override = var == "MOOS_MANUAL_OVERIDE"
            || var == "MOOS_MANUAL_OVERRIDE"
            || (!self.config.other_override_var.is_empty()
                && var == self.config.other_override_var);
        if is_override {
            if var != self.config.other_override_var {
                let ev = format!(
                    "var={var}:matter={}, skew={:.2}",
                    self.config.allow_park,
                    now - m.time
                );
                self.report.warnings.event(now - self.start_time, &ev);
            }
            if let Value::Str(s) = &m.value {
                if s.eq_ignore_ascii_case("false") {
                    self.has_control = true;
                } else if s.eq_ignore_ascii_case("true") && self.config.allow_park {
                    self.has_control = false;
                }
            }
            self.ib.set_value(var, &m.value, m.time);
            return;
        }
        match var {
            "IVPHELM_STATE" => {
                self.helm_state_seen = true;
                if !self.is_own_posting(m) {
                    if self.config.standby.is_some() {
                        if self.state == HelmState::Standby {
                            self.last_heartbeat = Some(now);
                        } else {
                            self.refresh_pending = true;
                        }
                    } else if !matches!(&m.value, Value::Str(s) if s == "STANDBY") {
                        self.all_stop("DisabledByStandbyHelm");
                        self.state = HelmState::Disabled;
                    }
                }
            }
            "DB_CLIENTS" => {
                if let Value::Str(list) = &m.value {
                    for app in list.split(',').map(str::trim).filter(|a| !a.is_empty()) {
                        if !self.apps_seen.iter().any(|a| a == app) {
                            self.apps_seen.push(app.to_string());
                        }
                    }
                }
                if !self.startup_messages.is_empty() && !self.hold_apps_seen() {
                    self.run_warning(HOLD_WAIT);
                }
            }
            "IVPHELM_REJOURNAL" => self.summary_last.clear(),
            "RESTART_HELM" => {
                if let Value::Str(t) = &m.value {
                    let t = t.trim().to_ascii_lowercase();
                    if t == "type1" || t == "type2" {
                        self.restart = Some(t);
                    }
                }
            }
            "BHV_ABLE_FILTER" => {}
            "NODE_REPORT_LOCAL" => self.note_local_report(m, parsed().as_ref()),
            _ if contacts::feeds_ledger(var) => {
                self.ingest_report(m, parsed().as_ref());
                self.ib.set_value(var, &m.value, m.time);
            }
            "HELM_MAP_CLEAR" => self.refresh_pending = true,
            _ => {
                if m.source_aux != "HELM_VAR_INIT" {
                    self.ib.set_value(var, &m.value, m.time);
                }
            }
        }
    }
}

impl Helm {
    /// A contact's report into the ledger (contacts-appcast.md §2.1, §2.2): its group
    /// and type go to the info buffer as `<NAME>_NAV_GROUP`/`_NAV_TYPE`; a refused report
    /// is two run warnings, and (as the real helm) still sets those two variables of the
    /// empty name to "".
    fn ingest_report(&mut self, m: &Mail, parsed: Option<&contacts::NodeReport<'_>>) {
        let Value::Str(report) = &m.value else {
            return;
        };
        let now = self.ib.curr_time();
        let got = match parsed {
            Some(r) => self.env.ledger.ingest_parsed(r, now),
            None => self.env.ledger.ingest(report, now),
        };
        match got {
            Ok(a) => self.ib.set_contact_nav(a.name, a.group, a.vtype, m.time),
            Err(e) => {
                for w in e.run_warnings(report) {
                    self.run_warning(&w);
                }
                self.ib.set_string("_NAV_GROUP", "", m.time);
                self.ib.set_string("_NAV_TYPE", "", m.time);
            }
        }
    }

    /// Ownship's own report (pNodeReporter): not a contact, only its group, type, colour
    /// and length go to the info buffer (`contacts::for_each_local_nav`; from `parsed`,
    /// its full reading, when given).
    fn note_local_report(&mut self, m: &Mail, parsed: Option<&contacts::NodeReport<'_>>) {
        let Value::Str(report) = &m.value else {
            return;
        };
        // The variable written into a kept string: the report comes every iteration.
        let mut var = std::mem::take(&mut self.report_var);
        let ib = &mut self.ib;
        let post = |name: &str, suffix, value| {
            nav_var(&mut var, name, suffix);
            match value {
                contacts::LocalValue::Text(s) => ib.set_string(&var, s, m.time),
                contacts::LocalValue::Num(n) => ib.set_value(&var, &Value::Num(n), m.time),
            }
        };
        let posted = match parsed {
            Some(r) => local_nav_of(r, post),
            None => contacts::for_each_local_nav(report, post).is_ok(),
        };
        self.report_var = var;
        if !posted {
            self.run_warning("Unhandled NODE_REPORT_LOCAL");
        }
    }
}

/// `contacts::for_each_local_nav` of a report already read (it reads the same five
/// fields as the full reading); false for a report without a name.
fn local_nav_of<'a>(
    r: &contacts::NodeReport<'a>,
    mut post: impl FnMut(&'a str, &'static str, contacts::LocalValue<'a>),
) -> bool {
    if r.name.is_empty() {
        return false;
    }
    for (suffix, s) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
        if !s.is_empty() {
            post(r.name, suffix, contacts::LocalValue::Text(s));
        }
    }
    if let Some(l) = r.length.filter(|&l| l != 0.0) {
        post(r.name, "LENGTH", contacts::LocalValue::Num(l));
    }
    true
}

#[cfg(test)]
mod tests {
    use contacts::{LocalValue, NodeReport};

    /// The same postings, in the same order, as the text's own reading.
    #[test]
    fn local_nav_of_a_reading_is_the_texts() {
        for text in [
            "NAME=alpha,X=1,Y=2,TYPE=kayak,COLOR=yellow,LENGTH=4,TIME=5",
            " name = Bob , group=red, len=2.5, LENGTH=nan, type= UUV ,color=",
            r#"{"NAME":"a","GROUP":"{x,y}","LENGTH":"3","LEN":"x"}"#,
            "NAME=a,LENGTH=0,GROUP=g",
            "",
            "X=1,Y=2",
        ] {
            let mut by_text: Vec<(String, &str, LocalValue)> = Vec::new();
            let ok = contacts::for_each_local_nav(text, |n, s, v| by_text.push((n.into(), s, v)));
            let mut by_read: Vec<(String, &str, LocalValue)> = Vec::new();
            let r = NodeReport::parse(text);
            let posted = super::local_nav_of(&r, |n, s, v| by_read.push((n.into(), s, v)));
            assert_eq!((ok.is_ok(), by_text), (posted, by_read), "{text}");
        }
    }
}
