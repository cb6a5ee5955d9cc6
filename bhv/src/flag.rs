//! Flag values (behavior-common.md §3.1):
//! `[<posttag> ][#<dest> ]VAR = VALUE [ [if] CONDITION ]` or `clearall`.

use crate::error::LogicError;
use crate::logic::LogicCondition;
use crate::number::{typed_value, Value};

/// One parsed flag.
#[derive(Clone, Debug)]
pub struct FlagSpec {
    /// A first word starting with `@`, `<` or `>` (contact behaviors).
    pub posttag: Option<String>,
    /// `#<dest>` without the `#`, lower-cased.
    pub dest: Option<String>,
    /// The variable to post.
    pub var: String,
    /// The typed value (number, quoted string without quotes, or string).
    pub value: Value,
    /// The value text as written (trimmed).
    pub raw_value: String,
    /// The `[if]` condition, if any.
    pub condition: Option<LogicCondition>,
}

/// A flag parameter value.
// The shape is fixed by the helm's API; flags are parsed once at startup.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum FlagParam {
    /// A flag to add to the list.
    Flag(FlagSpec),
    /// `clearall`: empty the list.
    ClearAll,
}

fn blank(c: char) -> bool {
    c == ' ' || c == '\t'
}

/// Splits off the first blank-separated word.
fn first_word(s: &str) -> (&str, &str) {
    match s.find(blank) {
        Some(i) => (&s[..i], s[i..].trim_start_matches(blank)),
        None => (s, ""),
    }
}

fn find_ci(hay: &str, needle: &str) -> Option<usize> {
    let (h, n) = (hay.as_bytes(), needle.as_bytes());
    (0..=h.len().checked_sub(n.len())?).find(|&i| h[i..i + n.len()].eq_ignore_ascii_case(n))
}

/// Parses a flag value.
///
/// ```
/// use bhv::flag::{parse_flag, FlagParam};
/// use bhv::number::Value;
/// let FlagParam::Flag(f) = parse_flag("#ALL+ RETURN = \"3\" [if] MODE = GO").unwrap() else {
///     panic!()
/// };
/// assert_eq!(f.dest.as_deref(), Some("all+"));
/// assert_eq!(f.value, Value::Str("3".into()));
/// assert!(f.condition.is_some());
/// ```
pub fn parse_flag(text: &str) -> Result<FlagParam, LogicError> {
    let t = text.trim_matches(blank);
    if t.eq_ignore_ascii_case("clearall") {
        return Ok(FlagParam::ClearAll);
    }
    let (main, cond_text) = match find_ci(t, "[if]") {
        Some(i) => (&t[..i], Some(t[i + 4..].trim_matches(blank))),
        None => (t, None),
    };
    let mut rest = main.trim_matches(blank);
    let mut posttag = None;
    let (w, r) = first_word(rest);
    if w.starts_with(['@', '<', '>']) {
        posttag = Some(w.to_string());
        rest = r;
    }
    let mut dest = None;
    let (w, r) = first_word(rest);
    if let Some(d) = w.strip_prefix('#') {
        dest = Some(d.to_lowercase());
        rest = r;
    }
    let Some((var, value)) = rest.split_once('=') else {
        return Err(LogicError::new(text, "flag needs VAR = VALUE"));
    };
    let (var, value) = (var.trim_matches(blank), value.trim_matches(blank));
    if var.is_empty() {
        return Err(LogicError::new(text, "flag variable is empty"));
    }
    if value.is_empty() {
        return Err(LogicError::new(text, "flag value is empty"));
    }
    let condition = match cond_text {
        Some(c) => Some(
            LogicCondition::parse(c)
                .map_err(|e| LogicError::new(text, format!("bad flag condition: {}", e.reason)))?,
        ),
        None => None,
    };
    Ok(FlagParam::Flag(FlagSpec {
        posttag,
        dest,
        var: var.to_string(),
        value: typed_value(value),
        raw_value: value.to_string(),
        condition,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flag(t: &str) -> FlagSpec {
        match parse_flag(t) {
            Ok(FlagParam::Flag(f)) => f,
            other => panic!("{t}: {other:?}"),
        }
    }

    #[test]
    fn plain() {
        let f = flag("RETURN = true");
        assert_eq!(f.var, "RETURN");
        assert_eq!(f.value, Value::Str("true".into()));
        assert_eq!(f.raw_value, "true");
        assert!(f.posttag.is_none() && f.dest.is_none() && f.condition.is_none());
        assert_eq!(flag("LEG=2").value, Value::Num(2.0));
        assert_eq!(flag("X = \"3\"").value, Value::Str("3".into()));
        assert_eq!(flag("X = \"3\"").raw_value, "\"3\"");
        assert_eq!(flag("HIT = $[PX],$[PY]").raw_value, "$[PX],$[PY]");
        assert_eq!(flag("M = a=b").raw_value, "a=b");
    }

    #[test]
    fn tags_and_dest() {
        let f = flag("@10 #Group=Red  CLOSE = yes");
        assert_eq!(f.posttag.as_deref(), Some("@10"));
        assert_eq!(f.dest.as_deref(), Some("group=red"));
        assert_eq!(f.var, "CLOSE");
        assert_eq!(flag("<20 X=1").posttag.as_deref(), Some("<20"));
        assert_eq!(flag(">20 X=1").posttag.as_deref(), Some(">20"));
        assert_eq!(flag("#all X=1").dest.as_deref(), Some("all"));
        assert_eq!(flag("#GROUP+ X=1").dest.as_deref(), Some("group+"));
    }

    #[test]
    fn condition() {
        let f = flag("DONE = true [if] (A = 1) and (B = x)");
        let c = f.condition.expect("condition");
        assert_eq!(c.vars(), ["A", "B"]);
        assert_eq!(f.raw_value, "true");
        assert!(flag("X = 1 [IF] A = 2").condition.is_some());
        assert!(parse_flag("X = 1 [if] A").is_err());
        assert!(parse_flag("X = 1 [if]").is_err());
        assert!(parse_flag("X = 1 [if] (A=1) and (B=2) and (C=3)").is_err());
    }

    #[test]
    fn clearall_and_errors() {
        assert!(matches!(parse_flag("clearall"), Ok(FlagParam::ClearAll)));
        assert!(matches!(parse_flag(" ClearAll "), Ok(FlagParam::ClearAll)));
        for bad in ["", "X", "= 3", "X =", "X = ", "#all", "@5 = 1"] {
            assert!(parse_flag(bad).is_err(), "{bad:?}");
        }
    }
}
