//! Number formatting into a caller's string: the compact formatter of MOOS-IvP
//! ([`mbutil::compact`]) without a string of its own, for text a helm or a behavior
//! writes every iteration into kept buffers. One implementation, in `mbutil`.

pub use mbutil::{push_compact, push_fixed, push_i64, push_u64};
