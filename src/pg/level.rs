//! Whole levels: the triangles of a level (`tin_triangles`,
//! `tin_as_geometry`) and the check of every level (`tin_validate`).
//!
//! A level that is a small part of a stored value (a coarse level of a
//! large terrain) is read in slices: its triangle and parent groups and
//! the vertices it uses, not the whole value ([`small_level`]).

use pgrx::prelude::*;

use super::errors::OrRaise;
use super::interrupt::interrupt;
use super::tin_type::{MeshSource, TinArg};
use tinmerge_core::interrupt::Ticker;
use tinmerge_core::io::ewkb;
use tinmerge_core::tin::mesh::Mesh;
use tinmerge_core::tin::{resolve_level, NONE};

/// A level read on its own: its SRID and, per triangle, the parent (or
/// [`NONE`]) and corners.
type LevelRows = (i32, Vec<(u32, [[f64; 3]; 3])>);

/// The triangles of `level` read in slices, when the value is read in
/// slices and the level holds at most an eighth of its triangles (all
/// levels counted); None otherwise (the caller decodes the whole value:
/// reading most of the groups one by one would cost more).
fn small_level(t: &TinArg, level: Option<i32>) -> Option<LevelRows> {
    let MeshSource::Sliced(s) = t.mesh_source() else {
        return None;
    };
    let h = s.header();
    let l = resolve_level(level, h.levels.len()).or_raise();
    let total: u64 = h.levels.iter().map(|x| x.num_triangles as u64).sum();
    // the level's triangles in the domain (the void ones are the last)
    let n = h.levels[l].num_triangles - h.levels[l].num_void;
    if h.levels[l].num_triangles as u64 * 8 > total {
        return None;
    }
    let mut fetch = t.fetch();
    let r = s.reader(&mut fetch);
    let mut rows = Vec::with_capacity(n as usize);
    let mut check = interrupt;
    let mut tk = Ticker::new(&mut check);
    for i in 0..n {
        tk.tick().or_raise();
        rows.push((r.parent(l, i).or_raise(), r.corners(l, i).or_raise()));
    }
    Some((h.srid, rows))
}

/// Every sliver, hidden crack and hole of a tin (see `tin::check::problems`):
/// values built by tinmerge 0.2.0 from grids whose pixel centres round off
/// their lattice lines have them; rebuild those (docs/upgrading.md).
#[pg_extern(support = _tin_plan_support, immutable, strict, parallel_safe, cost = 10000, requires = ["tin_type"])]
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
    problem_rows(found)
}

/// `tin_validate`'s rows: level, problem, triangle, detail.
#[allow(clippy::type_complexity)]
pub(super) fn problem_rows(
    found: Vec<tinmerge_core::tin::check::Problem>,
) -> TableIterator<
    'static,
    (
        name!(level, i32),
        name!(problem, String),
        name!(triangle, i32),
        name!(detail, String),
    ),
> {
    TableIterator::new(found.into_iter().map(|p| {
        (
            p.level as i32,
            p.kind.to_string(),
            p.triangle as i32,
            p.detail,
        )
    }))
}

extension_sql!(
    r#"
ALTER FUNCTION tin_validate(tin) ROWS 10;
COMMENT ON FUNCTION tin_validate(tin) IS 'Problems of a stored tin, one row each: level, problem (''crack'': a triangle of zero area up to rounding whose corner lies on the opposite edge while the surfaces on the two sides disagree there, a vertical wall; ''sliver'': the same where they agree; ''hole'': an edge without a neighbour inside the domain, a gap between triangles that should meet), triangle id (as in tin_triangles) and a detail. No rows for a sound tin. Tins built by tinmerge 0.2.0 from rasters whose pixel centres do not round exactly (geographic grids, fractional origins) have them: rebuild those (docs/upgrading.md).';
"#,
    name = "tin_validate_sql",
    requires = [tin_validate]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
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
    if let Some((srid, rows)) = small_level(&t, level) {
        return TableIterator::new(rows.into_iter().enumerate().map(move |(i, (p, c))| {
            (
                i as i32,
                (p != NONE).then_some(p as i32),
                ewkb::Writer::triangle_polygon(srid, &c),
            )
        }));
    }
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    let n = tin.levels[l].num_domain();
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

extension_sql!(
    r#"
ALTER FUNCTION _tin_triangles(tin, int) ROWS 10000;
COMMENT ON FUNCTION _tin_triangles(tin, int) IS 'Internal: use tin_triangles(tin, int).';
"#,
    name = "tin_triangles_sql",
    requires = [_tin_triangles]
);

#[pg_extern(immutable, parallel_safe, cost = 10000, requires = ["tin_type"])]
fn _tin_as_geometry(t: Option<TinArg>, level: default!(Option<i32>, "NULL")) -> Option<Vec<u8>> {
    let t = t?;
    if let Some((srid, rows)) = small_level(&t, level) {
        return Some(ewkb::Writer::tin(srid, rows.into_iter().map(|(_, c)| c)));
    }
    let tin = t.tin();
    let l = tin.level_index(level).or_raise();
    let n = tin.levels[l].num_domain() as u32;
    Some(ewkb::Writer::tin(
        tin.srid,
        (0..n).map(|i| tin.corners(l, i)),
    ))
}

extension_sql!(
    r#"
COMMENT ON FUNCTION _tin_as_geometry(tin, int) IS 'Internal: use tin_as_geometry(tin, int).';
"#,
    name = "tin_as_geometry_sql",
    requires = [_tin_as_geometry]
);
