//! The SQL layer: converts arguments, calls the pure core, maps errors to
//! SQLSTATEs. Nothing algorithmic lives here.

use pgrx::prelude::*;

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

// SAFETY: the argument is unboxed as its Datum through FromDatum above,
// which only wraps it; a NULL is an ERROR, never a value.
        unsafe impl<'fcx> pgrx::callconv::ArgAbi<'fcx> for $name {
            unsafe fn unbox_arg_unchecked(arg: pgrx::callconv::Arg<'_, 'fcx>) -> Self {
                let i = arg.index();
// SAFETY: the function's declared argument type is $sql, the type this
// wrapper stands for.
                unsafe { arg.unbox_arg_using_from_datum() }.unwrap_or_else(|| {
                    $crate::pg::errors::raise(
                        pgrx::PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
                        format!("{} argument {i} is NULL", $sql),
                    )
                })
            }
        }

        // as an element of an array argument (`tin[]`): the element's
        // Datum, which lives as long as the detoasted array
// SAFETY: the element's Datum is kept as it is, valid as long as the
// detoasted array it came from ('src).
        unsafe impl pgrx::datum::UnboxDatum for $name {
            type As<'src> = $name;
            unsafe fn unbox<'src>(datum: pgrx::datum::Datum<'src>) -> Self::As<'src>
            where
                Self: 'src,
            {
// SAFETY: an element Datum of an array of $sql.
                $name(unsafe { <pgrx::pg_sys::Datum as pgrx::datum::UnboxDatum>::unbox(datum) })
            }
        }

        pgrx::pgrx_sql_entity_graph::impl_sql_translatable!($name, arg_only = $sql);
    };
}

/// Run `$body` with `$m` bound to the tin's mesh: the decoded value, or the
/// stored value read in slices ([`tin_type::TinArg::mesh_source`]), and
/// `$l` to the resolved level, `$srid` to the tin's SRID. The body is
/// compiled for both, so a merge written over `tin::mesh::Indexed` runs on
/// either.
macro_rules! with_mesh {
    ($t:expr, $level:expr, |$m:ident, $l:ident, $srid:ident| $body:expr) => {
        match $t.mesh_source() {
            $crate::pg::tin_type::MeshSource::Decoded(tin) => {
                let $l = $crate::pg::errors::OrRaise::or_raise(tin.level_index($level));
                let $srid = tin.srid;
                let $m: &tinmerge_core::tin::Tin = &tin;
                $body
            }
            $crate::pg::tin_type::MeshSource::Sliced(s) => {
                let h = s.header();
                let $l = $crate::pg::errors::OrRaise::or_raise(tinmerge_core::tin::resolve_level(
                    $level,
                    h.levels.len(),
                ));
                let $srid = h.srid;
                let mut fetch = $t.fetch();
                let reader = s.reader(&mut fetch);
                let $m = &reader;
                $body
            }
        }
    };
}

mod analysis;
mod area;
mod args;
mod build;
mod cache;
mod compat;
mod errors;
mod header;
mod interrupt;
mod level;
mod line;
mod linetree;
mod memory;
mod overlay;
mod overviews;
mod planner;
mod point;
mod points_agg;
mod progress;
mod raster;
mod render;
mod serve;
mod table_source;
mod table_tiles;
mod threads;
mod tin_type;
mod varlena;
mod viewshed;

::pgrx::pg_module_magic!(name, version);

// The public SQL signatures (geometry/raster wrappers, operators), after
// every Rust function they call.
extension_sql_file!("../../sql/tinmerge.sql", name = "public_api", finalize);

#[pg_guard]
pub extern "C-unwind" fn _PG_init() {
    cache::define_guc();
    memory::define_guc();
    threads::define_guc();
    progress::define_guc();
    planner::init();
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

    /// A tin built from samples of a plane is that plane at every level:
    /// heights at points off the samples, and the heights of a profile,
    /// against the plane's own formula (z = 3x - 2y + 7; the samples a
    /// 12 x 12 grid of unit cells, jittered by a seeded sequence).
    #[pg_test]
    fn heights_on_a_plane_are_the_plane() {
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis").unwrap();
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis_raster").unwrap();
        Spi::run(
            "CREATE TABLE pt_plane AS
             SELECT tin_from_points(ST_SetSRID(ST_Collect(ST_MakePoint(x, y, 3 * x - 2 * y + 7)), 32616), 0.01, 3) AS t
             FROM (SELECT i + 0.3 * sin(i * 7 + j * 13) AS x, j + 0.3 * cos(i * 5 + j * 11) AS y
                   FROM generate_series(0, 11) i, generate_series(0, 11) j) s",
        )
        .unwrap();
        let worst: Option<f64> = Spi::get_one(
            "SELECT max(abs(tin_height(t, ST_SetSRID(ST_MakePoint(x, y), 32616), l) - (3 * x - 2 * y + 7)))
             FROM pt_plane, generate_series(0, 2) l,
                  (SELECT 1 + 9 * random_x AS x, 1 + 9 * random_y AS y
                   FROM (SELECT (k * 0.618034) % 1 AS random_x, (k * 0.414214) % 1 AS random_y
                         FROM generate_series(1, 200) k) r) p",
        )
        .unwrap();
        let worst = worst.expect("heights inside the samples' hull");
        assert!(worst < 1e-9, "heights off the plane by {worst}");
        let profile: Option<f64> = Spi::get_one(
            "SELECT max(abs(p.z - (3 * ST_X(q) - 2 * ST_Y(q) + 7)))
             FROM pt_plane, LATERAL (SELECT 'SRID=32616;LINESTRING(1.5 1.5, 9.5 8.25, 2 9)'::geometry AS g) g,
                  tin_line_profile(t, g.g) p,
                  LATERAL (SELECT ST_LineInterpolatePoint(g.g, p.distance / ST_Length(g.g)) AS q) q",
        )
        .unwrap();
        let profile = profile.expect("a profile");
        assert!(profile < 1e-9, "profile heights off the plane by {profile}");
    }

    /// Bad input is an ERROR with its SQLSTATE, not a crash: caught in
    /// PL/pgSQL, one per mistake.
    #[pg_test]
    fn bad_input_is_an_error_with_its_sqlstate() {
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis").unwrap();
        Spi::run("CREATE EXTENSION IF NOT EXISTS postgis_raster").unwrap();
        Spi::run(
            "CREATE FUNCTION pt_state(q text) RETURNS text LANGUAGE plpgsql AS $$
             BEGIN EXECUTE q; RETURN 'ok'; EXCEPTION WHEN others THEN RETURN SQLSTATE; END $$",
        )
        .unwrap();
        let tin = "tin_from_points('SRID=32616;MULTIPOINT Z (0 0 1, 10 0 2, 0 10 3, 10 10 9)'::geometry, 0.5, 1)";
        for (q, want) in [
            // another SRID
            (
                format!("SELECT tin_height({tin}, 'SRID=4326;POINT(1 1)'::geometry)"),
                "22023",
            ),
            // a bad level
            (
                format!("SELECT tin_height({tin}, 'SRID=32616;POINT(1 1)'::geometry, 7)"),
                "22023",
            ),
            // not a tin
            ("SELECT 'deadbeef'::tin".to_string(), "22P02"),
            // a good call
            (
                format!("SELECT tin_height({tin}, 'SRID=32616;POINT(1 1)'::geometry)"),
                "ok",
            ),
        ] {
            let got: Option<String> =
                Spi::get_one_with_args("SELECT pt_state($1)", &[q.as_str().into()]).unwrap();
            assert_eq!(got.as_deref(), Some(want), "{q}");
        }
    }
}
