//! Checks shared by the functions that take PostGIS geometries: SRIDs and
//! geometry types, with messages that say what was received.

use pgrx::pg_sys;
use pgrx::prelude::*;

use super::errors::{raise, raise_hint, OrRaise};
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
    /// The argument as it was passed, before any detoasting: its varlena
    /// bytes (the value itself, its compressed form, or, for a value stored
    /// out of line, the 18-byte TOAST pointer), and whether they are an
    /// on-disk TOAST pointer, which names the value only while this
    /// transaction runs (as PostGIS's TOAST-keyed cache keys by it). None
    /// for an in-memory pointer (indirect or expanded).
    pub fn as_passed(&self) -> Option<(&[u8], bool)> {
        let p = self.0.cast_mut_ptr::<pg_sys::varlena>();
        // SAFETY: self.0 is a non-NULL varlena Datum of this call; its first
        // byte tells the varlena kind and varsize_any reads its length from
        // the header of that kind, all within the value as passed.
        unsafe {
            let on_disk = pgrx::varatt_is_1b_e(p)
                && pgrx::vartag_external(p) as u32 == pg_sys::vartag_external::VARTAG_ONDISK;
            if pgrx::varatt_is_1b_e(p) && !on_disk {
                return None;
            }
            let n = pgrx::varsize_any(p);
            Some((std::slice::from_raw_parts(p as *const u8, n), on_disk))
        }
    }

    /// The value's bytes after the varlena header (detoasted if needed,
    /// short headers accepted).
    pub fn bytes(&self) -> &[u8] {
        // SAFETY: self.0 is a non-NULL geometry Datum of this call (raw_datum_arg!),
        // valid while the call runs; the detoasted copy is palloc'd in the current
        // memory context, which outlives the returned borrow of self.
        unsafe {
            let v = pg_sys::pg_detoast_datum_packed(self.0.cast_mut_ptr());
            pgrx::varlena::varlena_to_byte_slice(v)
        }
    }

    /// The x, y of a POINT argument (None for `POINT EMPTY`), after the SRID
    /// check; an ERROR naming the type for anything but a point.
    pub fn point_xy(&self, tin_srid: i32, func: &str) -> Option<[f64; 2]> {
        let p = gserialized::peek(self.bytes()).or_raise();
        check_srid(p.srid, tin_srid, func, "pt", p.point.flatten());
        if p.has_m {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                "geometries with M coordinates are not supported; use ST_Force3DZ or ST_Force2D",
            );
        }
        match p.point {
            Some(Some(xy)) => {
                tinmerge_core::tin::check_xy(format_args!("{func}: the point"), xy[0], xy[1])
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

// SAFETY: box_into returns the palloc'd varlena made by varlena_datum, a
// valid Datum of the declared result type.
unsafe impl BoxRet for GeomOut {
    unsafe fn box_into<'fcx>(self, fcinfo: &mut FcInfo<'fcx>) -> RetDatum<'fcx> {
        // SAFETY: a freshly palloc'd, fully written varlena (varlena_datum).
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

/// ERROR unless the geometry has the tin's SRID, as PostGIS refuses
/// geometries of mixed SRIDs, 0 (none) included: a point without an SRID
/// taken as if it were in the tin's answered quietly, often NULL (a
/// longitude/latitude point on a UTM tin). `at`: a coordinate of the
/// geometry, for the hint when it has none and looks like longitude and
/// latitude.
pub fn check_srid(geom_srid: i32, tin_srid: i32, func: &str, arg: &str, at: Option<[f64; 2]>) {
    if geom_srid == tin_srid {
        return;
    }
    let code = PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE;
    if geom_srid == 0 {
        let lonlat = at.is_some_and(|p| p[0].abs() <= 180.0 && p[1].abs() <= 90.0);
        raise_hint(
            code,
            format!("{func}: {arg} has no SRID (0) but the tin has SRID {tin_srid}"),
            if lonlat && tin_srid != 4326 {
                format!("its coordinates look like longitude and latitude: ST_Transform(ST_SetSRID({arg}, 4326), {tin_srid}); if they are in the tin's SRID already, ST_SetSRID({arg}, {tin_srid})")
            } else {
                format!("give it the tin's SRID with ST_SetSRID({arg}, {tin_srid}) if its coordinates are in it, or ST_Transform(ST_SetSRID({arg}, srid), {tin_srid}) from the SRID they are in")
            },
        );
    }
    if tin_srid == 0 {
        raise_hint(
            code,
            format!("{func}: {arg} has SRID {geom_srid} but the tin has none (0)"),
            format!(
                "build the tin from samples with an SRID, or query it with ST_SetSRID({arg}, 0)"
            ),
        );
    }
    raise(
        code,
        format!(
            "{func}: {arg} has SRID {geom_srid} but the tin has SRID {tin_srid}; transform it first, e.g. ST_Transform({arg}, {tin_srid})"
        ),
    );
}

/// The first x, y of a geometry (None when it is empty).
pub fn first_xy(g: &tinmerge_core::io::ewkb::Geom) -> Option<[f64; 2]> {
    let mut first = None;
    g.for_each_coord(&mut |c| {
        if first.is_none() {
            first = Some([c[0], c[1]]);
        }
    });
    first
}

thread_local! {
    /// The OIDs of PostGIS's `ST_IsValidReason(geometry)` and
    /// `ST_Transform(geometry, int)`, looked up once per backend (and again
    /// if the function is gone).
    static IS_VALID_REASON: std::cell::Cell<Option<pg_sys::Oid>> = const { std::cell::Cell::new(None) };
    static TRANSFORM: std::cell::Cell<Option<pg_sys::Oid>> = const { std::cell::Cell::new(None) };
}

thread_local! {
    /// PostGIS's schema (quoted for SQL) and its `geometry` type, looked
    /// up once per backend (and again if the type is gone).
    static POSTGIS: std::cell::RefCell<Option<(String, pg_sys::Oid)>> = const { std::cell::RefCell::new(None) };
}

/// PostGIS's schema, quoted for SQL, and the OID of its `geometry` type,
/// from the catalogs (`pg_extension`), whatever the session's search_path:
/// the Rust functions that call PostGIS or read its spatial_ref_sys name
/// them in that schema, so they pin no search_path (a function with a `SET`
/// clause pays a configuration change on every call: 6 % of a zonal join's
/// time, 0.27.0). An ERROR when PostGIS is not installed.
pub fn postgis() -> (String, pg_sys::Oid) {
    let held = POSTGIS.with(|c| c.borrow().clone()).filter(|(_, oid)| {
        // SAFETY: a catalog cache probe inside a transaction.
        unsafe {
            pg_sys::SearchSysCacheExists(
                pg_sys::SysCacheIdentifier::TYPEOID as i32,
                pg_sys::Datum::from(*oid),
                pg_sys::Datum::from(0),
                pg_sys::Datum::from(0),
                pg_sys::Datum::from(0),
            )
        }
    });
    if let Some(p) = held {
        return p;
    }
    let found = Spi::get_two::<String, pg_sys::Oid>(
        "SELECT pg_catalog.quote_ident(n.nspname), t.oid \
         FROM pg_catalog.pg_extension e \
         JOIN pg_catalog.pg_namespace n ON n.oid OPERATOR(pg_catalog.=) e.extnamespace \
         JOIN pg_catalog.pg_type t ON t.typnamespace OPERATOR(pg_catalog.=) n.oid \
          AND t.typname OPERATOR(pg_catalog.=) 'geometry' \
         WHERE e.extname OPERATOR(pg_catalog.=) 'postgis'",
    );
    let p = match found {
        Ok((Some(schema), Some(oid))) => (schema, oid),
        _ => raise(
            PgSqlErrorCode::ERRCODE_UNDEFINED_OBJECT,
            "PostGIS is not installed in this database (CREATE EXTENSION postgis)",
        ),
    };
    POSTGIS.with(|c| *c.borrow_mut() = Some(p.clone()));
    p
}

/// The OID of PostGIS's `geometry` type.
fn geometry_oid() -> pg_sys::Oid {
    postgis().1
}

/// The OID of the PostGIS function `name(args)`, found in PostGIS's schema
/// ([`postgis`]) and cached in `cell` while it exists.
fn postgis_proc(
    cell: &'static std::thread::LocalKey<std::cell::Cell<Option<pg_sys::Oid>>>,
    name: &str,
    args: impl FnOnce() -> Vec<pg_sys::Oid>,
) -> pg_sys::Oid {
    // SAFETY: catalog lookups inside a transaction, with a NUL-terminated name
    // and an argument OID array that lives across the call (args); an error in
    // them is a PostgreSQL ERROR, which pgrx turns into a Rust panic unwound
    // safely.
    unsafe {
        let cached = cell.get().filter(|oid| {
            pg_sys::SearchSysCacheExists(
                pg_sys::SysCacheIdentifier::PROCOID as i32,
                pg_sys::Datum::from(*oid),
                pg_sys::Datum::from(0),
                pg_sys::Datum::from(0),
                pg_sys::Datum::from(0),
            )
        });
        match cached {
            Some(oid) => oid,
            None => {
                let args = args();
                let qualified = std::ffi::CString::new(format!("{}.{name}", postgis().0))
                    .unwrap_or_else(|_| {
                        raise(
                            PgSqlErrorCode::ERRCODE_INVALID_NAME,
                            "PostGIS's schema name holds a NUL",
                        )
                    });
                let list = pg_sys::stringToQualifiedNameList(qualified.as_ptr());
                // errors (undefined function) when PostGIS lacks it
                let oid = pg_sys::LookupFuncName(list, args.len() as i32, args.as_ptr(), false);
                cell.set(Some(oid));
                oid
            }
        }
    }
}

/// Points from SRID `from` to SRID `to` through PostGIS's own
/// `ST_Transform(geometry, int)` (PROJ, with PostGIS's spatial_ref_sys),
/// called by OID with one MULTIPOINT; an ERROR for an unknown SRID or a
/// point PROJ cannot transform, or a result that is not finite.
pub fn postgis_transform(pts: &[[f64; 2]], from: i32, to: i32) -> Vec<[f64; 2]> {
    use tinmerge_core::io::ewkb::Geom;
    if pts.is_empty() {
        return Vec::new();
    }
    let g = Geom::MultiPoint(pts.iter().map(|p| [p[0], p[1], f64::NAN]).collect());
    let bytes = gserialized::write(from, false, &g);
    let oid = postgis_proc(&TRANSFORM, "st_transform", || {
        vec![geometry_oid(), pg_sys::INT4OID]
    });
    // SAFETY: the argument is a complete palloc'd geometry varlena and the
    // function is ST_Transform(geometry, int) by OID; its non-NULL result is a
    // geometry varlena in the current memory context, read before it is freed.
    let out = unsafe {
        let d = varlena_datum(&bytes, "geometry");
        let r = pg_sys::OidFunctionCall2Coll(oid, pg_sys::InvalidOid, d, pg_sys::Datum::from(to));
        let v = pg_sys::pg_detoast_datum_packed(r.cast_mut_ptr());
        gserialized::read(pgrx::varlena::varlena_to_byte_slice(v)).or_raise()
    };
    let Geom::MultiPoint(q) = out.geom else {
        raise(
            PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
            "ST_Transform returned something other than a MULTIPOINT",
        );
    };
    if q.len() != pts.len() || q.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("ST_Transform from SRID {from} to {to} gave points that are not finite: the terrain is outside where that projection is defined"),
        );
    }
    q.into_iter().map(|p| [p[0], p[1]]).collect()
}

impl GeomArg {
    /// PostGIS's own verdict on the geometry: `ST_IsValidReason(geom)`
    /// ("Valid Geometry", or what is wrong and where), called directly by
    /// its OID, so a Rust function taking a polygon checks validity as
    /// PostGIS does without a SQL wrapper to plan. The function is found in
    /// PostGIS's schema ([`postgis`]).
    pub fn postgis_validity(&self) -> String {
        // SAFETY: self.0 is this call's non-NULL geometry Datum; ST_IsValidReason
        // returns a non-NULL text, turned into a palloc'd C string that is copied
        // and then freed.
        unsafe {
            let oid = postgis_proc(
                &IS_VALID_REASON,
                "st_isvalidreason",
                || vec![geometry_oid()],
            );
            let reason = pg_sys::OidFunctionCall1Coll(oid, pg_sys::InvalidOid, self.0);
            let c = pg_sys::text_to_cstring(reason.cast_mut_ptr());
            let s = std::ffi::CStr::from_ptr(c).to_string_lossy().into_owned();
            pg_sys::pfree(c.cast());
            s
        }
    }
}
