//! `new_obs_flag` and `mailflag` (obstacles.md §2.1, §2.9): `VAR=VALUE` flags whose
//! string values are expanded with the manager's macros when posted.

use contact_manager::{Posting, Value};

/// A refused flag line.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FlagError {
    #[error("flag is not VAR=VALUE: {0}")]
    NotAFlag(String),
    #[error("mailflag is not KEY # VAR=VALUE: {0}")]
    NotAMailFlag(String),
}

/// `VAR=VALUE`; the value is a number when it passes the number test.
#[derive(Clone, Debug, PartialEq)]
pub struct Flag {
    pub var: String,
    pub val: Value,
}

impl Flag {
    pub fn parse(s: &str) -> Result<Flag, FlagError> {
        let (var, val) = s
            .split_once('=')
            .ok_or_else(|| FlagError::NotAFlag(s.to_string()))?;
        let (var, val) = (var.trim(), val.trim());
        if var.is_empty() || var.chars().any(char::is_whitespace) {
            return Err(FlagError::NotAFlag(s.to_string()));
        }
        Ok(Flag {
            var: var.to_string(),
            val: Value::flag(val),
        })
    }

    /// The posting with `macros` expanded in a string value; `None` when the expanded
    /// string is empty (not posted).
    pub fn posting(&self, macros: &[(&str, &str)]) -> Option<Posting> {
        match &self.val {
            Value::Num(v) => Some(Posting::num(&self.var, *v)),
            Value::Str(s) => {
                let out = expand(s, macros);
                let out = out.trim();
                (!out.is_empty()).then(|| Posting::str(&self.var, out))
            }
        }
    }
}

/// `s` with each `(macro, value)` replaced; an empty value leaves its macro as is
/// (`$[RECENT_DISABLED]` with an empty list stays unexpanded).
pub fn expand(s: &str, macros: &[(&str, &str)]) -> String {
    let mut out = s.to_string();
    if !out.contains("$[") {
        return out;
    }
    for (m, v) in macros {
        if !v.is_empty() && out.contains(m) {
            out = out.replace(m, v);
        }
    }
    out
}

/// `KEY # VAR=VALUE` (a leading `@` on KEY is dropped): post VAR=VALUE whenever mail
/// for KEY arrives; KEY `ANY` serves every mail without an exact entry.
#[derive(Clone, Debug, PartialEq)]
pub struct MailFlag {
    pub key: String,
    pub flag: Flag,
}

impl MailFlag {
    pub fn parse(s: &str) -> Result<MailFlag, FlagError> {
        let (key, flag) = s
            .split_once('#')
            .ok_or_else(|| FlagError::NotAMailFlag(s.to_string()))?;
        let key = key.trim();
        let key = key.strip_prefix('@').unwrap_or(key).trim();
        if key.is_empty() || key.chars().any(char::is_whitespace) {
            return Err(FlagError::NotAMailFlag(s.to_string()));
        }
        Ok(MailFlag {
            key: key.to_string(),
            flag: Flag::parse(flag)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_expand_and_type() {
        let f = Flag::parse("NEWOBS = now:$[OBS_NOW],ever:$[OBS_EVER]").unwrap();
        let p = f
            .posting(&[("$[OBS_NOW]", "2"), ("$[OBS_EVER]", "7")])
            .unwrap();
        assert_eq!(p, Posting::str("NEWOBS", "now:2,ever:7"));
        let n = Flag::parse("COUNT=3").unwrap();
        assert_eq!(n.posting(&[]), Some(Posting::num("COUNT", 3.0)));
        let e = Flag::parse("LAST=$[RECENT_DISABLED]").unwrap();
        assert_eq!(
            e.posting(&[("$[RECENT_DISABLED]", "")]).unwrap().val,
            Value::Str("$[RECENT_DISABLED]".into())
        );
        assert_eq!(Flag::parse("EMPTY= ").unwrap().posting(&[]), None);
        assert!(Flag::parse("=1").is_err());
        let m = MailFlag::parse("@GIVEN_OBSTACLE # GOT=$[CNT]").unwrap();
        assert_eq!(m.key, "GIVEN_OBSTACLE");
        assert!(MailFlag::parse("X=1").is_err());
    }
}
