//! SQL functions of the TIN/TIN overlay: `tin_overlay`, `tin_overlay_tin`,
//! `tin_difference`, and `tin_volume(a, b, area)` (cut and fill inside a
//! polygon). Not STRICT (a NULL level means finest): a NULL tin
//! gives no rows (NULL from `tin_overlay_tin`).

use pgrx::prelude::*;

use super::args::GeomArg;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::tin_level;
use super::tin_type::{TinArg, TinOut};
use tinmerge_core::io::ewkb;
use tinmerge_core::merge::overlay::volume::volumes_in;
use tinmerge_core::merge::overlay::{difference, mark_same, overlay, Overlay};
use tinmerge_core::tin::build::from_triangles_void;

/// The overlay of two tin arguments at their levels, SRIDs checked, with
/// the SRID of the result.
fn overlay_args(
    a: &TinArg,
    level_a: Option<i32>,
    b: &TinArg,
    level_b: Option<i32>,
    func: &str,
    same: bool,
) -> (Overlay, i32) {
    let (ta, la) = tin_level(a, level_a);
    let (tb, lb) = tin_level(b, level_b);
    if ta.srid != tb.srid {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!(
                "{func}: tin a has SRID {} but tin b has SRID {}; build both in the same spatial reference system",
                ta.srid, tb.srid
            ),
        );
    }
    let (na, nb) = (ta.levels[la].tris.len(), tb.levels[lb].tris.len());
    memory::reserve(tinmerge_core::merge::overlay::overlay_bytes(na, nb), || {
        format!("{func}: overlaying {na} and {nb} triangles")
    });
    let mut o = overlay(&ta, la, &tb, lb, &mut interrupt).or_raise();
    if same {
        mark_same(&mut o, &ta, la, &tb, lb);
    }
    (o, ta.srid)
}

type OverlayRow = (i32, i32, i32, Vec<u8>, Vec<u8>);

#[allow(clippy::type_complexity)]
#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_overlay(
    a: Option<TinArg>,
    b: Option<TinArg>,
    level_a: Option<i32>,
    level_b: Option<i32>,
) -> TableIterator<
    'static,
    (
        name!(id, i32),
        name!(triangle_a, i32),
        name!(triangle_b, i32),
        name!(geom_a, Vec<u8>),
        name!(geom_b, Vec<u8>),
    ),
> {
    let (Some(a), Some(b)) = (a, b) else {
        return TableIterator::new(Vec::<OverlayRow>::new());
    };
    let (o, srid) = overlay_args(&a, level_a, &b, level_b, "tin_overlay", false);
    let rows: Vec<usize> = o.domain().collect();
    TableIterator::new(rows.into_iter().map(move |t| {
        (
            t as i32,
            o.tri_a[t] as i32,
            o.tri_b[t] as i32,
            ewkb::Writer::triangle_polygon(srid, &o.corners(t, false)),
            ewkb::Writer::triangle_polygon(srid, &o.corners(t, true)),
        )
    }))
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_overlay(tin, tin, int, int) ROWS 100000;
COMMENT ON FUNCTION _tin_overlay(tin, tin, int, int) IS 'Internal: use tin_overlay(tin, tin, int, int).';
"#,
    name = "tin_overlay_sql",
    requires = [_tin_overlay]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_overlay_tin(
    a: Option<TinArg>,
    b: Option<TinArg>,
    level_a: Option<i32>,
    level_b: Option<i32>,
) -> Option<TinOut> {
    let (a, b) = (a?, b?);
    let (o, srid) = overlay_args(&a, level_a, &b, level_b, "tin_overlay_tin", false);
    // no output triangle where both have data: the domains do not overlap
    o.domain().next()?;
    let verts: Vec<[f64; 3]> = o
        .pts
        .iter()
        .zip(&o.za)
        .map(|(p, &z)| [p[0], p[1], z])
        .collect();
    memory::reserve(
        tinmerge_core::tin::build::build_bytes(verts.len(), 1),
        || {
            format!(
                "tin_overlay_tin: storing {} triangles as a tin",
                o.tris.len()
            )
        },
    );
    // the output triangles in a void triangle of a or b are void in the
    // result too (a hole of either is a hole of the overlay)
    let tin = from_triangles_void(verts, o.tris, o.void, srid, &mut interrupt).or_raise();
    Some(TinOut::from_tin(&tin))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_overlay_tin(tin, tin, int, int) IS 'Internal: use tin_overlay_tin(tin, tin, int, int).';
"#,
    name = "tin_overlay_tin_sql",
    requires = [_tin_overlay_tin]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_difference(
    a: Option<TinArg>,
    b: Option<TinArg>,
    level_a: Option<i32>,
    level_b: Option<i32>,
) -> TableIterator<'static, (name!(cut, f64), name!(fill, f64), name!(area_changed, f64))> {
    let (Some(a), Some(b)) = (a, b) else {
        return TableIterator::new(Vec::new());
    };
    let (o, _) = overlay_args(&a, level_a, &b, level_b, "tin_difference", true);
    if o.tris.is_empty() {
        return TableIterator::new(Vec::new());
    }
    TableIterator::new(vec![difference(&o)])
}

extension_sql!(
    r#"
ALTER FUNCTION _tin_difference(tin, tin, int, int) ROWS 1;
COMMENT ON FUNCTION _tin_difference(tin, tin, int, int) IS 'Internal: use tin_difference(tin, tin, int, int).';
"#,
    name = "tin_difference_sql",
    requires = [_tin_difference]
);

/// `tin_volume(a, b, area)`: cut and fill between two surfaces inside a
/// polygon.
#[allow(clippy::type_complexity)]
#[pg_extern(name = "tin_volume", support = _tin_plan_support, immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn tin_volume_between(
    a: Option<TinArg>,
    b: Option<TinArg>,
    area: Option<GeomArg>,
    level_a: default!(Option<i32>, "NULL"),
    level_b: default!(Option<i32>, "NULL"),
) -> TableIterator<
    'static,
    (
        name!(cut, f64),
        name!(fill, f64),
        name!(area_cut, f64),
        name!(area_fill, f64),
        name!(area_unchanged, f64),
    ),
> {
    let (Some(a), Some(b), Some(g)) = (a, b, area) else {
        return TableIterator::new(Vec::new());
    };
    let func = "tin_volume";
    let ta = a.tin();
    let units = super::area::area_units(None, ta.srid, &ta.bbox, func);
    let area = super::area::geom_area(&g, ta.srid, func);
    let (o, srid) = overlay_args(&a, level_a, &b, level_b, func, true);
    memory::reserve(
        tinmerge_core::tin::build::build_bytes(o.pts.len(), 1),
        || format!("{func}: measuring {} overlay triangles", o.tris.len()),
    );
    let v = volumes_in(&o, &area, srid, units, &mut interrupt).or_raise();
    TableIterator::new(vec![(
        v.cut,
        v.fill,
        v.area_cut,
        v.area_fill,
        v.area_unchanged,
    )])
}

extension_sql!(
    r#"
ALTER FUNCTION tin_volume(tin, tin, geometry, int, int) ROWS 1;
COMMENT ON FUNCTION tin_volume(tin, tin, geometry, int, int) IS
'Cut and fill between two surfaces inside a POLYGON or MULTIPOLYGON (holes count out), each at a level (NULL = finest): two epochs of a survey, or a design against the ground, as ArcGIS Surface Difference and Cut Fill. cut = volume where a is above b, fill = volume where a is below b, area_cut and area_fill the planar areas where it is so, area_unchanged where the two are one plane (their triangles'' planes agree within 1e-9 of the height, as tin_difference); exact for the linear surfaces, over the overlay of the two (tin_overlay) clipped to the polygon. Only the common domain counts: the three areas sum to the polygon''s part of it. The tins must share their SRID and the polygon must have it too; tins in a geographic SRID answer in metres on its spheroid (as tin_area_stats). No row for a NULL tin or polygon.';
"#,
    name = "tin_volume_between_sql",
    requires = [tin_volume_between]
);
