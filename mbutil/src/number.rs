//! Numbers as MOOS-IvP writes and reads them.
//!
//! The number test is stricter than C `atof`: after trimming blanks the text must be
//! digits with at most one `.`, optional `-` signs before any digit or `.`, an optional
//! leading `+`, and at least one digit. No exponents, no hex (bhv-format.md §8.6). The
//! numeric value is then C `atof` of the text.

fn is_blank(c: char) -> bool {
    c == ' ' || c == '\t' || c == '\r' || c == '\n'
}

/// The helm's number test (§8.6).
///
/// ```
/// assert!(mbutil::is_number(" -3.5 "));
/// assert!(!mbutil::is_number("1e5"));
/// ```
pub fn is_number(s: &str) -> bool {
    let t = s.trim_matches(is_blank);
    let t = match t.strip_prefix('+') {
        Some(rest) if !rest.is_empty() => rest,
        _ => t,
    };
    if t.is_empty() {
        return false;
    }
    let mut digits = 0usize;
    let mut dots = 0usize;
    let mut seen_digit_or_dot = false;
    for b in t.bytes() {
        match b {
            b'0'..=b'9' => {
                digits += 1;
                seen_digit_or_dot = true;
            }
            b'.' => {
                dots += 1;
                if dots > 1 {
                    return false;
                }
                seen_digit_or_dot = true;
            }
            b'-' => {
                if seen_digit_or_dot {
                    return false;
                }
            }
            _ => return false,
        }
    }
    digits > 0
}

/// C `atof`: the value of the longest numeric prefix (after leading white
/// space), or 0 when there is none. Accepts an optional sign, decimal digits
/// with an optional fraction and exponent, `inf`/`infinity`/`nan`, and
/// hexadecimal (`0x...`, with optional fraction and `p` exponent).
///
/// ```
/// assert_eq!(mbutil::atof("12.5abc"), 12.5);
/// assert_eq!(mbutil::atof("abc"), 0.0);
/// ```
pub fn atof(s: &str) -> f64 {
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() && matches!(b[i], b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c) {
        i += 1;
    }
    let mut neg = false;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        neg = b[i] == b'-';
        i += 1;
    }
    let rest = &b[i..];
    let lower_starts = |p: &[u8]| rest.len() >= p.len() && rest[..p.len()].eq_ignore_ascii_case(p);
    let mag = if lower_starts(b"inf") {
        f64::INFINITY
    } else if lower_starts(b"nan") {
        f64::NAN
    } else if (lower_starts(b"0x"))
        && rest.len() > 2
        && (rest[2].is_ascii_hexdigit()
            || (rest[2] == b'.' && rest.len() > 3 && rest[3].is_ascii_hexdigit()))
    {
        hex_prefix(&rest[2..])
    } else {
        match decimal_prefix(rest) {
            Some(v) => v,
            // No conversion: C gives +0 whatever sign came before (`atof("-")`).
            None => return 0.0,
        }
    };
    if neg {
        -mag
    } else {
        mag
    }
}

/// `None` when there is no digit (no conversion at all).
fn decimal_prefix(b: &[u8]) -> Option<f64> {
    let mut i = 0;
    let mut mant_digits = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
        mant_digits += 1;
    }
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
            mant_digits += 1;
        }
    }
    if mant_digits == 0 {
        return None;
    }
    let mant_end = i;
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        let start = j;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        if j > start {
            i = j;
        }
    }
    let end = if i > mant_end { i } else { mant_end };
    // The slice is ASCII digits/./e/sign only, so it is valid UTF-8 and a
    // valid Rust float literal (Rust accepts "5." and ".5").
    Some(
        std::str::from_utf8(&b[..end])
            .ok()
            .and_then(|t| t.parse::<f64>().ok())
            .unwrap_or(0.0),
    )
}

fn hex_prefix(b: &[u8]) -> f64 {
    let mut v = 0.0f64;
    let mut i = 0;
    while i < b.len() && b[i].is_ascii_hexdigit() {
        v = v * 16.0 + f64::from(hex_val(b[i]));
        i += 1;
    }
    if i < b.len() && b[i] == b'.' {
        i += 1;
        let mut scale = 1.0 / 16.0;
        while i < b.len() && b[i].is_ascii_hexdigit() {
            v += f64::from(hex_val(b[i])) * scale;
            scale /= 16.0;
            i += 1;
        }
    }
    if i < b.len() && (b[i] == b'p' || b[i] == b'P') {
        let mut j = i + 1;
        let mut eneg = false;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            eneg = b[j] == b'-';
            j += 1;
        }
        let start = j;
        let mut e: i32 = 0;
        while j < b.len() && b[j].is_ascii_digit() {
            e = e.saturating_mul(10).saturating_add(i32::from(b[j] - b'0'));
            j += 1;
        }
        if j > start {
            v *= 2f64.powi(if eneg { -e } else { e });
        }
    }
    v
}

fn hex_val(c: u8) -> u8 {
    match c {
        b'0'..=b'9' => c - b'0',
        b'a'..=b'f' => c - b'a' + 10,
        b'A'..=b'F' => c - b'A' + 10,
        _ => 0,
    }
}

/// Removes one pair of surrounding double quotes, if present.
pub fn strip_quotes(s: &str) -> &str {
    if s.len() >= 2 && s.starts_with('"') && s.ends_with('"') {
        &s[1..s.len() - 1]
    } else {
        s
    }
}

/// The number test followed by the value: `Some(atof(s))` when [`is_number`] holds.
///
/// ```
/// assert_eq!(mbutil::parse_number(" 2.5 "), Some(2.5));
/// assert_eq!(mbutil::parse_number("1e3"), None);
/// ```
pub fn parse_number(s: &str) -> Option<f64> {
    if let Some(v) = plain_decimal(s.as_bytes()) {
        return Some(v);
    }
    is_number(s).then(|| atof(s))
}

/// Powers of ten that are exact doubles.
const EXACT_POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// [`parse_number`]'s common case without the general parser: `[+-]digits[.digits]`,
/// no blanks, whose digits make an integer `m <= 2^53` with `k <= 22` of them after the
/// dot. Then `m` and `10^k` are exact doubles and one division rounds correctly
/// (Clinger's fast path), so this is the correctly rounded value `atof` gives. `None`
/// sends every other text (blanks, many digits, `--5`, `.`) down the general path.
/// Node reports carry a dozen numbers each, from every contact, every second.
fn plain_decimal(b: &[u8]) -> Option<f64> {
    let (neg, digits) = match b.first()? {
        b'-' => (true, &b[1..]),
        b'+' => (false, &b[1..]),
        _ => (false, b),
    };
    let mut m: u64 = 0;
    let mut count = 0usize;
    let mut dot = None;
    for (i, &c) in digits.iter().enumerate() {
        match c {
            b'0'..=b'9' => {
                count += 1;
                if count > 19 {
                    return None;
                }
                m = m * 10 + u64::from(c - b'0');
            }
            b'.' if dot.is_none() => dot = Some(i),
            _ => return None,
        }
    }
    let k = dot.map_or(0, |i| digits.len() - i - 1);
    if count == 0 || m > 1 << 53 || k >= EXACT_POW10.len() {
        return None;
    }
    let v = m as f64 / EXACT_POW10[k];
    Some(if neg { -v } else { v })
}

/// MOOS-IvP booleans: `true/false/yes/no/on/off`, any case, blanks around ignored
/// (helm config lines and behavior parameters alike).
///
/// ```
/// assert_eq!(mbutil::parse_bool(" Yes"), Some(true));
/// assert_eq!(mbutil::parse_bool("OFF"), Some(false));
/// assert_eq!(mbutil::parse_bool("1"), None);
/// ```
pub fn parse_bool(s: &str) -> Option<bool> {
    match s.trim().to_ascii_lowercase().as_str() {
        "true" | "yes" | "on" => Some(true),
        "false" | "no" | "off" => Some(false),
        _ => None,
    }
}

/// The compact number formatter (`fmtX` of behaviors-std.md §1.5, the helm's
/// `doubleToStringX`): printf `%.<decimals>f`, then trailing zeros and a trailing `.`
/// removed; `-0` becomes `0` (`3.000` → `3`, `2.50` → `2.5`).
///
/// ```
/// assert_eq!(mbutil::compact(63.43494882, 3), "63.435");
/// assert_eq!(mbutil::compact(-0.0001, 2), "0");
/// ```
pub fn compact(v: f64, decimals: usize) -> String {
    let mut s = String::new();
    push_compact(&mut s, v, decimals);
    s
}

/// [`compact`] appended to `out`, with no string of its own (the helm's summary, a
/// behavior's status postings and BHV_IPF headers format numbers every iteration).
pub fn push_compact(out: &mut String, v: f64, decimals: usize) {
    // glibc prints NaN as `nan` / `-nan` by its sign bit (Rust would print `NaN`).
    if v.is_nan() {
        out.push_str(if v.is_sign_negative() { "-nan" } else { "nan" });
    } else if v.fract() == 0.0 && v.abs() < 1e15 {
        // Whole numbers print the same at any precision (flag macros, mode values);
        // -0 prints as 0.
        crate::fixed::push_i64(out, v as i64);
    } else if let Some(n) = crate::fixed::scaled(v, decimals) {
        // What the general path below makes of `push_fixed`'s text, written directly.
        crate::fixed::push_scaled(out, v.is_sign_negative() && n != 0, n, decimals, true);
    } else {
        let start = out.len();
        crate::fixed::push_fixed(out, v, decimals);
        if out[start..].contains('.') {
            let kept = out.trim_end_matches('0').trim_end_matches('.').len();
            out.truncate(kept.max(start));
        }
        if &out[start..] == "-0" {
            out.truncate(start);
            out.push('0');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_examples() {
        for s in [
            "0", "12", "-3", "+4", "3.5", ".5", "5.", "-.5", " 7 ", "\t8\t", "--5", "-0.0", "+-1",
        ] {
            assert!(is_number(s), "{s:?} should be a number");
        }
        for s in [
            "", " ", "+", "-", ".", "-.", "1e5", "0x10", "1.2.3", "5-", "1-2", "abc", "12a", "++1",
            "1 2", "inf", "nan", "\"3\"",
        ] {
            assert!(!is_number(s), "{s:?} should not be a number");
        }
    }

    #[test]
    fn atof_semantics() {
        assert_eq!(atof("3.25"), 3.25);
        assert_eq!(atof("  -2.5xyz"), -2.5);
        assert_eq!(atof("+7"), 7.0);
        assert_eq!(atof("1e3"), 1000.0);
        assert_eq!(atof("1e"), 1.0);
        assert_eq!(atof("1e+"), 1.0);
        assert_eq!(atof(".5"), 0.5);
        assert_eq!(atof("5."), 5.0);
        assert_eq!(atof("--5"), 0.0);
        assert_eq!(atof(""), 0.0);
        assert_eq!(atof("abc"), 0.0);
        assert_eq!(atof("."), 0.0);
        assert_eq!(atof("0x10"), 16.0);
        assert_eq!(atof("0x1p4"), 16.0);
        assert_eq!(atof("0x"), 0.0);
        assert!(atof("inf").is_infinite());
        assert!(atof("-Infinity") < 0.0);
        assert!(atof("nan").is_nan());
        // No conversion is +0 whatever the sign before it; a real -0 stays -0.
        assert!(atof("-").is_sign_positive());
        assert!(atof("-abc").is_sign_positive());
        assert!(atof("-0").is_sign_negative());
    }

    #[test]
    fn parse_number_is_test_then_atof() {
        assert_eq!(parse_number("+4"), Some(4.0));
        assert_eq!(parse_number("\t-.5 "), Some(-0.5));
        assert_eq!(parse_number("12a"), None);
        assert_eq!(parse_number(""), None);
        assert_eq!(strip_quotes("\"a b\""), "a b");
        assert_eq!(strip_quotes("\""), "\"");
    }

    /// The fast path gives what the number test and `atof` give, bit for bit, on texts
    /// near its limits (digit counts around 15-20, 2^53, 22 decimals, signs, dots,
    /// blanks and stray characters).
    #[test]
    fn plain_decimals_are_what_the_general_path_gives() {
        let general = |s: &str| is_number(s).then(|| atof(s));
        let mut seed = 7u64;
        let mut next = move |n: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) % n
        };
        let mut fast = 0;
        for _ in 0..200_000 {
            let mut s = String::new();
            match next(8) {
                0 => s.push('-'),
                1 => s.push('+'),
                2 => s.push_str("--"),
                3 => s.push(' '),
                _ => {}
            }
            let whole = next(21);
            for _ in 0..whole {
                s.push(char::from(b'0' + next(10) as u8));
            }
            if next(3) > 0 {
                s.push('.');
                for _ in 0..next(25) {
                    s.push(char::from(b'0' + next(10) as u8));
                }
            }
            match next(12) {
                0 => s.push('.'),
                1 => s.push('e'),
                2 => s.push(' '),
                _ => {}
            }
            if plain_decimal(s.as_bytes()).is_some() {
                fast += 1;
            }
            let (got, want) = (parse_number(&s), general(&s));
            assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{s:?}");
        }
        for s in [
            "9007199254740992",
            "9007199254740993",
            "900719925474099.3",
            "0.9007199254740993",
            "1.0000000000000000000001",
            "-0",
            "-0.000",
            "+.5",
            "5.",
            "0.1",
            "43.82639681",
            "-70.32899417",
        ] {
            assert_eq!(
                parse_number(s).map(f64::to_bits),
                general(s).map(f64::to_bits),
                "{s:?}"
            );
        }
        // Most of the random texts took the fast path, so it was tested.
        assert!(fast > 50_000, "{fast}");
    }

    #[test]
    fn compact_format() {
        assert_eq!(compact(3.0, 6), "3");
        assert_eq!(compact(2.5, 6), "2.5");
        assert_eq!(compact(-0.0, 6), "0");
        assert_eq!(compact(1.23456789, 3), "1.235");
        assert_eq!(compact(-0.0001, 2), "0");
        assert_eq!(compact(-1.234, 1), "-1.2");
        assert_eq!(compact(100.0, 0), "100");
        assert_eq!(compact(63.43494882, 3), "63.435");
        assert_eq!(compact(1e20, 2), "100000000000000000000");
        assert_eq!(compact(-7.0, 0), "-7");
    }

    proptest::proptest! {
        #[test]
        fn recognized_numbers_roundtrip(v in -1.0e6f64..1.0e6) {
            let s = format!("{v:.4}");
            proptest::prop_assert!(is_number(&s));
            proptest::prop_assert!((atof(&s) - v).abs() < 1e-3);
        }

        #[test]
        fn never_panics(s in ".{0,20}") {
            let _ = is_number(&s);
            let _ = atof(&s);
            let _ = parse_number(&s);
        }
    }
}

#[cfg(test)]
mod push_compact_tests {
    use super::*;

    /// `compact` as it was written before it shared `push_compact`'s body.
    fn compact_reference(v: f64, decimals: usize) -> String {
        // glibc prints NaN as `nan` / `-nan` by its sign bit (Rust would print `NaN`).
        if v.is_nan() {
            return if v.is_sign_negative() { "-nan" } else { "nan" }.to_string();
        }
        // Whole numbers print the same at any precision (flag macros, mode values).
        if v.fract() == 0.0 && v.abs() < 1e15 {
            return if v == 0.0 {
                "0".to_string()
            } else {
                (v as i64).to_string()
            };
        }
        let mut s = format!("{v:.decimals$}");
        if s.contains('.') {
            while s.ends_with('0') {
                s.pop();
            }
            if s.ends_with('.') {
                s.pop();
            }
        }
        if s == "-0" {
            s = "0".to_string();
        }
        s
    }

    #[test]
    fn push_compact_appends_what_compact_gave() {
        let mut seed = 11u64;
        let mut out = String::from("x=");
        for k in 0..20_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let scale = [1e-6, 1e-3, 1.0, 1e3, 1e9, 1e17][k % 6];
            let mut v = ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale;
            if k % 7 == 0 {
                v = v.round();
            }
            for v in [
                v,
                -0.0,
                f64::NAN,
                -f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ] {
                for dec in [0, 2, 3, 5, 6] {
                    out.truncate(2);
                    push_compact(&mut out, v, dec);
                    assert_eq!(&out[2..], compact_reference(v, dec), "{v} {dec}");
                }
            }
        }
    }
}
