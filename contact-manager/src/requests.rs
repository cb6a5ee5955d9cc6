//! Run-time requests other than alerts: `BCM_REPORT_REQUEST` range reports and the
//! disable/enable/expunge variables that become `BHV_ABLE_FILTER` (contacts-appcast.md
//! §4.1).

use crate::alert::split_fields;
use crate::value::Posting;
use crate::Flag;

/// Most report variables a hostile sender can make us keep, whatever the configured
/// `range_report_maxsize`.
pub const MAX_REPORT_REQUESTS: usize = 1000;

/// A refused request.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RequestError {
    #[error("not key=value: {0}")]
    NotAPair(String),
    #[error("unknown key: {0}")]
    UnknownKey(String),
    #[error("missing var")]
    NoVar,
    #[error("missing or bad range: {0}")]
    BadRange(String),
    #[error("refresh must be true or false: {0}")]
    BadRefresh(String),
    #[error("empty contact")]
    NoContact,
}

/// One `BCM_REPORT_REQUEST`: post `var` = the contacts within `range`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportRequest {
    pub var: String,
    pub range: f64,
    pub group: String,
    pub vtype: String,
    pub reason: String,
    /// Post at the next iteration even when the list did not change.
    pub refresh: bool,
    /// When the request was last received.
    pub received: f64,
    /// The last value posted (`None` before the first posting).
    pub last: Option<String>,
}

impl ReportRequest {
    /// `var=<VAR>,range=<m>[,group=..][,type=..][,refresh=true][,reason=..]`.
    ///
    /// ```
    /// let r = contact_manager::ReportRequest::parse("var=NEAR,range=100,type=kayak", 5.0).unwrap();
    /// assert_eq!((r.var.as_str(), r.range, r.vtype.as_str()), ("NEAR", 100.0, "kayak"));
    /// ```
    pub fn parse(s: &str, now: f64) -> Result<ReportRequest, RequestError> {
        let mut r = ReportRequest {
            var: String::new(),
            range: -1.0,
            group: String::new(),
            vtype: String::new(),
            reason: String::new(),
            refresh: false,
            received: now,
            last: None,
        };
        for field in split_fields(s, ',') {
            if field.trim().is_empty() {
                continue;
            }
            let (k, v) = field
                .split_once('=')
                .ok_or_else(|| RequestError::NotAPair(field.trim().into()))?;
            let v = v.trim();
            match k.trim().to_ascii_lowercase().as_str() {
                "var" => r.var = v.to_string(),
                "range" => {
                    r.range = mbutil::parse_number(v)
                        .filter(|x| *x >= 0.0 && x.is_finite())
                        .ok_or_else(|| RequestError::BadRange(v.into()))?
                }
                "group" => r.group = v.to_string(),
                "type" => r.vtype = v.to_string(),
                "reason" => r.reason = v.to_string(),
                "refresh" => {
                    r.refresh = match v.to_ascii_lowercase().as_str() {
                        "true" => true,
                        "false" => false,
                        _ => return Err(RequestError::BadRefresh(v.into())),
                    }
                }
                other => return Err(RequestError::UnknownKey(other.into())),
            }
        }
        if r.var.is_empty() || r.var.contains(char::is_whitespace) {
            return Err(RequestError::NoVar);
        }
        if r.range < 0.0 {
            return Err(RequestError::BadRange(String::new()));
        }
        Ok(r)
    }
}

/// The report requests by variable, oldest first.
#[derive(Clone, Debug, Default)]
pub struct ReportRequests {
    pub list: Vec<ReportRequest>,
}

impl ReportRequests {
    /// Add or renew a request (the last posted value of a renewed one is kept, so it
    /// posts again only on change or `refresh`). While more than `maxsize` are held,
    /// the oldest expired one (not renewed within `timeout`) is dropped.
    pub fn add(&mut self, mut r: ReportRequest, now: f64, timeout: f64, maxsize: usize) {
        match self.list.iter().position(|q| q.var == r.var) {
            Some(i) => {
                let mut old = self.list.remove(i);
                r.last = old.last.take();
                self.list.push(r);
            }
            None => self.list.push(r),
        }
        let maxsize = maxsize.min(MAX_REPORT_REQUESTS);
        while self.list.len() > maxsize {
            let expired = self.list.iter().position(|q| now - q.received > timeout);
            match expired {
                Some(i) => {
                    self.list.remove(i);
                }
                // Nothing expired: keep them, up to our own hard cap.
                None if self.list.len() > MAX_REPORT_REQUESTS => {
                    self.list.remove(0);
                }
                None => break,
            }
        }
    }
}

/// What a disable/enable/expunge variable asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Able {
    Disable,
    Enable,
    Expunge,
}

impl Able {
    fn word(self) -> &'static str {
        match self {
            Able::Disable => "disable",
            Able::Enable => "enable",
            Able::Expunge => "expunge",
        }
    }
}

/// The `BHV_ABLE_FILTER` posting for a value `<contact>`, `contact=<c>` or
/// `vsource=<s>`, then the configured flags (`able_flag` always, `disable_flag` /
/// `enable_flag` by action; `$[CONTACT]` in them is the contact).
///
/// ```
/// use contact_manager::{able_postings, Able};
/// let p = able_postings(Able::Disable, "bob", &[], &[], &[]).unwrap();
/// assert_eq!(p[0].val.as_str(), Some("contact=bob,action=disable"));
/// let p = able_postings(Able::Expunge, "vsource=ais", &[], &[], &[]).unwrap();
/// assert_eq!(p[0].val.as_str(), Some("vsource=ais,action=expunge"));
/// ```
pub fn able_postings(
    action: Able,
    value: &str,
    able_flags: &[Flag],
    disable_flags: &[Flag],
    enable_flags: &[Flag],
) -> Result<Vec<Posting>, RequestError> {
    let v = value.trim();
    let (key, who) = match v.split_once('=') {
        Some((k, w)) => match k.trim().to_ascii_lowercase().as_str() {
            "contact" => ("contact", w.trim()),
            "vsource" => ("vsource", w.trim()),
            other => return Err(RequestError::UnknownKey(other.into())),
        },
        None => ("contact", v),
    };
    if who.is_empty() || who.contains(',') {
        return Err(RequestError::NoContact);
    }
    let mut out = vec![Posting::str(
        "BHV_ABLE_FILTER",
        format!("{key}={who},action={}", action.word()),
    )];
    let extra: &[Flag] = match action {
        Able::Disable => disable_flags,
        Able::Enable => enable_flags,
        Able::Expunge => &[],
    };
    for f in able_flags.iter().chain(extra) {
        out.push(Posting {
            var: f.var.clone(),
            val: crate::value::Value::flag(&f.val.replace("$[CONTACT]", who)),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_request_errors() {
        assert_eq!(
            ReportRequest::parse("range=5", 0.0),
            Err(RequestError::NoVar)
        );
        assert!(ReportRequest::parse("var=A,range=-5", 0.0).is_err());
        assert!(ReportRequest::parse("var=A", 0.0).is_err());
        assert!(ReportRequest::parse("var=A,range=5,colour=red", 0.0).is_err());
        assert!(ReportRequest::parse("var=A,range=5,refresh=maybe", 0.0).is_err());
        let r = ReportRequest::parse("var=A,range=5,refresh=TRUE,reason=x", 0.0).unwrap();
        assert!(r.refresh);
    }

    #[test]
    fn oldest_expired_pruned_only_above_maxsize() {
        let mut rr = ReportRequests::default();
        let req = |v: &str, t: f64| ReportRequest::parse(&format!("var={v},range=1"), t).unwrap();
        rr.add(req("A", 0.0), 0.0, 10.0, 2);
        rr.add(req("B", 5.0), 5.0, 10.0, 2);
        // Three at t=20: A and B are expired; the oldest (A) goes.
        rr.add(req("C", 20.0), 20.0, 10.0, 2);
        let vars: Vec<&str> = rr.list.iter().map(|r| r.var.as_str()).collect();
        assert_eq!(vars, ["B", "C"]);
        // Three, none expired: all kept.
        rr.add(req("B", 21.0), 21.0, 10.0, 2);
        rr.add(req("D", 22.0), 22.0, 10.0, 2);
        assert_eq!(rr.list.len(), 3);
    }

    #[test]
    fn able_flags_follow_the_action() {
        let able = [Flag::parse("ABLE=$[CONTACT]").unwrap()];
        let dis = [Flag::parse("DIS=1").unwrap()];
        let en = [Flag::parse("EN=yes").unwrap()];
        let p = able_postings(Able::Disable, "contact=Bob", &able, &dis, &en).unwrap();
        let vars: Vec<&str> = p.iter().map(|p| p.var.as_str()).collect();
        assert_eq!(vars, ["BHV_ABLE_FILTER", "ABLE", "DIS"]);
        assert_eq!(p[1].val.as_str(), Some("Bob"));
        let p = able_postings(Able::Enable, "bob", &able, &dis, &en).unwrap();
        assert_eq!(p[2].var, "EN");
        assert!(able_postings(Able::Enable, "  ", &[], &[], &[]).is_err());
        assert!(able_postings(Able::Enable, "group=x", &[], &[], &[]).is_err());
    }
}
