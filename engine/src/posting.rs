//! Postings leaving the helm, and the duplicate ("key") filter of helm.md §8.1.

use rustc_hash::FxHashMap as HashMap;

pub use bhv::number::Value;

/// Keep the string of a string value for later postings (a number has none).
pub(crate) fn give_value(pool: &mut mbutil::StringPool, value: Value) {
    if let Value::Str(s) = value {
        pool.give(s);
    }
}

/// One publication of the helm: what goes out to MOOS.
#[derive(Clone, Debug, PartialEq)]
pub struct Posting {
    pub var: String,
    pub value: Value,
    pub source_aux: String,
}

/// Remembers the last string and number published under each key.
#[derive(Default, Debug)]
pub struct DuplicateFilter {
    strings: HashMap<String, String>,
    numbers: HashMap<String, f64>,
}

impl DuplicateFilter {
    /// Whether a message with `key` and `value` is to be published; remembers it if so.
    /// An empty string is compared in the number table as 0 (the real helm's quirk).
    pub fn allow(&mut self, key: &str, value: &Value) -> bool {
        let repeatable = key.eq_ignore_ascii_case("repeatable");
        match value {
            // One look-up: a changed value is copied into the kept string (no new
            // allocation once it is long enough).
            Value::Str(s) if !s.is_empty() => match self.strings.get_mut(key) {
                Some(old) if repeatable || !mbutil::short_str::same(old, s) => {
                    old.clear();
                    old.push_str(s);
                    true
                }
                Some(_) => false,
                None => {
                    self.strings.insert(key.to_string(), s.clone());
                    true
                }
            },
            Value::Str(_) => self.allow_number(key, 0.0, repeatable),
            Value::Num(v) => self.allow_number(key, *v, repeatable),
        }
    }

    fn allow_number(&mut self, key: &str, v: f64, repeatable: bool) -> bool {
        match self.numbers.get_mut(key) {
            Some(old) if repeatable || *old != v => {
                *old = v;
                true
            }
            Some(_) => false,
            None => {
                self.numbers.insert(key.to_string(), v);
                true
            }
        }
    }

    /// HELM_MAP_CLEAR refresh: everything is published once more.
    pub fn clear(&mut self) {
        self.strings.clear();
        self.numbers.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_repeats_per_key_and_type() {
        let mut f = DuplicateFilter::default();
        assert!(f.allow("aX", &Value::Str("1".into())));
        assert!(!f.allow("aX", &Value::Str("1".into())));
        assert!(f.allow("aX", &Value::Num(1.0)));
        assert!(!f.allow("aX", &Value::Num(1.0)));
        assert!(f.allow("bX", &Value::Num(1.0)));
        assert!(f.allow("repeatable", &Value::Num(1.0)));
        assert!(f.allow("repeatable", &Value::Num(1.0)));
    }

    #[test]
    fn empty_string_compares_as_zero() {
        let mut f = DuplicateFilter::default();
        assert!(f.allow("k", &Value::Num(0.0)));
        assert!(!f.allow("k", &Value::Str(String::new())));
        f.clear();
        assert!(f.allow("k", &Value::Str(String::new())));
    }
}
