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

/// One [`IntervalCache`] (made when a function of that many dimensions first comes)
/// and one [`SlopeCache`] per dimension of the unrolled piece loops, and the batch the
/// pieces are formatted in (kept: not cleared per call).
pub(crate) struct Caches {
    pub(crate) intervals: [Option<Box<IntervalCache>>; 3],
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

    /// Made in place on the heap: built on the stack, its 10 KB would be copied.
    #[cold]
    fn new_boxed() -> Box<Caches> {
        // SAFETY: `Caches` is integers, arrays of them and `None`s of boxes: all zero
        // bits is a value. A slope cache's zero keys (the bits of `0.0`) are never
        // looked up (±0 is written directly).
        unsafe { Box::<Caches>::new_zeroed().assume_init() }
    }
}

/// The thread's caches made now, with the interval caches of functions of up to `dims`
/// dimensions: a helm calls this as it is built, so that its first decision does not
/// make them (48 KB zeroed: a first decision's cost three to five times a later one's).
/// Harmless on a thread that writes no function: they are only memory.
pub fn prepare_thread(dims: usize) {
    let mut caches = Caches::take();
    for cache in caches.intervals.iter_mut().take(dims) {
        interval_cache(cache);
    }
    Caches::put(caches);
}

/// An interval cache, made the first time it is needed.
#[inline(always)]
pub(crate) fn interval_cache(cache: &mut Option<Box<IntervalCache>>) -> &mut IntervalCache {
    cache.get_or_insert_with(IntervalCache::new_boxed)
}

/// The text (`,w`, up to 16 bytes) of a dimension's recent slopes, by their bits.
/// A tiling's pieces repeat a few slopes (one per interval of each dimension) where
/// the intercepts differ: copying their text is cheaper than printing it.
/// Direct-mapped by a hash of the bits; every slot holds a true entry or the key of
/// `0.0`, which is never looked up.
pub(crate) struct SlopeCache {
    pub(crate) slots: [SlopeSlot; SlopeCache::SLOTS],
}

/// A slope's bits and text in one 32-byte slot: a lookup reads one cache line (the
/// caches are cold at each call: a function's text is made once per iteration).
#[derive(Clone, Copy)]
#[repr(C, align(32))]
pub(crate) struct SlopeSlot {
    pub(crate) key: u64,
    /// The text in the low `len` bytes (past them, ASCII never shown).
    pub(crate) text: [u64; 2],
    pub(crate) len: u64,
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
    pub(crate) slots: [IntervalSlot; IntervalCache::SLOTS],
}

/// An interval and its text in one 32-byte slot: a lookup reads one cache line (the
/// caches are cold at each call: a function's text is made once per iteration).
#[derive(Clone, Copy)]
#[repr(C, align(32))]
pub(crate) struct IntervalSlot {
    /// `(lo, hi)` as in memory (`lo` low); a new slot `s` holds a `lo` that is not `s`
    /// modulo `SLOTS` (never matched).
    pub(crate) key: u64,
    /// The text in the low `len` bytes (past them, ASCII never shown).
    pub(crate) text: u64,
    pub(crate) len: u64,
}

impl IntervalCache {
    pub(crate) const SLOTS: usize = 512;

    /// Made in place on the heap (16 KB), only for the dimensions functions have.
    #[cold]
    fn new_boxed() -> Box<IntervalCache> {
        // SAFETY: integers only: all zero bits is a value.
        let mut c = unsafe { Box::<IntervalCache>::new_zeroed().assume_init() };
        // Zero keys match nothing looked up, but in slot 0 (the interval `0,0`): that
        // slot starts with a `lo` of 1.
        c.slots[0].key = 1;
        c
    }

    /// The text of an interval not in the cache (24 bytes, first lowest, and how
    /// many are its), kept if it fits.
    #[inline(never)]
    pub(crate) fn insert(&mut self, lo: i32, hi: i32) -> ([u64; 3], usize) {
        let key = u64::from(lo as u32) | (u64::from(hi as u32) << 32);
        if (0..1000).contains(&lo) && (0..1000).contains(&hi) {
            // The usual bounds: their digits from `SMALL` (low three bytes, their
            // number in the top one), no formatting; `,lo,hi` fits 8 bytes.
            let (a, b) = (super::SMALL[lo as usize], super::SMALL[hi as usize]);
            let la = (a >> 24) as usize;
            let len = 2 + la + (b >> 24) as usize;
            let text = u64::from(b',')
                | (u64::from(a & 0xFF_FFFF) << 8)
                | (u64::from(b',') << (8 * (1 + la)))
                | (u64::from(b & 0xFF_FFFF) << (8 * (2 + la)));
            let slot = &mut self.slots[lo as usize % Self::SLOTS];
            (slot.key, slot.text, slot.len) = (key, text, len as u64);
            return ([text, 0, 0], len);
        }
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
            self.slots[lo as usize % Self::SLOTS] = IntervalSlot {
                key,
                text: word(0),
                len: len as u64,
            };
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
        let cache = &mut *IntervalCache::new_boxed();
        for s in 0..IntervalCache::SLOTS {
            assert_ne!(cache.slots[s].key as usize % IntervalCache::SLOTS, s);
        }
        let pairs = [
            (0, 0),
            (5, 9),
            (999, 999),
            (10, 5),
            (99, 100),
            (-1, 3),
            (517, 520),
            (1000, 7),
            (7, 1000),
        ];
        let long = [(-1_000_000, 12), (i32::MIN, i32::MAX), (12345, 67890)];
        for (lo, hi) in pairs.into_iter().chain(long) {
            let want = format!(",{lo},{hi}");
            let (words, len) = cache.insert(lo, hi);
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
            assert_eq!(&bytes[..len], want.as_bytes());
            let slot = lo as usize % IntervalCache::SLOTS;
            let key = u64::from(lo as u32) | (u64::from(hi as u32) << 32);
            assert_eq!(cache.slots[slot].key == key, len <= 8, "{want}");
            if len <= 8 {
                let text = cache.slots[slot].text.to_le_bytes();
                assert_eq!(&text[..cache.slots[slot].len as usize], want.as_bytes());
            }
        }
    }

    /// A new slope cache holds the key of `0.0` (never looked up) in every slot.
    #[test]
    fn new_slope_caches_hold_only_the_key_of_zero() {
        let caches = Caches::new_boxed();
        for cache in &caches.slopes {
            assert!(cache.slots.iter().all(|s| s.key == 0.0f64.to_bits()));
        }
    }
}
