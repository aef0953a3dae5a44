//! SQL functions of the surface analyses: `tin_contours`,
//! `tin_slope_aspect` and `tin_line_of_sight`. Not STRICT (a NULL level means finest): a NULL tin
//! or interval gives no rows.

use pgrx::prelude::*;

use super::args::{check_srid, first_xy, GeomArg, GeomOut};
use super::errors::raise;
use super::errors::OrRaise;
use super::interrupt::interrupt;
use super::tin_type::{tin_level, TinArg};
use tinmerge_core::analysis::contour::contours;
use tinmerge_core::analysis::slope::slope_aspect_in;
use tinmerge_core::analysis::visibility::{line_of_sight, Curvature};
use tinmerge_core::io::ewkb::Geom;
use tinmerge_core::io::gserialized;
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;

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
    let units = super::area::area_units(None, tin.srid, &tin.bbox, "tin_slope_aspect");
    let n = tin.levels[l].num_domain();
    let mut rows = Vec::with_capacity(n);
    let mut check = interrupt;
    let mut tick = tinmerge_core::interrupt::Ticker::new(&mut check);
    for tri in 0..n as u32 {
        tick.tick().or_raise();
        let (s, a) = slope_aspect_in(&tin.corners(l, tri), units);
        rows.push((tri as i32, s, a));
    }
    TableIterator::new(rows)
}

extension_sql!(
    r#"
ALTER FUNCTION tin_slope_aspect(tin, int) ROWS 10000;
COMMENT ON FUNCTION tin_slope_aspect(tin, int) IS
'Slope and aspect of every triangle of a level (NULL = finest), exact for the plane of each triangle: slope in degrees from the horizontal, aspect the direction the triangle faces (steepest descent) in degrees clockwise from grid north, in [0, 360), NULL for a flat triangle; triangle as in tin_triangles. x, y in the unit of z, or, for a tin in a geographic SRID, each triangle in metres at its centroid''s latitude on the SRID''s spheroid (north then true north).';
"#,
    name = "tin_slope_aspect_sql",
    requires = [tin_slope_aspect]
);

/// An observer or target of `tin_line_of_sight`: its x, y and absolute
/// height (its own Z, or the surface of the level plus `above`).
fn sight_point(g: &GeomArg, tin: &Tin, l: usize, above: f64, what: &str) -> [f64; 3] {
    let func = "tin_line_of_sight";
    match sight_points(g, tin, l, above, what, func, false)[..] {
        [p] => p,
        _ => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: the {what} must be a POINT or POINT Z"),
        ),
    }
}

/// The points of a POINT (or, when `multi`, a MULTIPOINT) with their
/// absolute heights: their own Z, or the surface of the level plus
/// `above`. ERROR for another type, an empty one, the wrong SRID, or a
/// point without Z off the surface.
pub(super) fn sight_points(
    g: &GeomArg,
    tin: &Tin,
    l: usize,
    above: f64,
    what: &str,
    func: &str,
    multi: bool,
) -> Vec<[f64; 3]> {
    let e = gserialized::read(g.bytes()).or_raise();
    check_srid(e.srid, tin.srid, func, what, first_xy(&e.geom));
    let wanted = if multi {
        "a POINT or MULTIPOINT (with or without Z)"
    } else {
        "a POINT or POINT Z"
    };
    let empty = |kind: &str| -> ! {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: the {what} is an empty {kind}"),
        )
    };
    let pts = match e.geom {
        Geom::Point(Some(p)) => vec![p],
        Geom::Point(None) => empty("point"),
        Geom::MultiPoint(ps) if multi => {
            if ps.is_empty() {
                empty("MULTIPOINT")
            }
            ps
        }
        _ => raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: the {what} must be {wanted}"),
        ),
    };
    pts.into_iter()
        .map(|p| {
            tinmerge_core::tin::check_xy(format_args!("{func}: the {what}"), p[0], p[1]).or_raise();
            if e.has_z {
                if !p[2].is_finite() {
                    raise(
                        PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                        format!("{func}: the {what}'s Z must be finite"),
                    );
                }
                return [p[0], p[1], p[2]];
            }
            match height(tin, l, p[0], p[1]) {
                Some(z) => [p[0], p[1], z + above],
                None => raise(
                    PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                    format!(
                        "{func}: the {what} ({}, {}) is off the tin's surface at level {l}; give it a Z (an absolute height) to look from or at a point off the terrain",
                        p[0], p[1]
                    ),
                ),
            }
        })
        .collect()
}

/// Metres per horizontal unit along x and y near latitude `lat` (degrees)
/// for a geographic tin; 1, 1 for a projected one.
pub(super) fn metres_per_unit(geographic: bool, lat: f64) -> [f64; 2] {
    if geographic {
        let m = 111_319.490_793_273_6;
        [m * lat.to_radians().cos(), m]
    } else {
        [1.0, 1.0]
    }
}

#[allow(clippy::too_many_arguments, clippy::type_complexity)]
#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 500, requires = ["tin_type"])]
fn tin_line_of_sight(
    t: Option<TinArg>,
    observer: Option<GeomArg>,
    target: Option<GeomArg>,
    observer_height: default!(Option<f64>, "1.7"),
    target_height: default!(Option<f64>, "0"),
    level: default!(Option<i32>, "NULL"),
    curvature: default!(Option<bool>, "false"),
    refraction: default!(Option<f64>, "0.13"),
) -> TableIterator<
    'static,
    (
        name!(visible, bool),
        name!(obstruction, Option<GeomOut>),
        name!(distance, Option<f64>),
        name!(clearance, Option<f64>),
    ),
> {
    let (Some(t), Some(o), Some(g), Some(oh), Some(th), Some(curv), Some(k)) = (
        t,
        observer,
        target,
        observer_height,
        target_height,
        curvature,
        refraction,
    ) else {
        return TableIterator::new(Vec::new());
    };
    let func = "tin_line_of_sight";
    for (v, name) in [
        (oh, "observer_height"),
        (th, "target_height"),
        (k, "refraction"),
    ] {
        if !v.is_finite() {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("{func}: {name} must be finite, got {v}"),
            );
        }
    }
    let (tin, l) = tin_level(&t, level);
    let eye = sight_point(&o, &tin, l, oh, "observer");
    let aim = sight_point(&g, &tin, l, th, "target");
    let geographic = super::area::srid_is_geographic(None, tin.srid, &tin.bbox);
    let curvature = if curv {
        // metres per unit along the sight line, at its middle latitude
        let [mx, my] = metres_per_unit(geographic, 0.5 * (eye[1] + aim[1]));
        let (dx, dy) = (aim[0] - eye[0], aim[1] - eye[1]);
        let len = dx.hypot(dy);
        let metres_per_unit = if len > 0.0 {
            (mx * dx).hypot(my * dy) / len
        } else {
            my
        };
        Curvature::Earth {
            refraction: k,
            metres_per_unit,
        }
    } else {
        Curvature::None
    };
    let s = line_of_sight(&tin, l, eye, aim, curvature, &mut interrupt).or_raise();
    let obstruction = s
        .obstruction
        .map(|p| GeomOut(gserialized::write(tin.srid, true, &Geom::Point(Some(p)))));
    TableIterator::new(vec![(s.visible, obstruction, s.distance, s.clearance)])
}

extension_sql!(
    r#"
ALTER FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) ROWS 1;
COMMENT ON FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) IS
'Whether a target can be seen from an observer over the surface of a level (NULL = finest), exactly for its triangles: the straight sight line from the observer''s eye (a POINT: observer_height above the surface; a POINT Z: at that absolute height) to the target (target_height above the surface, or its Z) is cut at every triangle edge, and blocked where the surface rises above it. visible; obstruction, the first point where the surface meets the sight line, as a POINT Z on the surface (NULL when visible); distance, its horizontal distance from the observer in the tin''s units; clearance, the least height of the sight line above the surface strictly between the two (negative when blocked; NULL when the line crosses no edge). curvature: distant ground lowered by (1 - refraction) d^2 / (2 R), R = 6,371 km (as gdal_viewshed and r.viewshed), with d in metres (geographic tins: degrees converted along the line). Where the line leaves the domain nothing blocks. Points must have the tin''s SRID; a POINT off the surface needs a Z. No row for a NULL argument other than level.';
"#,
    name = "tin_line_of_sight_sql",
    requires = [tin_line_of_sight]
);
