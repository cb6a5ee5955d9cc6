//! Spare strings whose allocations the next texts reuse (the helm's decision path
//! allocates nothing in steady state, issue 19).
//!
//! Postings and behavior messages own their strings; when a batch of postings has been
//! handed out, its strings come back here cleared, and the next iteration's postings are
//! written into them. Capacities only grow, so once every string has been as long as the
//! longest text it is used for, no more allocation happens.

/// Stacks of cleared strings: short ones, and long ones (BHV_IPF packets) kept apart so
/// that a long text never gets a short string that must grow.
#[derive(Debug, Default)]
pub struct StringPool {
    spare: Vec<String>,
    long: Vec<String>,
}

/// Capacity from which a string is kept for long texts.
const LONG: usize = 1024;

/// More spare strings than any iteration uses are let go (a burst of postings, e.g. a
/// behavior-set restart, should not pin its memory for the rest of the run).
const MAX_SPARE: usize = 4096;

impl StringPool {
    /// An empty string, with a previous allocation when one is spare.
    /// (A long one only when no short one is left: whenever the pool is not empty,
    /// `take` gives a held string.)
    pub fn take(&mut self) -> String {
        self.spare
            .pop()
            .or_else(|| self.long.pop())
            .unwrap_or_default()
    }

    /// An empty string for a long text (up to a few KB), with a previous long
    /// allocation when one is spare.
    pub fn take_long(&mut self) -> String {
        self.long
            .pop()
            .or_else(|| self.spare.pop())
            .unwrap_or_default()
    }

    /// A copy of `text` in a spare string.
    pub fn copy_of(&mut self, text: &str) -> String {
        let mut s = self.take();
        s.push_str(text);
        s
    }

    /// Keep `s`'s allocation for a later `take`.
    pub fn give(&mut self, mut s: String) {
        let stack = if s.capacity() >= LONG {
            &mut self.long
        } else {
            &mut self.spare
        };
        if s.capacity() > 0 && stack.len() < MAX_SPARE {
            s.clear();
            stack.push(s);
        }
    }

    /// Spare strings held.
    pub fn len(&self) -> usize {
        self.spare.len() + self.long.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
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
        pool.give(t);
        let back = pool.take();
        assert_eq!(back.as_ptr(), ptr);
    }

    #[test]
    fn long_texts_get_the_long_strings_back() {
        let mut pool = StringPool::default();
        let long = String::with_capacity(2048);
        let ptr = long.as_ptr();
        pool.give(long);
        pool.give(String::with_capacity(16));
        // A short take leaves the long string for the long text.
        assert!(pool.take().capacity() < LONG);
        let t = pool.take_long();
        assert_eq!(t.as_ptr(), ptr);
        // No long one spare: a short one, then a new one.
        pool.give(String::with_capacity(8));
        assert_eq!(pool.take_long().capacity(), 8);
        assert_eq!(pool.take_long().capacity(), 0);
        // A short take falls back on a long string: a pool that is not empty always
        // gives a held string (callers move strings between pools until empty).
        pool.give(String::with_capacity(4096));
        assert!(!pool.is_empty());
        assert!(pool.take().capacity() >= LONG);
        assert!(pool.is_empty());
    }
}
