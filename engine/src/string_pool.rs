//! Spare strings whose allocations the next postings reuse (issue 19: the decision
//! path allocates nothing in steady state).
//!
//! Postings and behavior messages own their strings; when a batch of postings has been
//! handed out, its strings come back here cleared, and the next iteration's postings are
//! written into them. Capacities only grow, so once every string has been as long as the
//! longest text it is used for, no more allocation happens.

/// A stack of cleared strings.
#[derive(Debug, Default)]
pub struct StringPool {
    spare: Vec<String>,
}

/// More spare strings than any iteration uses are let go (a burst of postings, e.g. a
/// behavior-set restart, should not pin its memory for the rest of the run).
const MAX_SPARE: usize = 4096;

impl StringPool {
    /// An empty string, with a previous allocation when one is spare.
    pub fn take(&mut self) -> String {
        self.spare.pop().unwrap_or_default()
    }

    /// A copy of `text` in a spare string.
    pub fn copy_of(&mut self, text: &str) -> String {
        let mut s = self.take();
        s.push_str(text);
        s
    }

    /// Keep `s`'s allocation for a later `take`.
    pub fn give(&mut self, mut s: String) {
        if s.capacity() > 0 && self.spare.len() < MAX_SPARE {
            s.clear();
            self.spare.push(s);
        }
    }

    /// Keep the string of a string value (a number has none).
    pub fn give_value(&mut self, value: crate::posting::Value) {
        if let crate::posting::Value::Str(s) = value {
            self.give(s);
        }
    }

    /// Spare strings held.
    pub fn len(&self) -> usize {
        self.spare.len()
    }

    pub fn is_empty(&self) -> bool {
        self.spare.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_come_back_cleared_with_their_allocation() {
        let mut pool = StringPool::default();
        assert_eq!(pool.take(), "");
        let mut s = String::with_capacity(64);
        s.push_str("BHV_IPF");
        let ptr = s.as_ptr();
        pool.give(s);
        pool.give(String::new());
        assert_eq!(pool.len(), 1);
        let t = pool.copy_of("x");
        assert_eq!((t.as_str(), t.as_ptr()), ("x", ptr));
        assert!(pool.is_empty());
        pool.give_value(crate::posting::Value::Num(1.0));
        assert!(pool.is_empty());
        pool.give_value(crate::posting::Value::Str(t));
        let back = pool.take();
        assert_eq!(back.as_ptr(), ptr);
    }
}
