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
            Value::Str(s) if !s.is_empty() => {
                let same = self.strings.get(key).is_some_and(|old| old == s);
                if repeatable || !same {
                    // Copied into the kept string (no new allocation once it is long
                    // enough).
                    match self.strings.get_mut(key) {
                        Some(old) => {
                            old.clear();
                            old.push_str(s);
                        }
                        None => {
                            self.strings.insert(key.to_string(), s.clone());
                        }
                    }
                    return true;
                }
                false
            }
            Value::Str(_) => self.allow_number(key, 0.0, repeatable),
            Value::Num(v) => self.allow_number(key, *v, repeatable),
        }
    }

    fn allow_number(&mut self, key: &str, v: f64, repeatable: bool) -> bool {
        let same = self.numbers.get(key).is_some_and(|old| *old == v);
        if repeatable || !same {
            remember(&mut self.numbers, key, v);
            return true;
        }
        false
    }

    /// HELM_MAP_CLEAR refresh: everything is published once more.
    pub fn clear(&mut self) {
        self.strings.clear();
        self.numbers.clear();
    }
}

fn remember<V>(map: &mut HashMap<String, V>, key: &str, v: V) {
    if let Some(slot) = map.get_mut(key) {
        *slot = v;
    } else {
        map.insert(key.to_string(), v);
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
