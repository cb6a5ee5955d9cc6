//! Publication of mode variables and behavior output (helm.md §8).

use super::iterate::typed;
use super::Helm;
use crate::posting::Value;
use crate::runtime::RunState;

impl Helm {
    /// §8.2-§8.4, in order.
    pub(crate) fn publish_behavior_output(&mut self, now: f64) {
        let iter = self.env.helm_iteration;
        // Mode variables share the single key `mode_set` (quirk, QUIRKS.md).
        for (var, val) in std::mem::take(&mut self.mode_pairs) {
            let v = typed(&val);
            if self.filter.allow("mode_set", &v) {
                self.post(&var, v, "HELM_MODE");
            }
        }
        let cnt = self.behaviors.len() as f64;
        self.post_on_change("IVPHELM_BHV_CNT", Value::Num(cnt));
        let ever = self.bhv_cnt_ever as f64;
        self.post_on_change("IVPHELM_BHV_CNT_EVER", Value::Num(ever));
        self.post_num("IVPHELM_ITER", iter as f64);

        for i in 0..self.behaviors.len() {
            let messages = std::mem::take(&mut self.behaviors[i].core.messages);
            let name = self.behaviors[i].core.name.clone();
            let aux = format!("{iter}:{name}");
            for m in &messages {
                match m.var.as_str() {
                    "BHV_IPF" => {
                        self.post(&m.var, m.value.clone(), &name);
                        continue;
                    }
                    "BHV_WARNING" | "BHV_ERROR" | "BHV_EVENT" => {
                        if let Value::Str(s) = &m.value {
                            let text = format!("{}: {s}", m.var);
                            if m.var == "BHV_EVENT" {
                                self.report.warnings.event(now - self.start_time, s);
                            } else if m.key.ends_with("retract") {
                                self.retract_run_warning(&text);
                            } else {
                                self.run_warning(&text);
                            }
                        }
                    }
                    _ => {}
                }
                self.ib.set_value(&m.var, &m.value, now);
                if self.filter.allow(&m.key, &m.value) {
                    self.post(&m.var, m.value.clone(), &aux);
                    self.report
                        .posted(&m.var, &name, now - self.start_time, iter, &m.value);
                }
            }
            // Give the buffer back so its allocation is reused next iteration.
            let mut messages = messages;
            messages.clear();
            self.behaviors[i].core.messages = messages;
        }

        // The state-space variables change only with the behavior set's conditions and
        // flags (tracked by the subscription signature), not every iteration.
        if std::mem::take(&mut self.statevars_dirty) {
            let mut vars: Vec<String> = self
                .behaviors
                .iter()
                .flat_map(|b| b.core.state_vars())
                .collect();
            vars.sort();
            vars.dedup();
            if vars.len() > self.statevars.len() {
                self.statevars = vars;
                let s = self.statevars.join(",");
                self.post_str("IVPHELM_STATEVARS", &s);
            }
        }

        let pending = self
            .behaviors
            .iter()
            .any(|b| b.core.state == RunState::Completed);
        if self.completed_pending_last != Some(pending) {
            self.completed_pending_last = Some(pending);
            let v = if pending { "true" } else { "false" };
            self.post(
                "IVPHELM_COMPLETED_PENDING",
                Value::Str(v.into()),
                &iter.to_string(),
            );
        }
        let before = self.behaviors.len();
        let mut dead = Vec::new();
        let report = &mut self.report;
        self.behaviors.retain(|b| {
            let done = b.core.state == RunState::Completed;
            if done {
                report.completed(&b.core.name, now);
                dead.push(format!(
                    "bname={}, btype={}, event=death",
                    b.core.name, b.core.type_name
                ));
            }
            !done
        });
        self.life_events.extend(dead);
        let removed = before - self.behaviors.len();
        if self.completed_count_last != Some(removed) {
            self.completed_count_last = Some(removed);
            self.post(
                "IVPHELM_COMPLETED_COUNT",
                Value::Num(removed as f64),
                &iter.to_string(),
            );
        }
        let elapsed = now - self.start_time;
        for ev in std::mem::take(&mut self.life_events) {
            let time = if elapsed > 0.0 {
                format!(",time={elapsed:.2}")
            } else {
                String::new()
            };
            self.post_str(
                "IVPHELM_LIFE_EVENT",
                &format!("iter=0{time}, {ev},iter={iter}"),
            );
        }
    }

    /// §6 step 21: behavior lists and counts, each only when changed.
    pub(crate) fn publish_behavior_lists(&mut self) {
        let list = |h: &Helm, s: &[RunState]| -> (String, usize) {
            let names: Vec<&str> = h
                .behaviors
                .iter()
                .filter(|b| s.contains(&b.core.state))
                .map(|b| b.core.name.as_str())
                .collect();
            (names.join(","), names.len())
        };
        let groups: [(&'static str, &'static str, &[RunState]); 4] = [
            (
                "IVPHELM_BHV_ACTIVE",
                "IVPHELM_BHV_ACTIVE_CNT",
                &[RunState::Active],
            ),
            (
                "IVPHELM_BHV_RUNNING",
                "IVPHELM_BHV_RUNNING_CNT",
                &[RunState::Running],
            ),
            (
                "IVPHELM_BHV_IDLE",
                "IVPHELM_BHV_IDLE_CNT",
                &[RunState::Idle],
            ),
            (
                "IVPHELM_BHV_DISABLED",
                "IVPHELM_BHV_DISABLED_CNT",
                &[RunState::Disabled],
            ),
        ];
        for (var, cnt_var, states) in groups {
            let (names, n) = list(self, states);
            let last = self.last_posted.get(var).cloned().unwrap_or_default();
            if names != last {
                self.last_posted.insert(var, names.clone());
                self.post_str(var, &names);
                self.post_num(cnt_var, n as f64);
            }
        }
    }
}
