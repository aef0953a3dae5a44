//! Compatibility shims: C symbols that older install scripts declare. Each
//! `#[pg_extern(sql = false)]` here is a function no current install
//! creates, kept because `CREATE EXTENSION tinmerge VERSION '0.x'` and the
//! upgrade chain run the frozen scripts in `sql/versions/`, and PostgreSQL
//! checks that every C symbol they name exists. Each says which scripts
//! need it; `tests/upgrade.sh` installs 0.1.0 and updates through them
//! all. They call the current entry points.

use pgrx::prelude::*;

use super::area::{ewkb_area, stats_row, triangles_rows, volume_row, StatsRow};
use super::build::{
    _tin_from_points_domain, _tin_from_raster_domain, _tin_from_raster_tolerances_domain,
};
#[cfg(not(feature = "bench"))]
use super::errors::raise;
use super::errors::OrRaise;
use super::line::drape_checked;
use super::raster::{_tin_raster_owners, _tin_raster_zonal};
use super::tin_type::{tin_level, TinArg, TinOut};
use tinmerge_core::io::ewkb;

// ---- builds

/// 0.8.0's build of `tin_from_raster` with breaklines, declared by
/// `tinmerge--0.7.0--0.8.0.sql`: [`_tin_from_raster_domain`] without a
/// boundary.
#[allow(clippy::too_many_arguments)]
#[pg_extern(sql = false)]
fn _tin_from_raster_breaklines(
    rast: Option<&[u8]>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    band: Option<i32>,
    keep_border: Option<bool>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
) -> Option<TinOut> {
    _tin_from_raster_domain(
        rast,
        tolerance,
        levels,
        band,
        keep_border,
        breaklines,
        soft_breaklines,
        None,
        Some(true),
    )
}

/// 0.8.0's `tin_from_raster(raster, float8[], ...)` with breaklines,
/// declared by `tinmerge--0.7.0--0.8.0.sql`:
/// [`_tin_from_raster_tolerances_domain`] without a boundary.
#[pg_extern(sql = false)]
fn _tin_from_raster_tolerances_breaklines(
    rast: Option<&[u8]>,
    tolerances: Option<Vec<Option<f64>>>,
    band: Option<i32>,
    keep_border: Option<bool>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
) -> Option<TinOut> {
    _tin_from_raster_tolerances_domain(
        rast,
        tolerances,
        band,
        keep_border,
        breaklines,
        soft_breaklines,
        None,
        Some(true),
    )
}

/// 0.8.0's `tin_from_points` with breaklines, declared by
/// `tinmerge--0.7.0--0.8.0.sql`: [`_tin_from_points_domain`] without a
/// boundary.
#[pg_extern(sql = false)]
fn _tin_from_points_breaklines(
    pts: Option<&[u8]>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
) -> Option<TinOut> {
    _tin_from_points_domain(pts, tolerance, levels, breaklines, soft_breaklines, None)
}

// ---- the area merge

/// The EWKB entry point of 0.1.0 to 0.6.0 (the polygon as EWKB, PostGIS's
/// verdict as an argument), declared by `tinmerge--0.1.0.sql`.
#[pg_extern(sql = false)]
fn _tin_area_triangles(
    t: Option<TinArg>,
    area: Option<&[u8]>,
    level: Option<i32>,
    compact: Option<bool>,
    validity: Option<&str>,
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(level, i32),
        name!(relation, String),
        name!(coverage, f64),
    ),
> {
    let (Some(t), Some(area)) = (t, area) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(triangles_rows(
        &t,
        level,
        compact.unwrap_or(false),
        &|srid| ewkb_area(area, validity, srid, "tin_area_triangles"),
    ))
}

/// The EWKB entry point of 0.1.0 to 0.6.0 (the polygon as EWKB, PostGIS's
/// verdict as an argument), declared by `tinmerge--0.1.0.sql`.
#[allow(clippy::type_complexity)]
#[pg_extern(sql = false)]
fn _tin_area_stats(
    t: Option<TinArg>,
    area: Option<&[u8]>,
    level: Option<i32>,
    validity: Option<&str>,
    geographic: Option<bool>,
) -> TableIterator<
    'static,
    (
        name!(area2d, f64),
        name!(area3d, f64),
        name!(min_z, Option<f64>),
        name!(max_z, Option<f64>),
        name!(mean_z, Option<f64>),
        name!(mean_slope, Option<f64>),
        name!(max_slope, Option<f64>),
    ),
> {
    let (Some(t), Some(area)) = (t, area) else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    TableIterator::new(vec![stats_row(&t, level, geographic, &|srid| {
        ewkb_area(area, validity, srid, "tin_area_stats")
    })])
}

/// The EWKB entry point of 0.1.0 to 0.6.0 (the polygon as EWKB, PostGIS's
/// verdict as an argument), declared by `tinmerge--0.1.0.sql`.
#[pg_extern(sql = false)]
fn _tin_volume(
    t: Option<TinArg>,
    area: Option<&[u8]>,
    base_z: Option<f64>,
    level: Option<i32>,
    validity: Option<&str>,
    geographic: Option<bool>,
) -> TableIterator<'static, (name!(cut, f64), name!(fill, f64))> {
    let (Some(t), Some(area), Some(base)) = (t, area, base_z) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(vec![volume_row(&t, base, level, geographic, &|srid| {
        ewkb_area(area, validity, srid, "tin_volume")
    })])
}

/// Installs without the `bench` feature keep only the symbol of
/// `_tin_area_examined`: the frozen install scripts of 0.1.0 to 0.3.0 declare
/// the function (run by `CREATE EXTENSION tinmerge VERSION '0.x'` and by the
/// upgrade chain), and PostgreSQL checks the symbol exists when they do.
/// 0.4.0 drops the SQL function (`tinmerge--0.3.0--0.4.0.sql`); a database
/// still on an older version gets this error if it calls it.
#[cfg(not(feature = "bench"))]
#[pg_extern(sql = false)]
fn _tin_area_examined(_t: TinArg, _area: &[u8], _level: Option<i32>, _method: &str) -> i64 {
    raise(
        PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
        "_tin_area_examined is a benchmark entry point, only in builds with the bench feature (make bench); ALTER EXTENSION tinmerge UPDATE removes it",
    )
}

// ---- the raster merge

/// 0.1.0 to 0.6.0's `_tin_raster_stats` (without `half_open`), declared by
/// `tinmerge--0.1.0.sql`; a database still on one of them calls it.
/// 0.7.0's `tin_raster_stats` calls `_tin_raster_zonal`.
#[allow(clippy::type_complexity)]
#[pg_extern(sql = false)]
fn _tin_raster_stats(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
    band: Option<i32>,
    weighted: Option<bool>,
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(count, i64),
        name!(sum, f64),
        name!(mean, f64),
        name!(min, f64),
        name!(max, f64),
        name!(mode, Option<f64>),
    ),
> {
    _tin_raster_zonal(t, rast, level, band, weighted, Some(false))
}

/// 0.1.0 to 0.6.0's `_tin_raster_pixels` (without `half_open`), kept as a
/// symbol only (see `_tin_raster_stats`).
#[pg_extern(sql = false)]
fn _tin_raster_pixels(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
    band: Option<i32>,
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(col, i32),
        name!(row, i32),
        name!(value, f64),
    ),
> {
    _tin_raster_owners(t, rast, level, band, Some(false))
}

// ---- the line merge

/// The EWKB form that `tin_drape` was a SQL wrapper over until 0.4.0,
/// declared by `tinmerge--0.1.0.sql`, so the symbol stays (and
/// works, for a database not yet updated); 0.5.0 drops the SQL function.
#[pg_extern(sql = false)]
fn _tin_drape(
    t: Option<TinArg>,
    geom: Option<&[u8]>,
    level: default!(Option<i32>, "NULL"),
) -> Option<Vec<u8>> {
    let (t, geom) = (t?, geom?);
    let (tin, l) = tin_level(&t, level);
    let g = ewkb::read(geom).or_raise();
    let out = drape_checked(&tin, l, &g)?;
    Some(ewkb::Writer::write(g.srid, true, &out))
}
