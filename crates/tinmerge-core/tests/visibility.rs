//! Line of sight against a brute force written here from the triangles
//! alone: the sight segment clipped to every domain triangle of the level
//! (plain arithmetic), the clearance `g(d)` on each clip fitted as the
//! quadratic it is (three values, `common::plane_height`), the first
//! point below the surface found by bisection. Random pairs on both bundled
//! DEMs (UTM, geographic) and the DEM with a nodata hole, every level; the
//! earth's curvature against the textbook horizon distance.
use crate::common;

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use tinmerge_core::analysis::visibility::{Curvature, EARTH_RADIUS, line_of_sight};
use tinmerge_core::merge::point::height;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::build;

/// The oracle: (visible, distance of the first point where the sight line
/// is below the surface, least |g| over the clips' candidate minima: how
/// close to grazing the pair is).
fn oracle(
    tin: &Tin,
    level: usize,
    eye: [f64; 3],
    target: [f64; 3],
    c: f64,
) -> (bool, Option<f64>, f64) {
    let all: Vec<u32> = (0..tin.levels[level].num_domain() as u32).collect();
    oracle_in(tin, level, &all, eye, target, c)
}

/// [`oracle`] over the domain triangles `tris` of the level (a caller that
/// knows which triangles can meet its sight lines passes only those).
pub(crate) fn oracle_in(
    tin: &Tin,
    level: usize,
    tris: &[u32],
    eye: [f64; 3],
    target: [f64; 3],
    c: f64,
) -> (bool, Option<f64>, f64) {
    let total = (target[0] - eye[0]).hypot(target[1] - eye[1]);
    let zt = target[2] - c * total * total;
    let xy = |d: f64| {
        let t = d / total;
        (
            eye[0] + t * (target[0] - eye[0]),
            eye[1] + t * (target[1] - eye[1]),
        )
    };
    let (bx0, bx1) = (eye[0].min(target[0]), eye[0].max(target[0]));
    let (by0, by1) = (eye[1].min(target[1]), eye[1].max(target[1]));
    let mut first: Option<f64> = None;
    let mut graze = f64::INFINITY;
    for &t in tris {
        let co = tin.corners(level, t);
        if co.iter().all(|v| v[0] < bx0)
            || co.iter().all(|v| v[0] > bx1)
            || co.iter().all(|v| v[1] < by0)
            || co.iter().all(|v| v[1] > by1)
        {
            continue;
        }
        // clip the parameter interval by the three half-planes (CCW)
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for j in 0..3 {
            let (a, b) = (co[j], co[(j + 1) % 3]);
            let side = |x: f64, y: f64| (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
            let (s0, s1) = (side(eye[0], eye[1]), side(target[0], target[1]));
            if s0 < 0.0 && s1 < 0.0 {
                t1 = -1.0;
                break;
            }
            if s0 < 0.0 {
                t0 = t0.max(s0 / (s0 - s1));
            } else if s1 < 0.0 {
                t1 = t1.min(s0 / (s0 - s1));
            }
        }
        if t1 <= t0 {
            continue;
        }
        let (d0, d1) = (t0 * total, t1 * total);
        let g = |d: f64| {
            let (x, y) = xy(d);
            eye[2] + (zt - eye[2]) * (d / total) - common::plane_height(&co, x, y) + c * d * d
        };
        // the quadratic through three values: its least point on [d0, d1]
        let (ga, gm, gb) = (g(d0), g(0.5 * (d0 + d1)), g(d1));
        let h = 0.5 * (d1 - d0);
        let curv = (ga - 2.0 * gm + gb) / (2.0 * h * h);
        let mut dmin = if ga <= gb { d0 } else { d1 };
        if curv > 0.0 {
            let v = 0.5 * (d0 + d1) - (gb - ga) / (4.0 * h * curv);
            if v > d0 && v < d1 && g(v) < g(dmin) {
                dmin = v;
            }
        }
        let inner = |d: f64| d > 1e-9 * total && d < total * (1.0 - 1e-9);
        for d in [d0, d1, dmin] {
            if inner(d) {
                graze = graze.min(g(d).abs());
            }
        }
        // below by more than 1e-9 of the heights (the function's promise:
        // a target on the ground touches the sight line)
        let tol = 1e-9 * eye[2].abs().max(target[2].abs()).max(1.0);
        if g(dmin) < -tol && dmin < total {
            // bisection from the clip's start (or the start itself)
            let d = if ga < 0.0 {
                d0
            } else {
                let (mut lo, mut hi) = (d0, dmin);
                for _ in 0..200 {
                    let m = 0.5 * (lo + hi);
                    if g(m) < 0.0 { hi = m } else { lo = m }
                }
                hi
            };
            first = Some(first.map_or(d, |f: f64| f.min(d)));
        }
    }
    (first.is_none(), first, graze)
}

/// Random eye and target pairs on the level's domain, eyes 0-30 m and
/// targets 0-10 m above it, every other target on it (their heights from `tin_height`'s function:
/// input, not the answer).
fn pairs(tin: &Tin, level: usize, n: usize, seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    let mut rng = StdRng::seed_from_u64(seed);
    let b = tin.bbox;
    let mut out = Vec::new();
    let point = |rng: &mut StdRng, up: f64| loop {
        let (x, y) = (
            rng.random_range(b.min_x..b.max_x),
            rng.random_range(b.min_y..b.max_y),
        );
        if let Some(z) = height(tin, level, x, y) {
            return [
                x,
                y,
                if up > 0.0 {
                    z + rng.random_range(0.0..up)
                } else {
                    z
                },
            ];
        }
    };
    while out.len() < n {
        let e = point(&mut rng, 30.0);
        // every other target on the ground (target_height 0, the default)
        let t = point(&mut rng, if out.len() % 2 == 0 { 0.0 } else { 10.0 });
        out.push((e, t));
    }
    out
}

#[test]
fn line_of_sight_against_every_triangle() {
    let mut checked = 0;
    let mut blocked = 0;
    for terrain in common::terrains() {
        let tin = &terrain.tin;
        let relief = tin.bbox.max_z - tin.bbox.min_z;
        for level in 0..tin.num_levels() {
            for (k, (eye, target)) in pairs(tin, level, 150, 7 + level as u64)
                .into_iter()
                .enumerate()
            {
                let s = line_of_sight(tin, level, eye, target, Curvature::None, &mut || Ok(()))
                    .unwrap();
                let (vis, first, graze) = oracle(tin, level, eye, target, 0.0);
                let what = format!(
                    "{} level {level} pair {k}: {eye:?} -> {target:?}",
                    terrain.name
                );
                if graze < 1e-9 * relief.max(1.0) {
                    continue; // a grazing sight line: rounding decides
                }
                checked += 1;
                assert_eq!(
                    s.visible, vis,
                    "{what}: visible {} but the oracle says {vis} (first {first:?})",
                    s.visible
                );
                if let (Some(d), Some(want)) = (s.distance, first) {
                    blocked += 1;
                    let total = (target[0] - eye[0]).hypot(target[1] - eye[1]);
                    assert!(
                        (d - want).abs() <= 1e-6 * total,
                        "{what}: obstruction at {d}, the oracle's at {want}"
                    );
                    let o = s.obstruction.unwrap();
                    let z = height(tin, level, o[0], o[1]).unwrap();
                    assert!(
                        (o[2] - z).abs() <= 1e-6 * relief,
                        "{what}: obstruction z {} off the surface {z}",
                        o[2]
                    );
                }
                match (s.visible, s.clearance) {
                    (false, cl) => assert!(
                        cl.is_some_and(|c| c < 0.0),
                        "{what}: blocked with clearance {cl:?}"
                    ),
                    (true, Some(cl)) => {
                        assert!(cl >= -1e-9 * relief, "{what}: visible with clearance {cl}")
                    }
                    (true, None) => {}
                }
            }
        }
    }
    assert!(
        checked > 1500 && blocked > 300,
        "{checked} pairs checked, {blocked} blocked"
    );
}

#[test]
fn curvature_hides_beyond_the_textbook_horizon() {
    // flat ground at 0 over 200 km: an eye h above it sees ground at
    // distance D (target height 0) while D < sqrt(2 R' h), R' = R / (1 - k)
    let s = 100_000.0;
    let tin = build(
        vec![
            [-s, -s, 0.0],
            [s, -s, 0.0],
            [s, s, 0.0],
            [-s, s, 0.0],
            [0.0, 0.0, 0.0],
        ],
        &[0.0],
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    for (h, k) in [(100.0, 0.13), (10.0, 0.0), (500.0, 0.13), (1.7, 0.13)] {
        let horizon = (2.0 * EARTH_RADIUS / (1.0 - k) * h).sqrt();
        let curv = Curvature::Earth {
            refraction: k,
            metres_per_unit: 1.0,
        };
        for (f, want) in [(0.99, true), (1.01, false)] {
            let d = f * horizon;
            let eye = [-d / 2.0, 3.0, h];
            let target = [d / 2.0, 3.0, 0.0];
            let v = line_of_sight(&tin, 0, eye, target, curv, &mut || Ok(())).unwrap();
            assert_eq!(
                v.visible, want,
                "eye {h} m, k {k}: ground at {f} x the horizon ({horizon:.0} m)"
            );
            let flat =
                line_of_sight(&tin, 0, eye, target, Curvature::None, &mut || Ok(())).unwrap();
            assert!(flat.visible, "a flat earth hides nothing here");
        }
        // two heights: visible while D < sqrt(2R'h1) + sqrt(2R'h2)
        let h2 = 30.0;
        let both = horizon + (2.0 * EARTH_RADIUS / (1.0 - k) * h2).sqrt();
        for (f, want) in [(0.99, true), (1.01, false)] {
            let d = f * both;
            if d > 1.9 * s {
                continue;
            }
            let v = line_of_sight(
                &tin,
                0,
                [-d / 2.0, 0.0, h],
                [d / 2.0, 0.0, h2],
                curv,
                &mut || Ok(()),
            )
            .unwrap();
            assert_eq!(v.visible, want, "eyes {h} and {h2} m at {f} x {both:.0} m");
        }
    }
}

#[test]
fn degenerate_and_bad_input() {
    let tin = common::dem_tin();
    let b = tin.bbox;
    let (x, y) = ((b.min_x + b.max_x) / 2.0, (b.min_y + b.max_y) / 2.0);
    let z = height(&tin, 0, x, y).unwrap();
    // the same point: visible, nothing crossed
    let s = line_of_sight(
        &tin,
        0,
        [x, y, z + 2.0],
        [x, y, z],
        Curvature::None,
        &mut || Ok(()),
    )
    .unwrap();
    assert!(s.visible && s.clearance.is_none());
    // a target on the ground in plain view: seen, whatever the last bits of
    // its height (tin_line_of_sight's default target_height 0)
    let mut seen = 0;
    for k in 1..200 {
        let (tx, ty) = (x + k as f64 * 7.3, y - k as f64 * 3.1);
        let Some(tz) = height(&tin, 0, tx, ty) else {
            continue;
        };
        let s = line_of_sight(
            &tin,
            0,
            [x, y, z + 5000.0],
            [tx, ty, tz],
            Curvature::None,
            &mut || Ok(()),
        )
        .unwrap();
        assert!(
            s.visible,
            "from 5 km up, the ground at ({tx}, {ty}) is hidden at {:?}",
            s.distance
        );
        seen += 1;
    }
    assert!(seen > 100);
    assert!(
        line_of_sight(
            &tin,
            9,
            [x, y, z],
            [x + 1.0, y, z],
            Curvature::None,
            &mut || Ok(())
        )
        .is_err()
    );
    assert!(
        line_of_sight(
            &tin,
            0,
            [x, y, f64::NAN],
            [x + 1.0, y, z],
            Curvature::None,
            &mut || Ok(())
        )
        .is_err()
    );
    // an eye 1 km under the ground is blocked at once
    let s = line_of_sight(
        &tin,
        0,
        [x, y, z - 1000.0],
        [x + 500.0, y, z + 5000.0],
        Curvature::None,
        &mut || Ok(()),
    )
    .unwrap();
    assert!(!s.visible && s.distance == Some(0.0));
}
