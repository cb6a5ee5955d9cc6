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
