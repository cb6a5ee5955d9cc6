//! What `helm run` remembers of the traffic for its terminal lines and its stop rule.

use helm_engine::posting::{Posting, Value};
use helm_engine::Mail;

/// How long (MOOS s) the all-stop must stay non-clear before the mission counts as over.
pub const MISSION_OVER_AFTER: f64 = 5.0;

/// The "mission is over" rule of `helm run --embedded`.
///
/// Some missions post `IVPHELM_ALLSTOP=NothingToDo` before their first decision (the
/// behaviors are not active yet), so a non-clear all-stop alone means nothing. The rule:
/// after the helm has posted `IVPHELM_ALLSTOP=clear` at least once (it decided
/// something), the all-stop has been non-clear (`NothingToDo`, `ManualOverride`, ...)
/// for [`MISSION_OVER_AFTER`] seconds of MOOS time without going back to `clear`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EndWatch {
    seen_clear: bool,
    nonclear_since: Option<f64>,
}

impl EndWatch {
    /// The helm posted `IVPHELM_ALLSTOP = value` at `now`.
    pub fn on_allstop(&mut self, value: &str, now: f64) {
        if value.eq_ignore_ascii_case("clear") {
            self.seen_clear = true;
            self.nonclear_since = None;
        } else if self.nonclear_since.is_none() {
            self.nonclear_since = Some(now);
        }
    }

    pub fn is_over(&self, now: f64) -> bool {
        self.seen_clear
            && self
                .nonclear_since
                .is_some_and(|t| now - t >= MISSION_OVER_AFTER)
    }
}

/// Last known values of the variables the terminal shows.
#[derive(Clone, Debug, Default)]
pub struct Status {
    pub desired_heading: Option<f64>,
    pub desired_speed: Option<f64>,
    /// `IVPHELM_BHV_ACTIVE` (comma list of behavior names).
    pub active: String,
    pub allstop: String,
    pub nav: [Option<f64>; 4],
    /// Number of `DESIRED_*` postings.
    pub desired_posts: u64,
    pub iterations: u64,
    pub end: EndWatch,
}

const NAV: [&str; 4] = ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"];

fn num(v: &Value) -> Option<f64> {
    match v {
        Value::Num(n) => Some(*n),
        Value::Str(s) => s.trim().parse().ok(),
    }
}

fn show(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "-".to_string(), |v| format!("{v:.decimals$}"))
}

impl Status {
    pub fn on_posting(&mut self, p: &Posting, now: f64) {
        if p.var.starts_with("DESIRED_") {
            self.desired_posts += 1;
        }
        match (p.var.as_str(), &p.value) {
            ("DESIRED_HEADING", v) => self.desired_heading = num(v),
            ("DESIRED_SPEED", v) => self.desired_speed = num(v),
            ("IVPHELM_BHV_ACTIVE", Value::Str(s)) => self.active = s.clone(),
            ("IVPHELM_ALLSTOP", Value::Str(s)) => {
                self.allstop = s.clone();
                self.end.on_allstop(s, now);
            }
            _ => {}
        }
    }

    pub fn on_mail(&mut self, m: &Mail) {
        if let Some(i) = NAV.iter().position(|v| *v == m.var) {
            self.nav[i] = num(&m.value);
        }
    }

    /// One line: `t=  12.0s DRIVE  hdg=… spd=…  x=… y=…  active=…  allstop=…`.
    pub fn summary(&self, elapsed: f64, state: &str) -> String {
        let active = if self.active.is_empty() {
            "-"
        } else {
            &self.active
        };
        let allstop = if self.allstop.is_empty() {
            "-"
        } else {
            &self.allstop
        };
        format!(
            "t={elapsed:7.1}s {state:<9} desired hdg={} spd={}  nav x={} y={} hdg={} spd={}  active={active}  allstop={allstop}",
            show(self.desired_heading, 0),
            show(self.desired_speed, 2),
            show(self.nav[0], 1),
            show(self.nav[1], 1),
            show(self.nav[2], 0),
            show(self.nav[3], 2),
        )
    }

    /// The last line of a run, for people and scripts (`key=value` words).
    pub fn final_line(&self, reason: &str, elapsed: f64, state: &str) -> String {
        format!(
            "final: reason={reason} time={elapsed:.1} state={state} iterations={} x={} y={} heading={} speed={} allstop={} desired_posts={}",
            self.iterations,
            show(self.nav[0], 2),
            show(self.nav[1], 2),
            show(self.nav[2], 1),
            show(self.nav[3], 2),
            if self.allstop.is_empty() { "-" } else { &self.allstop },
            self.desired_posts,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_to_do_before_first_decision_is_not_the_end() {
        let mut w = EndWatch::default();
        w.on_allstop("NothingToDo", 0.0);
        assert!(!w.is_over(100.0));
        w.on_allstop("clear", 101.0);
        assert!(!w.is_over(200.0));
        w.on_allstop("NothingToDo", 200.0);
        w.on_allstop("IncompleteOrEmptyDecision", 200.25);
        assert!(!w.is_over(204.9));
        assert!(w.is_over(205.0));
        w.on_allstop("clear", 206.0);
        assert!(!w.is_over(300.0));
    }

    #[test]
    fn final_line_has_key_values() {
        let mut s = Status::default();
        s.on_posting(
            &Posting {
                var: "DESIRED_SPEED".into(),
                value: Value::Num(2.0),
                source_aux: String::new(),
            },
            1.0,
        );
        s.on_mail(&Mail {
            var: "NAV_X".into(),
            value: Value::Num(3.0),
            time: 1.0,
            source: "uSimMarine".into(),
            source_aux: String::new(),
        });
        let l = s.final_line("duration", 10.0, "DRIVE");
        assert!(l.contains("x=3.00 y=- "), "{l}");
        assert!(l.contains("desired_posts=1"), "{l}");
        assert!(l.contains("state=DRIVE"), "{l}");
    }
}
