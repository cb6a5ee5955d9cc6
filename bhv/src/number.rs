//! Typing of values in `.bhv` files (bhv-format.md §8.6).
//!
//! The number test, C `atof` and the compact formatter are MOOS-IvP's shared utilities
//! and live in `mbutil`; they are re-exported here so `bhv::number::...` keeps working.

pub use mbutil::number::{atof, compact, is_number, strip_quotes};

/// A typed value: a number or a string.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// Numeric value.
    Num(f64),
    /// String value (surrounding quotes already removed).
    Str(String),
}

impl Value {
    /// The numeric value, if this is a number.
    pub fn as_num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            Value::Str(_) => None,
        }
    }

    /// The string value, if this is a string.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::Num(_) => None,
            Value::Str(s) => Some(s),
        }
    }
}

/// Types a value as the helm does for inits, flags and constants: a number
/// (§8.6) → [`Value::Num`]; wrapped in double quotes → [`Value::Str`]
/// without the quotes; otherwise [`Value::Str`] as is.
///
/// ```
/// use bhv::number::{typed_value, Value};
/// assert_eq!(typed_value("3"), Value::Num(3.0));
/// assert_eq!(typed_value("\"3\""), Value::Str("3".into()));
/// ```
pub fn typed_value(s: &str) -> Value {
    if is_number(s) {
        Value::Num(atof(s))
    } else {
        Value::Str(strip_quotes(s).to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typing() {
        assert_eq!(typed_value("3"), Value::Num(3.0));
        assert_eq!(typed_value("-1.5"), Value::Num(-1.5));
        assert_eq!(typed_value("\"3\""), Value::Str("3".into()));
        assert_eq!(typed_value("\"\""), Value::Str(String::new()));
        assert_eq!(typed_value("Hello"), Value::Str("Hello".into()));
        assert_eq!(typed_value("\"a"), Value::Str("\"a".into()));
        assert_eq!(typed_value("\""), Value::Str("\"".into()));
    }

    proptest::proptest! {
        #[test]
        fn never_panics(s in ".{0,20}") {
            let _ = typed_value(&s);
        }
    }
}
