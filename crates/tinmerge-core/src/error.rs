//! The core's errors ([`TinError`]), below every other module: the
//! interrupt callback, io, the hierarchy and the merges all return them.

use thiserror::Error;

/// Errors of the core; the SQL layer maps each kind to an SQLSTATE.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TinError {
    /// Bad argument value (SQLSTATE 22023).
    #[error("{0}")]
    InvalidParameter(String),
    /// Level outside 0..num_levels (SQLSTATE 22023).
    #[error("level {level} is out of range: this tin has levels 0..{} (0 = coarsest, NULL = finest)", .num_levels.saturating_sub(1))]
    LevelOutOfRange { level: i64, num_levels: usize },
    /// Too few or degenerate samples (SQLSTATE 22023).
    #[error("{0}")]
    Degenerate(String),
    /// Stored or transmitted bytes that are not a valid value (SQLSTATE 22P03 / XX001).
    #[error("invalid tin value: {0}")]
    Corrupt(String),
    /// Stored or transmitted bytes that are not a valid `linetree`
    /// (SQLSTATE 22P03 / XX001).
    #[error("invalid linetree value: {0}")]
    CorruptLineTree(String),
    /// Would exceed a size limit (SQLSTATE 54000).
    #[error("{0}")]
    TooLarge(String),
    /// Would use more memory than the caller allows (`tinmerge.max_memory`,
    /// SQLSTATE 53400).
    #[error("{0}")]
    MemoryLimit(String),
    /// A value the core made breaks an invariant it promises (a build's
    /// crack, a level not nested in the one before): a bug of tinmerge's,
    /// never stored (SQLSTATE XX000).
    #[error("internal error: {0}")]
    Internal(String),
    /// Build was interrupted by the caller's interrupt check.
    #[error("interrupted")]
    Interrupted,
}

impl TinError {
    /// A stored or transmitted value that is not valid (`Corrupt`), or an
    /// internal invariant of a merge's walk that such a value broke.
    pub fn corrupt(s: impl Into<String>) -> TinError {
        TinError::Corrupt(s.into())
    }
}

impl From<std::convert::Infallible> for TinError {
    fn from(e: std::convert::Infallible) -> TinError {
        match e {}
    }
}
