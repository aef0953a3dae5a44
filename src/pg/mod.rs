//! The SQL layer: converts arguments, calls the pure core, maps errors to
//! SQLSTATEs. Nothing algorithmic lives here.

use pgrx::prelude::*;
use pgrx::{GucContext, GucFlags, GucRegistry, GucSetting};

use crate::io::IoError;
use crate::tin::TinError;

/// Declare an argument type that keeps the raw Datum of SQL type `$sql`
/// (no detoast, no copy): `FromDatum`, `ArgAbi` (a NULL where the function
/// is STRICT is an ERROR naming the argument) and the SQL type mapping.
macro_rules! raw_datum_arg {
    ($(#[$doc:meta])* $name:ident, $sql:literal) => {
        $(#[$doc])*
        pub struct $name(pgrx::pg_sys::Datum);

        impl pgrx::FromDatum for $name {
            unsafe fn from_polymorphic_datum(
                d: pgrx::pg_sys::Datum,
                is_null: bool,
                _: pgrx::pg_sys::Oid,
            ) -> Option<Self> {
                (!is_null).then_some($name(d))
            }
        }

        unsafe impl<'fcx> pgrx::callconv::ArgAbi<'fcx> for $name {
            unsafe fn unbox_arg_unchecked(arg: pgrx::callconv::Arg<'_, 'fcx>) -> Self {
                let i = arg.index();
                unsafe { arg.unbox_arg_using_from_datum() }.unwrap_or_else(|| {
                    $crate::pg::raise(
                        pgrx::PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
                        format!("{} argument {i} is NULL", $sql),
                    )
                })
            }
        }

        pgrx::pgrx_sql_entity_graph::impl_sql_translatable!($name, arg_only = $sql);
    };
}

mod area;
mod args;
mod cache;
mod functions;
mod line;
mod linetree;
mod memory;
mod overlay;
mod point;
mod raster;
mod render;
mod threads;
mod types;

::pgrx::pg_module_magic!(name, version);

/// `tinmerge.cache_size`: MB of decoded tin values kept per backend.
pub static CACHE_SIZE_MB: GucSetting<i32> = GucSetting::<i32>::new(256);

#[pg_guard]
pub extern "C-unwind" fn _PG_init() {
    GucRegistry::define_int_guc(
        c"tinmerge.cache_size",
        c"Megabytes of decoded tin values cached per backend.",
        c"A query calling tinmerge functions once per row on the same tin decodes it once per backend; this bounds the memory those decoded values use (0 disables the cache).",
        &CACHE_SIZE_MB,
        0,
        64 * 1024,
        GucContext::Userset,
        GucFlags::UNIT_MB,
    );
    memory::define_guc();
    threads::define_guc();
}

/// Raise an ERROR with an SQLSTATE; never returns.
pub(crate) fn raise(code: PgSqlErrorCode, msg: impl Into<String>) -> ! {
    let msg: String = msg.into();
    ereport!(ERROR, code, msg);
}

/// The core's interrupt callback: PostgreSQL's CHECK_FOR_INTERRUPTS, then
/// the running `tinmerge.max_memory` check.
pub(crate) fn interrupt() -> Result<(), TinError> {
    pg_sys::check_for_interrupts!();
    memory::check()
}

/// The decoded tin of an argument and a level resolved against it (one
/// cache look-up per row).
pub(crate) fn tin_level(
    t: &types::TinArg,
    level: Option<i32>,
) -> (std::sync::Arc<crate::tin::Tin>, usize) {
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    (tin, l)
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

#[cfg(feature = "pg_test")]
#[pg_schema]
mod tests {
    use pgrx::prelude::*;

    #[pg_test]
    fn build_roundtrip_and_cache() {
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis").unwrap();
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis_raster").unwrap();
        let n: Option<i32> = Spi::get_one(
            "SELECT tin_num_levels(tin_from_points('SRID=32616;MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 9, 5 5 20)'::geometry, 0.5, 2))",
        )
        .unwrap();
        assert_eq!(n, Some(2));
        let same: Option<bool> = Spi::get_one(
            "WITH t AS (SELECT tin_from_points('SRID=32616;MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 9, 5 5 20)'::geometry, 0.5, 2) AS t)
             SELECT (t::text)::tin::text = t::text FROM t",
        )
        .unwrap();
        assert_eq!(same, Some(true));
    }
}
