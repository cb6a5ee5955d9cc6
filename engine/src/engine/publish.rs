//! Publication of mode variables and behavior output (helm.md §8).

use super::Helm;
use crate::posting::Value;
use crate::runtime::RunState;
use behavior_api::contact::POST_MORTEM_MACRO;

impl Helm {
    /// §8.2-§8.4, in order.
    pub(crate) fn publish_behavior_output(&mut self, now: f64) {
        let iter = self.env.helm_iteration;
        // Mode variables share the single key `mode_set` (quirk, QUIRKS.md).
        // The pairs stay for the next iteration to refill (no new strings), and a
        // string value comes from the pool and goes back to it when filtered out.
        let pairs = std::mem::take(&mut self.mode_pairs);
        for (var, val) in &pairs {
            let v = match mbutil::parse_number(val) {
                Some(n) => Value::Num(n),
                None => Value::Str(self.pool.copy_of(val)),
            };
            if self.filter.allow("mode_set", &v) {
                self.post(var, v, "HELM_MODE");
            } else {
                crate::posting::give_value(&mut self.pool, v);
            }
        }
        self.mode_pairs = pairs;
        let cnt = self.behaviors.len() as f64;
        self.post_on_change("IVPHELM_BHV_CNT", Value::Num(cnt));
        let ever = self.bhv_cnt_ever as f64;
        self.post_on_change("IVPHELM_BHV_CNT_EVER", Value::Num(ever));
        self.post_num("IVPHELM_ITER", iter as f64);

        let mut name = self.pool.take_for(64);
        let mut aux = self.pool.take_for(96);
        let mut default_key = self.pool.take_for(64);
        for i in 0..self.behaviors.len() {
            let mut messages = std::mem::take(&mut self.behaviors[i].core.messages);
            self.refill.clear();
            let mut wanted = 0;
            name.clear();
            name.push_str(&self.behaviors[i].core.name);
            aux.clear();
            aux.push_str(itoa::Buffer::new().format(iter));
            aux.push(':');
            aux.push_str(&name);
            for mut m in messages.drain(..) {
                match m.var.as_str() {
                    "BHV_IPF" if m.helm_ipf => {
                        self.post_ipf_packets(i, &name, iter);
                        self.pool.give(m.var);
                        self.pool.give(m.key);
                        continue;
                    }
                    "BHV_IPF" => {
                        self.post_message(m, &name);
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
                // The behavior's own strings (BHV_IPF's are the helm's): a filtered
                // message's go straight back to its pool, a posted one's leave in the
                // posting and the behavior gets spare strings of their sizes instead.
                wanted += 1 + usize::from(!m.key.is_empty());
                wanted += usize::from(matches!(m.value, Value::Str(_)));
                self.ib.set_value(&m.var, &m.value, now);
                let key = if m.key.is_empty() {
                    default_key.clear();
                    default_key.push_str(&name);
                    default_key.push_str(&m.var);
                    &default_key
                } else {
                    &m.key
                };
                if self.filter.allow(key, &m.value) {
                    self.report
                        .posted(&m.var, &name, now - self.start_time, iter, &m.value);
                    self.refill.push(m.var.len());
                    if let Value::Str(s) = &m.value {
                        self.refill.push(s.len());
                    }
                    self.behaviors[i].core.pool.give(std::mem::take(&mut m.key));
                    self.post_message(m, &aux);
                } else {
                    let pool = &mut self.behaviors[i].core.pool;
                    pool.give(m.var);
                    pool.give(m.key);
                    crate::posting::give_value(pool, m.value);
                }
            }
            // Give the buffer back so its allocation is reused next iteration.
            let core = &mut self.behaviors[i].core;
            core.messages = messages;
            for &len in &self.refill {
                if core.pool.len() >= wanted || self.pool.is_empty() {
                    break;
                }
                core.pool.give(self.pool.take_for(len));
            }
        }
        self.pool.give(name);
        self.pool.give(aux);
        self.pool.give(default_key);

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
                // A behavior may say why it ended (contact behaviors: range and
                // bearing), through the post-mortem macro.
                let pm = b
                    .bhv
                    .expand_macros(POST_MORTEM_MACRO.into())
                    .into_result()
                    .map(String::from)
                    .unwrap_or_default();
                let pm = if pm.is_empty() || pm == POST_MORTEM_MACRO {
                    String::new()
                } else {
                    format!(", post_mortem={pm}")
                };
                dead.push(format!(
                    "bname={}, btype={}, event=death{pm}",
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

    /// Behavior `i`'s BHV_IPF (its kept text) split into packets (ivp-solver.md §9.2),
    /// each posted with source-aux `name`; every string is a reused one.
    fn post_ipf_packets(&mut self, i: usize, name: &str, iter: u64) {
        let kept = &self.behaviors[i].core.ipf_kept;
        let packets = self.ipf.kept_helm_packets(kept, name, iter);
        for k in 1..=packets.count() {
            let mut p = self.pool.take_long();
            packets.write(k, &mut p);
            self.outbox.push(crate::posting::Posting {
                var: self.pool.copy_of("BHV_IPF"),
                value: Value::Str(p),
                source_aux: self.pool.copy_of(name),
            });
        }
    }

    /// A behavior's message posted as it is (its strings move into the posting).
    fn post_message(&mut self, m: crate::runtime::Message, aux: &str) {
        let source_aux = self.pool.copy_of(aux);
        self.pool.give(m.key);
        self.outbox.push(crate::posting::Posting {
            var: m.var,
            value: m.value,
            source_aux,
        });
    }

    /// §6 step 21: behavior lists and counts, each only when changed (the list is
    /// written into a spare string and compared before anything is kept).
    pub(crate) fn publish_behavior_lists(&mut self) {
        use RunState::{Active, Disabled, Idle, Running};
        let groups = [
            ("IVPHELM_BHV_ACTIVE", "IVPHELM_BHV_ACTIVE_CNT", Active),
            ("IVPHELM_BHV_RUNNING", "IVPHELM_BHV_RUNNING_CNT", Running),
            ("IVPHELM_BHV_IDLE", "IVPHELM_BHV_IDLE_CNT", Idle),
            ("IVPHELM_BHV_DISABLED", "IVPHELM_BHV_DISABLED_CNT", Disabled),
        ];
        for (var, cnt_var, state) in groups {
            let len: usize = (self.behaviors.iter())
                .filter(|b| b.core.state == state)
                .map(|b| b.core.name.len() + 1)
                .sum();
            let mut names = self.pool.take_for(len);
            let mut n = 0;
            for b in self.behaviors.iter().filter(|b| b.core.state == state) {
                if n > 0 {
                    names.push(',');
                }
                names.push_str(&b.core.name);
                n += 1;
            }
            let last = self.last_posted.get(var).map_or("", |l| l.text.as_str());
            if mbutil::short_str::same(&names, last) {
                self.pool.give(names);
                continue;
            }
            self.post_str(var, &names);
            let posted = super::LastPosted {
                text: names,
                bits: None,
            };
            if let Some(old) = self.last_posted.insert(var, posted) {
                self.pool.give(old.text);
            }
            self.post_num(cnt_var, n as f64);
        }
    }
}
