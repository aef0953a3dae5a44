//! The builders: `tin_from_raster` (both forms), `tin_tiles`,
//! `tin_from_points` and the `tin_from_points_agg` aggregate.
//! Geometry and raster travel as (E)WKB `bytea`; the public
//! `geometry`/`raster` signatures are thin SQL wrappers in `sql/tinmerge.sql`.

use pgrx::prelude::*;

use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::TinOut;
use pgrx::{pg_sys, Internal, PgMemoryContexts};

use super::args::GeomArg;
use tinmerge_core::io::{ewkb, gserialized, raster};
use tinmerge_core::tin::build::{
    build, build_lattice, check_tolerances, default_tolerances, BuildOptions,
};
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::tiles::build_tiles;

/// Refuse a build that would pass `tinmerge.max_memory` (the samples are
/// already allocated); otherwise hand `tinmerge.threads` to the core.
fn reserve_build(func: &str, samples: usize, levels: usize) {
    super::threads::apply();
    memory::reserve(
        tinmerge_core::tin::build::build_bytes(samples, levels).saturating_sub(samples * 24),
        || format!("{func}: building a tin from {samples} samples at {levels} levels"),
    );
}

/// One band of a raster argument (an ERROR for a band that is not there
/// or an empty raster; reading it counts against `tinmerge.max_memory`).
fn raster_band(rast: &[u8], band: i32) -> (raster::Raster, raster::Band) {
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
    memory::reserve(raster::raster_bytes(head.width, head.height), || {
        format!("reading a {} x {} raster", head.width, head.height)
    });
    let mut r = raster::read(rast, Some(band as usize)).or_raise();
    let Some(b) = r.band.take() else {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            "raster has no such band",
        );
    };
    (r, b)
}

/// Valid pixels of one band as lattice samples (col, row, value), the
/// raster's pixel lattice and its SRID.
fn raster_samples(rast: &[u8], band: i32) -> (Vec<[f64; 3]>, Lattice, i32) {
    let (r, b) = raster_band(rast, band);
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

#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
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

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_raster(bytea, float8, int, int, boolean) IS 'Internal: use tin_from_raster(raster, ...).';
"#,
    name = "tin_from_raster_sql",
    requires = [_tin_from_raster]
);

#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
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

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_raster_tolerances(bytea, float8[], int, boolean) IS 'Internal: use tin_from_raster(raster, float8[], ...).';
"#,
    name = "tin_from_raster_tolerances_sql",
    requires = [_tin_from_raster_tolerances]
);

/// `tin_tiles`: the raster cut into tiles of `tile_px` pixels that share
/// their border column and row of samples, each built with keep_border
/// (`tin::tiles`), on `tinmerge.threads` threads.
#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_tiles(
    rast: &[u8],
    tile_px: i32,
    tolerance: f64,
    levels: i32,
    band: i32,
) -> TableIterator<'static, (name!(tx, i32), name!(ty, i32), name!(t, TinOut))> {
    if !(2..=65535).contains(&tile_px) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("tin_tiles: tile_px must be 2 to 65535 pixels, got {tile_px}"),
        );
    }
    let tols = default_tolerances(tolerance, levels).or_raise();
    let (r, b) = raster_band(rast, band);
    let lattice = r.gt.lattice();
    let per_tile = (tile_px as usize + 1).min(r.width) * (tile_px as usize + 1).min(r.height);
    super::threads::apply();
    let at_once = tinmerge_core::tin::par::threads().max(1);
    memory::reserve(
        tinmerge_core::tin::build::build_bytes(per_tile, tols.len()).saturating_mul(at_once),
        || {
            format!(
                "tin_tiles: building {at_once} tiles of {per_tile} samples at {} levels at once",
                tols.len()
            )
        },
    );
    let mut rows = Vec::new();
    build_tiles(
        &b.values,
        r.width,
        r.height,
        &|v| b.is_valid(v),
        &lattice,
        tile_px as usize,
        &tols,
        r.srid,
        &mut interrupt,
        &|tx, ty, tin| (tx as i32, ty as i32, TinOut::from_tin_on(&tin, &lattice)),
        &mut |row| {
            rows.push(row);
            Ok(())
        },
    )
    .or_raise();
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_tiles(bytea, int, float8, int, int) ROWS 100;
COMMENT ON FUNCTION _tin_tiles(bytea, int, float8, int, int) IS 'Internal: use tin_tiles(raster, int, float8, int, int).';
"#,
    name = "tin_tiles_sql",
    requires = [_tin_tiles]
);

/// The build behind both `tin_from_raster` forms.
fn build_raster(rast: &[u8], tols: &[f64], band: i32, keep_border: bool) -> TinOut {
    let (pts, lattice, srid) = raster_samples(rast, band);
    reserve_build("tin_from_raster", pts.len(), tols.len());
    let opts = BuildOptions { keep_border };
    TinOut::from_tin_on(
        &build_lattice(pts, &lattice, tols, srid, opts, &mut interrupt).or_raise(),
        &lattice,
    )
}

#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
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

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_points(bytea, float8, int) IS 'Internal: use tin_from_points(geometry, ...).';
"#,
    name = "tin_from_points_sql",
    requires = [_tin_from_points]
);

/// The state of the `tin_from_points_agg` aggregate: every vertex (with Z)
/// of the rows so far, their SRID, and the build's arguments (from the
/// first row), kept in the aggregate's memory context and dropped with it.
#[derive(Default)]
struct PointsAgg {
    samples: Vec<[f64; 3]>,
    srid: Option<i32>,
    args: Option<(f64, i32)>,
}

/// Transition function of `tin_from_points_agg(geometry, float8, int)`:
/// adds the row's vertices (NULL and empty geometries add nothing).
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_step(
    mut state: Internal,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    fcinfo: pg_sys::FunctionCallInfo,
) -> Internal {
    let mut agg: pg_sys::MemoryContext = std::ptr::null_mut();
    // SAFETY: fcinfo is this call's; AggCheckCallContext only reads it.
    if unsafe { pg_sys::AggCheckCallContext(fcinfo, &mut agg) } == 0 || agg.is_null() {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            "_tin_points_agg_step is the transition function of tin_from_points_agg; it cannot be called on its own",
        );
    }
    // SAFETY: the state is only ever a PointsAgg made here, in the
    // aggregate's context (dropped when that context goes).
    let st: &mut PointsAgg = unsafe {
        PgMemoryContexts::For(agg).switch_to(|_| state.get_or_insert_default::<PointsAgg>())
    };
    let (Some(tolerance), Some(levels)) = (tolerance, levels) else {
        raise(
            PgSqlErrorCode::ERRCODE_NULL_VALUE_NOT_ALLOWED,
            "tin_from_points_agg: tolerance and levels must not be NULL",
        );
    };
    match st.args {
        None => {
            default_tolerances(tolerance, levels).or_raise();
            st.args = Some((tolerance, levels));
        }
        Some((t, l)) if t.to_bits() != tolerance.to_bits() || l != levels => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: tolerance and levels must be the same in every row (first {t} and {l}, then {tolerance} and {levels})"
            ),
        ),
        Some(_) => {}
    }
    let Some(pt) = pt else { return state };
    let g = gserialized::read(pt.bytes()).or_raise();
    if g.geom.is_empty() {
        return state;
    }
    match st.srid {
        None => st.srid = Some(g.srid),
        Some(s) if s != g.srid => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: rows have SRIDs {s} and {}; transform them to one SRID first",
                g.srid
            ),
        ),
        Some(_) => {}
    }
    if !g.has_z {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "tin_from_points_agg: a {} has no Z coordinate: a tin needs 3D samples (ST_Force3DZ adds Z = 0)",
                g.geom.type_name()
            ),
        );
    }
    let before = st.samples.capacity();
    g.geom.for_each_coord(&mut |c| st.samples.push(*c));
    let grown = st.samples.capacity().saturating_sub(before);
    if grown > 0 {
        let n = st.samples.len();
        memory::reserve(0, || {
            format!("tin_from_points_agg: holding {n} samples ({grown} more places)")
        });
    }
    state
}

/// Final function of `tin_from_points_agg`: the tin of every vertex
/// gathered (NULL when no row gave one).
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_final(mut state: Internal) -> Option<TinOut> {
    // SAFETY: the state is only ever a PointsAgg (see the step function).
    // FINALFUNC_MODIFY = READ_WRITE: the samples are handed to the build,
    // not copied (PostgreSQL does not use the state after this call).
    let st = unsafe { state.get_mut::<PointsAgg>() }?;
    let (tolerance, levels) = st.args?;
    if st.samples.is_empty() {
        return None;
    }
    let tols = default_tolerances(tolerance, levels).or_raise();
    reserve_build("tin_from_points_agg", st.samples.len(), tols.len());
    let tin = build(
        std::mem::take(&mut st.samples),
        &tols,
        st.srid.unwrap_or(0),
        &mut interrupt,
    )
    .or_raise();
    Some(TinOut::from_tin(&tin))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_points_agg_step(internal, geometry, float8, int) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int).';
COMMENT ON FUNCTION _tin_points_agg_final(internal) IS 'Internal: the final function of tin_from_points_agg(geometry, float8, int).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int) (
    SFUNC = _tin_points_agg_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int) IS
'Builds a tin from every vertex (with Z) of the rows aggregated, as tin_from_points(ST_Collect(pt), tolerance, levels) does but without building one collection geometry (which PostgreSQL caps at 1 GB): e.g. tin_from_points_agg(geom, 0.5, 5) FILTER (WHERE class = 2) over LiDAR returns keeps the ground. Points with equal x,y are merged (mean z); NULL and empty rows add nothing; no row gives NULL. All rows must have one SRID, and the same tolerance and levels.';
"#,
    name = "tin_from_points_agg_sql",
    requires = [_tin_points_agg_step, _tin_points_agg_final]
);
