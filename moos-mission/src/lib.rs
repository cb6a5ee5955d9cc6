//! `moos-mission`: what MOOS keeps in files and strings, with no sockets, threads or
//! clients: the `.moos` mission-file reader ([`mission`]: globals, `ProcessConfig`
//! blocks, `define:`), MOOS's text helpers ([`text`]: `key=value` lists, `%g`-style
//! numbers, C `atof`, wildcards) and MOOS time ([`time`]: wall time, time warp).
//!
//! It exists so that a crate that reads a mission (the helm engine) need not depend on
//! the MOOS client or the MOOSDB, which live in `moos` (it re-exports these modules, so
//! `moos::mission` and `moos_mission::mission` are one). It depends on `mbutil` only
//! and must not depend on `moos` or anything of the helm.
//!
//! ```
//! use moos_mission::text::find_value;
//! let v = find_value("name=alpha,speed=1.5", "speed", false);
//! assert_eq!(v.as_deref(), Some("1.5"));
//! ```
#![forbid(unsafe_code)]

pub mod mission;
pub mod text;
pub mod time;
