//! Checks shared by the functions that take PostGIS geometries: SRIDs and
//! geometry types, with messages that say what was received.

use pgrx::pg_sys;
use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::varlena::varlena_datum;
use pgrx::callconv::{BoxRet, FcInfo};
use pgrx::datum::Datum as RetDatum;
use tinmerge_core::io::gserialized;

raw_datum_arg!(
    /// A PostGIS `geometry` argument as the raw Datum: read in PostGIS's own
    /// serialisation (see [`gserialized`]) with no conversion to WKB.
    GeomArg,
    "geometry"
);

impl GeomArg {
    /// The value's bytes after the varlena header (detoasted if needed,
    /// short headers accepted).
    pub fn bytes(&self) -> &[u8] {
        unsafe {
            let v = pg_sys::pg_detoast_datum_packed(self.0.cast_mut_ptr());
            pgrx::varlena::varlena_to_byte_slice(v)
        }
    }

    /// The x, y of a POINT argument (None for `POINT EMPTY`), after the SRID
    /// check; an ERROR naming the type for anything but a point.
    pub fn point_xy(&self, tin_srid: i32, func: &str) -> Option<[f64; 2]> {
        let p = gserialized::peek(self.bytes()).or_raise();
        check_srid(p.srid, tin_srid, func);
        if p.has_m {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                "geometries with M coordinates are not supported; use ST_Force3DZ or ST_Force2D",
            );
        }
        match p.point {
            Some(Some(xy)) => {
                tinmerge_core::tin::check_xy(&format!("{func}: the point"), xy[0], xy[1])
                    .or_raise();
                Some(xy)
            }
            Some(None) => None,
            None => not_a_point(func, gserialized::type_name(p.type_code)),
        }
    }
}

/// A `geometry` result: PostGIS's serialisation after the varlena header,
/// as [`gserialized::write`] gives it.
pub struct GeomOut(pub Vec<u8>);

unsafe impl BoxRet for GeomOut {
    unsafe fn box_into<'fcx>(self, fcinfo: &mut FcInfo<'fcx>) -> RetDatum<'fcx> {
        unsafe { fcinfo.return_raw_datum(varlena_datum(&self.0, "geometry")) }
    }
}

impl pgrx::IntoDatum for GeomOut {
    fn into_datum(self) -> Option<pg_sys::Datum> {
        Some(varlena_datum(&self.0, "geometry"))
    }
    fn type_oid() -> pg_sys::Oid {
        pg_sys::InvalidOid
    }
}

pgrx::pgrx_sql_entity_graph::impl_sql_translatable!(GeomOut, "geometry");

fn not_a_point(func: &str, type_name: &str) -> ! {
    raise(
        PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
        format!(
            "{func} takes a POINT, got a {type_name}{}",
            if type_name == "MULTIPOINT" {
                " (use tin_drape for MULTIPOINT, or ST_Dump it)"
            } else {
                ""
            }
        ),
    )
}

/// ERROR unless the SRIDs agree (0 on either side means "unknown": accepted).
pub fn check_srid(geom_srid: i32, tin_srid: i32, func: &str) {
    if geom_srid != 0 && tin_srid != 0 && geom_srid != tin_srid {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: geometry has SRID {geom_srid} but the tin has SRID {tin_srid}; transform it first, e.g. ST_Transform(geom, {tin_srid})"
            ),
        );
    }
}

thread_local! {
    /// The OID of PostGIS's `ST_IsValidReason(geometry)`, looked up once per
    /// backend (and again if that function is gone).
    static IS_VALID_REASON: std::cell::Cell<Option<pg_sys::Oid>> = const { std::cell::Cell::new(None) };
}

impl GeomArg {
    /// PostGIS's own verdict on the geometry: `ST_IsValidReason(geom)`
    /// ("Valid Geometry", or what is wrong and where), called directly by
    /// its OID, so a Rust function taking a polygon checks validity as
    /// PostGIS does without a SQL wrapper to plan. The function is found
    /// through the calling function's search_path (pinned to PostGIS's
    /// schema by `SET search_path FROM CURRENT` in sql/tinmerge.sql).
    pub fn postgis_validity(&self) -> String {
        unsafe {
            let cached = IS_VALID_REASON.get().filter(|oid| {
                pg_sys::SearchSysCacheExists(
                    pg_sys::SysCacheIdentifier::PROCOID as i32,
                    pg_sys::Datum::from(*oid),
                    pg_sys::Datum::from(0),
                    pg_sys::Datum::from(0),
                    pg_sys::Datum::from(0),
                )
            });
            let oid = match cached {
                Some(oid) => oid,
                None => {
                    let geometry = pg_sys::TypenameGetTypid(c"geometry".as_ptr());
                    if geometry == pg_sys::InvalidOid {
                        raise(
                            PgSqlErrorCode::ERRCODE_UNDEFINED_OBJECT,
                            "PostGIS's geometry type is not on the search_path",
                        );
                    }
                    let name = pg_sys::stringToQualifiedNameList(c"st_isvalidreason".as_ptr());
                    // errors (undefined function) when PostGIS lacks it
                    let oid = pg_sys::LookupFuncName(name, 1, &geometry, false);
                    IS_VALID_REASON.set(Some(oid));
                    oid
                }
            };
            let reason = pg_sys::OidFunctionCall1Coll(oid, pg_sys::InvalidOid, self.0);
            let c = pg_sys::text_to_cstring(reason.cast_mut_ptr());
            let s = std::ffi::CStr::from_ptr(c).to_string_lossy().into_owned();
            pg_sys::pfree(c.cast());
            s
        }
    }
}
