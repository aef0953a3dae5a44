//! Tiles of one terrain: two tiles of the DEM sharing one column of samples,
//! each built on its own with `keep_border`, have the same surface along the
//! shared column (heights continuous across the seam at every level), and
//! every seam sample is a vertex of both. Without `keep_border` the seam
//! samples are not all vertices: each build then refines the straight hull
//! edge along the seam on its own, and the two surfaces agree only as far as
//! the two greedy builds happen to choose the same seam vertices (on this
//! DEM they nearly do); the option makes the agreement a property of the
//! construction.
mod common;

use tinmerge_core::merge::point::height;
use tinmerge_core::tin::build::{build_with, default_tolerances, BuildOptions};
use tinmerge_core::tin::Tin;

/// Samples of the columns `c0..=c1` of the DEM.
fn tile(d: &common::Dem, c0: usize, c1: usize) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for r in 0..d.height {
        for c in c0..=c1 {
            let v = d.values[r * d.width + c];
            if !v.is_nan() && Some(v) != d.nodata {
                let (x, y) = d.centre(c, r);
                out.push([x, y, v]);
            }
        }
    }
    out
}

/// Largest |left - right| over the seam points both tiles cover (samples of
/// the seam column and the midpoints between consecutive ones), per level,
/// and how many seam samples are not answered by their own value.
fn seam(d: &common::Dem, col: usize, a: &Tin, b: &Tin) -> (Vec<f64>, usize, usize) {
    let mut worst = vec![0.0f64; a.levels.len()];
    let (mut points, mut not_vertex) = (0, 0);
    for r in 0..d.height {
        let v = d.values[r * d.width + col];
        if v.is_nan() || Some(v) == d.nodata {
            continue;
        }
        let (x, y) = d.centre(col, r);
        let (_, y2) = d.centre(col, r + 1);
        for (py, exact) in [(y, Some(v)), ((y + y2) / 2.0, None)] {
            for (l, w) in worst.iter_mut().enumerate() {
                let (Some(ha), Some(hb)) = (height(a, l, x, py), height(b, l, x, py)) else {
                    continue;
                };
                points += 1;
                *w = w.max((ha - hb).abs());
                if let Some(v) = exact {
                    if ha != v || hb != v {
                        not_vertex += 1;
                    }
                }
            }
        }
    }
    (worst, points, not_vertex)
}

#[test]
fn shared_border_column_gives_a_continuous_surface() {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let col = d.width / 2;
    let tols = default_tolerances(2.0, 3).unwrap();
    let keep = BuildOptions { keep_border: true };
    let left = build_with(tile(&d, 0, col), &tols, 32616, keep, &mut || Ok(())).unwrap();
    let right = build_with(tile(&d, col, d.width - 1), &tols, 32616, keep, &mut || {
        Ok(())
    })
    .unwrap();
    left.sanity_check().unwrap();
    right.sanity_check().unwrap();
    let (worst, points, not_vertex) = seam(&d, col, &left, &right);
    eprintln!("keep_border: {points} seam points, worst |left - right| per level {worst:?}");
    assert!(points > 500, "{points} seam points");
    assert_eq!(
        not_vertex, 0,
        "seam samples that are not vertices of both tiles"
    );
    for (l, w) in worst.iter().enumerate() {
        assert!(
            *w <= 1e-9,
            "level {l}: heights differ by {w} across the seam"
        );
    }
    // without the option the seam samples are not all vertices
    let free = BuildOptions::default();
    let l2 = build_with(tile(&d, 0, col), &tols, 32616, free, &mut || Ok(())).unwrap();
    let r2 = build_with(tile(&d, col, d.width - 1), &tols, 32616, free, &mut || {
        Ok(())
    })
    .unwrap();
    let (worst2, _, not_vertex2) = seam(&d, col, &l2, &r2);
    eprintln!("without keep_border: {not_vertex2} seam samples not vertices, worst {worst2:?}");
    assert!(
        not_vertex2 > 0,
        "free builds keep every seam sample: the option shows nothing"
    );
    let count = |t: &Tin| t.levels.iter().map(|l| l.num_vertices).collect::<Vec<_>>();
    eprintln!(
        "vertices per level: kept {:?}/{:?}, free {:?}/{:?}",
        count(&left),
        count(&right),
        count(&l2),
        count(&r2)
    );
}

/// `build_tiles` on both DEMs (UTM and geographic, nodata around the
/// warped one), tiles of 97 pixels at 3 levels: each tile is the tin of
/// the samples the docs' keep_border pattern gives it (cut here by the
/// test's own rule and built on their own), every sample on a shared seam
/// (columns and rows) is a vertex of both tiles at every level, and
/// heights along the seams agree exactly from both sides.
#[test]
fn build_tiles_cuts_the_keep_border_pattern_and_its_seams_agree() {
    use tinmerge_core::merge::point::height;
    use tinmerge_core::tin::build::build_lattice;
    use tinmerge_core::tin::tiles::build_tiles;
    let n = 97;
    for (name, file, tol, srid) in [
        ("utm", "jacksboro_fault_dem_utm16n.tif", 2.0, 32616),
        ("geographic", "jacksboro_fault_dem.tif", 0.00002, 4326),
    ] {
        let d = common::read_dem(file);
        let lat = d.lattice();
        let valid = |v: f64| !v.is_nan() && Some(v) != d.nodata;
        let tols = default_tolerances(tol, 3).unwrap();
        let mut tiles: Vec<(usize, usize, Tin)> = Vec::new();
        build_tiles(
            &d.values,
            d.width,
            d.height,
            &valid,
            &lat,
            n,
            &tols,
            srid,
            &mut || Ok(()),
            &|tx, ty, t| (tx, ty, t),
            &mut |t| {
                tiles.push(t);
                Ok(())
            },
        )
        .unwrap();
        let (nx, ny) = (d.width.div_ceil(n), d.height.div_ceil(n));
        // the test's own cut: own pixels plus one more column and row
        let mut expect = 0;
        for ty in 0..ny {
            for tx in 0..nx {
                let mut s = Vec::new();
                for r in ty * n..((ty + 1) * n + 1).min(d.height) {
                    for c in tx * n..((tx + 1) * n + 1).min(d.width) {
                        let v = d.values[r * d.width + c];
                        if valid(v) {
                            s.push([c as f64, r as f64, v]);
                        }
                    }
                }
                let keep = BuildOptions { keep_border: true };
                let Ok(want) = build_lattice(s, &lat, &tols, srid, keep, &mut || Ok(())) else {
                    continue;
                };
                let got = tiles.iter().find(|t| (t.0, t.1) == (tx, ty));
                let got = got.unwrap_or_else(|| panic!("{name}: tile {tx},{ty} missing"));
                assert!(
                    tinmerge_core::tin::layout::encode(&got.2)
                        == tinmerge_core::tin::layout::encode(&want),
                    "{name}: tile {tx},{ty} differs from its own build"
                );
                // (sanity_check is exact in the lattice frame only; in world
                // coordinates: valid, and no sliver hiding a crack)
                tinmerge_core::tin::check::validate_structure(&got.2).unwrap();
                assert!(
                    tinmerge_core::tin::check::problems(&got.2, &mut || Ok(()))
                        .unwrap()
                        .is_empty(),
                    "{name}: tile {tx},{ty} has slivers"
                );
                expect += 1;
            }
        }
        assert_eq!(tiles.len(), expect, "{name}: tiles");
        assert!(expect > 6, "{name}: {expect} tiles");
        // seams: the column (row) shared with the right (lower) neighbour
        let tile =
            |tx: usize, ty: usize| tiles.iter().find(|t| (t.0, t.1) == (tx, ty)).map(|t| &t.2);
        let (mut points, mut worst) = (0usize, 0.0f64);
        for &(tx, ty, ref a) in &tiles {
            for (dx, dy) in [(1, 0), (0, 1)] {
                let Some(b) = tile(tx + dx, ty + dy) else {
                    continue;
                };
                // the seam's pixels: a column of a's rows, or a row of a's columns
                let seam: Vec<(usize, usize)> = if dx == 1 {
                    let c = (tx + 1) * n;
                    (ty * n..((ty + 1) * n + 1).min(d.height))
                        .map(|r| (c, r))
                        .collect()
                } else {
                    let r = (ty + 1) * n;
                    (tx * n..((tx + 1) * n + 1).min(d.width))
                        .map(|c| (c, r))
                        .collect()
                };
                for w in seam.windows(2) {
                    let (c, r) = w[0];
                    let v = d.values[r * d.width + c];
                    let v2 = d.values[w[1].1 * d.width + w[1].0];
                    if !valid(v) || !valid(v2) {
                        continue;
                    }
                    let (px, py) = lat.centre(c as f64, r as f64);
                    let (qx, qy) = lat.centre(w[1].0 as f64, w[1].1 as f64);
                    let (p, q) = ([px, py], [qx, qy]);
                    let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                    for l in 0..tols.len() {
                        let (ha, hb) = (height(a, l, p[0], p[1]), height(b, l, p[0], p[1]));
                        assert_eq!(
                            (ha, hb),
                            (Some(v), Some(v)),
                            "{name}: seam sample ({c}, {r}) level {l}"
                        );
                        let (ma, mb) = (height(a, l, mid[0], mid[1]), height(b, l, mid[0], mid[1]));
                        if let (Some(ma), Some(mb)) = (ma, mb) {
                            worst = worst.max((ma - mb).abs());
                        }
                        points += 1;
                    }
                }
            }
        }
        eprintln!(
            "{name}: {} tiles, {points} seam points, worst difference between midpoints {worst}",
            tiles.len()
        );
        assert!(points > 1000, "{name}: {points} seam points");
        assert!(worst <= 1e-9, "{name}: seams differ by {worst}");
    }
}
