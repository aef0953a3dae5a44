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
