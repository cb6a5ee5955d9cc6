//! `IVPHELM_SUMMARY` (helm.md §8.5): the first report is full, later ones carry `iter`,
//! `utc_time` and the fields that changed.

use super::iterate::DecisionSummary;
use super::Helm;
use crate::runtime::RunState;

fn compact(v: f64) -> String {
    crate::runtime::fmt3(v)
}

impl Helm {
    /// Pieces of the function `name` produced this iteration (0 if none).
    pub(crate) fn pieces_of(&self, name: &str) -> usize {
        self.functions
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0, |(_, f)| f.piece_count())
    }

    fn bhv_list(&self, states: &[RunState], active: bool) -> String {
        let items: Vec<String> = self
            .behaviors
            .iter()
            .filter(|b| states.contains(&b.core.state))
            .map(|b| {
                let upd = b.core.update_counts();
                if active {
                    let pcs = self.pieces_of(&b.core.name);
                    format!(
                        "{}${:.2}${:.5}${}${:.5}${}$1$$",
                        b.core.name, b.core.state_entry_time, b.core.pwt, pcs, 0.0, upd
                    )
                } else {
                    format!("{}${:.2}${}", b.core.name, b.core.state_entry_time, upd)
                }
            })
            .collect();
        if items.is_empty() {
            "none".into()
        } else {
            items.join(":")
        }
    }

    /// Post IVPHELM_SUMMARY for this decision iteration.
    pub(crate) fn post_summary(&mut self, now: f64, s: &DecisionSummary) {
        let mut fields: Vec<(&'static str, String)> = Vec::with_capacity(16);
        fields.push(("ofnum", s.functions.to_string()));
        let pcs: usize = self.functions.iter().map(|(_, f)| f.piece_count()).sum();
        fields.push(("total_pcs_formed", pcs.to_string()));
        fields.push(("total_pcs_cached", "0".into()));
        fields.push(("warnings", self.config_warnings.len().to_string()));
        let mut decisions = Vec::new();
        for i in 0..self.config.domain.size() {
            let name = &self.config.domain.var(i).name;
            match self.decision.values.get(i).copied().flatten() {
                Some(v) if s.halted.is_none() && s.functions > 0 => {
                    decisions.push(format!("var={name}:{}", compact(v)))
                }
                _ => decisions.push(format!("var={name}:varbalk")),
            }
        }
        fields.push(("", decisions.join(",")));
        fields.push(("halted", s.halted.is_some().to_string()));
        fields.push(("active_goal", (s.functions > 0).to_string()));
        fields.push(("modes", self.modes.summary()));
        fields.push(("running_bhvs", self.bhv_list(&[RunState::Running], false)));
        fields.push(("active_bhvs", self.bhv_list(&[RunState::Active], true)));
        fields.push(("disabled_bhvs", self.bhv_list(&[RunState::Disabled], false)));
        fields.push(("idle_bhvs", self.bhv_list(&[RunState::Idle], false)));
        fields.push(("ivpdomain", format!("\"{}\"", self.env.helm_domain)));
        fields.push((
            "halt_msg",
            s.halted.clone().unwrap_or_else(|| "none".into()),
        ));

        let full = self.summary_last.is_empty();
        let mut out = format!("iter={},utc_time={:.2}", self.env.helm_iteration, now);
        for (k, v) in &fields {
            let changed = self.summary_last.get(k) != Some(v);
            if full || changed {
                out.push(',');
                if !k.is_empty() {
                    out.push_str(k);
                    out.push('=');
                }
                out.push_str(v);
            }
        }
        for (k, v) in fields {
            self.summary_last.insert(k, v);
        }
        self.post_str("IVPHELM_SUMMARY", &out);
    }
}
