//! `ivp-ipf`: BHV_IPF, an IvP function as the text the helm posts for it and the
//! packets that text is split into (ivp-solver.md §9). It depends on `ivp` and
//! `mbutil` alone: nothing of the helm, the solver or MOOS.
//!
//! Written for the decision step, where every kept function is serialised every
//! iteration: everything is appended to caller-owned strings (reused across iterations),
//! digits are written a character at a time (ASCII, no UTF-8 re-validation, no `format!`
//! per piece).

use ivp::IvpFunction;
use std::fmt::Write;

mod digits;
mod intervals;
mod packets;
mod piece_loop;
use digits::{long_digits, trunc_or_huge, DIGIT_PAIRS, SMALL, WEIGHT_TEXT};
pub use intervals::prepare_thread;
use intervals::{interval_cache, Caches, IntervalCache, SlopeCache, SlopeSlot};
pub use packets::{ipf_packets, IpfWriter, KeptIpf, Packets};
use piece_loop::pieces_n;

/// Numbers of the BHV_IPF text: compact, at most five decimals (as the domain's).
fn push_compact(out: &mut String, v: f64) {
    mbutil::push_compact(out, v, 5);
}

/// Appends to a string's bytes directly, one whole UTF-8 sequence at a time (an ASCII
/// byte or a whole `&str`), so digits go in without `char` encoding or re-validation.
struct Utf8Out<'a> {
    bytes: &'a mut Vec<u8>,
}

impl<'a> Utf8Out<'a> {
    fn new(s: &'a mut String) -> Self {
        // SAFETY: the bytes are only appended to by `byte` (ASCII: masked to 7 bits),
        // `str` (a whole `&str`) and `ascii` (a `PieceText`'s bytes: masked to 7 bits
        // as they were written, or copied from the tables `SMALL`, `WEIGHT_TEXT`,
        // `DIGIT_PAIRS`, literals, and the interval and slope caches,
        // whose shown bytes are digits and punctuation: their marks and lengths lie
        // past the text), so they are valid UTF-8 after every call, as a
        // `String` requires, whenever `s` can be seen again.
        let bytes = unsafe { s.as_mut_vec() };
        Utf8Out { bytes }
    }

    fn reserve(&mut self, extra: usize) {
        self.bytes.reserve(extra);
    }

    /// One ASCII character (callers pass digits and punctuation).
    #[inline]
    fn byte(&mut self, b: u8) {
        self.bytes.push(b & 0x7f);
    }

    fn str(&mut self, s: &str) {
        self.bytes.extend_from_slice(s.as_bytes());
    }

    /// A batch of formatted pieces (inlined: the batch's length then stays in a
    /// register through the piece loop).
    #[inline(always)]
    fn ascii(&mut self, text: &mut PieceText<'_>) {
        let b = text.take();
        debug_assert!(b.is_ascii());
        self.bytes.extend_from_slice(b);
    }

    /// Decimal digits of `n`.
    #[inline]
    fn u64(&mut self, n: u64) {
        // Box bounds and integer parts are mostly under 1000: no loop for those.
        if n < 10 {
            self.byte(b'0' + n as u8);
        } else if n < 100 {
            self.byte(b'0' + (n / 10) as u8);
            self.byte(b'0' + (n % 10) as u8);
        } else if n < 1000 {
            self.byte(b'0' + (n / 100) as u8);
            self.byte(b'0' + (n / 10 % 10) as u8);
            self.byte(b'0' + (n % 10) as u8);
        } else {
            self.long_u64(n);
        }
    }

    fn long_u64(&mut self, mut n: u64) {
        let mut buf = [0u8; 20];
        let mut i = buf.len();
        while n > 0 {
            i -= 1;
            buf[i] = b'0' + (n % 10) as u8;
            n /= 10;
        }
        for &b in &buf[i..] {
            self.byte(b);
        }
    }

    /// The custom 4-decimal weight encoding of spec §9.1.
    #[inline]
    fn weight(&mut self, w: f64) {
        let mut a = w;
        if a < 0.0 {
            self.byte(b'-');
            a = -a;
        }
        if a == 0.0 {
            self.byte(b'0');
            return;
        }
        let x = a * 10000.0 + 0.5;
        // Integer arithmetic gives the same digits as the float form for every weight
        // below 1e15 / 10000. Below 1e15 (< 2^53) `x as u64` is exactly `x.trunc()`.
        // (NaN and infinities fail the test and go the float way.)
        if x < 1e15 {
            let n = x as u64;
            if n == 0 {
                self.str("0.0000");
                return;
            }
            self.u64(n / 10000);
            self.byte(b'.');
            self.frac4((n % 10000) as u32);
            return;
        }
        self.float_weight(a);
    }

    /// Four fractional digits with trailing zeros removed (nothing for 0).
    #[inline]
    fn frac4(&mut self, frac: u32) {
        if frac == 0 {
            return;
        }
        let digits = [frac / 1000, frac / 100 % 10, frac / 10 % 10, frac % 10];
        let mut last = 4;
        while digits[last - 1] == 0 {
            last -= 1;
        }
        for &d in &digits[..last] {
            self.byte(b'0' + d as u8);
        }
    }

    /// Weights of 1e11 and more, infinities and NaN. `n = trunc(a·10000 + 0.5)` is an
    /// integer-valued float here; its digits come from exact integer arithmetic, as the
    /// spec's fixed-point rule says (u128 holds every such `n` below 2^128).
    #[cold]
    fn float_weight(&mut self, a: f64) {
        let mut text = String::new();
        if !a.is_finite() {
            let _ = write!(text, "{a}");
            self.str(&text);
            return;
        }
        let n = (a * 10000.0 + 0.5).trunc();
        if n < 3.4e38 {
            let n = n as u128;
            self.str(itoa::Buffer::new().format(n / 10000));
            self.byte(b'.');
            self.frac4((n % 10000) as u32);
            return;
        }
        // Past u128 a double has no fractional digits left: the integer part alone.
        let _ = write!(text, "{:.0}.", (n / 10000.0).trunc());
        self.str(&text);
    }
}

/// The custom 4-decimal weight encoding of spec §9.1.
pub fn encode_weight(w: f64, out: &mut String) {
    Utf8Out::new(out).weight(w);
}

/// What BHV_IPF shows of a function, borrowed, in [`IvpFunction`]'s layout: an owned
/// function's (see `From`) or a host's view of a plugin's buffers, read in place.
#[derive(Clone, Copy, Debug)]
pub struct IpfSource<'a> {
    pub context: &'a str,
    pub domain: &'a ivp::Domain,
    pub pwt: f64,
    pub gelbox: &'a [u32],
    pub bounds: &'a [i32],
    pub weights: &'a [f64],
}

impl<'a> From<&'a IvpFunction> for IpfSource<'a> {
    fn from(f: &'a IvpFunction) -> Self {
        IpfSource {
            context: f.context(),
            domain: f.domain(),
            pwt: f.pwt(),
            gelbox: f.gelbox(),
            bounds: f.bounds(),
            weights: f.weights(),
        }
    }
}

/// BHV_IPF whole-function string (spec §9.1).
pub fn encode(f: &IvpFunction) -> String {
    let mut s = String::new();
    encode_into(f, &mut s);
    s
}

/// BHV_IPF whole-function string (spec §9.1) written into `s` (cleared first), whose
/// allocation is kept: the decision step reuses one string for every function.
pub fn encode_into(f: &IvpFunction, s: &mut String) {
    encode_source_into(IpfSource::from(f), s);
}

/// [`encode_into`] from borrowed parts (e.g. a plugin's buffers read in place).
pub fn encode_source_into(f: IpfSource<'_>, s: &mut String) {
    encode_head_into(&f, s);
    encode_pieces_into(&f, s);
}

/// The whole-function string up to and including `F` (cleared first): everything but
/// the pieces.
fn encode_head_into(f: &IpfSource<'_>, s: &mut String) {
    encode_context_into(f, s);
    encode_shape_into(f, s);
}

/// The start of the whole-function string (cleared first): `H`, the context.
fn encode_context_into(f: &IpfSource<'_>, s: &mut String) {
    s.clear();
    s.push_str("H,");
    s.push_str(itoa::Buffer::new().format(f.context.chars().count()));
    s.push(',');
    s.push_str(f.context);
    s.push(',');
}

/// What follows the context up to and including `F`, appended to `s`: the sizes, the
/// weight, the domain and the gelbox.
fn encode_shape_into(f: &IpfSource<'_>, s: &mut String) {
    let dim = f.domain.size();
    let pieces = f.weights.len() / (dim + 1);
    s.push_str(itoa::Buffer::new().format(dim));
    s.push(',');
    s.push_str(itoa::Buffer::new().format(pieces));
    s.push_str(",1,");
    push_compact(s, f.pwt);
    s.push_str(",D,");
    f.domain.write_ipf(s);
    s.push_str(",G");
    for &g in f.gelbox {
        s.push(',');
        s.push_str(itoa::Buffer::new().format(g));
    }
    s.push_str(",F");
}

/// The pieces of the whole-function string, appended to `s`.
fn encode_pieces_into(f: &IpfSource<'_>, s: &mut String) {
    let dim = f.domain.size();
    if dim == 0 {
        return;
    }
    let pieces = f.weights.len() / (dim + 1);
    let mut out = Utf8Out::new(s);
    // Generous: growing a string of thousands of pieces copies it each time.
    out.reserve(pieces * (dim * 12 + (dim + 1) * 10));
    // Pieces are formatted in a batch and appended a batch at a time: no capacity
    // check per character. The batch and the caches are the thread's, taken for the
    // call (the batch is not cleared: only what is written in it is read).
    let mut caches = Caches::take();
    let Caches {
        intervals,
        slopes,
        batch,
    } = &mut *caches;
    let mut text = PieceText::new(batch);
    let (b, w) = (f.bounds, f.weights);
    // The usual dimensions with the piece's size a constant: the per-piece loops
    // unroll and the room is made once per piece.
    match dim {
        1 => {
            let i = [interval_cache(&mut intervals[0])];
            text = pieces_n::<1, 2, 2>(b, w, text, &mut out, i, slopes);
        }
        2 => {
            let [i0, i1, _] = intervals;
            let i = [interval_cache(i0), interval_cache(i1)];
            text = pieces_n::<2, 4, 3>(b, w, text, &mut out, i, slopes);
        }
        3 => {
            let [i0, i1, i2] = intervals;
            let i = [interval_cache(i0), interval_cache(i1), interval_cache(i2)];
            text = pieces_n::<3, 6, 4>(b, w, text, &mut out, i, slopes);
        }
        _ => {
            for (bounds, weights) in b.chunks_exact(2 * dim).zip(w.chunks_exact(dim + 1)) {
                for &b in bounds {
                    text.make_room(PieceText::BOUND_MAX, &mut out);
                    text.bound(b);
                }
                for &w in weights {
                    text.make_room(PieceText::WEIGHT_MAX, &mut out);
                    text.weight_or_slow(w, &mut out);
                }
            }
        }
    }
    out.ascii(&mut text);
    Caches::put(caches);
}

/// A batch of pieces' text (ASCII digits and punctuation only) on the stack: `SIZE`
/// bytes of text and room for the 8-byte stores that write a number's bytes at once
/// (the bytes past a number are overwritten by the next one).
pub(crate) type Batch = [u8; PieceText::SIZE + 8];

/// A [`Batch`] and its length. Apart, the array being indexed by the length cannot
/// be taken to overwrite it: the length stays in a register through the piece loop.
/// `len <= SIZE` always: every number is written after `make_room` left room for
/// its longest text (`put8` relies on it).
struct PieceText<'b> {
    buf: &'b mut Batch,
    len: usize,
}

impl<'b> PieceText<'b> {
    const SIZE: usize = 4096;
    /// Most bytes of one bound (`,`, sign, 10 digits).
    const BOUND_MAX: usize = 12;
    /// Most bytes of one fast-path weight (`,`, sign, 11 integer digits, `.`, 4 decimals).
    const WEIGHT_MAX: usize = 18;

    fn new(buf: &'b mut Batch) -> Self {
        PieceText { buf, len: 0 }
    }

    /// Where the next byte goes: `len` masked (a no-op, as `len < SIZE` here), which
    /// shows the compiler that the byte fits, in place of a bounds check.
    #[inline(always)]
    fn at(&self) -> usize {
        debug_assert!(self.len < Self::SIZE);
        self.len & (Self::SIZE - 1)
    }

    /// Eight bytes at the end of the text, of which the caller keeps a prefix.
    #[inline(always)]
    fn put8(&mut self, bytes: u64) {
        debug_assert!(self.len <= Self::SIZE);
        // Unchecked: two to four stores a number, each checked cost a tenth of the loop.
        // SAFETY: `len <= SIZE` at every store: a piece's (or number's) stores all start
        // before the end of its longest text, for which `make_room` left room, and the
        // buffer has the 8 bytes past `SIZE` that a store there reaches.
        unsafe {
            let at = self.buf.as_mut_ptr().add(self.len);
            at.cast::<[u8; 8]>().write_unaligned(bytes.to_le_bytes());
        }
    }

    /// `,` and a box bound: one store for the usual `0..=999`.
    #[inline(always)]
    fn bound(&mut self, b: i32) {
        if (0..1000).contains(&b) {
            let e = SMALL[b as usize];
            // The length byte lands past the text (overwritten by the next number).
            self.put8(u64::from(b',') | (u64::from(e) << 8));
            self.len += 1 + (e >> 24) as usize;
        } else {
            self.byte(b',');
            self.i32(b);
        }
    }

    /// `,lo,hi`: an interval's bounds, copied from `cache` when it holds them.
    #[inline(always)]
    fn interval(&mut self, lo: i32, hi: i32, cache: &mut IntervalCache) {
        let key = u64::from(lo as u32) | (u64::from(hi as u32) << 32);
        let slot = &cache.slots[lo as usize % IntervalCache::SLOTS];
        if slot.key == key {
            self.put8(slot.text);
            self.len += slot.len as usize;
            return;
        }
        // Out of line (and by value: the batch's length stays in a register).
        let ([a, b, c], len) = cache.insert(lo, hi);
        let start = self.len;
        self.put8(a);
        self.len = start + 8;
        self.put8(b);
        self.len = start + 16;
        self.put8(c);
        self.len = start + len;
    }

    /// `,` and a slope, copied from `cache` when it holds its bits (weights as
    /// [`PieceText::weight_or_slow`] writes them; a fast-path text is kept). The ±0
    /// (written directly: as cheap as a copy, not looked up) and the misses counted
    /// into `zeros` and `missed`.
    #[inline(always)]
    fn slope(
        &mut self,
        w: f64,
        cache: &mut SlopeCache,
        out: &mut Utf8Out<'_>,
        (zeros, missed): (&mut usize, &mut usize),
    ) {
        let bits = w.to_bits();
        if bits << 1 == 0 {
            self.weight(w);
            *zeros += 1;
            return;
        }
        let slot = SlopeCache::slot(bits);
        let kept = &cache.slots[slot];
        if kept.key == bits {
            let [a, b] = kept.text;
            let start = self.len;
            self.put8(a);
            self.len = start + 8;
            self.put8(b);
            self.len = start + kept.len as usize;
            return;
        }
        self.new_slope(w, cache, slot, out);
        *missed += 1;
    }

    /// [`PieceText::slope`] for bits not in the cache: written, and kept if it took
    /// the fast path.
    #[inline(always)]
    fn new_slope(&mut self, w: f64, cache: &mut SlopeCache, slot: usize, out: &mut Utf8Out<'_>) {
        let start = self.len;
        if !self.weight(w) {
            self.byte(b',');
            out.ascii(self);
            out.weight(w);
            return;
        }
        // At most `WEIGHT_MAX` (18) bytes were written from `start`, which `make_room`
        // left room for: the 16 read here are in the batch.
        let len = self.len - start;
        if len <= 16 {
            let word = |i: usize| {
                let at = start + 8 * i;
                u64::from_le_bytes(self.buf[at..at + 8].try_into().unwrap_or([0; 8]))
            };
            cache.slots[slot] = SlopeSlot {
                key: w.to_bits(),
                text: [word(0), word(1)],
                len: len as u64,
            };
        }
    }

    /// Room for `need` more bytes of text: the batch so far goes to `out` when near full.
    #[inline(always)]
    fn make_room(&mut self, need: usize, out: &mut Utf8Out<'_>) {
        if self.len > Self::SIZE - need {
            out.ascii(self);
        }
    }

    /// `,` and a weight; the huge, infinite and NaN ones the rare slow way, straight
    /// into `out` after the batch so far.
    #[inline(always)]
    fn weight_or_slow(&mut self, w: f64, out: &mut Utf8Out<'_>) {
        self.weight_or_slow_as::<true>(w, out);
    }

    /// [`PieceText::weight_or_slow`] for a piece's intercept, which is rarely ±0 (a
    /// slope often is): ±0 is sorted out off the straight path, with the tiny weights.
    #[inline(always)]
    fn intercept_or_slow(&mut self, w: f64, out: &mut Utf8Out<'_>) {
        self.weight_or_slow_as::<false>(w, out);
    }

    #[inline(always)]
    fn weight_or_slow_as<const ZERO_FIRST: bool>(&mut self, w: f64, out: &mut Utf8Out<'_>) {
        if !self.weight_as::<ZERO_FIRST>(w) {
            // Laid out of the way: the straight path then needs no jump over it.
            std::hint::cold_path();
            self.byte(b',');
            out.ascii(self);
            out.weight(w);
        }
    }

    /// The buffered text, emptied.
    #[inline(always)]
    fn take(&mut self) -> &[u8] {
        let n = std::mem::take(&mut self.len);
        &self.buf[..n]
    }

    /// One ASCII character (masked to 7 bits: the buffer only ever holds ASCII).
    #[inline(always)]
    fn byte(&mut self, b: u8) {
        let i = self.at();
        self.buf[i] = b & 0x7f;
        self.len += 1;
    }

    /// Two digits of `n < 100`.
    #[inline(always)]
    fn pair(&mut self, n: u32) {
        let (i, n) = (self.at(), 2 * n as usize);
        self.buf[i..i + 2].copy_from_slice(&DIGIT_PAIRS[n..n + 2]);
        self.len += 2;
    }

    /// Decimal digits of `n` (at most 20).
    #[inline(always)]
    fn u64(&mut self, n: u64) {
        if n < 100 {
            if n < 10 {
                self.byte(b'0' + n as u8);
            } else {
                self.pair(n as u32);
            }
        } else if n < 10_000 {
            let n = n as u32;
            if n < 1000 {
                self.byte(b'0' + (n / 100) as u8);
            } else {
                self.pair(n / 100);
            }
            self.pair(n % 100);
        } else {
            self.long_u64(n);
        }
    }

    #[inline(always)]
    fn long_u64(&mut self, n: u64) {
        // The digits come back by value, so the batch never has its address taken
        // and its length stays in a register through the piece loop.
        let (tmp, i) = long_digits(n);
        let k = tmp.len() - i;
        self.buf[self.len..self.len + k].copy_from_slice(&tmp[i..]);
        self.len += k;
    }

    #[inline(always)]
    fn i32(&mut self, v: i32) {
        if v < 0 {
            self.byte(b'-');
        }
        self.u64(u64::from(v.unsigned_abs()));
    }

    /// `,` and `-` for a negative weight (its sign bit: only a zero weight, handled
    /// apart, drops the sign of -0.0): `,-` written always, the `-` kept or not.
    #[inline(always)]
    fn sign(&mut self, bits: u64) {
        self.put8(u64::from(u16::from_le_bytes(*b",-")));
        self.len += 1 + (bits >> 63) as usize;
    }

    /// `,` and the 4-decimal weight encoding (spec §9.1) for the weights the integer
    /// path covers; false, with nothing written, for the others (|w|·10⁴ + 0.5 ≥ 1e15,
    /// infinities, NaN), which [`Utf8Out::weight`] handles.
    #[inline(always)]
    fn weight(&mut self, w: f64) -> bool {
        self.weight_as::<true>(w)
    }

    /// [`PieceText::weight`] with ±0 tested first (`ZERO_FIRST`, for weights that
    /// often are) or only where the tiny weights go (the text is the same).
    #[inline(always)]
    fn weight_as<const ZERO_FIRST: bool>(&mut self, w: f64) -> bool {
        let bits = w.to_bits();
        // ±0 first: in a tiling, slopes often are (half the weights of a contact's).
        if ZERO_FIRST && bits << 1 == 0 {
            self.put8(u64::from(u16::from_le_bytes(*b",0")));
            self.len += 2;
            return true;
        }
        let x = f64::from_bits(bits & !(1 << 63)) * 10000.0 + 0.5;
        let n = trunc_or_huge(x);
        // One test keeps the usual weights (n from 1 to 10^7 - 1) on the straight path:
        // the tiny ones (n = 0), those of 1000 and more, and the huge ones, infinities
        // and NaN (n past 10^7, or not exact) are sorted out off it.
        let frac = if n.wrapping_sub(1) < 10_000_000 - 1 {
            // `n / 10000` for `n < 10^7` as one multiply: 13743896 = 2^37 / 10^4 + ε
            // (ε < 0.66), so the product over 2^37 exceeds n / 10^4 by under
            // 10^7 · 0.66 / 2^37 < 10^-4, which never reaches the next integer (checked
            // for every such `n` in the tests).
            let whole = (n * 13_743_896) >> 37;
            // `,`, the sign and the whole part in one read and one store.
            let at = 2 * whole as usize + (bits >> 63) as usize;
            // SAFETY: `whole` is `n / 10000` (above), below 1000 as `n < 10^7`, so
            // `at < 2000`, the table's size.
            let e = unsafe { *WEIGHT_TEXT.signed_whole.get_unchecked(at) };
            // The length byte lands past the text (overwritten by the next number).
            self.put8(e);
            self.len += (e >> 56) as usize;
            // In u64 like `n` (as u32 it would be widened again to index `frac4`).
            n - whole * 10000
        } else {
            // Laid out of the way: the straight path then needs no jump over it.
            std::hint::cold_path();
            // `n = 0` only for 0 <= x < 1 (NaN and huge `x` give 2^63): ±0 and the tiny
            // weights, the commonest here, sorted out before the range test.
            if n == 0 {
                // ±0 (`,0`, the sign dropped) when not tested first.
                if !ZERO_FIRST && bits << 1 == 0 {
                    self.put8(u64::from(u16::from_le_bytes(*b",0")));
                    self.len += 2;
                    return true;
                }
                // `,0.0000` with the sign of a tiny weight (one that rounds to 0), from
                // a table by the sign bit: no call (a contact's functions have many).
                let neg = (bits >> 63) as usize;
                self.put8(TINY[neg]);
                self.len += 7 + neg;
                return true;
            }
            // One comparison (NaN fails it too); `is_nan() ||` would add one.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(x < 1e15) {
                return false;
            }
            // 1 <= x < 1e15 (< 2^53) from here: `n` is exactly `x.trunc()`.
            self.sign(bits);
            self.u64(n / 10000);
            n % 10000
        };
        // SAFETY: both arms give `n % 10000` (the first's quotient is exact, above).
        unsafe { std::hint::assert_unchecked(frac < 10000) };
        // `.` and four decimals, trailing zeros removed (the `.` stays); the length byte
        // lands past the text (overwritten by the next number).
        // SAFETY: `frac < 10000` (above), the table's size.
        let text = unsafe { *WEIGHT_TEXT.frac4.get_unchecked(frac as usize) };
        self.put8(text);
        self.len += (text >> 56) as usize;
        true
    }
}

/// `,` and the text of a tiny weight, one that rounds to 0, by its sign bit: `0.0000`
/// with its sign.
const TINY: [u64; 2] = [
    u64::from_le_bytes(*b",0.0000\0"),
    u64::from_le_bytes(*b",-0.0000"),
];

#[cfg(test)]
mod tests {
    use super::*;
    use ivp::Domain;

    /// The encoder and packet splitter as they were before the reusable-buffer rewrite,
    /// kept as the reference the fast ones are checked against.
    mod reference {
        use super::super::push_compact;
        use ivp::IvpFunction;
        use std::fmt::Write;
        /// The custom 4-decimal weight encoding of spec §9.1.
        pub(super) fn encode_weight(w: f64, out: &mut String) {
            let mut a = w;
            if a < 0.0 {
                out.push('-');
                a = -a;
            }
            if a == 0.0 {
                out.push('0');
                return;
            }
            if !a.is_finite() {
                let _ = write!(out, "{a}");
                return;
            }
            let x = a * 10000.0 + 0.5;
            // Integer arithmetic gives the same digits as the float form for every weight below
            // 1e15 / 10000 and avoids float formatting on the per-iteration path. Below 1e15
            // (< 2^53) `x as u64` is exactly `x.trunc()`, without a libm call per weight.
            if x < 1e15 {
                let n = x as u64;
                if n == 0 {
                    out.push_str("0.0000");
                    return;
                }
                // Integer part and up to four fractional digits on the stack, then one append.
                let mut ib = itoa::Buffer::new();
                out.push_str(ib.format(n / 10000));
                let frac = (n % 10000) as u32;
                let mut buf = [b'.', b'0', b'0', b'0', b'0'];
                let mut len = 1;
                if frac != 0 {
                    buf[1] += (frac / 1000) as u8;
                    buf[2] += (frac / 100 % 10) as u8;
                    buf[3] += (frac / 10 % 10) as u8;
                    buf[4] += (frac % 10) as u8;
                    len = 5;
                    while buf[len - 1] == b'0' {
                        len -= 1;
                    }
                }
                out.push_str(std::str::from_utf8(&buf[..len]).unwrap_or("."));
                return;
            }
            // Past the u64 path: the same fixed-point rule in u128 (the float
            // arithmetic this replaced printed `:` for a digit there).
            let n = x.trunc();
            if n < 3.4e38 {
                let n = n as u128;
                let _ = write!(out, "{}.", n / 10000);
                push_frac4(out, (n % 10000) as u32);
            } else {
                let _ = write!(out, "{:.0}.", (n / 10000.0).trunc());
            }
        }

        fn push_i32(out: &mut String, v: i32) {
            out.push_str(itoa::Buffer::new().format(v));
        }

        /// Four fractional digits with trailing zeros removed (nothing for 0).
        fn push_frac4(out: &mut String, frac: u32) {
            if frac == 0 {
                return;
            }
            let digits = [frac / 1000, frac / 100 % 10, frac / 10 % 10, frac % 10];
            let mut last = 4;
            while last > 0 && digits[last - 1] == 0 {
                last -= 1;
            }
            for d in &digits[..last] {
                out.push((b'0' + *d as u8) as char);
            }
        }

        /// BHV_IPF whole-function string (spec §9.1).
        pub(super) fn encode(f: &IvpFunction) -> String {
            let dim = f.dim();
            // Generous: growing a string of thousands of pieces copies it each time.
            let mut s = String::with_capacity(
                96 + f.context().len() + f.piece_count() * (dim * 12 + (dim + 1) * 10),
            );
            let _ = write!(
                s,
                "H,{},{},{},{},1,",
                f.context().chars().count(),
                f.context(),
                dim,
                f.piece_count(),
            );
            push_compact(&mut s, f.pwt());
            s.push_str(",D,");
            f.domain().write_ipf(&mut s);
            s.push_str(",G");
            for &g in f.gelbox() {
                s.push(',');
                s.push_str(itoa::Buffer::new().format(g));
            }
            s.push_str(",F");
            for p in f.pieces() {
                for d in 0..dim {
                    s.push(',');
                    push_i32(&mut s, p.lo(d));
                    s.push(',');
                    push_i32(&mut s, p.hi(d));
                }
                for &w in p.weights() {
                    s.push(',');
                    encode_weight(w, &mut s);
                }
            }
            s
        }

        /// Smallest packet body. The spec's `2000 - header` goes to 0 and below for behavior
        /// names of 1950+ characters (one packet per character, thousands per iteration); names
        /// under 1450 characters never reach this floor, so real missions are split as specified.
        const MIN_BODY: usize = 500;

        /// Split a whole-function string into BHV_IPF packets (spec §9.2, packet size 2000).
        pub(super) fn ipf_packets(id: &str, whole: &str) -> Vec<String> {
            if whole.is_ascii() && id.is_ascii() {
                let header = id.len() + 50;
                let body = 2000usize.saturating_sub(header).max(MIN_BODY);
                let count = whole.len() / body + 1;
                return (1..=count)
                    .map(|k| {
                        let a = ((k - 1) * body).min(whole.len());
                        let b = (k * body).min(whole.len());
                        let mut p = String::with_capacity(id.len() + 24 + (b - a));
                        let _ = write!(p, "P,{id},{count},{k},");
                        p.push_str(&whole[a..b]);
                        p
                    })
                    .collect();
            }
            let chars: Vec<char> = whole.chars().collect();
            let header = id.chars().count() + 50;
            let body = 2000usize.saturating_sub(header).max(MIN_BODY);
            let count = chars.len() / body + 1;
            (1..=count)
                .map(|k| {
                    let a = ((k - 1) * body).min(chars.len());
                    let b = (k * body).min(chars.len());
                    let mut p = format!("P,{id},{count},{k},");
                    p.extend(&chars[a..b]);
                    p
                })
                .collect()
        }
    }

    fn rng(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A weight of the kinds the encoder distinguishes: zero, signs, tiny values that
    /// round to `0.0000`, values on the rounding edge of the 4th decimal, integers,
    /// huge values past the integer path, infinities and NaN.
    fn random_weight(seed: &mut u64, finite_only: bool) -> f64 {
        let r = rng(seed);
        let sign = if rng(seed) < 0.5 { -1.0 } else { 1.0 };
        let kinds = if finite_only { 9.0 } else { 11.0 };
        match (rng(seed) * kinds) as u32 {
            0 => 0.0 * sign,
            1 => sign * r * 0.0001,
            2 => sign * ((r * 1e6).floor() + 0.5) / 10000.0,
            3 => sign * (r * 1000.0).floor(),
            4 => sign * r * 100.0,
            5 => sign * r * 1e9,
            6 => sign * r * 1e12,
            7 => sign * (1e11 + r * 1e13),
            8 => sign * 10f64.powf(r * 30.0 - 10.0),
            9 => sign * f64::INFINITY,
            _ => f64::NAN,
        }
    }

    #[test]
    fn large_weights_print_the_fixed_point_digits() {
        // n = trunc(123456789012.34567 * 10000 + 0.5) = 1234567890123457 (exact in f64).
        assert_eq!(enc(123_456_789_012.345_67), "123456789012.3457");
        assert_eq!(enc(-2e15), "-2000000000000000.");
        // 1e20 · 10000 is not a double: the product rounds to 999999999999999983222784,
        // whose fixed-point digits the rule prints.
        assert_eq!(enc(1e20), "99999999999999998322.2784");
        let mut seed = 11u64;
        for _ in 0..100_000 {
            let w = 1e11 + rng(&mut seed) * 1e24;
            let text = enc(w);
            assert!(
                text.bytes().all(|b| b.is_ascii_digit() || b == b'.'),
                "{w:e} -> {text}"
            );
        }
    }

    #[test]
    fn fast_weight_encoding_matches_the_reference() {
        let mut seed = 7u64;
        let (mut a, mut b) = (String::new(), String::new());
        for _ in 0..200_000 {
            let w = random_weight(&mut seed, false);
            a.clear();
            b.clear();
            encode_weight(w, &mut a);
            reference::encode_weight(w, &mut b);
            assert_eq!(a, b, "weight {w:e}");
        }
    }

    /// The multiply `PieceText::weight` divides by 10^4 with for `n < 10^7` is exact.
    #[test]
    fn whole_part_multiply_is_exact() {
        for n in 0..10_000_000u64 {
            assert_eq!((n * 13_743_896) >> 37, n / 10000, "n = {n}");
        }
    }

    /// Every fraction (0 to 4 trailing zeros, all mark combinations) after integer
    /// parts at the length and path boundaries (1, 2, 3 digits; 10^3 and up go the
    /// general way, as `n >= 10^7`; 2^32 / 10^4), both signs, as the reference.
    #[test]
    fn piece_text_fractions_match_the_reference() {
        let mut batch = [0; PieceText::SIZE + 8];
        let mut want = String::new();
        for whole in [
            0u64, 1, 9, 10, 99, 100, 999, 1000, 1001, 429_496, 429_497, 12_345_678,
        ] {
            for frac in 0..10_000 {
                for sign in [1.0, -1.0] {
                    let w = sign * (whole * 10_000 + frac) as f64 / 10_000.0;
                    want.clear();
                    reference::encode_weight(w, &mut want);
                    let mut text = PieceText::new(&mut batch);
                    assert!(text.weight(w));
                    assert_eq!(text.take(), format!(",{want}").as_bytes(), "weight {w:e}");
                }
            }
        }
    }

    /// The stack writer of the piece loop gives the reference's text for every weight it
    /// takes, and declines (writing nothing) exactly the huge and non-finite ones.
    #[test]
    fn piece_text_weights_match_the_reference() {
        let mut batch = [0; PieceText::SIZE + 8];
        // Every whole part of the straight path, with fractions of each length, both
        // signs, and ±0 and tiny weights: slope and intercept variants alike.
        let mut weights = vec![0.0, -0.0, 4e-5, -4e-5, 5e-5, -5e-5];
        for whole in 0..1000u32 {
            for frac in [0u32, 1, 10, 100, 1000, 9999, 5, 50, 500, 1234, 9990] {
                let w = f64::from(whole * 10000 + frac) / 10000.0;
                weights.extend([w, -w]);
            }
        }
        let mut want = String::new();
        for &w in &weights {
            want.clear();
            reference::encode_weight(w, &mut want);
            let want = format!(",{want}");
            let mut text = PieceText::new(&mut batch);
            assert!(text.weight_as::<true>(w));
            assert_eq!(text.take(), want.as_bytes(), "weight {w:e}");
            let mut text = PieceText::new(&mut batch);
            assert!(text.weight_as::<false>(w));
            assert_eq!(text.take(), want.as_bytes(), "intercept {w:e}");
        }
        let mut seed = 19u64;
        let mut want = String::new();
        for _ in 0..300_000 {
            let w = random_weight(&mut seed, false);
            want.clear();
            reference::encode_weight(w, &mut want);
            let mut text = PieceText::new(&mut batch);
            if text.weight(w) {
                assert_eq!(text.take(), format!(",{want}").as_bytes(), "weight {w:e}");
            } else {
                assert_eq!(text.len, 0);
                let x = w.abs() * 10000.0 + 0.5;
                assert!(x.is_nan() || x >= 1e15, "declined {w:e}");
            }
        }
        for v in [
            0,
            7,
            10,
            99,
            100,
            999,
            1000,
            9999,
            10_000,
            123_456_789,
            u32::MAX,
        ] {
            let mut text = PieceText::new(&mut batch);
            text.u64(u64::from(v));
            assert_eq!(text.take(), v.to_string().as_bytes());
        }
        let mut text = PieceText::new(&mut batch);
        text.u64(u64::MAX);
        assert_eq!(text.take(), u64::MAX.to_string().as_bytes());
        for v in [i32::MIN, -1, 0, 1, i32::MAX] {
            let mut text = PieceText::new(&mut batch);
            text.i32(v);
            assert_eq!(text.take(), v.to_string().as_bytes());
        }
        let mut text = PieceText::new(&mut batch);
        let mut want = String::new();
        for v in (-1100..1100).chain([9999, 10_000, 123_456, i32::MIN, i32::MAX]) {
            text.bound(v);
            want.push_str(&format!(",{v}"));
            if text.len > PieceText::SIZE - PieceText::BOUND_MAX {
                assert_eq!(text.take(), want.as_bytes());
                want.clear();
            }
        }
        assert_eq!(text.take(), want.as_bytes());
    }

    /// Random functions (1-3 dimensions, random boxes and weights, pwt, contexts with
    /// and without non-ASCII characters, behavior names of every length class) give the
    /// reference's whole string and packets, written into reused strings.
    #[test]
    fn fast_encoder_and_packets_match_the_reference() {
        let mut seed = 3u64;
        let mut whole = String::new();
        let mut packet = String::new();
        let mut kept = KeptIpf::default();
        for case in 0..1500 {
            // Now and then many dimensions (batches flushed inside a piece).
            let dim = if case % 97 == 0 {
                9 + case % 2
            } else {
                1 + (rng(&mut seed) * 3.0) as usize
            };
            let mut d = Domain::new();
            for i in 0..dim {
                let points = 1 + (rng(&mut seed) * 400.0) as u32;
                let low = (rng(&mut seed) * 20.0).floor() - 10.0;
                let high = if points == 1 {
                    low
                } else {
                    low + 1.0 + (rng(&mut seed) * 5000.0).floor() / 8.0
                };
                d.add_var(&format!("v{i}"), low, high, points).unwrap();
            }
            let pieces = if case % 50 == 0 {
                2000
            } else {
                (rng(&mut seed) * 120.0) as usize
            };
            let mut specs = Vec::with_capacity(pieces);
            for _ in 0..pieces {
                let boxes = d
                    .vars()
                    .iter()
                    .map(|v| {
                        let n = v.points as f64;
                        let lo = (rng(&mut seed) * n) as i32;
                        let hi = lo + (rng(&mut seed) * (n - lo as f64)) as i32;
                        (lo, hi.min(v.points as i32 - 1))
                    })
                    .collect();
                let weights = (0..=dim).map(|_| random_weight(&mut seed, true)).collect();
                specs.push((boxes, weights));
            }
            let mut f = IvpFunction::from_pieces(d, &specs).unwrap();
            f.set_pwt(match case % 4 {
                0 => 100.0,
                1 => rng(&mut seed) * 250.0,
                2 => 1e16 * rng(&mut seed),
                _ => (rng(&mut seed) * 1000.0).floor(),
            });
            let name = match case % 5 {
                0 => "waypt_survey".to_string(),
                1 => "n".repeat(1 + (rng(&mut seed) * 3000.0) as usize),
                2 => "avoid_é".to_string(),
                _ => format!("b{case}"),
            };
            f.set_context(&format!("{case}:{name}"));
            encode_into(&f, &mut whole);
            let expected = reference::encode(&f);
            assert_eq!(whole, expected, "case {case}");
            let id = format!("{name}^{case}");
            let want = reference::ipf_packets(&id, &expected);
            let packets = Packets::new(&id, &whole);
            assert_eq!(packets.count(), want.len(), "case {case}");
            for (k, w) in want.iter().enumerate() {
                packets.write(k + 1, &mut packet);
                assert_eq!(&packet, w, "case {case} packet {}", k + 1);
            }
            assert_eq!(ipf_packets(&id, &whole), want);
            kept_packets_match(&f, &mut kept, &id, case);
        }
    }

    /// The kept-text path gives the whole-string packets when the function is new (the
    /// last case's is kept), when it is the same again, when one weight changed (in its
    /// sign only; 0.0 to -0.0 included) and when only the weight (pwt) changed.
    fn kept_packets_match(f: &IvpFunction, kept: &mut KeptIpf, id: &str, case: usize) {
        let (name, iter) = id.rsplit_once('^').unwrap();
        let iter: u64 = iter.parse().unwrap();
        let mut weights = f.weights().to_vec();
        let (mut whole, mut a, mut b) = (String::new(), String::new(), String::new());
        let mut writer = IpfWriter::default();
        for round in 0..6 {
            if (2..5).contains(&round) && !weights.is_empty() {
                let k = case % weights.len();
                weights[k] = match round {
                    2 => -weights[k],
                    3 => 0.0,
                    _ => -0.0,
                };
            }
            let src = IpfSource {
                weights: &weights,
                pwt: if round == 5 { f.pwt() * 0.5 } else { f.pwt() },
                ..IpfSource::from(f)
            };
            encode_source_into(src, &mut whole);
            let want = Packets::new(id, &whole);
            let got = writer.kept_packets(src, kept, name, iter);
            assert_eq!(got.count(), want.count(), "case {case} round {round}");
            for k in 1..=want.count() {
                want.write(k, &mut a);
                got.write(k, &mut b);
                assert_eq!(a, b, "case {case} round {round} packet {k}");
            }
        }
    }

    /// A function that changes for a while and then holds: every iteration's packets are
    /// the whole string's, whether the pieces' numbers were kept or not.
    #[test]
    fn kept_text_follows_a_function_that_changes_then_holds() {
        let d = Domain::parse("course:0:359:360").unwrap();
        let spec = |k: i32| {
            (0..40i32)
                .map(|i| {
                    (
                        vec![(9 * i, 9 * i + 8)],
                        vec![0.5 * f64::from(i), f64::from(i + k)],
                    )
                })
                .collect::<Vec<_>>()
        };
        let (mut kept, mut writer) = (KeptIpf::default(), IpfWriter::default());
        let (mut whole, mut a, mut b) = (String::new(), String::new(), String::new());
        for iter in 0..60u64 {
            // Changes on iterations 0-29 (but repeats 12), then holds.
            let k = match iter {
                12 => 11,
                0..30 => iter as i32,
                _ => 30,
            };
            let mut f = IvpFunction::from_pieces(d.clone(), &spec(k)).unwrap();
            f.set_context(&format!("{iter}:hold"));
            encode_into(&f, &mut whole);
            let want = Packets::new("hold^1", &whole);
            let got = writer.kept_packets((&f).into(), &mut kept, "hold", 1);
            assert_eq!(got.count(), want.count());
            for p in 1..=want.count() {
                want.write(p, &mut a);
                got.write(p, &mut b);
                assert_eq!(a, b, "iteration {iter}");
            }
        }
        assert_eq!(kept.changed, 0, "the held function is kept");
    }

    /// A weight from anywhere in the encoder's cases: any bit pattern (every magnitude,
    /// subnormals, infinities, NaNs of both signs), the rounding edges of the 4th
    /// decimal and of the integer part's lengths (9.99995 becomes `10.`), the edge of the
    /// integer path (|w|·10⁴ + 0.5 near 1e15), zeros and tiny values of both signs.
    fn any_weight(seed: &mut u64) -> f64 {
        let r = rng(seed);
        let sign = if rng(seed) < 0.5 { -1.0 } else { 1.0 };
        let k = (rng(seed) * 1e6).floor();
        let nudge = |w: f64, ulps: i64| f64::from_bits((w.to_bits() as i64 + ulps) as u64);
        let ulps = (rng(seed) * 5.0) as i64 - 2;
        match (rng(seed) * 12.0) as u32 {
            0 => f64::from_bits(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)),
            1 => sign * nudge((k + 0.5) / 10000.0, ulps),
            2 => sign * nudge(k / 10000.0, ulps),
            3 => {
                let edge = [0.99995, 9.99995, 99.99995, 999.99995, 9999.99995];
                sign * nudge(edge[(r * 5.0) as usize], ulps)
            }
            4 => sign * nudge((1e15 - 0.5) / 10000.0, ulps * 8),
            5 => sign * [0.0, 5e-5, 4.9999e-5, f64::MIN_POSITIVE, 1e-300][(r * 5.0) as usize],
            6 => sign * 10f64.powf(r * 40.0 - 20.0),
            7 => sign * r * 10.0,
            8 => sign * r * 1000.0,
            9 => sign * [f64::INFINITY, f64::MAX, 1e19, 1.8e19][(r * 4.0) as usize],
            10 => f64::from_bits(f64::NAN.to_bits() | ((sign < 0.0) as u64) << 63),
            _ => sign * r * 1e7,
        }
    }

    /// The pieces' text as the reference writes it, from raw bounds and weights.
    fn reference_pieces(dim: usize, bounds: &[i32], weights: &[f64]) -> String {
        let mut s = String::new();
        for (b, w) in bounds
            .chunks_exact(2 * dim)
            .zip(weights.chunks_exact(dim + 1))
        {
            for v in b {
                s.push_str(&format!(",{v}"));
            }
            for &w in w {
                s.push(',');
                reference::encode_weight(w, &mut s);
            }
        }
        s
    }

    /// The piece loop (every dimension count, the unrolled ones and the others) gives
    /// the reference's text for weights of every kind, repeated (the slope cache, kept
    /// from case to case) or not, and for bounds of every kind:
    /// intervals repeated (the interval cache), sharing `lo` or its slot with another
    /// `hi`, negative, past 999, `i32::MIN` and `MAX`; many pieces, so batches flush
    /// between and around the slow weights.
    #[test]
    fn piece_loop_matches_the_reference_for_any_numbers() {
        let mut seed = 23u64;
        let mut got = String::new();
        for case in 0..400 {
            let dim = 1 + case % 5;
            let mut d = Domain::new();
            for i in 0..dim {
                d.add_var(&format!("v{i}"), 0.0, 10.0, 11).unwrap();
            }
            let pieces = 1 + (rng(&mut seed) * 400.0) as usize;
            let mut bounds: Vec<i32> = Vec::with_capacity(pieces * 2 * dim);
            for p in 0..pieces {
                for k in 0..dim {
                    let (lo, hi) = match (rng(&mut seed) * 8.0) as u32 {
                        // The interval of the piece before (the usual tiling).
                        0..=2 if p > 0 => {
                            let at = bounds.len() - 2 * dim;
                            (bounds[at], bounds[at + 1])
                        }
                        // The same `lo` (or `lo` ± 64: the same slot), another `hi`.
                        3 if p > 0 => {
                            let lo = bounds[bounds.len() - 2 * dim];
                            let lo = lo.wrapping_add([0, 64, -64][(rng(&mut seed) * 3.0) as usize]);
                            (lo, (rng(&mut seed) * 1100.0) as i32 - 50)
                        }
                        4 => {
                            let lo = (rng(&mut seed) * 1000.0) as i32;
                            (lo, lo + (rng(&mut seed) * 50.0) as i32)
                        }
                        5 => ((rng(&mut seed) * 2e9) as i32 - 1_000_000_000, k as i32),
                        6 => ([i32::MIN, -1, 999, 1000, i32::MAX][p % 5], -(k as i32)),
                        _ => (
                            (rng(&mut seed) * 1100.0) as i32 - 50,
                            (rng(&mut seed) * 1100.0) as i32,
                        ),
                    };
                    bounds.extend([lo, hi]);
                }
            }
            // Weights of the pieces 1 to 4 before, often (the slope cache), or any; in
            // a third of the cases never repeated (the loop stops using the cache).
            let (wl, repeat) = (dim + 1, if case % 3 == 0 { 0.0 } else { 0.5 });
            let mut weights: Vec<f64> = Vec::with_capacity(pieces * wl);
            for i in 0..pieces * wl {
                let back = wl * (1 + (rng(&mut seed) * 4.0) as usize);
                let w = if i >= back && rng(&mut seed) < repeat {
                    weights[i - back]
                } else {
                    any_weight(&mut seed)
                };
                weights.push(w);
            }
            let src = IpfSource {
                context: "x",
                domain: &d,
                pwt: 1.0,
                gelbox: &[],
                bounds: &bounds,
                weights: &weights,
            };
            got.clear();
            encode_pieces_into(&src, &mut got);
            let want = reference_pieces(dim, &bounds, &weights);
            if got != want {
                let at = got
                    .bytes()
                    .zip(want.bytes())
                    .take_while(|(a, b)| a == b)
                    .count();
                let from = at.saturating_sub(40);
                panic!(
                    "case {case} (dim {dim}) differs at byte {at}: got ..{} want ..{}",
                    &got[from..(at + 40).min(got.len())],
                    &want[from..(at + 40).min(want.len())]
                );
            }
        }
    }

    /// A function whose intercepts change from call to call (all, or one), then a slope,
    /// then a bound, of any numbers and sizes, in every dimension count: the kept
    /// packets are always the whole string's.
    #[test]
    fn kept_text_of_changing_intercepts_matches_the_whole_string() {
        let mut seed = 41u64;
        let (mut whole, mut a, mut b) = (String::new(), String::new(), String::new());
        for case in 0..240 {
            let dim = 1 + case % 4;
            let mut d = Domain::new();
            for i in 0..dim {
                d.add_var(&format!("v{i}"), 0.0, 10.0, 11).unwrap();
            }
            let pieces = match case % 8 {
                0 => 250 + (rng(&mut seed) * 20.0) as usize,
                _ => 1 + (rng(&mut seed) * 30.0) as usize,
            };
            let mut bounds: Vec<i32> = (0..pieces * 2 * dim)
                .map(|_| (rng(&mut seed) * 1200.0) as i32 - 100)
                .collect();
            let wl = dim + 1;
            let mut weights: Vec<f64> = (0..pieces * wl).map(|_| any_weight(&mut seed)).collect();
            let (mut kept, mut writer) = (KeptIpf::default(), IpfWriter::default());
            for round in 0..10 {
                let k = (rng(&mut seed) * pieces as f64) as usize;
                match round {
                    1..=6 => {
                        // Intercepts: all of them, or one (repeats in between).
                        for p in 0..pieces {
                            if round % 2 == 1 || p == k {
                                weights[p * wl + dim] = any_weight(&mut seed);
                            }
                        }
                    }
                    7 => weights[k * wl] = any_weight(&mut seed),
                    8 => bounds[k * 2 * dim] ^= 1,
                    _ => {}
                }
                let src = IpfSource {
                    context: "c",
                    domain: &d,
                    pwt: 1.0,
                    gelbox: &[],
                    bounds: &bounds,
                    weights: &weights,
                };
                encode_source_into(src, &mut whole);
                let want = Packets::new("t^1", &whole);
                let got = writer.kept_packets(src, &mut kept, "t", 1);
                assert_eq!(got.count(), want.count(), "case {case} round {round}");
                for p in 1..=want.count() {
                    want.write(p, &mut a);
                    got.write(p, &mut b);
                    assert_eq!(a, b, "case {case} (dim {dim}) round {round} packet {p}");
                }
            }
        }
    }

    fn enc(w: f64) -> String {
        let mut s = String::new();
        encode_weight(w, &mut s);
        s
    }

    #[test]
    fn weights() {
        assert_eq!(enc(2.0), "2.");
        assert_eq!(enc(100.0), "100.");
        assert_eq!(enc(-0.00004), "-0.0000");
        assert_eq!(enc(0.25), "0.25");
        assert_eq!(enc(123.45678), "123.4568");
        assert_eq!(enc(-1000.0), "-1000.");
        assert_eq!(enc(0.289425), "0.2894");
        assert_eq!(enc(0.0), "0");
        assert_eq!(enc(-0.0), "0");
        assert_eq!(enc(0.05), "0.05");
        assert_eq!(enc(1.0001), "1.0001");
        assert_eq!(enc(12345678.9), "12345678.9");
        assert_eq!(enc(3e14), "300000000000000.");
    }

    #[test]
    fn spec_packet_example() {
        let d = Domain::parse("speed:0:2:21").unwrap();
        let mut f = IvpFunction::from_pieces(
            d,
            &[
                (vec![(0, 4)], vec![2.0, 100.0]),
                (vec![(5, 11)], vec![-0.00004, 0.25]),
                (vec![(12, 20)], vec![123.45678, -1000.0]),
            ],
        )
        .unwrap();
        f.set_pwt(37.5);
        f.set_context("12:abc");
        let p = ipf_packets("abc^12", &encode(&f));
        assert_eq!(p, vec!["P,abc^12,1,1,H,6,12:abc,1,3,1,37.5,D,speed;0;2;21,G,20,F,0,4,2.,100.,5,11,-0.0000,0.25,12,20,123.4568,-1000.".to_string()]);
    }

    #[test]
    fn chunking_exact_multiple() {
        let id = "x";
        let body = 2000 - 51;
        let whole: String = "a".repeat(body * 2);
        let p = ipf_packets(id, &whole);
        assert_eq!(p.len(), 3);
        assert_eq!(p[2], "P,x,3,3,");
    }

    #[test]
    fn chunking_keeps_the_spec_body_up_to_the_floor() {
        let whole: String = "a".repeat(5000);
        // A 1449-character id: body 2000 - 1499 = 501, as specified.
        let id = "n".repeat(1449);
        let p = ipf_packets(&id, &whole);
        assert_eq!(p.len(), 5000 / 501 + 1);
        // Past it the body stays at 500 (the spec's would reach 0 at 1950).
        let id = "n".repeat(3000);
        let p = ipf_packets(&id, &whole);
        assert_eq!(p.len(), 5000 / 500 + 1);
        assert!(p[0].ends_with(&"a".repeat(500)));
    }
}
