//! The builders: `tin_from_raster` (both forms), `tin_tiles`,
//! `tin_from_points` and the `tin_from_points_agg` aggregate.
//! Geometry and raster travel as (E)WKB `bytea`; the public
//! `geometry`/`raster` signatures are thin SQL wrappers in `sql/tinmerge.sql`.

use pgrx::prelude::*;

use super::errors::{raise, raise_hint, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::TinOut;
use pgrx::{pg_sys, Internal, PgMemoryContexts};

use super::args::GeomArg;
use tinmerge_core::io::{ewkb, gserialized, raster};
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::tin::breaklines::Breakline;
use tinmerge_core::tin::build::{
    boundary_holds_all, build_domain_raster, build_lattice, build_points, check_tolerances,
    default_tolerances, domain_raster_build_bytes, points_build_bytes, BuildOptions,
};
use tinmerge_core::tin::dense::Dense;
use tinmerge_core::tin::domain::{cell_outline, outline_area};
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::tiles::build_tiles;

/// Refuse a build that would pass `tinmerge.max_memory` (the samples are
/// already allocated); otherwise hand `tinmerge.threads` to the core.
/// Raster builds on the lattice (`on_lattice`, all between the samples)
/// have their own estimate.
fn reserve_build(func: &str, samples: usize, levels: usize, on_lattice: bool) {
    let bytes = if on_lattice {
        tinmerge_core::tin::build::lattice_build_bytes(samples, levels, true)
    } else {
        tinmerge_core::tin::build::build_bytes(samples, levels)
    };
    reserve_build_bytes(func, samples, levels, bytes);
}

/// [`reserve_build`] with its estimate given.
fn reserve_build_bytes(func: &str, samples: usize, levels: usize, bytes: usize) {
    super::threads::apply();
    memory::reserve(bytes.saturating_sub(samples * 24), || {
        format!("{func}: building a tin from {samples} samples at {levels} levels")
    });
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
/// raster's pixel lattice, its SRID and its (width, height) in pixels.
fn raster_samples(rast: &[u8], band: i32) -> (Vec<[f64; 3]>, Lattice, i32, (usize, usize)) {
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
    (pts, r.gt.lattice(), r.srid, (r.width, r.height))
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

/// The build of `tin_from_raster` with breaklines or a boundary (its
/// wrapper calls `_tin_from_raster` without them). Not STRICT: the
/// breaklines and the boundary may be NULL; any other NULL argument gives
/// NULL.
#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
pub(super) fn _tin_from_raster_domain(
    rast: Option<&[u8]>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    band: Option<i32>,
    keep_border: Option<bool>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
    boundary: Option<&[u8]>,
    fill_gaps: Option<bool>,
) -> Option<TinOut> {
    let (rast, tolerance, levels, band, keep_border, fill_gaps) =
        (rast?, tolerance?, levels?, band?, keep_border?, fill_gaps?);
    let tols = default_tolerances(tolerance, levels).or_raise();
    Some(build_raster_constrained(
        rast,
        &tols,
        band,
        keep_border,
        breaklines,
        soft_breaklines,
        boundary,
        fill_gaps,
    ))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_raster_domain(bytea, float8, int, int, boolean, bytea, bytea, bytea, boolean) IS 'Internal: use tin_from_raster(raster, ..., breaklines, soft_breaklines, boundary, fill_gaps).';
"#,
    name = "tin_from_raster_domain_sql",
    requires = [_tin_from_raster_domain]
);

/// `tin_from_raster(raster, float8[], ...)` with breaklines or a
/// boundary; NULLs as for [`_tin_from_raster_domain`].
#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
pub(super) fn _tin_from_raster_tolerances_domain(
    rast: Option<&[u8]>,
    tolerances: Option<Vec<Option<f64>>>,
    band: Option<i32>,
    keep_border: Option<bool>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
    boundary: Option<&[u8]>,
    fill_gaps: Option<bool>,
) -> Option<TinOut> {
    let (rast, tolerances, band, keep_border, fill_gaps) =
        (rast?, tolerances?, band?, keep_border?, fill_gaps?);
    let tols = explicit_tolerances(tolerances);
    Some(build_raster_constrained(
        rast,
        &tols,
        band,
        keep_border,
        breaklines,
        soft_breaklines,
        boundary,
        fill_gaps,
    ))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_raster_tolerances_domain(bytea, float8[], int, boolean, bytea, bytea, bytea, boolean) IS 'Internal: use tin_from_raster(raster, float8[], ..., breaklines, soft_breaklines, boundary, fill_gaps).';
"#,
    name = "tin_from_raster_tolerances_domain_sql",
    requires = [_tin_from_raster_tolerances_domain]
);

/// Per-level tolerances given in SQL, checked.
fn explicit_tolerances(tolerances: Vec<Option<f64>>) -> Vec<f64> {
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
    tols
}

/// The lines of the `breaklines` (hard: Z required) and `soft_breaklines`
/// (Z ignored) arguments of `func`, in the samples' SRID.
pub(super) fn breaklines_arg(
    func: &str,
    hard: Option<&[u8]>,
    soft: Option<&[u8]>,
    srid: i32,
) -> Vec<Breakline> {
    let read = |b: Option<&[u8]>| b.map(|b| ewkb::read(b).or_raise());
    breaklines_of(func, read(hard), read(soft), srid)
}

/// [`breaklines_arg`] of geometries already read.
fn breaklines_of(
    func: &str,
    hard: Option<ewkb::Ewkb>,
    soft: Option<ewkb::Ewkb>,
    srid: i32,
) -> Vec<Breakline> {
    use tinmerge_core::io::ewkb::Geom;
    fn lines_of(func: &str, arg: &str, g: &Geom, out: &mut Vec<Vec<[f64; 3]>>) {
        match g {
            Geom::LineString(l) => out.push(l.clone()),
            Geom::MultiLineString(ls) => out.extend(ls.iter().cloned()),
            Geom::Collection(gs) => gs.iter().for_each(|g| lines_of(func, arg, g, out)),
            other => raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!(
                    "{func}: {arg} must be LINESTRING or MULTILINESTRING, got {}{}",
                    other.type_name(),
                    if matches!(other, Geom::Polygon(_) | Geom::MultiPolygon(_)) {
                        " (to build within a polygon pass it as boundary; ST_Boundary gives its rings as lines)"
                    } else {
                        ""
                    }
                ),
            ),
        }
    }
    let mut out = Vec::new();
    for (arg, g, is_hard) in [("breaklines", hard, true), ("soft_breaklines", soft, false)] {
        let Some(g) = g else { continue };
        check_arg_srid(func, arg, &g, srid);
        // the type first: a 2D polygon is no line at all, whatever its Z
        let mut lines = Vec::new();
        lines_of(func, arg, &g.geom, &mut lines);
        if is_hard && !g.has_z && !g.geom.is_empty() {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!(
                    "{func}: breaklines has no Z coordinate: hard breaklines carry their heights (LINESTRING Z); pass lines without heights as soft_breaklines"
                ),
            );
        }
        out.extend(lines.into_iter().filter(|l| !l.is_empty()).map(|mut pts| {
            if !is_hard {
                pts.iter_mut().for_each(|p| p[2] = f64::NAN);
            }
            Breakline { pts, hard: is_hard }
        }));
    }
    out
}

/// ERROR unless the geometry argument `arg` of a build has the samples'
/// SRID (0 included, as PostGIS refuses mixed SRIDs), with a hint saying
/// how to give it that SRID.
fn check_arg_srid(func: &str, arg: &str, g: &ewkb::Ewkb, srid: i32) {
    if g.srid == srid {
        return;
    }
    let code = PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE;
    // tin_validate checks a tin's lines; the builds, their samples'
    let whose = if func == "tin_validate" {
        "the tin has"
    } else {
        "the samples have"
    };
    if g.srid == 0 {
        raise_hint(
            code,
            format!("{func}: {arg} has no SRID (0) but {whose} SRID {srid}"),
            format!("give it that SRID with ST_SetSRID({arg}, {srid}) if its coordinates are in it, or ST_Transform(ST_SetSRID({arg}, srid), {srid}) from the SRID they are in"),
        );
    }
    raise(
        code,
        format!(
            "{func}: {arg} has SRID {} but {whose} SRID {srid} (ST_Transform it first)",
            g.srid
        ),
    );
}

/// The `boundary` argument of `func` (POLYGON or MULTIPOLYGON, holes
/// allowed, in the samples' SRID), checked.
fn boundary_arg(func: &str, bytes: Option<&[u8]>, srid: i32) -> Option<Area> {
    boundary_of(func, ewkb::read(bytes?).or_raise(), srid)
}

/// [`boundary_arg`] of a geometry already read.
fn boundary_of(func: &str, g: ewkb::Ewkb, srid: i32) -> Option<Area> {
    use tinmerge_core::io::ewkb::Geom;
    check_arg_srid(func, "boundary", &g, srid);
    let polys = match g.geom {
        Geom::Polygon(p) => vec![p],
        Geom::MultiPolygon(ps) => ps,
        other => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: boundary must be POLYGON or MULTIPOLYGON, got {}",
                other.type_name()
            ),
        ),
    };
    let polys: Vec<Vec<Vec<[f64; 2]>>> = polys
        .into_iter()
        .map(|p| {
            p.into_iter()
                .map(|r| r.into_iter().map(|c| [c[0], c[1]]).collect())
                .collect()
        })
        .collect();
    match tinmerge_core::tin::build::boundary(polys) {
        Ok(a) => Some(a),
        Err(e) => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: {e}"),
        ),
    }
}

/// A raster build with breaklines, a boundary or over the valid pixels
/// only (`fill_gaps` false): the valid pixel centres in world
/// coordinates, built as scattered samples with them, measured between
/// the samples too unless there are hard breaklines.
#[allow(clippy::too_many_arguments)]
fn build_raster_constrained(
    rast: &[u8],
    tols: &[f64],
    band: i32,
    keep_border: bool,
    hard: Option<&[u8]>,
    soft: Option<&[u8]>,
    boundary: Option<&[u8]>,
    fill_gaps: bool,
) -> TinOut {
    if hard.is_none() && soft.is_none() && boundary.is_none() && fill_gaps {
        return build_raster(rast, tols, band, keep_border);
    }
    if keep_border && (hard.is_some() || soft.is_some() || boundary.is_some()) {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            "tin_from_raster: keep_border cannot be combined with breaklines or a boundary (tiles with them are not built yet)",
        );
    }
    let (mut pts, lattice, srid, (w, h)) = raster_samples(rast, band);
    let lines = breaklines_arg("tin_from_raster", hard, soft, srid);
    let mut areas: Vec<Area> = boundary_arg("tin_from_raster", boundary, srid)
        .into_iter()
        .collect();
    // the valid pixels' own squares, holes included
    let mut footprint = None;
    if !fill_gaps && pts.len() < w * h {
        let mut valid = vec![false; w * h];
        for p in &pts {
            valid[p[1] as usize * w + p[0] as usize] = true;
        }
        let rings = cell_outline(w, h, &|c, r| valid[r * w + c]);
        drop(valid);
        footprint = Some(outline_area(&rings, &|c, r| {
            let (x, y) = lattice.centre(c - 0.5, r - 0.5);
            [x, y]
        }));
    }
    // the build follows the raster between its samples: its heights in
    // place (NaN without data); hard breaklines' heights are their own, the
    // grid segments they cut are left out of that
    let mut z = vec![f64::NAN; w * h];
    for p in &pts {
        z[p[1] as usize * w + p[0] as usize] = p[2];
    }
    for p in &mut pts {
        let (x, y) = lattice.centre(p[0], p[1]);
        (p[0], p[1]) = (x, y);
    }
    // boundaries holding the whole raster: the build without them, on the
    // pixel lattice
    areas.retain(|a| !boundary_holds_all(a, &pts));
    let footprint = footprint.filter(|a| !boundary_holds_all(a, &pts));
    areas.extend(footprint);
    if lines.is_empty() && areas.is_empty() {
        drop(pts);
        drop(z);
        return build_raster(rast, tols, band, keep_border);
    }
    if keep_border {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            "tin_from_raster: keep_border => true over a raster whose nodata pixels cut into the hull of its valid ones needs fill_gaps => true (tiles over the valid pixels only are not built yet)",
        );
    }
    let areas: Vec<&Area> = areas.iter().collect();
    reserve_build_bytes(
        "tin_from_raster",
        pts.len(),
        tols.len(),
        domain_raster_build_bytes(pts.len(), w * h, tols.len()),
    );
    let heights = Dense {
        c0: 0,
        r0: 0,
        width: w,
        height: h,
        z,
    };
    TinOut::from_tin_on(
        &build_domain_raster(
            pts,
            &lines,
            &areas,
            tols,
            srid,
            &heights,
            &lattice,
            &mut interrupt,
        )
        .or_raise(),
        &lattice,
    )
}

#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_from_raster_tolerances(
    rast: &[u8],
    tolerances: Vec<Option<f64>>,
    band: i32,
    keep_border: bool,
) -> TinOut {
    let tols = explicit_tolerances(tolerances);
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
        tinmerge_core::tin::build::lattice_build_bytes(per_tile, tols.len(), true)
            .saturating_mul(at_once),
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
    let (pts, lattice, srid, _) = raster_samples(rast, band);
    // between the samples, tiles (keep_border) too: tin_tiles decides each
    // tile in its own frame, as this raster's
    let opts = BuildOptions {
        keep_border,
        between_samples: true,
    };
    reserve_build("tin_from_raster", pts.len(), tols.len(), true);
    TinOut::from_tin_on(
        &build_lattice(pts, &lattice, tols, srid, opts, &mut interrupt).or_raise(),
        &lattice,
    )
}

#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_from_points(pts: &[u8], tolerance: f64, levels: i32) -> TinOut {
    let tols = default_tolerances(tolerance, levels).or_raise();
    let (samples, srid) = point_samples(pts);
    reserve_build_bytes(
        "tin_from_points",
        samples.len(),
        tols.len(),
        points_build_bytes(samples.len(), tols.len()),
    );
    TinOut::from_tin(&build_points(samples, &tols, srid, &mut interrupt).or_raise())
}

/// `tin_from_points` with breaklines or a boundary; NULLs as for
/// [`_tin_from_raster_domain`].
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
pub(super) fn _tin_from_points_domain(
    pts: Option<&[u8]>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    breaklines: Option<&[u8]>,
    soft_breaklines: Option<&[u8]>,
    boundary: Option<&[u8]>,
) -> Option<TinOut> {
    let (pts, tolerance, levels) = (pts?, tolerance?, levels?);
    let tols = default_tolerances(tolerance, levels).or_raise();
    let (samples, srid) = point_samples(pts);
    let lines = breaklines_arg("tin_from_points", breaklines, soft_breaklines, srid);
    let area = boundary_arg("tin_from_points", boundary, srid);
    reserve_build_bytes(
        "tin_from_points",
        samples.len(),
        tols.len(),
        points_build_bytes(samples.len(), tols.len()),
    );
    Some(TinOut::from_tin(&build_points_domain(
        samples, &lines, area, &tols, srid,
    )))
}

/// Scattered samples built with breaklines and an optional boundary.
fn build_points_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    area: Option<Area>,
    tols: &[f64],
    srid: i32,
) -> tinmerge_core::tin::Tin {
    tinmerge_core::tin::build::build_points_domain(
        samples,
        lines,
        &area.iter().collect::<Vec<_>>(),
        tols,
        srid,
        &mut interrupt,
    )
    .or_raise()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_from_points_domain(bytea, float8, int, bytea, bytea, bytea) IS 'Internal: use tin_from_points(geometry, ..., breaklines, soft_breaklines, boundary).';
"#,
    name = "tin_from_points_domain_sql",
    requires = [_tin_from_points_domain]
);

/// Every vertex of a geometry with Z as a sample, and its SRID.
fn point_samples(pts: &[u8]) -> (Vec<[f64; 3]>, i32) {
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
    // exactly as many places as samples, and the parsed geometry gone
    // before the build: the input is 24 bytes a sample at the build's peak
    let mut n = 0usize;
    g.geom.for_each_coord(&mut |_| n += 1);
    let mut samples = Vec::with_capacity(n);
    g.geom.for_each_coord(&mut |c| samples.push(*c));
    let srid = g.srid;
    drop(g);
    (samples, srid)
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
    /// The breaklines, soft breaklines and boundary of the first row (the
    /// six-argument form; PostGIS's aggregates also take such arguments
    /// from the first row), in PostGIS's serialisation.
    domain: Option<[Option<Vec<u8>>; 3]>,
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
    let st = points_agg_state(&mut state, fcinfo, "_tin_points_agg_step");
    points_agg_add(st, pt, tolerance, levels);
    state
}

/// The aggregate's state, made in its memory context on the first row;
/// an ERROR when `func` is called outside an aggregate.
fn points_agg_state<'a>(
    state: &'a mut Internal,
    fcinfo: pg_sys::FunctionCallInfo,
    func: &str,
) -> &'a mut PointsAgg {
    let mut agg: pg_sys::MemoryContext = std::ptr::null_mut();
    // SAFETY: fcinfo is this call's; AggCheckCallContext only reads it.
    if unsafe { pg_sys::AggCheckCallContext(fcinfo, &mut agg) } == 0 || agg.is_null() {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            format!("{func} is the transition function of tin_from_points_agg; it cannot be called on its own"),
        );
    }
    // SAFETY: the state is only ever a PointsAgg made here, in the
    // aggregate's context (dropped when that context goes).
    unsafe { PgMemoryContexts::For(agg).switch_to(|_| state.get_or_insert_default::<PointsAgg>()) }
}

/// Transition function of `tin_from_points_agg(geometry, float8, int,
/// geometry, geometry, geometry)`: as [`_tin_points_agg_step`], and the
/// breaklines, soft breaklines and boundary taken from the first row (read
/// once: later rows' values are not even detoasted).
#[allow(clippy::too_many_arguments)]
#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn _tin_points_agg_domain_step(
    mut state: Internal,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
    breaklines: Option<GeomArg>,
    soft_breaklines: Option<GeomArg>,
    boundary: Option<GeomArg>,
    fcinfo: pg_sys::FunctionCallInfo,
) -> Internal {
    let st = points_agg_state(&mut state, fcinfo, "_tin_points_agg_domain_step");
    if st.domain.is_none() {
        let own = |g: &Option<GeomArg>| g.as_ref().map(|g| g.bytes().to_vec());
        st.domain = Some([own(&breaklines), own(&soft_breaklines), own(&boundary)]);
    }
    points_agg_add(st, pt, tolerance, levels);
    state
}

/// One row of `tin_from_points_agg`: the arguments checked, the vertices
/// added.
fn points_agg_add(
    st: &mut PointsAgg,
    pt: Option<GeomArg>,
    tolerance: Option<f64>,
    levels: Option<i32>,
) {
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
    let Some(pt) = pt else { return };
    let g = gserialized::read(pt.bytes()).or_raise();
    if g.geom.is_empty() {
        return;
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
    reserve_build_bytes(
        "tin_from_points_agg",
        st.samples.len(),
        tols.len(),
        points_build_bytes(st.samples.len(), tols.len()),
    );
    // the places the doubling left unused handed back before the build
    let mut samples = std::mem::take(&mut st.samples);
    samples.shrink_to_fit();
    let srid = st.srid.unwrap_or(0);
    let tin = match &st.domain {
        Some(d) if d.iter().any(Option::is_some) => {
            const F: &str = "tin_from_points_agg";
            let read = |b: &Option<Vec<u8>>| b.as_ref().map(|b| gserialized::read(b).or_raise());
            let lines = breaklines_of(F, read(&d[0]), read(&d[1]), srid);
            let area = read(&d[2]).and_then(|g| boundary_of(F, g, srid));
            build_points_domain(samples, &lines, area, &tols, srid)
        }
        _ => build_points(samples, &tols, srid, &mut interrupt).or_raise(),
    };
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
COMMENT ON FUNCTION _tin_points_agg_domain_step(internal, geometry, float8, int, geometry, geometry, geometry) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int, breaklines geometry, soft_breaklines geometry, boundary geometry) (
    SFUNC = _tin_points_agg_domain_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry) IS
'Builds a tin from every vertex (with Z) of the rows aggregated with breaklines, soft breaklines and a boundary (each NULL for none; aggregates take no named or default arguments), as tin_from_points(ST_Collect(pt), tolerance, levels, breaklines, soft_breaklines, boundary) does: e.g. tin_from_points_agg(geom, 0.5, 5, (SELECT ST_Collect(geom) FROM roads), NULL, (SELECT geom FROM survey_area)). The three geometries are taken from the first row, as PostGIS aggregates take their extra arguments (pass constants or scalar subqueries); the rest as tin_from_points_agg(geometry, float8, int).';
"#,
    name = "tin_from_points_agg_sql",
    requires = [
        _tin_points_agg_step,
        _tin_points_agg_domain_step,
        _tin_points_agg_final
    ]
);

/// A table of raster tiles (`raster2pgsql -t`, `ST_Tile`) being built
/// tile by tile: `tin_tiles_from_table(tiles regclass, ...)`. Rows
/// of tiles are read through SPI as they are needed (a tile row and the one
/// below it held at once), tiles are built `tinmerge.threads` at a time,
/// and each result is handed out before the next batch is built, so the
/// call's memory is bounded by two rows of tiles and one batch of builds,
/// whatever the table's size.
struct TableTiles {
    /// `FROM` item and column, quoted.
    from: String,
    column: String,
    band: i32,
    tols: Vec<f64>,
    srid: i32,
    grid: tinmerge_core::tin::tiles::TableGrid,
    ctids: Vec<String>,
    /// Tiles in (ty, tx) order, and the next to build.
    order: Vec<usize>,
    next: usize,
    /// Tile index by (tx, ty).
    at: std::collections::HashMap<(usize, usize), usize>,
    /// Bands read, by tile index.
    loaded: std::collections::HashMap<usize, raster::Band>,
    ready: std::collections::VecDeque<(i32, i32, TinOut)>,
    /// Seam samples kept so far (`tin::tiles::Seams`): rounds of planning
    /// (`round`, while `planning`) build the tiles whose seams gained
    /// samples and keep only what they ask for (`asked`), as `tin_tiles`
    /// does; then every tile is built once more, with them, and returned.
    seams: tinmerge_core::tin::tiles::Seams,
    asked: Vec<tinmerge_core::tin::tiles::Wanted>,
    round: usize,
    planning: bool,
}

impl TableTiles {
    fn open(tab: pg_sys::Oid, column: &str, tolerance: f64, levels: i32, band: i32) -> TableTiles {
        use tinmerge_core::tin::tiles::place_tiles;
        if band < 1 {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("tin_tiles_from_table: band must be 1 or more (bands are numbered from 1), got {band}"),
            );
        }
        let tols = default_tolerances(tolerance, levels).or_raise();
        let (from, quoted, is_raster) = Spi::connect(|c| {
            let r = c
                .select(
                    "SELECT $1::regclass::text, quote_ident($2), (SELECT a.atttypid = 'raster'::regtype FROM pg_attribute a WHERE a.attrelid = $1 AND a.attname = $2 AND a.attnum > 0 AND NOT a.attisdropped)",
                    None,
                    &[tab.into(), column.into()],
                )?
                .first();
            Ok::<_, pgrx::spi::Error>((
                r.get::<String>(1)?.unwrap_or_default(),
                r.get::<String>(2)?.unwrap_or_default(),
                r.get::<bool>(3)?,
            ))
        })
        .unwrap_or_else(|e| raise(PgSqlErrorCode::ERRCODE_UNDEFINED_TABLE, format!("tin_tiles_from_table: {e}")));
        match is_raster {
            None => raise(
                PgSqlErrorCode::ERRCODE_UNDEFINED_COLUMN,
                format!("tin_tiles_from_table: column \"{column}\" of relation {from} does not exist"),
            ),
            Some(false) => raise(
                PgSqlErrorCode::ERRCODE_DATATYPE_MISMATCH,
                format!("tin_tiles_from_table: column \"{column}\" of relation {from} is not of type raster"),
            ),
            Some(true) => {}
        }
        // every tile's geotransform and size (PostGIS reads the header only)
        let q = format!(
            "SELECT ctid::text, (m).upperleftx, (m).upperlefty, (m).width, (m).height, (m).scalex, (m).scaley, (m).skewx, (m).skewy, (m).srid, (m).numbands FROM (SELECT ctid, ST_MetaData({quoted}) AS m FROM {from} WHERE {quoted} IS NOT NULL) s"
        );
        let mut ctids = Vec::new();
        let mut metas = Vec::new();
        let mut srids = Vec::new();
        Spi::connect(|c| {
            for row in c.select(&q, None, &[])? {
                let f = |i: usize| row.get::<f64>(i).map(|v| v.unwrap_or(f64::NAN));
                let n = |i: usize| row.get::<i32>(i).map(|v| v.unwrap_or(0));
                let ctid = row.get::<String>(1)?.unwrap_or_default();
                let lattice = Lattice {
                    ip_x: f(2)?,
                    ip_y: f(3)?,
                    scale_x: f(6)?,
                    scale_y: f(7)?,
                    skew_x: f(8)?,
                    skew_y: f(9)?,
                };
                let (w, h, nb) = (n(4)?, n(5)?, n(11)?);
                if nb < band {
                    raise(
                        PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                        format!("tin_tiles_from_table: the tile at {ctid} of {from} has {nb} band(s), no band {band}"),
                    );
                }
                metas.push((lattice, w.max(0) as usize, h.max(0) as usize));
                srids.push(n(10)?);
                ctids.push(ctid);
            }
            Ok::<_, pgrx::spi::Error>(())
        })
        .unwrap_or_else(|e| raise(PgSqlErrorCode::ERRCODE_INTERNAL_ERROR, format!("tin_tiles_from_table: reading {from}: {e}")));
        if let Some(k) = srids.iter().position(|&s| s != srids[0]) {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!(
                    "tin_tiles_from_table: the tiles of {from} have different SRIDs ({} at {}, {} at {})",
                    srids[0], ctids[0], srids[k], ctids[k]
                ),
            );
        }
        let grid = if metas.is_empty() {
            tinmerge_core::tin::tiles::TableGrid {
                lattice: Lattice {
                    ip_x: 0.0,
                    ip_y: 0.0,
                    scale_x: 1.0,
                    scale_y: -1.0,
                    skew_x: 0.0,
                    skew_y: 0.0,
                },
                tile_width: 1,
                tile_height: 1,
                tiles: Vec::new(),
            }
        } else {
            place_tiles(&metas).unwrap_or_else(|e| {
                raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!("tin_tiles_from_table: the tiles of {from}: {e}"),
                )
            })
        };
        let mut order: Vec<usize> = (0..grid.tiles.len()).collect();
        order.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        let at = grid
            .tiles
            .iter()
            .enumerate()
            .map(|(k, p)| ((p.tx, p.ty), k))
            .collect();
        super::threads::apply();
        TableTiles {
            from,
            column: quoted,
            band,
            tols,
            srid: srids.first().copied().unwrap_or(0),
            grid,
            ctids,
            order,
            next: 0,
            at,
            loaded: Default::default(),
            ready: Default::default(),
            seams: Default::default(),
            asked: Vec::new(),
            round: 0,
            planning: true,
        }
    }

    /// The end of a round of planning: the seam samples asked for taken,
    /// and the tiles that hold new ones to build in the next round; or,
    /// when there are none (or after `SEAM_ROUNDS` rounds), every tile, to
    /// return.
    fn end_round(&mut self) {
        use tinmerge_core::tin::tiles::SEAM_ROUNDS;
        let mut again: Vec<usize> = Vec::new();
        for w in std::mem::take(&mut self.asked) {
            for (c, r) in self.seams.add(&w) {
                again.extend(
                    self.grid
                        .tiles_holding(c, r)
                        .into_iter()
                        .filter_map(|t| self.at.get(&t).copied()),
                );
            }
        }
        self.round += 1;
        let grid = &self.grid;
        if again.is_empty() || self.round >= SEAM_ROUNDS {
            self.planning = false;
            again = (0..grid.tiles.len()).collect();
        }
        again.sort_by_key(|&k| (grid.tiles[k].ty, grid.tiles[k].tx));
        again.dedup();
        self.order = again;
        self.next = 0;
        self.loaded.clear();
    }

    /// Read the bands of tile rows `rows` not read yet, and forget the
    /// rows above the first.
    fn load_rows(&mut self, rows: std::ops::RangeInclusive<usize>) {
        let grid = &self.grid;
        self.loaded
            .retain(|&k, _| grid.tiles[k].ty >= *rows.start());
        let want: Vec<usize> = (0..grid.tiles.len())
            .filter(|&k| rows.contains(&grid.tiles[k].ty) && !self.loaded.contains_key(&k))
            .collect();
        if want.is_empty() {
            return;
        }
        let px: usize = want
            .iter()
            .map(|&k| grid.tiles[k].width * grid.tiles[k].height)
            .sum();
        memory::reserve(px.saturating_mul(8), || {
            format!(
                "tin_tiles_from_table: reading {} tiles of {} ({px} pixels)",
                want.len(),
                self.from
            )
        });
        let by_ctid: std::collections::HashMap<&str, usize> =
            want.iter().map(|&k| (self.ctids[k].as_str(), k)).collect();
        let ctids: Vec<String> = want.iter().map(|&k| self.ctids[k].clone()).collect();
        let q = format!(
            "SELECT ctid::text, {c}::bytea FROM {f} WHERE ctid = ANY($1::text[]::tid[])",
            c = self.column,
            f = self.from
        );
        let mut got = Vec::with_capacity(want.len());
        Spi::connect(|c| {
            let mut table = c.select(&q, None, &[ctids.into()])?;
            while table.next().is_some() {
                let ctid = table.get::<String>(1)?.unwrap_or_default();
                // The raw datum, detoasted here in SPI's own memory context
                // (freed by SPI_finish at the end of this batch): `get::<&[u8]>`
                // would copy every tile's bytes into the parent context,
                // which lives as long as the transaction (the whole raster
                // held by the end of the call: 650 MB for 100 million pixels).
                let Some(datum) = table.get_datum_by_ordinal(2)? else {
                    continue;
                };
                // SAFETY: a non-NULL bytea of the SPI tuple table, valid
                // until SPI_finish; the slice is only read inside this closure.
                let bytes: &[u8] = unsafe {
                    pgrx::varlena::varlena_to_byte_slice(pg_sys::pg_detoast_datum_packed(
                        datum.cast_mut_ptr(),
                    ))
                };
                let Some(&k) = by_ctid.get(ctid.as_str()) else { continue };
                let (r, b) = raster_band(bytes, self.band);
                let p = &self.grid.tiles[k];
                if (r.width, r.height) != (p.width, p.height) {
                    raise(
                        PgSqlErrorCode::ERRCODE_OBJECT_NOT_IN_PREREQUISITE_STATE,
                        format!("tin_tiles_from_table: the tile at {ctid} of {} changed during the build", self.from),
                    );
                }
                got.push((k, b));
            }
            Ok::<_, pgrx::spi::Error>(())
        })
        .unwrap_or_else(|e| raise(PgSqlErrorCode::ERRCODE_INTERNAL_ERROR, format!("tin_tiles_from_table: reading {}: {e}", self.from)));
        if got.len() != want.len() {
            raise(
                PgSqlErrorCode::ERRCODE_OBJECT_NOT_IN_PREREQUISITE_STATE,
                format!(
                    "tin_tiles_from_table: tiles of {} changed during the build (read {} of {})",
                    self.from,
                    got.len(),
                    want.len()
                ),
            );
        }
        self.loaded.extend(got);
    }

    /// Build the next batch of tiles (one per thread) into `ready`.
    fn build_batch(&mut self) {
        use tinmerge_core::tin::tiles::{build_tile_kept, keep_border_samples, Block};
        let threads = tinmerge_core::tin::par::threads().max(1);
        let batch: Vec<usize> =
            self.order[self.next..(self.next + threads).min(self.order.len())].to_vec();
        self.next += batch.len();
        let (first, last) = (
            self.grid.tiles[batch[0]].ty,
            self.grid.tiles[batch[batch.len() - 1]].ty,
        );
        self.load_rows(first..=last + 1);
        let per_tile = (self.grid.tile_width + 1) * (self.grid.tile_height + 1);
        memory::reserve(
            tinmerge_core::tin::build::lattice_build_bytes(per_tile, self.tols.len(), true)
                .saturating_mul(batch.len()),
            || {
                format!("tin_tiles_from_table: building {} tiles of {per_tile} samples at {} levels at once", batch.len(), self.tols.len())
            },
        );
        let valids: std::collections::HashMap<usize, Box<dyn Fn(f64) -> bool + Sync + '_>> = self
            .loaded
            .iter()
            .map(|(&k, b)| {
                (
                    k,
                    Box::new(move |v: f64| b.is_valid(v)) as Box<dyn Fn(f64) -> bool + Sync>,
                )
            })
            .collect();
        let block = |tx: usize, ty: usize| -> Option<Block> {
            let k = *self.at.get(&(tx, ty))?;
            Some(Block {
                place: self.grid.tiles[k],
                values: &self.loaded.get(&k)?.values,
                valid: valids.get(&k)?.as_ref(),
            })
        };
        let (lattice, tols, srid) = (self.grid.lattice, &self.tols, self.srid);
        let (seams, planning) = (&self.seams, self.planning);
        let built = tinmerge_core::tin::par::map(&batch, |&k| {
            let p = self.grid.tiles[k];
            let own = block(p.tx, p.ty)?;
            let s = keep_border_samples(
                &own,
                block(p.tx + 1, p.ty).as_ref(),
                block(p.tx, p.ty + 1).as_ref(),
                block(p.tx + 1, p.ty + 1).as_ref(),
            );
            let keep = seams.border(
                p.col..p.col + p.width as i64 + 1,
                p.row..p.row + p.height as i64 + 1,
            );
            Some(
                build_tile_kept(s, &lattice, (p.col, p.row), tols, srid, &keep, &mut || {
                    Ok(())
                })
                .map(|t| {
                    t.map(|(t, wanted)| {
                        if planning {
                            (None, wanted)
                        } else {
                            let out = TinOut::from_tin_on(&t, &lattice);
                            (Some((p.tx as i32, p.ty as i32, out)), Vec::new())
                        }
                    })
                }),
            )
        });
        for r in built {
            let Some(r) = r else {
                raise(
                    PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
                    "tin_tiles_from_table: a tile of the batch was not read",
                );
            };
            if let Some((row, wanted)) = r.or_raise() {
                self.ready.extend(row);
                self.asked.push(wanted);
            }
        }
    }
}

impl Iterator for TableTiles {
    type Item = (i32, i32, TinOut);
    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(r) = self.ready.pop_front() {
                return Some(r);
            }
            if self.next >= self.order.len() {
                if !self.planning {
                    return None;
                }
                self.end_round();
                continue;
            }
            pgrx::check_for_interrupts!();
            self.build_batch();
        }
    }
}

/// `tin_tiles_from_table(tiles regclass, tolerance, levels, rast_column, band)`:
/// every raster tile of a table built as a tin with its neighbours' border
/// pixels (the SQL wrapper passes the table's OID and the column's name).
#[pg_extern(stable, strict, parallel_restricted, cost = 100000, requires = ["tin_type"])]
fn _tin_tiles_table(
    tab: pg_sys::Oid,
    column: &str,
    tolerance: f64,
    levels: i32,
    band: i32,
) -> TableIterator<'static, (name!(tx, i32), name!(ty, i32), name!(t, TinOut))> {
    TableIterator::new(TableTiles::open(tab, column, tolerance, levels, band))
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_tiles_table(oid, text, float8, int, int) ROWS 100;
COMMENT ON FUNCTION _tin_tiles_table(oid, text, float8, int, int) IS 'Internal: use tin_tiles_from_table(regclass, float8, int, name, int).';
"#,
    name = "tin_tiles_table_sql",
    requires = [_tin_tiles_table]
);
