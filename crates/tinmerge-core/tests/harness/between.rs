//! Point builds between their samples: scattered samples of a trial's
//! terrain ([`samples`]: the pixel centres moved, uniform points, a
//! LiDAR-like cloud), and the oracle that holds every level to its
//! tolerance on the samples' own surface ([`check_between`]).
//!
//! Scattered samples say nothing of the ground between them but what a
//! triangulation of them says: the reference is their Delaunay
//! triangulation, made here by `delaunator` (not spade, which the build
//! uses). A level and the reference are both linear in each of their
//! triangles, so the level's error is largest at a sample, at a vertex of
//! the level that is not a sample, or where an edge of the level crosses
//! an edge of the reference: all three are checked (what
//! `tests/properties/check_points_between.py` checks in SQL on the two
//! whole DEMs, here on random windows and lattices).

use super::oracle::{Counts, corners, error_at};
use super::terrain::Raster;
use rand::Rng;
use rand::rngs::StdRng;
use std::collections::{HashMap, HashSet};
use tinmerge_core::tin::Tin;

/// One of three clouds of samples of `r` (world coordinates and heights)
/// and what it is: every valid pixel centre moved by up to a tenth of a
/// pixel (a grid's own points are cocircular, and no Delaunay
/// triangulation of them is *the* one); uniform points, heights bilinear
/// between the centres; or scan lines four pixels apart, slanted, dense
/// along the line, with 5 cm of noise.
pub fn samples(rng: &mut StdRng, r: &Raster) -> (Vec<[f64; 3]>, &'static str) {
    // bilinear between the four centres around lattice point (c, q)
    let height = |c: f64, q: f64| -> Option<f64> {
        let (c0, q0) = (c.floor(), q.floor());
        let (fc, fq) = (c - c0, q - q0);
        let (c0, q0) = (c0 as i64, q0 as i64);
        let z00 = r.at(c0, q0)?;
        let z10 = r.at(c0 + 1, q0)?;
        let z01 = r.at(c0, q0 + 1)?;
        let z11 = r.at(c0 + 1, q0 + 1)?;
        Some((1.0 - fq) * ((1.0 - fc) * z00 + fc * z10) + fq * ((1.0 - fc) * z01 + fc * z11))
    };
    let at = |c: f64, q: f64, z: f64| {
        let p = r.world(c, q);
        [p[0], p[1], z]
    };
    let (w, h) = (r.w as f64, r.h as f64);
    let mut pts = Vec::new();
    match rng.random_range(0..3) {
        0 => {
            for row in 0..r.h {
                for col in 0..r.w {
                    let (dc, dq) = (rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1));
                    if let Some(z) = r.at(col as i64, row as i64) {
                        pts.push(at(col as f64 + dc, row as f64 + dq, z));
                    }
                }
            }
            (
                pts,
                "the valid pixel centres moved by up to a tenth of a pixel",
            )
        }
        1 => {
            let n = (r.valid() as f64 * rng.random_range(0.2..1.0)) as usize;
            for _ in 0..n {
                let (c, q) = (
                    rng.random_range(0.0..w - 1.0),
                    rng.random_range(0.0..h - 1.0),
                );
                if let Some(z) = height(c, q) {
                    pts.push(at(c, q, z));
                }
            }
            (pts, "uniform samples, heights bilinear between the centres")
        }
        _ => {
            let along = (w * 4.0) as usize;
            let mut q0 = 2.0;
            while q0 < h {
                for k in 0..along {
                    let t = k as f64 / along as f64;
                    let c = t * (w - 1.0) + rng.random_range(0.0..0.05);
                    let q = q0 + t * 3.0 + rng.random_range(-0.15..0.15);
                    if let Some(z) = height(c, q) {
                        pts.push(at(c, q, z + rng.random_range(-0.05..0.05)));
                    }
                }
                q0 += 4.0;
            }
            (
                pts,
                "a LiDAR-like cloud: slanted scan lines four pixels apart",
            )
        }
    }
}

/// A point by its (x, y) bits.
type Key = (u64, u64);

/// Buckets of a uniform grid over a box: what each cell holds.
struct Cells {
    x0: f64,
    y0: f64,
    size: f64,
    nx: usize,
    ny: usize,
    items: Vec<Vec<u32>>,
}

impl Cells {
    fn new(lo: [f64; 2], hi: [f64; 2], n: usize) -> Cells {
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        let side = (n as f64).sqrt().clamp(1.0, 2048.0);
        let size = span / side;
        let nx = ((hi[0] - lo[0]) / size) as usize + 1;
        let ny = ((hi[1] - lo[1]) / size) as usize + 1;
        Cells {
            x0: lo[0],
            y0: lo[1],
            size,
            nx,
            ny,
            items: vec![Vec::new(); nx * ny],
        }
    }
    fn cell(&self, x: f64, y: f64) -> (usize, usize) {
        let cx = ((x - self.x0) / self.size)
            .floor()
            .clamp(0.0, (self.nx - 1) as f64);
        let cy = ((y - self.y0) / self.size)
            .floor()
            .clamp(0.0, (self.ny - 1) as f64);
        (cx as usize, cy as usize)
    }
    /// The cells a box (grown by a cell's hundredth) touches.
    fn in_box(&self, lo: [f64; 2], hi: [f64; 2]) -> impl Iterator<Item = usize> + '_ {
        let e = 0.01 * self.size;
        let (a, b) = (
            self.cell(lo[0] - e, lo[1] - e),
            self.cell(hi[0] + e, hi[1] + e),
        );
        (a.1..=b.1).flat_map(move |y| (a.0..=b.0).map(move |x| y * self.nx + x))
    }
    fn add_box(&mut self, lo: [f64; 2], hi: [f64; 2], id: u32) {
        let cells: Vec<usize> = self.in_box(lo, hi).collect();
        for c in cells {
            self.items[c].push(id);
        }
    }
    /// The cells a segment passes through (and their neighbours in x).
    fn along(&self, a: [f64; 2], b: [f64; 2]) -> Vec<usize> {
        let (lo, hi) = (a[1].min(b[1]), a[1].max(b[1]));
        let (r0, r1) = (self.cell(a[0], lo).1, self.cell(a[0], hi).1);
        let mut out = Vec::new();
        for row in r0..=r1 {
            // the segment's x range within this row's band
            let (y0, y1) = (
                self.y0 + row as f64 * self.size,
                self.y0 + (row + 1) as f64 * self.size,
            );
            let xs = if a[1] == b[1] {
                (a[0].min(b[0]), a[0].max(b[0]))
            } else {
                let t = |y: f64| ((y - a[1]) / (b[1] - a[1])).clamp(0.0, 1.0);
                let (xa, xb) = (a[0] + t(y0) * (b[0] - a[0]), a[0] + t(y1) * (b[0] - a[0]));
                (xa.min(xb), xa.max(xb))
            };
            let (c0, c1) = (self.cell(xs.0, y0).0, self.cell(xs.1, y0).0);
            for col in c0.saturating_sub(1)..=(c1 + 1).min(self.nx - 1) {
                out.push(row * self.nx + col);
            }
        }
        out
    }
}

/// Where segment `a`-`b` crosses `p`-`q` properly: the parameters along
/// each (exact orientation decides that they cross).
fn crossing(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3], q: &[f64; 3]) -> Option<(f64, f64)> {
    let o = |u: &[f64; 3], v: &[f64; 3], w: &[f64; 3]| {
        robust::orient2d(
            robust::Coord { x: u[0], y: u[1] },
            robust::Coord { x: v[0], y: v[1] },
            robust::Coord { x: w[0], y: w[1] },
        )
    };
    let (op, oq) = (o(a, b, p), o(a, b, q));
    let (oa, ob) = (o(p, q, a), o(p, q, b));
    if !(op * oq < 0.0 && oa * ob < 0.0) {
        return None;
    }
    Some((oa / (oa - ob), op / (op - oq)))
}

/// Every level of the point build `t` of `pts` within its tolerance of
/// the samples' Delaunay surface (plus a billionth, relative, for
/// rounding): at every sample, every vertex that is not one, and every
/// crossing of the level's edges with the reference's.
pub fn check_between(t: &Tin, pts: &[[f64; 3]]) -> Result<Counts, String> {
    let mut n = Counts::default();
    let dp: Vec<delaunator::Point> = pts
        .iter()
        .map(|p| delaunator::Point { x: p[0], y: p[1] })
        .collect();
    let dt = delaunator::triangulate(&dp);
    if dt.is_empty() {
        return Ok(n);
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let bbox = |c: &[[f64; 3]]| {
        let mut l = [f64::INFINITY; 2];
        let mut h = [f64::NEG_INFINITY; 2];
        for v in c {
            for k in 0..2 {
                l[k] = l[k].min(v[k]);
                h[k] = h[k].max(v[k]);
            }
        }
        (l, h)
    };
    // the reference: its triangles and its edges (each once), in cells
    let rtris: Vec<[[f64; 3]; 3]> = dt
        .triangles
        .chunks(3)
        .map(|c| [pts[c[0]], pts[c[1]], pts[c[2]]])
        .collect();
    let mut redges = Vec::new();
    for e in 0..dt.triangles.len() {
        let o = dt.halfedges[e];
        if o == delaunator::EMPTY || e < o {
            let (a, b) = (dt.triangles[e], dt.triangles[delaunator::next_halfedge(e)]);
            redges.push([pts[a], pts[b]]);
        }
    }
    let mut rt_cells = Cells::new(lo, hi, rtris.len());
    for (k, c) in rtris.iter().enumerate() {
        let (l, h) = bbox(c);
        rt_cells.add_box(l, h, k as u32);
    }
    let mut re_cells = Cells::new(lo, hi, redges.len());
    for (k, e) in redges.iter().enumerate() {
        let (l, h) = bbox(e);
        re_cells.add_box(l, h, k as u32);
    }
    let is_sample: HashSet<(u64, u64)> = pts
        .iter()
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    let zspan = (t.bbox.max_z - t.bbox.min_z).abs().max(1.0);
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    // a point on an edge up to rounding is in the triangle: a billionth of
    // the samples' extent (far above a coordinate's rounding)
    let slack = 1e-9 * span;
    for (l, lv) in t.levels.iter().enumerate() {
        let tol = lv.tolerance * (1.0 + 1e-9) + 1e-9 * zspan;
        let over = |what: String, e: f64| {
            format!(
                "level {l} (tolerance {}): {what} is {e} m off the samples' Delaunay surface",
                lv.tolerance
            )
        };
        let num_domain = lv.tris.len() - lv.num_void as usize;
        let tris: Vec<[[f64; 3]; 3]> = (0..num_domain).map(|k| corners(t, l, k)).collect();
        let mut lt_cells = Cells::new(lo, hi, tris.len());
        for (k, c) in tris.iter().enumerate() {
            let (l, h) = bbox(c);
            lt_cells.add_box(l, h, k as u32);
        }
        // every sample
        for p in pts {
            let c = lt_cells.cell(p[0], p[1]);
            let cand = &lt_cells.items[c.1 * lt_cells.nx + c.0];
            match error_at(&tris, cand, [p[0], p[1]], p[2], slack) {
                Some(e) if e > tol => {
                    return Err(over(format!("the sample ({:?}, {:?})", p[0], p[1]), e));
                }
                Some(_) => n.centres += 1,
                None => {
                    return Err(format!(
                        "level {l}: the sample ({:?}, {:?}) is in no triangle of the domain",
                        p[0], p[1]
                    ));
                }
            }
        }
        // every vertex that is not a sample, and every edge's crossings
        let mut edges: HashMap<(Key, Key), [[f64; 3]; 2]> = HashMap::new();
        for c in &tris {
            for j in 0..3 {
                let (a, b) = (c[j], c[(j + 1) % 3]);
                let (ka, kb) = (
                    (a[0].to_bits(), a[1].to_bits()),
                    (b[0].to_bits(), b[1].to_bits()),
                );
                edges.insert((ka.min(kb), ka.max(kb)), [a, b]);
            }
        }
        let mut seen_v = HashSet::new();
        for [a, b] in edges.values() {
            for v in [a, b] {
                let k = (v[0].to_bits(), v[1].to_bits());
                if is_sample.contains(&k) || !seen_v.insert(k) {
                    continue;
                }
                let c = rt_cells.cell(v[0], v[1]);
                let cand = &rt_cells.items[c.1 * rt_cells.nx + c.0];
                // a vertex a rounding outside the hull: nothing to compare
                if let Some(e) = error_at(&rtris, cand, [v[0], v[1]], v[2], slack)
                    && e > tol
                {
                    return Err(over(format!("the vertex ({:?}, {:?})", v[0], v[1]), e));
                }
            }
            let mut seen_e = HashSet::new();
            for c in re_cells.along([a[0], a[1]], [b[0], b[1]]) {
                for &k in &re_cells.items[c] {
                    if !seen_e.insert(k) {
                        continue;
                    }
                    let [p, q] = &redges[k as usize];
                    let Some((s, u)) = crossing(a, b, p, q) else {
                        continue;
                    };
                    // within rounding of a sample or of a vertex: measured there
                    let (la, lr) = (
                        (b[0] - a[0]).hypot(b[1] - a[1]),
                        (q[0] - p[0]).hypot(q[1] - p[1]),
                    );
                    let near = |f: f64, len: f64| f.min(1.0 - f) * len < 1e-9 * span;
                    if near(s, la) || near(u, lr) {
                        continue;
                    }
                    let got = a[2] + s * (b[2] - a[2]);
                    let want = p[2] + u * (q[2] - p[2]);
                    if (got - want).abs() > tol {
                        return Err(over(
                            format!(
                                "the edge ({:?}, {:?})-({:?}, {:?}) where it crosses the \
                                 reference's edge ({:?}, {:?})-({:?}, {:?})",
                                a[0], a[1], b[0], b[1], p[0], p[1], q[0], q[1]
                            ),
                            (got - want).abs(),
                        ));
                    }
                    n.crossings += 1;
                }
            }
        }
    }
    Ok(n)
}
