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
