//! The builders: `tin_from_raster` (both forms), `tin_tiles` and
//! `tin_from_points` (`tin_from_points_agg` is in [`super::points_agg`],
//! `tin_tiles_from_table` in [`super::table_tiles`]).
//! Geometry and raster travel as (E)WKB `bytea`; the public
//! `geometry`/`raster` signatures are thin SQL wrappers in `sql/tinmerge.sql`.

use pgrx::prelude::*;

use super::errors::{raise, raise_hint, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::progress::track;
use super::tin_type::TinOut;

use tinmerge_core::io::{ewkb, raster};
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::tin::breaklines::Breakline;
use tinmerge_core::tin::build::raster::{RasterBand, RasterBuild};
use tinmerge_core::tin::build::{
    build_lattice, check_tolerances, default_tolerances, points_build_bytes, BuildOptions,
};
use tinmerge_core::tin::construct::build_points;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::seam_rounds::build_tiles;
use tinmerge_core::tin::tile_domain::build_tile_window;

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
pub(super) fn reserve_build_bytes(func: &str, samples: usize, levels: usize, bytes: usize) {
    super::threads::apply();
    memory::reserve(bytes.saturating_sub(samples * 24), || {
        format!("{func}: building a tin from {samples} samples at {levels} levels")
    });
}

/// One band of a raster argument (an ERROR for a band that is not there
/// or an empty raster; reading it counts against `tinmerge.max_memory`).
pub(super) fn raster_band(rast: &[u8], band: i32) -> (raster::Raster, raster::Band) {
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
pub(super) fn breaklines_of(
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
pub(super) fn boundary_of(func: &str, g: ewkb::Ewkb, srid: i32) -> Option<Area> {
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
    if hard.is_none() && soft.is_none() && boundary.is_none() && fill_gaps && keep_border {
        return build_raster(rast, tols, band, keep_border);
    }
    if keep_border && (hard.is_some() || soft.is_some() || boundary.is_some()) {
        raise(
            PgSqlErrorCode::ERRCODE_FEATURE_NOT_SUPPORTED,
            "tin_from_raster: keep_border cannot be combined with breaklines or a boundary (tiles with them are not built yet)",
        );
    }
    let (pts, lattice, srid, (w, h)) = raster_samples(rast, band);
    let lines = breaklines_arg("tin_from_raster", hard, soft, srid);
    let boundary = boundary_arg("tin_from_raster", boundary, srid);
    // the heights in place, NaN without data
    let mut z = vec![f64::NAN; w * h];
    for p in &pts {
        z[p[1] as usize * w + p[0] as usize] = p[2];
    }
    let heights = RasterBand {
        z,
        width: w,
        height: h,
        lattice,
    };
    if keep_border && heights.footprint().is_none() {
        drop((pts, heights));
        return build_raster(rast, tols, band, keep_border);
    }
    if keep_border {
        // a tile over its data, as tin_tiles builds it (its seams chosen
        // from their samples alone)
        drop(heights);
        reserve_build("tin_from_raster", pts.len(), tols.len(), true);
        let tile = track("tin_from_raster", || {
            build_tile_window(
                pts,
                &lattice,
                (0, 0),
                (w, h),
                tols,
                srid,
                &Default::default(),
                false,
                &mut interrupt,
            )
        })
        .or_raise();
        let Some((tin, _)) = tile else {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                "tin_from_raster: the raster has fewer than three valid pixels that are not on one line",
            );
        };
        return TinOut::from_tin_on(&tin, &lattice);
    }
    drop(pts);
    let with = RasterBuild {
        lines: &lines,
        boundary,
        fill_gaps,
    };
    let tin = track("tin_from_raster", || {
        tinmerge_core::tin::build::raster::build_raster(
            heights,
            with,
            tols,
            srid,
            &mut |samples, bytes| {
                reserve_build_bytes("tin_from_raster", samples, tols.len(), bytes);
                Ok(())
            },
            &mut interrupt,
        )
    })
    .or_raise();
    TinOut::from_tin_on(&tin, &lattice)
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
/// (`tin::tiles`), over the valid pixels' squares only unless `fill_gaps`
/// (`tin::tile_domain`), on `tinmerge.threads` threads.
#[pg_extern(immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_tiles(
    rast: &[u8],
    tile_px: i32,
    tolerance: f64,
    levels: i32,
    band: i32,
    fill_gaps: bool,
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
    track("tin_tiles", || {
        build_tiles(
            &b.values,
            r.width,
            r.height,
            &|v| b.is_valid(v),
            &lattice,
            tile_px as usize,
            &tols,
            fill_gaps,
            r.srid,
            &mut interrupt,
            &|tx, ty, tin| (tx as i32, ty as i32, TinOut::from_tin_on(&tin, &lattice)),
            &mut |row| {
                rows.push(row);
                Ok(())
            },
        )
    })
    .or_raise();
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_tiles(bytea, int, float8, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_tiles(bytea, int, float8, int, int, boolean) IS 'Internal: use tin_tiles(raster, int, float8, int, int, boolean).';
"#,
    name = "tin_tiles_sql",
    requires = [_tin_tiles]
);

/// The build behind both `tin_from_raster` forms.
fn build_raster(rast: &[u8], tols: &[f64], band: i32, keep_border: bool) -> TinOut {
    if !keep_border {
        // over the valid pixels' hull: the core's build of a whole band
        return build_raster_constrained(rast, tols, band, false, None, None, None, true);
    }
    let (pts, lattice, srid, _) = raster_samples(rast, band);
    // between the samples, tiles (keep_border) too: tin_tiles decides each
    // tile in its own frame, as this raster's
    let opts = BuildOptions {
        keep_border,
        between_samples: true,
    };
    reserve_build("tin_from_raster", pts.len(), tols.len(), true);
    let tin = track("tin_from_raster", || {
        build_lattice(pts, &lattice, tols, srid, opts, &mut interrupt)
    });
    TinOut::from_tin_on(&tin.or_raise(), &lattice)
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
    let tin = track("tin_from_points", || {
        build_points(samples, &tols, srid, &mut interrupt)
    });
    TinOut::from_tin(&tin.or_raise())
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
pub(super) fn build_points_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    area: Option<Area>,
    tols: &[f64],
    srid: i32,
) -> tinmerge_core::tin::Tin {
    track("tin_from_points", || {
        tinmerge_core::tin::build::build_points_domain(
            samples,
            lines,
            &area.iter().collect::<Vec<_>>(),
            tols,
            srid,
            &mut interrupt,
        )
    })
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
