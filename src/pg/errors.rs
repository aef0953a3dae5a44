//! Errors of the core mapped to SQLSTATEs: every failure reaches the user
//! as an `ERROR` with a code and a message saying what was wrong.

use pgrx::prelude::*;

use tinmerge_core::io::IoError;
use tinmerge_core::tin::TinError;

/// Raise an ERROR with an SQLSTATE; never returns.
pub(crate) fn raise(code: PgSqlErrorCode, msg: impl Into<String>) -> ! {
    let msg: String = msg.into();
    ereport!(ERROR, code, msg);
}

/// Raise an ERROR with an SQLSTATE and a HINT saying what to do; never
/// returns.
pub(crate) fn raise_hint(
    code: PgSqlErrorCode,
    msg: impl Into<String>,
    hint: impl Into<String>,
) -> ! {
    pgrx::pg_sys::panic::ErrorReport::new(code, msg.into(), "tinmerge")
        .set_hint(hint)
        .report(PgLogLevel::ERROR);
    unreachable!("an ERROR does not return")
}

/// Map a core error to its SQLSTATE and raise it.
pub(crate) fn raise_tin(e: TinError) -> ! {
    use PgSqlErrorCode::*;
    let code = match &e {
        TinError::InvalidParameter(_)
        | TinError::LevelOutOfRange { .. }
        | TinError::Degenerate(_) => ERRCODE_INVALID_PARAMETER_VALUE,
        TinError::Corrupt(_) | TinError::CorruptLineTree(_) => ERRCODE_DATA_CORRUPTED,
        TinError::TooLarge(_) => ERRCODE_PROGRAM_LIMIT_EXCEEDED,
        TinError::MemoryLimit(_) => ERRCODE_CONFIGURATION_LIMIT_EXCEEDED,
        TinError::Interrupted => ERRCODE_QUERY_CANCELED,
        TinError::Internal(_) => ERRCODE_INTERNAL_ERROR,
    };
    raise(code, e.to_string())
}

/// Map an input-format error to its SQLSTATE and raise it.
pub(crate) fn raise_io(e: IoError) -> ! {
    use PgSqlErrorCode::*;
    let code = match &e {
        IoError::Geometry(_) | IoError::Raster(_) => ERRCODE_INVALID_BINARY_REPRESENTATION,
        IoError::Unsupported(_) => ERRCODE_INVALID_PARAMETER_VALUE,
    };
    raise(code, e.to_string())
}

pub(crate) trait OrRaise<T> {
    fn or_raise(self) -> T;
}

impl<T> OrRaise<T> for Result<T, TinError> {
    fn or_raise(self) -> T {
        self.unwrap_or_else(|e| raise_tin(e))
    }
}

impl<T> OrRaise<T> for Result<T, IoError> {
    fn or_raise(self) -> T {
        self.unwrap_or_else(|e| raise_io(e))
    }
}
