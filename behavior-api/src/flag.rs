//! The `.bhv` flag syntax (behavior-common.md §3.1), for a behavior's own flag
//! parameters: the parser the helm uses for `endflag`, `runflag`, ... so a type-specific
//! flag is accepted or refused exactly like a common one. Post a checked flag with
//! [`crate::sdk::Ctx::post_flag`].
//!
//! ```
//! use behavior_api::flag::{parse_flag, FlagParam};
//! assert!(matches!(parse_flag("HIT = $[NI]"), Ok(FlagParam::Flag(_))));
//! assert!(matches!(parse_flag("clearall"), Ok(FlagParam::ClearAll)));
//! assert!(parse_flag("HIT = ").is_err());
//! ```

pub use bhv::flag::{parse_flag, FlagParam, FlagSpec};

use crate::sdk::Ctx;

/// A list of flags a behavior takes as a parameter (`zigflag`, `leg_endflag`, ...):
/// each line is checked with [`parse_flag`] like the common flags, `clearall` empties
/// the list, and the list is posted with the type's own macros expanded first.
///
/// ```
/// use behavior_api::flag::FlagList;
/// let mut l = FlagList::default();
/// assert!(l.set("HIT = $[N]"));
/// assert!(!l.set("HIT ="));
/// assert_eq!(l.len(), 1);
/// assert!(l.set("clearall"));
/// assert!(l.is_empty());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlagList {
    flags: Vec<String>,
}

impl FlagList {
    /// Add a flag line (or `clearall`); false when it does not parse.
    pub fn set(&mut self, value: &str) -> bool {
        match parse_flag(value) {
            Ok(FlagParam::ClearAll) => self.flags.clear(),
            Ok(FlagParam::Flag(_)) => self.flags.push(value.trim().to_string()),
            Err(_) => return false,
        }
        true
    }

    pub fn len(&self) -> usize {
        self.flags.len()
    }

    pub fn is_empty(&self) -> bool {
        self.flags.is_empty()
    }

    /// Post every flag, each with `expand` applied first (the type's macros; the host
    /// expands the common ones), repeatable or under the default key.
    pub fn post(&self, ctx: &mut Ctx<'_>, repeatable: bool, expand: impl Fn(&str) -> String) {
        for f in &self.flags {
            ctx.post_flag(&expand(f), repeatable);
        }
    }
}

/// Replace `$[NAME]` and `$(NAME)` by their values for every `(NAME, value)` pair: a
/// type's own macros (behavior-common.md §3.4). Unknown macros are left alone.
///
/// ```
/// use behavior_api::flag::expand_macros;
/// assert_eq!(expand_macros("n=$[N],m=$(N),$[X]", &[("N", "3".into())]), "n=3,m=3,$[X]");
/// ```
pub fn expand_macros(text: &str, subs: &[(&str, String)]) -> String {
    let mut s = text.to_string();
    for (name, value) in subs {
        subst(&mut s, name, value);
    }
    s
}

/// The next `$` + `open` at or after byte `from`: a byte scan (flag texts are short; a
/// substring searcher per macro name cost ~20K instructions per expansion).
fn find_open(text: &str, from: usize, open: u8) -> Option<usize> {
    let b = text.as_bytes();
    (from..b.len().saturating_sub(1)).find(|&i| b[i] == b'$' && b[i + 1] == open)
}

/// Whether `name` and `close` follow the macro opening (`$` and a bracket) at byte `at`.
pub fn macro_at(text: &str, at: usize, name: &str, close: u8) -> bool {
    let rest = text.as_bytes().get(at + 2..).unwrap_or_default();
    rest.starts_with(name.as_bytes()) && rest.get(name.len()) == Some(&close)
}

/// Replace `$[NAME]` and `$(NAME)` by `value` everywhere in `text`, in place: all
/// `$[NAME]` first, then all `$(NAME)`, left to right, not rescanning what was put in.
/// Nothing is allocated unless the text must grow.
pub fn subst(text: &mut String, name: &str, value: &str) {
    for (open, close) in [(b'[', b']'), (b'(', b')')] {
        let mut from = 0;
        while let Some(at) = find_open(text, from, open) {
            if macro_at(text, at, name, close) {
                text.replace_range(at..at + name.len() + 3, value);
                from = at + value.len();
            } else {
                from = at + 1;
            }
        }
    }
}

/// True when `text` holds `$[NAME]` or `$(NAME)` (so that macro's value need not be
/// worked out otherwise).
pub fn has_macro_named(text: &str, name: &str) -> bool {
    let b = text.as_bytes();
    (0..b.len().saturating_sub(1)).any(|i| {
        b[i] == b'$'
            && match b[i + 1] {
                b'[' => macro_at(text, i, name, b']'),
                b'(' => macro_at(text, i, name, b')'),
                _ => false,
            }
    })
}

/// True when `text` holds a macro at all (so building the substitutions can be skipped).
pub fn has_macro(text: &str) -> bool {
    text.contains("$[") || text.contains("$(")
}
