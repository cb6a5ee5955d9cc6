//! Values that cross the boundary: a MOOS posting is a string or a number.

use abi_stable::std_types::RStr;
use abi_stable::StableAbi;

/// A value a behavior posts: MOOS knows strings and doubles.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub enum PostValue<'a> {
    Str(RStr<'a>),
    Num(f64),
}

impl<'a> From<&'a str> for PostValue<'a> {
    fn from(s: &'a str) -> Self {
        PostValue::Str(RStr::from(s))
    }
}

impl From<f64> for PostValue<'_> {
    fn from(v: f64) -> Self {
        PostValue::Num(v)
    }
}
