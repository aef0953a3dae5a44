//! Point location: grid cell in O(1), then a walk over neighbours decided by
//! exact orientation tests (`robust::orient2d`).
//!
//! The walk is a visibility walk (Devillers, Pion & Teillaud, *Walking in a
//! triangulation*): at each triangle, test the edges (skipping the edge just
//! crossed) and cross the first one with the point strictly on its outer
//! side. Edges are tried in a fixed order first, then, if the walk runs
//! long, in a pseudo-random order (the "remembering stochastic walk", which
//! terminates on any triangulation, Delaunay or not); a step limit with a
//! brute-force fallback guards values whose structure is valid but
//! geometrically unusual.
//!
//! Points on an edge or vertex belong to several closed triangles; the result
//! is always the smallest triangle id among them, so it does not depend on
//! the path of the walk.

//!
//! Every function is written once, over [`Mesh`]/[`Indexed`]: the same walk
//! runs on a decoded [`Tin`] (the `*_in` functions with `Err = Infallible`,
//! wrapped by [`locate`], [`walk`], ...) and on a stored value read block by
//! block ([`super::sliced`]).

use super::mesh::{Indexed, LevelRef, Mesh, infallible};
use super::{Level, NONE, Tin};
use crate::geom::{bbox2, point_segment_nearest, vco, xy};
use robust::{Coord, orient2d};

/// Outcome of a walk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// The closed triangle contains the point.
    Inside(u32),
    /// The point is outside the (convex) domain; the last triangle visited,
    /// on the hull, is the nearest the walk got.
    Outside(u32),
}

/// Grid-index start triangle for (x, y) at `level`.
#[inline]
pub fn start_in<M: Indexed>(m: &M, level: usize, x: f64, y: f64) -> Result<u32, M::Err> {
    let (cell, nx, ny) = m.grid(level);
    if nx == 0 || ny == 0 {
        return Ok(0);
    }
    let b = m.bbox();
    // `as u32` truncates (towards zero) and saturates (negative and NaN give
    // 0), which is floor for the non-negative values that matter here; the
    // `min` clamps points right of or above the grid.
    let cx = (((x - b.min_x) / cell) as u32).min(nx - 1);
    let cy = (((y - b.min_y) / cell) as u32).min(ny - 1);
    m.cell(level, cy * nx + cx)
}

/// [`start_in`] on a decoded tin.
#[inline]
pub fn start_triangle(tin: &Tin, level: usize, x: f64, y: f64) -> u32 {
    infallible(start_in(tin, level, x, y))
}

/// Walk from `start` towards (x, y) at `level`.
pub fn walk(tin: &Tin, level: usize, start: u32, x: f64, y: f64) -> Walk {
    infallible(walk_in(tin, level, start, x, y))
}

/// [`walk`] on a level given with its vertex array (used while building).
pub(crate) fn walk_raw(verts: &[[f64; 3]], lv: &Level, start: u32, x: f64, y: f64) -> Walk {
    infallible(walk_in(&LevelRef { verts, level: lv }, 0, start, x, y))
}

/// The walk. Edges are tried in a fixed order (starting after the edge just
/// crossed) for the first steps, which is fastest in practice; if the walk
/// has not arrived after `4 * sqrt(n) + 64` steps (possible in a constrained
/// triangulation, where a deterministic walk may cycle) it continues as a
/// remembering stochastic walk, which terminates; a final step limit falls
/// back to an exhaustive scan.
pub(crate) fn walk_in<M: Mesh>(
    m: &M,
    level: usize,
    start: u32,
    x: f64,
    y: f64,
) -> Result<Walk, M::Err> {
    Ok(walk_strict(m, level, start, x, y)?.0)
}

/// [`walk_in`], and whether an `Inside` triangle holds the point in its
/// interior (no edge through it: the triangle is the only one holding it,
/// so [`canonical_in`] has nothing to do). False when unknown (the walk
/// fell back on a scan).
fn walk_strict<M: Mesh>(
    m: &M,
    level: usize,
    start: u32,
    x: f64,
    y: f64,
) -> Result<(Walk, bool), M::Err> {
    let n = m.num_triangles(level);
    let p = Coord { x, y };
    let mut t = start;
    let mut came_from = NONE;
    let mut seed: u32 = 0x9e37_79b9 ^ start;
    let fixed_steps = 4 * (n as f64).sqrt() as usize + 64;
    let limit = 2 * n + 64 + fixed_steps;
    for step in 0..limit {
        let tri = m.tri(level, t)?;
        let nbrs = m.nbrs(level, t)?;
        let r = if step < fixed_steps {
            // start with the edge after the one we came through
            match nbrs.iter().position(|&b| b == came_from && b != NONE) {
                Some(j) => j + 1,
                None => 0,
            }
        } else {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed % 3) as usize
        };
        let mut crossed = false;
        let mut strict = true;
        for k in 0..3 {
            let j = (r + k) % 3;
            let nb = nbrs[j];
            if nb == came_from && nb != NONE {
                continue;
            }
            let a = vco(&m.vert(tri[(j + 1) % 3])?);
            let b = vco(&m.vert(tri[(j + 2) % 3])?);
            let o = orient2d(a, b, p);
            if o < 0.0 {
                if nb == NONE {
                    return Ok((Walk::Outside(t), false));
                }
                came_from = t;
                t = nb;
                crossed = true;
                break;
            }
            strict &= o > 0.0;
        }
        if !crossed {
            // The skipped edge (the one we came through) has p strictly on
            // its inner side (the walk crossed it because p was strictly
            // outside it seen from the other triangle), so t contains p,
            // in its interior when the edges tested have p strictly inside.
            return Ok((Walk::Inside(t), strict));
        }
    }
    let w = brute_force(m, level, x, y)?.map_or(Walk::Outside(t), Walk::Inside);
    Ok((w, false))
}

/// Whether the closed triangle `t` contains (x, y).
#[inline]
pub fn contains(tin: &Tin, level: usize, t: u32, x: f64, y: f64) -> bool {
    infallible(contains_in(tin, level, t, x, y))
}

/// [`contains`] on any mesh.
#[inline]
pub(crate) fn contains_in<M: Mesh>(
    m: &M,
    level: usize,
    t: u32,
    x: f64,
    y: f64,
) -> Result<bool, M::Err> {
    let c = m.corners(level, t)?;
    let p = Coord { x, y };
    Ok((0..3).all(|j| orient2d(vco(&c[j]), vco(&c[(j + 1) % 3]), p) >= 0.0))
}

fn brute_force<M: Mesh>(m: &M, level: usize, x: f64, y: f64) -> Result<Option<u32>, M::Err> {
    for t in 0..m.num_triangles(level) as u32 {
        if contains_in(m, level, t, x, y)? {
            return Ok(Some(t));
        }
    }
    Ok(None)
}

/// The neighbours of triangle `u` across its edges passing through `p`
/// (NONE for the others).
#[inline]
fn across_edges_through<M: Mesh>(
    m: &M,
    level: usize,
    u: u32,
    p: Coord<f64>,
) -> Result<[u32; 3], M::Err> {
    let c = m.corners(level, u)?;
    let nbrs = m.nbrs(level, u)?;
    let mut out = [NONE; 3];
    for j in 0..3 {
        if orient2d(vco(&c[(j + 1) % 3]), vco(&c[(j + 2) % 3]), p) == 0.0 {
            out[j] = nbrs[j];
        }
    }
    Ok(out)
}

/// Among the closed triangles containing (x, y), the smallest id, found by
/// visiting the triangles across edges that pass through the point.
pub fn canonical(tin: &Tin, level: usize, t: u32, x: f64, y: f64) -> u32 {
    infallible(canonical_in(tin, level, t, x, y))
}

/// [`canonical`] on any mesh.
pub(crate) fn canonical_in<M: Mesh>(
    m: &M,
    level: usize,
    t: u32,
    x: f64,
    y: f64,
) -> Result<u32, M::Err> {
    let p = Coord { x, y };
    let mut best = t;
    // fixed lists first (no allocation on the common path)
    let mut stack = [NONE; 16];
    let mut seen = [NONE; 16];
    let (mut sp, mut ns) = (1usize, 1usize);
    stack[0] = t;
    seen[0] = t;
    while sp > 0 {
        sp -= 1;
        let u = stack[sp];
        best = best.min(u);
        for nb in across_edges_through(m, level, u, p)? {
            if nb != NONE && !seen[..ns].contains(&nb) && ns < seen.len() && sp < stack.len() {
                seen[ns] = nb;
                ns += 1;
                stack[sp] = nb;
                sp += 1;
            }
        }
    }
    if ns == seen.len() {
        // A vertex with more than 15 incident triangles: the same search
        // with unbounded lists (rare; still exact, and local to the fan).
        let mut stack = vec![t];
        let mut seen = vec![t];
        while let Some(u) = stack.pop() {
            best = best.min(u);
            for nb in across_edges_through(m, level, u, p)? {
                if nb != NONE && !seen.contains(&nb) {
                    seen.push(nb);
                    stack.push(nb);
                }
            }
        }
    }
    Ok(best)
}

/// Triangle at `level` containing (x, y), or None outside the domain (off
/// the hull, or on a void triangle: [`super::Level::num_void`]) or for
/// non-finite coordinates. A point on the domain's boundary is in it: the
/// smallest id wins on shared edges, and the void triangles are the last.
pub fn locate(tin: &Tin, level: usize, x: f64, y: f64) -> Option<u32> {
    infallible(locate_in(tin, level, x, y))
}

/// [`locate`] on any indexed mesh.
pub fn locate_in<M: Indexed>(m: &M, level: usize, x: f64, y: f64) -> Result<Option<u32>, M::Err> {
    Ok(locate_hull_in(m, level, x, y)?.filter(|&t| !m.is_void(level, t)))
}

/// How far off a domain's hull [`locate_near_in`] still finds a point, in
/// units in the last place of its larger coordinate.
pub const NEAR_ULPS: f64 = 16.0;

/// [`locate_in`], and for a point off the domain by at most [`NEAR_ULPS`]
/// units in the last place of its larger coordinate, a triangle holding
/// the nearest point of the domain, with that point: `Some((t, qx, qy))`.
/// The same pixel centre computed from two origins differs by about that
/// much: PostGIS's `ST_PixelAsCentroids` of a raster tile starts from the
/// tile's own upper-left corner, a tiled tin from its table's top-left
/// tile, and a centre on the edge of the data can lie an ulp outside the
/// tin's hull. Farther off, or on a void triangle, None.
///
/// ```
/// use tinmerge_core::tin::build::build;
/// use tinmerge_core::tin::locate::{locate, locate_near_in};
/// let tin = build(vec![[0.0, 0.0, 0.0], [760863.208229844, 0.0, 1.0], [0.0, 10.0, 2.0]],
///                 &[0.0], 0, &mut || Ok(())).unwrap();
/// let x = f64::from_bits(760863.208229844_f64.to_bits() + 1); // one ulp east of the corner
/// assert_eq!(locate(&tin, 0, x, 0.0), None);
/// let (t, qx, _) = locate_near_in(&tin, 0, x, 0.0).unwrap().unwrap();
/// assert_eq!((t, qx), (0, 760863.208229844));
/// assert_eq!(locate_near_in(&tin, 0, 760863.21, 0.0).unwrap(), None); // 2 mm off: off
/// ```
pub fn locate_near_in<M: Indexed>(
    m: &M,
    level: usize,
    x: f64,
    y: f64,
) -> Result<Option<(u32, f64, f64)>, M::Err> {
    if let Some(t) = locate_in(m, level, x, y)? {
        return Ok(Some((t, x, y)));
    }
    if !(x.is_finite() && y.is_finite()) {
        return Ok(None);
    }
    let eps = NEAR_ULPS * f64::EPSILON * x.abs().max(y.abs());
    let b = m.bbox();
    if x < b.min_x - eps || x > b.max_x + eps || y < b.min_y - eps || y > b.max_y + eps {
        return Ok(None);
    }
    // into the box first (a point beside a side of the box), then onto the
    // hull edge the walk stops at
    let (cx, cy) = (x.clamp(b.min_x, b.max_x), y.clamp(b.min_y, b.max_y));
    let s = start_in(m, level, cx, cy)?;
    let (t, q) = match walk_strict(m, level, s, cx, cy)?.0 {
        Walk::Inside(t) => (t, [cx, cy]),
        Walk::Outside(t) => {
            let c = m.corners(level, t)?;
            let nbrs = m.nbrs(level, t)?;
            let mut best: Option<(f64, [f64; 2])> = None;
            for j in 0..3 {
                if nbrs[j] != NONE {
                    continue;
                }
                let (a, e) = (xy(&c[(j + 1) % 3]), xy(&c[(j + 2) % 3]));
                let (d, f) = point_segment_nearest([x, y], a, e);
                let q = [a[0] + f * (e[0] - a[0]), a[1] + f * (e[1] - a[1])];
                if best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, q));
                }
            }
            match best {
                Some((d, q)) if d <= eps => (t, q),
                _ => return Ok(None),
            }
        }
    };
    Ok((!m.is_void(level, t)).then_some((t, q[0], q[1])))
}

/// [`locate_hull_in`] on a decoded tin.
pub(crate) fn locate_hull(tin: &Tin, level: usize, x: f64, y: f64) -> Option<u32> {
    infallible(locate_hull_in(tin, level, x, y))
}

/// [`locate_in`] over the whole triangulation, void triangles included
/// (what a walk starts from): None only off the convex hull.
pub fn locate_hull_in<M: Indexed>(
    m: &M,
    level: usize,
    x: f64,
    y: f64,
) -> Result<Option<u32>, M::Err> {
    if !(x.is_finite() && y.is_finite()) {
        return Ok(None);
    }
    let b = m.bbox();
    if x < b.min_x || x > b.max_x || y < b.min_y || y > b.max_y {
        return Ok(None);
    }
    let s = start_in(m, level, x, y)?;
    Ok(match walk_strict(m, level, s, x, y)? {
        (Walk::Inside(t), true) => Some(t),
        (Walk::Inside(t), false) => Some(canonical_in(m, level, t, x, y)?),
        (Walk::Outside(t), _) if beside_hull_edge(m, level, t, x, y)? => {
            match near_hull(m, level, t, x, y)? {
                Some(t) => Some(canonical_in(m, level, t, x, y)?),
                None => None,
            }
        }
        (Walk::Outside(_), _) => None,
    })
}

/// The rounding band of the hull's edges: a billionth of the largest
/// coordinate ([`beside_hull_edge`], [`near_hull`]).
fn hull_band<M: Indexed>(m: &M) -> f64 {
    let b = m.bbox();
    1e-9 * [b.min_x, b.max_x, b.min_y, b.max_y]
        .iter()
        .fold(0.0_f64, |a, v| a.max(v.abs()))
}

/// Most triangles [`near_hull`] visits before it scans the level instead.
const NEAR_HULL_VISITS: usize = 4096;

/// A triangle containing (x, y), a point the walk found outside the hull
/// edge of `t` but within rounding of it ([`beside_hull_edge`]), or None:
/// the triangles whose bounding box, widened by `reach`, holds the point,
/// searched across edges from `t`. `reach` is the point's distance to the
/// triangle `t` (plus the rounding band). If a triangle contains the
/// point, the point is in the hull, and so is the segment from the nearest
/// point of `t` (on the hull) to it: the hull is convex up to rounding. The
/// triangles that segment crosses, edge by edge, are within `reach` of the
/// point, and so are their boxes: the search finds the triangle. After
/// [`NEAR_HULL_VISITS`] triangles (a geometrically unusual value) the
/// level is scanned.
fn near_hull<M: Indexed>(
    m: &M,
    level: usize,
    t: u32,
    x: f64,
    y: f64,
) -> Result<Option<u32>, M::Err> {
    let bbox =
        |u: u32| -> Result<[f64; 4], M::Err> { Ok(bbox2(m.corners(level, u)?.iter().map(xy))) };
    let band = hull_band(m);
    let c = m.corners(level, t)?;
    let reach = (0..3).fold(f64::INFINITY, |r, j| {
        let (a, e) = (xy(&c[j]), xy(&c[(j + 1) % 3]));
        r.min(point_segment_nearest([x, y], a, e).0)
    }) + 2.0 * band;
    let near = |e: [f64; 4]| {
        x >= e[0] - reach && x <= e[2] + reach && y >= e[1] - reach && y <= e[3] + reach
    };
    let mut seen = vec![t];
    let mut stack = vec![t];
    while let Some(u) = stack.pop() {
        if contains_in(m, level, u, x, y)? {
            return Ok(Some(u));
        }
        for nb in m.nbrs(level, u)? {
            if nb != NONE && !seen.contains(&nb) && near(bbox(nb)?) {
                if seen.len() >= NEAR_HULL_VISITS {
                    return brute_force(m, level, x, y);
                }
                seen.push(nb);
                stack.push(nb);
            }
        }
    }
    Ok(None)
}

/// Whether (x, y), outside a hull edge of `t`, is within rounding of that
/// edge's line (a billionth of the largest coordinate). The hull of a
/// scattered build is convex only up to rounding (a sample a rounding
/// inside a hull edge becomes a boundary vertex, the sliver it made
/// dropped: `Builder::snapshot` in the build), so the line of a hull edge
/// next to such a vertex can pass a rounding outside points of the domain
/// and the walk's "outside" is not proof there: [`locate_hull_in`] then
/// searches the triangles around ([`near_hull`]).
fn beside_hull_edge<M: Indexed>(
    m: &M,
    level: usize,
    t: u32,
    x: f64,
    y: f64,
) -> Result<bool, M::Err> {
    let band = hull_band(m);
    let c = m.corners(level, t)?;
    let nbrs = m.nbrs(level, t)?;
    let p = Coord { x, y };
    Ok((0..3).any(|j| {
        let (a, e) = (c[(j + 1) % 3], c[(j + 2) % 3]);
        let o = orient2d(vco(&a), vco(&e), p);
        nbrs[j] == NONE && o < 0.0 && -o <= band * (e[0] - a[0]).hypot(e[1] - a[1])
    }))
}
