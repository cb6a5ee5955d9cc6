//! The helm's AppCasting report (contacts-appcast.md §5.4) and what feeds it: run
//! warnings, events, completed behaviors and the table of the behaviors' last postings.
//! The report is built only when one is due, never on the iteration's path; the
//! iteration only records what went out.

use std::fmt::Write;

use rustc_hash::FxHashMap;

use super::{Helm, HelmState};
use crate::posting::Value;
use crate::runtime::RunState;

/// The last posting of one variable by a behavior.
#[derive(Clone, Debug, Default)]
pub(crate) struct PostedRow {
    pub behavior: String,
    /// Seconds since the helm started.
    pub time: f64,
    pub iter: u64,
    /// A text value, or the number (written only when a report shows it: most rows
    /// change every iteration and are never shown).
    pub value: String,
    pub num: Option<f64>,
}

/// What the report needs besides the behavior set.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReportFeed {
    pub warnings: crate::run_warnings::Warnings,
    /// Variable → last posting, for variables posted by behaviors (hashed: looked up
    /// for every posting, sorted only when a report is made).
    pub rows: FxHashMap<String, PostedRow>,
    /// Completed behaviors: name, times completed, time of the last completion.
    pub completed: Vec<(String, u32, f64)>,
    /// The last decision step's halt reason and function count.
    pub halted: bool,
    pub functions: usize,
    /// Seconds, last and max, of the decision step (loop), of its behavior part
    /// (create: the functions built) and of the solver (solve).
    pub loop_secs: (f64, f64),
    pub create_secs: (f64, f64),
    pub solve_secs: (f64, f64),
}

fn compact(v: f64) -> String {
    bhv::number::compact(v, 5)
}

fn keep_value(v: &Value, row: &mut PostedRow) {
    row.value.clear();
    row.num = match v {
        Value::Str(s) => {
            row.value.push_str(s);
            None
        }
        Value::Num(n) => Some(*n),
    };
}

impl PostedRow {
    /// The value as shown: the text, or the number compacted to 5 decimals.
    fn value_text(&self) -> String {
        let mut out = self.value.clone();
        if let Some(n) = self.num {
            crate::runtime::push_compact(&mut out, n, 5);
        }
        out
    }
}

/// A value cell: at most 55 characters, the middle cut as first 27 + `..` + last 26.
fn cell(v: &str) -> String {
    let n = v.chars().count();
    if n <= 55 {
        return v.to_string();
    }
    let head: String = v.chars().take(27).collect();
    let tail: String = v.chars().skip(n - 26).collect();
    format!("{head}..{tail}")
}

/// Columns padded to their widest cell, 2 blanks apart, trailing blanks removed, the
/// header underlined with dashes.
fn table(header: [&str; 5], rows: &[[String; 5]]) -> String {
    let mut w = header.map(str::len);
    for r in rows {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let line = |cells: [&str; 5]| -> String {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            let _ = write!(s, "{c:<width$}", width = w[i]);
        }
        s.trim_end().to_string()
    };
    let mut out = line(header);
    out.push('\n');
    let dashes: Vec<String> = w.iter().map(|n| "-".repeat(*n)).collect();
    out.push_str(&line([
        &dashes[0], &dashes[1], &dashes[2], &dashes[3], &dashes[4],
    ]));
    out.push('\n');
    for r in rows {
        out.push_str(&line([&r[0], &r[1], &r[2], &r[3], &r[4]]));
        out.push('\n');
    }
    out
}

impl ReportFeed {
    /// A behavior's posting went out (passed the duplicate filter).
    pub fn posted(&mut self, var: &str, behavior: &str, elapsed: f64, iter: u64, v: &Value) {
        if let Some(row) = self.rows.get_mut(var) {
            // Reuse the row's strings: no allocation for a variable seen before.
            row.behavior.clear();
            row.behavior.push_str(behavior);
            row.time = elapsed;
            row.iter = iter;
            keep_value(v, row);
            return;
        }
        let mut row = PostedRow {
            behavior: behavior.to_string(),
            time: elapsed,
            iter,
            value: String::new(),
            num: None,
        };
        keep_value(v, &mut row);
        self.rows.insert(var.to_string(), row);
    }

    pub fn completed(&mut self, name: &str, now: f64) {
        if let Some(i) = self.completed.iter().position(|(n, _, _)| n == name) {
            let (n, c, _) = self.completed.remove(i);
            self.completed.push((n, c + 1, now));
        } else {
            self.completed.push((name.to_string(), 1, now));
        }
    }
}

impl Helm {
    /// Run warnings and events of the helm's appcast.
    pub fn appcast_warnings(&mut self) -> &mut crate::run_warnings::Warnings {
        &mut self.report.warnings
    }

    /// A run warning: logged, and counted in the appcast.
    pub(crate) fn run_warning(&mut self, text: &str) {
        tracing::warn!("{text}");
        self.report.warnings.run_warning(text);
    }

    pub(crate) fn retract_run_warning(&mut self, text: &str) {
        self.report.warnings.retract(text);
    }

    /// The report body at MOOS time `now` (§5.4), with the comms policy in force.
    pub fn appcast_body(&self, now: f64, comms_policy: &str) -> String {
        if self.state == HelmState::Malconfig {
            let bar = "!".repeat(60);
            return format!(
                "{bar}\n!!{:^56}!!\n!!{:^56}!!\n!!{:^56}!!\n!!{:^56}!!\n{bar}",
                "The helm is in the MALCONFIG state due to",
                "unresolved configuration warnings.",
                "It will not drive. Fix them and restart;",
                "`helm check MISSION` lists them.",
            );
        }
        let f = &self.report;
        let mut s = String::with_capacity(2048);
        let pcs = self.pieces_total();
        let modes = if self.modes.is_empty() {
            String::new()
        } else {
            self.modes.summary()
        };
        let _ = writeln!(s, "  Comms Policy: {comms_policy}");
        // Not in the real report: people reading uMAC want the state first.
        let _ = writeln!(s, "  Helm State:      {}", self.state.as_str());
        let _ = writeln!(s, "  Helm Iteration:  {}", self.env.helm_iteration);
        let _ = writeln!(s, "  IvP Functions:   {}", f.functions);
        let _ = writeln!(s, "  Pieces (Formed): {pcs}");
        let _ = writeln!(s, "  Pieces (Cached): 0");
        let _ = writeln!(s, "  Mode(s):         {modes}");
        for (label, (last, max)) in [
            ("SolveTime: ", f.solve_secs),
            ("CreateTime:", f.create_secs),
            ("LoopTime:  ", f.loop_secs),
        ] {
            let _ = writeln!(s, "  {label}  {last:.2}   (max={max:.2})");
        }
        let _ = writeln!(
            s,
            "  Halted:         {}   ({} warnings)",
            f.halted,
            self.config_warnings.len()
        );
        let _ = writeln!(s, "  Active Goal:    {}", f.functions > 0);
        s.push_str("Helm Decision:");
        if self.decide_count == 0 {
            s.push_str(" []\n");
        } else {
            for v in self.config.domain.vars() {
                let _ = write!(
                    s,
                    " [{},{},{},{}]",
                    v.name,
                    compact(v.low),
                    compact(v.high),
                    v.points
                );
            }
            s.push('\n');
            for (i, v) in self.config.domain.vars().iter().enumerate() {
                match self.decision.values.get(i).copied().flatten() {
                    Some(x) if !f.halted && f.functions > 0 => {
                        let _ = writeln!(s, "  {} = {}", v.name, compact(x));
                    }
                    _ => {
                        let _ = writeln!(s, "  {} = no-decision", v.name);
                    }
                }
            }
        }
        let since = |t: f64| now - t;
        let _ = writeln!(
            s,
            "Behaviors Spawnable: --------- ({})",
            self.templates.len()
        );
        for t in &self.templates {
            let _ = writeln!(
                s,
                "  {}::{} (Spawned:{}/{})",
                t.spec.type_name, t.spec.name_prefix, t.made, t.tried
            );
        }
        let group = |st: RunState| self.behaviors.iter().filter(move |b| b.core.state == st);
        let _ = writeln!(
            s,
            "Behaviors Active: ---------- ({})",
            group(RunState::Active).count()
        );
        for b in group(RunState::Active) {
            let pcs = self.pieces_of(&b.core.name);
            let mut upd = String::new();
            b.core.push_update_counts(&mut upd);
            let _ = writeln!(
                s,
                "  {} [{:.2}] (pwt={}) (pcs={pcs}) (cpu={:.5}) (upd={upd})",
                b.core.name,
                since(b.core.state_entry_time),
                compact(b.core.pwt),
                b.core.step_secs
            );
        }
        for (title, st) in [
            ("Behaviors Running: --------- ", RunState::Running),
            ("Behaviors Disabled: --------- ", RunState::Disabled),
        ] {
            let _ = writeln!(s, "{title}({})", group(st).count());
            for b in group(st) {
                let _ = writeln!(
                    s,
                    "  {} [{:.2}]",
                    b.core.name,
                    since(b.core.state_entry_time)
                );
            }
        }
        let idle: Vec<String> = group(RunState::Idle)
            .map(|b| format!("{}[{:.2}]", b.core.name, since(b.core.state_entry_time)))
            .collect();
        let _ = writeln!(s, "Behaviors Idle: ------------ ({})", idle.len());
        let _ = writeln!(s, "  {}", idle.join(", "));
        let done: Vec<String> = f
            .completed
            .iter()
            .rev()
            .map(|(n, c, t)| {
                let count = if *c > 1 {
                    format!("({c})")
                } else {
                    String::new()
                };
                format!("{n}{count}[{:.2}]", since(*t))
            })
            .collect();
        let _ = writeln!(s, "Behaviors Completed: ------- ({})", f.completed.len());
        let _ = writeln!(s, "{}", done.join(","));
        let hold = if self.config.hold_on_apps.is_empty() {
            "none"
        } else if self.hold_apps_seen() {
            "satisfied"
        } else {
            "waiting"
        };
        let _ = writeln!(s, "Hold-On-Apps: {hold}");
        s.push_str("\n\n");
        let mut rows: Vec<[String; 5]> = f
            .rows
            .iter()
            .map(|(var, r)| {
                [
                    var.clone(),
                    r.behavior.clone(),
                    format!("{:.2}", r.time),
                    r.iter.to_string(),
                    cell(&r.value_text()),
                ]
            })
            .collect();
        rows.sort_unstable_by(|a, b| a[0].cmp(&b[0])); // the variables, each once
        s.push_str(&table(
            ["Variable", "Behavior", "Time", "Iter", "Value"],
            &rows,
        ));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_values_are_cut_in_the_middle() {
        let v: String = ('a'..='z').cycle().take(80).collect();
        let c = cell(&v);
        assert_eq!(c.chars().count(), 55);
        assert!(c.starts_with(&v[..27]) && c.ends_with(&v[54..]));
        assert_eq!(cell("short"), "short");
    }

    #[test]
    fn table_pads_and_underlines() {
        let rows = vec![[
            "WPT_STAT".to_string(),
            "waypt_survey".to_string(),
            "12.50".to_string(),
            "40".to_string(),
            "vname=alpha".to_string(),
        ]];
        let t = table(["Variable", "Behavior", "Time", "Iter", "Value"], &rows);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[0], "Variable  Behavior      Time   Iter  Value");
        assert_eq!(lines[1], "--------  ------------  -----  ----  -----------");
        assert_eq!(lines[2], "WPT_STAT  waypt_survey  12.50  40    vname=alpha");
    }

    /// A number is kept as the number and shown as it was written before (5 decimals,
    /// compacted); a text replaces it.
    #[test]
    fn posted_values_show_as_written() {
        let mut f = ReportFeed::default();
        f.posted("SPD", "b", 1.0, 1, &Value::Num(1.25));
        let mut want = String::new();
        crate::runtime::push_compact(&mut want, 1.25, 5);
        assert_eq!(f.rows["SPD"].value_text(), want);
        f.posted("SPD", "b", 2.0, 2, &Value::Str("fast".into()));
        assert_eq!(f.rows["SPD"].value_text(), "fast");
        f.posted("SPD", "b", 3.0, 3, &Value::Num(-0.000_001));
        let mut want = String::new();
        crate::runtime::push_compact(&mut want, -0.000_001, 5);
        assert_eq!(f.rows["SPD"].value_text(), want);
    }

    #[test]
    fn completions_are_counted_most_recent_last() {
        let mut f = ReportFeed::default();
        f.completed("a", 1.0);
        f.completed("b", 2.0);
        f.completed("a", 3.0);
        assert_eq!(f.completed[1], ("a".to_string(), 2, 3.0));
    }
}
