//! `IVPHELM_SUMMARY` (helm.md §8.5): the first report is full, later ones carry `iter`,
//! `utc_time` and the fields that changed.
//!
//! Every field is written into a string kept from the last iteration and compared with
//! the field last reported, so a steady summary allocates nothing.

use mbutil::short_str;

use super::iterate::DecisionSummary;
use super::Helm;
use crate::runtime::{push_compact, RunState};

/// The summary's fields in order (`""`: the decisions, written without a name).
const FIELDS: [&str; 14] = [
    "ofnum",
    "total_pcs_formed",
    "total_pcs_cached",
    "warnings",
    "",
    "halted",
    "active_goal",
    "modes",
    "running_bhvs",
    "active_bhvs",
    "disabled_bhvs",
    "idle_bhvs",
    "ivpdomain",
    "halt_msg",
];

impl Helm {
    /// Pieces of the function `name` produced this iteration (0 if none).
    pub(crate) fn pieces_of(&self, name: &str) -> usize {
        self.functions
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0, |(_, f)| f.view().piece_count())
    }

    /// Pieces of all this iteration's functions.
    pub(crate) fn pieces_total(&self) -> usize {
        self.functions
            .iter()
            .map(|(_, f)| f.view().piece_count())
            .sum()
    }

    fn push_bhv_list(&self, out: &mut String, state: RunState, active: bool) {
        let start = out.len();
        for b in self.behaviors.iter().filter(|b| b.core.state == state) {
            if out.len() > start {
                out.push(':');
            }
            // `name$entry:.2$` then, if active, `pwt:.5$pieces$0.00000$`: push_fixed
            // writes what `{:.N}` writes, without core::fmt.
            let c = &b.core;
            out.push_str(&c.name);
            out.push('$');
            mbutil::push_fixed(out, c.state_entry_time, 2);
            out.push('$');
            if active {
                mbutil::push_fixed(out, c.pwt, 5);
                out.push('$');
                mbutil::push_u64(out, self.pieces_of(&c.name) as u64);
                out.push_str("$0.00000$");
            }
            c.push_update_counts(out);
            out.push_str(if active { "$1$$" } else { "" });
        }
        if out.len() == start {
            out.push_str("none");
        }
    }

    /// The modes as `var@value` joined by `#` (numbers compacted), or `none`.
    fn push_modes(&self, out: &mut String) {
        let cur = self.modes.current();
        if cur.is_empty() {
            out.push_str("none");
        }
        for (k, (var, val)) in cur.iter().enumerate() {
            if k > 0 {
                out.push('#');
            }
            out.push_str(var);
            out.push('@');
            match mbutil::parse_number(val) {
                Some(n) => push_compact(out, n, 6),
                None => out.push_str(val),
            }
        }
    }

    /// Field `k` of this iteration's summary, written into `out` (cleared).
    fn write_field(&self, k: usize, out: &mut String, s: &DecisionSummary) {
        out.clear();
        let mut digits = itoa::Buffer::new();
        match k {
            0 => out.push_str(digits.format(s.functions)),
            1 => {
                let pcs = self.pieces_total();
                out.push_str(digits.format(pcs));
            }
            2 => out.push('0'),
            3 => out.push_str(digits.format(self.config_warnings.len())),
            4 => {
                for i in 0..self.config.domain.size() {
                    if i > 0 {
                        out.push(',');
                    }
                    out.push_str("var=");
                    out.push_str(&self.config.domain.var(i).name);
                    out.push(':');
                    match self.decision.values.get(i).copied().flatten() {
                        Some(v) if s.halted.is_none() && s.functions > 0 => push_compact(out, v, 3),
                        _ => out.push_str("varbalk"),
                    }
                }
            }
            5 => out.push_str(if s.halted.is_some() { "true" } else { "false" }),
            6 => out.push_str(if s.functions > 0 { "true" } else { "false" }),
            7 => self.push_modes(out),
            8 => self.push_bhv_list(out, RunState::Running, false),
            9 => self.push_bhv_list(out, RunState::Active, true),
            10 => self.push_bhv_list(out, RunState::Disabled, false),
            11 => self.push_bhv_list(out, RunState::Idle, false),
            12 => {
                out.push('"');
                out.push_str(&self.env.helm_domain);
                out.push('"');
            }
            _ => out.push_str(s.halted.as_deref().unwrap_or("none")),
        }
    }

    /// Post IVPHELM_SUMMARY for this decision iteration.
    pub(crate) fn post_summary(&mut self, now: f64, s: &DecisionSummary) {
        let mut fields = std::mem::take(&mut self.summary_fields);
        fields.resize_with(FIELDS.len(), String::new);
        for (k, field) in fields.iter_mut().enumerate() {
            self.write_field(k, field, s);
        }
        let full = self.summary_last.is_empty();
        // At most every field with its name, after `iter=...,utc_time=...`.
        let most: usize = fields
            .iter()
            .zip(FIELDS)
            .map(|(v, f)| v.len() + f.len() + 2)
            .sum();
        let mut out = self.pool.take_for(most + 48);
        out.push_str("iter=");
        mbutil::push_u64(&mut out, self.env.helm_iteration);
        out.push_str(",utc_time=");
        mbutil::push_fixed(&mut out, now, 2);
        for (k, v) in fields.iter().enumerate() {
            let changed = !(self.summary_last.get(k)).is_some_and(|l| short_str::same(l, v));
            if full || changed {
                out.push(',');
                if !FIELDS[k].is_empty() {
                    out.push_str(FIELDS[k]);
                    out.push('=');
                }
                out.push_str(v);
            }
        }
        self.summary_last.resize_with(FIELDS.len(), String::new);
        for (last, v) in self.summary_last.iter_mut().zip(&fields) {
            short_str::assign(last, v);
        }
        self.summary_fields = fields;
        self.post("IVPHELM_SUMMARY", crate::posting::Value::Str(out), "");
    }
}
