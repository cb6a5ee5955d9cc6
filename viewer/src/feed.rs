//! One posting (variable, value, time) turned into what the page shows: a vehicle
//! sample, a shape drawn or erased, a helm variable, an appcast. Shared by the live
//! server and the `.alog` index, so both read postings the same way; whatever is
//! skipped is counted by reason.

use std::collections::{BTreeMap, BTreeSet};

use serde::Serialize;

use crate::node::{read_node_report, NavVehicle, NodeError, VehicleState};
use crate::view::{read_view, ViewChange, ViewError, VIEW_VARS};

/// The helm's own variables shown in the side panel, besides every `DESIRED_*`.
pub const HELM_VARS: [&str; 6] = [
    "IVPHELM_STATE",
    "IVPHELM_ALLSTOP",
    "DEPLOY",
    "RETURN",
    "MOOS_MANUAL_OVERRIDE",
    "IVPHELM_SUMMARY",
];

/// Every variable a live viewer subscribes to (plus `DESIRED_*` by wildcard and the
/// mission's button variables).
pub fn subscriptions() -> Vec<&'static str> {
    let mut v = vec![
        "NODE_REPORT",
        "NODE_REPORT_LOCAL",
        "APPCAST",
        "NAV_X",
        "NAV_Y",
        "NAV_HEADING",
        "NAV_SPEED",
    ];
    v.extend(VIEW_VARS);
    v.extend(HELM_VARS);
    v
}

/// A posting's value.
#[derive(Clone, Copy, Debug)]
pub enum Value<'a> {
    Num(f64),
    Str(&'a str),
}

impl Value<'_> {
    /// The value as the page shows it (numbers compact, as MOOS-IvP prints them).
    pub fn text(&self) -> String {
        match self {
            Value::Num(v) => mbutil::compact(*v, 6),
            Value::Str(s) => (*s).to_owned(),
        }
    }
}

/// What one posting changes.
#[derive(Clone, Debug, PartialEq)]
pub enum Update {
    Vehicle(VehicleState),
    View(ViewChange),
    /// A helm variable's new value.
    Var(String, String),
    Appcast(Appcast),
}

/// An `APPCAST` (contacts-appcast.md §5.3), split into what the panel shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Appcast {
    /// `proc@node` (or `proc`): one report per app and node is kept.
    pub key: String,
    pub proc_name: String,
    pub node: String,
    pub iter: String,
    /// The report body, one entry per line.
    pub lines: Vec<String>,
    pub config_warnings: Vec<String>,
    pub run_warnings: Vec<String>,
}

/// Read an `APPCAST` value; `None` without `proc=`.
pub fn read_appcast(s: &str) -> Option<Appcast> {
    let mut a = Appcast {
        key: String::new(),
        proc_name: String::new(),
        node: String::new(),
        iter: String::new(),
        lines: Vec::new(),
        config_warnings: Vec::new(),
        run_warnings: Vec::new(),
    };
    let items = |v: &str| -> Vec<String> {
        v.split("!@")
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect()
    };
    for part in s.split("!@#") {
        let Some((k, v)) = part.split_once('=') else {
            continue;
        };
        match k {
            "proc" => a.proc_name = v.to_owned(),
            "node" => a.node = v.to_owned(),
            "iter" => a.iter = v.to_owned(),
            "messages" => {
                let mut lines: Vec<String> = v.split("!@").map(str::to_owned).collect();
                // Every line is followed by `!@`, so the split ends with one empty item.
                if lines.last().is_some_and(String::is_empty) {
                    lines.pop();
                }
                a.lines = lines;
            }
            "config_warnings" => a.config_warnings = items(v),
            "run_warnings" => a.run_warnings = items(v),
            _ => {}
        }
    }
    if a.proc_name.is_empty() {
        return None;
    }
    a.key = if a.node.is_empty() {
        a.proc_name.clone()
    } else {
        format!("{}@{}", a.proc_name, a.node)
    };
    Some(a)
}

/// Turns postings into [`Update`]s and counts what it skips.
#[derive(Clone, Debug)]
pub struct Feed {
    nav: NavVehicle,
    /// Once a node report arrived, `NAV_*` no longer makes a vehicle (pNodeReporter
    /// reports the ownship under its real name).
    pub node_reports_seen: bool,
    /// Further variables shown in the panel (the mission's button variables).
    extra_vars: BTreeSet<String>,
    /// Postings skipped, by reason.
    pub skipped: BTreeMap<String, u64>,
}

impl Feed {
    /// `ownship` names the vehicle built from `NAV_*`.
    pub fn new(ownship: &str, extra_vars: impl IntoIterator<Item = String>) -> Feed {
        Feed {
            nav: NavVehicle::new(ownship),
            node_reports_seen: false,
            extra_vars: extra_vars.into_iter().collect(),
            skipped: BTreeMap::new(),
        }
    }

    /// True when [`Feed::apply`] may do something with `var` (a cheap first filter).
    pub fn wants(&self, var: &str) -> bool {
        var.starts_with("VIEW_")
            || var.starts_with("NODE_REPORT")
            || var.starts_with("DESIRED_")
            || NavVehicle::wants(var)
            || var == "APPCAST"
            || HELM_VARS.contains(&var)
            || self.extra_vars.contains(var)
    }

    /// Count a skipped posting.
    pub fn skip(&mut self, why: &str) {
        *self.skipped.entry(why.to_owned()).or_insert(0) += 1;
    }

    /// The update one posting makes, if any.
    pub fn apply(&mut self, var: &str, value: Value<'_>, t: f64) -> Option<Update> {
        match (var, value) {
            ("NODE_REPORT" | "NODE_REPORT_LOCAL", Value::Str(s)) => match read_node_report(s, t) {
                Ok(v) => {
                    self.node_reports_seen = true;
                    Some(Update::Vehicle(v))
                }
                Err(e) => {
                    self.skip(match e {
                        NodeError::MissingName => "NODE_REPORT without NAME",
                        NodeError::MissingPosition => "NODE_REPORT without X/Y",
                    });
                    None
                }
            },
            (v, Value::Num(x)) if NavVehicle::wants(v) => {
                if self.node_reports_seen {
                    return None;
                }
                self.nav.apply(v, x, t).map(Update::Vehicle)
            }
            (v, Value::Str(s)) if VIEW_VARS.contains(&v) => match read_view(v, s) {
                Ok(c) => Some(Update::View(c)),
                Err(e) => {
                    let why = match e {
                        ViewError::Unreadable => "unreadable",
                        ViewError::NotFinite => "a coordinate not finite",
                        ViewError::TooManyVertices => "too many vertices",
                    };
                    self.skip(&format!("malformed {v} ({why})"));
                    None
                }
            },
            ("APPCAST", Value::Str(s)) => match read_appcast(s) {
                Some(a) => Some(Update::Appcast(a)),
                None => {
                    self.skip("APPCAST without proc=");
                    None
                }
            },
            (v, value)
                if v.starts_with("DESIRED_")
                    || HELM_VARS.contains(&v)
                    || self.extra_vars.contains(v) =>
            {
                Some(Update::Var(v.to_owned(), value.text()))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn appcast_is_split_into_lines_and_warnings() {
        let s = "proc=pHelmIvP!@#iter=1!@#node=alpha!@#iter=1!@#messages=  Comms Policy: open!@  Helm Iteration:  0!@!@#!@#events_total=0!@#!@#run_warning_total=2!@#run_warnings=2:Not all HoldOnApps have been detected";
        let a = read_appcast(s).unwrap();
        assert_eq!(a.key, "pHelmIvP@alpha");
        assert_eq!(a.lines, ["  Comms Policy: open", "  Helm Iteration:  0"]);
        assert_eq!(a.run_warnings, ["2:Not all HoldOnApps have been detected"]);
        assert!(read_appcast("iter=1!@#messages=x").is_none());
    }

    #[test]
    fn nav_vehicle_gives_way_to_node_reports_and_bad_input_is_counted() {
        let mut f = Feed::new("alpha", ["DEPLOY".to_string()]);
        f.apply("NAV_X", Value::Num(1.0), 0.0);
        assert!(matches!(
            f.apply("NAV_Y", Value::Num(2.0), 0.0),
            Some(Update::Vehicle(_))
        ));
        f.apply("NODE_REPORT_LOCAL", Value::Str("NAME=a,X=1,Y=2"), 1.0);
        assert_eq!(f.apply("NAV_Y", Value::Num(3.0), 1.0), None);
        assert_eq!(f.apply("VIEW_POINT", Value::Str("x=1"), 1.0), None);
        assert_eq!(f.apply("NODE_REPORT", Value::Str("X=1,Y=1"), 1.0), None);
        assert_eq!(f.skipped["malformed VIEW_POINT (unreadable)"], 1);
        assert_eq!(f.skipped["NODE_REPORT without NAME"], 1);
        assert_eq!(
            f.apply("DESIRED_SPEED", Value::Num(1.5), 2.0),
            Some(Update::Var("DESIRED_SPEED".into(), "1.5".into()))
        );
        assert!(f.wants("DEPLOY") && !f.wants("DB_TIME"));
    }
}
