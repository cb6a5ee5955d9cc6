//! Parameter-value helpers several behaviors share (MOOS-IvP's `setBooleanOnString`,
//! `setNonNegDoubleOnString`, ...), so every plugin reads `.bhv` values the same way.

use crate::parse_number;

/// A boolean parameter: `true/false/yes/no/on/off` (any case, trimmed) or `toggle`, which
/// flips `current`. `None` for any other word (the line is then refused).
///
/// ```
/// use behavior_api::params::parse_bool;
/// assert_eq!(parse_bool("YES", false), Some(true));
/// assert_eq!(parse_bool("toggle", true), Some(false));
/// assert_eq!(parse_bool("maybe", true), None);
/// ```
pub fn parse_bool(value: &str, current: bool) -> Option<bool> {
    match value.trim().to_ascii_lowercase().as_str() {
        "true" | "yes" | "on" => Some(true),
        "false" | "no" | "off" => Some(false),
        "toggle" => Some(!current),
        _ => None,
    }
}

/// A number that must be at least 0 (the helm's number test); `None` otherwise.
pub fn non_negative(value: &str) -> Option<f64> {
    parse_number(value).filter(|v| *v >= 0.0)
}

/// A number that must be above 0; `None` otherwise.
pub fn positive(value: &str) -> Option<f64> {
    parse_number(value).filter(|v| *v > 0.0)
}

/// A value without white space (a MOOS variable name); `None` if it has any. Empty is
/// allowed (it usually switches a posting off).
pub fn no_white(value: &str) -> Option<&str> {
    if value.chars().any(char::is_whitespace) {
        None
    } else {
        Some(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn booleans() {
        for (s, want) in [
            (" On ", true),
            ("off", false),
            ("No", false),
            ("TRUE", true),
        ] {
            assert_eq!(parse_bool(s, !want), Some(want), "{s}");
        }
        assert_eq!(parse_bool("toggle", false), Some(true));
        assert_eq!(parse_bool("", false), None);
        assert_eq!(parse_bool("1", false), None);
    }

    #[test]
    fn numbers() {
        assert_eq!(non_negative("0"), Some(0.0));
        assert_eq!(non_negative("-0.1"), None);
        assert_eq!(positive("0"), None);
        assert_eq!(positive(" 2.5"), Some(2.5));
        assert_eq!(positive("two"), None);
        assert_eq!(no_white("A_B"), Some("A_B"));
        assert_eq!(no_white("A B"), None);
    }
}
