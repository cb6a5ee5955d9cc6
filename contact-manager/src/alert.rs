//! Alerts (contacts-appcast.md §4.3): the `alert = ...` configuration lines and the
//! `BCM_ALERT_REQUEST` mail, same syntax — a comma list (quote- and brace-aware) of
//! `key=value`; lines and requests with one id merge into one alert.

use contacts::{ContactFilter, FilterError};

/// Most alert ids held (a guard against hostile requests; missions use one to three).
pub const MAX_ALERTS: usize = 100;
/// Most on- or off-flags one alert holds.
pub const MAX_FLAGS: usize = 32;

/// An alert line or request that was refused (nothing of it is applied).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AlertSpecError {
    #[error("not key=value: {0}")]
    NotAPair(String),
    /// The reference's configuration warning text.
    #[error("unhandled alert config component: {0}")]
    Unhandled(String),
    #[error("bad flag (want VAR=VALUE): {0}")]
    BadFlag(String),
    #[error("{key} must be a number >= 0: {value}")]
    BadRange { key: String, value: String },
    #[error("action must be disable or enable: {0}")]
    BadAction(String),
    #[error("{0}")]
    Filter(#[from] FilterError),
    #[error("too many alerts (at most {MAX_ALERTS})")]
    TooManyAlerts,
    #[error("too many flags in alert {0} (at most {MAX_FLAGS})")]
    TooManyFlags(String),
}

/// A `VAR=VALUE` flag; the value may hold macros (`$[VNAME]`, ...).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Flag {
    pub var: String,
    pub val: String,
}

impl Flag {
    /// `VAR=VALUE` split at the first `=`, both trimmed, one pair of quotes removed from
    /// the value; the variable must be non-empty and without blanks.
    ///
    /// ```
    /// let f = contact_manager::Flag::parse("CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]").unwrap();
    /// assert_eq!((f.var.as_str(), f.val.as_str()), ("CONTACT_INFO", "name=$[VNAME] # contact=$[VNAME]"));
    /// ```
    pub fn parse(s: &str) -> Option<Flag> {
        let (var, val) = s.split_once('=')?;
        let var = var.trim();
        if var.is_empty() || var.contains(char::is_whitespace) {
            return None;
        }
        Some(Flag {
            var: var.to_string(),
            val: mbutil::strip_quotes(val.trim()).to_string(),
        })
    }
}

/// One alert: its flags, ranges and filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Alert {
    pub id: String,
    pub on_flags: Vec<Flag>,
    pub off_flags: Vec<Flag>,
    /// Inner range; V20 alerts have no default, and one without it never fires.
    pub alert_range: Option<f64>,
    /// Outer range (kept >= alert_range); unset means the alert range.
    pub cpa_range: Option<f64>,
    pub filter: ContactFilter,
    /// `action=disable` switches the id off, `action=enable` back on.
    pub enabled: bool,
}

impl Alert {
    fn new(id: &str) -> Alert {
        Alert {
            id: id.to_string(),
            on_flags: Vec::new(),
            off_flags: Vec::new(),
            alert_range: None,
            cpa_range: None,
            filter: ContactFilter::default(),
            enabled: true,
        }
    }

    /// Valid (V20): a range set and an on- or off-flag.
    pub fn valid(&self) -> bool {
        self.alert_range.is_some() && !(self.on_flags.is_empty() && self.off_flags.is_empty())
    }

    /// The outer range in effect.
    pub fn cpa_range(&self) -> f64 {
        self.cpa_range.or(self.alert_range).unwrap_or(0.0)
    }

    fn set_alert_range(&mut self, r: f64) {
        self.alert_range = Some(r);
        if self.cpa_range.is_some_and(|c| c < r) {
            self.cpa_range = Some(r);
        }
    }

    fn set_cpa_range(&mut self, r: f64) {
        self.cpa_range = Some(r);
        if self.alert_range.is_some_and(|a| a > r) {
            self.alert_range = Some(r);
        }
    }

    fn add_flag(&mut self, on: bool, f: Flag) -> Result<(), AlertSpecError> {
        let list = if on {
            &mut self.on_flags
        } else {
            &mut self.off_flags
        };
        // V20 ignores an exact duplicate.
        if list.contains(&f) {
            return Ok(());
        }
        if list.len() >= MAX_FLAGS {
            return Err(AlertSpecError::TooManyFlags(self.id.clone()));
        }
        list.push(f);
        Ok(())
    }
}

/// Split at `sep` outside double quotes and outside `{...}`.
pub(crate) fn split_fields(s: &str, sep: char) -> Vec<&str> {
    let (mut quote, mut depth, mut start) = (false, 0usize, 0);
    let mut out = Vec::new();
    for (i, c) in s.char_indices() {
        match c {
            '"' => quote = !quote,
            '{' if !quote => depth += 1,
            '}' if !quote => depth = depth.saturating_sub(1),
            c if c == sep && !quote && depth == 0 => {
                out.push(&s[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

fn range_value(key: &str, v: &str) -> Result<f64, AlertSpecError> {
    mbutil::parse_number(v)
        .filter(|r| *r >= 0.0 && r.is_finite())
        .ok_or_else(|| AlertSpecError::BadRange {
            key: key.to_string(),
            value: v.to_string(),
        })
}

/// The alerts by id, in order of first appearance.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AlertSet {
    alerts: Vec<Alert>,
}

impl AlertSet {
    pub fn alerts(&self) -> &[Alert] {
        &self.alerts
    }

    pub fn get(&self, id: &str) -> Option<&Alert> {
        self.alerts.iter().find(|a| a.id == id)
    }

    pub fn len(&self) -> usize {
        self.alerts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.alerts.is_empty()
    }

    /// The largest outer range of the valid, enabled alerts (the radius drawn).
    pub fn max_cpa_range(&self) -> f64 {
        self.alerts
            .iter()
            .filter(|a| a.valid() && a.enabled)
            .map(Alert::cpa_range)
            .fold(0.0, f64::max)
    }

    /// Apply one `alert = ...` line or `BCM_ALERT_REQUEST`; all or nothing. Returns the
    /// alert's id (`no_id` when none was given).
    ///
    /// ```
    /// let mut set = contact_manager::AlertSet::default();
    /// let id = set.apply("id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=75").unwrap();
    /// let a = set.get(&id).unwrap();
    /// assert_eq!((a.alert_range, a.cpa_range()), (Some(50.0), 75.0));
    /// assert!(set.apply("id=x, colour=red").is_err());
    /// ```
    pub fn apply(&mut self, spec: &str) -> Result<String, AlertSpecError> {
        let mut fields = Vec::new();
        let mut id = None;
        for field in split_fields(spec, ',') {
            if field.trim().is_empty() {
                continue;
            }
            let (k, v) = field
                .split_once('=')
                .ok_or_else(|| AlertSpecError::NotAPair(field.trim().to_string()))?;
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            if k == "id" {
                id = Some(mbutil::strip_quotes(v).to_string());
            } else {
                fields.push((k, v));
            }
        }
        let id = match id {
            Some(i) if !i.is_empty() => i,
            _ => "no_id".to_string(),
        };
        let pos = self.alerts.iter().position(|a| a.id == id);
        if pos.is_none() && self.alerts.len() >= MAX_ALERTS {
            return Err(AlertSpecError::TooManyAlerts);
        }
        let mut a = match pos {
            Some(i) => self.alerts[i].clone(),
            None => Alert::new(&id),
        };
        let (mut var, mut val) = (None, None);
        for (k, v) in fields {
            match k.as_str() {
                "on_flag" | "onflag" => {
                    let f = Flag::parse(v).ok_or_else(|| AlertSpecError::BadFlag(v.into()))?;
                    a.add_flag(true, f)?;
                }
                "off_flag" | "offflag" => {
                    for part in v.split('#') {
                        let f = Flag::parse(part)
                            .ok_or_else(|| AlertSpecError::BadFlag(part.trim().into()))?;
                        a.add_flag(false, f)?;
                    }
                }
                "var" => var = Some(v),
                "val" | "pattern" => val = Some(mbutil::strip_quotes(v)),
                "alert_range" => a.set_alert_range(range_value(&k, v)?),
                "cpa_range" => a.set_cpa_range(range_value(&k, v)?),
                "action" => match v.to_ascii_lowercase().as_str() {
                    "disable" => a.enabled = false,
                    "enable" => a.enabled = true,
                    _ => return Err(AlertSpecError::BadAction(v.into())),
                },
                "match_name" | "ignore_name" | "match_group" | "ignore_group" | "match_type"
                | "ignore_type" | "match_region" | "ignore_region" | "strict_ignore" => {
                    a.filter.set_param(&k, v)?;
                }
                _ => return Err(AlertSpecError::Unhandled(k)),
            }
        }
        // Legacy: var + val together are one on-flag.
        match (var, val) {
            (Some(var), Some(val)) => {
                let f = Flag::parse(&format!("{var}={val}"))
                    .ok_or_else(|| AlertSpecError::BadFlag(format!("var={var}")))?;
                a.add_flag(true, f)?;
            }
            (Some(_), None) => return Err(AlertSpecError::BadFlag("var without val".into())),
            (None, Some(_)) => return Err(AlertSpecError::BadFlag("val without var".into())),
            (None, None) => {}
        }
        match pos {
            Some(i) => self.alerts[i] = a,
            None => self.alerts.push(a),
        }
        Ok(id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_with_one_id_merge() {
        let mut s = AlertSet::default();
        s.apply("id=say, on_flag=SAY_MOOS=hello").unwrap();
        s.apply("id=say, off_flag=SAY_MOOS=bye").unwrap();
        assert!(!s.get("say").unwrap().valid(), "no range yet");
        s.apply("id=say, alert_range=80, cpa_range=100").unwrap();
        let a = s.get("say").unwrap();
        assert!(a.valid());
        assert_eq!(a.on_flags.len(), 1);
        assert_eq!(a.off_flags[0].val, "bye");
        assert_eq!(s.len(), 1);
        // An exact duplicate on-flag is ignored.
        s.apply("id=say, on_flag=SAY_MOOS=hello").unwrap();
        assert_eq!(s.get("say").unwrap().on_flags.len(), 1);
    }

    #[test]
    fn ranges_keep_their_order() {
        let mut s = AlertSet::default();
        s.apply("id=a, alert_range=50, cpa_range=40").unwrap();
        let a = s.get("a").unwrap();
        assert_eq!((a.alert_range, a.cpa_range), (Some(40.0), Some(40.0)));
        s.apply("id=a, alert_range=60").unwrap();
        let a = s.get("a").unwrap();
        assert_eq!((a.alert_range, a.cpa_range), (Some(60.0), Some(60.0)));
        assert!(matches!(
            s.apply("id=a, alert_range=-1"),
            Err(AlertSpecError::BadRange { .. })
        ));
    }

    #[test]
    fn legacy_var_val_quoted_and_no_id() {
        let mut s = AlertSet::default();
        let id = s
            .apply(r#"var=CONTACT_INFO, val="name=$[VNAME] # contact=$[VNAME]", alert_range=40"#)
            .unwrap();
        assert_eq!(id, "no_id");
        let f = &s.get("no_id").unwrap().on_flags[0];
        assert_eq!(f.var, "CONTACT_INFO");
        assert_eq!(f.val, "name=$[VNAME] # contact=$[VNAME]");
    }

    #[test]
    fn off_flags_split_at_hash_and_actions() {
        let mut s = AlertSet::default();
        s.apply("id=z, off_flag=A=1 # B=two, alert_range=5")
            .unwrap();
        let a = s.get("z").unwrap();
        assert_eq!(a.off_flags.len(), 2);
        assert_eq!(a.off_flags[1].var, "B");
        s.apply("id=z, action=disable").unwrap();
        assert!(!s.get("z").unwrap().enabled);
        s.apply("id=z,action=enable").unwrap();
        assert!(s.get("z").unwrap().enabled);
        assert!(s.apply("id=z,action=maybe").is_err());
    }

    #[test]
    fn refused_requests_change_nothing() {
        let mut s = AlertSet::default();
        s.apply("id=q, on_flag=X=1, alert_range=5").unwrap();
        let before = s.clone();
        assert_eq!(
            s.apply("id=q, alert_range=9, bogus=3"),
            Err(AlertSpecError::Unhandled("bogus".into()))
        );
        assert!(s.apply("id=q, on_flag=novalue").is_err());
        assert!(s.apply("id=q, alert_range").is_err());
        assert_eq!(s, before);
    }

    #[test]
    fn filters_and_regions_with_commas() {
        let mut s = AlertSet::default();
        s.apply("id=f, on_flag=X=1, alert_range=5, match_type=kayak, ignore_region=pts={0,0:10,0:10,10:0,10}")
            .unwrap();
        let f = &s.get("f").unwrap().filter;
        assert!(f.check("b", "", "kayak", 20.0, 20.0).all());
        assert!(!f.check("b", "", "kayak", 5.0, 5.0).all());
        assert!(!f.check("b", "", "ship", 20.0, 20.0).all());
    }

    #[test]
    fn the_number_of_alerts_is_capped() {
        let mut s = AlertSet::default();
        for i in 0..MAX_ALERTS {
            s.apply(&format!("id=a{i}, alert_range=1")).unwrap();
        }
        assert_eq!(s.apply("id=one_more"), Err(AlertSpecError::TooManyAlerts));
        assert!(s.apply("id=a3, cpa_range=4").is_ok());
    }
}
