//! SQL functions of viewsheds: `tin_viewshed` on a grid of a given cell
//! size or on a reference raster's grid, one observer (visible 1, hidden
//! 0) or several counted (a MULTIPOINT: how many see each cell). Rasters
//! go out as WKB; the SQL wrappers make them `raster`. Not STRICT (a NULL
//! level means finest): a NULL tin, observer, radius or other argument
//! gives NULL.

use pgrx::prelude::*;

use super::analysis::{metres_per_unit, sight_points};
use super::area::srid_is_geographic;
use super::args::GeomArg;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::raster::{check_raster_srid, named, MAX_RASTER_BYTES};
use super::tin_type::{tin_level, TinArg};
use tinmerge_core::analysis::rasterize::aligned_grid;
use tinmerge_core::analysis::viewshed::{viewshed, Eye, MAX_OBSERVERS};
use tinmerge_core::io::raster::{self, GeoTransform};
use tinmerge_core::tin::Tin;

const FUNC: &str = "tin_viewshed";

/// The observers' eyes, checked.
#[allow(clippy::too_many_arguments)]
fn eyes(
    tin: &Tin,
    l: usize,
    observer: &GeomArg,
    observer_height: f64,
    curvature: bool,
    refraction: f64,
) -> Vec<Eye> {
    for (v, name) in [
        (observer_height, "observer_height"),
        (refraction, "refraction"),
    ] {
        if !v.is_finite() {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("{FUNC}: {name} must be finite, got {v}"),
            );
        }
    }
    let pts = sight_points(observer, tin, l, observer_height, "observer", FUNC, true);
    if pts.len() > MAX_OBSERVERS {
        raise(
            PgSqlErrorCode::ERRCODE_PROGRAM_LIMIT_EXCEEDED,
            format!(
                "{FUNC}: {} observers; at most {MAX_OBSERVERS} are counted in one call (add up several calls with ST_MapAlgebra)",
                pts.len()
            ),
        );
    }
    let geographic = srid_is_geographic(None, tin.srid, &tin.bbox);
    pts.into_iter()
        .map(|p| Eye {
            x: p[0],
            y: p[1],
            z: p[2],
            curvature: curvature.then(|| (refraction, metres_per_unit(geographic, p[1]))),
        })
        .collect()
}

/// The viewshed on the grid `gt` as WKB raster bytes: 8BUI (nodata 255)
/// for up to 254 observers, else 16BUI (nodata 65535).
#[allow(clippy::too_many_arguments)]
fn viewshed_raster(
    tin: &Tin,
    l: usize,
    eyes: &[Eye],
    target_height: f64,
    radius: f64,
    gt: &GeoTransform,
    width: usize,
    height: usize,
) -> Vec<u8> {
    if !target_height.is_finite() {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: target_height must be finite, got {target_height}"),
        );
    }
    if !(radius.is_finite() && radius > 0.0) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: radius must be positive and finite, got {radius}"),
        );
    }
    let byte = eyes.len() <= 254;
    let n = width.saturating_mul(height);
    let size = if byte { 1 } else { 2 };
    if n.saturating_mul(size) > MAX_RASTER_BYTES {
        raise(
            PgSqlErrorCode::ERRCODE_PROGRAM_LIMIT_EXCEEDED,
            format!(
                "{FUNC}: {width} x {height} cells make {} MB, more than a value can hold (1 GB); use larger cells or a smaller radius",
                n.saturating_mul(size) >> 20
            ),
        );
    }
    // the triangle under each cell (4 bytes a cell), counts (2), the
    // raster written (1 or 2) and the cells seen (4)
    memory::reserve(n.saturating_mul(12), || {
        format!("{FUNC}: a viewshed of {width} x {height} cells")
    });
    let v = viewshed(
        tin,
        l,
        eyes,
        target_height,
        radius,
        gt,
        width,
        height,
        &mut interrupt,
    )
    .map_err(|e| named(e, FUNC))
    .or_raise();
    raster::write_counts(tin.srid, gt, width, height, byte, &v.counts).or_raise()
}

#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, cost = 100000, requires = ["tin_type"])]
fn _tin_viewshed(
    t: Option<TinArg>,
    observer: Option<GeomArg>,
    radius: Option<f64>,
    cell_size: Option<f64>,
    observer_height: Option<f64>,
    target_height: Option<f64>,
    level: Option<i32>,
    curvature: Option<bool>,
    refraction: Option<f64>,
    gridx: Option<f64>,
    gridy: Option<f64>,
) -> Option<Vec<u8>> {
    let (t, o, radius, cell) = (t?, observer?, radius?, cell_size?);
    let (oh, th, curv, k, gx, gy) = (
        observer_height?,
        target_height?,
        curvature?,
        refraction?,
        gridx?,
        gridy?,
    );
    let (tin, l) = tin_level(&t, level);
    let eyes = eyes(&tin, l, &o, oh, curv, k);
    if !(radius.is_finite() && radius > 0.0) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: radius must be positive and finite, got {radius}"),
        );
    }
    // the observers' reach within the tin's extent
    let b = &tin.bbox;
    let mut win = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for e in &eyes {
        win[0] = win[0].min(e.x - radius);
        win[1] = win[1].min(e.y - radius);
        win[2] = win[2].max(e.x + radius);
        win[3] = win[3].max(e.y + radius);
    }
    let win = [
        win[0].max(b.min_x),
        win[1].max(b.min_y),
        win[2].min(b.max_x),
        win[3].min(b.max_y),
    ];
    if !(win[0] <= win[2] && win[1] <= win[3]) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: no observer is within the radius of the tin's extent"),
        );
    }
    if !(cell.is_finite() && cell > 0.0) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: cell_size must be positive and finite, got {cell}"),
        );
    }
    let side = |lo: f64, hi: f64, g: f64| ((hi - g) / cell).ceil() - ((lo - g) / cell).floor();
    let (w, h) = (side(win[0], win[2], gx), side(win[1], win[3], gy));
    if !(w <= 65535.0 && h <= 65535.0) {
        raise(
            PgSqlErrorCode::ERRCODE_PROGRAM_LIMIT_EXCEEDED,
            format!(
                "{FUNC}: cells of {cell} over the observers' reach make a raster of {w} x {h} cells; a PostGIS raster has at most 65535 a side: use larger cells or a smaller radius"
            ),
        );
    }
    let (gt, w, h) = aligned_grid(&win, cell, cell, gx, gy)
        .map_err(|e| named(e, FUNC))
        .or_raise();
    Some(viewshed_raster(&tin, l, &eyes, th, radius, &gt, w, h))
}

#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, cost = 100000, requires = ["tin_type"])]
fn _tin_viewshed_ref(
    t: Option<TinArg>,
    observer: Option<GeomArg>,
    radius: Option<f64>,
    rast: Option<&[u8]>,
    observer_height: Option<f64>,
    target_height: Option<f64>,
    level: Option<i32>,
    curvature: Option<bool>,
    refraction: Option<f64>,
) -> Option<Vec<u8>> {
    let (t, o, radius, rast) = (t?, observer?, radius?, rast?);
    let (oh, th, curv, k) = (observer_height?, target_height?, curvature?, refraction?);
    let head = raster::read(rast, None).or_raise();
    check_raster_srid(head.srid, t.header().srid, FUNC);
    let (tin, l) = tin_level(&t, level);
    let eyes = eyes(&tin, l, &o, oh, curv, k);
    Some(viewshed_raster(
        &tin,
        l,
        &eyes,
        th,
        radius,
        &head.gt,
        head.width,
        head.height,
    ))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_viewshed(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) IS 'Internal: use tin_viewshed(tin, geometry, float8, float8, ...).';
COMMENT ON FUNCTION _tin_viewshed_ref(tin, geometry, float8, bytea, float8, float8, int, boolean, float8) IS 'Internal: use tin_viewshed(tin, geometry, float8, raster, ...).';
"#,
    name = "tin_viewshed_internal_sql",
    requires = [_tin_viewshed, _tin_viewshed_ref]
);
