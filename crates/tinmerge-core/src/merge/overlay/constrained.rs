//! The robust path of the overlay: B loaded as a constrained triangulation of
//! its own edges, every edge of A walked through it (spade's
//! `LineIntersectionIterator`, exact), crossing points computed once per
//! pair of edges, pieces of every edge bulk-loaded into one CDT (spade;
//! pieces that rounding made cross again inserted with splitting, by
//! [`super::split::add_splitting`] rather than spade's own), output
//! triangles labelled by locating their centroids. Used when B's domain is
//! not convex or the face-by-face path ([`super::faces`]) refuses.
//!
//! Each output point gets its heights where it is made, from what it was
//! made of: a crossing from the two edges' ends ([`z_along`]), a vertex of
//! one tin from the edge or triangle of the other it was located on. They
//! used to be interpolated in the first output triangle met at the point;
//! along a tin's boundary the crossings' rounding leaves flat slivers a few
//! hundred metres long, whose centroid lies in a triangle far from some of
//! their corners, and the extrapolation there was metres off (issue 47's
//! shifted pair: 15 of 2,963 million m³ of cut).

use super::faces::HullBuckets;
use super::output::{Overlay, drop_unused};
use super::outside::{Cdt, beyond_hull_edges, outside_slivers};
use super::split::add_splitting;
use crate::geom::{co, crossing, point_segment_nearest, xy, z_along};
use crate::interrupt::{Interrupt, Ticker};
use crate::tin::{NONE, Tin, TinError, interpolate, locate};
use robust::orient2d;
use spade::handles::FixedVertexHandle;
use spade::{
    Intersection, LineIntersectionIterator, Point2, PositionInTriangulation, Triangulation,
};

/// The edges of one level, each once: (smaller vertex id, larger).
fn level_edges(tin: &Tin, level: usize) -> Vec<[u32; 2]> {
    let lv = &tin.levels[level];
    let mut e = Vec::with_capacity(lv.tris.len() * 3 / 2 + 8);
    for (t, (tri, nb)) in lv.tris.iter().zip(&lv.nbrs).enumerate() {
        for j in 0..3 {
            if nb[j] == NONE || (t as u32) < nb[j] {
                let (u, v) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
                e.push([u.min(v), u.max(v)]);
            }
        }
    }
    e
}

/// B's level as a CDT with B's triangles (vertex handle i = B vertex i),
/// plus rounding-wide slivers where the level's outer boundary bends in by
/// an ulp. Refused when the level's triangles do not cover the convex hull
/// of its vertices (the CDT would fill real concavities).
fn load(tin: &Tin, level: usize, which: &str) -> Result<Cdt, TinError> {
    let lv = &tin.levels[level];
    let nv = lv.num_vertices as usize;
    let verts: Vec<Point2<f64>> = tin.verts[..nv]
        .iter()
        .map(|v| Point2::new(v[0], v[1]))
        .collect();
    let edges: Vec<[usize; 2]> = level_edges(tin, level)
        .iter()
        .map(|e| [e[0] as usize, e[1] as usize])
        .collect();
    if edges.iter().any(|e| e[1] >= nv) {
        return Err(TinError::Corrupt(format!(
            "tin {which}: a triangle uses a vertex beyond the level's vertex count"
        )));
    }
    let mut conflicts = 0usize;
    let cdt = Cdt::try_bulk_load_cdt(verts, edges, |_| conflicts += 1)
        .map_err(|e| TinError::Corrupt(format!("tin {which}: {e:?}")))?;
    // With every edge of the level a constraint, each of its triangles is a
    // face of the CDT; faces beyond them fill concavities of the level's
    // outer boundary. Those a rounding wide are accepted: a boundary
    // ring's cut with the samples' hull lands an ulp inside the hull, so a
    // level with void triangles covers the hull only up to rounding. They
    // lie outside B, and an output face in one is given the nearest of B's
    // triangles (its area is rounding noise).
    let extra = cdt.num_inner_faces().checked_sub(lv.tris.len());
    let slivers_only = extra == Some(0) || {
        let area = |f: [[f64; 2]; 3]| crate::geom::tri_area(&f).abs();
        let total: f64 = cdt
            .inner_faces()
            .map(|f| area(f.positions().map(|p| [p.x, p.y])))
            .sum();
        let ours: f64 = lv
            .tris
            .iter()
            .map(|t| area(t.map(|v| xy(&tin.verts[v as usize]))))
            .sum();
        extra.is_some() && total - ours <= 1e-9 * total
    };
    if conflicts > 0 || cdt.num_vertices() != nv || !slivers_only {
        return Err(TinError::InvalidParameter(format!(
            "tin {which} at level {level} is not a triangulation of the convex hull of its vertices \
             ({} triangles, {} expected); the overlay needs convex domains",
            lv.tris.len(),
            cdt.num_inner_faces()
        )));
    }
    Ok(cdt)
}

/// Output vertices as they are found.
struct Points {
    pts: Vec<Point2<f64>>,
    /// A or B vertex id behind each output vertex (NONE: a crossing).
    src_a: Vec<u32>,
    src_b: Vec<u32>,
    /// Heights on A's and B's surfaces.
    za: Vec<f64>,
    zb: Vec<f64>,
}

impl Points {
    fn with_capacity(n: usize) -> Points {
        Points {
            pts: Vec::with_capacity(n),
            src_a: Vec::with_capacity(n),
            src_b: Vec::with_capacity(n),
            za: Vec::with_capacity(n),
            zb: Vec::with_capacity(n),
        }
    }

    /// A point, the vertices of A and B behind it (or NONE), its heights.
    fn push(&mut self, p: [f64; 2], (a, b): (u32, u32), (za, zb): (f64, f64)) -> u32 {
        self.pts.push(Point2::new(p[0], p[1]));
        self.src_a.push(a);
        self.src_b.push(b);
        self.za.push(za);
        self.zb.push(zb);
        (self.pts.len() - 1) as u32
    }
}

/// The overlay as one constrained Delaunay triangulation of all vertices
/// and edge pieces (see the module comment): the vertices of both located
/// ([`locate_vertices`]), A's edges walked through B ([`walk_edges_of_a`]),
/// B's edges cut at what was found on them ([`pieces_of_b`]), all
/// triangulated at once ([`triangulate`]) and the faces labelled
/// ([`label_faces`]).
pub(crate) fn overlay_cdt(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Overlay, TinError> {
    let mut tk = Ticker::new(interrupt);
    if a.bbox.disjoint_xy(&b.bbox) {
        return Ok(Overlay::default()); // disjoint domains
    }
    let cdt_b = load(b, level_b, "b")?;
    let (hull_a, hull_b) = (
        HullBuckets::new(a, &a.levels[level_a]),
        HullBuckets::new(b, &b.levels[level_b]),
    );
    let (a, b) = (
        Side {
            tin: a,
            level: level_a,
            hull: &hull_a,
        },
        Side {
            tin: b,
            level: level_b,
            hull: &hull_b,
        },
    );
    let mut found = locate_vertices(a, b, &cdt_b, &mut tk)?;
    let (mut pieces, crossings) = walk_edges_of_a(a, b, &cdt_b, &mut found, &mut tk)?;
    pieces_of_b(&cdt_b, &found, &mut pieces, &mut tk)?;
    for p in pieces.iter_mut() {
        if p[0] > p[1] {
            p.swap(0, 1);
        }
    }
    pieces.sort_unstable();
    pieces.dedup();
    // a crossing rounded onto another point, or a few ulps from it (a
    // breakline's vertex on B's edge up to rounding, two tins' vertices on one
    // grid line), is that point
    let (pts, pieces) = merge_coincident(found.pts, pieces);
    let (cdt, resplit) = triangulate(&pts.pts, pieces, &mut tk)?;
    let mut o = Overlay {
        pts: cdt
            .vertices()
            .map(|v| [v.position().x, v.position().y])
            .collect(),
        crossings,
        resplit,
        ..Overlay::default()
    };
    // the points in the order given (the CDT keeps it), then those its
    // splitting insertion added where two pieces crossed again: located
    o.za = pts.za;
    o.zb = pts.zb;
    for p in &o.pts[o.za.len()..] {
        tk.tick()?;
        o.za.push(z_at(a, *p));
        o.zb.push(z_at(b, *p));
    }
    let band = 1e-9
        * o.pts
            .iter()
            .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let mut outside = outside_slivers(&cdt, band, &mut tk)?;
    beyond_hull_edges(
        &cdt,
        &[
            (&a.tin.levels[a.level], &pts.src_a),
            (&b.tin.levels[b.level], &pts.src_b),
        ],
        band,
        &mut outside,
        &mut tk,
    )?;
    label_faces(a, b, &cdt, &outside, &mut o, &mut tk)?;
    Ok(o)
}

/// One input of the overlay: a tin at a level, and its hull triangles.
#[derive(Clone, Copy)]
struct Side<'a> {
    tin: &'a Tin,
    level: usize,
    hull: &'a HullBuckets,
}

impl Side<'_> {
    fn num_vertices(&self) -> usize {
        self.tin.levels[self.level].num_vertices as usize
    }

    /// The hull triangle nearest `p` by distance to its hull edges, with
    /// that distance, among those whose box is within `reach` of `p`
    /// (all of them when `reach` is infinite).
    fn nearest_hull(&self, p: [f64; 2], reach: f64) -> Option<(f64, u32)> {
        let lv = &self.tin.levels[self.level];
        let (lo, hi) = ([p[0] - reach, p[1] - reach], [p[0] + reach, p[1] + reach]);
        let mut best: Option<(f64, u32)> = None;
        for t in self.hull.near(lo, hi) {
            let (tri, nb) = (lv.tris[t as usize], lv.nbrs[t as usize]);
            for j in (0..3).filter(|&j| nb[j] == NONE) {
                let (u, v) = (
                    xy(&self.tin.verts[tri[(j + 1) % 3] as usize]),
                    xy(&self.tin.verts[tri[(j + 2) % 3] as usize]),
                );
                let d = point_segment_nearest(p, u, v).0;
                if d <= reach && best.is_none_or(|b| d < b.0) {
                    best = Some((d, t));
                }
            }
        }
        best
    }
}

/// The output points found so far and where the inputs' vertices went.
struct Found {
    pts: Points,
    /// each vertex of A's output point (NONE: outside B's domain)
    out_a: Vec<u32>,
    /// each vertex of B's output point (NONE: outside A's domain)
    out_b: Vec<u32>,
    /// the points on each undirected edge of B (besides its ends)
    on_b: Vec<Vec<u32>>,
}

/// A's vertices located in B (on a vertex of B, on an edge, in a face),
/// then B's vertices inside A's domain.
fn locate_vertices(
    a: Side<'_>,
    b: Side<'_>,
    cdt_b: &Cdt,
    tk: &mut Ticker<'_, '_>,
) -> Result<Found, TinError> {
    let (nva, nvb) = (a.num_vertices(), b.num_vertices());
    let mut f = Found {
        pts: Points::with_capacity(nva + nvb),
        out_a: vec![NONE; nva],
        out_b: vec![NONE; nvb],
        on_b: vec![Vec::new(); cdt_b.num_undirected_edges()],
    };
    let lb = &b.tin.levels[b.level];
    let big = [&a.tin.bbox, &b.tin.bbox]
        .iter()
        .flat_map(|b| [b.min_x, b.max_x, b.min_y, b.max_y])
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let eps = snap_eps(big);
    // a point in a rounding-wide sliver outside B (an edge or a face of
    // the CDT that is no edge or triangle of B, see `load`): outside B
    // unless within `eps` of it, as for B's vertices below
    let near_b = |v: &[f64; 3]| b.nearest_hull(xy(v), eps).map(|_| z_at(b, xy(v)));
    for (i, v) in a.tin.verts[..nva].iter().enumerate() {
        tk.tick()?;
        let hint = {
            let t = locate::start_triangle(b.tin, b.level, v[0], v[1]);
            FixedVertexHandle::from_index(lb.tris.get(t as usize).map_or(0, |tr| tr[0] as usize))
        };
        let zb = |h: FixedVertexHandle| b.tin.verts[h.index()];
        match cdt_b.locate_with_hint(Point2::new(v[0], v[1]), hint) {
            PositionInTriangulation::OnVertex(h) => {
                let id = f
                    .pts
                    .push(xy(v), (i as u32, h.index() as u32), (v[2], zb(h)[2]));
                f.out_a[i] = id;
                f.out_b[h.index()] = id;
            }
            PositionInTriangulation::OnEdge(e) => {
                let e = cdt_b.directed_edge(e);
                let on_edge_of_b = e.is_constraint_edge();
                let z = if on_edge_of_b {
                    Some(z_along(&zb(e.from().fix()), &zb(e.to().fix()), xy(v)))
                } else {
                    near_b(v)
                };
                if let Some(z) = z {
                    let id = f.pts.push(xy(v), (i as u32, NONE), (v[2], z));
                    f.out_a[i] = id;
                    if on_edge_of_b {
                        f.on_b[e.as_undirected().index()].push(id);
                    }
                }
            }
            PositionInTriangulation::OnFace(h) => {
                let face = cdt_b.face(h);
                // a triangle of B has constraints for sides; a sliver
                // outside it does not
                let z = if face.adjacent_edges().iter().all(|e| e.is_constraint_edge()) {
                    Some(interpolate(
                        &face.vertices().map(|w| zb(w.fix())),
                        v[0],
                        v[1],
                    ))
                } else {
                    near_b(v)
                };
                if let Some(z) = z {
                    f.out_a[i] = f.pts.push(xy(v), (i as u32, NONE), (v[2], z));
                }
            }
            _ => {}
        }
    }
    // B's vertices in A, and those a rounding outside it: A's outer
    // boundary can bend in by an ulp where a boundary ring meets the
    // samples' hull, and a vertex of B on the hull line is then outside
    // A's triangles. The crossings of A's edges with B's edges there
    // round onto that vertex (`merge_coincident`), as the faces path snaps
    // them; left out, the vertex would be missing from the output.
    for (j, v) in b.tin.verts[..nvb].iter().enumerate() {
        tk.tick()?;
        if f.out_b[j] != NONE {
            continue;
        }
        let t = locate::locate_hull(a.tin, a.level, v[0], v[1])
            .or_else(|| a.nearest_hull(xy(v), eps).map(|n| n.1));
        if let Some(t) = t {
            let z = interpolate(&a.tin.corners(a.level, t), v[0], v[1]);
            f.out_b[j] = f.pts.push(xy(v), (NONE, j as u32), (z, v[2]));
        }
    }
    Ok(f)
}

/// Every edge of A walked through B: its pieces between the points on it
/// (its ends inside B's domain, B's vertices on it, its proper crossings
/// with B's edges, pushed as new points and noted on B's edges). The
/// pieces, and the number of crossings.
fn walk_edges_of_a(
    a: Side<'_>,
    b: Side<'_>,
    cdt_b: &Cdt,
    f: &mut Found,
    tk: &mut Ticker<'_, '_>,
) -> Result<(Vec<[usize; 2]>, usize), TinError> {
    let mut pieces: Vec<[usize; 2]> = Vec::new();
    let mut crossings = 0usize;
    let mut chain: Vec<u32> = Vec::new();
    for [i, k] in level_edges(a.tin, a.level) {
        tk.tick()?;
        let (pa, qa) = (&a.tin.verts[i as usize], &a.tin.verts[k as usize]);
        let (p, q) = (xy(pa), xy(qa));
        chain.clear();
        if f.out_a[i as usize] != NONE {
            chain.push(f.out_a[i as usize]);
        }
        let it =
            LineIntersectionIterator::new(cdt_b, Point2::new(p[0], p[1]), Point2::new(q[0], q[1]));
        for x in it {
            match x {
                Intersection::VertexIntersection(h) => {
                    let id = f.out_b[h.fix().index()];
                    if id == NONE {
                        return Err(TinError::Corrupt(
                            "overlay: an edge of a meets a vertex of b outside a's domain".into(),
                        ));
                    }
                    chain.push(id);
                }
                // an edge of the CDT that is no edge of B spans a
                // rounding-wide sliver outside B (see `load`): nothing
                // of the overlay is there
                Intersection::EdgeIntersection(e) if !e.is_constraint_edge() => {}
                Intersection::EdgeIntersection(e) => {
                    let (hu, hv) = (e.from(), e.to());
                    let (u, v) = (hu.position(), hv.position());
                    let (u, v) = ([u.x, u.y], [v.x, v.y]);
                    let (op, oq) = (orient2d(co(u), co(v), co(p)), orient2d(co(u), co(v), co(q)));
                    if op == 0.0 || oq == 0.0 {
                        // an end of the edge of A on this edge of B: that
                        // end is in the chain already (located OnEdge)
                        continue;
                    }
                    // a proper crossing (ends of the edge of B are reported
                    // as vertex intersections)
                    let (s, t) = if i < k { (p, q) } else { (q, p) };
                    let (s2, t2) = if hu.fix().index() < hv.fix().index() {
                        (u, v)
                    } else {
                        (v, u)
                    };
                    let x = crossing(s, t, s2, t2);
                    let (ub, vb) = (
                        &b.tin.verts[hu.fix().index()],
                        &b.tin.verts[hv.fix().index()],
                    );
                    let zb = z_along(ub, vb, x);
                    let id = f.pts.push(x, (NONE, NONE), (z_along(pa, qa, x), zb));
                    crossings += 1;
                    f.on_b[e.as_undirected().index()].push(id);
                    chain.push(id);
                }
                Intersection::EdgeOverlap(_) => {}
            }
        }
        if f.out_a[k as usize] != NONE {
            chain.push(f.out_a[k as usize]);
        }
        chain.dedup();
        for w in chain.windows(2) {
            pieces.push([w[0] as usize, w[1] as usize]);
        }
    }
    Ok((pieces, crossings))
}

/// Every edge of B: its ends inside A's domain and the points found on it,
/// in order along it, as pieces.
fn pieces_of_b(
    cdt_b: &Cdt,
    f: &Found,
    pieces: &mut Vec<[usize; 2]>,
    tk: &mut Ticker<'_, '_>,
) -> Result<(), TinError> {
    let mut along: Vec<(f64, u32)> = Vec::new();
    // B's own edges: not those spanning a sliver outside it (`load`)
    for e in cdt_b.undirected_edges().filter(|e| e.is_constraint_edge()) {
        tk.tick()?;
        let [hu, hv] = e.vertices();
        let (iu, iv) = (hu.fix().index(), hv.fix().index());
        let (u, v) = (hu.position(), hv.position());
        let d = [v.x - u.x, v.y - u.y];
        along.clear();
        let pt = |id: u32| f.pts.pts[id as usize];
        let param = |p: Point2<f64>| (p.x - u.x) * d[0] + (p.y - u.y) * d[1];
        if f.out_b[iu] != NONE {
            along.push((f64::NEG_INFINITY, f.out_b[iu]));
        }
        for &id in &f.on_b[e.index()] {
            along.push((param(pt(id)), id));
        }
        if f.out_b[iv] != NONE {
            along.push((f64::INFINITY, f.out_b[iv]));
        }
        along.sort_by(|x, y| x.0.total_cmp(&y.0));
        for w in along.windows(2) {
            if w[0].1 != w[1].1 {
                pieces.push([w[0].1 as usize, w[1].1 as usize]);
            }
        }
    }
    Ok(())
}

/// One constrained triangulation of all points and pieces, the pieces
/// that rounding made cross again inserted with splitting (their number is
/// the second value).
fn triangulate(
    pts: &[Point2<f64>],
    pieces: Vec<[usize; 2]>,
    tk: &mut Ticker<'_, '_>,
) -> Result<(Cdt, usize), TinError> {
    let n_in = pts.len();
    let mut conflicts: Vec<[usize; 2]> = Vec::new();
    let mut cdt = Cdt::try_bulk_load_cdt(pts.to_vec(), pieces, |e| conflicts.push(e))
        .map_err(|e| TinError::Degenerate(format!("overlay: {e:?}")))?;
    if cdt.num_vertices() != n_in {
        return Err(TinError::Degenerate(
            "overlay: two output points coincide (a crossing rounded onto a vertex)".into(),
        ));
    }
    let resplit = conflicts.len();
    if resplit > 0 {
        let big = pts
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
        let eps = snap_eps(big);
        for [u, v] in conflicts {
            tk.tick()?;
            add_splitting(
                &mut cdt,
                FixedVertexHandle::from_index(u),
                FixedVertexHandle::from_index(v),
                eps,
                tk,
            )?;
        }
    }
    Ok((cdt, resplit))
}

/// The CDT's faces as the overlay's triangles, each labelled with the
/// triangles of A and B holding its centroid; those [`outside_slivers`]
/// found dropped, and the points only they used.
fn label_faces(
    a: Side<'_>,
    b: Side<'_>,
    cdt: &Cdt,
    outside: &[bool],
    o: &mut Overlay,
    tk: &mut Ticker<'_, '_>,
) -> Result<(), TinError> {
    o.tris.reserve(cdt.num_inner_faces());
    for f in cdt.inner_faces() {
        tk.tick()?;
        if outside[f.fix().index()] {
            continue;
        }
        let vs = f.vertices().map(|v| v.fix().index() as u32);
        let c = vs.map(|v| o.pts[v as usize]);
        let (cx, cy) = (
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        );
        let (ta, tb) = (owner(a, cx, cy), owner(b, cx, cy));
        o.tris.push(vs);
        o.tri_a.push(ta);
        o.tri_b.push(tb);
    }
    drop_unused(o);
    Ok(())
}

/// Points this close in x and in y are one output point: 8 ulps of the
/// largest coordinate `big` ([`merge_coincident`]).
pub(super) fn snap_eps(big: f64) -> f64 {
    8.0 * f64::EPSILON * big.max(f64::MIN_POSITIVE)
}

/// Points at the same position, or a few units in the last place apart,
/// made one (the first, which is an input vertex when one of them is: those
/// are pushed before the crossings; its sources those of any of them), the
/// pieces renumbered, those reduced to a point dropped.
///
/// Two crossings of nearly collinear edges (coarse edges of two tins
/// crossing the same grid line next to each other), or a crossing and a
/// vertex that lies on the other edge up to rounding, can round to points
/// an ulp apart that are different but not separable: the constrained
/// triangulation then has pieces crossing at a point it cannot place
/// between them (spade's splitting insertion fails on them). Within `eps`
/// (8 ulps of the largest coordinate) they are one point; the pieces
/// through it bend by that much.
fn merge_coincident(pts: Points, mut pieces: Vec<[usize; 2]>) -> (Points, Vec<[usize; 2]>) {
    let big = pts
        .pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let eps = snap_eps(big);
    let cell = |v: f64| (v / (2.0 * eps)).floor() as i64;
    // points by cell of side 2 eps: a point within eps of another is in one
    // of the 3 x 3 cells around it
    let mut grid: rustc_hash::FxHashMap<(i64, i64), Vec<u32>> = Default::default();
    let mut id = Vec::with_capacity(pts.pts.len());
    let mut out = Points::with_capacity(pts.pts.len());
    for (k, p) in pts.pts.iter().enumerate() {
        let (cx, cy) = (cell(p.x), cell(p.y));
        let mut found = None;
        'near: for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(ids) = grid.get(&(cx + dx, cy + dy)) {
                    for &j in ids {
                        let q = out.pts[j as usize];
                        if (q.x - p.x).abs() <= eps && (q.y - p.y).abs() <= eps {
                            found = Some(j as usize);
                            break 'near;
                        }
                    }
                }
            }
        }
        match found {
            Some(j) => {
                // an input vertex's own height wins over one interpolated
                if out.src_a[j] == NONE && pts.src_a[k] != NONE {
                    out.src_a[j] = pts.src_a[k];
                    out.za[j] = pts.za[k];
                }
                if out.src_b[j] == NONE && pts.src_b[k] != NONE {
                    out.src_b[j] = pts.src_b[k];
                    out.zb[j] = pts.zb[k];
                }
                id.push(j);
            }
            None => {
                let j = out.push(
                    [p.x, p.y],
                    (pts.src_a[k], pts.src_b[k]),
                    (pts.za[k], pts.zb[k]),
                );
                grid.entry((cx, cy)).or_default().push(j);
                id.push(j as usize);
            }
        }
    }
    if out.pts.len() == pts.pts.len() {
        return (out, pieces);
    }
    for q in pieces.iter_mut() {
        *q = [id[q[0]], id[q[1]]];
        if q[0] > q[1] {
            q.swap(0, 1);
        }
    }
    pieces.retain(|q| q[0] != q[1]);
    pieces.sort_unstable();
    pieces.dedup();
    (out, pieces)
}

/// Height of `tin`'s level at `p`, in the triangle holding it (or the hull
/// triangle nearest, for a point a rounding outside).
fn z_at(s: Side<'_>, p: [f64; 2]) -> f64 {
    let t = owner(s, p[0], p[1]);
    interpolate(&s.tin.corners(s.level, t), p[0], p[1])
}

/// The triangle of `s` holding `(x, y)`, or for a point outside the
/// level's triangles (a rounding outside: a crossing on an edge of the
/// constrained triangulation that spans a rounding-wide concavity of the
/// level's outer boundary, see `load`) the hull triangle nearest it.
///
/// A walk towards such a point can leave the hull through any hull edge
/// whose line the point is beyond, kilometres away along a nearly
/// straight boundary; heights extrapolated from there were hundreds of
/// metres off (issue 47's shifted pair).
fn owner(s: Side<'_>, x: f64, y: f64) -> u32 {
    let (tin, level) = (s.tin, s.level);
    if let Some(t) = locate::locate_hull(tin, level, x, y) {
        return t;
    }
    // the cells around first: a point a rounding outside lies in the box
    // of its hull triangle; then every hull triangle
    let cell = s.hull.cell[0].hypot(s.hull.cell[1]);
    let near = s.nearest_hull([x, y], cell);
    match near.or_else(|| s.nearest_hull([x, y], f64::INFINITY)) {
        Some((_, t)) => t,
        // no hull triangle: not a level a build makes
        None => {
            let st = locate::start_triangle(tin, level, x, y);
            match locate::walk(tin, level, st, x, y) {
                locate::Walk::Inside(t) | locate::Walk::Outside(t) => t,
            }
        }
    }
}

#[cfg(feature = "bench")]
/// The naive method, for comparison: all vertices of both levels in one
/// CDT, then every edge of A and of B inserted with splitting where it
/// crosses. Returns (vertices, triangles) of the triangulation of the union
/// of the convex hulls.
pub fn naive(a: &Tin, level_a: usize, b: &Tin, level_b: usize) -> Result<(usize, usize), TinError> {
    std::panic::catch_unwind(|| naive_inner(a, level_a, b, level_b)).map_err(|_| {
        TinError::Degenerate("naive overlay: spade failed (one of its assertions)".into())
    })?
}

#[cfg(feature = "bench")]
fn naive_inner(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
) -> Result<(usize, usize), TinError> {
    let (nva, nvb) = (
        a.levels[level_a].num_vertices as usize,
        b.levels[level_b].num_vertices as usize,
    );
    let verts: Vec<Point2<f64>> = a.verts[..nva]
        .iter()
        .chain(&b.verts[..nvb])
        .map(|v| Point2::new(v[0], v[1]))
        .collect();
    let mut cdt =
        Cdt::bulk_load(verts).map_err(|e| TinError::Degenerate(format!("overlay: {e:?}")))?;
    let handle =
        |cdt: &Cdt, v: &[f64; 3]| cdt.locate_vertex(Point2::new(v[0], v[1])).map(|h| h.fix());
    for (tin, level) in [(a, level_a), (b, level_b)] {
        for [u, v] in level_edges(tin, level) {
            let (hu, hv) = (
                handle(&cdt, &tin.verts[u as usize]),
                handle(&cdt, &tin.verts[v as usize]),
            );
            if let (Some(hu), Some(hv)) = (hu, hv) {
                cdt.add_constraint_and_split(hu, hv, |p| p);
            }
        }
    }
    Ok((cdt.num_vertices(), cdt.num_inner_faces()))
}
