//! Raster merge against brute force: for every pixel centre, the owning
//! triangle is found by testing every triangle whose bounding box holds it
//! (written here from the rule's definition, with its own predicates), and
//! the sweep must hand exactly those pixels to exactly those triangles.
//! Rasters: the DEM itself (every tin vertex is a pixel centre: ties on
//! edges and vertices everywhere), a 4x finer grid, a shifted partial copy
//! with nodata, and a south-up copy.

use crate::common;

use common::{dem_tin, read_dem};
use robust::{Coord, orient2d};
use tinmerge_core::io::raster::GeoTransform;
use tinmerge_core::merge::raster::patch::TinLevel;
use tinmerge_core::merge::raster::stats::zonal_stats;
use tinmerge_core::merge::raster::{PixelGrid, sweep};
use tinmerge_core::tin::{NONE, Tin};

const UNOWNED: u32 = u32::MAX;

fn co(p: [f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

/// The rule, from its definition: the point moved by (ε, ε²) is inside.
fn moved_inside(t: [[f64; 2]; 3], p: [f64; 2]) -> bool {
    (0..3).all(|j| {
        let (u, v) = (t[j], t[(j + 1) % 3]);
        let o = orient2d(co(u), co(v), co(p));
        if o != 0.0 {
            return o > 0.0;
        }
        // orient(u, v, p + (ε, ε²)) = ε (v - u) x (1, ε)
        let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
        if dy != 0.0 { dy < 0.0 } else { dx > 0.0 }
    })
}

#[derive(Clone)]
struct Raster {
    gt: GeoTransform,
    w: usize,
    h: usize,
    values: Vec<f64>,
    nodata: f64,
}

impl Raster {
    fn centre(&self, col: usize, row: usize) -> [f64; 2] {
        let (x, y) = self.gt.centre(col, row);
        [x, y]
    }
}

/// Owner of every pixel by brute force (UNOWNED outside the domain: off
/// the hull, or in a void triangle, the last `num_void` of the level).
fn brute_owner(tin: &Tin, level: usize, r: &Raster) -> Vec<u32> {
    let lv = &tin.levels[level];
    let domain = lv.tris.len() as u32 - lv.num_void;
    let mut owner = vec![UNOWNED; r.w * r.h];
    let xs: Vec<f64> = (0..r.w).map(|c| r.centre(c, 0)[0]).collect();
    let ys: Vec<f64> = (0..r.h).map(|k| r.centre(0, k)[1]).collect();
    for t in 0..domain {
        let cs = tin.corners(level, t).map(|v| [v[0], v[1]]);
        let (x0, x1) = (
            cs.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
            cs.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            cs.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            cs.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
        );
        let cols: Vec<usize> = (0..r.w).filter(|&c| xs[c] >= x0 && xs[c] <= x1).collect();
        for row in (0..r.h).filter(|&k| ys[k] >= y0 && ys[k] <= y1) {
            for &col in &cols {
                let p = [xs[col], ys[row]];
                if moved_inside(cs, p) {
                    let o = &mut owner[row * r.w + col];
                    assert_eq!(*o, UNOWNED, "pixel ({col}, {row}) owned by {} and {t}", *o);
                    *o = t;
                }
            }
        }
    }
    // the domain's boundary (the hull, and edges to void triangles): a
    // centre on such an edge goes to its triangle; on a vertex of it, to
    // the triangle of the boundary edge starting there
    let mut hull = Vec::new();
    for (t, (tri, nb)) in lv
        .tris
        .iter()
        .zip(&lv.nbrs)
        .enumerate()
        .take(domain as usize)
    {
        for j in 0..3 {
            if nb[j] == NONE || nb[j] >= domain {
                let u = tin.verts[tri[(j + 1) % 3] as usize];
                let v = tin.verts[tri[(j + 2) % 3] as usize];
                hull.push((t as u32, [u[0], u[1]], [v[0], v[1]]));
            }
        }
    }
    for row in 0..r.h {
        for col in 0..r.w {
            if owner[row * r.w + col] != UNOWNED {
                continue;
            }
            let p = [xs[col], ys[row]];
            let mut hit = None;
            for &(t, u, v) in &hull {
                let on = orient2d(co(u), co(v), co(p)) == 0.0
                    && p[0] >= u[0].min(v[0])
                    && p[0] <= u[0].max(v[0])
                    && p[1] >= u[1].min(v[1])
                    && p[1] <= u[1].max(v[1]);
                if on && p != v {
                    assert!(hit.is_none(), "centre {p:?} on two hull edges");
                    hit = Some(t);
                }
            }
            if let Some(t) = hit {
                owner[row * r.w + col] = t;
            }
        }
    }
    owner
}

fn swept_owner(tin: &Tin, level: usize, r: &Raster, ordered: bool) -> Vec<u32> {
    let g = PixelGrid::new(&r.gt, r.w, r.h).unwrap();
    let mut owner = vec![UNOWNED; r.w * r.h];
    let mut last = (0usize, 0usize);
    sweep(
        &TinLevel::new(tin, level).unwrap(),
        &g,
        ordered,
        &mut || Ok(()),
        &mut |t, row, c0, c1| {
            assert!(c0 < c1 && c1 <= r.w);
            if ordered {
                assert!((row, c0) >= last, "runs out of order at row {row}");
                last = (row, c1);
            }
            for col in c0..c1 {
                let o = &mut owner[row * r.w + col];
                assert_eq!(*o, UNOWNED, "pixel ({col}, {row}) handed twice");
                *o = t;
            }
        },
    )
    .unwrap();
    owner
}

fn dem_raster() -> Raster {
    raster_of("jacksboro_fault_dem_utm16n.tif")
}

/// A bundled DEM as a raster (nodata -9999).
fn raster_of(file: &str) -> Raster {
    let d = read_dem(file);
    Raster {
        gt: d.geotransform(),
        w: d.width,
        h: d.height,
        nodata: d.nodata.unwrap_or(-9999.0),
        values: d
            .values
            .iter()
            .map(|&v| if v.is_nan() { -9999.0 } else { v })
            .collect(),
    }
}

/// A finer grid over the same area: each pixel `f x f` sub-pixels with the
/// parent's value.
fn finer(r: &Raster, f: usize) -> Raster {
    let (w, h) = (r.w * f, r.h * f);
    let mut values = vec![0.0; w * h];
    for row in 0..h {
        for col in 0..w {
            values[row * w + col] = r.values[(row / f) * r.w + col / f];
        }
    }
    Raster {
        gt: GeoTransform {
            scale_x: r.gt.scale_x / f as f64,
            scale_y: r.gt.scale_y / f as f64,
            ..r.gt
        },
        w,
        h,
        values,
        nodata: r.nodata,
    }
}

fn check(tin: &Tin, level: usize, r: &Raster) -> usize {
    let want = brute_owner(tin, level, r);
    for ordered in [false, true] {
        let got = swept_owner(tin, level, r, ordered);
        let diff: Vec<usize> = (0..want.len()).filter(|&i| want[i] != got[i]).collect();
        assert!(
            diff.is_empty(),
            "level {level}: {} pixels differ, first ({}, {}): brute {} sweep {}",
            diff.len(),
            diff[0] % r.w,
            diff[0] / r.w,
            want[diff[0]],
            got[diff[0]]
        );
    }
    // every owner's closed triangle holds the centre (tie-free check)
    for (i, &t) in want.iter().enumerate() {
        if t != UNOWNED {
            let cs = tin.corners(level, t);
            let p = r.centre(i % r.w, i / r.w);
            for j in 0..3 {
                let (u, v) = (cs[j], cs[(j + 1) % 3]);
                assert!(orient2d(co([u[0], u[1]]), co([v[0], v[1]]), co(p)) >= 0.0);
            }
        }
    }
    want.iter().filter(|&&t| t != UNOWNED).count()
}

fn check_stats(tin: &Tin, level: usize, r: &Raster) {
    let owner = brute_owner(tin, level, r);
    let n = tin.levels[level].tris.len();
    let mut vals: Vec<Vec<f64>> = vec![Vec::new(); n];
    for (i, &t) in owner.iter().enumerate() {
        let v = r.values[i];
        if t != UNOWNED && v != r.nodata {
            vals[t as usize].push(v);
        }
    }
    let g = PixelGrid::new(&r.gt, r.w, r.h).unwrap();
    let got = zonal_stats(
        &TinLevel::new(tin, level).unwrap(),
        &g,
        &r.values,
        Some(r.nodata),
        true,
        &mut || Ok(()),
    )
    .unwrap();
    let want: Vec<usize> = (0..n).filter(|&t| !vals[t].is_empty()).collect();
    assert_eq!(got.len(), want.len(), "triangles with pixels");
    for (z, &t) in got.iter().zip(&want) {
        let v = &vals[t];
        assert_eq!(z.triangle as usize, t);
        assert_eq!(z.count as usize, v.len());
        let sum: f64 = v.iter().sum();
        assert!((z.sum - sum).abs() <= 1e-9 * sum.abs().max(1.0));
        assert_eq!(z.min, v.iter().copied().fold(f64::INFINITY, f64::min));
        assert_eq!(z.max, v.iter().copied().fold(f64::NEG_INFINITY, f64::max));
        // mode: most frequent, smallest on ties, counted by a map
        let mut counts: std::collections::BTreeMap<u64, usize> = Default::default();
        for x in v {
            *counts.entry(x.to_bits() ^ (1 << 63)).or_default() += 1;
        }
        let best = v
            .iter()
            .copied()
            .max_by(|a, b| {
                let (ca, cb) = (
                    counts[&(a.to_bits() ^ (1 << 63))],
                    counts[&(b.to_bits() ^ (1 << 63))],
                );
                ca.cmp(&cb).then(b.total_cmp(a))
            })
            .unwrap();
        assert_eq!(z.mode, Some(best), "mode of triangle {t}");
    }
}

#[test]
fn dem_pixels_every_level() {
    for common::Terrain { name, file, tin } in common::terrains() {
        eprintln!("{name}");
        let r = raster_of(file);
        let valid = r.values.iter().filter(|&&v| v != r.nodata).count();
        let top = tin.num_levels() - 1;
        for level in 0..=top {
            let owned = check(&tin, level, &r);
            // a domain that is the hull of the valid pixels has them all
            assert!(
                tin.levels[level].num_void > 0 || owned >= valid,
                "{name} level {level}: {owned} centres owned, {valid} valid"
            );
        }
        check_stats(&tin, top, &r);
        check_stats(&tin, 0, &r);
    }
}

#[test]
fn finer_grid_no_vertex_ties() {
    let tin = dem_tin();
    let r = finer(&dem_raster(), 4);
    for level in [0, 2, 4] {
        check(&tin, level, &r);
    }
    check_stats(&tin, 4, &r);
}

#[test]
fn shifted_partial_raster_with_nodata() {
    // a window of the DEM grid starting 37 columns right and 50 rows down,
    // reaching 60 pixels past the east edge, every 7th pixel nodata
    let tin = dem_tin();
    let d = dem_raster();
    let (c0, r0, w, h) = (37usize, 50usize, d.w - 37 + 60, 200usize);
    let mut values = vec![-1.0; w * h];
    for row in 0..h {
        for col in 0..w {
            let (sc, sr) = (c0 + col, r0 + row);
            let v = if sc < d.w && sr < d.h {
                d.values[sr * d.w + sc]
            } else {
                1.0
            };
            values[row * w + col] = if (row * w + col) % 7 == 0 { -1.0 } else { v };
        }
    }
    let r = Raster {
        gt: GeoTransform {
            ip_x: d.gt.ip_x + c0 as f64 * d.gt.scale_x,
            ip_y: d.gt.ip_y + r0 as f64 * d.gt.scale_y,
            ..d.gt
        },
        w,
        h,
        values,
        nodata: -1.0,
    };
    for level in [0, 3, 4] {
        check(&tin, level, &r);
    }
    check_stats(&tin, 4, &r);
    check_stats(&tin, 1, &r);
}

#[test]
fn south_up_and_east_to_west_rasters() {
    let tin = dem_tin();
    let d = dem_raster();
    // the same grid stored bottom row first, then right column first
    let mut s = Raster {
        gt: GeoTransform {
            ip_y: d.gt.ip_y + d.h as f64 * d.gt.scale_y,
            scale_y: -d.gt.scale_y,
            ..d.gt
        },
        w: d.w,
        h: d.h,
        values: (0..d.h)
            .rev()
            .flat_map(|row| d.values[row * d.w..(row + 1) * d.w].to_vec())
            .collect(),
        nodata: d.nodata,
    };
    for level in [0, 4] {
        check(&tin, level, &s);
    }
    check_stats(&tin, 4, &s);
    s.gt.ip_x += d.w as f64 * d.gt.scale_x;
    s.gt.scale_x = -d.gt.scale_x;
    s.values = (0..d.h)
        .flat_map(|row| (0..d.w).rev().map(move |col| (row, col)))
        .map(|(row, col)| s.values[row * d.w + col])
        .collect();
    check(&tin, 2, &s);
    check_stats(&tin, 2, &s);
}

#[test]
fn skewed_raster_refused() {
    let gt = GeoTransform {
        scale_x: 1.0,
        scale_y: -1.0,
        ip_x: 0.0,
        ip_y: 0.0,
        skew_x: 0.1,
        skew_y: 0.0,
    };
    let e = PixelGrid::new(&gt, 3, 3).unwrap_err().to_string();
    assert!(e.contains("skewed"), "{e}");
}

// ---- coverage-weighted statistics -------------------------------------
//
// Oracle: every pixel square in a triangle's bounding box clipped by the
// triangle's three edge half-planes (Sutherland-Hodgman written here, in
// coordinates relative to the raster origin) and measured by the shoelace
// formula. The code under test clips the other way round (the triangle by
// row strips, then columns, in pixel units) and skips the arithmetic for
// whole pixels. Spot checks of the worst cells against exact rational
// clipping agreed to 1e-14; geo's BooleanOps was tried as the oracle but
// rounds to a fixed-point grid (errors ~2e-7 of a pixel).

use common::clip_half;
use std::collections::BTreeMap;
use tinmerge_core::merge::raster::coverage::coverage;
use tinmerge_core::merge::raster::stats::weighted_stats;

fn shoelace(p: &[[f64; 2]]) -> f64 {
    let mut s = 0.0;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    0.5 * s.abs()
}

/// (triangle, row, col) -> covered fraction, for fractions above 1e-10.
fn brute_coverage(tin: &Tin, level: usize, r: &Raster) -> BTreeMap<(u32, usize, usize), f64> {
    let gt = &r.gt;
    let px_area = (gt.scale_x * gt.scale_y).abs();
    let mut out = BTreeMap::new();
    let edge_x = |c: usize| c as f64 * gt.scale_x;
    let edge_y = |k: usize| k as f64 * gt.scale_y;
    for t in 0..tin.levels[level].tris.len() as u32 {
        // counter-clockwise corners relative to the origin (exact: the
        // same magnitudes)
        let cs = tin
            .corners(level, t)
            .map(|v| [v[0] - gt.ip_x, v[1] - gt.ip_y]);
        let (x0, x1) = (
            cs.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
            cs.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            cs.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            cs.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
        );
        for row in 0..r.h {
            let (ya, yb) = (edge_y(row), edge_y(row + 1));
            if ya.max(yb) <= y0 || ya.min(yb) >= y1 {
                continue;
            }
            for col in 0..r.w {
                let (xa, xb) = (edge_x(col), edge_x(col + 1));
                if xa.max(xb) <= x0 || xa.min(xb) >= x1 {
                    continue;
                }
                let mut p = vec![[xa, ya], [xb, ya], [xb, yb], [xa, yb]];
                for j in 0..3 {
                    p = clip_half(&p, cs[j], cs[(j + 1) % 3]);
                }
                let a = if p.len() < 3 {
                    0.0
                } else {
                    shoelace(&p) / px_area
                };
                // the documented noise floor
                if a > 1e-10 {
                    out.insert((t, row, col), a);
                }
            }
        }
    }
    out
}

fn check_coverage(tin: &Tin, level: usize, r: &Raster) -> BTreeMap<(u32, usize, usize), f64> {
    let want = brute_coverage(tin, level, r);
    let mut got = BTreeMap::new();
    let mut last = (0u32, 0usize, 0usize);
    coverage(
        &TinLevel::new(tin, level).unwrap(),
        &r.gt,
        r.w,
        r.h,
        &mut || Ok(()),
        &mut |t, row, col, f| {
            assert!((t, row, col) > last || got.is_empty(), "cells out of order");
            last = (t, row, col);
            assert!(f > 1e-10 && f <= 1.0, "fraction {f}");
            got.insert((t, row, col), f);
        },
    )
    .unwrap();
    for (k, &a) in &want {
        let g = got.get(k).copied().unwrap_or(0.0);
        assert!(
            (g - a).abs() < 1e-10,
            "level {level} cell {k:?}: brute {a}, coverage {g}"
        );
    }
    for (k, &g) in &got {
        if !want.contains_key(k) {
            assert!(g < 1e-10, "level {level} cell {k:?}: coverage {g}, brute 0");
        }
    }
    // a pixel wholly inside the domain is covered exactly once in total
    let mut per_px: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    for (&(_, row, col), &f) in &got {
        *per_px.entry((row, col)).or_default() += f;
    }
    assert!(per_px.values().all(|&s| s < 1.0 + 1e-12));
    let inside = per_px.values().filter(|&&s| s > 1.0 - 1e-7).count();
    let exact = per_px
        .values()
        .filter(|&&s| (s - 1.0).abs() < 1e-12)
        .count();
    assert!(
        inside > 0 && exact == inside,
        "{inside} pixels inside, {exact} summing to 1 within 1e-12"
    );
    got
}

fn check_weighted(tin: &Tin, level: usize, r: &Raster) {
    let cov = brute_coverage(tin, level, r);
    let mut per: BTreeMap<u32, Vec<(f64, f64)>> = BTreeMap::new();
    for (&(t, row, col), &f) in &cov {
        let v = r.values[row * r.w + col];
        if v != r.nodata {
            per.entry(t).or_default().push((v, f));
        }
    }
    let got = weighted_stats(
        &TinLevel::new(tin, level).unwrap(),
        &r.gt,
        r.w,
        r.h,
        &r.values,
        Some(r.nodata),
        true,
        &mut || Ok(()),
    )
    .unwrap();
    assert_eq!(
        got.len(),
        per.len(),
        "level {level}: triangles overlapping valid pixels"
    );
    for (z, (&t, vf)) in got.iter().zip(&per) {
        assert_eq!(z.triangle, t);
        assert_eq!(z.count as usize, vf.len(), "triangle {t}: {vf:?}");
        let w: f64 = vf.iter().map(|p| p.1).sum();
        let s: f64 = vf.iter().map(|p| p.0 * p.1).sum();
        assert!((z.weight - w).abs() < 1e-10 * vf.len() as f64);
        assert!(
            (z.mean() - s / w).abs() <= 1e-9 * (s / w).abs().max(1.0),
            "mean of {t}"
        );
        assert_eq!(z.min, vf.iter().map(|p| p.0).fold(f64::INFINITY, f64::min));
        assert_eq!(
            z.max,
            vf.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max)
        );
        // weighted mode: value of greatest total coverage (values here
        // are distinct enough that ties within 1e-9 do not occur)
        let mut tot: BTreeMap<u64, f64> = BTreeMap::new();
        for &(v, f) in vf {
            *tot.entry(v.to_bits()).or_default() += f;
        }
        let best = tot.values().copied().fold(0.0, f64::max);
        let m = z.mode.unwrap();
        assert!(tot[&m.to_bits()] >= best - 1e-10, "mode of {t}");
    }
}

#[test]
fn coverage_on_the_dem_grid() {
    let tin = dem_tin();
    let r = dem_raster();
    // the vertices are pixel centres: triangle edges cross pixels anywhere
    for level in [0, 2] {
        check_coverage(&tin, level, &r);
    }
    check_weighted(&tin, 0, &r);
}

#[test]
fn coverage_with_vertices_on_pixel_corners() {
    // the grid shifted by half a pixel: tin vertices are pixel corners, so
    // axis-parallel edges run along pixel edges (zero-area slivers)
    let tin = dem_tin();
    let d = dem_raster();
    let mut r = finer(&d, 2);
    r.gt.ip_x += d.gt.scale_x / 2.0;
    r.gt.ip_y += d.gt.scale_y / 2.0;
    check_coverage(&tin, 1, &r);
    check_weighted(&tin, 4, &r);
}

#[test]
fn coverage_of_a_partial_raster_with_nodata() {
    let tin = dem_tin();
    let d = dem_raster();
    // 3x coarser pixels, a window that starts outside the domain
    let (w, h) = (60usize, 40usize);
    let gt = GeoTransform {
        scale_x: d.gt.scale_x * 3.3,
        scale_y: d.gt.scale_y * 3.3,
        ip_x: d.gt.ip_x - 20.0 * d.gt.scale_x,
        ip_y: d.gt.ip_y + 100.0 * d.gt.scale_y,
        ..d.gt
    };
    let values = (0..w * h)
        .map(|i| if i % 11 == 0 { -1.0 } else { (i % 17) as f64 })
        .collect();
    let r = Raster {
        gt,
        w,
        h,
        values,
        nodata: -1.0,
    };
    for level in [0, 3] {
        check_coverage(&tin, level, &r);
        check_weighted(&tin, level, &r);
    }
}

/// `tinmerge.threads`: the banded sweep on 2 threads hands the same runs in
/// the same order as the serial sweep, and zonal (with mode) and weighted
/// statistics are bit for bit those of 1 thread. A 4x and a 3x finer grid
/// (1.9M and 1.07M pixels: several bands, band borders at rows no vertex
/// lies on and at rows through vertices) and the DEM itself, coarse and
/// fine levels.
#[test]
fn threads_give_identical_answers() {
    use tinmerge_core::merge::raster::stats::weighted_stats;
    use tinmerge_core::merge::raster::sweep_par;
    use tinmerge_core::tin::par;
    let tin = dem_tin();
    let d = dem_raster();
    for r in [finer(&d, 4), finer(&d, 3), d.clone()] {
        let g = PixelGrid::new(&r.gt, r.w, r.h).unwrap();
        for level in [0, 2, 4] {
            let mut serial = Vec::new();
            sweep(
                &TinLevel::new(&tin, level).unwrap(),
                &g,
                false,
                &mut || Ok(()),
                &mut |t, row, c0, c1| serial.push((t, row, c0, c1)),
            )
            .unwrap();
            par::set_threads(2);
            let mut banded = Vec::new();
            sweep_par(
                &TinLevel::new(&tin, level).unwrap(),
                &g,
                &mut || Ok(()),
                &|t, row, c0, c1| (t, row, c0, c1),
                &mut |s| banded.push(s),
            )
            .unwrap();
            assert!(
                serial == banded,
                "{} px, level {level}: runs differ",
                r.w * r.h
            );
            let mut stats = Vec::new();
            for n in [1, 2] {
                par::set_threads(n);
                let z = zonal_stats(
                    &TinLevel::new(&tin, level).unwrap(),
                    &g,
                    &r.values,
                    Some(r.nodata),
                    true,
                    &mut || Ok(()),
                )
                .unwrap();
                let w = weighted_stats(
                    &TinLevel::new(&tin, level).unwrap(),
                    &r.gt,
                    r.w,
                    r.h,
                    &r.values,
                    Some(r.nodata),
                    true,
                    &mut || Ok(()),
                )
                .unwrap();
                stats.push((z, w));
            }
            par::set_threads(1);
            assert!(!stats[0].0.is_empty() && !stats[0].1.is_empty());
            assert!(
                stats[0] == stats[1],
                "{} px, level {level}: statistics differ",
                r.w * r.h
            );
        }
    }
}
