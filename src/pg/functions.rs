//! SQL functions of the foundation: constructors, header accessors, and the
//! triangles of a level. Geometry and raster travel as (E)WKB `bytea`; the
//! public `geometry`/`raster` signatures are thin SQL wrappers in
//! `sql/tinmerge.sql`.

use pgrx::prelude::*;
use pgrx::JsonB;
use serde_json::json;

use super::types::{TinArg, TinOut};
use super::{cache, interrupt, memory, raise, OrRaise};
use crate::io::{ewkb, raster};
use crate::tin::build::{build, build_lattice, check_tolerances, default_tolerances, BuildOptions};
use crate::tin::lattice::Lattice;
use crate::tin::memory as tmem;
use crate::tin::{resolve_level, NONE};

/// Refuse a build that would pass `tinmerge.max_memory` (the samples are
/// already allocated); otherwise hand `tinmerge.threads` to the core.
fn reserve_build(func: &str, samples: usize, levels: usize) {
    super::threads::apply();
    memory::reserve(
        tmem::build_bytes(samples, levels).saturating_sub(samples * 24),
        || format!("{func}: building a tin from {samples} samples at {levels} levels"),
    );
}

/// Valid pixels of one band as lattice samples (col, row, value), the
/// raster's pixel lattice and its SRID.
fn raster_samples(rast: &[u8], band: i32) -> (Vec<[f64; 3]>, Lattice, i32) {
    if band < 1 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("band must be 1 or more (bands are numbered from 1), got {band}"),
        );
    }
    let head = raster::read(rast, None).or_raise();
    if head.width == 0 || head.height == 0 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("raster is empty ({} x {} pixels)", head.width, head.height),
        );
    }
    memory::reserve(tmem::raster_bytes(head.width, head.height), || {
        format!("reading a {} x {} raster", head.width, head.height)
    });
    let r = raster::read(rast, Some(band as usize)).or_raise();
    let Some(b) = r.band else {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            "raster has no such band",
        );
    };
    let mut pts = Vec::new();
    for row in 0..r.height {
        for col in 0..r.width {
            let v = b.values[row * r.width + col];
            if b.is_valid(v) {
                pts.push([col as f64, row as f64, v]);
            }
        }
    }
    if pts.is_empty() {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("band {band} has no valid pixels (every pixel is nodata)"),
        );
    }
    (pts, r.gt.lattice(), r.srid)
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn _tin_from_raster(
    rast: &[u8],
    tolerance: f64,
    levels: i32,
    band: i32,
    keep_border: bool,
) -> TinOut {
    let tols = default_tolerances(tolerance, levels).or_raise();
    build_raster(rast, &tols, band, keep_border)
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn _tin_from_raster_tolerances(
    rast: &[u8],
    tolerances: Vec<Option<f64>>,
    band: i32,
    keep_border: bool,
) -> TinOut {
    let tols: Vec<f64> = tolerances
        .into_iter()
        .map(|t| {
            t.unwrap_or_else(|| {
                raise(
                    PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
                    "tolerances must not contain NULL",
                )
            })
        })
        .collect();
    check_tolerances(&tols).or_raise();
    build_raster(rast, &tols, band, keep_border)
}

/// The build behind both `tin_from_raster` forms.
fn build_raster(rast: &[u8], tols: &[f64], band: i32, keep_border: bool) -> TinOut {
    let (pts, lattice, srid) = raster_samples(rast, band);
    reserve_build("tin_from_raster", pts.len(), tols.len());
    let opts = BuildOptions { keep_border };
    TinOut::from_tin(&build_lattice(pts, &lattice, tols, srid, opts, &mut interrupt).or_raise())
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn _tin_from_points(pts: &[u8], tolerance: f64, levels: i32) -> TinOut {
    let tols = default_tolerances(tolerance, levels).or_raise();
    let g = ewkb::read(pts).or_raise();
    if g.geom.is_empty() {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            "geometry is empty: no samples to build a tin from",
        );
    }
    if !g.has_z {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{} has no Z coordinate: tin_from_points needs 3D samples (e.g. MULTIPOINT Z; ST_Force3DZ adds Z = 0)",
                g.geom.type_name()
            ),
        );
    }
    let mut samples = Vec::new();
    g.geom.for_each_coord(&mut |c| samples.push(*c));
    reserve_build("tin_from_points", samples.len(), tols.len());
    TinOut::from_tin(&build(samples, &tols, g.srid, &mut interrupt).or_raise())
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_srid(t: TinArg) -> i32 {
    t.header().srid
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_num_levels(t: TinArg) -> i32 {
    t.header().num_levels() as i32
}

/// The header's record for a level (None = finest).
fn level_info(t: &TinArg, level: Option<i32>) -> crate::tin::layout::LevelInfo {
    let h = t.header();
    let l = resolve_level(level, h.num_levels()).or_raise();
    h.levels[l]
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn tin_num_triangles(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<i32> {
    t.map(|t| level_info(&t, level).num_triangles as i32)
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn tin_num_vertices(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<i32> {
    t.map(|t| level_info(&t, level).num_vertices as i32)
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn tin_tolerance(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<f64> {
    t.map(|t| level_info(&t, level).tolerance)
}

/// Every sliver and hidden crack of a tin (see `tin::check::problems`):
/// values built by tinmerge 0.2.0 from grids whose pixel centres round off
/// their lattice lines have them; rebuild those (docs/upgrading.md).
#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_validate(
    t: TinArg,
) -> TableIterator<
    'static,
    (
        name!(level, i32),
        name!(problem, String),
        name!(triangle, i32),
        name!(detail, String),
    ),
> {
    let tin = t.tin();
    let found = crate::tin::check::problems(&tin, &mut interrupt).or_raise();
    TableIterator::new(found.into_iter().map(|p| {
        (
            p.level as i32,
            p.kind.to_string(),
            p.triangle as i32,
            p.detail,
        )
    }))
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn tin_info(t: TinArg) -> JsonB {
    let h = t.header();
    let b = h.bbox;
    let levels: Vec<_> = h
        .levels
        .iter()
        .enumerate()
        .map(|(i, l)| {
            json!({
                "level": i,
                "tolerance": l.tolerance,
                "triangles": l.num_triangles,
                "vertices": l.num_vertices,
                "max_error": l.max_error,
            })
        })
        .collect();
    JsonB(json!({
        "srid": h.srid,
        "bbox": [b.min_x, b.min_y, b.max_x, b.max_y],
        "z_range": [b.min_z, b.max_z],
        "bytes": h.total_len,
        "num_levels": h.num_levels(),
        "num_vertices": h.num_vertices,
        "levels": levels,
    }))
}

#[pg_extern(immutable, strict, parallel_safe, requires = ["tin_type"])]
fn _tin_envelope(t: TinArg) -> Vec<u8> {
    let h = t.header();
    let b = h.bbox;
    let ring = vec![
        [b.min_x, b.min_y, 0.0],
        [b.min_x, b.max_y, 0.0],
        [b.max_x, b.max_y, 0.0],
        [b.max_x, b.min_y, 0.0],
        [b.min_x, b.min_y, 0.0],
    ];
    ewkb::Writer::write(h.srid, false, &ewkb::Geom::Polygon(vec![ring]))
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_triangles(
    t: Option<TinArg>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(id, i32),
        name!(parent, Option<i32>),
        name!(geom, Vec<u8>),
    ),
> {
    let Some(t) = t else {
        return TableIterator::new(Vec::new());
    };
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    let n = tin.levels[l].tris.len();
    TableIterator::new((0..n).map(move |i| {
        let p = tin.levels[l].parent[i];
        let c = tin.corners(l, i as u32);
        (
            i as i32,
            (p != NONE).then_some(p as i32),
            ewkb::Writer::triangle_polygon(tin.srid, &c),
        )
    }))
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_as_geometry(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<Vec<u8>> {
    let t = t?;
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    let n = tin.levels[l].tris.len() as u32;
    Some(ewkb::Writer::tin(
        tin.srid,
        (0..n).map(|i| tin.corners(l, i)),
    ))
}

#[pg_extern(volatile, parallel_safe)]
fn tin_cache_stats() -> TableIterator<
    'static,
    (
        name!(hits, i64),
        name!(misses, i64),
        name!(entries, i32),
        name!(bytes, i64),
    ),
> {
    let (h, m, e, b) = cache::stats();
    TableIterator::once((h as i64, m as i64, e as i32, b as i64))
}

extension_sql_file!("../../sql/tinmerge.sql", name = "public_api", finalize);
