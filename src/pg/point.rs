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

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn tin_locate(
    t: Option<TinArg>,
    pt: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<i32> {
    let (t, pt) = (t?, pt?);
    let (tin, l) = tin_level(&t, level);
    let [x, y] = pt.point_xy(tin.srid, "tin_locate")?;
    point::locate(&tin, l, x, y).map(|i| i as i32)
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
fn tin_height(
    t: Option<TinArg>,
    pt: Option<GeomArg>,
    level: default!(Option<i32>, "NULL"),
) -> Option<f64> {
    let (t, pt) = (t?, pt?);
    let (tin, l) = tin_level(&t, level);
    let [x, y] = pt.point_xy(tin.srid, "tin_height")?;
    point::height(&tin, l, x, y)
}

#[pg_extern(immutable, parallel_safe, requires = ["tin_type"])]
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
