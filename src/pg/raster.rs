//! SQL functions of the raster merge: `tin_raster_stats` (by pixel centre
//! or coverage-weighted), `tin_raster_pixels`, `tin_paint`; and the surface
//! out as a raster, `tin_as_raster`. Rasters arrive as WKB (the SQL wrapper casts
//! `raster` to `bytea`). Not STRICT (a NULL level means finest): a NULL tin,
//! raster or band gives no rows. A stored tin read in slices is merged
//! through a [`Patch`] of the triangles under the raster when the raster
//! covers at most an eighth of the tin's extent (a tile of a large
//! terrain: the first call reads those groups, not the whole value);
//! otherwise the whole value is decoded (and cached) as before.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::{tin_level, MeshSource, TinArg};
use std::sync::Arc;
use tinmerge_core::io::raster::{self, Band, GeoTransform};
use tinmerge_core::merge::raster::patch::{AnyLevel, Patch, RasterLevel, TinLevel};
use tinmerge_core::merge::raster::stats::{is_data, paint, weighted_stats, zonal_stats};
use tinmerge_core::merge::raster::{sweep, PixelGrid};
use tinmerge_core::tin::{resolve_level, Tin, TinError};

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
    tin_srid: i32,
    rast: &[u8],
    band: i32,
    func: &str,
) -> Option<(GeoTransform, PixelGrid, Band)> {
    let head = raster::read(rast, None).or_raise();
    check_raster_srid(head.srid, tin_srid, func);
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

/// The level's triangles for a raster merge over the pixels of `g`: the
/// decoded level, or, for a stored value read in slices when the raster's
/// window (its pixels and one more all round) covers at most an eighth of
/// the tin's extent, a [`Patch`] of the triangles meeting that window. A
/// triangle outside the window owns no centre and overlaps no pixel, so the
/// answers are the same (tests/sliced.rs, pg_regress storage).
/// `keep` holds the decoded value the level borrows from.
fn raster_level<'a>(
    t: &TinArg,
    level: Option<i32>,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    keep: &'a mut Option<Arc<Tin>>,
) -> AnyLevel<'a> {
    let (w, h) = (width as f64, height as f64);
    let xs = [gt.ip_x, gt.ip_x + w * gt.scale_x];
    let ys = [gt.ip_y, gt.ip_y + h * gt.scale_y];
    let (px, py) = (gt.scale_x.abs(), gt.scale_y.abs());
    let window = [
        xs[0].min(xs[1]) - px,
        ys[0].min(ys[1]) - py,
        xs[0].max(xs[1]) + px,
        ys[0].max(ys[1]) + py,
    ];
    let whole = |keep: &'a mut Option<Arc<Tin>>, tin: Arc<Tin>| {
        let l = tin.level_index(level).or_raise();
        let tin: &'a Tin = keep.insert(tin);
        AnyLevel::Whole(TinLevel::new(tin, l).or_raise())
    };
    match t.mesh_source() {
        MeshSource::Decoded(tin) => whole(keep, tin),
        MeshSource::Sliced(s) => {
            let b = &s.header().bbox;
            let clip = |lo: f64, hi: f64, a: f64, z: f64| (hi.min(z) - lo.max(a)).max(0.0);
            let inside = clip(window[0], window[2], b.min_x, b.max_x)
                * clip(window[1], window[3], b.min_y, b.max_y);
            let extent = (b.max_x - b.min_x) * (b.max_y - b.min_y);
            // (a degenerate or NaN extent decodes whole too)
            if inside.is_nan() || extent.is_nan() || inside > extent / 8.0 {
                return whole(keep, t.tin());
            }
            let l = resolve_level(level, s.header().levels.len()).or_raise();
            let mut fetch = t.fetch();
            let reader = s.reader(&mut fetch);
            AnyLevel::Patch(Patch::new(&reader, l, window, &mut interrupt).or_raise())
        }
    }
}

type StatsRow = (i32, i64, f64, f64, f64, f64, Option<f64>);

/// `tin_raster_stats`: zonal statistics per triangle (see its comment).
#[allow(clippy::type_complexity)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
pub(super) fn _tin_raster_zonal(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
    band: Option<i32>,
    weighted: Option<bool>,
    half_open: Option<bool>,
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
    let (Some(t), Some(rast), Some(band), Some(weighted), Some(half_open)) =
        (t, rast, band, weighted, half_open)
    else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    let Some((gt, mut grid, b)) = raster_arg(t.header().srid, rast, band, "tin_raster_stats")
    else {
        return TableIterator::new(Vec::<StatsRow>::new());
    };
    grid.half_open = half_open;
    let mut keep = None;
    let lv = raster_level(&t, level, &gt, grid.width, grid.height, &mut keep);
    super::threads::apply();
    let st = if weighted {
        weighted_stats(
            &lv,
            &gt,
            grid.width,
            grid.height,
            &b.values,
            b.nodata,
            true,
            &mut interrupt,
        )
    } else {
        zonal_stats(&lv, &grid, &b.values, b.nodata, true, &mut interrupt)
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
ALTER FUNCTION _tin_raster_zonal(tin, bytea, int, int, boolean, boolean) ROWS 10000;
COMMENT ON FUNCTION _tin_raster_zonal(tin, bytea, int, int, boolean, boolean) IS 'Internal: use tin_raster_stats(tin, raster, int, int, boolean, boolean).';
"#,
    name = "tin_raster_zonal_sql",
    requires = [_tin_raster_zonal]
);

/// `tin_raster_pixels`: every valid pixel with the triangle owning it.
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
pub(super) fn _tin_raster_owners(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
    band: Option<i32>,
    half_open: Option<bool>,
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(col, i32),
        name!(row, i32),
        name!(value, f64),
    ),
> {
    let (Some(t), Some(rast), Some(band), Some(half_open)) = (t, rast, band, half_open) else {
        return TableIterator::new(Vec::new());
    };
    let Some((gt, mut grid, b)) = raster_arg(t.header().srid, rast, band, "tin_raster_pixels")
    else {
        return TableIterator::new(Vec::new());
    };
    grid.half_open = half_open;
    let mut keep = None;
    let lv = raster_level(&t, level, &gt, grid.width, grid.height, &mut keep);
    let w = grid.width;
    let mut rows = Vec::new();
    sweep(&lv, &grid, true, &mut interrupt, &mut |k, r, c0, c1| {
        let tri = lv.id(k as usize);
        for c in c0..c1 {
            let v = b.values[r * w + c];
            if is_data(v, b.nodata) {
                // PostGIS numbers pixels from 1
                rows.push((tri as i32, c as i32 + 1, r as i32 + 1, v));
            }
        }
    })
    .or_raise();
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_raster_owners(tin, bytea, int, int, boolean) ROWS 100000;
COMMENT ON FUNCTION _tin_raster_owners(tin, bytea, int, int, boolean) IS 'Internal: use tin_raster_pixels(tin, raster, int, int, boolean).';
"#,
    name = "tin_raster_owners_sql",
    requires = [_tin_raster_owners]
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
    let srid = t.header().srid;
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
    let Some((gt, grid, red)) = raster_arg(srid, rast, 1, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let Some((_, _, green)) = raster_arg(srid, rast, 2, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let Some((_, _, blue)) = raster_arg(srid, rast, 3, "tin_paint") else {
        return TableIterator::new(Vec::new());
    };
    let mut keep = None;
    let lv = raster_level(&t, level, &gt, grid.width, grid.height, &mut keep);
    let rows = paint(
        &lv,
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

/// `tin_validate(tin, raster, band)`: the problems of `tin_validate(tin)`
/// and every level over its tolerance against the raster's surface, at the
/// pixel centres and between them on the grid lines
/// (`tin::check::over_tolerance`).
#[pg_extern(immutable, strict, parallel_safe, cost = 100000, requires = ["tin_type"])]
fn _tin_validate_raster(
    t: TinArg,
    rast: &[u8],
    band: i32,
    breaklines: &[u8],
) -> TableIterator<
    'static,
    (
        name!(level, i32),
        name!(problem, String),
        name!(triangle, i32),
        name!(detail, String),
    ),
> {
    let func = "tin_validate";
    let head = raster::read(rast, None).or_raise();
    check_raster_srid(head.srid, t.header().srid, func);
    if band < 1 || band as usize > head.num_bands {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: band {band} does not exist: the raster has {} band(s), numbered from 1",
                head.num_bands
            ),
        );
    }
    memory::reserve(
        tinmerge_core::io::raster::raster_bytes(head.width, head.height)
            .saturating_add(head.width.saturating_mul(head.height).saturating_mul(8)),
        || format!("{func}: reading a {} x {} raster", head.width, head.height),
    );
    // the hard breaklines the tin was built with (empty: none): the grid
    // segments they cut hold their heights, not the raster's
    let hard = if breaklines.is_empty() {
        Vec::new()
    } else {
        tinmerge_core::tin::breaklines::hard_segments(&super::build::breaklines_arg(
            func,
            Some(breaklines),
            None,
            head.srid,
        ))
    };
    let r = raster::read(rast, Some(band as usize)).or_raise();
    let tin = t.tin();
    let mut found = tinmerge_core::tin::check::problems(&tin, &mut interrupt).or_raise();
    if let Some(b) = &r.band {
        let heights = tinmerge_core::tin::dense::Dense {
            c0: 0,
            r0: 0,
            width: r.width,
            height: r.height,
            z: b.values
                .iter()
                .map(|&v| if b.is_valid(v) { v } else { f64::NAN })
                .collect(),
        };
        found.extend(
            tinmerge_core::tin::check::over_tolerance(
                &tin,
                &heights,
                &r.gt.lattice(),
                &hard,
                &mut interrupt,
            )
            .or_raise(),
        );
    }
    super::level::problem_rows(found)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_validate_raster(tin, bytea, int, bytea) ROWS 10;
COMMENT ON FUNCTION _tin_validate_raster(tin, bytea, int, bytea) IS 'Internal: use tin_validate(tin, raster, int, geometry).';
"#,
    name = "tin_validate_raster_sql",
    requires = [_tin_validate_raster]
);

/// The largest raster `tin_as_raster` returns: a varlena holds at most 1 GB.
pub(super) const MAX_RASTER_BYTES: usize = (1 << 30) - (1 << 20);

/// A core error about an argument, its message led by the SQL function's
/// name.
pub(super) fn named(e: TinError, func: &str) -> TinError {
    match e {
        TinError::InvalidParameter(m) => TinError::InvalidParameter(format!("{func}: {m}")),
        TinError::TooLarge(m) => TinError::TooLarge(format!("{func}: {m}")),
        e => e,
    }
}

/// `tin_as_raster`: the surface of a level at the pixel centres of the
/// grid `gt`, as WKB raster bytes (the SQL wrapper makes them a raster).
#[allow(clippy::too_many_arguments)]
fn as_raster(
    tin: &Tin,
    l: usize,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    pixel_type: &str,
    nodata: f64,
) -> Vec<u8> {
    let func = "tin_as_raster";
    let pt = raster::float_pixel_type(pixel_type).or_raise();
    let size = raster::pixel_type(pt).map_or(8, |(_, size)| size);
    let n = width.saturating_mul(height);
    if n.saturating_mul(size) > MAX_RASTER_BYTES {
        raise(
            PgSqlErrorCode::ERRCODE_PROGRAM_LIMIT_EXCEEDED,
            format!(
                "{func}: {width} x {height} pixels of {pixel_type} make {} MB, more than a value can hold (1 GB); use larger pixels, '32BF', or tiles: tin_as_raster(t, tile) over ST_MakeEmptyCoverage",
                n.saturating_mul(size) >> 20
            ),
        );
    }
    memory::reserve(n.saturating_mul(8 + size), || {
        format!("{func}: a {width} x {height} raster")
    });
    let z =
        tinmerge_core::analysis::rasterize::rasterize(tin, l, gt, width, height, &mut interrupt)
            .map_err(|e| named(e, func))
            .or_raise();
    raster::write_float(tin.srid, gt, width, height, pt, nodata, &z).or_raise()
}

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_as_raster(
    t: Option<TinArg>,
    rast: Option<&[u8]>,
    level: Option<i32>,
    pixel_type: Option<&str>,
    nodata: Option<f64>,
) -> Option<Vec<u8>> {
    let (t, rast, pixel_type, nodata) = (t?, rast?, pixel_type?, nodata?);
    let head = raster::read(rast, None).or_raise();
    check_raster_srid(head.srid, t.header().srid, "tin_as_raster");
    let (tin, l) = tin_level(&t, level);
    Some(as_raster(
        &tin,
        l,
        &head.gt,
        head.width,
        head.height,
        pixel_type,
        nodata,
    ))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_as_raster(tin, bytea, int, text, float8) IS 'Internal: use tin_as_raster(tin, raster, int, text, float8).';
"#,
    name = "tin_as_raster_ref_sql",
    requires = [_tin_as_raster]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_as_raster_sized(
    t: Option<TinArg>,
    pixel_size: Option<f64>,
    level: Option<i32>,
    pixel_type: Option<&str>,
    nodata: Option<f64>,
    gridx: Option<f64>,
    gridy: Option<f64>,
) -> Option<Vec<u8>> {
    let (t, size, pixel_type, nodata) = (t?, pixel_size?, pixel_type?, nodata?);
    let (gx, gy) = (gridx?, gridy?);
    let (tin, l) = tin_level(&t, level);
    let b = &tin.bbox;
    let (gt, w, h) = tinmerge_core::analysis::rasterize::aligned_grid(
        &[b.min_x, b.min_y, b.max_x, b.max_y],
        size,
        size,
        gx,
        gy,
    )
    .map_err(|e| named(e, "tin_as_raster"))
    .or_raise();
    Some(as_raster(&tin, l, &gt, w, h, pixel_type, nodata))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_as_raster_sized(tin, float8, int, text, float8, float8, float8) IS 'Internal: use tin_as_raster(tin, float8, int, text, float8, float8, float8).';
"#,
    name = "tin_as_raster_sized_sql",
    requires = [_tin_as_raster_sized]
);
