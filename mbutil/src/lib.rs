//! `mbutil`: the small string, number and colour utilities every MOOS-IvP application
//! shares (named after MOOS-IvP's `lib_mbutil`). A leaf crate: the `.bhv` reader (`bhv`),
//! the geometry (`geometry`) and every behavior use the same number test, the same C
//! `atof`, the same compact number formatter and the same colour parser, so a value a
//! user writes means one thing wherever it appears. Also the helm's pool of spare
//! strings ([`StringPool`]), which its postings are written into, and the per-thread
//! [`spare`] buffers that IvP functions are built in again every iteration.
//!
//! ```
//! assert!(mbutil::is_number(" -3.5 "));
//! assert_eq!(mbutil::compact(2.50, 2), "2.5");
//! assert!(mbutil::is_color("Gray_70"));
//! ```

pub mod color;
pub mod file;
pub mod fixed;
pub mod name_index;
pub mod number;
pub mod short_str;
pub mod spare;
pub mod string_pool;

pub use color::{is_color, parse_color, Color};
pub use fixed::{push_fixed, push_i64, push_u64};
pub use name_index::NameIndex;
pub use number::{atof, compact, is_number, parse_bool, parse_number, push_compact, strip_quotes};
pub use string_pool::StringPool;
