//! The digit tables and bit tricks the piece text is written with: the box bounds'
//! and weights' digits, a few at a time.

pub(crate) use mbutil::fixed::DIGIT_PAIRS;

/// The decimal digits of `n >= 100` at the end of a 20-byte array, and where they start.
#[cold]
pub(crate) fn long_digits(n: u64) -> ([u8; 20], usize) {
    let mut tmp = [0u8; 20];
    let i = mbutil::fixed::put_digits_back(&mut tmp, 20, n);
    (tmp, i)
}

/// `0..=999` as text: the digits in the low three bytes (first digit lowest), their
/// number in the top byte; one table read and one store write a small number.
pub(crate) const SMALL: [u32; 1000] = {
    let mut t = [0u32; 1000];
    let mut n = 0;
    while n < 1000 {
        let (h, d, u) = ((n / 100) as u32, (n / 10 % 10) as u32, (n % 10) as u32);
        let z = b'0' as u32;
        t[n] = if n < 10 {
            (1 << 24) | (z + u)
        } else if n < 100 {
            (2 << 24) | (z + d) | ((z + u) << 8)
        } else {
            (3 << 24) | (z + h) | ((z + d) << 8) | ((z + u) << 16)
        };
        n += 1;
    }
    t
};

/// The two tables a usual weight is written with, in one place: one address for
/// both (the loop computes it once a weight, not once a table).
#[repr(C)]
pub(crate) struct WeightText {
    pub(crate) signed_whole: [u64; 2000],
    pub(crate) frac4: [u64; 10000],
}

pub(crate) static WEIGHT_TEXT: WeightText = WeightText {
    signed_whole: signed_whole(),
    frac4: frac4(),
};

/// `,`, `-` for a negative weight and the digits of `0..=999`, first byte lowest, and
/// the text's length in the top byte: entry `2·n` for `n`, `2·n + 1` for `-n` (the sign
/// bit added to twice the number indexes it). 16 KB.
const fn signed_whole() -> [u64; 2000] {
    let mut t = [0u64; 2000];
    let mut i = 0;
    while i < 2000 {
        let (n, neg) = (i / 2, i % 2);
        let small = SMALL[n] as u64;
        let digits = small >> 24;
        let mut text = b',' as u64 | ((b'-' as u64 * neg as u64) << 8);
        text |= (small & 0xff_ffff) << (8 * (1 + neg));
        t[i] = text | ((1 + neg as u64 + digits) << 56);
        i += 1;
    }
    t
}

/// `.` and the four decimals of `0..=9999` with trailing zeros dropped (the `.` stays),
/// first byte lowest, and the text's length (1 to 5) in the top byte: one table read
/// and one store write a weight's fraction, where splitting it into two pairs and
/// finding the length took ten instructions more. 80 KB, read only where weights are.
const fn frac4() -> [u64; 10000] {
    let mut t = [0u64; 10000];
    let mut n = 0;
    while n < 10000 {
        let digits = [n / 1000, n / 100 % 10, n / 10 % 10, n % 10];
        let mut kept = 4;
        while kept > 0 && digits[kept - 1] == 0 {
            kept -= 1;
        }
        let mut text = b'.' as u64;
        let mut i = 0;
        while i < kept {
            text |= (b'0' as u64 + digits[i] as u64) << (8 * (i + 1));
            i += 1;
        }
        t[n] = text | ((1 + kept as u64) << 56);
        n += 1;
    }
    t
}

/// `x.trunc()` for `0.5 <= x < 2^63`, and 2^63 or more for NaN and larger `x`, by one
/// `cvttsd2si` on x86-64 (an out-of-range value gives `i64::MIN`, 2^63 as a u64), where
/// `as` would add its saturation tests. Callers test the range on the result.
#[inline(always)]
pub(crate) fn trunc_or_huge(x: f64) -> u64 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_cvttsd_si64, _mm_set_sd};
        // SAFETY: the two need SSE2, which every x86-64 processor has (the target's
        // baseline).
        unsafe { _mm_cvttsd_si64(_mm_set_sd(x)) as u64 }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        if x < 9.2e18 {
            x as u64
        } else {
            u64::MAX
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every entry is `,`, the sign and the number, its length in the top byte and
    /// nothing between.
    #[test]
    fn signed_whole_is_the_comma_sign_and_digits() {
        for (i, &e) in WEIGHT_TEXT.signed_whole.iter().enumerate() {
            let want = format!(",{}{}", if i % 2 == 1 { "-" } else { "" }, i / 2);
            let len = (e >> 56) as usize;
            assert_eq!(len, want.len(), "{i}");
            assert_eq!(&e.to_le_bytes()[..len], want.as_bytes(), "{i}");
            assert_eq!(e & (u64::MAX << (8 * len)) & !(0xff << 56), 0, "{i}");
        }
    }

    /// Every entry is `.` and the four decimals with trailing zeros dropped, its length
    /// in the top byte and nothing between.
    #[test]
    fn frac4_is_the_trimmed_decimals() {
        for (n, &e) in WEIGHT_TEXT.frac4.iter().enumerate() {
            let want = format!(".{n:04}");
            let want = want.trim_end_matches('0');
            let len = (e >> 56) as usize;
            assert_eq!(len, want.len(), "{n}");
            assert_eq!(&e.to_le_bytes()[..len], want.as_bytes(), "{n}");
            assert_eq!(e & (u64::MAX << (8 * len)) & !(0xff << 56), 0, "{n}");
        }
    }

    #[test]
    fn trunc_or_huge_truncates_or_goes_past_the_range() {
        for x in [
            0.5,
            0.99,
            1.0,
            1.5,
            9_999_999.5,
            1e7,
            1e15 - 0.5,
            1e15,
            9e18,
        ] {
            assert_eq!(trunc_or_huge(x), x.trunc() as u64, "{x}");
        }
        for x in [9.3e18, 1e19, 1e300, f64::INFINITY, f64::NAN] {
            assert!(trunc_or_huge(x) >= 1 << 63, "{x}");
        }
    }
}
