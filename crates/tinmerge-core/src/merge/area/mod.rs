//! Area merge (Scarlatos §6.5): the triangles of a level on and inside a polygon,
//! found by the hierarchical polygonal sweep.
//!
//! 1. The boundary: the rings are walked once, at the target level, with
//!    the line merge's walker ([`crate::merge::line::Walker`]). A walked
//!    triangle is a *boundary* triangle when a ring segment meets its open
//!    inside (exact separating-axis test, [`segment_meets_open_triangle`](crate::polygon::segment_meets_open_triangle)):
//!    then the polygon covers part of it, not all. The parent of a boundary
//!    triangle is a boundary triangle, so the coarser levels' boundary comes
//!    from parent links; a segment that only runs along the edges of the
//!    fine triangles it touches is tested again against their ancestors
//!    (it may cross a coarse triangle's inside). Every other triangle lies
//!    wholly inside or wholly outside.
//! 2. The sweep at the coarsest level: from the boundary inward, over
//!    triangle adjacency. A triangle that no ring touches has the status of
//!    its neighbour; next to the boundary the status is decided by an exact
//!    point-in-polygon test of a corner ([`Area::locate`]).
//! 3. Down the levels: a triangle wholly inside at a coarse level has all
//!    its descendants inside, so none is visited; one wholly outside has
//!    none in the polygon. Only the children of boundary triangles are
//!    examined at the next level: each is a boundary triangle there, or
//!    wholly inside (reported at this level: the coarsest whose triangle is
//!    inside), or outside.
//!
//! The work is the boundary at each level plus the inside of the coarsest
//! level, instead of every triangle of the target level ([`Method::Scan`])
//! or every triangle inside the polygon at the target level
//! ([`Method::Flat`], the plain sweep without the hierarchy).
//!
//! Coverage (the fraction of a boundary triangle inside the polygon) comes
//! from the boundary pieces in the triangle ([`crate::merge::area::clip`]).
//!
//! Invariants (tests/area.rs on contour bands with holes, multipolygons,
//! random star polygons and grid-aligned degenerate cases, at every level):
//! inside and boundary rows at a level are exactly the triangles whose inside
//! meets the polygon's inside (oracle: brute force with an independent
//! clipper, and PostGIS `ST_Within`/`ST_Intersection`); compact rows expanded
//! through parent links give the full list; the sum of coverage times
//! triangle area is the polygon's area within the domain.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::area::{area_rows, sweep, Method, Relation};
//! use tinmerge_core::merge::area::polygon::Area;
//! // a paraboloid on a 5 x 5 grid: 32 triangles of area 0.5
//! let mut pts = Vec::new();
//! for i in 0..5 { for j in 0..5 { pts.push([i as f64, j as f64, (i * i + j * j) as f64]); } }
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! // a square of side 2 along grid lines, and a strip cutting triangles
//! let sq = Area::new(vec![vec![vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]]]]);
//! let s = sweep(&tin, 0, &sq, Method::Hierarchy, &mut || Ok(())).unwrap();
//! let rows = area_rows(&tin, &sq, &s, false, &mut || Ok(())).unwrap();
//! assert_eq!(rows.len(), 8);
//! assert!(rows.iter().all(|r| r.relation == Relation::Inside && r.coverage == 1.0));
//! let strip = Area::new(vec![vec![vec![[0.0, 0.5], [4.0, 0.5], [4.0, 1.5], [0.0, 1.5]]]]);
//! let s = sweep(&tin, 0, &strip, Method::Hierarchy, &mut || Ok(())).unwrap();
//! let rows = area_rows(&tin, &strip, &s, false, &mut || Ok(())).unwrap();
//! let covered: f64 = rows.iter().map(|r| r.coverage * 0.5).sum();
//! assert!((covered - 4.0).abs() < 1e-12);
//! ```

pub mod clip;
pub use crate::polygon;
mod scratch;
pub mod surface;
mod sweep;
pub mod whole;

pub(crate) use self::sweep::corners2;
pub use self::sweep::{Method, Sweep, sweep};

use crate::geom::tri_area;
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::clip::clipped_moments;
use crate::polygon::Area;
use crate::tin::TinError;
use crate::tin::hierarchy::descendants;
use crate::tin::mesh::Mesh;

/// How a reported triangle relates to the polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    /// Wholly inside (touching the boundary allowed).
    Inside,
    /// Inside in part: the polygon's boundary crosses its inside.
    Boundary,
}

impl Relation {
    pub fn as_str(&self) -> &'static str {
        match self {
            Relation::Inside => "inside",
            Relation::Boundary => "boundary",
        }
    }
}

/// One reported triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaRow {
    pub triangle: u32,
    pub level: usize,
    pub relation: Relation,
    /// Fraction of the triangle's area inside the polygon.
    pub coverage: f64,
}

/// Coverage of each boundary triangle of the sweep, in `boundary` order.
pub(crate) fn coverages<M: Mesh>(tin: &M, area: &Area, s: &Sweep) -> Result<Vec<f64>, TinError>
where
    TinError: From<M::Err>,
{
    let mut out = Vec::with_capacity(s.boundary.len());
    let mut k = 0;
    for &t in &s.boundary {
        let cs = corners2(tin, s.level, t)?;
        let m = clipped_moments(&cs, cs[0], s.chains_of(t, &mut k), &mut |p| area.locate(p));
        out.push((m.a / tri_area(&cs)).clamp(0.0, 1.0));
    }
    Ok(out)
}

/// The rows of `tin_area_triangles`: compact (inside triangles at the
/// coarsest level wholly inside, sorted by level then id) or full (every
/// triangle of the target level, sorted by id).
pub fn area_rows<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    compact: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<AreaRow>, TinError>
where
    TinError: From<M::Err>,
{
    let mut rows = Vec::new();
    let inside_row = |t: u32, level: usize| AreaRow {
        triangle: t,
        level,
        relation: Relation::Inside,
        coverage: 1.0,
    };
    let mut tk = Ticker::new(interrupt);
    for (l, ts) in s.inside.iter().enumerate() {
        if compact || l == s.level {
            rows.extend(ts.iter().map(|&t| inside_row(t, l)));
        } else {
            let mut d = Vec::new();
            for &t in ts {
                tk.tick()?;
                descendants(tin, l, t, s.level, &mut d)?;
            }
            rows.extend(d.into_iter().map(|t| inside_row(t, s.level)));
        }
    }
    for (&t, cov) in s.boundary.iter().zip(coverages(tin, area, s)?) {
        rows.push(AreaRow {
            triangle: t,
            level: s.level,
            relation: Relation::Boundary,
            coverage: cov,
        });
    }
    if compact {
        rows.sort_by_key(|r| (r.level, r.triangle));
    } else {
        rows.sort_by_key(|r| r.triangle);
    }
    Ok(rows)
}
