//! Equality and byte order of the short strings the helm and its contact managers
//! compare many times an iteration (vehicle names and types, variable names): a
//! string of up to 64 bytes (32 for order) is compared in place (words for equality,
//! byte by byte for order), with no call to the C library's `memcmp` (a call and a dispatch
//! for a handful of bytes, a visible share of a fleet's wall time). Longer strings go
//! to the ordinary compare.
//!
//! ```
//! use std::cmp::Ordering;
//! assert!(mbutil::short_str::same("kayak", "kayak"));
//! assert!(!mbutil::short_str::same("kayak", "kayal"));
//! assert_eq!(mbutil::short_str::order("abe", "abel"), Ordering::Less);
//! let mut s = String::from("ship");
//! mbutil::short_str::assign(&mut s, "kayak");
//! assert_eq!(s, "kayak");
//! ```

use std::cmp::Ordering;

/// The 8 bytes of `b` from `at`, little-endian (`at + 8 <= b.len()` at every call: the
/// `0` is never read).
#[inline(always)]
fn le8(b: &[u8], at: usize) -> u64 {
    b.get(at..at + 8)
        .and_then(|w| w.try_into().ok())
        .map_or(0, u64::from_le_bytes)
}

#[inline(always)]
fn le4(b: &[u8], at: usize) -> u32 {
    b.get(at..at + 4)
        .and_then(|w| w.try_into().ok())
        .map_or(0, u32::from_le_bytes)
}

/// `a == b` for byte strings: equal lengths first, then up to 64 bytes as words (the
/// last one overlapping the others: together they cover every byte), longer ones by
/// `==`.
#[inline(always)]
pub fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    let n = a.len();
    if n != b.len() {
        return false;
    }
    match n {
        0 => true,
        1..=3 => a[0] == b[0] && a[n / 2] == b[n / 2] && a[n - 1] == b[n - 1],
        4..=7 => le4(a, 0) == le4(b, 0) && le4(a, n - 4) == le4(b, n - 4),
        8..=16 => le8(a, 0) == le8(b, 0) && le8(a, n - 8) == le8(b, n - 8),
        17..=32 => {
            le8(a, 0) == le8(b, 0)
                && le8(a, 8) == le8(b, 8)
                && le8(a, n - 16) == le8(b, n - 16)
                && le8(a, n - 8) == le8(b, n - 8)
        }
        33..=64 => {
            // A plain loop: `step_by` over a range cost three times as much here.
            let mut i = 0;
            while i + 8 < n {
                if le8(a, i) != le8(b, i) {
                    return false;
                }
                i += 8;
            }
            le8(a, n - 8) == le8(b, n - 8)
        }
        _ => a == b,
    }
}

/// `a == b` (see [`same_bytes`]).
#[inline(always)]
pub fn same(a: &str, b: &str) -> bool {
    same_bytes(a.as_bytes(), b.as_bytes())
}

/// `a.cmp(b)` (byte order, that of `str`'s `Ord`), for the sorted tables of contacts:
/// strings of up to 32 bytes byte by byte in place (names mostly differ in their first
/// bytes, so the loop is short), longer ones by the ordinary compare.
#[inline(always)]
pub fn order(a: &str, b: &str) -> Ordering {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() > 32 || b.len() > 32 {
        return a.cmp(b);
    }
    for (x, y) in a.iter().zip(b) {
        if x != y {
            return x.cmp(y);
        }
    }
    a.len().cmp(&b.len())
}

/// `dst = src` in `dst`'s room, not copied when a short `src` is already there (a kept
/// field that mostly stays the same). A long one is copied without comparing: the
/// compare would cost about what the copy does.
#[inline(always)]
pub fn assign(dst: &mut String, src: &str) {
    if src.len() <= 64 && same(dst, src) {
        return;
    }
    dst.clear();
    dst.push_str(src);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strings of every length to 72 that differ in one byte anywhere, are each other's
    /// prefix or hold zero bytes, against `==` and `cmp`.
    fn samples() -> Vec<String> {
        let mut v = vec![String::new(), "\0".into(), "\0\0".into(), "a\0".into()];
        for n in 1..=72 {
            let base: String = (0..n).map(|i| char::from(b'a' + (i % 26) as u8)).collect();
            v.push(base.clone());
            v.push(format!("{base}\0"));
            for at in 0..n {
                for c in [b'\0', b'_', b'z' + 1] {
                    let mut b = base.clone().into_bytes();
                    b[at] = c;
                    v.push(String::from_utf8(b).unwrap_or_default());
                }
            }
        }
        v.push("é".repeat(9));
        v
    }

    #[test]
    fn same_and_order_as_the_standard_ones() {
        let v = samples();
        for a in &v {
            for b in &v {
                assert_eq!(same(a, b), a == b, "{a:?} {b:?}");
                assert_eq!(order(a, b), a.cmp(b), "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn assign_copies_only_a_change() {
        let mut s = String::with_capacity(32);
        assign(&mut s, "kayak");
        let p = s.as_ptr();
        assign(&mut s, "kayak");
        assign(&mut s, "ship");
        assert_eq!((s.as_str(), s.as_ptr()), ("ship", p));
    }
}
