//! Mode declarations (`set` blocks), bhv-format.md §6.

use crate::error::LogicError;
use crate::logic::{LogicCondition, VarSource};
use crate::number::{atof, compact, is_number};

/// One `set <VAR> = <VALUE> { ... } [<ELSE>]` block.
#[derive(Clone, Debug)]
pub struct ModeEntry {
    var: String,
    value: String,
    else_value: Option<String>,
    prefix: Option<String>,
    conditions: Vec<LogicCondition>,
    modevar_cond: Option<usize>,
    var_idx: usize,
}

impl ModeEntry {
    /// A new entry assigning `value` to the mode variable `var`.
    pub fn new(var: &str, value: &str) -> ModeEntry {
        ModeEntry {
            var: var.to_string(),
            value: value.to_string(),
            else_value: None,
            prefix: None,
            conditions: Vec::new(),
            modevar_cond: None,
            var_idx: 0,
        }
    }

    /// Adds one condition line (mode grammar: no `==`, commas kept) and
    /// performs the prefix detection of §6.1.
    pub fn add_condition(&mut self, text: &str) -> Result<(), LogicError> {
        let cond = LogicCondition::parse_mode(text)?;
        if self.prefix.is_none() {
            if let Some((left, right)) = text.split_once('=') {
                let right = right.trim();
                if left.trim() == self.var && !right.is_empty() {
                    self.prefix = Some(right.to_string());
                    self.modevar_cond = Some(self.conditions.len());
                }
            }
        }
        self.conditions.push(cond);
        Ok(())
    }

    /// Sets the else-value.
    pub fn set_else_value(&mut self, v: &str) {
        self.else_value = Some(v.to_string());
    }

    /// The mode variable.
    pub fn var(&self) -> &str {
        &self.var
    }
    /// The value assigned when all conditions hold.
    pub fn value(&self) -> &str {
        &self.value
    }
    /// The else-value, if any.
    pub fn else_value(&self) -> Option<&str> {
        self.else_value.as_deref()
    }
    /// The parent prefix (§6.1), if any.
    pub fn prefix(&self) -> Option<&str> {
        self.prefix.as_deref()
    }
    /// The conditions, in order.
    pub fn conditions(&self) -> &[LogicCondition] {
        &self.conditions
    }

    fn parent(&self) -> &str {
        match &self.prefix {
            Some(p) => p.rsplit(':').next().unwrap_or(p).trim(),
            None => "---",
        }
    }
}

/// All mode entries of a behavior set, in file order, with the state of
/// the last evaluation.
///
/// ```
/// use bhv::modes::{ModeEntry, ModeSet};
/// use bhv::number::Value;
/// use std::collections::HashMap;
/// let mut e = ModeEntry::new("MODE", "ACTIVE");
/// e.add_condition("DEPLOY = true").unwrap();
/// e.set_else_value("INACTIVE");
/// let mut m = ModeSet::default();
/// m.push(e);
/// let mut info = HashMap::new();
/// info.insert("DEPLOY".to_string(), Value::Str("true".into()));
/// assert_eq!(m.evaluate(&info), &[("MODE".to_string(), "ACTIVE".to_string())]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct ModeSet {
    entries: Vec<ModeEntry>,
    /// Distinct mode variables, sorted by name.
    mode_vars: Vec<String>,
    /// Per mode variable: value computed in this evaluation.
    values: Vec<String>,
    assigned: Vec<bool>,
    /// Output buffer (reused); the first `n_out` pairs are current.
    out: Vec<(String, String)>,
    n_out: usize,
}

impl ModeSet {
    /// Appends an entry (file order).
    pub fn push(&mut self, mut entry: ModeEntry) {
        if let Err(pos) = self.mode_vars.binary_search(&entry.var) {
            self.mode_vars.insert(pos, entry.var.clone());
            self.values.insert(pos, String::new());
            self.assigned.insert(pos, false);
        }
        entry.var_idx = 0;
        self.entries.push(entry);
        for e in &mut self.entries {
            e.var_idx = self.mode_vars.binary_search(&e.var).unwrap_or(0);
        }
    }

    /// No entries.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The entries in file order.
    pub fn entries(&self) -> &[ModeEntry] {
        &self.entries
    }

    /// The distinct mode variables (left sides of `set`), sorted by name.
    pub fn mode_vars(&self) -> &[String] {
        &self.mode_vars
    }

    /// All variables read by mode conditions, de-duplicated, in order of
    /// appearance.
    pub fn vars(&self) -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        for c in self.entries.iter().flat_map(|e| &e.conditions) {
            for name in c.vars() {
                if !v.contains(name) {
                    v.push(name.clone());
                }
            }
        }
        v
    }

    /// One evaluation (§6.2). Returns the (mode variable, value) pairs
    /// assigned in this evaluation, sorted by variable name. The caller
    /// types them (numeric if a number) and writes them to the info buffer.
    pub fn evaluate(&mut self, src: &dyn VarSource) -> &[(String, String)] {
        let ModeSet {
            entries,
            mode_vars,
            values,
            assigned,
            out,
            n_out,
        } = self;
        for c in entries.iter_mut().flat_map(|e| e.conditions.iter_mut()) {
            c.update(src);
        }
        assigned.iter_mut().for_each(|a| *a = false);
        for i in 0..entries.len() {
            let e = &entries[i];
            let candidate: &str = if e.conditions.iter().all(LogicCondition::eval) {
                &e.value
            } else if e.modevar_cond.is_none_or(|k| e.conditions[k].eval()) {
                e.else_value.as_deref().unwrap_or("")
            } else {
                ""
            };
            if candidate.is_empty() {
                continue;
            }
            let vi = e.var_idx;
            let buf = &mut values[vi];
            buf.clear();
            if let Some(p) = &e.prefix {
                buf.push_str(p);
                buf.push(':');
            }
            buf.push_str(candidate);
            assigned[vi] = true;
            let (var, val) = (&mode_vars[vi], &values[vi]);
            for c in entries.iter_mut().flat_map(|e| e.conditions.iter_mut()) {
                c.set_string(var, val);
            }
        }
        let mut k = 0;
        for vi in 0..mode_vars.len() {
            if !assigned[vi] {
                continue;
            }
            if k < out.len() {
                out[k].0.clear();
                out[k].0.push_str(&mode_vars[vi]);
                out[k].1.clear();
                out[k].1.push_str(&values[vi]);
            } else {
                out.push((mode_vars[vi].clone(), values[vi].clone()));
            }
            k += 1;
        }
        *n_out = k;
        &out[..k]
    }

    /// The pairs of the last evaluation (empty before the first).
    pub fn current(&self) -> &[(String, String)] {
        &self.out[..self.n_out]
    }

    /// The `IVPHELM_MODESET` string (§6.3); empty without entries.
    pub fn modeset_string(&self) -> String {
        let mut s = String::new();
        for (i, e) in self.entries.iter().enumerate() {
            if i > 0 {
                s.push('#');
            }
            if i == 0 || self.entries[i - 1].var != e.var {
                s.push_str(&e.var);
                s.push('#');
            }
            let parent = e.parent();
            s.push_str(parent);
            s.push(',');
            s.push_str(&e.value);
            if let Some(ev) = &e.else_value {
                s.push('#');
                s.push_str(parent);
                s.push(',');
                s.push_str(ev);
            }
        }
        s
    }

    /// The mode summary of `IVPHELM_SUMMARY` (§6.3): `<VAR>@<value>` for
    /// each variable assigned by the last evaluation, sorted by name, joined
    /// by `#`, numeric values compacted; `none` when nothing is assigned.
    pub fn summary(&self) -> String {
        let cur = self.current();
        if cur.is_empty() {
            return "none".to_string();
        }
        let parts: Vec<String> = cur
            .iter()
            .map(|(var, val)| {
                if is_number(val) {
                    format!("{var}@{}", compact(atof(val), 6))
                } else {
                    format!("{var}@{val}")
                }
            })
            .collect();
        parts.join("#")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::number::Value;
    use std::collections::HashMap;

    fn info(pairs: &[(&str, &str)]) -> HashMap<String, Value> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), Value::Str(v.to_string())))
            .collect()
    }

    /// The example of §6.2.
    fn example() -> ModeSet {
        let mut m = ModeSet::default();
        let mut e = ModeEntry::new("MODE", "ACTIVE");
        e.add_condition("DEPLOY = true").unwrap();
        e.set_else_value("INACTIVE");
        m.push(e);
        let mut e = ModeEntry::new("MODE", "RETURNING");
        e.add_condition("MODE = ACTIVE").unwrap();
        e.add_condition("RETURN = true").unwrap();
        e.set_else_value("SURVEYING");
        m.push(e);
        m
    }

    fn pairs(v: &[(String, String)]) -> Vec<(&str, &str)> {
        v.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect()
    }

    #[test]
    fn prefix_detection() {
        let m = example();
        assert_eq!(m.entries()[0].prefix(), None);
        assert_eq!(m.entries()[1].prefix(), Some("ACTIVE"));
        let mut e = ModeEntry::new("MODE", "X");
        e.add_condition("MODE != ACTIVE").unwrap();
        e.add_condition("MODE = A:B").unwrap();
        e.add_condition("MODE = C").unwrap();
        assert_eq!(e.prefix(), Some("A:B"));
        assert_eq!(e.modevar_cond, Some(1));
    }

    #[test]
    fn evaluation_example() {
        let mut m = example();
        let out = m.evaluate(&info(&[("DEPLOY", "true"), ("RETURN", "false")]));
        assert_eq!(pairs(out), [("MODE", "ACTIVE:SURVEYING")]);
        let out = m.evaluate(&info(&[("DEPLOY", "true"), ("RETURN", "true")]));
        assert_eq!(pairs(out), [("MODE", "ACTIVE:RETURNING")]);
        assert_eq!(m.summary(), "MODE@ACTIVE:RETURNING");
        let mut m = example();
        let out = m.evaluate(&info(&[("DEPLOY", "false"), ("RETURN", "false")]));
        assert_eq!(pairs(out), [("MODE", "INACTIVE")]);
    }

    #[test]
    fn unposted_variable_blocks_value() {
        // RETURN never posted: `RETURN = true` false, so else-value.
        let mut m = example();
        let out = m.evaluate(&info(&[("DEPLOY", "true")]));
        assert_eq!(pairs(out), [("MODE", "ACTIVE:SURVEYING")]);
        // and `RETURN != true` is false as well
        let mut m = ModeSet::default();
        let mut e = ModeEntry::new("MODE", "GO");
        e.add_condition("RETURN != true").unwrap();
        m.push(e);
        assert!(m.evaluate(&info(&[])).is_empty());
        assert_eq!(m.summary(), "none");
    }

    #[test]
    fn later_entries_overwrite_and_see_value() {
        let mut m = ModeSet::default();
        let mut e = ModeEntry::new("MODE", "A");
        e.add_condition("X = 1").unwrap();
        m.push(e);
        let mut e = ModeEntry::new("MODE", "B");
        e.add_condition("MODE = A").unwrap();
        e.add_condition("Y = 1").unwrap();
        m.push(e);
        let mut e = ModeEntry::new("ZED", "ON");
        e.add_condition("MODE = A:B").unwrap();
        m.push(e);
        let mut e = ModeEntry::new("AAA", "7");
        e.add_condition("X = 1").unwrap();
        m.push(e);
        let mut src: HashMap<String, Value> = HashMap::new();
        src.insert("X".into(), Value::Num(1.0));
        src.insert("Y".into(), Value::Num(1.0));
        let out = m.evaluate(&src);
        assert_eq!(
            pairs(out),
            [("AAA", "7"), ("MODE", "A:B"), ("ZED", "ON")],
            "sorted by variable name"
        );
        assert_eq!(m.summary(), "AAA@7#MODE@A:B#ZED@ON");
        // Unassigned variables are not reported; slots persist, so the
        // conditions still see MODE = A:B from the last assignment.
        src.insert("X".into(), Value::Num(0.0));
        let out = m.evaluate(&src);
        assert_eq!(pairs(out), [("ZED", "ON")]);
        assert_eq!(pairs(m.current()), [("ZED", "ON")]);
        src.insert("MODE".into(), Value::Str("Q".into()));
        assert!(m.evaluate(&src).is_empty());
        assert!(m.current().is_empty());
    }

    #[test]
    fn mode_var_without_condition_is_vacuous_for_else() {
        let mut m = ModeSet::default();
        let mut e = ModeEntry::new("M", "ON");
        e.add_condition("X = 1").unwrap();
        e.set_else_value("OFF");
        m.push(e);
        let out = m.evaluate(&info(&[]));
        assert_eq!(pairs(out), [("M", "OFF")]);
    }

    #[test]
    fn modeset_string_example() {
        assert_eq!(
            example().modeset_string(),
            "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING"
        );
        let mut m = example();
        let mut e = ModeEntry::new("MODE", "LEG");
        e.add_condition("MODE = ACTIVE:SURVEYING").unwrap();
        m.push(e);
        let mut e = ModeEntry::new("OTHER", "X");
        e.add_condition("A = 1").unwrap();
        m.push(e);
        assert_eq!(
            m.modeset_string(),
            "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING#SURVEYING,LEG#OTHER#---,X"
        );
        assert_eq!(ModeSet::default().modeset_string(), "");
        assert_eq!(
            m.vars(),
            ["DEPLOY", "MODE", "RETURN", "A"].map(String::from).to_vec()
        );
    }

    #[test]
    fn numeric_summary_compacted() {
        let mut m = ModeSet::default();
        let mut e = ModeEntry::new("LVL", "3.50");
        e.add_condition("X = 1").unwrap();
        m.push(e);
        let mut src: HashMap<String, Value> = HashMap::new();
        src.insert("X".into(), Value::Num(1.0));
        m.evaluate(&src);
        assert_eq!(m.summary(), "LVL@3.5");
    }

    #[test]
    fn field_match_rejected() {
        let mut e = ModeEntry::new("MODE", "X");
        assert!(e.add_condition("MODE == ACTIVE").is_err());
    }
}
