//! Varlena helpers shared by the `tin` and `linetree` types: a result
//! Datum from bytes, the bytes of a binary (`*_recv`) or hex text (`*_in`)
//! input.

use pgrx::pg_sys;
use pgrx::prelude::*;
use std::ffi::CStr;

use super::errors::raise;
use tinmerge_core::tin::layout;

/// Largest value we write: under PostgreSQL's 1 GB varlena limit.
const MAX_VALUE_BYTES: usize = (1 << 30) - 1024;

/// Copy storage bytes into a palloc'd varlena Datum (ERROR beyond 1 GB).
pub(crate) fn varlena_datum(bytes: &[u8], what: &str) -> pg_sys::Datum {
    if bytes.len() > MAX_VALUE_BYTES {
        raise(
            PgSqlErrorCode::ERRCODE_PROGRAM_LIMIT_EXCEEDED,
            format!(
                "{what} value of {} bytes exceeds the 1 GB limit of one value; use a larger tolerance or tiles",
                bytes.len()
            ),
        );
    }
    // SAFETY: total bytes are palloc'd (at most 1 GB plus the header, checked
    // above) and written whole: the header by set_varsize_4b, the rest by the
    // copy from a slice that cannot overlap the new allocation.
    unsafe {
        let total = bytes.len() + pg_sys::VARHDRSZ;
        let p = pg_sys::palloc(total) as *mut u8;
        std::ptr::copy_nonoverlapping(bytes.as_ptr(), p.add(pg_sys::VARHDRSZ), bytes.len());
        pgrx::set_varsize_4b(p as *mut pg_sys::varlena, total as i32);
        pg_sys::Datum::from(p)
    }
}

/// The bytes of a binary-input buffer (`*_recv`), consumed.
pub(crate) fn recv_bytes(buf: &mut pgrx::datum::Internal, what: &str) -> Vec<u8> {
    // SAFETY: a *_recv function's internal argument is the StringInfo of the
    // message being read (PostgreSQL's receive protocol).
    let si = unsafe { buf.get_mut::<pg_sys::StringInfoData>() }.unwrap_or_else(|| {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_BINARY_REPRESENTATION,
            format!("no {what} data"),
        )
    });
    let (start, len) = (si.cursor.max(0) as usize, si.len.max(0) as usize);
    let bytes: Vec<u8> = if len > start {
        // SAFETY: data holds len bytes and start < len (both clamped to >= 0).
        unsafe { std::slice::from_raw_parts((si.data as *const u8).add(start), len - start) }
            .to_vec()
    } else {
        Vec::new()
    };
    si.cursor = si.len;
    bytes
}

/// The bytes of a text input (`*_in`: hex of the binary form); an ERROR
/// naming the type for anything else.
pub(crate) fn hex_input(input: &CStr, what: &str) -> Vec<u8> {
    let code = PgSqlErrorCode::ERRCODE_INVALID_TEXT_REPRESENTATION;
    let text = input
        .to_str()
        .unwrap_or_else(|_| raise(code, format!("{what} text is not valid UTF-8")));
    layout::from_hex(text).unwrap_or_else(|e| {
        let msg = match e {
            tinmerge_core::tin::TinError::Corrupt(m) => m,
            other => other.to_string(),
        };
        raise(code, format!("invalid {what} value: {msg}"))
    })
}
