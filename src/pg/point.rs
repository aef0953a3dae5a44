//! SQL functions of the point merge: `tin_locate`, `tin_height` and
//! `tin_footprint` (`tin_drape` is in [`super::line`]). A NULL tin or geometry gives NULL (the
//! functions are not STRICT because the level argument may be NULL =
//! finest); an empty geometry gives NULL.

use pgrx::prelude::*;

use super::args::GeomArg;
use super::errors::OrRaise;
use super::interrupt::interrupt;
use super::tin_type::tin_level;
use super::tin_type::TinArg;
use tinmerge_core::merge::point::{self, Rect};
use tinmerge_core::tin::locate;
use tinmerge_core::tin::TinError;

// (with_mesh! expands the body for both mesh sources: the decoded value's
// errors are Infallible, the sliced reader's TinError, so the conversion is
// the identity in one of them)
#[allow(clippy::useless_conversion)]
#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 50, requires = ["tin_type"])]
fn tin_locate(
    t: Option<TinArg>,
    pt: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<i32> {
    let (t, pt) = (t?, pt?);
    with_mesh!(t, level, |m, l, srid| {
        let [x, y] = pt.point_xy(srid, "tin_locate")?;
        locate::locate_in(m, l, x, y)
            .map_err(TinError::from)
            .or_raise()
    })
    .map(|i| i as i32)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_locate(tin, geometry, int) IS 'Id (as in tin_triangles) of the triangle of a level (NULL = finest) containing a POINT; on a shared edge or vertex, the smallest id; NULL outside the domain. Grid index + exact walk: constant time per point.';
"#,
    name = "tin_locate_sql",
    requires = [tin_locate]
);

#[pg_extern(immutable, parallel_safe, cost = 50, support = _tin_plan_support, requires = ["tin_type"])]
fn tin_height(
    t: Option<TinArg>,
    pt: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<f64> {
    let (t, pt) = (t?, pt?);
    height_at(&t, level, &pt, "tin_height")
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_height(tin, geometry, int) IS 'Height of the surface of a level (NULL = finest) at a POINT, by linear interpolation on the triangle containing it; NULL outside the domain. The point''s own Z, if any, is ignored.';
"#,
    name = "tin_height_sql",
    requires = [tin_height]
);

/// The height at a point argument (what `tin_height` returns), on the
/// decoded value or the stored value read in slices
/// ([`TinArg::mesh_source`]).
// (with_mesh! expands the body for both mesh sources: the decoded value's
// errors are Infallible, the sliced reader's TinError, so the conversion is
// the identity in one of them)
#[allow(clippy::useless_conversion)]
pub(crate) fn height_at(t: &TinArg, level: Option<i32>, pt: &GeomArg, func: &str) -> Option<f64> {
    with_mesh!(t, level, |m, l, srid| {
        let [x, y] = pt.point_xy(srid, func)?;
        point::height_near_in(m, l, x, y)
            .map_err(TinError::from)
            .or_raise()
    })
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 500, requires = ["tin_type"])]
fn tin_footprint(
    t: Option<TinArg>,
    pt: Option<GeomArg>,
    width: Option<f64>,
    length: Option<f64>,
    angle: Option<f64>,
    level: default!(Option<i32>, "NULL"),
) -> SetOfIterator<'static, i32> {
    let none = || SetOfIterator::new(Vec::new());
    let (Some(t), Some(pt), Some(width), Some(length), Some(angle)) = (t, pt, width, length, angle)
    else {
        return none();
    };
    let (tin, l) = tin_level(&t, level);
    let Some([x, y]) = pt.point_xy(tin.srid, "tin_footprint") else {
        return none();
    };
    let rect = Rect::within(x, y, width, length, angle, &tin.bbox).or_raise();
    let ids = point::footprint(&tin, l, &rect, &mut interrupt).or_raise();
    SetOfIterator::new(ids.into_iter().map(|i| i as i32))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_footprint(tin, geometry, float8, float8, float8, int) ROWS 20;
COMMENT ON FUNCTION tin_footprint(tin, geometry, float8, float8, float8, int) IS 'Ids of the triangles of a level (NULL = finest) meeting the closed rectangle centred on a POINT, width across and length along angle (degrees clockwise from north), in increasing id order. Width and length >= 0 (0 gives a segment or a point).';
"#,
    name = "tin_footprint_sql",
    requires = [tin_footprint]
);
