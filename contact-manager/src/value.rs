//! What goes in and out of the manager: mail values and postings, as plain strings and
//! numbers (no MOOS types, so a simulator can drive the manager in-process).

/// One mail value: MOOS mail is a double or a string.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MailValue<'a> {
    Num(f64),
    Str(&'a str),
}

impl MailValue<'_> {
    /// The value as a number: a double as is, a string when it passes the number test.
    pub fn num(&self) -> Option<f64> {
        match self {
            MailValue::Num(v) => Some(*v),
            MailValue::Str(s) => mbutil::parse_number(s),
        }
    }

    /// The value as text: a string as is, a double in compact form.
    pub fn text(&self) -> std::borrow::Cow<'_, str> {
        match self {
            MailValue::Num(v) => mbutil::compact(*v, 6).into(),
            MailValue::Str(s) => (*s).into(),
        }
    }
}

/// One posting's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Num(f64),
    Str(String),
}

impl Value {
    /// A flag value: posted as a number when it looks numeric (contacts-appcast.md §4.3).
    pub fn flag(s: &str) -> Value {
        match mbutil::parse_number(s) {
            Some(v) => Value::Num(v),
            None => Value::Str(s.to_string()),
        }
    }

    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::Str(s) => Some(s),
            Value::Num(_) => None,
        }
    }

    pub fn as_num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            Value::Str(_) => None,
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Num(v) => f.write_str(&mbutil::compact(*v, 6)),
            Value::Str(s) => f.write_str(s),
        }
    }
}

/// One posting: a variable and its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Posting {
    pub var: String,
    pub val: Value,
}

impl Posting {
    pub fn str(var: &str, val: impl Into<String>) -> Posting {
        Posting {
            var: var.to_string(),
            val: Value::Str(val.into()),
        }
    }

    pub fn num(var: &str, val: f64) -> Posting {
        Posting {
            var: var.to_string(),
            val: Value::Num(val),
        }
    }
}

/// Ownship's navigation as last mailed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ownship {
    pub x: f64,
    pub y: f64,
    pub hdg: f64,
    pub spd: f64,
}
