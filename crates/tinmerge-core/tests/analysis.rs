//! Contours and slope/aspect against oracles written here: per triangle,
//! the isoline piece from the corners' heights (each edge whose ends are on
//! either side of the height, a corner at the height counting as above),
//! summed per height; the plane's gradient by Cramer's rule. Both bundled
//! DEMs (UTM and geographic), every level.
use crate::common;

use std::collections::BTreeMap;
use tinmerge_core::analysis::contour::contours;
use tinmerge_core::analysis::slope::slope_aspect;
use tinmerge_core::tin::{NONE, Tin};

fn tins() -> Vec<(&'static str, Tin)> {
    vec![
        ("utm", common::dem_tin()),
        ("geographic", common::geo_tin(2.0)),
    ]
}

/// The oracle's isoline pieces of `level` at height `z`: (length, ends).
fn oracle_pieces(tin: &Tin, level: usize, z: f64) -> Vec<(f64, [[f64; 2]; 2])> {
    let mut out = Vec::new();
    for t in 0..tin.levels[level].tris.len() as u32 {
        let c = tin.corners(level, t);
        let mut pts: Vec<[f64; 2]> = Vec::new();
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (c[i], c[j]);
            if (a[2] >= z) == (b[2] >= z) {
                continue;
            }
            let p = if a[2] == z {
                [a[0], a[1]]
            } else if b[2] == z {
                [b[0], b[1]]
            } else {
                let r = (z - a[2]) / (b[2] - a[2]);
                [a[0] + r * (b[0] - a[0]), a[1] + r * (b[1] - a[1])]
            };
            pts.push(p);
        }
        assert!(
            pts.is_empty() || pts.len() == 2,
            "triangle {t}: {} crossings",
            pts.len()
        );
        if pts.len() == 2 {
            let len = (pts[0][0] - pts[1][0]).hypot(pts[0][1] - pts[1][1]);
            if len > 0.0 {
                out.push((len, [pts[0], pts[1]]));
            }
        }
    }
    out
}

#[test]
fn contours_match_the_per_triangle_oracle() {
    for (name, tin) in tins() {
        // hull edges, to check that open lines end on the domain's edge
        for level in 0..tin.levels.len() {
            let lv = &tin.levels[level];
            let mut hull = Vec::new();
            for (t, nb) in lv.nbrs.iter().enumerate() {
                for j in 0..3 {
                    if nb[j] == NONE {
                        let c = tin.corners(level, t as u32);
                        hull.push((
                            [c[(j + 1) % 3][0], c[(j + 1) % 3][1]],
                            [c[(j + 2) % 3][0], c[(j + 2) % 3][1]],
                        ));
                    }
                }
            }
            let on_hull = |p: [f64; 2]| {
                hull.iter().any(|&(a, b)| {
                    let o = robust::orient2d(
                        robust::Coord { x: a[0], y: a[1] },
                        robust::Coord { x: b[0], y: b[1] },
                        robust::Coord { x: p[0], y: p[1] },
                    );
                    // a crossing interpolated on a hull edge is within
                    // rounding of it
                    let scale = (b[0] - a[0]).abs().max((b[1] - a[1]).abs());
                    o.abs() <= 1e-9 * scale * scale
                        && p[0] >= a[0].min(b[0]) - 1e-9 * scale
                        && p[0] <= a[0].max(b[0]) + 1e-9 * scale
                        && p[1] >= a[1].min(b[1]) - 1e-9 * scale
                        && p[1] <= a[1].max(b[1]) + 1e-9 * scale
                })
            };
            // 10 m contours, and 7.3 m ones offset so they miss the
            // whole-metre heights (both kinds of crossing)
            for (interval, base) in [(10.0, 0.0), (7.3, 0.41)] {
                let lines = contours(&tin, level, interval, base, &mut || Ok(())).unwrap();
                let mut got: BTreeMap<u64, (f64, usize)> = BTreeMap::new();
                let (mut open, mut rings) = (0, 0);
                for l in &lines {
                    assert!(l.points.len() >= 2);
                    let e = got.entry(l.z.to_bits()).or_default();
                    for w in l.points.windows(2) {
                        e.0 += (w[0][0] - w[1][0]).hypot(w[0][1] - w[1][1]);
                        e.1 += 1;
                    }
                    let (a, b) = (l.points[0], *l.points.last().unwrap());
                    if a == b {
                        rings += 1;
                    } else {
                        open += 1;
                        assert!(
                            on_hull(a) && on_hull(b),
                            "{name} level {level} z {}: open line ends inside the domain",
                            l.z
                        );
                    }
                }
                let zs: Vec<f64> = {
                    let (lo, hi) = tin.verts[..lv.num_vertices as usize]
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                            (lo.min(v[2]), hi.max(v[2]))
                        });
                    let mut k = ((lo - base) / interval).ceil();
                    let mut v = Vec::new();
                    while base + k * interval <= hi {
                        v.push(base + k * interval);
                        k += 1.0;
                    }
                    v
                };
                let mut checked = 0;
                for z in zs {
                    let want = oracle_pieces(&tin, level, z);
                    let want_len: f64 = want.iter().map(|p| p.0).sum();
                    let (got_len, got_n) = got.get(&z.to_bits()).copied().unwrap_or((0.0, 0));
                    assert_eq!(got_n, want.len(), "{name} level {level} z {z}: pieces");
                    assert!(
                        (got_len - want_len).abs() <= 1e-9 * want_len.max(1.0),
                        "{name} level {level} z {z}: length {got_len} vs {want_len}"
                    );
                    checked += want.len();
                }
                assert!(checked > 100, "{name} level {level}: {checked} pieces");
                if level + 1 == tin.levels.len() && interval == 10.0 {
                    eprintln!(
                        "{name} finest level, 10 m: {} lines ({open} open, {rings} rings), {checked} pieces",
                        lines.len()
                    );
                }
            }
        }
    }
}

#[test]
fn slope_and_aspect_match_the_plane_gradient() {
    let tin = common::dem_tin();
    for level in 0..tin.levels.len() {
        for t in 0..tin.levels[level].tris.len() as u32 {
            let c = tin.corners(level, t);
            // z = a x + b y + k through the three corners (Cramer's rule)
            let m = |i: usize| [c[i][0] - c[0][0], c[i][1] - c[0][1], c[i][2] - c[0][2]];
            let (u, v) = (m(1), m(2));
            let det = u[0] * v[1] - u[1] * v[0];
            let a = (u[2] * v[1] - u[1] * v[2]) / det;
            let b = (u[0] * v[2] - u[2] * v[0]) / det;
            let want_slope = a.hypot(b).atan().to_degrees();
            let (s, asp) = slope_aspect(&c);
            assert!(
                (s - want_slope).abs() < 1e-9,
                "level {level} triangle {t}: slope {s} vs {want_slope}"
            );
            if a == 0.0 && b == 0.0 {
                assert_eq!(asp, None);
            } else {
                // downhill: (-a, -b); compass angle from north, clockwise
                let want = (-a).atan2(-b).to_degrees().rem_euclid(360.0);
                let got = asp.unwrap();
                let d = (got - want).abs();
                assert!(
                    d.min(360.0 - d) < 1e-7,
                    "level {level} triangle {t}: aspect {got} vs {want}"
                );
            }
        }
    }
}
