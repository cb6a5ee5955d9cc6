//! Small helpers shared by the bundled plugin behaviors (included with `#[path]`, so each
//! plugin stays a self-contained `cdylib` without an extra crate).

#![allow(dead_code)]

/// The helm's number test (bhv-format.md §8.6) followed by the value (C `atof`).
pub use behavior_api::parse_number;

/// A string without white space (empty allowed).
pub fn no_white(s: &str) -> Option<&str> {
    if s.chars().any(char::is_whitespace) {
        None
    } else {
        Some(s)
    }
}
