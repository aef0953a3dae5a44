//! TIN/TIN overlay on real TINs built from the bundled DEM, checked against
//! oracles written here: the common domain from a hull and a half-plane
//! clipper of the test's own, exact orientation tests, and heights from
//! point location in the inputs.

use crate::common;

use common::read_dem;
use robust::{Coord, orient2d};
use std::collections::{HashMap, HashSet};
use tinmerge_core::merge::overlay::{Overlay, difference, mark_same, overlay, overlay_constrained};
use tinmerge_core::tin::build::build;
use tinmerge_core::tin::{NONE, Tin, locate};

type P = [f64; 2];

fn co(p: P) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

/// DEM samples of a window of rows/columns, shifted by (dx, dy) pixels and
/// raised by dz.
fn window(r0: usize, c0: usize, n: usize, dx: f64, dy: f64, dz: f64) -> Vec<[f64; 3]> {
    window_of("jacksboro_fault_dem_utm16n.tif", r0, c0, n, dx, dy, dz)
}

/// [`window`] of a bundled DEM.
fn window_of(
    file: &str,
    r0: usize,
    c0: usize,
    n: usize,
    dx: f64,
    dy: f64,
    dz: f64,
) -> Vec<[f64; 3]> {
    let dem = read_dem(file);
    let mut out = Vec::new();
    for r in r0..r0 + n {
        for c in c0..c0 + n {
            let v = dem.values[r * dem.width + c];
            if v.is_nan() || Some(v) == dem.nodata {
                continue;
            }
            let (x, y) = dem.centre(c, r);
            out.push([x + dx * dem.scale_x, y - dy * dem.scale_y, v + dz]);
        }
    }
    out
}

fn tin(samples: Vec<[f64; 3]>, tols: &[f64]) -> Tin {
    build(samples, tols, 32616, &mut || Ok(())).unwrap()
}

/// Convex hull (Andrew's monotone chain, exact turns), CCW, no collinear
/// points.
fn hull(mut p: Vec<P>) -> Vec<P> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    let mut h: Vec<P> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let it: Box<dyn Iterator<Item = &P>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in it {
            while h.len() >= start + 2
                && orient2d(co(h[h.len() - 2]), co(h[h.len() - 1]), co(q)) <= 0.0
            {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

/// Convex polygon `poly` clipped by the convex polygon `by` (both CCW).
fn clip(poly: &[P], by: &[P]) -> Vec<P> {
    let mut out = poly.to_vec();
    for i in 0..by.len() {
        out = common::clip_half(&out, by[i], by[(i + 1) % by.len()]);
    }
    out
}

/// Shoelace area, about the first corner (in degrees, products of raw
/// coordinates lose seven digits of a pixel-sized polygon's area).
fn area(poly: &[P]) -> f64 {
    let Some(&o) = poly.first() else {
        return 0.0;
    };
    let mut s = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (p, q) = ([p[0] - o[0], p[1] - o[1]], [q[0] - o[0], q[1] - o[1]]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    s / 2.0
}

fn level_pts(t: &Tin, l: usize) -> Vec<P> {
    t.verts[..t.levels[l].num_vertices as usize]
        .iter()
        .map(|v| [v[0], v[1]])
        .collect()
}

fn in_closed(poly: &[P], p: P) -> bool {
    (0..poly.len()).all(|i| orient2d(co(poly[i]), co(poly[(i + 1) % poly.len()]), co(p)) >= 0.0)
}

fn edges(t: &Tin, l: usize) -> Vec<(P, P)> {
    let lv = &t.levels[l];
    let mut e = Vec::new();
    for (i, (tri, nb)) in lv.tris.iter().zip(&lv.nbrs).enumerate() {
        for j in 0..3 {
            if nb[j] == NONE || (i as u32) < nb[j] {
                let (u, v) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
                let (u, v) = (t.verts[u as usize], t.verts[v as usize]);
                e.push(([u[0], u[1]], [v[0], v[1]]));
            }
        }
    }
    e
}

/// Segment (p, q) clipped to the convex polygons `hulls` (Cyrus-Beck over
/// all their sides), or None. The sides are the inputs' own hull lines,
/// through input vertices, not the common domain's sides between its
/// computed corners: a corner rounded by 6e-15 degree tilts a side enough
/// to move its crossing with a nearly parallel edge (0.06 degree apart) by
/// 1e-11 degree, more than the oracle's tolerance (harness seeds 150023,
/// 152471, 155230), and two sides along one hull line could turn a
/// rounding the wrong way at the corner between them (seed 91719). The
/// sides' values are exact up to one rounding (`orient2d`). An end within
/// `snap` of a side is that end; a larger `snap` (a millionth of the edge,
/// as it was) took an input vertex 5 um outside the domain for the
/// clipped end (seed 137591).
///
/// With each end, its slack: how far along the segment a point a few
/// roundings off both lines may be from the exact crossing, 8 units in the
/// last place of the coordinates over the sine of the angle between the
/// segment and the side (0 at an end of the segment itself). Two codes
/// rounding one crossing of lines 0.06 degree apart put it 2e-11 degree
/// apart along them (harness seeds 152471, 155230).
fn clip_segment(hulls: &[&[P]], p: P, q: P, snap: f64) -> Option<(P, P, [f64; 2])> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let mut slack = [0.0f64; 2];
    let len = (q[0] - p[0]).hypot(q[1] - p[1]);
    let slack_at = |a: P, b: P| {
        let big = [p, q, a, b]
            .iter()
            .fold(0.0f64, |m, r| m.max(r[0].abs()).max(r[1].abs()));
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let sin = ((q[0] - p[0]) * dy - (q[1] - p[1]) * dx).abs() / (len * dx.hypot(dy));
        8.0 * f64::EPSILON * big / sin
    };
    let at = |t: f64| [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
    for poly in hulls {
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let side = |r: P| orient2d(co(a), co(b), co(r));
            let (sp, sq) = (side(p), side(q));
            if sp < 0.0 && sq < 0.0 {
                return None;
            }
            if sp < 0.0 {
                let t = sp / (sp - sq);
                if t > t0 {
                    (t0, slack[0]) = (t, slack_at(a, b));
                }
            } else if sq < 0.0 {
                let t = sp / (sp - sq);
                if t < t1 {
                    (t1, slack[1]) = (t, slack_at(a, b));
                }
            }
        }
    }
    // an end on a side up to rounding is that end
    if t0 * len <= snap {
        (t0, slack[0]) = (0.0, 0.0);
    }
    if (1.0 - t1) * len <= snap {
        (t1, slack[1]) = (1.0, 0.0);
    }
    (t1 - t0 > 1e-12).then(|| (at(t0), at(t1), slack))
}

const TOL: f64 = 1e-6; // metres, for points computed by two codes

/// A metre in the tin's horizontal unit, near enough for thresholds: 1 for
/// the projected grids, 1e-5 degree (about 1.1 m at the DEM's latitude) for
/// the geographic one. Every length threshold below is in metres times it.
fn unit(t: &Tin) -> f64 {
    if t.srid == 4326 { 1e-5 } else { 1.0 }
}

struct Index<'a> {
    o: &'a Overlay,
    unit: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
    adj: Vec<Vec<u32>>,
}

impl<'a> Index<'a> {
    fn new(o: &'a Overlay, unit: f64) -> Self {
        let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (i, p) in o.pts.iter().enumerate() {
            cells
                .entry(((p[0] / unit).floor() as i64, (p[1] / unit).floor() as i64))
                .or_default()
                .push(i as u32);
        }
        let mut adj = vec![Vec::new(); o.pts.len()];
        for t in &o.tris {
            for j in 0..3 {
                let (u, v) = (t[j], t[(j + 1) % 3]);
                adj[u as usize].push(v);
                adj[v as usize].push(u);
            }
        }
        Index {
            o,
            unit,
            cells,
            adj,
        }
    }
    /// The output vertex nearest `p` within the oracle's tolerance and
    /// `slack` more.
    fn find(&self, p: P, slack: f64) -> Option<u32> {
        let d = |i: &u32| {
            let q = self.o.pts[*i as usize];
            (q[0] - p[0]).hypot(q[1] - p[1])
        };
        self.within(p, TOL * self.unit + slack)
            .into_iter()
            .min_by(|x, y| d(x).total_cmp(&d(y)))
    }
    /// The output vertex nearest `p` and its distance, for a message.
    fn nearest(&self, p: P) -> String {
        let best = self
            .o
            .pts
            .iter()
            .map(|q| ((q[0] - p[0]).hypot(q[1] - p[1]), *q))
            .min_by(|x, y| x.0.total_cmp(&y.0));
        match best {
            Some((d, q)) => format!("{q:?}, {:.3e} m", d / self.unit),
            None => "none".into(),
        }
    }
    /// The output vertices within `tol` of `p`.
    fn within(&self, p: P, tol: f64) -> Vec<u32> {
        let (cx, cy) = (
            (p[0] / self.unit).floor() as i64,
            (p[1] / self.unit).floor() as i64,
        );
        let r = (tol / self.unit).ceil() as i64;
        let mut out = Vec::new();
        for dx in -r..=r {
            for dy in -r..=r {
                for &i in self.cells.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let q = self.o.pts[i as usize];
                    if (q[0] - p[0]).hypot(q[1] - p[1]) <= tol {
                        out.push(i);
                    }
                }
            }
        }
        out
    }
    /// Follow output edges from s to e along the segment, each step forward
    /// and each vertex within the tolerance of the segment's line. (The
    /// length such a chain covers adds up to the segment's; counted with
    /// the distance of its last vertex to `e`, it came out up to twice the
    /// tolerance long when that vertex is a twin a rounding beyond `e`,
    /// harness seed 156972, and measured nothing else.)
    /// Depth first, the nearest step ahead first: a vertex within the
    /// oracle's tolerance of the segment need not be on it (a vertex of the
    /// other input 5.6e-7 m beside an edge, harness seed 4012526), so a
    /// step that leads nowhere is taken back. An end computed by the clip
    /// is found within its `slack` more than the tolerance.
    fn follow(&self, s: P, e: P, slack: [f64; 2]) -> Result<(), String> {
        let len = (e[0] - s[0]).hypot(e[1] - s[1]);
        let dir = [(e[0] - s[0]) / len, (e[1] - s[1]) / len];
        let start = self.find(s, slack[0]).ok_or_else(|| {
            format!(
                "start {s:?} of the clipped edge is not an output vertex (nearest {})",
                self.nearest(s)
            )
        })?;
        let end = self.find(e, slack[1]).ok_or_else(|| {
            format!(
                "end {e:?} of the clipped edge is not an output vertex (nearest {})",
                self.nearest(e)
            )
        })?;
        let mut stack: Vec<u32> = vec![start];
        let mut seen: std::collections::HashSet<u32> = Default::default();
        let mut stuck = None;
        let mut steps = 0;
        while let Some(cur) = stack.pop() {
            if cur == end {
                return Ok(());
            }
            // within the oracle's tolerance of the end: there (two output
            // points a rounding apart, one on each input's edge)
            let c = self.o.pts[cur as usize];
            if (e[0] - c[0]).hypot(e[1] - c[1]) <= TOL * self.unit + slack[1] {
                return Ok(());
            }
            if !seen.insert(cur) {
                continue;
            }
            steps += 1;
            if steps > 100_000 {
                return Err("does not arrive".into());
            }
            // from this vertex, or another a rounding from it (two output
            // points the oracle's tolerance apart, one on each input's edge)
            let twins = self.within(c, TOL * self.unit);
            let mut next: Vec<(f64, u32)> = Vec::new();
            for &v in twins.iter().flat_map(|&w| &self.adj[w as usize]) {
                let q = self.o.pts[v as usize];
                let (wx, wy) = (q[0] - c[0], q[1] - c[1]);
                let forward = wx * dir[0] + wy * dir[1];
                let off = (q[0] - s[0]) * dir[1] - (q[1] - s[1]) * dir[0];
                if forward > 0.0 && off.abs() <= TOL * self.unit && !seen.contains(&v) {
                    next.push((forward, v));
                }
            }
            if next.is_empty() {
                stuck.get_or_insert(c);
            }
            // the nearest on top
            next.sort_by(|x, y| y.0.total_cmp(&x.0));
            stack.extend(next.into_iter().map(|(_, v)| v));
        }
        Err(format!(
            "no output edge continues the segment at {:?}",
            stuck.unwrap_or(s)
        ))
    }
}

/// Both paths (faces, and the constrained triangulation) checked against
/// the oracles; the faces path must not have fallen back on these inputs.
fn check(a: &Tin, la: usize, b: &Tin, lb: usize) -> Overlay {
    let c = overlay_constrained(a, la, b, lb, &mut || Ok(())).unwrap();
    check_one_with(a, la, b, lb, &c, true, true);
    let o = overlay(a, la, b, lb, &mut || Ok(())).unwrap();
    assert_eq!(o.fallback, None, "the faces path fell back");
    check_one(a, la, b, lb, &o);
    o
}

pub(crate) fn check_one(a: &Tin, la: usize, b: &Tin, lb: usize, o: &Overlay) {
    check_one_with(a, la, b, lb, o, false, true)
}

/// [`check_one`]; with `snapped`, an input vertex may be an output point
/// within 8 units in the last place of the largest coordinate (the
/// constrained path makes points that near one point, its
/// `merge_coincident`: two tins' vertices an ulp apart at a grid-line
/// crossing, harness seeds 73123, 73307, 74016); without `labels`, only
/// the output's conformity, area, vertices and edges are checked, not
/// each triangle's owners nor each point's heights.
pub(crate) fn check_one_with(
    a: &Tin,
    la: usize,
    b: &Tin,
    lb: usize,
    o: &Overlay,
    snapped: bool,
    labels: bool,
) {
    let (ha, hb) = (hull(level_pts(a, la)), hull(level_pts(b, lb)));
    let dom = clip(&ha, &hb);
    let dom_area = area(&dom);

    // triangles strictly CCW, every directed edge once, areas add up
    let mut directed = HashSet::new();
    let mut sum = 0.0;
    for (t, tri) in o.tris.iter().enumerate() {
        let c = tri.map(|v| o.pts[v as usize]);
        assert!(
            orient2d(co(c[0]), co(c[1]), co(c[2])) > 0.0,
            "triangle {t} not CCW"
        );
        for j in 0..3 {
            assert!(
                directed.insert((tri[j], tri[(j + 1) % 3])),
                "directed edge twice"
            );
        }
        sum += o.area(t);
    }
    assert!(
        (sum - dom_area).abs() <= 1e-9 * dom_area,
        "area {sum} vs common domain {dom_area}"
    );

    // every input vertex in the common domain is an output vertex
    let out: HashSet<(u64, u64)> = o
        .pts
        .iter()
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    let big = o
        .pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let eps = 8.0 * f64::EPSILON * big;
    let present = |p: P| {
        out.contains(&(p[0].to_bits(), p[1].to_bits()))
            || (snapped
                && o.pts
                    .iter()
                    .any(|q| (q[0] - p[0]).abs() <= eps && (q[1] - p[1]).abs() <= eps))
    };
    for (t, l) in [(a, la), (b, lb)] {
        for p in level_pts(t, l) {
            if in_closed(&dom, p) {
                assert!(present(p), "vertex {p:?} missing");
            }
        }
    }

    // every input edge, clipped, is a chain of output edges; but an edge
    // along the common domain's boundary up to rounding (a hull line of
    // one tin through vertices of the other, on aligned grids) meets it
    // anywhere along its length by the exact clip, and is checked as the
    // boundary the output has there instead
    let m = unit(a);
    let idx = Index::new(o, m);
    let along_boundary = |p: P, q: P| {
        (0..dom.len()).any(|i| {
            let (u, v) = (dom[i], dom[(i + 1) % dom.len()]);
            let len = (v[0] - u[0]).hypot(v[1] - u[1]);
            let off = |w: P| orient2d(co(u), co(v), co(w)).abs() / len;
            off(p) <= TOL * m && off(q) <= TOL * m
        })
    };
    for (t, l) in [(a, la), (b, lb)] {
        for (p, q) in edges(t, l) {
            if along_boundary(p, q) {
                continue;
            }
            if let Some((s, e, slack)) = clip_segment(&[&ha, &hb], p, q, 1e-3 * TOL * m) {
                let len = (e[0] - s[0]).hypot(e[1] - s[1]);
                if len < 1e-3 * m {
                    continue;
                }
                idx.follow(s, e, slack)
                    .unwrap_or_else(|m| panic!("edge {p:?}-{q:?}: {m}"));
            }
        }
    }

    if !labels {
        return;
    }
    // each output triangle inside its triangle of A and of B
    for (t, tri) in o.tris.iter().enumerate() {
        for (src, l, owner) in [(a, la, o.tri_a[t]), (b, lb, o.tri_b[t])] {
            let c = src.corners(l, owner).map(|v| [v[0], v[1]]);
            for &v in tri {
                let p = o.pts[v as usize];
                for j in 0..3 {
                    let (u, w) = (c[j], c[(j + 1) % 3]);
                    let d = ((w[0] - u[0]) * (p[1] - u[1]) - (w[1] - u[1]) * (p[0] - u[0]))
                        / (w[0] - u[0]).hypot(w[1] - u[1]);
                    assert!(
                        d >= -1e-7 * m,
                        "output triangle {t} pokes out of its owner {owner} by {d} (void: {:?}; its centroid's triangle by brute force: {:?}; output corners {:?}; owner corners {:?}; level has {} triangles, {} void)",
                        o.void.get(t),
                        {
                            let cc = tri.map(|v| o.pts[v as usize]);
                            let (cx, cy) = (
                                (cc[0][0] + cc[1][0] + cc[2][0]) / 3.0,
                                (cc[0][1] + cc[1][1] + cc[2][1]) / 3.0,
                            );
                            (0..src.levels[l].tris.len())
                                .filter(|&k| {
                                    let q = src.corners(l, k as u32);
                                    (0..3).all(|j| {
                                        orient2d(
                                            co([q[j][0], q[j][1]]),
                                            co([q[(j + 1) % 3][0], q[(j + 1) % 3][1]]),
                                            co([cx, cy]),
                                        ) >= 0.0
                                    })
                                })
                                .collect::<Vec<_>>()
                        },
                        tri.map(|v| o.pts[v as usize]),
                        c,
                        src.levels[l].tris.len(),
                        src.levels[l].num_void
                    );
                }
            }
        }
    }
    // heights: on A's and B's surfaces, from the inputs' own point
    // location, or (a point a rounding outside a tin's triangles) the
    // nearest of its triangles by brute force
    for (i, p) in o.pts.iter().enumerate() {
        for (src, l, z) in [(a, la, o.za[i]), (b, lb, o.zb[i])] {
            let t =
                locate::locate(src, l, p[0], p[1]).unwrap_or_else(|| nearest_triangle(src, l, *p));
            let zz = common::plane_height(&src.corners(l, t), p[0], p[1]);
            // a micrometre, or a hundred-millionth of the height: planes
            // through corners millions of metres from the origin round so
            assert!(
                (zz - z).abs() < 1e-6 + 1e-8 * z.abs(),
                "height {z} vs {zz} at {p:?}"
            );
        }
    }
}

/// The triangle of level `l` nearest `p` (0 inside it; else the distance
/// to its nearest side), by a scan of all of them.
fn nearest_triangle(t: &Tin, l: usize, p: P) -> u32 {
    let dist = |k: u32| {
        let c = t.corners(l, k).map(|v| [v[0], v[1]]);
        if in_closed(&c, p) {
            return 0.0;
        }
        (0..3)
            .map(|j| {
                let (u, v) = (c[j], c[(j + 1) % 3]);
                let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
                let s = (((p[0] - u[0]) * dx + (p[1] - u[1]) * dy) / (dx * dx + dy * dy))
                    .clamp(0.0, 1.0);
                (p[0] - u[0] - s * dx).hypot(p[1] - u[1] - s * dy)
            })
            .fold(f64::INFINITY, f64::min)
    };
    (0..t.levels[l].tris.len() as u32)
        .min_by(|&x, &y| dist(x).total_cmp(&dist(y)))
        .unwrap()
}

#[test]
fn overlay_of_different_tolerances_shares_vertices_and_edges() {
    // same samples, different tolerances: A's vertices are B's, many edges
    // coincide (collinear overlaps), the rest cross
    let a = tin(window(40, 60, 70, 0.0, 0.0, 0.0), &[8.0, 3.0]);
    let b = tin(window(40, 60, 70, 0.0, 0.0, 0.0), &[5.0, 1.5]);
    for (la, lb) in [(0, 0), (1, 1), (0, 1), (1, 0)] {
        let o = check(&a, la, &b, lb);
        assert!(o.crossings > 0);
    }
}

#[test]
fn overlay_of_a_shifted_copy_crosses_everywhere() {
    let a = tin(window(100, 100, 60, 0.0, 0.0, 0.0), &[6.0, 2.0]);
    let b = tin(window(100, 100, 60, 0.37, 0.61, 0.0), &[6.0, 2.0]);
    let o = check(&a, 1, &b, 1);
    assert!(o.crossings > a.levels[1].tris.len());
    // partial overlap: shifted by 25 pixels
    let c = tin(window(100, 100, 60, 25.0, 13.5, 0.0), &[6.0, 2.0]);
    check(&a, 1, &c, 0);
}

/// The oracle can fail: every crossing moved a millimetre off its edges
/// (the triangles around it still CCW) is caught, inside the domain by the
/// edge check, on its boundary by the area.
#[test]
fn the_overlay_oracle_catches_a_moved_crossing() {
    let a = tin(window(100, 100, 40, 0.0, 0.0, 0.0), &[6.0, 2.0]);
    let b = tin(window(100, 100, 40, 0.37, 0.61, 0.0), &[6.0, 2.0]);
    let o = overlay(&a, 1, &b, 1, &mut || Ok(())).unwrap();
    check_one(&a, 1, &b, 1, &o);
    let inputs: HashSet<(u64, u64)> = [(&a, 1), (&b, 1)]
        .iter()
        .flat_map(|(t, l)| level_pts(t, *l))
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    let mut caught = 0;
    let mut tried = 0;
    for (i, p) in o.pts.iter().enumerate() {
        if inputs.contains(&(p[0].to_bits(), p[1].to_bits())) {
            continue;
        }
        for shift in [[1e-3, 7e-4], [-8e-4, 1e-3]] {
            let mut moved = o.clone();
            moved.pts[i] = [p[0] + shift[0], p[1] + shift[1]];
            let still_ccw = moved.tris.iter().all(|t| {
                let c = t.map(|v| moved.pts[v as usize]);
                orient2d(co(c[0]), co(c[1]), co(c[2])) > 0.0
            });
            if !still_ccw {
                continue;
            }
            tried += 1;
            let r = std::panic::catch_unwind(|| check_one_with(&a, 1, &b, 1, &moved, false, false));
            if r.is_err() {
                caught += 1;
            }
        }
        if tried >= 20 {
            break;
        }
    }
    assert!(tried >= 10, "only {tried} moves kept the triangles CCW");
    assert_eq!(caught, tried, "the oracle missed a moved crossing");
}

/// A window of the DEM built between samples against its own pixels
/// (`tin_from_raster`'s build over the data), its grid moved by (dx, dy)
/// whole pixels: vertices where coarse edges cross grid lines, on the same
/// grid lines as any other build of the grid.
fn between(r0: usize, c0: usize, n: usize, dx: f64, dy: f64, tols: &[f64]) -> Tin {
    between_over(r0, c0, n, (dx, dy), tols, false)
}

/// [`between`], over the data alone when `data_only` (the valid pixels'
/// squares as the build's boundary, as `tin_from_raster(...,
/// fill_gaps => false)` builds): void triangles where the window has
/// nodata.
fn between_over(
    r0: usize,
    c0: usize,
    n: usize,
    (dx, dy): (f64, f64),
    tols: &[f64],
    data_only: bool,
) -> Tin {
    use tinmerge_core::tin::build::build_domain_raster;
    use tinmerge_core::tin::dense::Dense;
    use tinmerge_core::tin::domain::{cell_outline, outline_area};
    let dem = read_dem("jacksboro_fault_dem_utm16n.tif");
    let mut lat = dem.lattice();
    lat.ip_x += dx * lat.scale_x;
    lat.ip_y += dy * lat.scale_y;
    let mut z = Vec::with_capacity(n * n);
    let mut s = Vec::new();
    for r in r0..r0 + n {
        for c in c0..c0 + n {
            let v = dem.values[r * dem.width + c];
            let v = if Some(v) == dem.nodata { f64::NAN } else { v };
            z.push(v);
            if !v.is_nan() {
                let (x, y) = lat.centre(c as f64, r as f64);
                s.push([x, y, v]);
            }
        }
    }
    let heights = Dense {
        c0: c0 as i64,
        r0: r0 as i64,
        width: n,
        height: n,
        z,
    };
    let rings = cell_outline(n, n, &|c, r| !heights.z[r * n + c].is_nan());
    let area = outline_area(&rings, &|c, r| {
        let (x, y) = lat.centre(c0 as f64 + c - 0.5, r0 as f64 + r - 0.5);
        [x, y]
    });
    let boundary = if data_only { vec![&area] } else { vec![] };
    build_domain_raster(s, &[], &boundary, tols, 32616, &heights, &lat, &mut || {
        Ok(())
    })
    .unwrap()
}

/// Issue 43: two builds between samples of one grid (moved by whole
/// pixels, other tolerances) have vertices on the same grid lines a few
/// ulps apart, and crossings of their nearly collinear edges rounding onto
/// each other; spade's splitting insertion panicked on them until such
/// points were merged. Both paths, every pair of levels.
#[test]
fn overlay_of_builds_between_samples_on_one_grid() {
    let a = between(150, 150, 120, 0.0, 0.0, &[16.0, 4.0, 1.0]);
    let b = between(150, 150, 120, 4.0, -4.0, &[8.0, 2.0]);
    let c = between(150, 150, 120, 0.0, 0.0, &[6.0, 1.5]);
    for (x, y) in [(&a, &b), (&b, &a), (&a, &c)] {
        for la in 0..x.levels.len() {
            for lb in 0..y.levels.len() {
                let o = overlay_constrained(x, la, y, lb, &mut || Ok(())).unwrap();
                check_one(x, la, y, lb, &o);
                let o = overlay(x, la, y, lb, &mut || Ok(())).unwrap();
                check_one(x, la, y, lb, &o);
                assert_eq!(
                    o.fallback, None,
                    "levels {la}, {lb}: the faces path fell back"
                );
            }
        }
    }
}

/// Issue 47: two raster builds of the DEM whose grids are moved by a
/// fraction of a pixel (31 m and -17 m on the full DEM: 3.1 and -1.7 of
/// its 10 m pixels). Their edges run along the same directions, and an
/// edge of one passes within an ulp of vertices of the other: the
/// crossings there round on or around the vertex, and the faces path fell
/// back on the constrained triangulation (six times slower) for "face
/// vertices not in strict angular order", then "two faces disagree on
/// their common boundary" (a sliver face flat once rounded). Such
/// crossings are now the vertex itself. Every pair of levels, the faces
/// path, against the oracles.
#[test]
fn overlay_of_raster_builds_a_fraction_of_a_pixel_apart() {
    let a = between(200, 200, 100, 0.0, 0.0, &[8.0, 2.0]);
    let b = between(200, 200, 100, 3.1, -1.7, &[8.0, 2.0]);
    let c = between(200, 200, 100, 0.5, 0.5, &[4.0, 1.0]);
    for (x, y) in [(&a, &b), (&b, &a), (&a, &c)] {
        for la in 0..x.levels.len() {
            for lb in 0..y.levels.len() {
                let o = overlay(x, la, y, lb, &mut || Ok(())).unwrap();
                assert_eq!(
                    o.fallback, None,
                    "levels {la}, {lb}: the faces path fell back"
                );
                check_one(x, la, y, lb, &o);
                assert!(o.crossings > 0);
                // cut and fill against exact integration over the pairs of
                // input triangles
                let (want_cut, want_fill) = exact_cut_fill(x, la, y, lb);
                let scale = want_cut + want_fill;
                let (cut, fill, _) = difference(&o);
                assert!(
                    (cut - want_cut).abs() <= 1e-9 * scale
                        && (fill - want_fill).abs() <= 1e-9 * scale,
                    "levels {la}/{lb}: cut {cut} fill {fill}, exact {want_cut} {want_fill}"
                );
                let c = overlay_constrained(x, la, y, lb, &mut || Ok(())).unwrap();
                let (cc, cf, _) = difference(&c);
                eprintln!(
                    "levels {la}/{lb}: constrained path off by {:.3e} and {:.3e} of {scale:.3e}",
                    cc - want_cut,
                    cf - want_fill
                );
            }
        }
    }
}

/// The constrained path (what `overlay` falls back on when the faces path
/// refuses) on raster builds of the DEM's corner with its ragged nodata
/// border: void triangles, and an outer boundary that bends in by a
/// rounding, which the constrained triangulation fills with slivers
/// hundreds of metres long. Until 0.17.1 a crossing on such a sliver's
/// edge took its height from the line between that edge's ends, and a
/// point a rounding outside a tin from the hull triangle a walk left by,
/// kilometres away; the output heights were metres (on the full DEM,
/// hundreds of metres) off, and the cut of the shifted pair 15 million m³
/// (0.5 %) too large. Both paths, every pair of levels, against the
/// oracles and exact integration.
#[test]
fn constrained_overlay_with_void_triangles_against_exact_integration() {
    let a = between_over(0, 250, 94, (0.0, 0.0), &[8.0, 2.0], true);
    let b = between_over(0, 250, 94, (3.1, -1.7), &[8.0, 2.0], true);
    let c = between_over(0, 250, 94, (-0.4, 0.3), &[4.0, 1.0], true);
    for t in [&a, &b, &c] {
        assert!(t.levels.iter().all(|l| l.num_void > 0), "no void triangles");
    }
    for (x, y) in [(&a, &b), (&b, &a), (&a, &c)] {
        for la in 0..x.levels.len() {
            for lb in 0..y.levels.len() {
                let want = exact_difference(x, la, y, lb);
                for o in [
                    overlay_constrained(x, la, y, lb, &mut || Ok(())).unwrap(),
                    overlay(x, la, y, lb, &mut || Ok(())).unwrap(),
                ] {
                    let what = format!("levels {la}/{lb} ({:?})", o.fallback);
                    assert_difference(o.clone(), (x, la), (y, lb), &want, &what);
                    check_one(x, la, y, lb, &o);
                }
            }
        }
    }
}

/// The topology checks of [`check_one`] on the geographic DEM (degrees:
/// its thresholds scale by [`unit`]), both paths: other tolerances on the
/// same samples, a copy shifted by a fraction of a pixel, and one shifted
/// by 25 pixels (partial overlap). The faces path refused most of these
/// pairs until 0.16.0 ("face vertices not in strict angular order":
/// crossings rounding onto each other next to a vertex) and `overlay`
/// answered by the constrained path, about 4x slower; it is asserted now.
#[test]
fn overlay_on_the_geographic_dem() {
    let file = "jacksboro_fault_dem.tif";
    let geo = |dx: f64, dy: f64, tols: &[f64]| {
        build(
            window_of(file, 120, 150, 60, dx, dy, 0.0),
            tols,
            4326,
            &mut || Ok(()),
        )
        .unwrap()
    };
    let a = geo(0.0, 0.0, &[6.0, 2.0]);
    let b = geo(0.0, 0.0, &[4.0, 1.5]);
    let c = geo(0.37, 0.61, &[6.0, 2.0]);
    let d = geo(25.0, 13.5, &[6.0, 2.0]);
    for (x, la, y, lb) in [
        (&a, 0, &b, 0),
        (&a, 1, &b, 1),
        (&a, 0, &b, 1),
        (&a, 1, &c, 1),
        (&a, 1, &d, 0),
    ] {
        let o = overlay_constrained(x, la, y, lb, &mut || Ok(())).unwrap();
        check_one(x, la, y, lb, &o);
        let o = overlay(x, la, y, lb, &mut || Ok(())).unwrap();
        check_one(x, la, y, lb, &o);
        assert_eq!(o.fallback, None, "the faces path fell back");
        assert!(o.crossings > 0);
    }
}

/// A tin overlaid with itself at two levels (the generalisation error of
/// a level, as `tin_volume(t, t, polygon, 0, NULL)` measures it): each
/// level's edges run along its parents' within a few roundings
/// (`geom::BEND`), so a child edge and its coarse edge cross at points a
/// few nanometres apart; spade's splitting insertion routed such an edge
/// 7 cm off its line (harness seed 197197, kept by the harness's
/// `seeds_the_soaks_found_stay_fixed`; these windows pass with spade's
/// splitting too). Engine 2's builds of windows of both DEMs, on their own
/// grids and on 1/9" pixels with an origin of many digits, every pair of
/// levels, both paths, against the oracles.
#[test]
fn a_tin_overlaid_with_itself_at_two_levels() {
    use tinmerge_core::tin::construct::build_band;
    for (file, r0, c0, w, h, ninth) in [
        ("jacksboro_fault_dem_utm16n.tif", 125, 288, 50, 50, false),
        ("jacksboro_fault_dem_utm16n.tif", 300, 120, 70, 45, true),
        ("jacksboro_fault_dem.tif", 150, 200, 60, 55, false),
        ("jacksboro_fault_dem.tif", 40, 330, 45, 64, true),
    ] {
        let dem = read_dem(file);
        let mut lat = dem.lattice();
        if ninth {
            lat.ip_x = 162.8386382115849;
            lat.ip_y = 52.87551690288227;
            lat.scale_x = 1.0 / 32400.0;
            lat.scale_y = -1.0 / 32400.0;
        }
        let z: Vec<f64> = (r0..r0 + h)
            .flat_map(|r| (c0..c0 + w).map(move |c| (r, c)))
            .map(|(r, c)| dem.values[r * dem.width + c])
            .collect();
        let t = build_band(&z, w, h, &lat, &[12.0, 4.0, 1.5, 0.5], 4326, &mut || Ok(())).unwrap();
        for la in 0..t.levels.len() {
            for lb in 0..t.levels.len() {
                if la == lb {
                    continue;
                }
                let o = overlay_constrained(&t, la, &t, lb, &mut || Ok(())).unwrap();
                check_one_with(&t, la, &t, lb, &o, true, false);
                let o = overlay(&t, la, &t, lb, &mut || Ok(())).unwrap();
                check_one_with(
                    &t,
                    la,
                    &t,
                    lb,
                    &o,
                    o.fallback.is_some(),
                    o.fallback.is_none(),
                );
            }
        }
    }
}

/// A level the tin does not have is an error, not a panic (the SQL layer
/// resolves levels first; the core's callers need not).
#[test]
fn overlay_of_a_level_out_of_range_is_an_error() {
    let a = tin(window(10, 10, 30, 0.0, 0.0, 0.0), &[4.0, 2.0]);
    for (la, lb) in [(2, 0), (0, 2), (7, 9)] {
        for r in [
            overlay(&a, la, &a, lb, &mut || Ok(())),
            overlay_constrained(&a, la, &a, lb, &mut || Ok(())),
        ] {
            assert!(
                matches!(
                    r,
                    Err(tinmerge_core::tin::TinError::LevelOutOfRange { num_levels: 2, .. })
                ),
                "levels {la}/{lb}: {r:?}"
            );
        }
    }
}

#[test]
fn overlay_with_itself_is_itself() {
    let a = tin(window(10, 10, 50, 0.0, 0.0, 0.0), &[4.0, 2.0]);
    let o = check(&a, 1, &a, 1);
    assert_eq!(o.crossings, 0);
    assert_eq!(o.tris.len(), a.levels[1].tris.len());
    let (cut, fill, changed) = difference(&o);
    assert_eq!((cut, fill, changed), (0.0, 0.0, 0.0));
}

/// The linear function through a triangle's three corners, as
/// `(x, y) -> z` (`common::plane_height`: the tests' own, not the
/// extension's interpolation).
fn plane(c: [[f64; 3]; 3]) -> impl Fn(P) -> f64 {
    move |p: P| common::plane_height(&c, p[0], p[1])
}

/// The integral of the linear `f` over the part of the convex polygon
/// where `f >= 0`: the polygon cut at the zero line of `f` (by the values
/// at its corners), then a fan of triangles, each area times the mean of
/// its corners' values.
fn positive_integral(poly: &[P], f: &dyn Fn(P) -> f64) -> f64 {
    let mut cut: Vec<(P, f64)> = Vec::with_capacity(poly.len() + 2);
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            cut.push((p, fp));
        }
        if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
            let t = fp / (fp - fq);
            cut.push(([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])], 0.0));
        }
    }
    let mut total = 0.0;
    for k in 1..cut.len().saturating_sub(1) {
        let (a, b, c) = (cut[0], cut[k], cut[k + 1]);
        let area =
            ((b.0[0] - a.0[0]) * (c.0[1] - a.0[1]) - (c.0[0] - a.0[0]) * (b.0[1] - a.0[1])) / 2.0;
        total += area * (a.1 + b.1 + c.1) / 3.0;
    }
    total
}

/// Cut and fill of A over B by exact integration over every pair of
/// triangles that overlap: each of A's triangles clipped by each of B's
/// (the test's Sutherland-Hodgman), where both surfaces are linear, and
/// `max(zA - zB, 0)` and `max(zB - zA, 0)` integrated there exactly. No
/// code of the extension's overlay, location or interpolation.
fn exact_cut_fill(a: &Tin, la: usize, b: &Tin, lb: usize) -> (f64, f64) {
    let d = exact_difference(a, la, b, lb);
    (d.cut, d.fill)
}

/// What [`exact_difference`] finds.
struct Exact {
    cut: f64,
    fill: f64,
    /// area of the overlapping pairs whose planes differ by more than
    /// twice and by more than half `SAME_PLANE` (a pair between the two
    /// is on the fence, and rounding decides)
    changed_lo: f64,
    changed_hi: f64,
    /// area of all overlapping pairs (the common domain)
    area: f64,
}

/// Whether two triangles are one plane: each one's corners on the other's
/// plane within `k` times 1e-9 of their height (at least 1), `k` = 1 the
/// definition of `SAME_PLANE`, evaluated with the tests' own plane.
fn one_plane(ca: &[[f64; 3]; 3], cb: &[[f64; 3]; 3], k: f64) -> bool {
    let on = |p: &[f64; 3], c: &[[f64; 3]; 3]| {
        (common::plane_height(c, p[0], p[1]) - p[2]).abs() <= k * 1e-9 * p[2].abs().max(1.0)
    };
    ca.iter().all(|p| on(p, cb)) && cb.iter().all(|p| on(p, ca))
}

/// [`exact_cut_fill`], with the area where the surfaces differ (the pairs
/// of triangles that are not [`one_plane`]) and the area of the common
/// domain.
fn exact_difference(a: &Tin, la: usize, b: &Tin, lb: usize) -> Exact {
    let tris = |t: &Tin, l: usize| -> Vec<([[f64; 3]; 3], [f64; 4])> {
        let lv = &t.levels[l];
        (0..lv.tris.len() as u32 - lv.num_void)
            .map(|k| {
                let c = t.corners(l, k);
                let bb = [
                    c.iter().map(|p| p[0]).fold(f64::MAX, f64::min),
                    c.iter().map(|p| p[1]).fold(f64::MAX, f64::min),
                    c.iter().map(|p| p[0]).fold(f64::MIN, f64::max),
                    c.iter().map(|p| p[1]).fold(f64::MIN, f64::max),
                ];
                (c, bb)
            })
            .collect()
    };
    let (ta, mut tb) = (tris(a, la), tris(b, lb));
    // B's triangles by their boxes' west side, for a sweep along x
    tb.sort_by(|p, q| p.1[0].total_cmp(&q.1[0]));
    let widest = tb.iter().map(|t| t.1[2] - t.1[0]).fold(0.0, f64::max);
    let (mut cut, mut fill, mut total) = (0.0, 0.0, 0.0);
    let (mut changed_lo, mut changed_hi) = (0.0, 0.0);
    for (ca, ba) in &ta {
        let fa = plane(*ca);
        let from = tb.partition_point(|t| t.1[0] < ba[0] - widest);
        for (cb, bb) in tb[from..].iter().take_while(|t| t.1[0] <= ba[2]) {
            if bb[2] < ba[0] || bb[1] > ba[3] || bb[3] < ba[1] {
                continue;
            }
            let poly = clip(&ca.map(|p| [p[0], p[1]]), &cb.map(|p| [p[0], p[1]]));
            if poly.len() < 3 {
                continue;
            }
            let fb = plane(*cb);
            cut += positive_integral(&poly, &|p| fa(p) - fb(p));
            fill += positive_integral(&poly, &|p| fb(p) - fa(p));
            total += area(&poly);
            if !one_plane(ca, cb, 2.0) {
                changed_lo += area(&poly);
            }
            if !one_plane(ca, cb, 0.5) {
                changed_hi += area(&poly);
            }
        }
    }
    Exact {
        cut,
        fill,
        changed_lo,
        changed_hi,
        area: total,
    }
}

/// `difference` after `mark_same` against [`exact_difference`]: cut and
/// fill within 1e-9 of the volume moved, the changed area between the
/// pairs surely changed and those changed at all (1e-9 of the area).
fn assert_difference(
    o: Overlay,
    (x, la): (&Tin, usize),
    (y, lb): (&Tin, usize),
    want: &Exact,
    what: &str,
) {
    let scale = want.cut + want.fill;
    let (cut, fill, changed) = difference_marked(o, x, la, y, lb);
    assert!(
        (cut - want.cut).abs() <= 1e-9 * scale
            && (fill - want.fill).abs() <= 1e-9 * scale
            && changed >= want.changed_lo - 1e-9 * want.area
            && changed <= want.changed_hi + 1e-9 * want.area,
        "{what}: cut {cut} fill {fill} changed {changed}, exact {} {} {}..{} of {}",
        want.cut,
        want.fill,
        want.changed_lo,
        want.changed_hi,
        want.area
    );
}

/// `difference` after `mark_same`, as `tin_difference` computes it.
fn difference_marked(mut o: Overlay, a: &Tin, la: usize, b: &Tin, lb: usize) -> (f64, f64, f64) {
    mark_same(&mut o, a, la, b, lb);
    difference(&o)
}

/// `difference` (cut and fill over the overlay's faces) against
/// [`exact_cut_fill`] at 1e-9 of the volume moved: two epochs of each
/// bundled DEM (a coarser copy moved by a fraction of a pixel), every pair
/// of levels, and a tin against itself raised by 1 m.
#[test]
fn difference_against_exact_integration_on_both_dems() {
    for (file, srid) in [
        ("jacksboro_fault_dem_utm16n.tif", 32616),
        ("jacksboro_fault_dem.tif", 4326),
    ] {
        let build = |s: Vec<[f64; 3]>, tols: &[f64]| build(s, tols, srid, &mut || Ok(())).unwrap();
        let a = build(window_of(file, 200, 150, 70, 0.0, 0.0, 0.0), &[8.0, 2.0]);
        let b = build(window_of(file, 200, 150, 70, 0.31, 0.17, 0.0), &[6.0, 3.0]);
        let up = build(window_of(file, 200, 150, 70, 0.0, 0.0, 1.0), &[8.0, 2.0]);
        for (x, y, what) in [(&a, &b, "two epochs"), (&up, &a, "raised by 1 m")] {
            for la in 0..x.levels.len() {
                for lb in 0..y.levels.len() {
                    let want = exact_difference(x, la, y, lb);
                    for o in [
                        overlay(x, la, y, lb, &mut || Ok(())).unwrap(),
                        overlay_constrained(x, la, y, lb, &mut || Ok(())).unwrap(),
                    ] {
                        let label = format!("{file} {what} levels {la}/{lb}");
                        assert_difference(o, (x, la), (y, lb), &want, &label);
                    }
                    eprintln!(
                        "{file} {what} levels {la}/{lb}: cut {:.6e} fill {:.6e} changed {:.6e} of {:.6e}",
                        want.cut, want.fill, want.changed_lo, want.area
                    );
                }
            }
        }
    }
}

#[test]
fn difference_of_a_raised_copy_is_its_domain() {
    let a = tin(window(60, 60, 50, 0.0, 0.0, 0.0), &[3.0]);
    let raised = tin(window(60, 60, 50, 0.0, 0.0, 1.0), &[3.0]);
    let o = check(&raised, 0, &a, 0);
    let (cut, fill, changed) = difference(&o);
    let dom = hull(level_pts(&a, 0));
    let dom_area = area(&dom);
    assert!(
        (cut - dom_area).abs() <= 1e-9 * dom_area,
        "{cut} vs {dom_area}"
    );
    assert!(fill.abs() <= 1e-9 * dom_area);
    assert!((changed - dom_area).abs() <= 1e-9 * dom_area);
}

#[test]
fn interrupt_stops_the_overlay_and_its_panic_is_not_swallowed() {
    let a = tin(window(100, 100, 60, 0.0, 0.0, 0.0), &[2.0]);
    let b = tin(window(100, 100, 60, 0.37, 0.61, 0.0), &[2.0]);
    // an interrupt check that reports cancellation: the error comes back
    let r = overlay(&a, 0, &b, 0, &mut || {
        Err(tinmerge_core::tin::TinError::Interrupted)
    });
    assert!(matches!(r, Err(tinmerge_core::tin::TinError::Interrupted)));
    // one that unwinds (as the host's error handling does): it keeps
    // unwinding, it is not turned into an overlay error
    let r = std::panic::catch_unwind(|| overlay(&a, 0, &b, 0, &mut || panic!("cancelled")));
    assert!(r.is_err());
}

/// `tin_difference`'s changed area against [`exact_difference`]: two raster
/// builds of the DEM 40 m apart (0.444 of its 90 m pixels, as the
/// tutorial's pair), both one plane over ramps of the DEM. The heights at
/// crossings come from an edge of each tin and differ in their last bits
/// where the surfaces are one plane, and exact equality at the corners
/// counted 1,250 m² of this window as changed (the tutorial's whole DEM:
/// 17,600 to 44,000 m², depending on how the crossings' heights were
/// interpolated). `mark_same` decides by the planes.
#[test]
fn changed_area_where_the_surfaces_are_one_plane() {
    let a = between_over(100, 100, 150, (0.0, 0.0), &[8.0, 2.0], false);
    let b = between_over(100, 100, 150, (0.4444, 0.0), &[8.0], false);
    for la in 0..a.levels.len() {
        let want = exact_difference(&a, la, &b, 0);
        assert!(
            want.area - want.changed_lo > 1000.0,
            "no area where the planes agree"
        );
        for o in [
            overlay(&a, la, &b, 0, &mut || Ok(())).unwrap(),
            overlay_constrained(&a, la, &b, 0, &mut || Ok(())).unwrap(),
        ] {
            let (_, _, changed) = difference_marked(o, &a, la, &b, 0);
            assert!(
                changed >= want.changed_lo - 1e-9 * want.area
                    && changed <= want.changed_hi + 1e-9 * want.area,
                "level {la}: changed {changed}, exact {}..{}",
                want.changed_lo,
                want.changed_hi
            );
        }
    }
}

/// What [`exact_in`] finds inside one convex piece.
#[derive(Clone, Copy, Debug, Default)]
struct ExactIn {
    cut: f64,
    fill: f64,
    area_cut: f64,
    area_fill: f64,
    /// area of the pairs surely one plane (`one_plane` at half `SAME_PLANE`)
    area_same: f64,
    /// the pairs on the fence (one plane at twice `SAME_PLANE`, not at
    /// half): their area and the integral of |A - B| over them, which may
    /// count either way
    fence_area: f64,
    fence_volume: f64,
    /// the common domain's area inside the piece
    area: f64,
}

impl std::ops::AddAssign for ExactIn {
    fn add_assign(&mut self, o: ExactIn) {
        self.cut += o.cut;
        self.fill += o.fill;
        self.area_cut += o.area_cut;
        self.area_fill += o.area_fill;
        self.area_same += o.area_same;
        self.fence_area += o.fence_area;
        self.fence_volume += o.fence_volume;
        self.area += o.area;
    }
}

/// The area of the part of the convex polygon where the linear `f > 0`.
fn positive_area(poly: &[P], f: &dyn Fn(P) -> f64) -> f64 {
    // the integral of the indicator: the polygon cut at the zero line
    let mut cut: Vec<P> = Vec::with_capacity(poly.len() + 2);
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            cut.push(p);
        }
        if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
            let t = fp / (fp - fq);
            cut.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    area(&cut)
}

/// Cut, fill and their areas of A over B inside the convex CCW polygon
/// `piece`, by exact integration over every overlapping pair of triangles
/// clipped by the piece (the test's Sutherland-Hodgman); no code of the
/// extension's overlay or area merge.
fn exact_in(a: &Tin, la: usize, b: &Tin, lb: usize, piece: &[P]) -> ExactIn {
    let dom = |t: &Tin, l: usize| -> Vec<[[f64; 3]; 3]> {
        let lv = &t.levels[l];
        (0..lv.num_domain() as u32)
            .map(|k| t.corners(l, k))
            .collect()
    };
    let (ta, tb) = (dom(a, la), dom(b, lb));
    let bbox = |c: &[[f64; 3]; 3]| {
        [
            c.iter().map(|p| p[0]).fold(f64::MAX, f64::min),
            c.iter().map(|p| p[1]).fold(f64::MAX, f64::min),
            c.iter().map(|p| p[0]).fold(f64::MIN, f64::max),
            c.iter().map(|p| p[1]).fold(f64::MIN, f64::max),
        ]
    };
    let pb = [
        piece.iter().map(|p| p[0]).fold(f64::MAX, f64::min),
        piece.iter().map(|p| p[1]).fold(f64::MAX, f64::min),
        piece.iter().map(|p| p[0]).fold(f64::MIN, f64::max),
        piece.iter().map(|p| p[1]).fold(f64::MIN, f64::max),
    ];
    let meets =
        |x: &[f64; 4], y: &[f64; 4]| !(x[2] < y[0] || y[2] < x[0] || x[3] < y[1] || y[3] < x[1]);
    let tb: Vec<_> = tb
        .into_iter()
        .map(|c| (bbox(&c), c))
        .filter(|(bb, _)| meets(bb, &pb))
        .collect();
    let mut e = ExactIn::default();
    for ca in &ta {
        let ba = bbox(ca);
        if !meets(&ba, &pb) {
            continue;
        }
        let pa = clip(piece, &ca.map(|p| [p[0], p[1]]));
        if pa.len() < 3 {
            continue;
        }
        let fa = plane(*ca);
        for (bb, cb) in &tb {
            if !meets(&ba, bb) {
                continue;
            }
            let poly = clip(&pa, &cb.map(|p| [p[0], p[1]]));
            if poly.len() < 3 {
                continue;
            }
            let fb = plane(*cb);
            let d = |p: P| fa(p) - fb(p);
            let nd = |p: P| fb(p) - fa(p);
            let ar = area(&poly);
            e.area += ar;
            if one_plane(ca, cb, 0.5) {
                e.area_same += ar;
            } else if one_plane(ca, cb, 2.0) {
                e.fence_area += ar;
                e.fence_volume += positive_integral(&poly, &d) + positive_integral(&poly, &nd);
            } else {
                e.cut += positive_integral(&poly, &d);
                e.fill += positive_integral(&poly, &nd);
                e.area_cut += positive_area(&poly, &d);
                e.area_fill += positive_area(&poly, &nd);
            }
        }
    }
    e
}

/// `tin_volume(a, b, polygon)`'s core (`volumes_in`) against exact
/// integration inside polygons: convex ones inside the domain and across
/// its ragged nodata border (void triangles), an L (two rectangles sharing
/// an edge: the oracle sums them), two disjoint pieces (a MultiPolygon),
/// and a square with a square hole (the oracle: the outer minus the hole).
/// Both overlay paths, every pair of levels, a pair with void triangles and
/// a pair one plane over ramps (the unchanged area).
#[test]
fn volumes_between_two_surfaces_inside_polygons_against_exact_integration() {
    use tinmerge_core::merge::overlay::volume::volumes_in;
    use tinmerge_core::polygon::Area;
    let pairs = [
        (
            between_over(0, 250, 94, (0.0, 0.0), &[8.0, 2.0], true),
            between_over(0, 250, 94, (3.1, -1.7), &[8.0, 2.0], true),
        ),
        (
            between_over(100, 100, 150, (0.0, 0.0), &[8.0, 2.0], false),
            between_over(100, 100, 150, (0.4444, 0.0), &[8.0], false),
        ),
    ];
    let mut same_seen = 0.0;
    for (a, b) in &pairs {
        let bb = a.bbox;
        let (x0, y0, w, h) = (bb.min_x, bb.min_y, bb.max_x - bb.min_x, bb.max_y - bb.min_y);
        let at = |u: f64, v: f64| [x0 + u * w, y0 + v * h];
        let rect = |u0: f64, v0: f64, u1: f64, v1: f64| {
            vec![at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1)]
        };
        // (the polygon's rings, the convex pieces the oracle adds, and the
        // ones it takes away)
        type Case = (&'static str, Vec<Vec<Vec<P>>>, Vec<Vec<P>>, Vec<Vec<P>>);
        let l_shape = vec![
            at(0.2, 0.2),
            at(0.7, 0.2),
            at(0.7, 0.4),
            at(0.4, 0.4),
            at(0.4, 0.8),
            at(0.2, 0.8),
        ];
        let cases: Vec<Case> = vec![
            (
                "quad",
                vec![vec![vec![
                    at(0.2, 0.1),
                    at(0.8, 0.3),
                    at(0.7, 0.9),
                    at(0.1, 0.6),
                ]]],
                vec![vec![at(0.2, 0.1), at(0.8, 0.3), at(0.7, 0.9), at(0.1, 0.6)]],
                vec![],
            ),
            (
                "across the border",
                vec![vec![rect(-0.2, -0.1, 0.5, 0.45)]],
                vec![rect(-0.2, -0.1, 0.5, 0.45)],
                vec![],
            ),
            (
                "L",
                vec![vec![l_shape]],
                vec![rect(0.2, 0.2, 0.7, 0.4), rect(0.2, 0.4, 0.4, 0.8)],
                vec![],
            ),
            (
                "everything",
                vec![vec![rect(-0.1, -0.1, 1.1, 1.1)]],
                vec![rect(-0.1, -0.1, 1.1, 1.1)],
                vec![],
            ),
            (
                "two pieces",
                vec![
                    vec![rect(0.05, 0.05, 0.3, 0.3)],
                    vec![rect(0.6, 0.55, 0.95, 0.9)],
                ],
                vec![rect(0.05, 0.05, 0.3, 0.3), rect(0.6, 0.55, 0.95, 0.9)],
                vec![],
            ),
            (
                "with a hole",
                vec![vec![rect(0.1, 0.1, 0.9, 0.9), {
                    let mut hole = rect(0.3, 0.35, 0.6, 0.7);
                    hole.reverse();
                    hole
                }]],
                vec![rect(0.1, 0.1, 0.9, 0.9)],
                vec![rect(0.3, 0.35, 0.6, 0.7)],
            ),
        ];
        for (name, rings, plus, minus) in &cases {
            let area = Area::new(rings.clone());
            for la in 0..a.levels.len() {
                for lb in 0..b.levels.len() {
                    let mut want = ExactIn::default();
                    for p in plus {
                        want += exact_in(a, la, b, lb, p);
                    }
                    let mut gone = ExactIn::default();
                    for p in minus {
                        gone += exact_in(a, la, b, lb, p);
                    }
                    let sub = |x: f64, y: f64| x - y;
                    let w = ExactIn {
                        cut: sub(want.cut, gone.cut),
                        fill: sub(want.fill, gone.fill),
                        area_cut: sub(want.area_cut, gone.area_cut),
                        area_fill: sub(want.area_fill, gone.area_fill),
                        area_same: sub(want.area_same, gone.area_same),
                        fence_area: want.fence_area + gone.fence_area,
                        fence_volume: want.fence_volume + gone.fence_volume,
                        area: sub(want.area, gone.area),
                    };
                    assert!(w.area > 0.0, "{name}: nothing of the domain inside");
                    same_seen += w.area_same;
                    eprintln!(
                        "{name} {la}/{lb}: same {} fence {} area {}",
                        w.area_same, w.fence_area, w.area
                    );
                    for mut o in [
                        overlay(a, la, b, lb, &mut || Ok(())).unwrap(),
                        overlay_constrained(a, la, b, lb, &mut || Ok(())).unwrap(),
                    ] {
                        mark_same(&mut o, a, la, b, lb);
                        let what = format!("{name}, levels {la}/{lb} ({:?})", o.fallback);
                        let v = volumes_in(
                            &o,
                            &area,
                            a.srid,
                            tinmerge_core::geom::Units::Planar,
                            &mut || Ok(()),
                        )
                        .unwrap();
                        let vol = 1e-9 * (w.cut + w.fill).max(w.area) + w.fence_volume;
                        let ar = 1e-9 * w.area + w.fence_area;
                        assert!(
                            (v.cut - w.cut).abs() <= vol,
                            "{what}: cut {} want {}",
                            v.cut,
                            w.cut
                        );
                        assert!(
                            (v.fill - w.fill).abs() <= vol,
                            "{what}: fill {} want {}",
                            v.fill,
                            w.fill
                        );
                        assert!(
                            (v.area_cut - w.area_cut).abs() <= ar,
                            "{what}: area_cut {} want {}",
                            v.area_cut,
                            w.area_cut
                        );
                        assert!(
                            (v.area_fill - w.area_fill).abs() <= ar,
                            "{what}: area_fill {} want {}",
                            v.area_fill,
                            w.area_fill
                        );
                        assert!(
                            (v.area_unchanged - w.area_same).abs() <= ar,
                            "{what}: unchanged {} want {} (fence {})",
                            v.area_unchanged,
                            w.area_same,
                            w.fence_area
                        );
                        let total = v.area_cut + v.area_fill + v.area_unchanged;
                        assert!(
                            (total - w.area).abs() <= 1e-9 * w.area,
                            "{what}: areas sum to {total}, the domain inside is {}",
                            w.area
                        );
                    }
                }
            }
        }
    }
    assert!(
        same_seen > 1000.0,
        "no unchanged area in any case: {same_seen} m²"
    );
}
