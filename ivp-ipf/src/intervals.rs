//! The text of boxes' intervals and of slopes, kept: the piece loop copies an
//! interval's text (`,lo,hi`) or a slope's (`,w`) where it would print it (see
//! `PieceText::interval` and `PieceText::slope`).

use super::Batch;

thread_local! {
    /// The piece loop's caches and batch, kept from call to call: a behavior's tiling
    /// is the same every iteration (and behaviors' tilings share intervals).
    pub(crate) static CACHES: std::cell::Cell<Option<Box<Caches>>> =
        const { std::cell::Cell::new(None) };
}

/// One [`IntervalCache`] and one [`SlopeCache`] per dimension of the unrolled piece
/// loops, and the batch the pieces are formatted in (kept: not cleared per call).
pub(crate) struct Caches {
    pub(crate) intervals: [IntervalCache; 3],
    pub(crate) slopes: [SlopeCache; 3],
    pub(crate) batch: Batch,
}

impl Caches {
    /// Taken from the thread for a call (a new one the first time, or if a panic lost
    /// it); give it back with [`Caches::put`].
    pub(crate) fn take() -> Box<Caches> {
        CACHES.take().unwrap_or_else(Caches::new_boxed)
    }

    pub(crate) fn put(caches: Box<Caches>) {
        CACHES.set(Some(caches));
    }

    /// Made in place on the heap: built on the stack, its 27 KB would be copied.
    #[cold]
    fn new_boxed() -> Box<Caches> {
        // SAFETY: `Caches` is integers and arrays of them: all zero bits is a value.
        let mut c = unsafe { Box::<Caches>::new_zeroed().assume_init() };
        for cache in &mut c.intervals {
            for (s, key) in cache.keys.iter_mut().enumerate() {
                *key = (s ^ 1) as u64;
            }
        }
        // Every slot holds `0.0`, whose text is `,0` (a true entry in any slot).
        for cache in &mut c.slopes {
            cache.texts = [[u64::from(u16::from_le_bytes(*b",0")), 0]; SlopeCache::SLOTS];
            cache.lens = [2; SlopeCache::SLOTS];
        }
        c
    }
}

/// The text (`,w`, up to 16 bytes) of a dimension's recent slopes, by their bits.
/// A tiling's pieces repeat a few slopes (one per interval of each dimension) where
/// the intercepts differ: copying their text is cheaper than printing it.
/// Direct-mapped by a hash of the bits; every slot holds a true entry.
pub(crate) struct SlopeCache {
    pub(crate) keys: [u64; SlopeCache::SLOTS],
    /// The text in the low `lens` bytes (past them, ASCII never shown).
    pub(crate) texts: [[u64; 2]; SlopeCache::SLOTS],
    pub(crate) lens: [u8; SlopeCache::SLOTS],
}

impl SlopeCache {
    pub(crate) const SLOTS: usize = 64;

    /// The slot of a weight's bits.
    #[inline(always)]
    pub(crate) fn slot(bits: u64) -> usize {
        (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 58) as usize
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// `insert` gives an interval's text, keeps it when it fits 8 bytes (under its key,
    /// in `lo`'s slot) and leaves the cache alone otherwise; a new interval cache's keys
    /// match no interval of their slot.
    #[test]
    fn insert_gives_and_keeps_the_text() {
        let mut caches = Caches::new_boxed();
        for cache in &caches.intervals {
            for s in 0..IntervalCache::SLOTS {
                assert_ne!(cache.keys[s] as usize % IntervalCache::SLOTS, s);
            }
        }
        let cache = &mut caches.intervals[0];
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

    /// A new slope cache holds `0.0` (text `,0`) in every slot.
    #[test]
    fn new_slope_caches_hold_zero() {
        let caches = Caches::new_boxed();
        for cache in &caches.slopes {
            for s in 0..SlopeCache::SLOTS {
                assert_eq!(cache.keys[s], 0.0f64.to_bits());
                let text = cache.texts[s][0].to_le_bytes();
                assert_eq!(&text[..usize::from(cache.lens[s])], b",0");
            }
        }
    }
}
