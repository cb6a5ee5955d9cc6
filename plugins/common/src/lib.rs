//! Code shared by the behavior plugins of this repository.
//!
//! An ordinary library crate on `behavior-api` alone, linked into each plugin's `cdylib`:
//! it exports no behaviors itself (no `export_behaviors!`), so the plugins stay separate
//! libraries with their own types. A third party can share code between its plugins
//! the same way.

pub mod constant;
pub mod peak;
pub mod testing;

/// A parameter value without white space (empty allowed), such as a MOOS variable name.
pub fn no_white(s: &str) -> Option<&str> {
    if s.chars().any(char::is_whitespace) {
        None
    } else {
        Some(s)
    }
}
