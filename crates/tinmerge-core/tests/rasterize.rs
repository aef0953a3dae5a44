//! `rasterize` (`tin_as_raster`) against two oracles at every pixel centre,
//! on the three terrains of `common::terrains` (projected, geographic, and
//! with void triangles), every level, on grids aligned with the source
//! DEM (where pixel centres fall on vertices and edges) and on grids of odd
//! pixel sizes with fractional origins reaching past the tin:
//! - `tin_height`'s function (`merge::point::height`), bit for bit, with
//!   NaN exactly where it has no height;
//! - a brute force written here: every domain triangle's pixel centres by
//!   its own orientation test, the height by `common::plane_height`. A
//!   centre clearly inside a triangle must carry its plane's height (within
//!   1e-9 of the relief), one clearly outside every domain triangle must be
//!   NaN;
//! - the triangle named at each centre holds it and its plane gives the
//!   height, the same on one thread and two.
use crate::common;

use tinmerge_core::analysis::rasterize::{aligned_grid, rasterize, triangles_at};
use tinmerge_core::io::raster::GeoTransform;
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::{Tin, par};

/// Signed twice-area of (a, b, p), in plain f64: the oracle's own test,
/// trusted only away from zero.
fn side(a: &[f64; 3], b: &[f64; 3], p: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Counts of (centres with a height, centres on ties checked loosely).
fn check(name: &str, tin: &Tin, level: usize, gt: &GeoTransform, w: usize, h: usize) -> usize {
    let z = rasterize(tin, level, gt, w, h, &mut || Ok(())).unwrap();
    assert_eq!(z.len(), w * h);
    // 1. tin_height, bit for bit
    let mut valued = 0;
    for r in 0..h {
        for c in 0..w {
            let (x, y) = gt.centre(c, r);
            let got = z[r * w + c];
            match height(tin, level, x, y) {
                Some(want) => {
                    assert!(
                        got.to_bits() == want.to_bits(),
                        "{name} level {level}: pixel ({c}, {r}) at ({x}, {y}) is {got}, tin_height says {want}"
                    );
                    valued += 1;
                }
                None => assert!(
                    got.is_nan(),
                    "{name} level {level}: pixel ({c}, {r}) at ({x}, {y}) is {got} off the domain"
                ),
            }
        }
    }
    // 2. the brute force: triangle by triangle, the centres in its box
    let lv = &tin.levels[level];
    let relief = tin.verts.iter().map(|v| v[2].abs()).fold(1.0, f64::max);
    let inv_x = 1.0 / gt.scale_x;
    let inv_y = 1.0 / gt.scale_y;
    let mut inside_some = vec![false; w * h];
    for t in 0..lv.num_domain() as u32 {
        let co = tin.corners(level, t);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for v in &co {
            x0 = x0.min(v[0]);
            x1 = x1.max(v[0]);
            y0 = y0.min(v[1]);
            y1 = y1.max(v[1]);
        }
        // columns and rows whose centres may be in the box (one more each side)
        let col = |x: f64| ((x - gt.ip_x) * inv_x - 0.5).floor();
        let row = |y: f64| ((y - gt.ip_y) * inv_y - 0.5).floor();
        let (ca, cb) = (col(x0).min(col(x1)) - 1.0, col(x0).max(col(x1)) + 2.0);
        let (ra, rb) = (row(y0).min(row(y1)) - 1.0, row(y0).max(row(y1)) + 2.0);
        let ca = ca.max(0.0) as usize;
        let cb = (cb.max(0.0) as usize).min(w);
        let ra = ra.max(0.0) as usize;
        let rb = (rb.max(0.0) as usize).min(h);
        let scale = (x1 - x0).max(y1 - y0);
        for r in ra..rb {
            for c in ca..cb {
                let (x, y) = gt.centre(c, r);
                let s = [
                    side(&co[0], &co[1], [x, y]),
                    side(&co[1], &co[2], [x, y]),
                    side(&co[2], &co[0], [x, y]),
                ];
                let margin = 1e-9 * scale * scale.max(gt.scale_x.abs());
                if s.iter().all(|&v| v > margin) {
                    let want = common::plane_height(&co, x, y);
                    let got = z[r * w + c];
                    assert!(
                        (got - want).abs() <= 1e-9 * relief,
                        "{name} level {level}: pixel ({c}, {r}) inside triangle {t} is {got}, its plane gives {want}"
                    );
                }
                if s.iter().all(|&v| v >= -margin) {
                    inside_some[r * w + c] = true;
                }
            }
        }
    }
    for (i, &v) in z.iter().enumerate() {
        assert!(
            inside_some[i] || v.is_nan(),
            "{name} level {level}: pixel ({}, {}) is {v} but no domain triangle holds its centre",
            i % w,
            i / w
        );
    }
    // 3. the triangle triangles_at names at each centre (the viewshed's
    // heights and walks start there): a domain triangle holding it, whose
    // plane gives its height; none off the domain. On one thread and on
    // two, the same.
    let before = par::threads();
    par::set_threads(1);
    let z1 = rasterize(tin, level, gt, w, h, &mut || Ok(())).unwrap();
    let tris = triangles_at(tin, level, gt, w, h, &mut || Ok(())).unwrap();
    par::set_threads(2);
    let z2 = rasterize(tin, level, gt, w, h, &mut || Ok(())).unwrap();
    let tris2 = triangles_at(tin, level, gt, w, h, &mut || Ok(())).unwrap();
    par::set_threads(before);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(
        bits(&z1) == bits(&z) && bits(&z2) == bits(&z) && tris == tris2,
        "{name} level {level}: threads change the heights"
    );
    for (i, (&v, &t)) in z.iter().zip(&tris).enumerate() {
        let (c, r) = (i % w, i / w);
        if v.is_nan() {
            assert_eq!(
                t,
                u32::MAX,
                "{name} level {level}: pixel ({c}, {r}) off the domain names a triangle"
            );
            continue;
        }
        assert!(
            (t as usize) < lv.num_domain(),
            "{name} level {level}: pixel ({c}, {r}) names {t}"
        );
        let co = tin.corners(level, t);
        let (x, y) = gt.centre(c, r);
        let span = |k: usize| {
            let v = [co[0][k], co[1][k], co[2][k]];
            v.iter().fold(f64::MIN, |a, &b| a.max(b)) - v.iter().fold(f64::MAX, |a, &b| a.min(b))
        };
        let scale = span(0).max(span(1));
        let margin = 1e-9 * scale * scale.max(gt.scale_x.abs());
        let s = [
            side(&co[0], &co[1], [x, y]),
            side(&co[1], &co[2], [x, y]),
            side(&co[2], &co[0], [x, y]),
        ];
        assert!(
            s.iter().all(|&v| v >= -margin),
            "{name} level {level}: pixel ({c}, {r}) is not in the triangle {t} named"
        );
        assert!(
            (common::plane_height(&co, x, y) - v).abs() <= 1e-9 * relief,
            "{name} level {level}: pixel ({c}, {r}): triangle {t}'s plane is not its height"
        );
    }
    valued
}

#[test]
fn heights_at_pixel_centres_equal_tin_height_and_the_triangles_planes() {
    for terrain in common::terrains() {
        let dem = common::read_dem(terrain.file);
        let tin = &terrain.tin;
        let b = &tin.bbox;
        let (sx, sy) = (dem.scale_x, dem.scale_y);
        let grids = [
            // the source DEM's own grid: centres on every vertex
            ("source grid", dem.geotransform(), dem.width, dem.height),
            // the source grid at twice the resolution: centres on edges too
            {
                let (gt, w, h) = aligned_grid(
                    &[b.min_x, b.min_y, b.max_x, b.max_y],
                    sx / 2.0,
                    sy / 2.0,
                    dem.origin_x,
                    dem.origin_y,
                )
                .unwrap();
                ("half-pixel grid", gt, w, h)
            },
            // odd pixels, a fractional origin, past the tin on every side
            {
                let gt = GeoTransform {
                    scale_x: sx * 2.37,
                    scale_y: -sy * 1.91,
                    ip_x: b.min_x - 3.3 * sx,
                    ip_y: b.max_y + 2.7 * sy,
                    skew_x: 0.0,
                    skew_y: 0.0,
                };
                let w = ((b.max_x - b.min_x) / (sx * 2.37)) as usize + 5;
                let h = ((b.max_y - b.min_y) / (sy * 1.91)) as usize + 5;
                ("odd grid", gt, w, h)
            },
        ];
        for (gname, gt, w, h) in grids {
            for level in 0..tin.num_levels() {
                let name = format!("{} ({gname})", terrain.name);
                let n = check(&name, tin, level, &gt, w, h);
                assert!(
                    n > w * h / 2,
                    "{name} level {level}: only {n} of {} pixels have heights",
                    w * h
                );
            }
        }
    }
}

#[test]
fn aligned_grids_cover_the_rectangle_with_the_fewest_pixels() {
    // the oracle: the grid lines k * size + origin just outside each side
    let cases = [
        ([0.0, 0.0, 10.0, 10.0], 2.0, 0.0),
        ([0.3, -7.1, 10.2, 3.3], 2.5, 0.0),
        ([1000.25, 2000.75, 1003.0, 2009.0], 0.7, 0.1),
        ([-84.5, 36.2, -84.1, 36.4], 1.0 / 3600.0, 0.0),
    ];
    for (bbox, size, origin) in cases {
        let (gt, w, h) = aligned_grid(&bbox, size, size, origin, origin).unwrap();
        let right = gt.ip_x + w as f64 * size;
        let bottom = gt.ip_y - h as f64 * size;
        let eps = 1e-9 * size;
        assert!(
            gt.ip_x <= bbox[0] + eps && gt.ip_x > bbox[0] - size + eps,
            "{bbox:?}"
        );
        assert!(
            right >= bbox[2] - eps && right < bbox[2] + size - eps,
            "{bbox:?}"
        );
        assert!(
            bottom <= bbox[1] + eps && bottom > bbox[1] - size + eps,
            "{bbox:?}"
        );
        assert!(
            gt.ip_y >= bbox[3] - eps && gt.ip_y < bbox[3] + size - eps,
            "{bbox:?}"
        );
        let k = (gt.ip_x - origin) / size;
        assert!(
            (k - k.round()).abs() < 1e-6,
            "{bbox:?}: left edge off the grid"
        );
        let k = (gt.ip_y - origin) / size;
        assert!(
            (k - k.round()).abs() < 1e-6,
            "{bbox:?}: top edge off the grid"
        );
    }
    assert!(aligned_grid(&[0.0, 0.0, 1.0, 1.0], 0.0, 1.0, 0.0, 0.0).is_err());
    assert!(aligned_grid(&[0.0, 0.0, 1.0, 1.0], f64::NAN, 1.0, 0.0, 0.0).is_err());
    assert!(aligned_grid(&[0.0, 0.0, 1e6, 1.0], 1.0, 1.0, 0.0, 0.0).is_err());
}

#[test]
fn rotated_grids_are_refused() {
    let tin = common::dem_tin();
    let gt = GeoTransform {
        scale_x: 10.0,
        scale_y: -10.0,
        ip_x: tin.bbox.min_x,
        ip_y: tin.bbox.max_y,
        skew_x: 0.5,
        skew_y: 0.0,
    };
    let e = rasterize(&tin, 0, &gt, 10, 10, &mut || Ok(())).unwrap_err();
    assert!(e.to_string().contains("rotated"), "{e}");
}
