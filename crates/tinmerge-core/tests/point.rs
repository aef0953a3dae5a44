//! Point merge on the bundled DEMs (both grids, and one with a nodata hole:
//! [`common::terrains`]) against brute-force oracles that share no code
//! with the grid index or the walk: every triangle of the level is tested
//! (after an exact bounding-box bucket) with `geo`'s predicates; heights come
//! from the plane through the oracle's triangle by a cross product; footprints
//! are `geo::Intersects` between each triangle and the rectangle.
use crate::common;

use geo::{Coord, Intersects, Line, Point, Polygon, Triangle};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tinmerge_core::merge::point::{Rect, footprint, height, locate, locate_descend};
use tinmerge_core::tin::Tin;

use common::terrains;

/// Triangles bucketed by every grid bin their bounding box overlaps: the
/// oracle then tests every triangle whose box could contain the point.
struct Bins {
    x0: f64,
    y0: f64,
    size: f64,
    n: usize,
    bins: Vec<Vec<u32>>,
}

fn bbox(c: &[[f64; 3]; 3]) -> (f64, f64, f64, f64) {
    let f = |i: usize, init: f64, op: fn(f64, f64) -> f64| c.iter().map(|p| p[i]).fold(init, op);
    (
        f(0, f64::INFINITY, f64::min),
        f(1, f64::INFINITY, f64::min),
        f(0, f64::NEG_INFINITY, f64::max),
        f(1, f64::NEG_INFINITY, f64::max),
    )
}

impl Bins {
    fn new(tin: &Tin, level: usize) -> Bins {
        let n = 64;
        let b = tin.bbox;
        let size = ((b.max_x - b.min_x).max(b.max_y - b.min_y)) / n as f64 * 1.0001;
        let mut bins = vec![Vec::new(); n * n];
        for t in 0..tin.levels[level].tris.len() as u32 {
            let (x0, y0, x1, y1) = bbox(&tin.corners(level, t));
            let c = |v: f64, o: f64| (((v - o) / size).floor().max(0.0) as usize).min(n - 1);
            for i in c(x0, b.min_x)..=c(x1, b.min_x) {
                for j in c(y0, b.min_y)..=c(y1, b.min_y) {
                    bins[j * n + i].push(t);
                }
            }
        }
        Bins {
            x0: b.min_x,
            y0: b.min_y,
            size,
            n,
            bins,
        }
    }

    /// Candidate triangles for a point (every triangle, for points whose bin
    /// falls outside the grid: there are none of those inside the domain).
    fn candidates(&self, x: f64, y: f64) -> &[u32] {
        let i = ((x - self.x0) / self.size).floor();
        let j = ((y - self.y0) / self.size).floor();
        if i < 0.0 || j < 0.0 || i >= self.n as f64 || j >= self.n as f64 {
            return &[];
        }
        &self.bins[j as usize * self.n + i as usize]
    }
}

fn geo_triangle(c: &[[f64; 3]; 3]) -> Triangle<f64> {
    Triangle::new(
        Coord {
            x: c[0][0],
            y: c[0][1],
        },
        Coord {
            x: c[1][0],
            y: c[1][1],
        },
        Coord {
            x: c[2][0],
            y: c[2][1],
        },
    )
}

/// Brute force: smallest id among closed triangles containing (x, y), None
/// when that one is void (outside the domain: the void triangles are the
/// last of a level, so a point on the domain's edge is in the domain).
fn oracle_locate(tin: &Tin, level: usize, bins: &Bins, x: f64, y: f64) -> Option<u32> {
    let p = Point::new(x, y);
    let lv = &tin.levels[level];
    let void_from = lv.tris.len() as u32 - lv.num_void;
    bins.candidates(x, y)
        .iter()
        .copied()
        .filter(|&t| geo_triangle(&tin.corners(level, t)).intersects(&p))
        .min()
        .filter(|&t| t < void_from)
}

/// Height on the plane through the triangle, by the normal vector.
fn oracle_height(c: &[[f64; 3]; 3], x: f64, y: f64) -> f64 {
    common::plane_height(c, x, y)
}

#[test]
fn locate_and_height_match_brute_force_at_every_level() {
    for common::Terrain { name, tin, .. } in terrains() {
        eprintln!("{name}");
        locate_and_height_on(&tin);
    }
}

fn locate_and_height_on(tin: &Tin) {
    let tin = tin.clone();
    let b = tin.bbox;
    let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let mut rng = StdRng::seed_from_u64(20261122);
    for level in 0..tin.levels.len() {
        let lv = &tin.levels[level];
        let bins = Bins::new(&tin, level);
        let mut pts: Vec<(f64, f64, &str)> = Vec::new();
        for _ in 0..10_000 {
            // uniform over the bbox grown by 5 %: the domain is the convex hull
            // of the valid pixels, so some of these are outside
            let x = b.min_x - 0.05 * w + rng.random::<f64>() * 1.1 * w;
            let y = b.min_y - 0.05 * h + rng.random::<f64>() * 1.1 * h;
            pts.push((x, y, "random"));
        }
        for _ in 0..2_000 {
            let v = tin.verts[rng.random_range(0..lv.num_vertices as usize)];
            pts.push((v[0], v[1], "vertex"));
        }
        for _ in 0..2_000 {
            let t = lv.tris[rng.random_range(0..lv.tris.len())];
            let j = rng.random_range(0..3);
            let (p, q) = (tin.verts[t[j] as usize], tin.verts[t[(j + 1) % 3] as usize]);
            pts.push(((p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, "edge midpoint"));
        }
        // within rounding of a hull edge's line, both sides of it: where
        // the walk's "outside" is not proof and the triangles around are
        // searched (`locate::near_hull`)
        let band = 1e-9
            * [b.min_x, b.max_x, b.min_y, b.max_y]
                .iter()
                .fold(0.0_f64, |a, v| a.max(v.abs()));
        let hull: Vec<(usize, usize)> = (0..lv.tris.len())
            .flat_map(|t| (0..3).map(move |j| (t, j)))
            .filter(|&(t, j)| lv.nbrs[t][j] == u32::MAX)
            .collect();
        for i in 0..2_000 {
            let (t, j) = hull[rng.random_range(0..hull.len())];
            let tri = lv.tris[t];
            let (p, q) = (
                tin.verts[tri[(j + 1) % 3] as usize],
                tin.verts[tri[(j + 2) % 3] as usize],
            );
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let len = dx.hypot(dy);
            // along the edge, past its ends too; across it, within two bands
            let s = if i % 4 == 0 {
                [0.0, 1.0][i % 8 / 4]
            } else {
                rng.random::<f64>() * 1.2 - 0.1
            };
            let off = (rng.random::<f64>() * 4.0 - 2.0) * band;
            pts.push((
                p[0] + s * dx + off * dy / len,
                p[1] + s * dy - off * dx / len,
                "beside a hull edge",
            ));
        }
        for _ in 0..1_000 {
            let a = rng.random::<f64>() * std::f64::consts::TAU;
            pts.push((
                (b.min_x + b.max_x) / 2.0 + a.cos() * w,
                (b.min_y + b.max_y) / 2.0 + a.sin() * h,
                "far outside",
            ));
        }
        let (mut inside, mut outside) = (0, 0);
        for &(x, y, kind) in &pts {
            let want = oracle_locate(&tin, level, &bins, x, y);
            let got = locate(&tin, level, x, y);
            assert_eq!(got, want, "level {level} {kind} ({x}, {y})");
            assert_eq!(
                locate_descend(&tin, level, x, y),
                want,
                "descend, level {level} {kind}"
            );
            let z = height(&tin, level, x, y);
            match want {
                Some(t) => {
                    inside += 1;
                    let c = tin.corners(level, t);
                    let zo = oracle_height(&c, x, y);
                    let z = z.expect("height inside");
                    assert!((z - zo).abs() < 1e-6, "level {level} {kind}: {z} vs {zo}");
                    if kind == "vertex" {
                        let v = c.iter().find(|v| v[0] == x && v[1] == y).expect("vertex");
                        assert!((z - v[2]).abs() < 1e-9);
                    }
                }
                None => {
                    outside += 1;
                    assert!(z.is_none());
                }
            }
        }
        eprintln!("level {level}: {inside} points inside, {outside} outside, all agree");
        assert!(inside > 10_000 && outside > 1_000);
    }
    assert_eq!(locate(&tin, 0, f64::NAN, 0.0), None);
    assert_eq!(height(&tin, 0, f64::INFINITY, 0.0), None);
}

/// The rectangle as geo sees it: a polygon, or a line or point when flat.
fn oracle_footprint(tin: &Tin, level: usize, r: &Rect) -> Vec<u32> {
    let c: Vec<Coord<f64>> = r
        .corners
        .iter()
        .map(|p| Coord { x: p[0], y: p[1] })
        .collect();
    let (rx0, ry0, rx1, ry1) = (
        c.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
        c.iter().map(|p| p.y).fold(f64::INFINITY, f64::min),
        c.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
        c.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
    );
    let meets = |tri: &Triangle<f64>| -> bool {
        if c.iter().all(|p| *p == c[0]) {
            tri.intersects(&Point::from(c[0]))
        } else if c[0] == c[1] || c[1] == c[2] {
            // zero width or zero length: the long side is a segment
            let (a, b) = if c[0] == c[1] {
                (c[1], c[2])
            } else {
                (c[0], c[1])
            };
            tri.intersects(&Line::new(a, b))
        } else {
            let mut ring = c.clone();
            ring.push(c[0]);
            tri.to_polygon()
                .intersects(&Polygon::new(ring.into(), vec![]))
        }
    };
    // the void triangles (outside the domain) are the last of the level
    let lv = &tin.levels[level];
    (0..lv.tris.len() as u32 - lv.num_void)
        .filter(|&t| {
            let k = tin.corners(level, t);
            let (x0, y0, x1, y1) = bbox(&k);
            x0 <= rx1 && x1 >= rx0 && y0 <= ry1 && y1 >= ry0 && meets(&geo_triangle(&k))
        })
        .collect()
}

#[test]
fn footprints_match_brute_force_polygon_intersection() {
    for common::Terrain { name, tin, .. } in terrains() {
        eprintln!("{name}");
        footprints_on(&tin);
    }
}

fn footprints_on(tin: &Tin) {
    let tin = tin.clone();
    let b = tin.bbox;
    let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let mut rng = StdRng::seed_from_u64(7);
    for level in 0..tin.levels.len() {
        let mut total = 0;
        for i in 0..150 {
            let (x, y) = (
                b.min_x - 0.1 * w + rng.random::<f64>() * 1.2 * w,
                b.min_y - 0.1 * h + rng.random::<f64>() * 1.2 * h,
            );
            // about 10 m, 300 m and 3 km on the UTM DEM
            let scale = [3e-4, 1e-2, 1e-1][i % 3] * w.max(h);
            let (mut wd, mut ln) = (rng.random::<f64>() * scale, rng.random::<f64>() * scale);
            match i % 10 {
                7 => wd = 0.0,
                8 => ln = 0.0,
                9 => (wd, ln) = (0.0, 0.0),
                _ => {}
            }
            let angle = rng.random::<f64>() * 720.0 - 360.0;
            let r = Rect::new(x, y, wd, ln, angle).unwrap();
            let got = footprint(&tin, level, &r, &mut || Ok(())).unwrap();
            let want = oracle_footprint(&tin, level, &r);
            assert_eq!(
                got, want,
                "level {level} rect {i} at ({x}, {y}) {wd} x {ln} @ {angle}"
            );
            total += got.len();
        }
        // a point footprint on a vertex takes its whole fan
        let lv = &tin.levels[level];
        let v = tin.verts[lv.tris[lv.tris.len() / 2][0] as usize];
        let r = Rect::new(v[0], v[1], 0.0, 0.0, 0.0).unwrap();
        let fan = footprint(&tin, level, &r, &mut || Ok(())).unwrap();
        assert_eq!(fan, oracle_footprint(&tin, level, &r));
        assert!(fan.len() >= 2, "fan {fan:?}");
        eprintln!("level {level}: 151 footprints, {total} triangles, all agree");
    }
    // the whole domain
    let r = Rect::new(
        (b.min_x + b.max_x) / 2.0,
        (b.min_y + b.max_y) / 2.0,
        2.0 * w,
        2.0 * h,
        30.0,
    )
    .unwrap();
    assert_eq!(
        footprint(&tin, 0, &r, &mut || Ok(())).unwrap().len(),
        tin.levels[0].tris.len() - tin.levels[0].num_void as usize
    );
    // huge sizes (1e308 m, whose corners would overflow the exact tests)
    // select what a strip just longer than the domain selects
    let diag = w.hypot(h);
    for (i, &(x, y)) in [
        (b.min_x + 0.3 * w, b.min_y + 0.6 * h),
        (b.max_x + 0.2 * w, b.min_y - 0.1 * h),
    ]
    .iter()
    .enumerate()
    {
        for angle in [0.0, 33.0, 90.0, 151.0] {
            let huge = Rect::within(x, y, 1e308, diag / 100.0, angle, &b).unwrap();
            let strip = Rect::new(x, y, 10.0 * diag, diag / 100.0, angle).unwrap();
            for level in [0, tin.levels.len() - 1] {
                let got = footprint(&tin, level, &huge, &mut || Ok(())).unwrap();
                assert_eq!(
                    got,
                    oracle_footprint(&tin, level, &strip),
                    "centre {i} angle {angle}"
                );
                assert!(i == 1 || !got.is_empty());
            }
        }
    }
    // bad sizes are errors, not panics
    assert!(Rect::new(0.0, 0.0, -1.0, 1.0, 0.0).is_err());
    assert!(Rect::new(0.0, 0.0, 1.0, f64::NAN, 0.0).is_err());
    assert!(Rect::new(0.0, 0.0, 1.0, 1.0, f64::INFINITY).is_err());
}

#[test]
fn footprint_orientation_follows_the_compass() {
    // angle 90 (east): length runs along x
    let r = Rect::new(0.0, 0.0, 2.0, 10.0, 90.0).unwrap();
    let xs: Vec<f64> = r.corners.iter().map(|c| c[0]).collect();
    let ys: Vec<f64> = r.corners.iter().map(|c| c[1]).collect();
    let span = |v: &[f64]| {
        v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - v.iter().cloned().fold(f64::INFINITY, f64::min)
    };
    assert!((span(&xs) - 10.0).abs() < 1e-12 && (span(&ys) - 2.0).abs() < 1e-12);
    // angle 0 (north): length runs along y
    let r = Rect::new(0.0, 0.0, 2.0, 10.0, 0.0).unwrap();
    let ys: Vec<f64> = r.corners.iter().map(|c| c[1]).collect();
    assert!((span(&ys) - 10.0).abs() < 1e-12);
}
