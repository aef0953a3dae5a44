//! SQL functions of the surface analyses: `tin_contours` and
//! `tin_slope_aspect`. Not STRICT (a NULL level means finest): a NULL tin
//! or interval gives no rows.

use pgrx::prelude::*;

use super::args::GeomOut;
use super::errors::OrRaise;
use super::interrupt::interrupt;
use super::tin_type::{tin_level, TinArg};
use tinmerge_core::analysis::contour::contours;
use tinmerge_core::analysis::slope::slope_aspect;
use tinmerge_core::io::ewkb::Geom;
use tinmerge_core::io::gserialized;

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_contours(
    t: Option<TinArg>,
    interval: Option<f64>,
    level: default!(Option<i32>, "NULL"),
    base: default!(Option<f64>, "0"),
) -> TableIterator<'static, (name!(z, f64), name!(geom, GeomOut))> {
    let (Some(t), Some(interval), Some(base)) = (t, interval, base) else {
        return TableIterator::new(Vec::new());
    };
    let (tin, l) = tin_level(&t, level);
    let lines = contours(&tin, l, interval, base, &mut interrupt).or_raise();
    let srid = tin.srid;
    TableIterator::new(lines.into_iter().map(move |c| {
        let pts = c.points.iter().map(|p| [p[0], p[1], f64::NAN]).collect();
        (
            c.z,
            GeomOut(gserialized::write(srid, false, &Geom::LineString(pts))),
        )
    }))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_contours(tin, float8, int, float8) ROWS 1000;
COMMENT ON FUNCTION tin_contours(tin, float8, int, float8) IS
'Exact contour lines of the surface of a level (NULL = finest) at the heights base + k * interval, as LINESTRINGs with the tin''s SRID, by increasing z: the isolines of the linear surface on each triangle, joined across triangles; a closed contour is a closed ring, an open one ends on the domain''s edge. A vertex exactly at a contour height counts as above it (a contour along a flat area at that height follows its lower edge; a horizontal triangle at it gives no line). At most 100,000 heights per call.';
"#,
    name = "tin_contours_sql",
    requires = [tin_contours]
);

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_slope_aspect(
    t: Option<TinArg>,
    level: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(triangle, i32),
        name!(slope, f64),
        name!(aspect, Option<f64>),
    ),
> {
    let Some(t) = t else {
        return TableIterator::new(Vec::new());
    };
    let (tin, l) = tin_level(&t, level);
    super::area::refuse_geographic(None, tin.srid, &tin.bbox, "tin_slope_aspect");
    let n = tin.levels[l].num_domain();
    let mut rows = Vec::with_capacity(n);
    let mut check = interrupt;
    let mut tick = tinmerge_core::interrupt::Ticker::new(&mut check);
    for tri in 0..n as u32 {
        tick.tick().or_raise();
        let (s, a) = slope_aspect(&tin.corners(l, tri));
        rows.push((tri as i32, s, a));
    }
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION tin_slope_aspect(tin, int) ROWS 10000;
COMMENT ON FUNCTION tin_slope_aspect(tin, int) IS
'Slope and aspect of every triangle of a level (NULL = finest), exact for the plane of each triangle: slope in degrees from the horizontal, aspect the direction the triangle faces (steepest descent) in degrees clockwise from grid north, in [0, 360), NULL for a flat triangle; triangle as in tin_triangles. Planar SRIDs only (x, y in the unit of z): a geographic tin is an error.';
"#,
    name = "tin_slope_aspect_sql",
    requires = [tin_slope_aspect]
);
