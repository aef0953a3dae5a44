//! Tiles over their data only (`tin_tiles(..., fill_gaps => false)`,
//! issue 48), on both DEMs: the UTM one (nodata on its rotated border, a
//! ragged staircase through many tiles) and the geographic one with holes
//! put across the seams (a disc around a corner where four tiles meet,
//! single pixels on a seam column and a seam row, a ragged band of pixels).
//!
//! Oracles, the tests' own: the domain of each tile is the valid pixels'
//! squares clipped to the tile's rectangle of pixel centres and to the
//! convex hull of its valid centres (each square clipped by
//! `common::clip_half`, areas summed); along every seam, both tiles answer
//! at the same points (a quarter pixel apart) with the same heights, and
//! have the same vertices on it at every level.
use crate::common;

use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::default_tolerances;

/// The geographic DEM with nodata holes across the seams of `n`-pixel
/// tiles.
fn holed(n: usize) -> common::Dem {
    let mut d = common::read_dem("jacksboro_fault_dem.tif");
    let nd = -9999.0;
    d.nodata = Some(nd);
    let (w, h) = (d.width, d.height);
    for r in 0..h {
        for c in 0..w {
            let (dc, dr) = (c as f64 - (2 * n) as f64, r as f64 - (2 * n) as f64);
            let disc = dc * dc + dr * dr <= 15.0 * 15.0;
            let single = (c, r) == (n, 50) || (c, r) == (50, n) || (c, r) == (3 * n, 3 * n + 7);
            // a ragged band: scattered pixels near a seam column
            let band = c.abs_diff(3 * n) <= 3 && r > n && (c * 7 + r * 13) % 5 == 0;
            if disc || single || band {
                d.values[r * w + c] = nd;
            }
        }
    }
    d
}

/// The convex hull of integer points (monotone chain, counter-clockwise
/// with y up, collinear points dropped).
fn hull(mut p: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    p.sort();
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: (i64, i64), a: (i64, i64), b: (i64, i64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut lower: Vec<(i64, i64)> = Vec::new();
    for &q in &p {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0 {
            lower.pop();
        }
        lower.push(q);
    }
    let mut upper: Vec<(i64, i64)> = Vec::new();
    for &q in p.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0 {
            upper.pop();
        }
        upper.push(q);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

fn area(poly: &[[f64; 2]]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            (a[0] * b[1] - b[0] * a[1]) / 2.0
        })
        .sum()
}

/// Area of the triangles of level `l` that are not void.
fn domain_area(t: &Tin, l: usize) -> f64 {
    let lv = &t.levels[l];
    (0..lv.num_domain())
        .map(|k| {
            let [a, b, c] = lv.tris[k].map(|v| t.verts[v as usize]);
            (((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2.0).abs()
        })
        .sum()
}

/// The vertices of level `l` of `t` on a seam (`on`) that are corners of
/// a triangle of the domain, as bit patterns, sorted.
fn seam_vertices(t: &Tin, l: usize, on: &dyn Fn(&[f64; 3]) -> bool) -> Vec<(u64, u64)> {
    let lv = &t.levels[l];
    let mut v: Vec<(u64, u64)> = (0..lv.num_domain())
        .flat_map(|k| lv.tris[k])
        .map(|v| t.verts[v as usize])
        .filter(|p| on(p))
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

#[test]
fn tiles_over_the_data_cover_the_valid_squares_and_agree_on_their_seams() {
    let n = 61;
    for (name, d, tol, srid) in [
        (
            "utm",
            common::read_dem("jacksboro_fault_dem_utm16n.tif"),
            2.0,
            32616,
        ),
        ("geographic, holed", holed(n), 2.0, 4326),
    ] {
        let lat = d.lattice();
        let valid = |c: usize, r: usize| {
            let v = d.values[r * d.width + c];
            !v.is_nan() && Some(v) != d.nodata
        };
        let tols = default_tolerances(tol, 3).unwrap();
        let mut tiles = Vec::new();
        tinmerge_core::tin::seam_rounds::build_tiles(
            &d.values,
            d.width,
            d.height,
            &|v: f64| !v.is_nan() && Some(v) != d.nodata,
            &lat,
            n,
            &tols,
            false,
            srid,
            &mut || Ok(()),
            &|tx, ty, t| (tx, ty, t),
            &mut |t| {
                tiles.push(t);
                Ok(())
            },
        )
        .unwrap();
        let det = (lat.scale_x * lat.scale_y - lat.skew_x * lat.skew_y).abs();
        let window = |tx: usize, ty: usize| {
            let (c0, r0) = (tx * n, ty * n);
            (
                c0,
                r0,
                ((tx + 1) * n).min(d.width - 1),
                ((ty + 1) * n).min(d.height - 1),
            )
        };
        // the domain: valid squares in the rectangle and the hull
        let (mut cut, mut worst_area) = (0, 0.0f64);
        for (tx, ty, t) in &tiles {
            let (c0, r0, c1, r1) = window(*tx, *ty);
            let pts: Vec<(i64, i64)> = (r0..=r1)
                .flat_map(|r| (c0..=c1).map(move |c| (c, r)))
                .filter(|&(c, r)| valid(c, r))
                .map(|(c, r)| (c as i64, r as i64))
                .collect();
            let hl = hull(pts);
            let mut want = 0.0;
            let mut all_valid = true;
            for r in r0..=r1 {
                for c in c0..=c1 {
                    if !valid(c, r) {
                        all_valid = false;
                        continue;
                    }
                    let (x, y) = (c as f64, r as f64);
                    let mut sq = vec![
                        [(x - 0.5).max(c0 as f64), (y - 0.5).max(r0 as f64)],
                        [(x + 0.5).min(c1 as f64), (y - 0.5).max(r0 as f64)],
                        [(x + 0.5).min(c1 as f64), (y + 0.5).min(r1 as f64)],
                        [(x - 0.5).max(c0 as f64), (y + 0.5).min(r1 as f64)],
                    ];
                    for k in 0..hl.len() {
                        let (a, b) = (hl[k], hl[(k + 1) % hl.len()]);
                        sq = common::clip_half(
                            &sq,
                            [a.0 as f64, a.1 as f64],
                            [b.0 as f64, b.1 as f64],
                        );
                    }
                    want += area(&sq).abs();
                }
            }
            let want = want * det;
            if !all_valid {
                cut += 1;
            }
            for l in 0..tols.len() {
                let got = domain_area(t, l);
                let e = (got / want - 1.0).abs();
                worst_area = worst_area.max(e);
                assert!(
                    e < 1e-9,
                    "{name}: tile {tx},{ty} level {l}: domain {got} against the valid squares' {want}"
                );
            }
            tinmerge_core::tin::check::validate_structure(t).unwrap();
            let p = tinmerge_core::tin::check::problems(t, &mut || Ok(())).unwrap();
            assert!(p.is_empty(), "{name}: tile {tx},{ty}: {p:?}");
            // tolerance at the valid samples
            for r in r0..=r1 {
                for c in c0..=c1 {
                    if !valid(c, r) {
                        // a third of a pixel off a nodata centre: no height
                        let (x, y) = lat.centre(c as f64 + 0.33, r as f64 - 0.17);
                        assert!(
                            height(t, tols.len() - 1, x, y).is_none(),
                            "{name}: tile {tx},{ty} answers in nodata pixel {c},{r}"
                        );
                        continue;
                    }
                    let (x, y) = lat.centre(c as f64, r as f64);
                    let v = d.values[r * d.width + c];
                    for (l, &tl) in tols.iter().enumerate() {
                        let h = height(t, l, x, y).unwrap_or_else(|| {
                            panic!("{name}: tile {tx},{ty} level {l}: no height at {c},{r}")
                        });
                        assert!(
                            (h - v).abs() <= tl * (1.0 + 1e-9),
                            "{name}: tile {tx},{ty} level {l} at {c},{r}: {h} against {v}"
                        );
                    }
                }
            }
        }
        // seams: both tiles answer at the same points, with the same
        // heights, and have the same vertices
        let tile =
            |tx: usize, ty: usize| tiles.iter().find(|t| (t.0, t.1) == (tx, ty)).map(|t| &t.2);
        let (mut points, mut one_sided, mut worst) = (0usize, 0usize, 0.0f64);
        for (tx, ty, a) in &tiles {
            for (dx, dy) in [(1, 0), (0, 1)] {
                let Some(b) = tile(tx + dx, ty + dy) else {
                    continue;
                };
                let (c0, r0, c1, r1) = window(*tx, *ty);
                let seam: Vec<(f64, f64)> = if dx == 1 {
                    (0..=4 * (r1 - r0))
                        .map(|k| (c1 as f64, r0 as f64 + k as f64 / 4.0))
                        .collect()
                } else {
                    (0..=4 * (c1 - c0))
                        .map(|k| (c0 as f64 + k as f64 / 4.0, r1 as f64))
                        .collect()
                };
                for &(c, r) in &seam {
                    if (c.fract() - 0.5).abs() < 1e-12 || (r.fract() - 0.5).abs() < 1e-12 {
                        // a square's edge: where a run of data ends
                        continue;
                    }
                    let (x, y) = lat.centre(c, r);
                    for l in 0..tols.len() {
                        match (height(a, l, x, y), height(b, l, x, y)) {
                            (Some(p), Some(q)) => {
                                worst = worst.max((p - q).abs());
                                points += 1;
                            }
                            (None, None) => {}
                            _ => one_sided += 1,
                        }
                    }
                }
                let (sx, sy) = lat.centre(c1 as f64, r1 as f64);
                let on = |p: &[f64; 3]| if dx == 1 { p[0] == sx } else { p[1] == sy };
                for l in 0..tols.len() {
                    assert_eq!(
                        seam_vertices(a, l, &on),
                        seam_vertices(b, l, &on),
                        "{name}: seam of tile {tx},{ty} and {},{} level {l}: vertices differ",
                        tx + dx,
                        ty + dy
                    );
                }
            }
        }
        eprintln!(
            "{name}: {} tiles ({cut} with nodata in their window), domain areas within {worst_area:.1e}, {points} seam points, largest difference {worst:.1e}",
            tiles.len()
        );
        assert!(cut > 3, "{name}: {cut} tiles with nodata");
        assert_eq!(
            one_sided, 0,
            "{name}: seam points answered by one tile only"
        );
        assert!(points > 1000, "{name}: {points} seam points");
        assert!(worst <= 1e-9, "{name}: seams differ by {worst}");
    }
}
