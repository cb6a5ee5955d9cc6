//! Templating: behaviors spawned at run time from `templating = spawn|clone` blocks
//! (bhv-format.md §9).

use bhv::reader::BehaviorSpec;

use super::instance::make_instance;
use super::Helm;
use crate::posting::Value;
use crate::runtime::{apply_config_line, spawned};

/// A `.bhv` block that can spawn behaviors.
#[derive(Debug)]
pub(crate) struct Template {
    pub spec: BehaviorSpec,
    pub made: u32,
    pub tried: u32,
}

impl Template {
    pub fn new(spec: BehaviorSpec) -> Self {
        Template {
            spec,
            made: 0,
            tried: 0,
        }
    }
}

/// Split an update string into `key=value` pairs at `#`, outside double quotes.
fn pairs(update: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, c) in update.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted => {
                out.push(&update[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&update[start..]);
    out
}

/// The `name` field of an update string; "" if some field is not exactly `key=value`.
fn name_field(update: &str) -> String {
    let mut name = String::new();
    for p in pairs(update) {
        let Some((k, v)) = p.split_once('=') else {
            return String::new();
        };
        if k.trim() == "name" {
            name = v.trim().to_string();
        }
    }
    name
}

impl Helm {
    fn has_behavior(&self, name: &str) -> bool {
        self.behaviors.iter().any(|b| b.core.name == name)
    }

    /// Process this iteration's spawn requests of every template.
    pub(crate) fn process_spawns(&mut self, now: f64) {
        let mut warnings = Vec::new();
        for t in 0..self.templates.len() {
            // Borrowed: nothing is copied unless a request came (the usual case).
            let Some(var) = &self.templates[t].spec.updates_var else {
                continue;
            };
            let requests: Vec<String> = self
                .ib
                .string_deltas(var)
                .iter()
                .filter(|u| u.contains("name"))
                .cloned()
                .collect();
            for u in requests {
                let n = name_field(&u);
                let prefix = self.templates[t].spec.name_prefix.clone();
                let full = format!("{prefix}{n}");
                let max = self.templates[t].spec.max_spawnings;
                let free = !self.has_behavior(&full) && !self.has_behavior(&n);
                if free && (max == 0 || self.templates[t].made < max) {
                    self.templates[t].tried += 1;
                    match self.spawn_one(t, &u, &n, &prefix) {
                        Ok(name) => {
                            self.templates[t].made += 1;
                            self.bhv_cnt_ever += 1;
                            let ty = self.templates[t].spec.type_name.clone();
                            self.life_events
                                .push(format!("bname={name}, btype={ty}, event=spawn, seed={u}"));
                        }
                        Err(w) => {
                            let ty = self.templates[t].spec.type_name.clone();
                            self.life_events
                                .push(format!("bname={full}, btype={ty}, event=abort, seed={u}"));
                            warnings.push(w);
                        }
                    }
                }
                if !self.has_behavior(&full) && !self.has_behavior(&n) {
                    warnings.push(format!(
                        "Behavior named [{n}] or [{full}] not found or spawned."
                    ));
                }
            }
        }
        for (i, w) in warnings.into_iter().enumerate() {
            self.run_warning(&w);
            self.post("IVPHELM_BHVSET_WARNING", Value::Str(format!("{i}:{w}")), "");
        }
        let _ = now;
    }

    /// Build a behavior from template `t` and apply the update's pairs to it.
    fn spawn_one(
        &mut self,
        t: usize,
        update: &str,
        n: &str,
        prefix: &str,
    ) -> Result<String, String> {
        let spec = &self.templates[t].spec;
        let ownship = self.env.ownship.clone();
        let mut inst = make_instance(spec, &self.factory, &self.env, &self.ib, &ownship)
            .map_err(|e| format!("Failed to spawn {prefix}{n}. Bad config: {}", e.join("; ")))?;
        for p in pairs(update) {
            let (k, v) = p.split_once('=').unwrap_or((p, ""));
            let (k, v) = (k.trim(), v.trim());
            let ok = if k == "name" {
                let name = if n.starts_with(&inst.core.name) {
                    n.to_string()
                } else {
                    format!("{prefix}{n}")
                };
                apply_config_line(&mut inst, &self.env, &self.ib, "name", &name) == Ok(true)
            } else {
                apply_config_line(&mut inst, &self.env, &self.ib, k, v) == Ok(true)
            };
            if !ok {
                return Err(format!(
                    "Failed to spawn {}. Bad config: {p}",
                    inst.core.name
                ));
            }
        }
        inst.core.spawn_prefix = Some(prefix.to_string());
        spawned(&mut inst, &self.env, &self.ib);
        let name = inst.core.name.clone();
        self.behaviors.push(inst);
        Ok(name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn name_field_rules() {
        assert_eq!(name_field("name=abc # speed=2"), "abc");
        assert_eq!(name_field("speed=2#name=x"), "x");
        assert_eq!(name_field("name=abc # junk"), "");
        assert_eq!(pairs("a=\"x#y\"#b=2"), vec!["a=\"x#y\"", "b=2"]);
    }
}
