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

/// One contact as the helm's ledger holds it this iteration (contacts-appcast.md §2.5):
/// the last accepted report, X/Y filled from LAT/LON and the other way round.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactState {
    pub x: f64,
    pub y: f64,
    /// Heading, compass degrees.
    pub hdg: f64,
    /// Speed, m/s.
    pub spd: f64,
    pub dep: f64,
    pub lat: f64,
    pub lon: f64,
    /// The report's own time stamp (MOOS time).
    pub utc: f64,
    /// Helm time minus `utc`.
    pub utc_age: f64,
    /// Helm time when the report was accepted, and its age.
    pub utc_received: f64,
    pub utc_age_received: f64,
    /// Vehicle length, m (a default by type when not reported).
    pub length: f64,
    /// Whether the position was moved forward in time from the report. The real helm
    /// never extrapolates in its ledger, so this is false; a behavior that extrapolates
    /// (`extrapolate = true`) does so itself.
    pub extrapolated: bool,
}
