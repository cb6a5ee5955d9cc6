//! The text primitives every geometry string format is defined in terms of
//! (geometry-formats.md §2.1–§2.3). They are byte/ASCII based and deliberately match the
//! real parsers, quirks included (e.g. `split` drops only a trailing empty element).

/// Leading blanks/tabs removed; trailing blanks, tabs, CR, LF and NUL removed.
pub fn trim(s: &str) -> &str {
    s.trim_start_matches([' ', '\t'])
        .trim_end_matches([' ', '\t', '\r', '\n', '\0'])
}

/// Every blank and tab deleted (CR/LF kept).
pub fn nowhite(s: &str) -> String {
    s.chars().filter(|c| *c != ' ' && *c != '\t').collect()
}

/// Split on every `c`; empty input gives nothing, a separator at the very end gives no
/// trailing empty element, other empty elements are kept.
pub fn split(s: &str, c: char) -> Vec<&str> {
    if s.is_empty() {
        return Vec::new();
    }
    let mut v: Vec<&str> = s.split(c).collect();
    if v.len() > 1 && v.last().is_some_and(|l| l.is_empty()) {
        v.pop();
    }
    v
}

/// [`split`], except inside double quotes or braces (state carried over the whole string).
pub fn split_q(s: &str, c: char) -> Vec<&str> {
    if s.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::new();
    let (mut quoted, mut depth, mut start) = (false, 0u32, 0usize);
    for (i, ch) in s.char_indices() {
        match ch {
            '"' => quoted = !quoted,
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if ch == c && !quoted && depth == 0 {
            out.push(&s[start..i]);
            start = i + ch.len_utf8();
        }
    }
    if start < s.len() {
        out.push(&s[start..]);
    }
    out
}

/// Text before the first `c` and the remainder after it (or the whole text and "").
pub fn bite(s: &str, c: char) -> (&str, &str) {
    match s.find(c) {
        Some(i) => (&s[..i], &s[i + c.len_utf8()..]),
        None => (s, ""),
    }
}

/// [`bite`] with both parts trimmed.
pub fn bite_x(s: &str, c: char) -> (&str, &str) {
    let (a, b) = bite(s, c);
    (trim(a), trim(b))
}

/// The real parsers' notion of a number: digits, at most one `.`, `-` only before any
/// digit or `.`, an optional leading `+`, at least one digit. No exponents.
pub fn is_number(t: &str) -> bool {
    let mut t = trim(t);
    if t.is_empty() {
        return false;
    }
    if t.len() > 1 && t.starts_with('+') {
        t = &t[1..];
    }
    let (mut digit, mut dot) = (false, false);
    for b in t.bytes() {
        match b {
            b'0'..=b'9' => digit = true,
            b'.' if !dot => dot = true,
            b'-' if !digit && !dot => {}
            _ => return false,
        }
    }
    digit
}

fn is_c_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

/// C `atof`/`strtod`: the longest convertible prefix, 0 if none (the one shared by every
/// MOOS-IvP string reader).
pub use mbutil::atof;

/// C `atoi`/`strtol` base 10 on the longest prefix (saturating).
pub fn atoi(t: &str) -> i64 {
    let b = t.as_bytes();
    let mut i = 0;
    while i < b.len() && is_c_space(b[i]) {
        i += 1;
    }
    let mut neg = false;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        neg = b[i] == b'-';
        i += 1;
    }
    let mut v: i64 = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        let d = i64::from(b[i] - b'0');
        v = v.saturating_mul(10).saturating_add(d);
        i += 1;
    }
    if neg {
        -v
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitting() {
        assert_eq!(split("a,,b", ','), vec!["a", "", "b"]);
        assert_eq!(split(",a", ','), vec!["", "a"]);
        assert_eq!(split("a,", ','), vec!["a"]);
        assert_eq!(split(",", ','), vec![""]);
        assert!(split("", ',').is_empty());
        assert_eq!(
            split_q("a={1,2},b=\"x,y\",c", ','),
            vec!["a={1,2}", "b=\"x,y\"", "c"]
        );
        assert_eq!(bite_x(" a = b = c ", '='), ("a", "b = c"));
        assert_eq!(bite("abc", '='), ("abc", ""));
        assert_eq!(trim("\t a \r\n\0"), "a");
    }

    #[test]
    fn numbers() {
        for ok in ["5", "--5", "-.5", "+-5", " 3 ", "+3", "1.", ".5"] {
            assert!(is_number(ok), "{ok}");
        }
        for bad in [
            "5-", "1e3", "inf", "nan", "0x10", "", "+", "-", ".", "1.2.3", "4,",
        ] {
            assert!(!is_number(bad), "{bad}");
        }
        assert_eq!(atof("--5"), 0.0);
        assert_eq!(atof("+-5"), 0.0);
        assert_eq!(atof("abc"), 0.0);
        assert_eq!(atof("1e3"), 1000.0);
        assert_eq!(atof("12abc"), 12.0);
        assert_eq!(atof(" -2.5e"), -2.5);
        assert_eq!(atof("0x1p4"), 16.0);
        assert_eq!(atof("-Infinity"), f64::NEG_INFINITY);
        assert!(atof("nan").is_nan());
        assert_eq!(atoi("8.9"), 8);
        assert_eq!(atoi("-3"), -3);
        assert_eq!(atoi("--3"), 0);
    }
}
