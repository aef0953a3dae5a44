//! SQL functions of the line merge: `tin_line_triangles`,
//! `tin_line_segments`, `tin_line_profile`, `tin_line_climb`, and
//! `tin_drape` for every geometry type. Lines arrive as EWKB (the SQL
//! wrappers cast `geometry` to `bytea`); `tin_drape` reads and writes
//! `geometry` directly. Not STRICT (a NULL level means
//! finest): a NULL tin or line gives no rows / NULL.

use pgrx::prelude::*;

use super::args::{check_srid, GeomArg, GeomOut};
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::point::height_at;
use super::tin_type::tin_level;
use super::tin_type::TinArg;
use tinmerge_core::io::ewkb::{self, Geom};
use tinmerge_core::io::gserialized;
use tinmerge_core::merge::line::drape::drape;
use tinmerge_core::merge::line::widened::near_line;
use tinmerge_core::merge::line::{
    pieces_in, runs, walk_parts, Part, Piece, PieceSink, TriangleSink,
};
use tinmerge_core::tin::mesh::Indexed;
use tinmerge_core::tin::{check_xy, Tin, TinError};

/// The parts of a LINESTRING or MULTILINESTRING argument (SRID checked,
/// coordinates finite); an ERROR naming the type for anything else.
pub(crate) fn line_parts(bytes: &[u8], tin_srid: i32, func: &str) -> Vec<Part> {
    let g = ewkb::read(bytes).or_raise();
    check_srid(
        g.srid,
        tin_srid,
        func,
        "line",
        super::args::first_xy(&g.geom),
    );
    let lines: Vec<&Vec<[f64; 3]>> = match &g.geom {
        Geom::LineString(l) => vec![l],
        Geom::MultiLineString(ls) => ls.iter().collect(),
        other => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func} takes a LINESTRING or MULTILINESTRING, got a {}{}",
                other.type_name(),
                match other {
                    Geom::Polygon(_) | Geom::MultiPolygon(_) =>
                        " (use ST_Boundary for its rings, or tin_drape)",
                    _ => "",
                }
            ),
        ),
    };
    lines
        .into_iter()
        .map(|l| {
            for c in l.iter() {
                tinmerge_core::tin::check_xy(format_args!("{func}: the line"), c[0], c[1])
                    .or_raise();
            }
            Part::new(l.iter().map(|c| [c[0], c[1]]).collect())
        })
        .collect()
}

pub(crate) fn check_width(width: f64) -> f64 {
    if !(width.is_finite() && width >= 0.0) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("line width must be a finite number >= 0, got {width}"),
        );
    }
    width
}

/// Triangles of the line: travel order (width 0) or first approach.
pub(crate) fn line_triangles<L: tinmerge_core::merge::line::Polyline>(
    tin: &Tin,
    l: usize,
    parts: &[L],
    width: f64,
) -> Vec<u32> {
    if width > 0.0 {
        near_line(tin, l, parts, width / 2.0, &mut interrupt).or_raise()
    } else {
        let mut sink = TriangleSink::default();
        walk_parts(tin, l, parts, &mut sink, &mut |_, _| {}, &mut interrupt).or_raise();
        sink.tris
    }
}

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_line_triangles(
    t: Option<TinArg>,
    line: Option<&[u8]>,
    level: default!(Option<i32>, "NULL"),
    width: default!(Option<f64>, "0"),
) -> TableIterator<'static, (name!(seq, i32), name!(triangle, i32))> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    let width = check_width(width.unwrap_or(0.0));
    let tris = if width > 0.0 {
        let (tin, l) = tin_level(&t, level);
        let parts = line_parts(line, tin.srid, "tin_line_triangles");
        line_triangles(&tin, l, &parts, width)
    } else {
        with_mesh!(t, level, |m, l, srid| {
            let parts = line_parts(line, srid, "tin_line_triangles");
            let mut sink = TriangleSink::default();
            walk_parts(m, l, &parts, &mut sink, &mut |_, _| {}, &mut interrupt).or_raise();
            sink.tris
        })
    };
    TableIterator::new(seq_rows(tris))
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_line_triangles(tin, bytea, int, float8) ROWS 100;
COMMENT ON FUNCTION _tin_line_triangles(tin, bytea, int, float8) IS 'Internal: use tin_line_triangles(tin, geometry, int, float8).';
"#,
    name = "tin_line_triangles_sql",
    requires = [_tin_line_triangles]
);

/// Triangle ids as (seq from 1, triangle) rows.
pub(crate) fn seq_rows(tris: Vec<u32>) -> Vec<(i32, i32)> {
    tris.into_iter()
        .enumerate()
        .map(|(i, t)| (i as i32 + 1, t as i32))
        .collect()
}

type SegmentRow = (i32, i32, Vec<u8>, f64, f64, f64);

pub(crate) fn segment_rows<M: Indexed>(
    tin: &M,
    srid: i32,
    l: usize,
    drive: impl FnOnce(&mut PieceSink<M>) -> Result<(), TinError>,
) -> Vec<SegmentRow>
where
    TinError: From<M::Err>,
{
    let mut sink = PieceSink::new(tin, l);
    drive(&mut sink).or_raise();
    let pieces = sink.finish().or_raise();
    pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut pts = p.points.clone();
            if pts.len() == 1 {
                pts.push(pts[0]);
            }
            (
                i as i32 + 1,
                p.triangle as i32,
                ewkb::Writer::write(srid, true, &Geom::LineString(pts)),
                p.length2d(),
                p.length3d(),
                p.rise(),
            )
        })
        .collect()
}

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_line_segments(
    t: Option<TinArg>,
    line: Option<&[u8]>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(seq, i32),
        name!(triangle, i32),
        name!(geom, Vec<u8>),
        name!(length2d, f64),
        name!(length3d, f64),
        name!(rise, f64),
    ),
> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    let rows = with_mesh!(t, level, |m, l, srid| {
        let parts = line_parts(line, srid, "tin_line_segments");
        segment_rows(m, srid, l, |sink| {
            walk_parts(m, l, &parts, sink, &mut |s, i| s.part = i, &mut interrupt)
        })
    });
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_line_segments(tin, bytea, int) ROWS 100;
COMMENT ON FUNCTION _tin_line_segments(tin, bytea, int) IS 'Internal: use tin_line_segments(tin, geometry, int).';
"#,
    name = "tin_line_segments_sql",
    requires = [_tin_line_segments]
);

/// Profile points (distance along the whole line, z) and the climb.
pub(crate) fn profile(pieces: &[Piece], part_offsets: &[f64]) -> (Vec<(f64, f64)>, Option<f64>) {
    let mut pts = Vec::new();
    let mut climb: Option<f64> = None;
    for (part, p, along) in runs(pieces) {
        let off = part_offsets.get(part).copied().unwrap_or(0.0);
        for (i, (q, a)) in p.iter().zip(along.iter()).enumerate() {
            pts.push((off + a, q[2]));
            if i > 0 {
                let c = climb.get_or_insert(0.0);
                *c += (q[2] - p[i - 1][2]).max(0.0);
            } else {
                climb.get_or_insert(0.0);
            }
        }
    }
    (pts, climb)
}

/// Distance along the whole line at which each part starts (parts follow
/// each other; the gaps between them are not counted).
pub(crate) fn part_offsets(lengths: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut offs = Vec::new();
    let mut d = 0.0;
    for l in lengths {
        offs.push(d);
        d += l;
    }
    offs
}

fn profile_of(
    t: &TinArg,
    line: &[u8],
    level: Option<i32>,
    func: &str,
) -> (Vec<(f64, f64)>, Option<f64>) {
    with_mesh!(t, level, |m, l, srid| {
        let parts = line_parts(line, srid, func);
        let pieces = pieces_in(m, l, &parts, &mut interrupt).or_raise();
        profile(&pieces, &part_offsets(parts.iter().map(|p| p.length())))
    })
}

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_line_profile(
    t: Option<TinArg>,
    line: Option<&[u8]>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<'static, (name!(distance, f64), name!(z, f64))> {
    let (Some(t), Some(line)) = (t, line) else {
        return TableIterator::new(Vec::new());
    };
    TableIterator::new(profile_of(&t, line, level, "tin_line_profile").0)
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_line_profile(tin, bytea, int) ROWS 100;
COMMENT ON FUNCTION _tin_line_profile(tin, bytea, int) IS 'Internal: use tin_line_profile(tin, geometry, int).';
"#,
    name = "tin_line_profile_sql",
    requires = [_tin_line_profile]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_line_climb(
    t: Option<TinArg>,
    line: Option<&[u8]>,
    level: default!(Option<i32>, "NULL"),
) -> Option<f64> {
    let (t, line) = (t?, line?);
    profile_of(&t, line, level, "tin_line_climb").1
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_line_climb(tin, bytea, int) IS 'Internal: use tin_line_climb(tin, geometry, int).';
"#,
    name = "tin_line_climb_sql",
    requires = [_tin_line_climb]
);

/// `tin_drape`: the argument is read and the result written in PostGIS's own
/// serialisation ([`gserialized`]), with no EWKB conversion either way; a
/// POINT, the common per-row form, takes the point merge's path directly.
#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_drape(
    t: Option<TinArg>,
    geom: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<GeomOut> {
    let (t, geom) = (t?, geom?);
    let bytes = geom.bytes();
    let p = gserialized::peek(bytes).or_raise();
    if let (Some(Some([x, y])), false) = (p.point, p.has_m) {
        if !(x.is_nan() && y.is_nan()) {
            let z = height_at(&t, level, &geom, "tin_drape")?;
            let out = Geom::Point(Some([x, y, z]));
            return Some(GeomOut(gserialized::write(p.srid, true, &out)));
        }
    }
    let (tin, l) = tin_level(&t, level);
    let g = gserialized::read(bytes).or_raise();
    let out = drape_checked(&tin, l, &g)?;
    Some(GeomOut(gserialized::write(g.srid, true, &out)))
}

/// Drape a decoded geometry after the SRID and coordinate checks.
pub(super) fn drape_checked(tin: &Tin, l: usize, g: &ewkb::Ewkb) -> Option<Geom> {
    check_srid(
        g.srid,
        tin.srid,
        "tin_drape",
        "geom",
        super::args::first_xy(&g.geom),
    );
    let mut bad = None;
    g.geom.for_each_coord(&mut |c| {
        if bad.is_none() && check_xy("", c[0], c[1]).is_err() {
            bad = Some(*c);
        }
    });
    if let Some(c) = bad {
        check_xy("tin_drape: the geometry", c[0], c[1]).or_raise();
    }
    drape(tin, l, &g.geom).or_raise()
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_drape(tin, geometry, int) IS 'The geometry with Z from the surface of a level (NULL = finest) and a vertex added wherever a line or ring crosses a triangle edge (as ArcGIS Interpolate Shape or H2GIS ST_Drape). Any type, multi* and collections included. Points outside the domain are dropped; lines keep their stretches inside (a line leaving and coming back becomes a MULTILINESTRING); polygons keep their intersection with the domain (a polygon cut in pieces becomes a MULTIPOLYGON), the new edges along the domain''s edge. NULL when nothing is left.';
"#,
    name = "tin_drape_sql",
    requires = [tin_drape]
);
