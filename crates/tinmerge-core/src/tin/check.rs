//! Invariant checkers.
//!
//! [`validate_structure`] is what every value read from disk or the wire must
//! pass before any algorithm touches it: it is linear in the value's size and
//! guarantees that no index is out of range, links are symmetric, triangles
//! are counter-clockwise and children lie in their parents, so no later walk
//! can index out of bounds or loop forever.
//!
//! [`Tin::sanity_check`] adds the geometric properties of the hierarchy that
//! tests check on real data: each level tiles one convex domain, children tile
//! their parent (so coarse edges persist), and triangles are constrained
//! Delaunay (edges inside a parent are locally Delaunay). These are exact in
//! the frame the build decided topology in: world coordinates for point
//! builds, the pixel lattice for raster builds (check a raster build's
//! lattice-frame tin, before [`super::lattice::Lattice::to_world`]); in
//! world coordinates a raster build is convex and nested up to rounding.
//!
//! [`problems`] finds what must never be in a tin and what tinmerge 0.2.0
//! could store: slivers, triangles of zero area up to rounding, each hiding
//! a crack (its corner lies on the opposite edge, so the surface on the
//! two sides of that edge disagrees).

use super::{MAX_LEVELS, NONE, Tin, TinError, par};
use crate::geom::{BEND, vco};
use crate::interrupt::Interrupt;
use robust::{incircle, orient2d};

fn bad(msg: String) -> TinError {
    TinError::Corrupt(msg)
}

/// Cheap structural validation (see module docs).
pub fn validate_structure(tin: &Tin) -> Result<(), TinError> {
    validate_structure_checked(tin, &mut || Ok(()))
}

/// Triangles checked as one piece of work (`interrupt` is called before
/// every 4 per thread).
const CHECK_RUN: usize = 4096;

/// [`validate_structure`] calling `interrupt` between levels and every
/// 16384 triangles per thread (a stored value of 15 MB takes about 20 ms),
/// checking triangles on `tinmerge.threads` ([`par`]). Its phases, per
/// level after the vertices: the level's counts and bounds, its triangles
/// and neighbour links, its parents and child offsets, its grid index.
pub(crate) fn validate_structure_checked(
    tin: &Tin,
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    validate_levels(tin, true, interrupt)
}

/// [`validate_structure_checked`], the grid indexes checked only when
/// `grids` (a build on a lattice has none until `Lattice::to_world`).
fn validate_levels(tin: &Tin, grids: bool, interrupt: &mut Interrupt<'_>) -> Result<(), TinError> {
    let nl = tin.levels.len();
    if nl == 0 || nl > MAX_LEVELS {
        return Err(bad(format!(
            "number of levels {nl} is not in 1..{MAX_LEVELS}"
        )));
    }
    check_vertices(tin)?;
    interrupt()?;
    let mut prev_nv = 0u32;
    let mut prev_tol = f64::INFINITY;
    for l in 0..nl {
        check_level_counts(tin, l, prev_nv, prev_tol)?;
        let lv = &tin.levels[l];
        (prev_nv, prev_tol) = (lv.num_vertices, lv.tolerance);
        // triangles, then parents, in runs checked on `tinmerge.threads`
        // (the first error in triangle order is the one reported)
        let nt = lv.tris.len();
        let runs: Vec<std::ops::Range<usize>> = (0..nt)
            .step_by(CHECK_RUN)
            .map(|a| a..(a + CHECK_RUN).min(nt))
            .collect();
        par::map_batched(
            &runs,
            |r| r.clone().try_for_each(|t| check_triangle(tin, l, t)),
            interrupt,
            &mut |r| r,
        )?;
        check_parents(tin, l, &runs, interrupt)?;
        if l + 1 == nl && !lv.child_start.is_empty() {
            return Err(bad("finest level must have no children".into()));
        }
        if grids {
            check_grid(tin, l)?;
        }
    }
    if prev_nv as usize != tin.verts.len() {
        return Err(bad("the finest level must use every vertex".into()));
    }
    Ok(())
}

/// What every build checks of the value it made before it returns it (the
/// frame it decided topology in: the pixel lattice for a raster build on
/// it, world coordinates otherwise), so that no build ever hands out a
/// crack (issue 73): the structure ([`validate_structure`]: indices,
/// mirrored neighbour links, counter-clockwise triangles of positive area,
/// every triangle inside its parent); at every level, every edge shared
/// by exactly two triangles with the same two vertices, but for one
/// outer boundary cycle (no `"hole"` of [`problems`]: two vertices a
/// rounding apart where there should be one, a T-junction); no triangle
/// of zero area up to rounding ([`crate::geom::is_sliver`]: a hidden
/// T-junction); the children of every triangle tiling it. Linear in the
/// value (on `tinmerge.threads` for the structure; its levels reported
/// as a phase's progress, [`crate::progress::step`]). A failure is a bug of
/// the build: [`TinError::Internal`], naming the level, triangle and what
/// failed.
pub fn verify_built(tin: &Tin, grids: bool, interrupt: &mut Interrupt<'_>) -> Result<(), TinError> {
    let internal =
        |what: &str, e: String| TinError::Internal(format!("the build made {what}: {e}"));
    validate_levels(tin, grids, interrupt).map_err(|e| {
        internal(
            "a value that fails its own structural checks",
            e.to_string(),
        )
    })?;
    let n = tin.levels.len() as u64;
    for l in 0..tin.levels.len() {
        crate::progress::step("checking the levels", "levels", l as u64, n);
        interrupt()?;
        let mut found = Vec::new();
        holes(tin, l, &mut found);
        if let Some(p) = found.first() {
            return Err(internal(
                "a crack",
                format!("level {l}, triangle {}: {}", p.triangle, p.detail),
            ));
        }
        for (t, tri) in tin.levels[l].tris.iter().enumerate() {
            let c = tri.map(|v| tin.verts[v as usize]);
            if crate::geom::is_sliver(&c[0], &c[1], &c[2]) {
                return Err(internal(
                    "a triangle of zero area",
                    format!(
                        "level {l}, triangle {t} (vertices {} {} {})",
                        tri[0], tri[1], tri[2]
                    ),
                ));
            }
        }
        if l + 1 < tin.levels.len() {
            tin.check_children_tile(l)
                .map_err(|e| internal("a level not nested in the one before", e.to_string()))?;
        }
    }
    crate::progress::step("checking the levels", "levels", n, n);
    Ok(())
}

/// At least three vertices, every coordinate finite and in range, and the
/// bounding box theirs.
fn check_vertices(tin: &Tin) -> Result<(), TinError> {
    let nv = tin.verts.len();
    if nv < 3 {
        return Err(bad(format!("{nv} vertices, at least 3 needed")));
    }
    for (i, v) in tin.verts.iter().enumerate() {
        if !v[2].is_finite() || super::check_xy("", v[0], v[1]).is_err() {
            return Err(bad(format!(
                "vertex {i} has a non-finite or out-of-range coordinate"
            )));
        }
    }
    if super::Bbox::of(&tin.verts) != tin.bbox {
        return Err(bad("bounding box does not match the vertices".into()));
    }
    Ok(())
}

/// Level `l`'s tolerance (below the previous level's `prev_tol`), its
/// max error, its vertex count (at least the previous level's `prev_nv`)
/// and its arrays' lengths.
fn check_level_counts(tin: &Tin, l: usize, prev_nv: u32, prev_tol: f64) -> Result<(), TinError> {
    let lv = &tin.levels[l];
    let nv = tin.verts.len();
    if !(lv.tolerance.is_finite() && lv.tolerance >= 0.0 && lv.tolerance < prev_tol) {
        return Err(bad(format!(
            "level {l}: tolerance {} is not finite, >= 0 and below the previous level's",
            lv.tolerance
        )));
    }
    if !(lv.max_error.is_finite() && lv.max_error >= 0.0) {
        return Err(bad(format!(
            "level {l}: max error {} is invalid",
            lv.max_error
        )));
    }
    if lv.num_vertices < prev_nv.max(3) || lv.num_vertices as usize > nv {
        return Err(bad(format!(
            "level {l}: vertex count {} is not in {}..={nv}",
            lv.num_vertices,
            prev_nv.max(3)
        )));
    }
    let nt = lv.tris.len();
    if nt == 0 || lv.nbrs.len() != nt || lv.parent.len() != nt {
        return Err(bad(format!("level {l}: inconsistent triangle arrays")));
    }
    if lv.num_void as usize > nt {
        return Err(bad(format!(
            "level {l}: {} void triangles of {nt}",
            lv.num_void
        )));
    }
    Ok(())
}

/// Triangle `t` of level `l`: its vertices in range, counter-clockwise
/// with positive area (exactly), and each neighbour link mirrored along
/// the shared edge.
fn check_triangle(tin: &Tin, l: usize, t: usize) -> Result<(), TinError> {
    let lv = &tin.levels[l];
    let nt = lv.tris.len();
    let tri = lv.tris[t];
    if tri.iter().any(|&v| v >= lv.num_vertices) {
        return Err(bad(format!(
            "level {l}: triangle {t} has a vertex index out of range"
        )));
    }
    let o = orient2d(
        vco(&tin.verts[tri[0] as usize]),
        vco(&tin.verts[tri[1] as usize]),
        vco(&tin.verts[tri[2] as usize]),
    );
    if o <= 0.0 {
        return Err(bad(format!(
            "level {l}: triangle {t} is not counter-clockwise with positive area"
        )));
    }
    for j in 0..3 {
        let nb = lv.nbrs[t][j];
        if nb == NONE {
            continue;
        }
        if nb as usize >= nt || nb as usize == t {
            return Err(bad(format!(
                "level {l}: triangle {t} has an invalid neighbour {nb}"
            )));
        }
        let (a, bb) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
        let other = lv.tris[nb as usize];
        let back = (0..3).find(|&k| lv.nbrs[nb as usize][k] == t as u32);
        match back {
            Some(k) if other[(k + 1) % 3] == bb && other[(k + 2) % 3] == a => {}
            _ => {
                return Err(bad(format!(
                    "level {l}: neighbour link {t} -> {nb} is not mirrored along the shared edge"
                )));
            }
        }
    }
    Ok(())
}

/// Level `l`'s parents: none at level 0; otherwise in range, sorted, void
/// exactly when the parent is, each triangle inside its parent (up to
/// rounding, [`BEND`]), and the coarser level's child offsets those of the
/// parents.
fn check_parents(
    tin: &Tin,
    l: usize,
    runs: &[std::ops::Range<usize>],
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let lv = &tin.levels[l];
    if l == 0 {
        if lv.parent.iter().any(|&p| p != NONE) {
            return Err(bad("level 0 triangles must have no parent".into()));
        }
        return Ok(());
    }
    let pl = &tin.levels[l - 1];
    let check_parent = |t: usize| -> Result<(), TinError> {
        let p = lv.parent[t];
        let last = if t == 0 { 0 } else { lv.parent[t - 1] };
        if p as usize >= pl.tris.len() || p < last {
            return Err(bad(format!(
                "level {l}: triangle {t} has parent {p}, out of range or not sorted"
            )));
        }
        if pl.is_void(p) != lv.is_void(t as u32) {
            return Err(bad(format!(
                "level {l}: triangle {t} is void and its parent {p} is not, or the other way round"
            )));
        }
        let pt = pl.tris[p as usize].map(|v| tin.verts[v as usize]);
        for &v in &lv.tris[t] {
            let q = &tin.verts[v as usize];
            for j in 0..3 {
                // up to rounding: a vertex on a parent's edge in the
                // frame the build decided topology in (the pixel
                // lattice) may lie a hair beside it in world
                // coordinates, a sample a few roundings ([`BEND`])
                let (a, b) = (&pt[j], &pt[(j + 1) % 3]);
                if !crate::geom::left_or_within_roundings(a, b, q, BEND) {
                    return Err(bad(format!(
                        "level {l}: triangle {t} is not inside its parent {p}"
                    )));
                }
            }
        }
        Ok(())
    };
    par::map_batched(
        runs,
        |r| r.clone().try_for_each(check_parent),
        interrupt,
        &mut |r| r,
    )?;
    if pl.child_start.len() != pl.tris.len() + 1
        || pl.child_start != super::hierarchy::child_starts(&lv.parent, pl.tris.len())
    {
        return Err(bad(format!(
            "level {}: child offsets are inconsistent",
            l - 1
        )));
    }
    Ok(())
}

/// Level `l`'s grid index: a finite positive cell, its cells those of its
/// size, each naming a triangle of the level.
fn check_grid(tin: &Tin, l: usize) -> Result<(), TinError> {
    let lv = &tin.levels[l];
    let g = &lv.grid;
    if !(g.cell.is_finite() && g.cell > 0.0)
        || g.nx == 0
        || g.ny == 0
        || (g.nx as u64) * (g.ny as u64) != g.cells.len() as u64
        || g.cells.iter().any(|&c| c as usize >= lv.tris.len())
    {
        return Err(bad(format!("level {l}: invalid grid index")));
    }
    Ok(())
}

/// Twice the signed area of triangle `t` (positive for CCW), and a bound on
/// its rounding error (products of coordinate differences).
fn area2(tin: &Tin, tri: &[u32; 3]) -> (f64, f64) {
    let [a, b, c] = [
        tin.verts[tri[0] as usize],
        tin.verts[tri[1] as usize],
        tin.verts[tri[2] as usize],
    ];
    let (p, q) = ((b[0] - a[0]) * (c[1] - a[1]), (c[0] - a[0]) * (b[1] - a[1]));
    // each coordinate difference is off by at most an ulp of the magnitude
    let mag = crate::geom::max_abs_xy(&a, &b, &c);
    let m = (b[0] - a[0])
        .abs()
        .max((b[1] - a[1]).abs())
        .max((c[0] - a[0]).abs())
        .max((c[1] - a[1]).abs());
    let err = 8.0 * f64::EPSILON * (p.abs() + q.abs() + 4.0 * mag * m);
    (p - q, err)
}

impl Tin {
    /// Check every invariant of the hierarchy (structure, tiling of one convex
    /// domain per level, nesting, persistence of coarse edges, constrained
    /// Delaunay). Meant for tests: O(n log n).
    pub fn sanity_check(&self) -> Result<(), TinError> {
        self.sanity_check_constrained(&|_, _| false)
    }

    /// [`Tin::sanity_check`] for a tin built with constraints: an edge
    /// for which `constraint(a, b)` holds (the test's own knowledge of
    /// where its breaklines run, or of the segments of the surface a build
    /// makes edges of) need not be locally Delaunay.
    pub fn sanity_check_constrained(
        &self,
        constraint: &dyn Fn(&[f64; 3], &[f64; 3]) -> bool,
    ) -> Result<(), TinError> {
        validate_structure(self)?;
        let mut domain_area = None;
        for l in 0..self.levels.len() {
            let poly2 = self.boundary_area2(l)?;
            match domain_area {
                None => domain_area = Some(poly2),
                Some(d) if (d - poly2).abs() <= 1e-9 * d.abs() => {}
                Some(d) => {
                    return Err(bad(format!(
                        "level {l}: domain area {} differs from level 0's {}",
                        poly2 / 2.0,
                        d / 2.0
                    )));
                }
            }
            if l + 1 < self.levels.len() {
                self.check_children_tile(l)?;
            }
            self.check_locally_delaunay(l, constraint)?;
        }
        Ok(())
    }

    /// Level `l`'s boundary: one closed cycle, convex (up to rounding),
    /// enclosing what its triangles cover; twice that area.
    fn boundary_area2(&self, l: usize) -> Result<f64, TinError> {
        let lv = &self.levels[l];
        // boundary: one closed convex cycle
        let mut next = std::collections::HashMap::new();
        for (t, tri) in lv.tris.iter().enumerate() {
            for j in 0..3 {
                if lv.nbrs[t][j] == NONE {
                    let (a, b) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
                    if next.insert(a, b).is_some() {
                        return Err(bad(format!(
                            "level {l}: boundary touches itself at vertex {a}"
                        )));
                    }
                }
            }
        }
        let Some((&start, _)) = next.iter().next() else {
            return Err(bad(format!("level {l}: no boundary")));
        };
        let mut cycle = vec![start];
        let mut cur = start;
        while let Some(&n) = next.get(&cur) {
            if n == start {
                break;
            }
            cycle.push(n);
            cur = n;
            if cycle.len() > next.len() {
                break;
            }
        }
        if cycle.len() != next.len() {
            return Err(bad(format!("level {l}: boundary is not a single cycle")));
        }
        let k = cycle.len();
        let mut poly2 = 0.0;
        for i in 0..k {
            let a = self.verts[cycle[i] as usize];
            let b = self.verts[cycle[(i + 1) % k] as usize];
            let c = self.verts[cycle[(i + 2) % k] as usize];
            if !crate::geom::left_or_on_rounded(&a, &b, &c) {
                return Err(bad(format!(
                    "level {l}: domain is not convex at vertex {}",
                    cycle[(i + 1) % k]
                )));
            }
            poly2 += a[0] * b[1] - b[0] * a[1];
        }
        let tri2: f64 = lv.tris.iter().map(|t| area2(self, t).0).sum();
        if (tri2 - poly2).abs() > 1e-9 * poly2.abs() {
            return Err(bad(format!(
                "level {l}: triangles cover area {} but the boundary encloses {} (overlap or gap)",
                tri2 / 2.0,
                poly2 / 2.0
            )));
        }
        Ok(poly2)
    }

    /// The children of every triangle of level `l` tile it (their areas
    /// sum to its own, up to rounding).
    fn check_children_tile(&self, l: usize) -> Result<(), TinError> {
        let lv = &self.levels[l];
        // children tile their parent
        let cl = &self.levels[l + 1];
        for (p, tri) in lv.tris.iter().enumerate() {
            let (s, e) = (lv.child_start[p] as usize, lv.child_start[p + 1] as usize);
            let (mut sum, mut err) = (0.0, 0.0);
            for t in &cl.tris[s..e] {
                let (a, e) = area2(self, t);
                let c = t.map(|v| self.verts[v as usize]);
                sum += a;
                // a child corner may be a hair outside, up to [`BEND`]
                // roundings (see validate_structure)
                err += e + BEND * crate::geom::orient_slack(&c[0], &c[1], &c[2]);
            }
            let (pa, pe) = area2(self, tri);
            if e == s || (sum - pa).abs() > err + pe + 1e-12 * pa {
                return Err(bad(format!(
                    "level {l}: children of triangle {p} do not tile it (area {} vs {})",
                    sum / 2.0,
                    pa / 2.0
                )));
            }
        }
        Ok(())
    }

    /// Constrained Delaunay: every edge of level `l` inside one parent (at
    /// level 0, every edge but a breakline's, `constraint`) is locally
    /// Delaunay.
    fn check_locally_delaunay(
        &self,
        l: usize,
        constraint: &dyn Fn(&[f64; 3], &[f64; 3]) -> bool,
    ) -> Result<(), TinError> {
        let lv = &self.levels[l];
        // constrained Delaunay: an edge inside one parent is locally Delaunay
        for (t, tri) in lv.tris.iter().enumerate() {
            for j in 0..3 {
                let nb = lv.nbrs[t][j];
                if nb == NONE || (nb as usize) < t {
                    continue;
                }
                if l > 0 && lv.parent[t] != lv.parent[nb as usize] {
                    continue; // on a persisted coarser edge: a constraint
                }
                let (ea, eb) = (
                    self.verts[tri[(j + 1) % 3] as usize],
                    self.verts[tri[(j + 2) % 3] as usize],
                );
                if constraint(&ea, &eb) {
                    continue; // a breakline, a segment of the surface
                }
                let ot = lv.tris[nb as usize];
                let k = (0..3)
                    .find(|&k| lv.nbrs[nb as usize][k] == t as u32)
                    .unwrap_or(0);
                let d = self.verts[ot[k] as usize];
                let [a, b, c] = [
                    self.verts[tri[0] as usize],
                    self.verts[tri[1] as usize],
                    self.verts[tri[2] as usize],
                ];
                if incircle(vco(&a), vco(&b), vco(&c), vco(&d)) > 0.0 {
                    return Err(bad(format!(
                        "level {l}: edge between triangles {t} and {nb} is not locally Delaunay"
                    )));
                }
            }
        }
        Ok(())
    }
}

/// What [`problems`] finds.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub level: usize,
    pub triangle: u32,
    /// `"sliver"` (the corner lies on the opposite edge and the surface
    /// agrees there), `"crack"` (it does not: a vertical wall) or
    /// `"hole"` (an edge without a neighbour inside the domain), or, from
    /// [`over_tolerance`], `"over tolerance"`.
    pub kind: &'static str,
    pub detail: String,
}

/// Every sliver of every level: a triangle with zero area up to rounding
/// ([`crate::geom::is_sliver`]). Its corner opposite the longest edge lies on
/// that edge, which the triangle on the other side has whole: a hidden
/// T-junction. `kind` is `"crack"` when the corner's height differs from
/// the edge's height there (the sliver is a wall), `"sliver"` otherwise;
/// and every gap between triangles that should meet ([`holes`]).
pub fn problems(tin: &Tin, interrupt: &mut Interrupt<'_>) -> Result<Vec<Problem>, TinError> {
    let mut out = Vec::new();
    let zspan = (tin.bbox.max_z - tin.bbox.min_z).abs();
    for (l, lv) in tin.levels.iter().enumerate() {
        for (t, tri) in lv.tris.iter().enumerate() {
            if t % 16384 == 16383 {
                interrupt()?;
            }
            let c = tri.map(|v| tin.verts[v as usize]);
            if !crate::geom::is_sliver(&c[0], &c[1], &c[2]) {
                continue;
            }
            // the longest edge (j+1, j+2) and its opposite corner j
            let len = |j: usize| {
                let (p, q) = (&c[(j + 1) % 3], &c[(j + 2) % 3]);
                (p[0] - q[0]).hypot(p[1] - q[1])
            };
            let j = (0..3)
                .max_by(|&a, &b| len(a).total_cmp(&len(b)))
                .unwrap_or(0);
            let (p, q, v) = (&c[(j + 1) % 3], &c[(j + 2) % 3], &c[j]);
            let d = len(j);
            let s = if d > 0.0 {
                ((v[0] - p[0]) * (q[0] - p[0]) + (v[1] - p[1]) * (q[1] - p[1])) / (d * d)
            } else {
                0.0
            };
            let wall = (v[2] - (p[2] + s.clamp(0.0, 1.0) * (q[2] - p[2]))).abs();
            let crack = wall > 1e-9 * zspan.max(1.0);
            out.push(Problem {
                level: l,
                triangle: t as u32,
                kind: if crack { "crack" } else { "sliver" },
                detail: format!(
                    "vertex {} lies on edge {}-{} up to rounding ({:.3e} from it, edge {:.6} long); \
                     the surface jumps {:.6} there",
                    tri[j],
                    tri[(j + 1) % 3],
                    tri[(j + 2) % 3],
                    crate::geom::orient(&c[0], &c[1], &c[2]).abs() / d.max(f64::MIN_POSITIVE),
                    d,
                    wall
                ),
            });
        }
        holes(tin, l, &mut out);
    }
    Ok(out)
}

/// The `"hole"` problems of level `l`: edges without a neighbour that are
/// not on the domain's outer boundary. A level's triangles on the outside
/// have an edge without a neighbour each, and those edges make one cycle;
/// any other cycle (or a vertex where two such edges start) is a gap
/// between triangles that should meet: two vertices a few ulps apart where
/// there should be one, for example, which no sliver shows (its two sides
/// simply do not share vertices). Each triangle on such an edge is
/// reported once.
fn holes(tin: &Tin, l: usize, out: &mut Vec<Problem>) {
    let lv = &tin.levels[l];
    let mut next: std::collections::HashMap<u32, (u32, u32)> = Default::default();
    let mut bad: Vec<(u32, String)> = Vec::new();
    for (t, tri) in lv.tris.iter().enumerate() {
        for j in 0..3 {
            if lv.nbrs[t][j] == NONE {
                let (a, b) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
                if let Some((_, t0)) = next.insert(a, (b, t as u32)) {
                    let why = format!("two edges without a neighbour start at vertex {a}");
                    bad.push((t0, why.clone()));
                    bad.push((t as u32, why));
                }
            }
        }
    }
    // the cycles of those edges, by signed area; the largest is the outside
    let mut seen: std::collections::HashSet<u32> = Default::default();
    let mut cycles: Vec<(f64, Vec<u32>)> = Vec::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    for s in starts {
        if seen.contains(&s) {
            continue;
        }
        let (mut cur, mut area, mut tris) = (s, 0.0, Vec::new());
        while seen.insert(cur) {
            let Some(&(n, t)) = next.get(&cur) else { break };
            let (a, b) = (tin.verts[cur as usize], tin.verts[n as usize]);
            area += a[0] * b[1] - b[0] * a[1];
            tris.push(t);
            cur = n;
        }
        cycles.push((area, tris));
    }
    let outer = cycles
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.0.total_cmp(&y.1.0))
        .map(|(i, _)| i);
    for (i, (area, tris)) in cycles.iter().enumerate() {
        if Some(i) != outer {
            for &t in tris {
                bad.push((
                    t,
                    format!(
                        "an edge without a neighbour inside the domain (a gap of {} edges, area {:.3e})",
                        tris.len(),
                        -area / 2.0
                    ),
                ));
            }
        }
    }
    bad.sort_by_key(|b| b.0);
    bad.dedup_by_key(|b| b.0);
    for (t, detail) in bad {
        out.push(Problem {
            level: l,
            triangle: t,
            kind: "hole",
            detail,
        });
    }
}

// the problems are each produced by a hand-made value in
// tests/validate.rs (and read through tin_validate by pg_regress
// validate_problems.sql)

/// Every level of `tin` that is further from a raster's surface than its
/// tolerance, one [`Problem`] (`"over tolerance"`) each, at its worst
/// place. The surface is the raster's (`heights` on `lat`, NaN without
/// data): its value at each valid pixel centre and, between them, on every
/// grid segment joining two valid pixel centres the straight line between
/// them (what `gdal_contour` and bilinear sampling use). A level is linear
/// in each triangle, so on those segments its error is largest at a pixel
/// centre or where an edge crosses one ([`super::surface`]): both are
/// measured, the error bound on the grid lines is exact. A level is over
/// when one of them is over its tolerance by more than rounding (1e-9 of
/// the tolerance or of the tin's height range). Values built before the
/// build measured between samples (tinmerge 0.10.0 and earlier, and tiles
/// still) are within tolerance at the samples only, and show here.
/// `hard`: the segments of the hard breaklines the tin was built with
/// (world coordinates); the grid segments they cut hold the lines' own
/// heights, not the raster's, and are left out
/// ([`super::surface::GridReference::cut_by`]), as the build leaves them.
pub fn over_tolerance(
    tin: &Tin,
    heights: &super::dense::Dense,
    lat: &super::lattice::Lattice,
    hard: &[([f64; 2], [f64; 2])],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Problem>, TinError> {
    use super::surface::{GridReference, Reference};
    let reference = GridReference::in_world(heights, *lat).cut_by(hard);
    let zspan = (tin.bbox.max_z - tin.bbox.min_z).abs();
    let mut out = Vec::new();
    for (l, lv) in tin.levels.iter().enumerate() {
        let limit = lv.tolerance + 1e-9 * lv.tolerance.max(zspan);
        // (error, triangle, x, y, between samples)
        let mut worst = (0.0f64, 0u32, 0.0, 0.0, false);
        let (mut crossings, mut crossings_over) = (0usize, 0usize);
        for (t, (tri, nb)) in lv.tris.iter().zip(&lv.nbrs).enumerate() {
            if t % 4096 == 4095 {
                interrupt()?;
            }
            if lv.is_void(t as u32) {
                continue;
            }
            for j in 0..3 {
                if nb[j] != NONE && (nb[j] as usize) < t && !lv.is_void(nb[j]) {
                    continue; // the edge is its neighbour's too: measured there
                }
                let a = tin.verts[tri[(j + 1) % 3] as usize];
                let b = tin.verts[tri[(j + 2) % 3] as usize];
                reference.for_each_crossing(&a, &b, &mut |c| {
                    let e = c.error(&a, &b);
                    crossings += 1;
                    if e > limit {
                        crossings_over += 1;
                    }
                    if e > worst.0 {
                        worst = (e, t as u32, c.p[0], c.p[1], true);
                    }
                });
            }
        }
        let (mut centres, mut centres_over) = (0usize, 0usize);
        for (i, &z) in heights.z.iter().enumerate() {
            if i % 4096 == 4095 {
                interrupt()?;
            }
            if z.is_nan() {
                continue;
            }
            let (c, r) = heights.col_row(i);
            if reference.cuts_centre(c, r) {
                continue;
            }
            let (x, y) = lat.centre(c as f64, r as f64);
            let Some(t) = super::locate::locate(tin, l, x, y) else {
                continue;
            };
            if lv.is_void(t) {
                continue;
            }
            centres += 1;
            let e = (super::interpolate(&tin.corners(l, t), x, y) - z).abs();
            if e > limit {
                centres_over += 1;
            }
            if e > worst.0 {
                worst = (e, t, x, y, false);
            }
        }
        if crossings_over + centres_over > 0 {
            let (e, t, x, y, between) = worst;
            out.push(Problem {
                level: l,
                triangle: t,
                kind: "over tolerance",
                detail: format!(
                    "error {e} at POINT({x} {y}) ({}), tolerance {}: {crossings_over} of {crossings} \
                     grid-line crossings and {centres_over} of {centres} pixel centres over",
                    if between {
                        "between pixel centres"
                    } else {
                        "at a pixel centre"
                    },
                    lv.tolerance
                ),
            });
        }
    }
    Ok(out)
}
