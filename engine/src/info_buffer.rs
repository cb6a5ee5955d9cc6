//! The info buffer: the behaviors' view of MOOS data (behavior-common.md §7).

use bhv::logic::{Stamps, VarSource};

#[derive(Debug, Default, Clone)]
struct Entry {
    sval: Option<String>,
    dval: Option<f64>,
    /// Buffer time of the last write (any type).
    time: f64,
    /// Timestamp of the message that last wrote it.
    msg_time: f64,
    /// This iteration's strings are the first `str_count`; the strings past it are
    /// spare, never read (the next iteration's deltas reuse their room, and their
    /// text when it is the same).
    str_deltas: Vec<String>,
    str_count: usize,
    dbl_deltas: Vec<f64>,
}

/// Latest values per variable, their times, and this iteration's values.
#[derive(Debug, Default)]
pub struct InfoBuffer {
    /// Each variable's place in `entries`, looked up many times per iteration by name
    /// (short names without hashing their bytes). A place rather than the entry: a write
    /// finds an existing variable with one look-up, and a new one is added without a
    /// second.
    index: mbutil::NameIndex,
    entries: Vec<Entry>,
    /// Places of the variables with deltas this iteration, so clearing touches only
    /// those.
    touched: Vec<usize>,
    /// Lets conditions skip the variables not written since they last read them.
    stamps: Stamps,
    /// Places of `<NAME>_NAV_GROUP` and `_NAV_TYPE` by contact name.
    nav_places: Vec<(String, [usize; 2])>,
    curr_time: f64,
    start_time: f64,
}

impl InfoBuffer {
    pub fn new(start_time: f64) -> Self {
        InfoBuffer {
            curr_time: start_time,
            start_time,
            ..Default::default()
        }
    }

    pub fn set_curr_time(&mut self, t: f64) {
        self.curr_time = t;
    }
    pub fn curr_time(&self) -> f64 {
        self.curr_time
    }
    pub fn local_time(&self) -> f64 {
        self.curr_time - self.start_time
    }

    /// `var`'s place in `entries`, made on first sight.
    fn place(&mut self, var: &str) -> usize {
        if let Some(i) = self.index.get(var) {
            return i;
        }
        self.entries.push(Entry::default());
        self.index.insert(var, self.entries.len() - 1);
        self.entries.len() - 1
    }

    /// The entry at `i`, for a write with a delta: stamped, and listed for clearing at
    /// its first delta of the iteration.
    fn entry_at(&mut self, i: usize) -> &mut Entry {
        self.stamps.write(i);
        let e = &mut self.entries[i];
        if e.str_count == 0 && e.dbl_deltas.is_empty() {
            self.touched.push(i);
        }
        e
    }

    /// Inlined: every behavior reads NAV_X, NAV_Y, ... through it every iteration, and
    /// the lookup is a few instructions beside the call's own (left to itself, the
    /// compiler keeps it a call).
    #[inline(always)]
    fn get(&self, var: &str) -> Option<&Entry> {
        self.index.get(var).map(|i| &self.entries[i])
    }

    pub fn set_string(&mut self, var: &str, val: &str, msg_time: f64) {
        let i = self.place(var);
        self.set_string_at(i, val, msg_time);
    }

    /// A contact's group and type, as `<NAME>_NAV_GROUP` and `<NAME>_NAV_TYPE` (from
    /// every contact every second: each contact's two places are found once).
    pub fn set_contact_nav(&mut self, name: &str, group: &str, vtype: &str, msg_time: f64) {
        let found = (self.nav_places.iter())
            .find(|(n, _)| mbutil::short_str::same(n, name))
            .map(|e| e.1);
        let [g, t] = found.unwrap_or_else(|| {
            let mut var = String::new();
            let places = ["GROUP", "TYPE"].map(|suffix| {
                contacts::ledger::nav_var(&mut var, name, suffix);
                self.place(&var)
            });
            self.nav_places.push((name.to_string(), places));
            places
        });
        self.set_string_at(g, group, msg_time);
        self.set_string_at(t, vtype, msg_time);
    }

    fn set_string_at(&mut self, i: usize, val: &str, msg_time: f64) {
        let now = self.curr_time;
        let e = self.entry_at(i);
        // Mostly the value it had (a mode, a contact's type): not copied again.
        match &mut e.sval {
            Some(s) => mbutil::short_str::assign(s, val),
            None => e.sval = Some(val.to_string()),
        }
        e.time = now;
        e.msg_time = msg_time;
        push_reused(&mut e.str_deltas, &mut e.str_count, val);
    }

    pub fn set_double(&mut self, var: &str, val: f64, msg_time: f64) {
        let now = self.curr_time;
        let i = self.place(var);
        let e = self.entry_at(i);
        e.dval = Some(val);
        e.time = now;
        e.msg_time = msg_time;
        e.dbl_deltas.push(val);
    }

    pub fn set_value(&mut self, var: &str, val: &crate::posting::Value, msg_time: f64) {
        match val {
            crate::posting::Value::Str(s) => self.set_string(var, s, msg_time),
            crate::posting::Value::Num(v) => self.set_double(var, *v, msg_time),
        }
    }

    pub fn is_known(&self, var: &str) -> bool {
        self.index.get(var).is_some()
    }
    pub fn dval(&self, var: &str) -> Option<f64> {
        self.get(var).and_then(|e| e.dval)
    }
    pub fn sval(&self, var: &str) -> Option<&str> {
        self.get(var).and_then(|e| e.sval.as_deref())
    }

    /// `getBufferDoubleVal`: the number, else a numeric string converted, else the
    /// `_DELTA` convention, else none.
    pub fn double_val(&self, var: &str) -> Option<f64> {
        if let Some(e) = self.get(var) {
            if let Some(d) = e.dval {
                return Some(d);
            }
            return e.sval.as_deref().and_then(mbutil::parse_number);
        }
        let base = var.strip_suffix("_DELTA")?;
        let v = self.double_val(base)?;
        Some(self.curr_time - v)
    }

    /// `getBufferStringVal`: the string, else the number printed `%.6f`.
    pub fn string_val(&self, var: &str) -> Option<String> {
        let e = self.get(var)?;
        if let Some(s) = &e.sval {
            return Some(s.clone());
        }
        e.dval.map(|d| format!("{d:.6}"))
    }

    /// Seconds since the variable was last written; -1 if never.
    pub fn time_val(&self, var: &str) -> f64 {
        self.get(var).map_or(-1.0, |e| self.curr_time - e.time)
    }
    /// Seconds since the timestamp of the message that last wrote it; -1 if never.
    pub fn msg_time_val(&self, var: &str) -> f64 {
        self.get(var).map_or(-1.0, |e| self.curr_time - e.msg_time)
    }
    /// Buffer time of the last write, if any.
    pub fn update_time(&self, var: &str) -> Option<f64> {
        self.get(var).map(|e| e.time)
    }

    pub fn string_deltas(&self, var: &str) -> &[String] {
        self.get(var).map_or(&[], |e| &e.str_deltas[..e.str_count])
    }
    pub fn double_deltas(&self, var: &str) -> &[f64] {
        self.get(var).map_or(&[], |e| &e.dbl_deltas)
    }

    /// End of an iteration (or parked): this iteration's values are forgotten.
    pub fn clear_deltas(&mut self) {
        for &i in &self.touched {
            let e = &mut self.entries[i];
            e.str_count = 0;
            e.dbl_deltas.clear();
        }
        self.touched.clear();
    }
}

/// Append `text` as the `count`th string of `list`, reusing a kept string's allocation.
fn push_reused(list: &mut Vec<String>, count: &mut usize, text: &str) {
    match list.get_mut(*count) {
        Some(slot) => mbutil::short_str::assign(slot, text),
        None => list.push(text.to_string()),
    }
    *count += 1;
}

impl VarSource for InfoBuffer {
    fn string_val(&self, var: &str) -> Option<&str> {
        self.sval(var)
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        self.dval(var)
    }
    fn stamps(&self) -> Option<&Stamps> {
        Some(&self.stamps)
    }
    fn place(&self, var: &str) -> Option<usize> {
        self.index.get(var)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_times_and_deltas() {
        let mut b = InfoBuffer::new(100.0);
        assert_eq!(b.time_val("X"), -1.0);
        b.set_double("X", 3.0, 100.0);
        b.set_string("X", "abc", 100.0);
        assert_eq!(b.dval("X"), Some(3.0));
        assert_eq!(b.sval("X"), Some("abc"));
        assert_eq!(b.string_deltas("X"), ["abc".to_string()]);
        b.set_curr_time(101.5);
        assert_eq!(b.time_val("X"), 1.5);
        b.clear_deltas();
        assert!(b.double_deltas("X").is_empty());
        assert_eq!(b.string_val("Y"), None);
        b.set_double("Y", 2.0, 101.5);
        assert_eq!(b.string_val("Y").as_deref(), Some("2.000000"));
        assert_eq!(b.double_val("Y_DELTA"), Some(99.5));
    }
}
