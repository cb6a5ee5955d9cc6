//! Spare strings whose allocations the next texts reuse (the helm's decision path
//! allocates nothing in steady state, issue 19).
//!
//! Postings and behavior messages own their strings; when a batch of postings has been
//! handed out, its strings come back here cleared, and the next iteration's postings are
//! written into them. Capacities only grow, so once every string has been as long as the
//! longest text it is used for, no more allocation happens.

/// Cleared strings kept in stacks by the lengths they hold, so that a text is written
/// into a string that already fits it: strings of every length circulate through one
/// pool (names, values, BHV_IPF packets), and a plain stack would hand a short string to
/// a long text, which then grows (an allocation) though a fitting string sits below it.
///
/// Texts fall into length classes (below 16, then one per doubling, then long ones from
/// 1024). A string is kept in the highest class all of whose lengths it holds, and a
/// string made or grown here gets the whole of its class's room: so any string of a
/// text's class fits the text, and texts of steady lengths stop allocating once every
/// class has as many strings as an iteration takes from it.
#[derive(Debug, Default)]
pub struct StringPool {
    stacks: [Vec<String>; CLASSES],
    count: usize,
}

/// Length classes: `[0, 16)`, then `[8·2^k, 16·2^k)` for k = 1..6, then long (1024 up).
const CLASSES: usize = 8;
const LONG: usize = CLASSES - 1;

/// More spare strings than any iteration uses are let go (a burst of postings, e.g. a
/// behavior-set restart, should not pin its memory for the rest of the run).
const MAX_SPARE: usize = 4096;

/// The class of a text of `len` bytes.
fn class_of_len(len: usize) -> usize {
    ((usize::BITS - (len >> 4).leading_zeros()) as usize).min(LONG)
}

/// The room that holds every length of class `c` (below [`LONG`]).
fn room(c: usize) -> usize {
    (16 << c) - 1
}

/// The highest class whose every length fits in `cap` bytes (class 0 and long strings
/// may still be short for a given text).
fn class_of_cap(cap: usize) -> usize {
    if cap >= 1024 {
        LONG
    } else {
        ((usize::BITS - ((cap + 1) >> 4).leading_zeros()) as usize).saturating_sub(1)
    }
}

impl StringPool {
    /// An empty string, the smallest spare one (for a text of unknown length; prefer
    /// [`StringPool::take_for`] when the length is known).
    pub fn take(&mut self) -> String {
        self.take_for(0)
    }

    /// An empty string with room for `len` bytes: a spare one of `len`'s class or the
    /// next one up, else the largest spare one grown (or a new one) to the class's room.
    #[inline]
    pub fn take_for(&mut self, len: usize) -> String {
        let c0 = class_of_len(len);
        // The usual case, inlined: the top of the text's own class fits it. This is
        // the search below at its first step (same string), for the several strings
        // every behavior's messages take each iteration.
        if let Some(stack) = self.stacks.get_mut(c0) {
            if stack.last().is_some_and(|s| s.capacity() >= len) {
                if let Some(s) = stack.pop() {
                    self.count -= 1;
                    return s;
                }
            }
        }
        self.take_for_search(len, c0)
    }

    /// [`StringPool::take_for`] past its first step: the classes from `c0` up, then
    /// the largest smaller string grown (or a new one).
    #[inline(never)]
    fn take_for_search(&mut self, len: usize, c0: usize) -> String {
        for stack in self.stacks.iter_mut().skip(c0) {
            if stack.last().is_some_and(|s| s.capacity() >= len) {
                if let Some(s) = stack.pop() {
                    self.count -= 1;
                    return s;
                }
            }
        }
        let mut s = match (0..=c0).rev().find(|&c| !self.stacks[c].is_empty()) {
            Some(c) => {
                self.count -= 1;
                self.stacks[c].pop().unwrap_or_default()
            }
            None => String::new(),
        };
        if c0 < LONG {
            s.reserve_exact(room(c0));
        } else {
            s.reserve(len);
        }
        s
    }

    /// An empty string for a long text (up to a few KB): the largest spare one.
    pub fn take_long(&mut self) -> String {
        match (0..CLASSES).rev().find(|&c| !self.stacks[c].is_empty()) {
            Some(c) => {
                self.count -= 1;
                self.stacks[c].pop().unwrap_or_default()
            }
            None => String::new(),
        }
    }

    /// A copy of `text` in a spare string that fits it when one does.
    #[inline]
    pub fn copy_of(&mut self, text: &str) -> String {
        let mut s = self.take_for(text.len());
        s.push_str(text);
        s
    }

    /// Keep `s`'s allocation for a later `take`.
    pub fn give(&mut self, mut s: String) {
        if s.capacity() > 0 && self.count < MAX_SPARE {
            s.clear();
            self.stacks[class_of_cap(s.capacity())].push(s);
            self.count += 1;
        }
    }

    /// Spare strings held.
    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
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
        assert!(pool.take().capacity() < 1024);
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
        assert!(pool.take().capacity() >= 1024);
        assert!(pool.is_empty());
    }

    #[test]
    fn a_text_gets_a_string_that_fits_it_when_one_is_spare() {
        let mut pool = StringPool::default();
        for cap in [8, 200, 40, 17] {
            pool.give(String::with_capacity(cap));
        }
        let t = pool.copy_of(&"x".repeat(30));
        assert_eq!(t.capacity(), 40);
        let u = pool.copy_of(&"y".repeat(100));
        assert_eq!(u.capacity(), 200);
        // Within its own class a text may find the top just short: it looks higher.
        pool.give(String::with_capacity(20));
        pool.give(String::with_capacity(300));
        assert_eq!(pool.copy_of(&"z".repeat(25)).capacity(), 300);
        // Nothing fits: the largest smaller one grows.
        assert_eq!(pool.len(), 3);
        let big = pool.copy_of(&"w".repeat(500));
        assert!(big.capacity() >= 500);
        assert_eq!(pool.len(), 2);
        assert!(pool.take().capacity() < 32);
    }

    #[test]
    fn texts_of_steady_lengths_stop_growing_strings_after_one_round() {
        // A stand-in for the helm's iterations: each round takes strings for texts of
        // the same lengths in a shuffled order, then gives them all back.
        let mut lens: Vec<usize> = (0..300).map(|i| (i * 7919) % 700 + 1).collect();
        let mut pool = StringPool::default();
        let mut seed = 12345u64;
        let mut grown = Vec::new();
        let mut last: Vec<(usize, usize)> = Vec::new();
        for _ in 0..20 {
            for i in (1..lens.len()).rev() {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                lens.swap(i, (seed >> 33) as usize % (i + 1));
            }
            let mut out = Vec::new();
            for &len in &lens {
                let mut s = pool.take_for(len);
                assert!(s.capacity() >= len);
                s.extend(std::iter::repeat_n('a', len));
                out.push(s);
            }
            // Each allocation (new or grown) shows as a new (address, capacity).
            let mut held: Vec<(usize, usize)> = out
                .iter()
                .map(|s| (s.as_ptr() as usize, s.capacity()))
                .collect();
            held.sort_unstable();
            let n = held
                .iter()
                .filter(|h| last.binary_search(h).is_err())
                .count();
            grown.push(n);
            last = held;
            for s in out {
                pool.give(s);
            }
        }
        assert_eq!(grown[0], 300, "the first round allocates every string");
        assert!(grown[1..].iter().all(|&n| n == 0), "{grown:?}");
    }
}
