//! The text of boxes' intervals, kept: the piece loop copies an interval's text
//! (`,lo,hi`) where it would print it (see `PieceText::interval`).

thread_local! {
    /// The piece loop's interval caches, kept from call to call: a behavior's tiling
    /// is the same every iteration (and behaviors' tilings share intervals).
    pub(crate) static INTERVALS: std::cell::Cell<Option<Box<IntervalCaches>>> =
        const { std::cell::Cell::new(None) };
}

/// One [`IntervalCache`] per dimension of the unrolled piece loops.
#[derive(Default)]
pub(crate) struct IntervalCaches(pub(crate) [IntervalCache; 3]);

/// The text (`,lo,hi`) of a dimension's recent intervals. A tiling repeats each
/// dimension's few intervals from piece to piece: copying their text is cheaper than
/// printing it. Direct-mapped by `lo` (no two meet below `SLOTS`); only texts of up to
/// 8 bytes are kept.
pub(crate) struct IntervalCache {
    /// `(lo, hi)` as in memory (`lo` low); slot `s` starts with a `lo` not `s` (never
    /// matched).
    pub(crate) keys: [u64; IntervalCache::SLOTS],
    /// The text in the low `lens` bytes (past them, ASCII never shown).
    pub(crate) texts: [u64; IntervalCache::SLOTS],
    pub(crate) lens: [u8; IntervalCache::SLOTS],
}

impl IntervalCache {
    pub(crate) const SLOTS: usize = 512;

    /// The text of an interval not in the cache (24 bytes, first lowest, and how
    /// many are its), kept if it fits.
    #[inline(never)]
    pub(crate) fn insert(&mut self, lo: i32, hi: i32) -> ([u64; 3], usize) {
        let mut text = [0u8; 24];
        let mut len = 0;
        for v in [lo, hi] {
            let mut digits = itoa::Buffer::new();
            let digits = digits.format(v).as_bytes();
            text[len] = b',';
            text[len + 1..len + 1 + digits.len()].copy_from_slice(digits);
            len += 1 + digits.len();
        }
        let word =
            |i: usize| u64::from_le_bytes(text[8 * i..8 * i + 8].try_into().unwrap_or([0; 8]));
        if len <= 8 {
            let slot = lo as usize % Self::SLOTS;
            self.keys[slot] = u64::from(lo as u32) | (u64::from(hi as u32) << 32);
            self.texts[slot] = word(0);
            self.lens[slot] = len as u8;
        }
        ([word(0), word(1), word(2)], len)
    }
}

impl Default for IntervalCache {
    fn default() -> Self {
        IntervalCache {
            keys: std::array::from_fn(|s| (s ^ 1) as u64),
            texts: [0; Self::SLOTS],
            lens: [0; Self::SLOTS],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `insert` gives an interval's text, keeps it when it fits 8 bytes (under its key,
    /// in `lo`'s slot) and leaves the cache alone otherwise; a new cache's keys match
    /// no interval of their slot.
    #[test]
    fn insert_gives_and_keeps_the_text() {
        let mut cache = IntervalCache::default();
        for s in 0..IntervalCache::SLOTS {
            assert_ne!(cache.keys[s] as usize % IntervalCache::SLOTS, s);
        }
        let pairs = [(0, 0), (5, 9), (999, 999), (-1, 3), (517, 520), (1000, 7)];
        let long = [(-1_000_000, 12), (i32::MIN, i32::MAX), (12345, 67890)];
        for (lo, hi) in pairs.into_iter().chain(long) {
            let want = format!(",{lo},{hi}");
            let (words, len) = cache.insert(lo, hi);
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
            assert_eq!(&bytes[..len], want.as_bytes());
            let slot = lo as usize % IntervalCache::SLOTS;
            let key = u64::from(lo as u32) | (u64::from(hi as u32) << 32);
            assert_eq!(cache.keys[slot] == key, len <= 8, "{want}");
            if len <= 8 {
                let text = cache.texts[slot].to_le_bytes();
                assert_eq!(&text[..usize::from(cache.lens[slot])], want.as_bytes());
            }
        }
    }
}
