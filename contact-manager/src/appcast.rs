//! A minimal AppCasting (contacts-appcast.md §5) for the `contactmgr` app, pure: the
//! `APPCAST_REQ` table, when an appcast is pending, the serialized `APPCAST` value and
//! the manager's report body. (The helm's AppCasting lives in `helm-app`, which would
//! bring the whole helm engine with it; this is the small part an app needs.)

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::manager::ContactManager;
use crate::warnings::Warnings;

/// Variables the AppCasting base consumes itself.
pub const BASE_VARS: [&str; 4] = [
    "APPCAST_REQ",
    "LOADCAST_REQ",
    "TERM_REPORT_INTERVAL",
    "COMMS_POLICY",
];

#[derive(Clone, Debug, PartialEq)]
struct Request {
    start: f64,
    duration: f64,
    run_warning_only: bool,
}

/// The remembered `APPCAST_REQ`s (one per key) and the posting rule.
#[derive(Clone, Debug)]
pub struct Caster {
    requests: HashMap<String, Request>,
    interval: f64,
    warp: f64,
    last_cast: Option<f64>,
    casts: u64,
}

/// Most request keys remembered (hostile senders cannot grow the table).
const MAX_KEYS: usize = 256;

impl Caster {
    pub fn new(warp: f64) -> Caster {
        Caster {
            requests: HashMap::new(),
            interval: 0.5,
            warp: if warp > 0.0 { warp } else { 1.0 },
            last_cast: None,
            casts: 0,
        }
    }

    /// Take one base variable's mail; false when `var` is not one of [`BASE_VARS`].
    pub fn handle(&mut self, var: &str, value: &str, community: &str, app: &str, now: f64) -> bool {
        match var {
            "APPCAST_REQ" => {
                self.request(value, community, app, now);
                true
            }
            "TERM_REPORT_INTERVAL" => {
                if let Some(v) = mbutil::parse_number(value).filter(|v| v.is_finite()) {
                    self.interval = v.max(0.4);
                }
                true
            }
            "LOADCAST_REQ" | "COMMS_POLICY" => true,
            _ => false,
        }
    }

    fn request(&mut self, value: &str, community: &str, app: &str, now: f64) {
        let (mut node, mut req_app, mut key) = ("", "", None);
        let (mut duration, mut run_warning_only) = (0.0, false);
        for part in value.split(',') {
            let Some((k, v)) = part.split_once('=') else {
                continue;
            };
            let v = v.trim();
            match k.trim().to_ascii_lowercase().as_str() {
                "node" => node = v,
                "app" => req_app = v,
                "key" => key = Some(v),
                "duration" => duration = mbutil::parse_number(v).unwrap_or(0.0).clamp(0.0, 30.0),
                "thresh" => run_warning_only = v.eq_ignore_ascii_case("run_warning"),
                _ => {}
            }
        }
        let Some(key) = key else { return };
        if (node != "all" && node != community) || (req_app != "all" && req_app != app) {
            return;
        }
        if !self.requests.contains_key(key) && self.requests.len() >= MAX_KEYS {
            return;
        }
        self.requests.insert(
            key.to_string(),
            Request {
                start: now,
                duration,
                run_warning_only,
            },
        );
    }

    /// After an iteration at MOOS time `now` (`iteration` counted from 1): whether an
    /// `APPCAST` is due now (§5.2, without terminal reporting).
    pub fn due(&mut self, now: f64, iteration: u64, w: &Warnings) -> bool {
        if let Some(t) = self.last_cast {
            if (now - t) / self.warp < self.interval {
                return false;
            }
        }
        let wanted = self
            .requests
            .values()
            .any(|r| now - r.start < r.duration && (!r.run_warning_only || w.new_run()));
        let pending = wanted || w.new_config() || iteration < 2;
        if pending {
            self.last_cast = Some(now);
            self.casts += 1;
        }
        pending
    }

    pub fn casts(&self) -> u64 {
        self.casts
    }
}

/// The `APPCAST` value (§5.3).
pub fn serialize(app: &str, community: &str, iteration: u64, body: &str, w: &Warnings) -> String {
    let mut s = format!("proc={app}!@#iter={iteration}!@#");
    if !community.is_empty() {
        let _ = write!(s, "node={community}!@#");
    }
    let _ = write!(s, "iter={iteration}!@#messages=");
    for line in body.split('\n') {
        // A body line starting with `#` would be mis-split by receivers.
        s.push_str(line.strip_prefix('#').unwrap_or(line));
        s.push_str("!@");
    }
    s.push_str("!@#");
    if !w.config_warnings().is_empty() {
        let _ = write!(s, "config_warnings={}", w.config_warnings().join("!@"));
    }
    let events: Vec<&str> = w.events().collect();
    let _ = write!(s, "!@#events_total={}!@#", events.len());
    if !events.is_empty() {
        let _ = write!(s, "events={}", events.join("!@"));
    }
    let _ = write!(s, "!@#run_warning_total={}!@#", w.run_total());
    let runs: Vec<String> = w.run_warnings().map(|(t, n)| format!("{n}:{t}")).collect();
    if !runs.is_empty() {
        let _ = write!(s, "run_warnings={}", runs.join("!@"));
    }
    s
}

/// The manager's report body: ownship, alerts, contacts with range, age and alerts.
pub fn body(m: &ContactManager, now: f64) -> String {
    let mut s = String::new();
    let os = m.ownship();
    let (reqs, reps) = m.received();
    let _ = writeln!(
        s,
        "Ownship: {} x={:.1} y={:.1} hdg={:.1} spd={:.2}",
        m.ownship_name(),
        os.x,
        os.y,
        os.hdg,
        os.spd
    );
    let _ = writeln!(
        s,
        "Node reports: {reps}   Alert requests: {reqs}   Helm in DRIVE: {}",
        m.helm_drive_seen()
    );
    let _ = writeln!(s, "\nAlerts: {}", m.alerts().len());
    for a in m.alerts().alerts() {
        let _ = writeln!(
            s,
            "  id={} alert_range={} cpa_range={} on_flags={} off_flags={}{}{}",
            a.id,
            a.alert_range
                .map_or("unset".to_string(), |r| mbutil::compact(r, 1)),
            mbutil::compact(a.cpa_range(), 1),
            a.on_flags.len(),
            a.off_flags.len(),
            if a.valid() { "" } else { " (invalid)" },
            if a.enabled { "" } else { " (disabled)" },
        );
    }
    let _ = writeln!(s, "\nContacts: {}", m.table().len());
    let _ = writeln!(s, "  Contact  Range  CPA  Age  Alerted");
    for c in m.table().contacts() {
        let g = m.geometry(c, now);
        let ids: Vec<&str> = m
            .alerted()
            .filter(|(n, _)| *n == c.name)
            .map(|(_, i)| i)
            .collect();
        let _ = writeln!(
            s,
            "  {}  {:.1}  {:.1}  {:.1}  {}",
            c.name,
            g.range,
            g.cpa,
            g.age,
            ids.join(",")
        );
    }
    let retired: Vec<&str> = m.retired().iter().map(String::as_str).collect();
    let _ = write!(s, "\nRetired: {}", retired.join(","));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_and_the_posting_rule() {
        let mut c = Caster::new(2.0);
        let w = Warnings::default();
        // The first iteration always casts.
        assert!(c.due(0.0, 1, &w));
        assert!(!c.due(2.0, 2, &w), "no request");
        assert!(c.handle(
            "APPCAST_REQ",
            "node=other,app=all,duration=3,key=k",
            "alpha",
            "pContactMgrV20",
            2.0
        ));
        assert!(!c.due(3.0, 3, &w), "not our node");
        c.handle(
            "APPCAST_REQ",
            "node=all,app=pContactMgrV20,duration=3,key=uMAC",
            "alpha",
            "pContactMgrV20",
            3.0,
        );
        assert!(c.due(3.5, 4, &w));
        // Within 0.5 real s (1 MOOS s at warp 2): not again.
        assert!(!c.due(4.0, 5, &w));
        assert!(c.due(4.5, 6, &w));
        assert!(!c.due(7.0, 7, &w), "expired");
        assert!(!c.handle("NAV_X", "1", "alpha", "p", 0.0));
    }

    #[test]
    fn serialized_form() {
        let mut w = Warnings::default();
        let s = serialize("pContactMgrV20", "alpha", 1, "a\nb", &w);
        assert_eq!(
            s,
            "proc=pContactMgrV20!@#iter=1!@#node=alpha!@#iter=1!@#messages=a!@b!@!@#!@#events_total=0!@#!@#run_warning_total=0!@#"
        );
        w.run_warning("x");
        w.run_warning("x");
        w.config_warning("c1");
        let s = serialize("p", "", 2, "", &w);
        assert!(s.ends_with("run_warning_total=2!@#run_warnings=2:x"), "{s}");
        assert!(s.contains("!@#config_warnings=c1!@#"), "{s}");
        assert!(!s.contains("node="));
    }
}
