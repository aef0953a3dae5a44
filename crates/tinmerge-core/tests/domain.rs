//! The valid-data outline of a raster (`tin::domain`) against the block
//! rule applied directly, on both bundled DEMs (nodata around each) and on
//! synthetic rasters with a hole, a checkerboard of corners touching, and
//! lone pixels: the rings' area equals the blocks' (squares plus half
//! triangles), and random points are inside the rings (crossing number)
//! exactly when the block rule puts them in the domain.
use crate::common;

use rand::{Rng, SeedableRng};
use tinmerge_core::tin::domain::{LatticePoint, ring_area2, valid_outline};

/// The block rule: is lattice point (x, y) (not on a lattice line) in the
/// domain? Its block's valid corners: all four, or three with the point in
/// their triangle.
fn oracle(valid: &dyn Fn(i64, i64) -> bool, x: f64, y: f64) -> bool {
    let (c, r) = (x.floor() as i64, y.floor() as i64);
    let ok = [
        valid(c, r),
        valid(c + 1, r),
        valid(c + 1, r + 1),
        valid(c, r + 1),
    ];
    let n = ok.iter().filter(|&&b| b).count();
    let (fx, fy) = (x - c as f64, y - r as f64);
    match n {
        4 => true,
        3 => {
            // the missing corner's triangle is cut off by the diagonal
            let missing = ok.iter().position(|&b| !b).unwrap_or(0);
            match missing {
                0 => fx + fy > 1.0,
                1 => fy > fx,
                2 => fx + fy < 1.0,
                _ => fx > fy,
            }
        }
        _ => false,
    }
}

fn inside(rings: &[Vec<LatticePoint>], x: f64, y: f64) -> bool {
    let mut c = false;
    for r in rings {
        for i in 0..r.len() {
            let (p, q) = (r[i], r[(i + 1) % r.len()]);
            let (px, py, qx, qy) = (p[0] as f64, p[1] as f64, q[0] as f64, q[1] as f64);
            if (py > y) != (qy > y) && x < px + (y - py) / (qy - py) * (qx - px) {
                c = !c;
            }
        }
    }
    c
}

fn check(name: &str, w: usize, h: usize, valid: &dyn Fn(usize, usize) -> bool) -> (usize, i64) {
    let rings = valid_outline(w, h, valid);
    let v = |c: i64, r: i64| {
        c >= 0 && r >= 0 && (c as usize) < w && (r as usize) < h && valid(c as usize, r as usize)
    };
    // area: squares count 2, triangles 1 (twice the area)
    let mut want = 0i64;
    for r in 0..h.saturating_sub(1) as i64 {
        for c in 0..w.saturating_sub(1) as i64 {
            let n = [v(c, r), v(c + 1, r), v(c + 1, r + 1), v(c, r + 1)]
                .iter()
                .filter(|&&b| b)
                .count();
            want += match n {
                4 => 2,
                3 => 1,
                _ => 0,
            };
        }
    }
    let got: i64 = rings.iter().map(|r| ring_area2(r)).sum();
    assert_eq!(
        got, want,
        "{name}: the rings hold {got} half blocks, the rule {want}"
    );
    // no ring passes a point twice, and none has a straight-on point
    for r in &rings {
        let mut s: Vec<_> = r.clone();
        s.sort_unstable();
        s.dedup();
        assert_eq!(s.len(), r.len(), "{name}: a ring passes a point twice");
    }
    let mut rng = rand::rngs::StdRng::seed_from_u64(26);
    for _ in 0..20_000 {
        let (x, y) = (
            rng.random::<f64>() * w as f64,
            rng.random::<f64>() * h as f64,
        );
        assert_eq!(inside(&rings, x, y), oracle(&v, x, y), "{name}: ({x}, {y})");
    }
    (rings.len(), got)
}

#[test]
fn outline_matches_the_block_rule() {
    for file in ["jacksboro_fault_dem_utm16n.tif", "jacksboro_fault_dem.tif"] {
        let d = common::read_dem(file);
        let valid = |c: usize, r: usize| {
            let v = d.values[r * d.width + c];
            !v.is_nan() && Some(v) != d.nodata
        };
        let (n, area2) = check(file, d.width, d.height, &valid);
        // against the convex hull of the valid centres (today's domain)
        let pts: Vec<[f64; 2]> = (0..d.height)
            .flat_map(|r| (0..d.width).map(move |c| (c, r)))
            .filter(|&(c, r)| valid(c, r))
            .map(|(c, r)| [c as f64, r as f64])
            .collect();
        use geo::{Area, ConvexHull, MultiPoint};
        let hull = MultiPoint::from(
            pts.iter()
                .map(|p| geo::Point::new(p[0], p[1]))
                .collect::<Vec<_>>(),
        )
        .convex_hull();
        println!(
            "{file}: {n} rings, data {} px², convex hull {:.1} px² ({:.1} % more)",
            area2 as f64 / 2.0,
            hull.unsigned_area(),
            100.0 * (hull.unsigned_area() / (area2 as f64 / 2.0) - 1.0)
        );
    }
    // a hole, corners touching (checkerboard of 2x2 blocks), lone pixels
    let holed =
        |c: usize, r: usize| !(((5..9).contains(&c) && (4..7).contains(&r)) || (c == 15 && r == 3));
    let (n, _) = check("hole", 20, 12, &holed);
    assert!(n >= 2, "the hole is a ring of its own");
    let checker = |c: usize, r: usize| ((c / 2) + (r / 2)).is_multiple_of(2);
    check("checkerboard", 16, 16, &checker);
    let lone = |c: usize, r: usize| (c * 7 + r * 3).is_multiple_of(5);
    check("lone pixels", 15, 15, &lone);
    let diag = |c: usize, r: usize| c + r >= 6 && c + r <= 14;
    check("diagonal band", 12, 12, &diag);
    // two triangles touching at one corner: (0,0), (1,0), (1,1) and
    // (1,1), (2,2), (1,2); the rings stay apart there
    let pinch = |c: usize, r: usize| [(0, 0), (1, 0), (1, 1), (2, 2), (1, 2)].contains(&(c, r));
    let (n, _) = check("pinch", 3, 3, &pinch);
    assert_eq!(n, 2, "two triangles touching at a corner are two rings");
    let pinches =
        |c: usize, r: usize| [(0, 0), (1, 0), (1, 1), (2, 2), (1, 2)].contains(&(c % 4, r % 4));
    check("pinches", 16, 16, &pinches);
}
