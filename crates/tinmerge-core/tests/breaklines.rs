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
use crate::common;

use common::{Dem, along, edge_on, read_dem};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::breaklines::Breakline;
use tinmerge_core::tin::build::{build_breaklines, default_tolerances};
use tinmerge_core::tin::check::problems;

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

fn segments(lines: &[Breakline]) -> Vec<([f64; 3], [f64; 3], bool)> {
    lines
        .iter()
        .flat_map(|l| l.pts.windows(2).map(move |w| (w[0], w[1], l.hard)))
        .collect()
}

/// The area a level's triangles cover.
fn domain_area(tin: &Tin, lv: &tinmerge_core::tin::Level) -> f64 {
    lv.tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| tin.verts[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
        })
        .sum()
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
        let area = domain_area(&tin, lv);
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

/// Seeded random breakline sets on small grids, geographic-like (1/1200
/// degree pixels, a fractional origin) and projected: lines from random
/// points and from grid points (so lines overlap exactly, run through
/// samples and end on each other), hard lines on one plane (so crossing
/// hard lines agree and a bridge is never the reason to refuse), some
/// lines partly outside. Every build either refuses with a message about
/// the input (InvalidParameter: lines within rounding of each other) or
/// gives a tin whose every input segment, cut at the hull, is covered by
/// edges on it at every level, with no sliver, crack or broken invariant,
/// and every sample off the lines within tolerance. Never a panic, never
/// an internal error.
#[test]
fn random_breakline_sets_build_or_refuse_cleanly() {
    let mut rng = StdRng::seed_from_u64(26);
    let mut built = 0;
    let mut refused = 0;
    for case in 0..2000 {
        let geo = case % 2 == 0;
        let (px, ox, oy) = if geo {
            (1.0 / 1200.0, -84.31 + 1.0 / 2400.0, 36.47 + 1.0 / 3600.0)
        } else {
            (30.0, 732_000.123_4, 4_036_601.162_225_269)
        };
        let n = 24usize;
        let at = |c: f64, r: f64| [ox + c * px, oy + r * px];
        let mut samples = Vec::new();
        for r in 0..n {
            for c in 0..n {
                let [x, y] = at(c as f64, r as f64);
                let z = 100.0
                    + 10.0 * ((c as f64) * 0.7).sin() * ((r as f64) * 0.5).cos()
                    + (c * r) as f64 * 0.05;
                samples.push([x, y, z]);
            }
        }
        let plane = |x: f64, y: f64| 50.0 + (x - ox) / px * 1.5 - (y - oy) / px * 0.75;
        let mut lines = Vec::new();
        for _ in 0..rng.random_range(1..5) {
            let hard = rng.random_bool(0.5);
            let on_grid = rng.random_bool(0.5);
            let k = rng.random_range(2..5);
            let pts: Vec<[f64; 3]> = (0..k)
                .map(|_| {
                    let (c, r) = if on_grid {
                        (
                            rng.random_range(-2..n as i64 + 2) as f64,
                            rng.random_range(-2..n as i64 + 2) as f64,
                        )
                    } else {
                        (
                            rng.random_range(-2.0..n as f64 + 1.0),
                            rng.random_range(-2.0..n as f64 + 1.0),
                        )
                    };
                    let [x, y] = at(c, r);
                    [x, y, if hard { plane(x, y) } else { f64::NAN }]
                })
                .collect();
            if pts.iter().all(|p| p[..2] == pts[0][..2]) {
                continue;
            }
            lines.push(Breakline { pts, hard });
        }
        let tols = [2.0, 0.5];
        match build_breaklines(
            samples.clone(),
            &lines,
            &tols,
            if geo { 4326 } else { 32616 },
            &mut || Ok(()),
        ) {
            Err(e) => {
                assert!(
                    matches!(e, tinmerge_core::tin::TinError::InvalidParameter(_))
                        && e.to_string().contains("within rounding"),
                    "case {case}: refused with {e:?} for {lines:?}"
                );
                refused += 1;
            }
            Ok(tin) => {
                built += 1;
                assert!(
                    problems(&tin, &mut || Ok(())).unwrap().is_empty(),
                    "case {case}: slivers or cracks for {lines:?}"
                );
                // every sample off the lines within tolerance
                // (a line's repeated point is no segment)
                let segs: Vec<_> = segments(&lines)
                    .into_iter()
                    .filter(|(a, b, _)| a[..2] != b[..2])
                    .collect();
                // the hierarchy's invariants (one convex boundary cycle,
                // nesting, ...), told which level-0 edges are breaklines
                tin.sanity_check_constrained(&|p, q| {
                    segs.iter()
                        .any(|(a, b, _)| edge_on(a, b, p, q, 1e-9).is_some())
                })
                .unwrap_or_else(|e| panic!("case {case}: {e}: {lines:?}"));
                for (l, lv) in tin.levels.iter().enumerate() {
                    for s in &samples {
                        let near = segs.iter().any(|(a, b, _)| {
                            let (t, dist) = along(a, b, s);
                            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                            dist * len <= 1e-6 * px && (-1e-9..=1.0 + 1e-9).contains(&t)
                        });
                        if !near {
                            let Some(hz) = height(&tin, l, s[0], s[1]) else {
                                let o = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| {
                                    robust::orient2d(
                                        robust::Coord { x: a[0], y: a[1] },
                                        robust::Coord { x: b[0], y: b[1] },
                                        robust::Coord { x: c[0], y: c[1] },
                                    )
                                };
                                let mut area = 0.0;
                                for (ti, tr) in lv.tris.iter().enumerate() {
                                    let [a, b, c] = tr.map(|v| tin.verts[v as usize]);
                                    area += o(&a, &b, &c);
                                    if o(&a, &b, s) >= 0.0
                                        && o(&b, &c, s) >= 0.0
                                        && o(&c, &a, s) >= 0.0
                                    {
                                        eprintln!(
                                            "contained by {ti}: {a:?} {b:?} {c:?} area {}",
                                            o(&a, &b, &c)
                                        );
                                    }
                                }
                                eprintln!("total 2*area {area}, tris {}", lv.tris.len());
                                for (ti, tr) in lv.tris.iter().enumerate() {
                                    for j in 0..3 {
                                        if lv.nbrs[ti][j] == u32::MAX {
                                            let (u, w) = (
                                                tin.verts[tr[(j + 1) % 3] as usize],
                                                tin.verts[tr[(j + 2) % 3] as usize],
                                            );
                                            let cu = ((u[0] - ox) / px, (u[1] - oy) / px);
                                            let cw = ((w[0] - ox) / px, (w[1] - oy) / px);
                                            eprintln!("boundary edge of {ti}: {cu:?} -> {cw:?}");
                                        }
                                    }
                                }
                                panic!(
                                    "case {case} level {l}: sample {s:?} outside the tin: {lines:?}"
                                );
                            };
                            assert!(
                                (hz - s[2]).abs() <= tols[l] + 1e-6,
                                "case {case} level {l}: sample off by {}",
                                hz - s[2]
                            );
                        }
                    }
                    // a point in the middle of each piece of each segment
                    // well inside the grid lies on an edge along the segment
                    for (a, b, hard) in &segs {
                        for k in 1..20 {
                            let t = k as f64 / 20.0;
                            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0];
                            let (c, r) = ((p[0] - ox) / px, (p[1] - oy) / px);
                            if !(0.01..n as f64 - 1.01).contains(&c)
                                || !(0.01..n as f64 - 1.01).contains(&r)
                            {
                                continue;
                            }
                            // the edge along the segment holding the point,
                            // and the surface's height there along that edge
                            let on = lv.tris.iter().find_map(|tr| {
                                (0..3).find_map(|j| {
                                    let (u, v) = (
                                        &tin.verts[tr[j] as usize],
                                        &tin.verts[tr[(j + 1) % 3] as usize],
                                    );
                                    let (s, dist) = along(u, v, &p);
                                    let (_, du) = along(a, b, u);
                                    let (_, dv) = along(a, b, v);
                                    (du <= 1e-9
                                        && dv <= 1e-9
                                        && dist <= 1e-9
                                        && (-1e-9..=1.0 + 1e-9).contains(&s))
                                    .then(|| u[2] + s.clamp(0.0, 1.0) * (v[2] - u[2]))
                                })
                            });
                            let Some(z) = on else {
                                panic!(
                                    "case {case} level {l}: point {p:?} (t {t}, px {c} {r}) of {a:?}-{b:?} is on no edge along it: {lines:?}"
                                );
                            };
                            // along a hard line, the line's own heights (read
                            // along the edge: `height` at a point computed on
                            // the line may land a rounding inside a triangle
                            // whose third corner, a sample a millimetre from
                            // the line, is tens of metres off it)
                            if *hard {
                                assert!(
                                    (z - plane(p[0], p[1])).abs() <= 1e-6,
                                    "case {case} level {l}: hard line off by {} at {p:?} (t {t}) of {a:?}-{b:?}: {lines:?}",
                                    z - plane(p[0], p[1])
                                );
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!("built {built}, refused {refused}");
    assert!(built > 400, "built {built}, refused {refused}");
}

/// A line through a corner of the samples' hull, from outside (on a
/// geographic grid: the corner is on the line only up to rounding). The
/// corner sample is on the line, so it would be left out of the build; it
/// stays a vertex (of the line, cut at the corner), and the domain keeps
/// its whole area.
#[test]
fn a_line_through_a_hull_corner_keeps_the_domain() {
    let (px, ox, oy) = (1.0 / 1200.0, -84.31 + 1.0 / 2400.0, 36.47 + 1.0 / 3600.0);
    let n = 16usize;
    let at = |c: f64, r: f64| [ox + c * px, oy + r * px];
    let mut samples = Vec::new();
    for r in 0..n {
        for c in 0..n {
            let [x, y] = at(c as f64, r as f64);
            samples.push([x, y, 100.0 + ((c * 7 + r * 3) % 11) as f64]);
        }
    }
    let side = (n - 1) as f64 * px;
    for hard in [false, true] {
        for (p, q) in [
            ((-2.0, -2.0), (6.0, 6.0)),
            ((17.0, 17.0), (9.0, 9.0)),
            ((-3.0, 18.0), (5.0, 10.0)),
        ] {
            let z = |c: f64| if hard { 100.0 + c } else { f64::NAN };
            let [x0, y0] = at(p.0, p.1);
            let [x1, y1] = at(q.0, q.1);
            let line = Breakline {
                pts: vec![[x0, y0, z(p.0)], [x1, y1, z(q.0)]],
                hard,
            };
            let tin = build_breaklines(samples.clone(), &[line], &[4.0, 1.0], 4326, &mut || Ok(()))
                .unwrap();
            assert!(problems(&tin, &mut || Ok(())).unwrap().is_empty());
            for (l, lv) in tin.levels.iter().enumerate() {
                let area = domain_area(&tin, lv);
                assert!(
                    (area - side * side).abs() <= 1e-9 * side * side,
                    "hard {hard}, line {p:?}-{q:?}, level {l}: domain {area}, the grid's {}",
                    side * side
                );
                for s in &samples {
                    assert!(
                        height(&tin, l, s[0], s[1]).is_some(),
                        "sample {s:?} outside the tin"
                    );
                }
            }
        }
    }
}
