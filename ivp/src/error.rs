//! Typed errors of the IvP crate. Every variant names the offending parameter.

use thiserror::Error;

/// Errors reported by domains, functions, builders and the solver.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum IvpError {
    /// A domain variable needs at least one point.
    #[error("domain variable `{var}`: points must be >= 1 (got {points})")]
    PointsTooFew { var: String, points: u32 },
    /// `low > high` for a domain variable.
    #[error("domain variable `{var}`: low ({low}) > high ({high})")]
    LowAboveHigh { var: String, low: f64, high: f64 },
    /// A single-point variable must have `low == high`.
    #[error("domain variable `{var}`: points == 1 but low ({low}) != high ({high})")]
    SinglePointRange { var: String, low: f64, high: f64 },
    /// A NaN / infinite number where a finite one is required.
    #[error("parameter `{param}` is not a finite number ({value})")]
    NotFinite { param: String, value: f64 },
    /// A parameter that must be non-negative was negative.
    #[error("parameter `{param}` must be >= 0 (got {value})")]
    Negative { param: String, value: f64 },
    /// `minutil >= maxutil`.
    #[error("parameter `minutil` ({min}) must be < `maxutil` ({max})")]
    MinNotBelowMax { min: f64, max: f64 },
    /// A variable name was given twice.
    #[error("domain variable `{0}` already exists")]
    DuplicateVar(String),
    /// A variable name is empty or contains separators.
    #[error("domain variable name `{0}` is invalid")]
    BadVarName(String),
    /// A domain string could not be parsed.
    #[error("cannot parse domain `{spec}`: field `{field}` {reason}")]
    Parse {
        spec: String,
        field: String,
        reason: String,
    },
    /// A variable used by a function is not part of the target domain.
    #[error("DomainVar {0} not recognized")]
    UnknownVar(String),
    /// A ZAIC component index out of range.
    #[error("parameter `index`: component {index} does not exist ({count} components)")]
    BadComponent { index: usize, count: usize },
    /// The builder's variable needs a positive delta (more than one point).
    #[error("domain variable `{0}`: delta must be > 0 for this builder")]
    ZeroDelta(String),
    /// Malformed piece data.
    #[error("piece {piece}: {reason}")]
    BadPiece { piece: usize, reason: String },
    /// Two functions to couple share variables or are otherwise incompatible.
    #[error("cannot couple: {0}")]
    Couple(String),
    /// Generic invalid builder input (e.g. mismatched vector lengths).
    #[error("parameter `{param}`: {reason}")]
    Invalid { param: String, reason: String },
}

/// Check that `value` is finite, naming `param` otherwise.
pub(crate) fn finite(param: &str, value: f64) -> Result<f64, IvpError> {
    if value.is_finite() {
        Ok(value)
    } else {
        let param = param.to_string();
        Err(IvpError::NotFinite { param, value })
    }
}

/// [`IvpError::Invalid`] of `param`.
pub(crate) fn invalid(param: &str, reason: impl Into<String>) -> IvpError {
    let (param, reason) = (param.to_string(), reason.into());
    IvpError::Invalid { param, reason }
}

/// [`IvpError::BadPiece`] of piece `piece`.
pub(crate) fn bad_piece(piece: usize, reason: impl Into<String>) -> IvpError {
    let reason = reason.into();
    IvpError::BadPiece { piece, reason }
}
