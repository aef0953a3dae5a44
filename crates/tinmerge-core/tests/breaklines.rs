//! Breaklines on both bundled DEMs (geographic and UTM), against this
//! file's own oracles, at every level:
//! - every input segment of every breakline is covered by edges of the
//!   level lying on it (intervals along the segment, gaps under 1e-9);
//! - along a hard breakline the surface is the line's own interpolated Z
//!   (every vertex on it has the line's height there);
//! - every sample not on a breakline is within the level's tolerance;
//! - along a soft breakline the surface follows the pixels: at every level,
//!   at 400 points along each soft segment, it lies within the level's
//!   tolerance of the range of the valid pixels in the 5 x 5 window around
//!   the point (a surface running straight between the line's own vertices,
//!   as the first build with breaklines had, missed by up to 335 m), away
//!   from the hard lines it meets;
//! - no sliver or crack (`check::problems`), and the hierarchy's invariants
//!   (`sanity_check_constrained`, told which level-0 edges are breaklines
//!   by this file's geometry, not the build's).
//!
//! The lines are seeded random polylines (crossing each other, hard and
//! soft), a soft line through a row of pixel centres, a soft line ending on
//! a hard one (a T-junction within rounding) and two overlapping lines.
mod common;

use common::{read_dem, Dem};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::breaklines::Breakline;
use tinmerge_core::tin::build::{build_breaklines, default_tolerances};
use tinmerge_core::tin::check::problems;
use tinmerge_core::tin::Tin;

/// World coordinates of fractional pixel position (col, row).
fn world(d: &Dem, c: f64, r: f64) -> (f64, f64) {
    (
        d.origin_x + (c + 0.5) * d.scale_x,
        d.origin_y - (r + 0.5) * d.scale_y,
    )
}

fn lines_for(d: &Dem, seed: u64) -> Vec<Breakline> {
    let mut rng = StdRng::seed_from_u64(seed);
    let (w, h) = (d.width as f64, d.height as f64);
    let rnd = |rng: &mut StdRng| {
        let c = rng.random_range(0.1 * w..0.9 * w);
        let r = rng.random_range(0.1 * h..0.9 * h);
        world(d, c, r)
    };
    let mut out = Vec::new();
    // a hard road: 6 random points from west to east in the northern
    // part (two hard lines crossing at different heights are a bridge, an
    // ERROR), heights 300 .. 305 m
    let mut cols: Vec<f64> = (0..6).map(|_| rng.random_range(0.1 * w..0.9 * w)).collect();
    cols.sort_by(f64::total_cmp);
    let road: Vec<[f64; 3]> = cols
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let (x, y) = world(d, c, rng.random_range(0.1 * h..0.4 * h));
            [x, y, 300.0 + i as f64]
        })
        .collect();
    // a soft line ending on the road's second segment (a T-junction up to
    // rounding: the point is computed, not on it exactly)
    let (a, b) = (road[1], road[2]);
    let t = 0.37;
    let on = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), f64::NAN];
    let (x, y) = rnd(&mut rng);
    out.push(Breakline {
        pts: vec![[x, y, f64::NAN], on],
        hard: false,
    });
    out.push(Breakline {
        pts: road.clone(),
        hard: true,
    });
    // soft ridge lines crossing everything
    for _ in 0..3 {
        let pts = (0..8)
            .map(|_| {
                let (x, y) = rnd(&mut rng);
                [x, y, f64::NAN]
            })
            .collect();
        out.push(Breakline { pts, hard: false });
    }
    // a soft line along a row of pixel centres (through samples exactly or
    // within rounding)
    let r = (d.height / 2) as f64;
    let (x0, y0) = world(d, 0.2 * w, r);
    let (x1, y1) = world(d, 0.7 * w, r);
    out.push(Breakline {
        pts: vec![[x0, y0, f64::NAN], [x1, y1, f64::NAN]],
        hard: false,
    });
    // a hard line overlapping the row line's middle part
    let (x2, y2) = world(d, 0.4 * w, r);
    let (x3, y3) = world(d, 0.8 * w, r);
    out.push(Breakline {
        pts: vec![[x2, y2, 250.0], [x3, y3, 250.0]],
        hard: true,
    });
    out
}

/// Parameter of p along a-b and its distance from the line, in units of
/// the segment's length.
fn along(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2;
    let d = ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / l2;
    (t, d)
}

/// Whether edge p-q lies on segment a-b (both ends on its line within
/// `eps` of its length, inside its extent).
fn edge_on(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3], q: &[f64; 3], eps: f64) -> Option<(f64, f64)> {
    let (tp, dp) = along(a, b, p);
    let (tq, dq) = along(a, b, q);
    (dp <= eps && dq <= eps && tp.min(tq) >= -eps && tp.max(tq) <= 1.0 + eps)
        .then(|| (tp.min(tq), tp.max(tq)))
}

fn segments(lines: &[Breakline]) -> Vec<([f64; 3], [f64; 3], bool)> {
    lines
        .iter()
        .flat_map(|l| l.pts.windows(2).map(move |w| (w[0], w[1], l.hard)))
        .collect()
}

fn check(d: &Dem, srid: i32, seed: u64, tol: f64) {
    let lines = lines_for(d, seed);
    let samples = d.samples();
    let tols = default_tolerances(tol, 4).unwrap();
    let tin: Tin = build_breaklines(samples.clone(), &lines, &tols, srid, &mut || Ok(())).unwrap();
    let segs = segments(&lines);
    let eps = 1e-9;
    let is_breakline = |p: &[f64; 3], q: &[f64; 3]| {
        segs.iter()
            .any(|(a, b, _)| edge_on(a, b, p, q, eps).is_some())
    };
    tin.sanity_check_constrained(&is_breakline).unwrap();
    let probs = problems(&tin, &mut || Ok(())).unwrap();
    assert!(
        probs.is_empty(),
        "slivers or cracks: {:?}",
        &probs[..probs.len().min(3)]
    );
    // samples on a breakline (up to 1e-9 of a pixel) are not held to the
    // tolerance: the line stands for them
    let px = d.scale_x.abs();
    let off_lines: Vec<&[f64; 3]> = samples
        .iter()
        .filter(|s| {
            !segs.iter().any(|(a, b, _)| {
                let (t, dist) = along(a, b, s);
                let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                dist * len <= 1e-9 * px && (-1e-9..=1.0 + 1e-9).contains(&t)
            })
        })
        .collect();
    assert!(off_lines.len() > samples.len() - 2000);
    for (l, lv) in tin.levels.iter().enumerate() {
        // coverage of every input segment by edges on it
        for (a, b, hard) in &segs {
            let mut iv: Vec<(f64, f64)> = Vec::new();
            for t in &lv.tris {
                for j in 0..3 {
                    let (p, q) = (
                        &tin.verts[t[j] as usize],
                        &tin.verts[t[(j + 1) % 3] as usize],
                    );
                    if let Some(r) = edge_on(a, b, p, q, eps) {
                        iv.push(r);
                    }
                }
            }
            iv.sort_by(|u, v| u.0.total_cmp(&v.0));
            let mut reach = 0.0f64;
            for (s, e) in &iv {
                assert!(
                    *s <= reach + 1e-9,
                    "{srid} level {l}: segment ({} {})-({} {}) not covered between {reach} and {s}",
                    a[0],
                    a[1],
                    b[0],
                    b[1]
                );
                reach = reach.max(*e);
            }
            assert!(
                reach >= 1.0 - 1e-9,
                "{srid} level {l}: segment covered to {reach} only"
            );
            if *hard {
                // the surface along the line is the line: every vertex of
                // the level on it has the line's interpolated height (and
                // the edges between them cover it, above)
                for t in &lv.tris {
                    for &v in t {
                        let p = &tin.verts[v as usize];
                        let (s, dist) = along(a, b, p);
                        if dist <= eps && (-eps..=1.0 + eps).contains(&s) {
                            let z = a[2] + s.clamp(0.0, 1.0) * (b[2] - a[2]);
                            assert!(
                                (p[2] - z).abs() <= 1e-9 * z.abs().max(1.0),
                                "{srid} level {l}: vertex at {} on a hard line at {z}",
                                p[2]
                            );
                        }
                    }
                }
            }
        }
        // soft lines follow the pixels
        for (a, b, hard) in &segs {
            if *hard {
                continue;
            }
            for k in 1..400 {
                let t = k as f64 / 400.0;
                let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
                // (where it meets a hard line the surface takes the hard
                // line's height: points within 3 pixels of one are left out)
                let near_hard = segs.iter().any(|(p, q, h)| {
                    let u = along(p, q, &[x, y, 0.0]).0.clamp(0.0, 1.0);
                    let (px, py) = (p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1]));
                    *h && (px - x).hypot(py - y) < 3.0 * d.scale_x.abs()
                });
                if near_hard {
                    continue;
                }
                let c = ((x - d.origin_x) / d.scale_x - 0.5).round() as i64;
                let r = ((d.origin_y - y) / d.scale_y - 0.5).round() as i64;
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for rr in r - 2..=r + 2 {
                    for cc in c - 2..=c + 2 {
                        if rr < 0 || cc < 0 || rr >= d.height as i64 || cc >= d.width as i64 {
                            continue;
                        }
                        let v = d.values[rr as usize * d.width + cc as usize];
                        if !(v.is_nan() || Some(v) == d.nodata) {
                            lo = lo.min(v);
                            hi = hi.max(v);
                        }
                    }
                }
                let hz = height(&tin, l, x, y).unwrap();
                assert!(
                    hz >= lo - tols[l] - 1e-9 && hz <= hi + tols[l] + 1e-9,
                    "{srid} level {l}: on a soft line at ({x} {y}) the surface is at {hz}, the pixels around between {lo} and {hi} (tolerance {})",
                    tols[l]
                );
            }
        }
        for s in &off_lines {
            let hz = height(&tin, l, s[0], s[1]).unwrap();
            assert!(
                (hz - s[2]).abs() <= tols[l] + 1e-6,
                "{srid} level {l}: sample ({} {}) at {} but the surface at {hz} (tolerance {})",
                s[0],
                s[1],
                s[2],
                tols[l]
            );
        }
    }
}

#[test]
fn breaklines_on_the_utm_dem() {
    check(&read_dem("jacksboro_fault_dem_utm16n.tif"), 32616, 7, 2.0);
}

#[test]
fn breaklines_on_the_geographic_dem() {
    check(&read_dem("jacksboro_fault_dem.tif"), 4326, 11, 2.0);
}

/// A road from 5 pixels west of the DEM's north-west corner to its middle,
/// and a soft line wholly outside: the parts outside the samples' convex
/// hull are cut off. Oracle: `geo`'s convex hull of the samples; every point
/// along the road inside it (by more than a millionth of a pixel) lies on
/// an edge of every level, on the road, and the tin's domain is the hull
/// (its area equals the hull's).
#[test]
fn breaklines_are_cut_at_the_samples_hull() {
    use geo::{Area, ConvexHull, Distance, Euclidean, LineString, MultiPoint, Point};
    let d = read_dem("jacksboro_fault_dem_utm16n.tif");
    let samples = d.samples();
    let (x0, y0) = world(&d, -5.0, -5.0);
    let (x1, y1) = world(&d, d.width as f64 * 0.5, d.height as f64 * 0.5);
    let (x2, y2) = world(&d, -20.0, d.height as f64 * 0.5);
    let (x3, y3) = world(&d, -10.0, d.height as f64 * 0.7);
    let lines = [
        Breakline {
            pts: vec![[x0, y0, 500.0], [x1, y1, 400.0]],
            hard: true,
        },
        Breakline {
            pts: vec![[x2, y2, f64::NAN], [x3, y3, f64::NAN]],
            hard: false,
        },
    ];
    let tols = [8.0, 4.0, 2.0];
    let tin = build_breaklines(samples.clone(), &lines, &tols, 32616, &mut || Ok(())).unwrap();
    assert!(problems(&tin, &mut || Ok(())).unwrap().is_empty());
    let hull = MultiPoint::from(
        samples
            .iter()
            .map(|p| Point::new(p[0], p[1]))
            .collect::<Vec<_>>(),
    )
    .convex_hull();
    let ring = LineString::from(hull.exterior().0.clone());
    let px = d.scale_x.abs();
    for (l, lv) in tin.levels.iter().enumerate() {
        let area: f64 = lv
            .tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| tin.verts[v as usize]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
            })
            .sum();
        assert!(
            (area - hull.unsigned_area()).abs() <= 1e-9 * area,
            "level {l}: domain {area} against the hull's {}",
            hull.unsigned_area()
        );
        let mut inside = 0;
        for k in 0..=1000 {
            let t = k as f64 / 1000.0;
            let p = [x0 + t * (x1 - x0), y0 + t * (y1 - y0), 0.0];
            let pt = Point::new(p[0], p[1]);
            if !geo::Contains::contains(&hull, &pt) || Euclidean.distance(&pt, &ring) < 1e-6 * px {
                continue;
            }
            inside += 1;
            let on_edge = lv.tris.iter().any(|tr| {
                (0..3).any(|j| {
                    let (a, b) = (
                        &tin.verts[tr[j] as usize],
                        &tin.verts[tr[(j + 1) % 3] as usize],
                    );
                    let (s, dist) = along(a, b, &p);
                    let road = along(&[x0, y0, 0.0], &[x1, y1, 0.0], a).1 <= 1e-9
                        && along(&[x0, y0, 0.0], &[x1, y1, 0.0], b).1 <= 1e-9;
                    road && dist <= 1e-9 && (-1e-9..=1.0 + 1e-9).contains(&s)
                })
            });
            assert!(
                on_edge,
                "level {l}: road point {k} inside the hull is on no edge along the road"
            );
        }
        assert!(inside > 800, "{inside}");
    }
}
