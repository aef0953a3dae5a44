//! Point builds between their samples (issue 43): `build_points`, what
//! `tin_from_points` and its aggregate build, on three kinds of samples
//! from the bundled DEMs: the DEM's pixel centres moved by up to a tenth
//! of a pixel (seeded; a grid's own points are cocircular, so no Delaunay
//! triangulation of them is the one), scattered samples, and a LiDAR-like
//! cloud (dense along scan lines, sparse across them, noisy). Every level
//! is a valid hierarchy without holes, cracks or slivers, with its
//! tolerance met at the samples (measured here by this file's own
//! interpolation in each triangle); the bound between the samples is
//! checked against an independent Delaunay triangulation (matplotlib's
//! qhull) by `tests/properties/check_points_between.py`, in SQL.
use crate::common;

use std::time::Instant;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::construct::build_points;

/// xorshift, seeded: the same samples on every run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The DEM's height at world (x, y): bilinear between pixel centres (None
/// off the data).
fn dem_z(d: &common::Dem, x: f64, y: f64) -> Option<f64> {
    let c = (x - d.origin_x) / d.scale_x - 0.5;
    let r = (d.origin_y - y) / d.scale_y - 0.5;
    let (c0, r0) = (c.floor(), r.floor());
    if c0 < 0.0 || r0 < 0.0 || c0 + 1.0 >= d.width as f64 || r0 + 1.0 >= d.height as f64 {
        return None;
    }
    let (fc, fr) = (c - c0, r - r0);
    let (c0, r0) = (c0 as usize, r0 as usize);
    let z = |cc: usize, rr: usize| {
        let v = d.values[rr * d.width + cc];
        (Some(v) != d.nodata).then_some(v)
    };
    let (a, b) = (z(c0, r0)?, z(c0 + 1, r0)?);
    let (e, g) = (z(c0, r0 + 1)?, z(c0 + 1, r0 + 1)?);
    Some((a * (1.0 - fc) + b * fc) * (1.0 - fr) + (e * (1.0 - fc) + g * fc) * fr)
}

/// The three sample sets of one DEM: (name, samples).
fn sample_sets(d: &common::Dem) -> Vec<(String, Vec<[f64; 3]>)> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (px, py) = (d.scale_x, d.scale_y);
    let mut jittered = Vec::new();
    for r in (0..d.height).step_by(2) {
        for c in (0..d.width).step_by(2) {
            let x = d.origin_x + (c as f64 + 0.5 + 0.2 * (rng.next() - 0.5)) * px;
            let y = d.origin_y - (r as f64 + 0.5 + 0.2 * (rng.next() - 0.5)) * py;
            if let Some(z) = dem_z(d, x, y) {
                jittered.push([x, y, z]);
            }
        }
    }
    let (w, h) = (d.width as f64 * px, d.height as f64 * py);
    let mut scattered = Vec::new();
    while scattered.len() < 40_000 {
        let (x, y) = (d.origin_x + rng.next() * w, d.origin_y - rng.next() * h);
        if let Some(z) = dem_z(d, x, y) {
            scattered.push([x, y, z]);
        }
    }
    // scan lines across the DEM at a slant, points a fifth of a pixel
    // apart along them and four pixels apart across, 0.15 m of noise
    let mut lidar = Vec::new();
    let lines = (d.height / 4) as i64;
    for k in 0..lines {
        let y0 = d.origin_y - (k as f64 * 4.0 + 2.0) * py;
        let n = (d.width * 5) as i64;
        for i in 0..n {
            let x = d.origin_x + (i as f64 / 5.0 + 0.1 * rng.next()) * px;
            let y = y0 - (i as f64 / n as f64) * 3.0 * py + 0.3 * (rng.next() - 0.5) * py;
            if let Some(z) = dem_z(d, x, y) {
                lidar.push([x, y, z + 0.15 * (rng.next() - 0.5)]);
            }
        }
    }
    vec![
        ("DEM points moved a tenth of a pixel".to_string(), jittered),
        ("scattered".to_string(), scattered),
        ("LiDAR-like".to_string(), lidar),
    ]
}

/// The largest error at the samples, per level, by this file's own
/// barycentric interpolation (samples located by brute force over a
/// bucketing of the triangles).
fn sample_errors(tin: &Tin, samples: &[[f64; 3]]) -> Vec<f64> {
    tin.levels
        .iter()
        .map(|l| {
            // bucket triangles by their boxes
            let (x0, y0) = (tin.bbox.min_x, tin.bbox.min_y);
            let n = 256usize;
            let (cw, ch) = (
                (tin.bbox.max_x - x0) / n as f64 * 1.000001,
                (tin.bbox.max_y - y0) / n as f64 * 1.000001,
            );
            let mut cells: Vec<Vec<u32>> = vec![Vec::new(); n * n];
            for (t, tri) in l.tris[..l.num_domain()].iter().enumerate() {
                let p = tri.map(|v| tin.verts[v as usize]);
                let cx = |x: f64| (((x - x0) / cw) as usize).min(n - 1);
                let cy = |y: f64| (((y - y0) / ch) as usize).min(n - 1);
                let (a, b) = (
                    cx(p.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min)),
                    cx(p.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max)),
                );
                let (c, e) = (
                    cy(p.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min)),
                    cy(p.iter().map(|q| q[1]).fold(f64::NEG_INFINITY, f64::max)),
                );
                for i in a..=b {
                    for j in c..=e {
                        cells[j * n + i].push(t as u32);
                    }
                }
            }
            let mut worst = 0.0f64;
            for s in samples {
                let i = (((s[0] - x0) / cw) as usize).min(n - 1);
                let j = (((s[1] - y0) / ch) as usize).min(n - 1);
                let mut best: Option<f64> = None;
                for &t in &cells[j * n + i] {
                    let [a, b, c] = l.tris[t as usize].map(|v| tin.verts[v as usize]);
                    let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                    let u = ((b[0] - s[0]) * (c[1] - s[1]) - (c[0] - s[0]) * (b[1] - s[1])) / det;
                    let v = ((c[0] - s[0]) * (a[1] - s[1]) - (a[0] - s[0]) * (c[1] - s[1])) / det;
                    let w = 1.0 - u - v;
                    let e = 1e-9;
                    if u >= -e && v >= -e && w >= -e {
                        let z = u * a[2] + v * b[2] + w * c[2];
                        let err = (z - s[2]).abs();
                        best = Some(best.map_or(err, |b: f64| b.min(err)));
                    }
                }
                if let Some(e) = best {
                    worst = worst.max(e);
                }
            }
            worst
        })
        .collect()
}

/// Whether an edge runs along an edge of the samples' Delaunay
/// triangulation (spade's, made here): both its ends within a thousandth
/// of that edge's length of it (the engine makes a segment of the surface
/// through a vertex that near it, rather than split an edge beside a thin
/// fan: its `ROUTE`), or within rounding.
fn along_reference(pts: &[[f64; 3]]) -> impl Fn(&[f64; 3], &[f64; 3]) -> bool {
    use spade::{DelaunayTriangulation, Point2, Triangulation};
    use std::collections::HashMap;
    let dt = DelaunayTriangulation::<Point2<f64>>::bulk_load(
        pts.iter().map(|p| Point2::new(p[0], p[1])).collect(),
    )
    .unwrap();
    let segs: Vec<[[f64; 2]; 2]> = dt
        .undirected_edges()
        .map(|e| {
            let [u, v] = e.positions();
            [[u.x, u.y], [v.x, v.y]]
        })
        .collect();
    let len = |s: &[[f64; 2]; 2]| (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1]);
    let cell = segs.iter().map(len).sum::<f64>() / segs.len() as f64;
    let scale = pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let slack = 1e-12 * scale;
    let key = move |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
    for (i, s) in segs.iter().enumerate() {
        let pad = 1e-3 * len(s) + slack;
        let lo = key(s[0][0].min(s[1][0]) - pad, s[0][1].min(s[1][1]) - pad);
        let hi = key(s[0][0].max(s[1][0]) + pad, s[0][1].max(s[1][1]) + pad);
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                grid.entry((cx, cy)).or_default().push(i as u32);
            }
        }
    }
    // distance from p to the closed segment s
    let dist = |s: &[[f64; 2]; 2], p: &[f64; 3]| {
        let (dx, dy) = (s[1][0] - s[0][0], s[1][1] - s[0][1]);
        let t =
            (((p[0] - s[0][0]) * dx + (p[1] - s[0][1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        (p[0] - s[0][0] - t * dx).hypot(p[1] - s[0][1] - t * dy)
    };
    move |a, b| {
        grid.get(&key(a[0], a[1])).is_some_and(|ids| {
            ids.iter().any(|&i| {
                let s = &segs[i as usize];
                let tol = 1e-3 * len(s) + slack;
                dist(s, a) <= tol && dist(s, b) <= tol
            })
        })
    }
}

#[test]
fn point_builds_between_samples() {
    for file in ["jacksboro_fault_dem_utm16n.tif", "jacksboro_fault_dem.tif"] {
        let d = common::read_dem(file);
        let tols = default_tolerances(2.0, 4).unwrap();
        for (name, pts) in sample_sets(&d) {
            let t0 = Instant::now();
            let old = build(pts.clone(), &tols, 0, &mut || Ok(())).unwrap();
            let t_old = t0.elapsed();
            let t0 = Instant::now();
            let new = build_points(pts.clone(), &tols, 0, &mut || Ok(())).unwrap();
            let t_new = t0.elapsed();
            let p = tinmerge_core::tin::check::problems(&new, &mut || Ok(())).unwrap();
            assert!(
                p.is_empty(),
                "{file} {name}: {} problems, e.g. {:?}",
                p.len(),
                &p[..p.len().min(4)]
            );
            // engine 2's levels are constrained Delaunay: the edges of
            // the samples' Delaunay triangulation it made edges of (where a
            // level's edge crossed one too far from the surface) are their
            // only edges that need not be locally Delaunay, told here by
            // spade's own triangulation of the samples
            new.sanity_check_constrained(&along_reference(&pts))
                .unwrap();
            tinmerge_core::tin::check::validate_structure(&new).unwrap();
            let errs = sample_errors(&new, &pts);
            println!(
                "{file} {name}: {} samples; finest triangles {} -> {} ({:.2}x), time {:.0} -> {:.0} ms; error at the samples per level {:?}",
                pts.len(),
                old.levels[tols.len() - 1].num_triangles(),
                new.levels[tols.len() - 1].num_triangles(),
                new.levels[tols.len() - 1].num_triangles() as f64
                    / old.levels[tols.len() - 1].num_triangles() as f64,
                t_old.as_secs_f64() * 1e3,
                t_new.as_secs_f64() * 1e3,
                errs
            );
            for (l, e) in errs.iter().enumerate() {
                assert!(
                    *e <= tols[l] * (1.0 + 1e-9),
                    "{file} {name}: level {l} is {e} off at a sample, tolerance {}",
                    tols[l]
                );
            }
        }
    }
}

/// pointcloud.sql's domain build: a jittered grid of 120 x 120 DEM pixel
/// centres, within its hull less a square hole, with a soft line along the
/// diagonal, built between samples. It first looped without end in
/// `close_chains` (one vertex twice in a side's chain), then left holes
/// beside the line: a side from a vertex on an edge of the reference (a
/// ring's crossing) crossed that edge again 1e-7 m from its start, past
/// the 1e-9 parameter slack, and a vertex put there stood beside the
/// corner. The bound against the samples' Delaunay is checked by
/// `tests/properties/check_points_between.py` (its domain builds).
#[test]
fn point_build_with_a_boundary_and_a_soft_line() {
    use tinmerge_core::merge::area::polygon::Area;
    use tinmerge_core::tin::breaklines::Breakline;
    use tinmerge_core::tin::build::build_points_domain;
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let (px, py) = (d.scale_x, d.scale_y);
    // pointcloud.sql: the window 10 pixels in, pixels 1..=120 (1-based)
    let mut pts = Vec::new();
    for y in 1..=120usize {
        for x in 1..=120usize {
            let (c, r) = (9 + x, 9 + y);
            let v = d.values[r * d.width + c];
            if Some(v) == d.nodata {
                continue;
            }
            let jx = ((x * 7919 + y * 104729) % 101) as f64 - 50.0;
            let jy = ((x * 104729 + y * 7919) % 101) as f64 - 50.0;
            pts.push([
                d.origin_x + (c as f64 + 0.5) * px + jx * 0.004 * px,
                d.origin_y - (r as f64 + 0.5) * py + jy * 0.004 * py,
                v,
            ]);
        }
    }
    // their convex hull (monotone chain), less a square of 600 m about its
    // centroid
    let mut sorted: Vec<[f64; 2]> = pts.iter().map(|p| [p[0], p[1]]).collect();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let it: Vec<[f64; 2]> = if pass == 0 {
            sorted.clone()
        } else {
            sorted.iter().rev().copied().collect()
        };
        for q in it {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    let n = hull.len();
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (hull[i], hull[(i + 1) % n]);
        let f = p[0] * q[1] - q[0] * p[1];
        a += f;
        cx += (p[0] + q[0]) * f;
        cy += (p[1] + q[1]) * f;
    }
    let (cx, cy) = (cx / (3.0 * a), cy / (3.0 * a));
    let mut shell = hull.clone();
    shell.push(hull[0]);
    let (x0, x1) = (
        sorted.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
        sorted
            .iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max),
    );
    let (y0, y1) = (
        sorted.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
        sorted
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max),
    );
    let boundary = Area::new(vec![vec![
        shell,
        vec![
            [cx - 300.0, cy - 300.0],
            [cx - 300.0, cy + 300.0],
            [cx + 300.0, cy + 300.0],
            [cx + 300.0, cy - 300.0],
            [cx - 300.0, cy - 300.0],
        ],
    ]]);
    let line = Breakline {
        pts: vec![[x0, y0, 0.0], [x1, y1, 0.0]],
        hard: false,
    };
    let tols = default_tolerances(1.0, 3).unwrap();
    let t0 = Instant::now();
    let tin =
        build_points_domain(pts.clone(), &[line], &[&boundary], &tols, 0, &mut || Ok(())).unwrap();
    println!(
        "{} samples, {} finest triangles, {:.0} ms",
        pts.len(),
        tin.levels[2].num_triangles(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    let p = tinmerge_core::tin::check::problems(&tin, &mut || Ok(())).unwrap();
    assert!(p.is_empty(), "{p:?}");
}
