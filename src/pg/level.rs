//! Whole levels: the triangles of a level (`tin_triangles`,
//! `tin_as_geometry`) and the check of every level (`tin_validate`).

use pgrx::prelude::*;

use super::errors::OrRaise;
use super::interrupt::interrupt;
use super::tin_type::TinArg;
use tinmerge_core::io::ewkb;
use tinmerge_core::tin::NONE;

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
    let found = tinmerge_core::tin::check::problems(&tin, &mut interrupt).or_raise();
    TableIterator::new(found.into_iter().map(|p| {
        (
            p.level as i32,
            p.kind.to_string(),
            p.triangle as i32,
            p.detail,
        )
    }))
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
