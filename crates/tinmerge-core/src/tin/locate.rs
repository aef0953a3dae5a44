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

use super::{Level, Tin, NONE};
use crate::geom::vco;
use robust::{orient2d, Coord};

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
pub fn start_triangle(tin: &Tin, level: usize, x: f64, y: f64) -> u32 {
    let g = &tin.levels[level].grid;
    if g.cells.is_empty() {
        return 0;
    }
    // `as u32` truncates (towards zero) and saturates (negative and NaN give
    // 0), which is floor for the non-negative values that matter here; the
    // `min` clamps points right of or above the grid.
    let cx = (((x - tin.bbox.min_x) / g.cell) as u32).min(g.nx - 1);
    let cy = (((y - tin.bbox.min_y) / g.cell) as u32).min(g.ny - 1);
    g.cells[(cy * g.nx + cx) as usize]
}

/// Walk from `start` towards (x, y) at `level`.
pub fn walk(tin: &Tin, level: usize, start: u32, x: f64, y: f64) -> Walk {
    walk_raw(&tin.verts, &tin.levels[level], start, x, y)
}

/// [`walk`] on a level given with its vertex array (used while building).
///
/// Edges are tried in a fixed order (starting after the edge just crossed)
/// for the first steps, which is fastest in practice; if the walk has not
/// arrived after `4 * sqrt(n) + 64` steps (possible in a constrained
/// triangulation, where a deterministic walk may cycle) it continues as a
/// remembering stochastic walk, which terminates; a final step limit falls
/// back to an exhaustive scan.
pub fn walk_raw(verts: &[[f64; 3]], lv: &Level, start: u32, x: f64, y: f64) -> Walk {
    let n = lv.tris.len();
    let p = Coord { x, y };
    let mut t = start;
    let mut came_from = NONE;
    let mut seed: u32 = 0x9e37_79b9 ^ start;
    let fixed_steps = 4 * (n as f64).sqrt() as usize + 64;
    let limit = 2 * n + 64 + fixed_steps;
    for step in 0..limit {
        let tri = lv.tris[t as usize];
        let nbrs = lv.nbrs[t as usize];
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
        for k in 0..3 {
            let j = (r + k) % 3;
            let nb = nbrs[j];
            if nb == came_from && nb != NONE {
                continue;
            }
            let a = vco(&verts[tri[(j + 1) % 3] as usize]);
            let b = vco(&verts[tri[(j + 2) % 3] as usize]);
            if orient2d(a, b, p) < 0.0 {
                if nb == NONE {
                    return Walk::Outside(t);
                }
                came_from = t;
                t = nb;
                crossed = true;
                break;
            }
        }
        if !crossed {
            // The skipped edge (the one we came through) has p on its inner
            // side by construction, so t contains p.
            return Walk::Inside(t);
        }
    }
    brute_force(verts, lv, x, y).map_or(Walk::Outside(t), Walk::Inside)
}

/// Whether the closed triangle `t` contains (x, y).
#[inline]
pub fn contains(tin: &Tin, level: usize, t: u32, x: f64, y: f64) -> bool {
    contains_raw(&tin.verts, &tin.levels[level], t, x, y)
}

#[inline]
fn contains_raw(verts: &[[f64; 3]], lv: &Level, t: u32, x: f64, y: f64) -> bool {
    let tri = lv.tris[t as usize];
    let p = Coord { x, y };
    (0..3).all(|j| {
        orient2d(
            vco(&verts[tri[j] as usize]),
            vco(&verts[tri[(j + 1) % 3] as usize]),
            p,
        ) >= 0.0
    })
}

fn brute_force(verts: &[[f64; 3]], lv: &Level, x: f64, y: f64) -> Option<u32> {
    (0..lv.tris.len() as u32).find(|&t| contains_raw(verts, lv, t, x, y))
}

/// The neighbours of triangle `u` across its edges passing through `p`
/// (NONE for the others).
#[inline]
fn across_edges_through(tin: &Tin, lv: &Level, u: u32, p: Coord<f64>) -> [u32; 3] {
    let tri = lv.tris[u as usize];
    let mut out = [NONE; 3];
    for j in 0..3 {
        let a = vco(&tin.verts[tri[(j + 1) % 3] as usize]);
        let b = vco(&tin.verts[tri[(j + 2) % 3] as usize]);
        if orient2d(a, b, p) == 0.0 {
            out[j] = lv.nbrs[u as usize][j];
        }
    }
    out
}

/// Among the closed triangles containing (x, y), the smallest id, found by
/// visiting the triangles across edges that pass through the point.
pub fn canonical(tin: &Tin, level: usize, t: u32, x: f64, y: f64) -> u32 {
    let lv = &tin.levels[level];
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
        for nb in across_edges_through(tin, lv, u, p) {
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
            for nb in across_edges_through(tin, lv, u, p) {
                if nb != NONE && !seen.contains(&nb) {
                    seen.push(nb);
                    stack.push(nb);
                }
            }
        }
    }
    best
}

/// Triangle at `level` containing (x, y), or None outside the domain or for
/// non-finite coordinates.
pub fn locate(tin: &Tin, level: usize, x: f64, y: f64) -> Option<u32> {
    if !(x.is_finite() && y.is_finite()) {
        return None;
    }
    let b = &tin.bbox;
    if x < b.min_x || x > b.max_x || y < b.min_y || y > b.max_y {
        return None;
    }
    let s = start_triangle(tin, level, x, y);
    match walk(tin, level, s, x, y) {
        Walk::Inside(t) => Some(canonical(tin, level, t, x, y)),
        Walk::Outside(_) => None,
    }
}
