//! AppCasting (appcast.md, contacts-appcast.md §5): how a MOOS-IvP app shows its status
//! to uMAC and pMarineViewer.
//!
//! - [`Requests`] keeps the `APPCAST_REQ` requests (one per client key) and tells when
//!   a report is pending;
//! - [`AppCast`] is one report: the app's body plus its configuration warnings, events
//!   and run warnings; [`AppCast::serialize`] is the `APPCAST` value,
//!   [`AppCast::terminal`] the form printed on the terminal;
//! - [`Warnings`] (the engine's) counts run warnings (with retraction) and keeps the
//!   last events;
//! - [`Caster`] is the per-iteration rule of §5.2: when to print, when to post.
//!
//! Nothing here knows the helm: the helm's body is built by the engine
//! (`Helm::appcast_body`).

use std::collections::HashMap;

pub use helm_engine::run_warnings::{Warnings, MAX_EVENTS, MAX_RUN_WARNINGS};

/// Variables the AppCasting base registers for and consumes itself.
pub const BASE_VARS: [&str; 4] = [
    "APPCAST_REQ",
    "LOADCAST_REQ",
    "TERM_REPORT_INTERVAL",
    "COMMS_POLICY",
];

/// One remembered `APPCAST_REQ`.
#[derive(Clone, Debug, PartialEq)]
struct Request {
    start: f64,
    duration: f64,
    /// `thresh=run_warning`: only when a new run warning arrived.
    run_warning_only: bool,
}

/// The appcast requests of every client, by key.
#[derive(Clone, Debug, Default)]
pub struct Requests {
    by_key: HashMap<String, Request>,
}

impl Requests {
    /// Take one `APPCAST_REQ` value (`node=..,app=..,duration=..,key=..,thresh=..`).
    /// Returns false when it is not for this app (node or app differ, or no key).
    pub fn handle(&mut self, value: &str, community: &str, app: &str, now: f64) -> bool {
        let (mut node, mut req_app, mut key) = (None, None, None);
        let (mut duration, mut run_warning_only) = (0.0, false);
        for part in value.split(',') {
            let Some((k, v)) = part.split_once('=') else {
                continue;
            };
            let v = v.trim();
            match k.trim().to_ascii_lowercase().as_str() {
                "node" => node = Some(v.to_string()),
                "app" => req_app = Some(v.to_string()),
                "key" => key = Some(v.to_string()),
                "duration" => {
                    duration = v
                        .parse::<f64>()
                        .ok()
                        .filter(|d| d.is_finite())
                        .unwrap_or(0.0)
                }
                "thresh" => run_warning_only = v.eq_ignore_ascii_case("run_warning"),
                _ => {}
            }
        }
        let node_ok = node
            .as_deref()
            .is_some_and(|n| n == community || n == "all");
        let app_ok = req_app.as_deref().is_some_and(|a| a == app || a == "all");
        let Some(key) = key.filter(|k| !k.is_empty()) else {
            return false;
        };
        if !node_ok || !app_ok {
            return false;
        }
        self.by_key.insert(
            key,
            Request {
                start: now,
                duration: duration.clamp(0.0, 30.0),
                run_warning_only,
            },
        );
        true
    }

    /// Whether some request asks for a report now.
    pub fn wanted(&self, now: f64, new_run_warning: bool) -> bool {
        self.by_key
            .values()
            .any(|r| now - r.start < r.duration && (!r.run_warning_only || new_run_warning))
    }
}

/// One report.
#[derive(Clone, Debug)]
pub struct AppCast<'a> {
    pub proc_name: &'a str,
    pub community: &'a str,
    /// The app's iteration count (every Iterate call).
    pub iteration: u64,
    pub body: &'a str,
    pub config_warnings: &'a [String],
    pub warnings: &'a Warnings,
}

const OUTER: &str = "!@#";
const INNER: &str = "!@";

impl AppCast<'_> {
    /// The `APPCAST` value (§5.3).
    pub fn serialize(&self) -> String {
        let mut s = format!(
            "proc={}{OUTER}iter={}{OUTER}",
            self.proc_name, self.iteration
        );
        if !self.community.is_empty() {
            s.push_str(&format!("node={}{OUTER}", self.community));
        }
        s.push_str(&format!("iter={}{OUTER}messages=", self.iteration));
        for line in self.body.split('\n') {
            s.push_str(line);
            s.push_str(INNER);
        }
        s.push_str(OUTER);
        if !self.config_warnings.is_empty() {
            s.push_str("config_warnings=");
            s.push_str(&self.config_warnings.join(INNER));
        }
        s.push_str(OUTER);
        s.push_str(&format!(
            "events_total={}{OUTER}",
            self.warnings.events_total()
        ));
        if !self.warnings.events().is_empty() {
            s.push_str("events=");
            let ev: Vec<&str> = self.warnings.events().iter().map(String::as_str).collect();
            s.push_str(&ev.join(INNER));
        }
        s.push_str(OUTER);
        s.push_str(&format!(
            "run_warning_total={}{OUTER}",
            self.warnings.run_total()
        ));
        let runs = self.warnings.run_entries();
        if !runs.is_empty() {
            s.push_str("run_warnings=");
            s.push_str(&runs.join(INNER));
        }
        s
    }

    /// The terminal form (§5.5), without the newlines printed before it.
    pub fn terminal(&self) -> String {
        let rule = "=".repeat(62);
        let counts = format!(
            "{}/{}({})",
            self.config_warnings.len(),
            self.warnings.run_total(),
            self.iteration
        );
        let title = format!("{} {}", self.proc_name, self.community);
        let pad = 62usize.saturating_sub(title.chars().count() + counts.len());
        let mut s = format!("{rule}\n{title}{}{counts}\n{rule}\n", " ".repeat(pad));
        let n = self.config_warnings.len();
        if n > 0 {
            s.push_str(&format!("Configuration Warnings: {n}\n"));
            for (i, w) in self.config_warnings.iter().enumerate() {
                s.push_str(&format!(" [{} of {n}]: {w}\n", i + 1));
            }
            s.push('\n');
        }
        if self.warnings.run_total() > 0 {
            s.push_str(&format!(
                "Runtime Warnings: {}\n",
                self.warnings.run_total()
            ));
            for (t, c) in self.warnings.run() {
                s.push_str(&format!(" [{c}]: {t}\n"));
            }
            s.push('\n');
        }
        s.push_str(self.body);
        if !self.warnings.events().is_empty() {
            let rule = "=".repeat(67);
            s.push_str(&format!(
                "\n{rule}\nMost Recent Events ({}):\n{rule}\n",
                self.warnings.events().len()
            ));
            for e in self.warnings.events().iter().rev() {
                s.push_str(e);
                s.push('\n');
            }
        }
        s
    }
}

/// What the per-iteration rule decided.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Due {
    pub print: bool,
    pub post: bool,
}

/// The AppCasting base's per-iteration state (§5.2).
#[derive(Clone, Debug)]
pub struct Caster {
    pub requests: Requests,
    /// Report to the terminal (verbose mode on a terminal, or `TERM_REPORTING=true`).
    pub term_reporting: bool,
    /// Minimum real seconds between reports (`TERM_REPORT_INTERVAL`, at least 0.4).
    pub interval: f64,
    pub time_warp: f64,
    /// Iterate calls so far.
    pub iteration: u64,
    /// A configuration warning arrived since the last appcast.
    pub new_config_warning: bool,
    last_term: f64,
    last_cast: f64,
    /// `COMMS_POLICY` in force: open, lean or dire.
    pub comms_policy: &'static str,
    /// The configured policy: mail may make it stricter, never looser.
    pub configured_policy: &'static str,
}

const POLICIES: [&str; 3] = ["open", "lean", "dire"];

impl Caster {
    pub fn new(time_warp: f64, term_reporting: bool) -> Caster {
        Caster {
            requests: Requests::default(),
            term_reporting,
            interval: 0.5,
            time_warp,
            iteration: 0,
            new_config_warning: false,
            last_term: f64::NEG_INFINITY,
            last_cast: f64::NEG_INFINITY,
            comms_policy: "open",
            configured_policy: "open",
        }
    }

    /// Mail on one of [`BASE_VARS`] (the app never sees it). `LOADCAST_REQ` is
    /// accepted and not acted on.
    pub fn handle_mail(
        &mut self,
        w: &mut Warnings,
        var: &str,
        value: &str,
        ids: (&str, &str),
        now: f64,
    ) {
        let (community, app) = ids;
        match var {
            "APPCAST_REQ" => {
                self.requests.handle(value, community, app, now);
            }
            "TERM_REPORT_INTERVAL" => {
                if let Ok(v) = value.trim().parse::<f64>() {
                    self.interval = v.max(0.4);
                }
            }
            "COMMS_POLICY" => {
                let v = value.trim().to_ascii_lowercase();
                let rank = |p: &str| POLICIES.iter().position(|x| *x == p);
                match (rank(&v), rank(self.configured_policy)) {
                    (Some(new), Some(conf)) if new >= conf => self.comms_policy = POLICIES[new],
                    // `open` under a stricter configuration is ignored.
                    (Some(0), _) => {}
                    _ => w.run_warning(&format!("Unhandled COMMS_POLICY:{v}")),
                }
            }
            _ => {}
        }
    }

    /// After an iteration at MOOS time `now`: count it, and say whether to print the
    /// report and whether to post `APPCAST`.
    pub fn after_iterate(&mut self, w: &mut Warnings, now: f64) -> Due {
        self.iteration += 1;
        if self.time_warp <= 0.0 {
            return Due::default();
        }
        let t_term = (now - self.last_term) / self.time_warp;
        let t_cast = (now - self.last_cast) / self.time_warp;
        if t_term < self.interval && t_cast < self.interval {
            return Due::default();
        }
        let pending = self.requests.wanted(now, w.new_run_warning)
            || self.new_config_warning
            || self.iteration < 2;
        if !self.term_reporting && !pending {
            return Due::default();
        }
        if !pending && t_term < self.interval {
            return Due::default();
        }
        if !self.term_reporting && t_cast < self.interval {
            return Due::default();
        }
        let due = Due {
            print: self.term_reporting,
            post: pending,
        };
        if due.print {
            self.last_term = now;
        }
        if due.post {
            self.last_cast = now;
            self.new_config_warning = false;
            w.new_run_warning = false;
        }
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_match_node_and_app_and_need_a_key() {
        let mut r = Requests::default();
        assert!(!r.handle(
            "node=other,app=all,duration=3,key=u",
            "alpha",
            "pHelmIvP",
            0.0
        ));
        assert!(!r.handle("node=all,app=pX,duration=3,key=u", "alpha", "pHelmIvP", 0.0));
        assert!(!r.handle("node=all,app=all,duration=3", "alpha", "pHelmIvP", 0.0));
        assert!(!r.wanted(0.5, false));
        assert!(r.handle(
            "NODE=alpha, App=pHelmIvP, duration=3.0, key=uMAC_123, thresh=any",
            "alpha",
            "pHelmIvP",
            10.0
        ));
        assert!(r.wanted(12.9, false));
        assert!(!r.wanted(13.0, false), "expired after its duration");
        // Duration clipped to 30.
        r.handle(
            "node=all,app=all,duration=100,key=k2",
            "alpha",
            "pHelmIvP",
            0.0,
        );
        assert!(r.wanted(29.9, false) && !r.wanted(30.0, false));
        // run_warning threshold: only with a new run warning.
        let mut r = Requests::default();
        r.handle(
            "node=all,app=all,duration=3,key=g,thresh=run_warning",
            "a",
            "p",
            0.0,
        );
        assert!(!r.wanted(1.0, false) && r.wanted(1.0, true));
    }

    #[test]
    fn serialized_form_has_every_section_in_order() {
        let mut w = Warnings::default();
        w.run_warning("b warning");
        w.run_warning("a warning");
        w.run_warning("a warning");
        w.event(10.284, "var=MOOS_MANUAL_OVERRIDE:matter=true, skew=0.24");
        let cw = vec!["bad line".to_string()];
        let a = AppCast {
            proc_name: "pHelmIvP",
            community: "alpha",
            iteration: 7,
            body: "  Comms Policy: open\nHelm Decision: []\n",
            config_warnings: &cw,
            warnings: &w,
        };
        assert_eq!(
            a.serialize(),
            "proc=pHelmIvP!@#iter=7!@#node=alpha!@#iter=7!@#messages=  Comms Policy: open!@\
             Helm Decision: []!@!@!@#config_warnings=bad line!@#events_total=1!@#\
             events=[10.28]: var=MOOS_MANUAL_OVERRIDE:matter=true, skew=0.24!@#\
             run_warning_total=3!@#run_warnings=2:a warning!@1:b warning"
        );
        let empty = Warnings::default();
        let a = AppCast {
            proc_name: "p",
            community: "",
            iteration: 1,
            body: "x",
            config_warnings: &[],
            warnings: &empty,
        };
        assert_eq!(
            a.serialize(),
            "proc=p!@#iter=1!@#iter=1!@#messages=x!@!@#!@#events_total=0!@#!@#run_warning_total=0!@#"
        );
    }

    #[test]
    fn retraction_removes_the_text_and_its_count() {
        let mut w = Warnings::default();
        w.run_warning("No waypts given");
        w.run_warning("other");
        w.retract("No waypts given");
        assert_eq!(w.run_total(), 1);
        assert_eq!(w.run_entries(), vec!["1:other".to_string()]);
        for i in 0..12 {
            w.event(f64::from(i), "e");
        }
        assert_eq!(w.events().len(), MAX_EVENTS);
        assert_eq!(w.events_total(), 12);
    }

    #[test]
    fn terminal_title_is_62_wide() {
        let w = Warnings::default();
        let a = AppCast {
            proc_name: "pHelmIvP",
            community: "alpha",
            iteration: 3,
            body: "body",
            config_warnings: &[],
            warnings: &w,
        };
        let t = a.terminal();
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[0].len(), 62);
        assert_eq!(lines[1].len(), 62);
        assert!(lines[1].starts_with("pHelmIvP alpha") && lines[1].ends_with("0/0(3)"));
        assert_eq!(lines[3], "body");
    }

    #[test]
    fn first_reports_are_always_posted_then_only_on_request() {
        let mut w = Warnings::default();
        let mut c = Caster::new(1.0, false);
        assert_eq!(
            c.after_iterate(&mut w, 0.0),
            Due {
                print: false,
                post: true
            }
        );
        assert_eq!(
            c.after_iterate(&mut w, 0.25),
            Due::default(),
            "within the interval"
        );
        assert_eq!(c.after_iterate(&mut w, 1.0), Due::default(), "no request");
        c.handle_mail(
            &mut w,
            "APPCAST_REQ",
            "node=all,app=all,duration=3,key=uMAC",
            ("alpha", "pHelmIvP"),
            1.0,
        );
        assert!(c.after_iterate(&mut w, 1.25).post);
        assert!(
            !c.after_iterate(&mut w, 1.5).post,
            "0.25 s after the last one"
        );
        assert!(c.after_iterate(&mut w, 1.75).post);
        assert!(!c.after_iterate(&mut w, 4.5).post, "request expired");
        // A terminal report every interval, with no request.
        let mut t = Caster::new(2.0, true);
        assert_eq!(
            t.after_iterate(&mut w, 0.0),
            Due {
                print: true,
                post: true
            }
        );
        assert_eq!(
            t.after_iterate(&mut w, 0.5),
            Due::default(),
            "0.25 real s at warp 2"
        );
        assert_eq!(
            t.after_iterate(&mut w, 1.0),
            Due {
                print: true,
                post: false
            }
        );
    }

    #[test]
    fn comms_policy_never_looser_than_configured() {
        let mut w = Warnings::default();
        let mut c = Caster::new(1.0, false);
        c.handle_mail(&mut w, "COMMS_POLICY", "lean", ("a", "p"), 0.0);
        assert_eq!(c.comms_policy, "lean");
        // Configured open: open again is allowed.
        c.handle_mail(&mut w, "COMMS_POLICY", "open", ("a", "p"), 0.0);
        assert_eq!(c.comms_policy, "open");
        c.configured_policy = "dire";
        c.handle_mail(&mut w, "COMMS_POLICY", "open", ("a", "p"), 0.0);
        assert_eq!((c.comms_policy, w.run_total()), ("open", 0), "ignored");
        c.handle_mail(&mut w, "COMMS_POLICY", "lean", ("a", "p"), 0.0);
        c.handle_mail(&mut w, "COMMS_POLICY", "loud", ("a", "p"), 0.0);
        assert_eq!(w.run_total(), 2);
    }
}
