//! The harness's verdicts, from the triangles' own coordinates and the
//! raster alone (nothing here calls the code under test): edges counted by
//! the bits of their ends, areas by the shoelace formula against the
//! domain's own (valid pixels counted, hulls by a monotone chain of this
//! file), nesting by exact orientation, the tolerance at every valid pixel
//! centre and wherever an edge crosses a grid segment between two valid
//! pixel centres, both found by this file's own scans.

use super::terrain::Raster;
use robust::{Coord, orient2d};
use std::collections::HashMap;
use tinmerge_core::tin::Tin;

pub type P = [f64; 2];

fn co(p: P) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

fn key(p: P) -> (u64, u64) {
    (p[0].to_bits(), p[1].to_bits())
}

/// What was checked, summed over a run.
#[derive(Default, Clone, Copy, Debug)]
pub struct Counts {
    pub levels: usize,
    pub triangles: usize,
    pub crossings: usize,
    pub centres: usize,
}

impl std::ops::AddAssign for Counts {
    fn add_assign(&mut self, o: Counts) {
        self.levels += o.levels;
        self.triangles += o.triangles;
        self.crossings += o.crossings;
        self.centres += o.centres;
    }
}

/// Convex hull (counter-clockwise) of points, by a monotone chain with
/// exact orientation.
pub fn hull(mut p: Vec<P>) -> Vec<P> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut h: Vec<P> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let pts: Vec<P> = if pass == 0 {
            p.clone()
        } else {
            p.iter().rev().copied().collect()
        };
        for q in pts {
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

/// A polygon's signed area (counter-clockwise positive), from its first
/// corner (so the size of the coordinates costs no precision).
pub fn area(poly: &[P]) -> f64 {
    let n = poly.len();
    let Some(&o) = poly.first() else { return 0.0 };
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1])
        })
        .sum::<f64>()
        / 2.0
}

fn tri_area(c: &[P; 3]) -> f64 {
    ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1])) / 2.0
}

/// A set of triangles (world coordinates) is one conforming triangulation
/// of a region without holes: every triangle counter-clockwise with a
/// smallest altitude of at least `min_alt`, every edge used once or by two
/// triangles in opposite directions, and the edges used once one cycle
/// (anything else is a crack: a T-junction, or two vertices a rounding
/// apart where there should be one). Returns the cycle's area.
pub fn conforming(tris: &[[P; 3]], min_alt: f64) -> Result<f64, String> {
    // each edge by its ends' bits: its uses one way and the other
    type Ends = ((u64, u64), (u64, u64));
    let mut edges: HashMap<Ends, (u32, u32)> = HashMap::new();
    for (t, c) in tris.iter().enumerate() {
        if orient2d(co(c[0]), co(c[1]), co(c[2])) <= 0.0 {
            return Err(format!("triangle {t} {c:?} is not counter-clockwise"));
        }
        let a2 = 2.0 * tri_area(c);
        let longest = (0..3)
            .map(|j| (c[j][0] - c[(j + 1) % 3][0]).hypot(c[j][1] - c[(j + 1) % 3][1]))
            .fold(0.0, f64::max);
        if a2 / longest < min_alt {
            return Err(format!(
                "triangle {t} {c:?} is a sliver (altitude {:.3e}, {:.3e} of the smallest side of a pixel)",
                a2 / longest,
                a2 / longest / min_alt * 1e-6
            ));
        }
        for j in 0..3 {
            let (u, v) = (key(c[j]), key(c[(j + 1) % 3]));
            let e = edges.entry((u.min(v), u.max(v))).or_default();
            if u < v { e.0 += 1 } else { e.1 += 1 }
        }
    }
    let mut next: HashMap<(u64, u64), (u64, u64)> = HashMap::new();
    for (&(a, b), &(f, r)) in &edges {
        let (s, e) = match (f, r) {
            (1, 1) => continue,
            (1, 0) => (a, b),
            (0, 1) => (b, a),
            _ => {
                return Err(format!(
                    "edge ({}, {})-({}, {}) used {f} times one way and {r} the other",
                    f64::from_bits(a.0),
                    f64::from_bits(a.1),
                    f64::from_bits(b.0),
                    f64::from_bits(b.1)
                ));
            }
        };
        if next.insert(s, e).is_some() {
            return Err(format!(
                "two boundary edges start at ({}, {})",
                f64::from_bits(s.0),
                f64::from_bits(s.1)
            ));
        }
    }
    let Some(&start) = next.keys().next() else {
        return Err("no boundary".into());
    };
    let (mut cur, mut n) = (start, 0usize);
    let mut cycle: Vec<P> = Vec::new();
    loop {
        let Some(&nx) = next.get(&cur) else {
            return Err("the boundary is not closed".into());
        };
        cycle.push([f64::from_bits(cur.0), f64::from_bits(cur.1)]);
        n += 1;
        cur = nx;
        if cur == start || n > next.len() {
            break;
        }
    }
    if n != next.len() {
        return Err(format!(
            "a crack: {} edges used once make more than one cycle (the outer one has {n}; \
             the others are gaps between triangles that should meet)",
            next.len()
        ));
    }
    Ok(area(&cycle))
}

pub fn corners(t: &Tin, l: usize, k: usize) -> [[f64; 3]; 3] {
    t.levels[l].tris[k].map(|v| t.verts[v as usize])
}

fn xy(c: &[[f64; 3]; 3]) -> [P; 3] {
    c.map(|v| [v[0], v[1]])
}

/// What a tin's domain must be, checked against the area of its
/// non-void triangles (relative 1e-9).
pub enum Domain {
    /// an area computed independently
    Area(f64),
    /// not known to the harness (a user boundary): the void and non-void
    /// triangles together are checked only
    Unknown,
}

/// How far (times the edge's length) a point may be beside the edge u-v
/// and still be taken as on it: four of the build's roundings of an
/// orientation, 64 units in the last place of the largest coordinate
/// times the sum of the three sides (each its larger coordinate
/// difference). A sample that near a coarse edge is put on it, as a
/// crossing on it is within rounding of it (harness seeds 143164,
/// 158431): up to 2e-11 degree or 0.6 um at UTM northings.
fn bent(u: P, v: P, q: P) -> f64 {
    let m = [u, v, q]
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let d = |a: P, b: P| (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
    4.0 * 64.0 * f64::EPSILON * m * (d(u, v) + d(v, q) + d(q, u))
}

/// Every structural verdict on one tin: each level conforming, the
/// triangles (void included) covering the convex hull of its vertices,
/// the non-void ones the expected domain, each triangle inside its parent
/// (exact orientation, up to `slack` world units for a lattice build's
/// rounding or [`bent`] of a side) and the children of each triangle
/// covering it. No triangle
/// is thinner than `thin` of `unit` (a pixel: see the harness's module
/// doc for which builds are held to what).
pub fn check_tin(t: &Tin, dom: &Domain, unit: f64, thin: f64) -> Result<Counts, String> {
    let (min_alt, slack) = (thin * unit, 1e-7 * unit);
    let mut n = Counts::default();
    let hull_area = area(&hull(t.verts.iter().map(|v| [v[0], v[1]]).collect()));
    // the rounding of a sum of `k` triangles' areas: each coordinate
    // difference is off by an ulp of the coordinates' magnitude
    let m = [t.bbox.min_x, t.bbox.max_x, t.bbox.min_y, t.bbox.max_y]
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let near = |a: f64, b: f64, k: usize| {
        (a - b).abs() <= 1e-9 * a.abs().max(b.abs()) + k as f64 * 64.0 * f64::EPSILON * m * unit
    };
    for (l, lv) in t.levels.iter().enumerate() {
        let all: Vec<[P; 3]> = (0..lv.tris.len()).map(|k| xy(&corners(t, l, k))).collect();
        let a = conforming(&all, min_alt).map_err(|e| format!("level {l}: {e}"))?;
        if !near(a, hull_area, all.len()) {
            return Err(format!(
                "level {l}: the triangles cover {a}, the hull of the vertices {hull_area}"
            ));
        }
        let num_domain = lv.tris.len() - lv.num_void as usize;
        let dom_area: f64 = all[..num_domain].iter().map(tri_area).sum();
        if let Domain::Area(want) = dom
            && !near(dom_area, *want, all.len())
        {
            return Err(format!(
                "level {l}: the domain's triangles cover {dom_area}, the domain is {want}"
            ));
        }
        if l > 0 {
            let mut child_area = vec![0.0; t.levels[l - 1].tris.len()];
            for (k, c) in all.iter().enumerate() {
                let p = lv.parent[k] as usize;
                let pc = xy(&corners(t, l - 1, p));
                child_area[p] += tri_area(c);
                for q in c {
                    for j in 0..3 {
                        let (u, v) = (pc[j], pc[(j + 1) % 3]);
                        let len = (v[0] - u[0]).hypot(v[1] - u[1]);
                        let d = orient2d(co(u), co(v), co(*q)) / len;
                        if d < -slack.max(bent(u, v, *q) / len) {
                            return Err(format!(
                                "level {l}: triangle {k} pokes {:.3e} out of its parent {p}",
                                -d
                            ));
                        }
                    }
                }
            }
            let mut children = vec![0usize; child_area.len()];
            for &p in &lv.parent {
                children[p as usize] += 1;
            }
            for (p, &ca) in child_area.iter().enumerate() {
                let pc = xy(&corners(t, l - 1, p));
                let pa = tri_area(&pc);
                // each child corner bent outside (or a neighbour's
                // inside) by up to `bent` of a side moves the area by
                // half that times the side (harness seed 202371: a
                // needle parent whose children cover 3.2e-5 of it less)
                let bends: f64 = (0..3)
                    .map(|j| bent(pc[j], pc[(j + 1) % 3], pc[(j + 2) % 3]) / 2.0)
                    .fold(0.0, f64::max);
                if !near(ca, pa, 16) && (ca - pa).abs() > children[p] as f64 * bends {
                    return Err(format!(
                        "level {}: the children of triangle {p} cover {ca} of its {pa}",
                        l - 1
                    ));
                }
            }
        }
        n.levels += 1;
        n.triangles += lv.tris.len();
    }
    Ok(n)
}

/// A level's height at point `q` from triangles (with heights): the
/// smallest error against `z` over the triangles that hold `q` (up to
/// `slack` of distance, in the triangles' units: on the lattice 1e-7
/// pixel, the rounding of the world coordinates the lattice coordinates
/// were recovered from), None if none does.
pub fn error_at(tris: &[[[f64; 3]; 3]], cand: &[u32], q: P, z: f64, slack: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for &k in cand {
        let c = &tris[k as usize];
        let d =
            (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
        // signed distance (pixels) of q inside each side
        let inside = (0..3).all(|j| {
            let (a, b) = (c[j], c[(j + 1) % 3]);
            let o = (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
            o * d.signum() / (b[0] - a[0]).hypot(b[1] - a[1]) >= -slack
        });
        if !inside {
            continue;
        }
        let b1 =
            ((q[0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (q[1] - c[0][1])) / d;
        let b2 =
            ((c[1][0] - c[0][0]) * (q[1] - c[0][1]) - (q[0] - c[0][0]) * (c[1][1] - c[0][1])) / d;
        let h = (1.0 - b1 - b2) * c[0][2] + b1 * c[1][2] + b2 * c[2][2];
        let err = (h - z).abs();
        best = Some(best.map_or(err, |b: f64| b.min(err)));
    }
    best
}

/// The tolerance of every level on the raster's surface: at every valid
/// pixel centre in the level's domain and, unless `samples_only`, at
/// every crossing of a domain triangle's edge with a grid segment between
/// two valid pixel centres (the segment's straight line between them), up
/// to rounding. `covered`: every valid centre must lie in the domain.
pub fn check_tolerance(
    t: &Tin,
    r: &Raster,
    samples_only: bool,
    covered: bool,
) -> Result<Counts, String> {
    let mut n = Counts::default();
    let zspan = (t.bbox.max_z - t.bbox.min_z).abs().max(1.0);
    for (l, lv) in t.levels.iter().enumerate() {
        let tol = lv.tolerance * (1.0 + 1e-9) + 1e-9 * zspan;
        let num_domain = lv.tris.len() - lv.num_void as usize;
        let tris: Vec<[[f64; 3]; 3]> = (0..num_domain)
            .map(|k| {
                corners(t, l, k).map(|v| {
                    let q = r.lattice_of(&v);
                    [q[0], q[1], v[2]]
                })
            })
            .collect();
        // a bucket of triangles per pixel row
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); r.h + 1];
        for (k, c) in tris.iter().enumerate() {
            let lo = c.iter().map(|v| v[1]).fold(f64::INFINITY, f64::min);
            let hi = c.iter().map(|v| v[1]).fold(f64::NEG_INFINITY, f64::max);
            let (a, b) = (
                (lo - 1e-6).floor().max(0.0) as usize,
                ((hi + 1e-6).ceil().max(0.0) as usize).min(r.h),
            );
            for row in rows.iter_mut().take(b + 1).skip(a) {
                row.push(k as u32);
            }
        }
        for (row, cand) in rows.iter().enumerate().take(r.h) {
            for col in 0..r.w {
                let Some(z) = r.at(col as i64, row as i64) else {
                    continue;
                };
                match error_at(&tris, cand, [col as f64, row as f64], z, 1e-7) {
                    Some(e) if e > tol => {
                        return Err(format!(
                            "level {l} (tolerance {}): pixel ({col}, {row}) is {e} off",
                            lv.tolerance
                        ));
                    }
                    None if covered => {
                        return Err(format!(
                            "level {l}: valid pixel ({col}, {row}) is in no triangle of the domain"
                        ));
                    }
                    _ => n.centres += 1,
                }
            }
        }
        if samples_only {
            continue;
        }
        // every edge's crossings with the grid lines, in lattice terms
        let mut seen = std::collections::HashSet::new();
        for c in &tris {
            for j in 0..3 {
                let (a, b) = (c[j], c[(j + 1) % 3]);
                let k = (
                    a[0].to_bits(),
                    a[1].to_bits(),
                    b[0].to_bits(),
                    b[1].to_bits(),
                );
                let kr = (k.2, k.3, k.0, k.1);
                if !seen.insert(k.min(kr)) {
                    continue;
                }
                for axis in 0..2 {
                    let (u0, u1) = (a[axis], b[axis]);
                    let (lo, hi) = (u0.min(u1), u0.max(u1));
                    let mut line = lo.ceil();
                    while line <= hi {
                        let s = (line - u0) / (u1 - u0);
                        if !(0.0..=1.0).contains(&s) || u1 == u0 {
                            line += 1.0;
                            continue;
                        }
                        let o = a[1 - axis] + s * (b[1 - axis] - a[1 - axis]);
                        let (o0, f) = (o.floor(), o - o.floor());
                        let (p0, p1) = if axis == 0 {
                            ((line as i64, o0 as i64), (line as i64, o0 as i64 + 1))
                        } else {
                            ((o0 as i64, line as i64), (o0 as i64 + 1, line as i64))
                        };
                        if let (Some(z0), Some(z1)) = (r.at(p0.0, p0.1), r.at(p1.0, p1.1)) {
                            let want = z0 + f * (z1 - z0);
                            let got = a[2] + s * (b[2] - a[2]);
                            // a crossing within rounding of a pixel centre
                            // is that centre (measured above)
                            if (got - want).abs() > tol && f > 1e-6 && f < 1.0 - 1e-6 {
                                return Err(format!(
                                    "level {l} (tolerance {}): the edge ({:.9}, {:.9})-({:.9}, {:.9}) \
                                     crosses the grid segment ({}, {})-({}, {}) {} off",
                                    lv.tolerance,
                                    a[0],
                                    a[1],
                                    b[0],
                                    b[1],
                                    p0.0,
                                    p0.1,
                                    p1.0,
                                    p1.1,
                                    (got - want).abs()
                                ));
                            }
                            n.crossings += 1;
                        }
                        line += 1.0;
                    }
                }
            }
        }
    }
    Ok(n)
}

/// Tiles of one raster: each one's structure ([`check_tin`]) and
/// tolerance at the samples (the strips along the seams are held there
/// only), and their seams ([`check_seams`]).
pub fn check_tiles(tiles: &[Tin], r: &Raster, unit: f64) -> Result<Counts, String> {
    let mut n = Counts::default();
    for (i, t) in tiles.iter().enumerate() {
        n += check_tin(t, &Domain::Unknown, unit, crate::harness::LATTICE_THIN)
            .map_err(|e| format!("tile {i}: {e}"))?;
        n += check_tolerance(t, r, true, false).map_err(|e| format!("tile {i}: {e}"))?;
    }
    check_seams(&tiles.iter().collect::<Vec<_>>())?;
    Ok(n)
}

/// Tins meant to meet along their seams (tiles) meet there: at every level
/// an edge on the outside of one tile that lies inside another tile's
/// domain (its midpoint strictly inside one of its triangles, or on one of
/// its edges that is not the same edge) is a crack across the seam.
pub fn check_seams(tiles: &[&Tin]) -> Result<(), String> {
    let levels = tiles.iter().map(|t| t.levels.len()).min().unwrap_or(0);
    for l in 0..levels {
        // every tile's triangles, bucketed on a coarse grid
        let all: Vec<(usize, [P; 3])> = tiles
            .iter()
            .enumerate()
            .flat_map(|(i, t)| (0..t.levels[l].tris.len()).map(move |k| (i, xy(&corners(t, l, k)))))
            .collect();
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        for (_, c) in &all {
            for p in c {
                (x0, y0, x1, y1) = (x0.min(p[0]), y0.min(p[1]), x1.max(p[0]), y1.max(p[1]));
            }
        }
        let nb = 64usize;
        let (cw, ch) = ((x1 - x0) / nb as f64, (y1 - y0) / nb as f64);
        let cell = |p: P| {
            (
                (((p[0] - x0) / cw) as usize).min(nb - 1),
                (((p[1] - y0) / ch) as usize).min(nb - 1),
            )
        };
        let mut grid: Vec<Vec<u32>> = vec![Vec::new(); nb * nb];
        for (k, (_, c)) in all.iter().enumerate() {
            let (a, b) = (
                cell([
                    c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
                    c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
                ]),
                cell([
                    c.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
                    c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
                ]),
            );
            for gy in a.1..=b.1 {
                for gx in a.0..=b.0 {
                    grid[gy * nb + gx].push(k as u32);
                }
            }
        }
        // each tile's outside edges
        for (i, t) in tiles.iter().enumerate() {
            let lv = &t.levels[l];
            for (k, nbrs) in lv.nbrs.iter().enumerate() {
                for j in 0..3 {
                    if nbrs[j] != tinmerge_core::tin::NONE {
                        continue;
                    }
                    let c = xy(&corners(t, l, k));
                    let (p, q) = (c[(j + 1) % 3], c[(j + 2) % 3]);
                    let m = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                    let (gx, gy) = cell(m);
                    let others = || {
                        grid[gy * nb + gx]
                            .iter()
                            .map(|&o| &all[o as usize])
                            .filter(|(oi, _)| *oi != i)
                    };
                    let shared = others().any(|(_, oc)| {
                        (0..3).any(|e| key(oc[e]) == key(q) && key(oc[(e + 1) % 3]) == key(p))
                    });
                    if shared {
                        continue;
                    }
                    for (oi, oc) in others() {
                        let eps = 1e-9 * (q[0] - p[0]).hypot(q[1] - p[1]);
                        let held = (0..3).all(|e| {
                            let (u, v) = (oc[e], oc[(e + 1) % 3]);
                            orient2d(co(u), co(v), co(m)) / (v[0] - u[0]).hypot(v[1] - u[1]) >= -eps
                        });
                        if held {
                            return Err(format!(
                                "level {l}: tile {i}'s outside edge {p:?}-{q:?} has its middle in tile {oi}'s triangle {oc:?}, which does not share it: a crack across the seam"
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
