//! SQL functions of the raster merge: `tin_raster_stats` (by pixel centre
//! or coverage-weighted), `tin_raster_pixels`, `tin_paint`. Rasters arrive as WKB (the SQL wrapper casts
//! `raster` to `bytea`). Not STRICT (a NULL level means finest): a NULL tin,
//! raster or band gives no rows.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::tin_level;
use super::tin_type::TinArg;
use tinmerge_core::io::raster::{self, Band, GeoTransform};
use tinmerge_core::merge::raster::stats::{is_data, paint, weighted_stats, zonal_stats};
use tinmerge_core::merge::raster::{sweep, PixelGrid};
use tinmerge_core::tin::Tin;

/// ERROR unless the raster and the tin both have an SRID and it is the same.
pub(super) fn check_raster_srid(raster_srid: i32, tin_srid: i32, func: &str) {
    if raster_srid == 0 || tin_srid == 0 || raster_srid != tin_srid {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            if raster_srid == 0 || tin_srid == 0 {
                format!(
                    "{func}: the raster (SRID {}) and the tin (SRID {}) must both have an SRID; set it with ST_SetSRID",
                    raster_srid, tin_srid
                )
            } else {
                format!(
                    "{func}: raster has SRID {} but the tin has SRID {}; transform it first, e.g. ST_Transform(rast, {})",
                    raster_srid, tin_srid, tin_srid
                )
            },
        );
    }
}

/// The band of a raster argument with its pixel grid; `None` when the
/// raster has no pixels or the band is flagged all-nodata (no rows).
fn raster_arg(
    tin: &Tin,
    rast: &[u8],
    band: i32,
    func: &str,
) -> Option<(GeoTransform, PixelGrid, Band)> {
    let head = raster::read(rast, None).or_raise();
    check_raster_srid(head.srid, tin.srid, func);
    if band < 1 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: band {band} does not exist: bands are numbered from 1"),
        );
    }
    if head.width == 0 || head.height == 0 {
        return None;
    }
    memory::reserve(
        tinmerge_core::io::raster::raster_bytes(head.width, head.height),
        || format!("{func}: reading a {} x {} raster", head.width, head.height),
    );
    let r = raster::read(rast, Some(band as usize)).or_raise();
    let grid = PixelGrid::new(&r.gt, r.width, r.height).or_raise();
    let b = r.band?;
    if b.all_nodata {
        return None;
    }
    Some((r.gt, grid, b))
}

type StatsRow = (i32, i64, f64, f64, f64, f64, Option<f64>);

#[allow(clippy::type_complexity)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
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
    let (Some(t), Some(rast), Some(band), Some(weighted)) = (t, rast, band, weighted) else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    let (tin, l) = tin_level(&t, level);
    let Some((gt, grid, b)) = raster_arg(&tin, rast, band, "tin_raster_stats") else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    super::threads::apply();
    let st = if weighted {
        weighted_stats(
            &tin,
            l,
            &gt,
            grid.width,
            grid.height,
            &b.values,
            b.nodata,
            true,
            &mut interrupt,
        )
    } else {
        zonal_stats(&tin, l, &grid, &b.values, b.nodata, true, &mut interrupt)
    }
    .or_raise();
    TableIterator::new(st.into_iter().map(|z| {
        (
            z.triangle as i32,
            z.count as i64,
            z.sum,
            z.mean(),
            z.min,
            z.max,
            z.mode,
        )
    }))
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_raster_stats(tin, bytea, int, int, boolean) ROWS 10000;
COMMENT ON FUNCTION _tin_raster_stats(tin, bytea, int, int, boolean) IS 'Internal: use tin_raster_stats(tin, raster, int, int, boolean).';
"#,
    name = "tin_raster_stats_sql",
    requires = [_tin_raster_stats]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
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
    let (Some(t), Some(rast), Some(band)) = (t, rast, band) else {
        return TableIterator::new(Vec::new());
    };
    let (tin, l) = tin_level(&t, level);
    let Some((_, grid, b)) = raster_arg(&tin, rast, band, "tin_raster_pixels") else {
        return TableIterator::new(Vec::new());
    };
    let w = grid.width;
    let mut rows = Vec::new();
    sweep(
        &tin,
        l,
        &grid,
        true,
        &mut interrupt,
        &mut |tri, r, c0, c1| {
            for c in c0..c1 {
                let v = b.values[r * w + c];
                if is_data(v, b.nodata) {
                    // PostGIS numbers pixels from 1
                    rows.push((tri as i32, c as i32 + 1, r as i32 + 1, v));
                }
            }
        },
    )
    .or_raise();
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_raster_pixels(tin, bytea, int, int) ROWS 100000;
COMMENT ON FUNCTION _tin_raster_pixels(tin, bytea, int, int) IS 'Internal: use tin_raster_pixels(tin, raster, int, int).';
"#,
    name = "tin_raster_pixels_sql",
    requires = [_tin_raster_pixels]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_paint(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(r, f64),
        name!(g, f64),
        name!(b, f64),
    ),
> {
    let (Some(t), Some(rast)) = (t, rast) else {
        return TableIterator::new(Vec::new());
    };
    let (tin, l) = tin_level(&t, level);
    let head = raster::read(rast, None).or_raise();
    if head.num_bands < 3 && head.width > 0 && head.height > 0 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_paint: the raster has {} band(s); it needs 3 (red, green, blue), e.g. ST_ColorMap(rast, 'grayscale') or ST_AddBand",
                head.num_bands
            ),
        );
    }
    let Some((_, grid, red)) = raster_arg(&tin, rast, 1, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let Some((_, _, green)) = raster_arg(&tin, rast, 2, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let Some((_, _, blue)) = raster_arg(&tin, rast, 3, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let rows = paint(
        &tin,
        l,
        &grid,
        [&red.values, &green.values, &blue.values],
        [red.nodata, green.nodata, blue.nodata],
        &mut interrupt,
    )
    .or_raise();
    TableIterator::new(
        rows.into_iter()
            .map(|(t, _, c)| (t as i32, c[0], c[1], c[2])),
    )
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_paint(tin, bytea, int) ROWS 10000;
COMMENT ON FUNCTION _tin_paint(tin, bytea, int) IS 'Internal: use tin_paint(tin, raster, int).';
"#,
    name = "tin_paint_sql",
    requires = [_tin_paint]
);
