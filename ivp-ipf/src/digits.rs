//! The digit tables and bit tricks the piece text is written with: the box bounds'
//! and weights' digits, a few at a time.

use std::num::NonZeroU64;

/// The decimal digits of `n >= 100` at the end of a 20-byte array, and where they start.
#[cold]
pub(crate) fn long_digits(mut n: u64) -> ([u8; 20], usize) {
    let mut tmp = [0u8; 20];
    let mut i = tmp.len();
    while n >= 100 {
        let p = 2 * (n % 100) as usize;
        n /= 100;
        i -= 2;
        tmp[i..i + 2].copy_from_slice(&DIGIT_PAIRS[p..p + 2]);
    }
    if n >= 10 {
        i -= 2;
        tmp[i..i + 2].copy_from_slice(&DIGIT_PAIRS[2 * n as usize..2 * n as usize + 2]);
    } else {
        i -= 1;
        tmp[i] = b'0' + n as u8;
    }
    (tmp, i)
}

/// `"00".."99"`: two digits per table read.
pub(crate) const DIGIT_PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        t[2 * i] = b'0' + (i / 10) as u8;
        t[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    t
};

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

/// `0..=99` as two digits, first digit in the low byte.
pub(crate) const PAIRS: [u16; 100] = {
    let mut t = [0u16; 100];
    let mut n = 0;
    while n < 100 {
        t[n] = (b'0' as u16 + (n / 10) as u16) | ((b'0' as u16 + (n % 10) as u16) << 8);
        n += 1;
    }
    t
};

/// `.` and the two digits of `0..=99` (first digit in the second byte), with a mark
/// bit at `40 + L` (past the text), `L` the length of `.` and those digits with their
/// trailing zeros dropped: 1 (`.`), 2 or 3. See [`PAIRS_MARKED`].
pub(crate) const DOT_PAIRS: [NonZeroU64; 100] = {
    let mut t = [NonZeroU64::MIN; 100];
    let mut n = 0;
    while n < 100 {
        let len = if n == 0 {
            1
        } else if n % 10 == 0 {
            2
        } else {
            3
        };
        let text = b'.' as u64 | ((PAIRS[n] as u64) << 8) | (1 << (40 + len));
        t[n] = match NonZeroU64::new(text) {
            Some(t) => t,
            None => panic!("the `.` is nonzero"),
        };
        n += 1;
    }
    t
};

/// `0..=99` as two digits (first digit in the low byte), with a mark bit at `16 + L`
/// for a nonzero value, `L` the length of `.dddd` with this pair as the last two
/// digits and trailing zeros dropped: 5, or 4 for a multiple of 10. Shifted to follow
/// a [`DOT_PAIRS`] entry, the marks land in the same byte past the text, where the
/// highest one is the text's length: the pair's if it has one, else the dot pair's.
pub(crate) const PAIRS_MARKED: [u32; 100] = {
    let mut t = [0u32; 100];
    let mut n = 0;
    while n < 100 {
        let mark = if n == 0 {
            0
        } else if n % 10 == 0 {
            1 << (16 + 4)
        } else {
            1 << (16 + 5)
        };
        t[n] = PAIRS[n] as u32 | mark;
        n += 1;
    }
    t
};

/// `x.ilog2()`, as the one `bsr` it is on x86-64: written as `ilog2`, the compiler
/// folds the `- 40` after it into `63 - leading_zeros` and spends three instructions
/// more a weight undoing that.
#[inline(always)]
pub(crate) fn highest_bit(x: NonZeroU64) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        let r: u64;
        // SAFETY: `bsr` reads one register and writes one register and the flags; on a
        // nonzero source (`x` is one) its result is defined: the highest set bit.
        unsafe {
            std::arch::asm!(
                "bsr {r}, {x}",
                x = in(reg) x.get(),
                r = lateout(reg) r,
                options(pure, nomem, nostack),
            );
        }
        // A u64 result: no zero-extension of a 32-bit one.
        r as usize
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        x.ilog2() as usize
    }
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

    #[test]
    fn highest_bit_is_ilog2() {
        for i in 0..64 {
            for low in [0, 1, u64::MAX] {
                let bits = (1u64 << i) | (low & ((1u64 << i) - 1));
                let x = NonZeroU64::new(bits).expect("the top bit is set");
                assert_eq!(highest_bit(x), x.ilog2() as usize, "{x:#x}");
            }
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
