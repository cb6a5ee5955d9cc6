//! Fixed-point number text without `core::fmt`: the helm formats a few numbers into its
//! postings every iteration (`pwt=`, `dist=`, the summary), and the formatting machinery
//! cost more than the numbers' decisions. Every function here writes exactly what
//! `write!(out, "{v:.decimals$}")` writes; where it cannot be sure cheaply (near a
//! rounding tie, very large values, NaN and infinities) it asks `core::fmt`.

use std::fmt::Write as _;

/// Powers of ten exact in both `u64` and `f64`, for up to 15 decimals.
const POW10: [u64; 16] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
    1_000_000_000,
    10_000_000_000,
    100_000_000_000,
    1_000_000_000_000,
    10_000_000_000_000,
    100_000_000_000_000,
    1_000_000_000_000_000,
];

/// Scaled values up to this stay within 2^-13 of the exact product (relative error
/// 2^-53), far less than the tie margin below.
const SCALED_MAX: f64 = (1u64 << 40) as f64;

/// How far from a rounding tie (in units of the last decimal) the fast path decides.
const TIE_MARGIN: f64 = 1e-3;

/// `write!(out, "{v:.decimals$}")`, the same text.
///
/// ```
/// let mut s = String::new();
/// mbutil::push_fixed(&mut s, -2.345678, 3);
/// assert_eq!(s, "-2.346");
/// ```
pub fn push_fixed(out: &mut String, v: f64, decimals: usize) {
    match scaled(v, decimals) {
        Some(n) => push_scaled(out, v.is_sign_negative(), n, decimals, false),
        None => {
            let _ = write!(out, "{v:.decimals$}");
        }
    }
}

/// The unsigned integer's decimal digits, appended.
pub fn push_u64(out: &mut String, n: u64) {
    out.push_str(itoa::Buffer::new().format(n));
}

/// The signed integer's decimal digits, appended (`write!(out, "{n}")`).
pub fn push_i64(out: &mut String, n: i64) {
    if n < 0 {
        out.push('-');
    }
    push_u64(out, n.unsigned_abs());
}

/// `|v| * 10^decimals` rounded to the nearest integer, when the rounding direction is
/// certain; `None` otherwise.
pub(crate) fn scaled(v: f64, decimals: usize) -> Option<u64> {
    if !v.is_finite() || decimals >= POW10.len() {
        return None;
    }
    let y = v.abs() * POW10[decimals] as f64;
    if y >= SCALED_MAX {
        return None;
    }
    let whole = y.floor();
    let frac = y - whole;
    // Rounding to the nearest integer only jumps at .5: away from it, the computed and
    // the exact product round alike.
    if (frac - 0.5).abs() <= TIE_MARGIN {
        return None;
    }
    Some(whole as u64 + u64::from(frac > 0.5))
}

/// `n / 10^decimals` with `decimals` digits after the dot (with `trim`, trailing zeros
/// and a bare dot left out), `-` first when `neg`: written backwards into one buffer
/// and appended at once (one length check, not one per character).
pub(crate) fn push_scaled(out: &mut String, neg: bool, mut n: u64, decimals: usize, trim: bool) {
    let mut decimals = decimals;
    while trim && decimals > 0 && n.is_multiple_of(10) {
        n /= 10;
        decimals -= 1;
    }
    // n < 2^40 (13 digits), up to 15 decimals: at most 16 digits, a dot and a sign.
    let mut buf = [b'0'; 24];
    let mut i = buf.len();
    // Two digits per division (a table lookup): half the divisions of one at a time.
    let mut d = decimals;
    while d >= 2 {
        i -= 2;
        put_pair(&mut buf, i, n % 100);
        n /= 100;
        d -= 2;
    }
    if d == 1 {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
    }
    if decimals > 0 {
        i -= 1;
        buf[i] = b'.';
    }
    i = put_digits_back(&mut buf, i, n);
    if neg {
        i -= 1;
        buf[i] = b'-';
    }
    // SAFETY: `buf` holds ASCII only (digits, `.`, `-`), so `out` stays UTF-8; the
    // check `from_utf8` would make costs more than the digits.
    unsafe { out.as_mut_vec() }.extend_from_slice(&buf[i..]);
}

/// `"00".."99"`: two digits per table read (also ivp-ipf's, for BHV_IPF text).
pub const DIGIT_PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// The two digits of `r` (below 100) at `buf[i..i + 2]`.
#[inline(always)]
fn put_pair(buf: &mut [u8], i: usize, r: u64) {
    let r = (r as usize % 100) * 2;
    buf[i..i + 2].copy_from_slice(&DIGIT_PAIRS[r..r + 2]);
}

/// The decimal digits of `n` written backwards into `buf`, ending just before `end`,
/// two a division; returns where they start. `buf[..end]` must hold them (20 bytes
/// hold any `u64`).
#[inline(always)]
pub fn put_digits_back(buf: &mut [u8], end: usize, mut n: u64) -> usize {
    let mut i = end;
    while n >= 100 {
        i -= 2;
        put_pair(buf, i, n % 100);
        n /= 100;
    }
    if n >= 10 {
        i -= 2;
        put_pair(buf, i, n);
    } else {
        i -= 1;
        buf[i] = b'0' + n as u8;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `put_digits_back` writes `n`'s decimal text and nothing before it.
    #[test]
    fn put_digits_back_is_the_decimal_text() {
        let mut ns = vec![0, 1, 9, 10, 11, 99, 100, 101, 999, 1000, 12345, u64::MAX];
        ns.extend((0..64).map(|k| 1u64 << k));
        ns.extend((1..20).map(|k| 10u64.pow(k) - 1));
        for n in ns {
            let mut buf = [b'x'; 24];
            let at = put_digits_back(&mut buf, 22, n);
            assert_eq!(&buf[at..22], n.to_string().as_bytes(), "{n}");
            assert!(buf[..at].iter().all(|&b| b == b'x'), "{n}");
        }
    }

    fn by_fmt(v: f64, d: usize) -> String {
        format!("{v:.d$}")
    }

    fn ours(v: f64, d: usize) -> String {
        let mut s = String::new();
        push_fixed(&mut s, v, d);
        s
    }

    #[test]
    fn special_values_match_fmt() {
        let values = [
            0.0,
            -0.0,
            0.5,
            1.5,
            2.5,
            -0.5,
            0.125,
            0.375,
            -0.001,
            1e-300,
            -1e-300,
            0.045,
            1.005,
            2.675,
            123456.789,
            9.9999999,
            -9.9995,
            99.5,
            1e11,
            1e15,
            1e16,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for v in values {
            for d in 0..=17 {
                assert_eq!(ours(v, d), by_fmt(v, d), "{v:e} at {d} decimals");
            }
        }
    }

    #[test]
    fn random_values_match_fmt() {
        // A fixed xorshift: the same values on every run, spread over magnitudes.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..400_000 {
            let r = next();
            let mantissa = (r >> 11) as f64 / (1u64 << 53) as f64;
            let exp = (next() % 24) as i32 - 12;
            let mut v = mantissa * 10f64.powi(exp);
            if r & 1 == 1 {
                v = -v;
            }
            let d = (next() % 8) as usize;
            assert_eq!(ours(v, d), by_fmt(v, d), "{v:e} at {d} decimals");
            // Values on a decimal grid: ties and near-ties at every precision.
            let g = (next() % 2_000_000) as f64 / 1000.0 - 1000.0;
            assert_eq!(ours(g, d), by_fmt(g, d), "{g:e} at {d} decimals");
            let w = (next() % 100_000) as f64 - 50_000.0;
            assert_eq!(ours(w, d), by_fmt(w, d), "{w:e} at {d} decimals");
        }
    }

    #[test]
    fn integers_match_fmt() {
        for n in [0i64, 1, -1, 9, 10, 99, 100, -12345, i64::MAX, i64::MIN] {
            let mut s = String::new();
            push_i64(&mut s, n);
            assert_eq!(s, n.to_string());
        }
    }
}
