//! Area merge on the real DEM against independent oracles written here:
//! coverage by Sutherland-Hodgman clipping of every ring to every triangle,
//! the relation from vertex/crossing tests on `geo`'s exact line
//! intersection, and statistics and volumes integrated over the clipped
//! polygons by fan triangulation. Polygons: `gdal_contour -p` bands of the
//! bundled DEM (multipolygons with holes), seeded random star polygons with
//! holes, and hand-made polygons along the triangle edges of a grid TIN.

use crate::common;

use common::dem_tin;
use geo::orient::{Direction, Orient};
use geo::{Coord, Line, LineIntersection, line_intersection::line_intersection};
use rand::{Rng, SeedableRng, rngs::StdRng};
use std::collections::{BTreeMap, HashSet};
use tinmerge_core::geom::Units;
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::surface::{
    SubtreeSums, SurfaceStats, stats, stats_with, volume, volume_parts, volume_parts_with,
};
use tinmerge_core::merge::area::{AreaRow, Method, Relation, area_rows, sweep};
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::build;
use wkt::TryFromWkt;

type P2 = [f64; 2];
type Polys = Vec<Vec<Vec<P2>>>;

fn no_interrupt() -> Result<(), tinmerge_core::tin::TinError> {
    Ok(())
}

/// The bundled contour bands (`gdal_contour -p -i 50` of the UTM DEM),
/// rings oriented by `geo` (shells counter-clockwise, holes clockwise).
fn bands() -> Vec<(String, Polys)> {
    let text = std::fs::read_to_string(common::data_path("contour_bands.csv")).unwrap();
    let mut out = Vec::new();
    for line in text.lines().skip(1) {
        let mut it = line.splitn(3, ',');
        let (lo, hi, w) = (it.next().unwrap(), it.next().unwrap(), it.next().unwrap());
        let mp = geo::MultiPolygon::<f64>::try_from_wkt_str(w.trim_matches('"')).unwrap();
        out.push((format!("band {lo}-{hi}"), polys_of(&mp)));
    }
    out
}

fn polys_of(mp: &geo::MultiPolygon<f64>) -> Polys {
    mp.orient(Direction::Default)
        .0
        .iter()
        .map(|p| {
            std::iter::once(p.exterior())
                .chain(p.interiors())
                .map(|r| r.0.iter().map(|c| [c.x, c.y]).collect())
                .collect()
        })
        .collect()
}

fn signed_area(r: &[P2]) -> f64 {
    let o = r[0];
    let mut s = 0.0;
    for i in 0..r.len() {
        let (p, q) = (r[i], r[(i + 1) % r.len()]);
        s += (p[0] - o[0]) * (q[1] - o[1]) - (q[0] - o[0]) * (p[1] - o[1]);
    }
    s / 2.0
}

/// Sutherland-Hodgman of one ring against a counter-clockwise triangle.
fn clip_ring(ring: &[P2], t: &[P2; 3]) -> Vec<P2> {
    let mut poly: Vec<P2> = ring.to_vec();
    if poly.first() == poly.last() {
        poly.pop();
    }
    for j in 0..3 {
        let (a, b) = (t[j], t[(j + 1) % 3]);
        let side = |p: P2| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let mut out = Vec::new();
        for i in 0..poly.len() {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let s = sp / (sp - sq);
                out.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

fn tri2(tin: &Tin, l: usize, t: u32) -> [P2; 3] {
    tin.corners(l, t).map(|v| [v[0], v[1]])
}

fn strictly_inside(t: &[P2; 3], p: P2) -> bool {
    (0..3).all(|j| {
        let (a, b) = (t[j], t[(j + 1) % 3]);
        robust::orient2d(
            robust::Coord { x: a[0], y: a[1] },
            robust::Coord { x: b[0], y: b[1] },
            robust::Coord { x: p[0], y: p[1] },
        ) > 0.0
    })
}

/// Whether a ring segment passes through the open triangle: an end or the
/// midpoint strictly inside, or a proper crossing of an edge.
fn crosses_inside(t: &[P2; 3], a: P2, b: P2) -> bool {
    let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    if strictly_inside(t, a) || strictly_inside(t, b) || strictly_inside(t, mid) {
        return true;
    }
    let s = Line::new(Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] });
    (0..3).any(|j| {
        let e = Line::new(
            Coord {
                x: t[j][0],
                y: t[j][1],
            },
            Coord {
                x: t[(j + 1) % 3][0],
                y: t[(j + 1) % 3][1],
            },
        );
        matches!(
            line_intersection(s, e),
            Some(LineIntersection::SinglePoint {
                is_proper: true,
                ..
            })
        )
    })
}

fn strictly_outside(t: &[P2; 3], p: P2) -> bool {
    (0..3).any(|j| {
        let (a, b) = (t[j], t[(j + 1) % 3]);
        robust::orient2d(
            robust::Coord { x: a[0], y: a[1] },
            robust::Coord { x: b[0], y: b[1] },
            robust::Coord { x: p[0], y: p[1] },
        ) < 0.0
    })
}

fn bbox(pts: &[P2]) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in pts {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    b
}

fn overlaps(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3]
}

/// The oracle's answer for every triangle of a level: (relation, coverage).
fn oracle(tin: &Tin, l: usize, polys: &Polys) -> BTreeMap<u32, (Relation, f64)> {
    let rings: Vec<(&Vec<P2>, [f64; 4])> = polys.iter().flatten().map(|r| (r, bbox(r))).collect();
    let mut out = BTreeMap::new();
    // the void triangles (outside the domain) are the last of the level
    let lv = &tin.levels[l];
    for t in 0..lv.tris.len() as u32 - lv.num_void {
        let tc = tri2(tin, l, t);
        let tb = bbox(&tc);
        let area_t = signed_area(&tc);
        let mut covered = 0.0;
        let mut crossed = false;
        for (r, rb) in &rings {
            covered += signed_area_or_zero(&clip_ring(r, &tc));
            if !crossed && overlaps(rb, &tb) {
                crossed = r.windows(2).any(|w| crosses_inside(&tc, w[0], w[1]));
            }
        }
        let cov = covered / area_t;
        if crossed {
            out.insert(t, (Relation::Boundary, cov));
        } else if cov > 0.5 {
            out.insert(t, (Relation::Inside, cov));
        }
    }
    out
}

fn signed_area_or_zero(p: &[P2]) -> f64 {
    if p.len() < 3 { 0.0 } else { signed_area(p) }
}

fn rows_of(tin: &Tin, l: usize, polys: &Polys, method: Method) -> Vec<AreaRow> {
    let area = Area::new(polys.clone());
    let s = sweep(tin, l, &area, method, &mut no_interrupt).unwrap();
    area_rows(tin, &area, &s, false, &mut no_interrupt).unwrap()
}

fn check_against_oracle(tin: &Tin, l: usize, polys: &Polys, what: &str) {
    let want = oracle(tin, l, polys);
    let got = rows_of(tin, l, polys, Method::Hierarchy);
    let got_map: BTreeMap<u32, (Relation, f64)> = got
        .iter()
        .map(|r| (r.triangle, (r.relation, r.coverage)))
        .collect();
    assert_eq!(
        got.len(),
        got_map.len(),
        "{what} level {l}: a triangle twice"
    );
    let mut worst: f64 = 0.0;
    for (t, (rel, cov)) in &want {
        let Some((grel, gcov)) = got_map.get(t) else {
            panic!("{what} level {l}: triangle {t} ({rel:?}, {cov}) missing");
        };
        assert_eq!(grel, rel, "{what} level {l}: triangle {t} relation");
        worst = worst.max((gcov - cov).abs());
        assert!(
            (gcov - cov).abs() < 1e-9,
            "{what} level {l}: triangle {t} coverage {gcov} vs {cov}"
        );
    }
    for t in got_map.keys() {
        assert!(
            want.contains_key(t),
            "{what} level {l}: triangle {t} reported but outside"
        );
    }
    println!(
        "{what} level {l}: {} inside, {} boundary, worst coverage difference {worst:.1e}",
        want.values().filter(|v| v.0 == Relation::Inside).count(),
        want.values().filter(|v| v.0 == Relation::Boundary).count()
    );
}

#[test]
fn contour_bands_match_the_oracle_at_every_level() {
    let tin = dem_tin();
    for (name, polys) in bands() {
        let size: usize = polys.iter().flatten().map(|r| r.len()).sum();
        // keep the brute-force oracle affordable on the large bands
        let top = match size {
            0..=1000 => tin.num_levels() - 1,
            1001..=3000 => 2,
            _ => 1,
        };
        for l in 0..=top {
            check_against_oracle(&tin, l, &polys, &name);
        }
    }
}

/// Seeded random star-shaped polygons (valid by construction) with a hole,
/// some reaching outside the domain, and two-part multipolygons.
fn random_polys(rng: &mut StdRng, tin: &Tin) -> Polys {
    let b = tin.bbox;
    let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let mut out = Vec::new();
    let parts = rng.random_range(1..=2);
    for k in 0..parts {
        let cx = b.min_x + w * (0.25 + 0.5 * k as f64) + rng.random_range(-0.1..0.1) * w;
        let cy = b.min_y + h * rng.random_range(0.2..0.8);
        let r0 = w.min(h) * rng.random_range(0.05..0.3);
        let n = rng.random_range(5..60);
        let star = |rmin: f64, rmax: f64, rng: &mut StdRng, ccw: bool| -> Vec<P2> {
            let mut ring: Vec<P2> = (0..n)
                .map(|i| {
                    let a =
                        std::f64::consts::TAU * (i as f64 + rng.random_range(0.0..0.9)) / n as f64;
                    let r = rng.random_range(rmin..rmax);
                    [cx + r * a.cos(), cy + r * a.sin()]
                })
                .collect();
            if !ccw {
                ring.reverse();
            }
            let f = ring[0];
            ring.push(f);
            ring
        };
        let mut poly = vec![star(r0 * 0.5, r0, rng, true)];
        if rng.random_bool(0.6) {
            poly.push(star(r0 * 0.1, r0 * 0.45, rng, false));
        }
        out.push(poly);
    }
    out
}

#[test]
fn random_polygons_match_the_oracle() {
    for common::Terrain { name, tin, .. } in common::terrains() {
        let mut rng = StdRng::seed_from_u64(20261122);
        for i in 0..6 {
            let polys = random_polys(&mut rng, &tin);
            for l in [0, 2, tin.num_levels() - 1] {
                check_against_oracle(&tin, l, &polys, &format!("{name}: random {i}"));
            }
        }
        // polygons over the domain's holes: a square around the void
        // triangles' middle one, twice their extent, with a smaller square
        // hole in it
        for l in [0, 2, tin.num_levels() - 1] {
            let lv = &tin.levels[l];
            if lv.num_void == 0 {
                continue;
            }
            let voids = lv.tris.len() as u32 - lv.num_void..lv.tris.len() as u32;
            let c = tin.corners(l, voids.start + lv.num_void / 2);
            let m = [
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            ];
            let r = c
                .iter()
                .map(|p| (p[0] - m[0]).hypot(p[1] - m[1]))
                .fold(0.0, f64::max)
                * 2.0;
            let sq = |r: f64, ccw: bool| {
                let mut q = vec![
                    [m[0] - r, m[1] - r],
                    [m[0] + r, m[1] - r],
                    [m[0] + r, m[1] + r],
                    [m[0] - r, m[1] + r],
                ];
                if !ccw {
                    q.reverse();
                }
                ring(&q)
            };
            let polys = vec![vec![sq(r, true), sq(r / 5.0, false)]];
            check_against_oracle(&tin, l, &polys, &format!("{name}: over a hole"));
        }
    }
}

/// A paraboloid on an n x n integer grid: every vertex kept, so polygons
/// along grid lines run along triangle edges and through vertices.
fn grid_tin(n: usize) -> Tin {
    let mut pts = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64, j as f64);
            pts.push([x, y, (x - 3.3) * (x - 3.3) + 0.5 * (y - 2.1) * (y - 2.1)]);
        }
    }
    build(pts, &[8.0, 2.0, 0.0], 0, &mut || Ok(())).unwrap()
}

fn ring(pts: &[P2]) -> Vec<P2> {
    let mut r = pts.to_vec();
    r.push(pts[0]);
    r
}

#[test]
fn degenerate_positions_on_a_grid() {
    let tin = grid_tin(9);
    let cases: Vec<(&str, Polys)> = vec![
        (
            "box along grid lines",
            vec![vec![ring(&[
                [1.0, 1.0],
                [6.0, 1.0],
                [6.0, 5.0],
                [1.0, 5.0],
            ])]],
        ),
        (
            "diamond through vertices",
            vec![vec![ring(&[
                [4.0, 0.0],
                [8.0, 4.0],
                [4.0, 8.0],
                [0.0, 4.0],
            ])]],
        ),
        (
            "box with a hole along grid lines",
            vec![vec![
                ring(&[[0.0, 0.0], [8.0, 0.0], [8.0, 8.0], [0.0, 8.0]]),
                ring(&[[2.0, 2.0], [2.0, 5.0], [5.0, 5.0], [5.0, 2.0]]),
            ]],
        ),
        (
            "whole domain and beyond",
            vec![vec![ring(&[
                [-5.0, -5.0],
                [20.0, -5.0],
                [20.0, 20.0],
                [-5.0, 20.0],
            ])]],
        ),
        (
            "partly outside",
            vec![vec![ring(&[
                [-3.0, 2.5],
                [5.5, 2.5],
                [5.5, 11.0],
                [-3.0, 11.0],
            ])]],
        ),
        (
            "inside one triangle",
            vec![vec![ring(&[[3.1, 3.05], [3.3, 3.05], [3.1, 3.25]])]],
        ),
        (
            "two squares touching at a vertex",
            vec![
                vec![ring(&[[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]])],
                vec![ring(&[[3.0, 3.0], [5.5, 3.0], [5.5, 5.5], [3.0, 5.5]])],
            ],
        ),
        (
            "hole touching its shell at a point",
            vec![vec![
                ring(&[[0.5, 0.5], [7.5, 0.5], [7.5, 7.5], [0.5, 7.5]]),
                ring(&[[0.5, 0.5], [3.0, 4.0], [4.0, 3.0]]),
            ]],
        ),
        (
            "starting on an edge",
            vec![vec![ring(&[
                [2.5, 2.0],
                [6.0, 2.0],
                [6.0, 6.3],
                [2.5, 6.3],
            ])]],
        ),
    ];
    for (name, polys) in cases {
        let polys: Polys = polys
            .into_iter()
            .map(|p| {
                p.into_iter()
                    .enumerate()
                    .map(|(i, mut r)| {
                        // shells counter-clockwise, holes clockwise
                        if (i == 0) != (signed_area(&r[..r.len() - 1]) > 0.0) {
                            r.reverse();
                        }
                        r
                    })
                    .collect()
            })
            .collect();
        for l in 0..tin.num_levels() {
            check_against_oracle(&tin, l, &polys, name);
        }
    }
}

#[test]
fn the_three_methods_agree_and_the_hierarchy_examines_fewer() {
    let tin = dem_tin();
    let fin = tin.num_levels() - 1;
    for (name, polys) in bands() {
        let area = Area::new(polys.clone());
        let mut got = Vec::new();
        for m in [Method::Hierarchy, Method::Flat, Method::Scan] {
            let s = sweep(&tin, fin, &area, m, &mut no_interrupt).unwrap();
            let rows = area_rows(&tin, &area, &s, false, &mut no_interrupt).unwrap();
            println!("{name}: {m:?} examined {}", s.examined);
            got.push((rows, s.examined));
        }
        assert_eq!(got[0].0, got[1].0, "{name}: hierarchy vs flat");
        assert_eq!(got[0].0, got[2].0, "{name}: hierarchy vs scan");
        assert!(got[2].1 == tin.levels[fin].tris.len() || got[2].1 > got[0].1);
    }
}

#[test]
fn compact_output_expands_to_the_full_list() {
    let tin = dem_tin();
    let mut polys_all: Vec<(String, Polys)> = bands();
    let mut rng = StdRng::seed_from_u64(7);
    polys_all.push(("random".into(), random_polys(&mut rng, &tin)));
    for (name, polys) in polys_all {
        let area = Area::new(polys.clone());
        for l in 0..tin.num_levels() {
            let s = sweep(&tin, l, &area, Method::Hierarchy, &mut no_interrupt).unwrap();
            let full = area_rows(&tin, &area, &s, false, &mut no_interrupt).unwrap();
            let compact = area_rows(&tin, &area, &s, true, &mut no_interrupt).unwrap();
            // expand with the parent links (not the child ranges the code uses)
            let coarse: HashSet<(usize, u32)> = compact
                .iter()
                .filter(|r| r.relation == Relation::Inside)
                .map(|r| (r.level, r.triangle))
                .collect();
            let mut expanded: Vec<u32> = Vec::new();
            for t in 0..tin.levels[l].tris.len() as u32 {
                let (mut lv, mut a) = (l, t);
                loop {
                    if coarse.contains(&(lv, a)) {
                        expanded.push(t);
                        break;
                    }
                    if lv == 0 {
                        break;
                    }
                    a = tin.levels[lv].parent[a as usize];
                    lv -= 1;
                }
            }
            let inside_full: Vec<u32> = full
                .iter()
                .filter(|r| r.relation == Relation::Inside)
                .map(|r| r.triangle)
                .collect();
            assert_eq!(expanded, inside_full, "{name} level {l}");
            let bf: Vec<&AreaRow> = full
                .iter()
                .filter(|r| r.relation == Relation::Boundary)
                .collect();
            let bc: Vec<&AreaRow> = compact
                .iter()
                .filter(|r| r.relation == Relation::Boundary)
                .collect();
            assert_eq!(bf, bc, "{name} level {l}: boundary rows");
            // coarse inside triangles have no inside parent
            for &(lv, a) in &coarse {
                if lv > 0 {
                    let p = tin.levels[lv].parent[a as usize];
                    assert!(!coarse.contains(&(lv - 1, p)));
                }
            }
            if l == tin.num_levels() - 1 {
                println!(
                    "{name}: full {} rows, compact {} rows",
                    full.len(),
                    compact.len()
                );
            }
        }
    }
}

/// Integrals over the clipped polygons (oracle): area, surface area, the
/// integral of z, of the slope, min/max z, cut and fill at `base`.
#[derive(Debug, Default)]
struct Integrals {
    a: f64,
    a3: f64,
    z: f64,
    slope: f64,
    min_z: f64,
    max_z: f64,
    max_slope: f64,
    cut: f64,
    fill: f64,
}

fn plane_z(c: &[[f64; 3]; 3], p: P2) -> f64 {
    let d = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
    let wb = ((p[0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (p[1] - c[0][1])) / d;
    let wc = ((c[1][0] - c[0][0]) * (p[1] - c[0][1]) - (p[0] - c[0][0]) * (c[1][1] - c[0][1])) / d;
    c[0][2] + wb * (c[1][2] - c[0][2]) + wc * (c[2][2] - c[0][2])
}

/// Integral of a function linear on the polygon, by fan triangulation.
fn fan_integral(poly: &[P2], f: &dyn Fn(P2) -> f64) -> f64 {
    let mut s = 0.0;
    for i in 1..poly.len().saturating_sub(1) {
        let (a, b, c) = (poly[0], poly[i], poly[i + 1]);
        let ar = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2.0;
        s += ar * (f(a) + f(b) + f(c)) / 3.0;
    }
    s
}

fn half_plane(poly: &[P2], h: &dyn Fn(P2) -> f64) -> Vec<P2> {
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (hp, hq) = (h(p), h(q));
        if hp >= 0.0 {
            out.push(p);
        }
        if (hp >= 0.0) != (hq >= 0.0) {
            let s = hp / (hp - hq);
            out.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
        }
    }
    out
}

fn oracle_integrals(tin: &Tin, l: usize, polys: &Polys, base: f64) -> Integrals {
    let rings: Vec<&Vec<P2>> = polys.iter().flatten().collect();
    let to_ring = |r: &Vec<P2>| {
        geo::LineString::from(
            r.iter()
                .map(|c| Coord { x: c[0], y: c[1] })
                .collect::<Vec<_>>(),
        )
    };
    let mp = geo::MultiPolygon::new(
        polys
            .iter()
            .map(|p| geo::Polygon::new(to_ring(&p[0]), p[1..].iter().map(to_ring).collect()))
            .collect(),
    );
    let mut o = Integrals {
        min_z: f64::INFINITY,
        max_z: f64::NEG_INFINITY,
        max_slope: f64::NEG_INFINITY,
        ..Integrals::default()
    };
    for t in 0..tin.levels[l].tris.len() as u32 {
        let c = tin.corners(l, t);
        let tc = tri2(tin, l, t);
        let z = |p: P2| plane_z(&c, p);
        let n = {
            let (u, v) = (
                [c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]],
                [c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]],
            );
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        let sec = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / n[2].abs();
        let slope = (sec * sec - 1.0).max(0.0).sqrt().atan().to_degrees();
        let mut a_t = 0.0;
        for r in &rings {
            let p = clip_ring(r, &tc);
            if p.len() < 3 {
                continue;
            }
            let a = signed_area(&p);
            if a == 0.0 {
                continue;
            }
            a_t += a;
            o.z += fan_integral(&p, &z);
            o.cut += fan_integral(&half_plane(&p, &|q| z(q) - base), &|q| z(q) - base);
            o.fill += fan_integral(&half_plane(&p, &|q| base - z(q)), &|q| base - z(q));
        }
        if a_t > 0.0 {
            // the region's vertices: corners of the triangle in the polygon,
            // ring vertices in the triangle, crossings of rings and edges
            let mut vs: Vec<P2> = tc
                .iter()
                .filter(|c| geo::Intersects::intersects(&mp, &geo::Point::new(c[0], c[1])))
                .copied()
                .collect();
            let tb = bbox(&tc);
            for r in &rings {
                for w in r.windows(2) {
                    if !overlaps(&bbox(w), &tb) {
                        continue;
                    }
                    if !strictly_outside(&tc, w[0]) {
                        vs.push(w[0]);
                    }
                    let sg = Line::new(
                        Coord {
                            x: w[0][0],
                            y: w[0][1],
                        },
                        Coord {
                            x: w[1][0],
                            y: w[1][1],
                        },
                    );
                    for j in 0..3 {
                        let e = Line::new(
                            Coord {
                                x: tc[j][0],
                                y: tc[j][1],
                            },
                            Coord {
                                x: tc[(j + 1) % 3][0],
                                y: tc[(j + 1) % 3][1],
                            },
                        );
                        match line_intersection(sg, e) {
                            Some(LineIntersection::SinglePoint { intersection, .. }) => {
                                vs.push([intersection.x, intersection.y])
                            }
                            Some(LineIntersection::Collinear { intersection }) => {
                                vs.push([intersection.start.x, intersection.start.y]);
                                vs.push([intersection.end.x, intersection.end.y]);
                            }
                            None => {}
                        }
                    }
                }
            }
            for q in vs {
                o.min_z = o.min_z.min(z(q));
                o.max_z = o.max_z.max(z(q));
            }
        }
        if a_t > 1e-9 * signed_area(&tc) {
            o.a += a_t;
            o.a3 += a_t * sec;
            o.slope += a_t * slope;
            o.max_slope = o.max_slope.max(slope);
        }
    }
    o
}

fn close(a: f64, b: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-9 * scale.abs().max(1.0),
        "{what}: {a} vs {b} (scale {scale})"
    );
}

/// Statistics and (cut, fill) against the clipped triangles' integrals.
fn check_against(what: &str, st: &SurfaceStats, (cut, fill): (f64, f64), o: &Integrals) {
    close(st.area2d, o.a, o.a, &format!("{what} area2d"));
    close(st.area3d, o.a3, o.a3, &format!("{what} area3d"));
    close(st.z_integral, o.z, o.z, &format!("{what} integral of z"));
    close(
        st.slope_integral,
        o.slope,
        o.slope,
        &format!("{what} integral of slope"),
    );
    close(
        st.max_slope,
        o.max_slope,
        90.0,
        &format!("{what} max slope"),
    );
    close(st.min_z, o.min_z, 1000.0, &format!("{what} min z"));
    close(st.max_z, o.max_z, 1000.0, &format!("{what} max z"));
    close(cut, o.cut, o.z.abs(), &format!("{what} cut"));
    close(fill, o.fill, o.z.abs(), &format!("{what} fill"));
}

#[test]
fn stats_and_volumes_match_the_clipped_triangles() {
    let tin = dem_tin();
    let mut cases: Vec<(String, Polys)> = bands().into_iter().take(1).collect();
    let mut rng = StdRng::seed_from_u64(99);
    for i in 0..3 {
        cases.push((format!("random {i}"), random_polys(&mut rng, &tin)));
    }
    // bands(): the first line of the file is the 250-300 band; use the
    // smallest one as well
    cases.push(bands().into_iter().last().unwrap());
    // most of the terrain, a hole in it, and a polygon reaching past the
    // terrain: coarse triangles wholly inside at every level
    let b = &tin.bbox;
    let (cx, cy, w, h) = (
        (b.min_x + b.max_x) / 2.0,
        (b.min_y + b.max_y) / 2.0,
        b.max_x - b.min_x,
        b.max_y - b.min_y,
    );
    let circle = |r: f64, n: usize, cw: bool| -> Vec<P2> {
        let mut v: Vec<P2> = (0..n)
            .map(|k| {
                let a =
                    2.0 * std::f64::consts::PI * k as f64 / n as f64 * if cw { -1.0 } else { 1.0 };
                [cx + r * a.cos() * w / h.max(w), cy + r * a.sin()]
            })
            .collect();
        v.push(v[0]);
        v
    };
    cases.push((
        "most of the terrain, with a hole".to_string(),
        vec![vec![
            circle(0.45 * h, 200, false),
            circle(0.1 * h, 50, true),
        ]],
    ));
    cases.push((
        "past the terrain".to_string(),
        vec![vec![vec![
            [b.min_x - w, b.min_y - h],
            [b.max_x + w, b.min_y - h],
            [b.max_x + w, b.max_y + h],
            [b.min_x - w, b.max_y + h],
            [b.min_x - w, b.min_y - h],
        ]]],
    ));
    for (name, polys) in cases {
        let area = Area::new(polys.clone());
        let size: usize = polys.iter().flatten().map(|r| r.len()).sum();
        let levels = if size > 1000 {
            vec![0]
        } else {
            vec![0, tin.num_levels() - 1]
        };
        // the extension sums over the flat sweep (it reads only the target
        // level); the hierarchical one finds the same triangles
        for (l, method) in levels
            .into_iter()
            .flat_map(|l| [(l, Method::Flat), (l, Method::Hierarchy)])
        {
            let s = sweep(&tin, l, &area, method, &mut no_interrupt).unwrap();
            let st = stats(&tin, &area, &s, &mut no_interrupt).unwrap();
            let base = (tin.bbox.min_z + tin.bbox.max_z) / 2.0;
            let (cut, fill) = volume(&tin, &area, &s, base, &mut no_interrupt).unwrap();
            let o = oracle_integrals(&tin, l, &polys, base);
            let what = format!("{name} level {l} {method:?}");
            check_against(&what, &st, (cut, fill), &o);
            // coarse triangles wholly inside taken whole from their
            // subtree sums: the same against the same oracle
            let sums = SubtreeSums::build(&tin, l, Units::Planar, &mut no_interrupt).unwrap();
            let coarse: usize = s.inside.iter().take(l).map(|v| v.len()).sum();
            if name.starts_with("most") && method == Method::Hierarchy && l > 0 {
                assert!(coarse > 0, "{what}: no coarse triangle inside");
            }
            let f = stats_with(
                &tin,
                &area,
                &s,
                Some(&sums),
                Units::Planar,
                &mut no_interrupt,
            );
            let f = f.unwrap();
            let w = format!("{what} with subtree sums");
            let fast = |b: f64| {
                volume_parts_with(
                    &tin,
                    &area,
                    &s,
                    b,
                    Some(&sums),
                    Units::Planar,
                    &mut no_interrupt,
                )
                .unwrap()
            };
            let v = fast(base);
            check_against(&w, &f, (v.cut, v.fill), &o);
            // the same bits with or without the sums, and at bases below,
            // inside and above the terrain
            assert_eq!(
                f,
                stats_with(&tin, &area, &s, None, Units::Planar, &mut no_interrupt).unwrap(),
                "{w}"
            );
            for b in [
                base,
                tin.bbox.min_z - 1.0,
                tin.bbox.min_z + 0.25 * (tin.bbox.max_z - tin.bbox.min_z),
                tin.bbox.max_z + 1.0,
            ] {
                let flat = volume_parts(&tin, &area, &s, b, &mut no_interrupt).unwrap();
                assert_eq!(fast(b), flat, "{w} at base {b}");
            }
            println!(
                "{what}: area {:.1} m2, mean z {:.3} m, cut {:.1} m3, fill {:.1} m3",
                st.area2d,
                st.mean_z(),
                cut,
                fill
            );
        }
    }
}

#[test]
fn full_domain_box_volume_is_the_prism_sum() {
    let tin = dem_tin();
    let b = tin.bbox;
    let m = 1000.0;
    let polys = vec![vec![vec![
        [b.min_x - m, b.min_y - m],
        [b.max_x + m, b.min_y - m],
        [b.max_x + m, b.max_y + m],
        [b.min_x - m, b.max_y + m],
        [b.min_x - m, b.min_y - m],
    ]]];
    let area = Area::new(polys);
    for l in 0..tin.num_levels() {
        for (base, method) in [
            (b.min_z - 10.0, Method::Flat),
            ((b.min_z + b.max_z) / 2.0, Method::Flat),
            (b.min_z - 10.0, Method::Hierarchy),
        ] {
            let s = sweep(&tin, l, &area, method, &mut no_interrupt).unwrap();
            assert!(s.boundary.is_empty());
            let (cut, fill) = volume(&tin, &area, &s, base, &mut no_interrupt).unwrap();
            // analytic: each triangle is a prism of its area times its mean
            // height above base (signed), summed
            let mut net = 0.0;
            let mut domain = 0.0;
            for t in 0..tin.levels[l].tris.len() as u32 {
                let c = tin.corners(l, t);
                let a = signed_area(&tri2(&tin, l, t));
                domain += a;
                net += a * ((c[0][2] + c[1][2] + c[2][2]) / 3.0 - base);
            }
            close(
                cut - fill,
                net,
                net,
                &format!("level {l} base {base}: cut - fill"),
            );
            if base < b.min_z {
                assert_eq!(fill, 0.0);
                close(cut, net, net, &format!("level {l}: prism sum"));
            }
            let st = stats(&tin, &area, &s, &mut no_interrupt).unwrap();
            close(st.area2d, domain, domain, "domain area");
        }
    }
}

/// `geom::is_strictly_convex_ring` (which lets the area functions skip
/// PostGIS's validity check) against `geo`'s own convexity and validity
/// predicates, on seeded random rings: hulls of random points (convex),
/// the same points in random order (mostly not), stars going round twice,
/// rings with a repeated or a collinear corner, reversed rings, unclosed
/// rings, and hulls at the DEM's coordinates and at 1e-9 scale.
#[test]
fn strictly_convex_rings_agree_with_geo_and_are_valid() {
    use geo::{
        ConvexHull, IsConvex, LineString, MultiPoint, Point, Polygon, RemoveRepeatedPoints,
        Validation,
    };
    use tinmerge_core::geom::is_strictly_convex_ring;
    let mut rng = StdRng::seed_from_u64(27);
    // as the readers give a 2D ring: z is NaN (with z = 0 here, a check
    // comparing whole points passed this test while every 2D polygon
    // users send went to GEOS)
    let ring3 = |ls: &LineString<f64>| -> Vec<[f64; 3]> {
        ls.0.iter().map(|c| [c.x, c.y, f64::NAN]).collect()
    };
    let (mut yes, mut no) = (0, 0);
    for case in 0..6000 {
        let (ox, oy, s) = match case % 3 {
            0 => (0.0, 0.0, 1.0),
            1 => (758000.3, 4052000.7, 500.0),
            _ => (-84.4, 36.46, 1e-9),
        };
        let n = rng.random_range(3..12);
        let pts: Vec<Point<f64>> = (0..n)
            .map(|_| Point::new(ox + s * rng.random::<f64>(), oy + s * rng.random::<f64>()))
            .collect();
        let mut ls = match case % 7 {
            // a hull (strictly convex unless degenerate)
            0 | 1 => MultiPoint(pts.clone()).convex_hull().exterior().clone(),
            // a hull, reversed (clockwise)
            2 => {
                let mut h = MultiPoint(pts.clone()).convex_hull().exterior().clone();
                h.0.reverse();
                h
            }
            // a hull with a corner repeated, or the middle of a side added, either way round
            3 => {
                let mut h = MultiPoint(pts.clone()).convex_hull().exterior().clone();
                if h.0.len() >= 4 {
                    let (a, b) = (h.0[0], h.0[1]);
                    if rng.random::<bool>() {
                        h.0.insert(1, a);
                    } else {
                        h.0.insert(
                            1,
                            geo::coord! { x: (a.x + b.x) / 2.0, y: (a.y + b.y) / 2.0 },
                        );
                    }
                }
                if rng.random::<bool>() {
                    h.0.reverse();
                }
                h
            }
            // a regular star that goes round twice
            4 => {
                let k = 5 + 2 * rng.random_range(0..3);
                let mut c: Vec<geo::Coord<f64>> = (0..k)
                    .map(|i| {
                        let a = std::f64::consts::TAU * (2 * i) as f64 / k as f64;
                        geo::coord! { x: ox + s * a.cos(), y: oy + s * a.sin() }
                    })
                    .collect();
                c.push(c[0]);
                LineString(c)
            }
            // the points in the order drawn, closed
            5 => {
                let mut c: Vec<geo::Coord<f64>> = pts.iter().map(|p| p.0).collect();
                c.push(c[0]);
                LineString(c)
            }
            // a hull left open
            _ => {
                let mut h = MultiPoint(pts.clone()).convex_hull().exterior().clone();
                h.0.pop();
                h
            }
        };
        if ls.0.is_empty() {
            ls.0.push(geo::coord! { x: ox, y: oy });
        }
        let ours = is_strictly_convex_ring(&ring3(&ls));
        let closed = ls.0.len() >= 4 && ls.0.first() == ls.0.last();
        // geo's predicate on the ring without repeated points (a repeated
        // point is valid in PostGIS; geo's convexity counts some of them as
        // corners)
        let theirs = closed && ls.remove_repeated_points().is_strictly_convex();
        assert_eq!(ours, theirs, "case {case}: {ls:?}");
        if ours {
            assert!(
                Polygon::new(ls.clone(), vec![]).is_valid(),
                "case {case}: {ls:?}"
            );
            yes += 1;
        } else {
            no += 1;
        }
    }
    assert!(yes > 2000 && no > 2000, "{yes} convex, {no} not");
    assert!(!is_strictly_convex_ring(&[
        [0.0, 0.0, 0.0],
        [f64::NAN, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0]
    ]));
}

/// Each coarse triangle's subtree sums (made in one walk over the target
/// level's triangles, parent links only) are, bit for bit, its children's
/// sums added in order to an empty one, down to the target level's
/// triangles: the definition, folded here recursively through `children`.
#[test]
fn subtree_sums_are_the_recursive_fold_bit_for_bit() {
    fn fold(tin: &Tin, level: usize, l: usize, t: u32) -> SurfaceStats {
        if l == level {
            return SurfaceStats::of_triangle(&tin.corners(level, t), Units::Planar);
        }
        let mut a = SurfaceStats::empty();
        for c in tinmerge_core::tin::mesh::Mesh::children(tin, l, t).unwrap() {
            a.add(&fold(tin, level, l + 1, c));
        }
        a
    }
    let tin = dem_tin();
    for level in [1, 3, tin.num_levels() - 1] {
        let sums = SubtreeSums::build(&tin, level, Units::Planar, &mut no_interrupt).unwrap();
        for l in 0..level {
            for t in 0..tin.levels[l].tris.len() as u32 {
                assert_eq!(
                    sums.of(l, t),
                    Some(&fold(&tin, level, l, t)),
                    "level {level}: triangle {t} of level {l}"
                );
            }
        }
        assert_eq!(sums.of(level, 0), None);
    }
}

/// A point of the WGS84 spheroid (longitude, latitude in degrees) in
/// earth-centred coordinates, metres: the oracle's own geometry.
fn ecef(lon: f64, lat: f64) -> [f64; 3] {
    let (a, f) = (6_378_137.0, 1.0 / 298.257_223_563);
    let e2 = f * (2.0 - f);
    let (l, p) = (lon.to_radians(), lat.to_radians());
    let n = a / (1.0 - e2 * p.sin() * p.sin()).sqrt();
    [
        n * p.cos() * l.cos(),
        n * p.cos() * l.sin(),
        n * (1.0 - e2) * p.sin(),
    ]
}

/// Metres per degree east and north at (lon, lat), and the area of a
/// square degree there, from the spheroid's surface by central
/// differences of [`ecef`].
fn jacobian(lon: f64, lat: f64) -> (f64, f64, f64) {
    let h = 1e-5;
    let d = |p: [f64; 3], q: [f64; 3]| {
        [
            (q[0] - p[0]) / (2.0 * h),
            (q[1] - p[1]) / (2.0 * h),
            (q[2] - p[2]) / (2.0 * h),
        ]
    };
    let u = d(ecef(lon - h, lat), ecef(lon + h, lat));
    let v = d(ecef(lon, lat - h), ecef(lon, lat + h));
    let n = |w: [f64; 3]| (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    (n(u), n(v), n(cross))
}

/// The integral over polygon `poly` (degrees, signed by orientation) of
/// `g(point, metres-per-degree east, north)` against the spheroid's area
/// element: each fan triangle by Dunavant's 7-point rule (degree 5).
fn spheroid_integral(poly: &[P2], g: &dyn Fn(P2, f64, f64) -> f64) -> f64 {
    const R: [(f64, f64, f64, f64); 7] = [
        (1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.225),
        (
            0.059_715_871_789_770,
            0.470_142_064_105_115,
            0.470_142_064_105_115,
            0.132_394_152_788_506,
        ),
        (
            0.470_142_064_105_115,
            0.059_715_871_789_770,
            0.470_142_064_105_115,
            0.132_394_152_788_506,
        ),
        (
            0.470_142_064_105_115,
            0.470_142_064_105_115,
            0.059_715_871_789_770,
            0.132_394_152_788_506,
        ),
        (
            0.797_426_985_353_087,
            0.101_286_507_323_456,
            0.101_286_507_323_456,
            0.125_939_180_544_827,
        ),
        (
            0.101_286_507_323_456,
            0.797_426_985_353_087,
            0.101_286_507_323_456,
            0.125_939_180_544_827,
        ),
        (
            0.101_286_507_323_456,
            0.101_286_507_323_456,
            0.797_426_985_353_087,
            0.125_939_180_544_827,
        ),
    ];
    let mut s = 0.0;
    for i in 1..poly.len().saturating_sub(1) {
        let (a, b, c) = (poly[0], poly[i], poly[i + 1]);
        let ar = ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2.0;
        for (wa, wb, wc, w) in R {
            let p = [
                wa * a[0] + wb * b[0] + wc * c[0],
                wa * a[1] + wb * b[1] + wc * c[1],
            ];
            let (kx, ky, da) = jacobian(p[0], p[1]);
            s += ar * w * da * g(p, kx, ky);
        }
    }
    s
}

/// Issue 76: a tin in degrees (the geographic DEM, EPSG:4326) answers in
/// metres on the WGS84 spheroid, within 1e-6 of the oracle: the clipped
/// triangles integrated against the spheroid's own area element and
/// metres per degree (earth-centred coordinates differenced), point by
/// point, not at each part's centroid as the code does.
#[test]
fn geographic_stats_are_metres_on_the_spheroid() {
    use tinmerge_core::geom::Spheroid;
    let tin = crate::common::geo_tin(2.0);
    let units = Units::Degrees(Spheroid::WGS84);
    let mut rng = StdRng::seed_from_u64(7601);
    let mut worst: f64 = 0.0;
    for case in 0..4 {
        let polys = random_polys(&mut rng, &tin);
        let area = Area::new(polys.clone());
        for l in [1usize, 3] {
            let s = sweep(&tin, l, &area, Method::Hierarchy, &mut no_interrupt).unwrap();
            let st = stats_with(&tin, &area, &s, None, units, &mut no_interrupt).unwrap();
            let base = st.min_z + 0.4 * (st.max_z - st.min_z);
            let v =
                volume_parts_with(&tin, &area, &s, base, None, units, &mut no_interrupt).unwrap();
            let sums = SubtreeSums::build(&tin, l, units, &mut no_interrupt).unwrap();
            assert_eq!(
                st,
                stats_with(&tin, &area, &s, Some(&sums), units, &mut no_interrupt).unwrap(),
                "case {case} level {l}: the same bits with the sums"
            );
            let rings: Vec<&Vec<P2>> = polys.iter().flatten().collect();
            let (mut a, mut a3, mut zi, mut si, mut cut, mut fill) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
            for t in 0..tin.levels[l].tris.len() as u32 {
                let c = tin.corners(l, t);
                let tc = tri2(&tin, l, t);
                let z = |p: P2| plane_z(&c, p);
                let (gx, gy) = {
                    let d = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                        - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
                    (
                        ((c[1][2] - c[0][2]) * (c[2][1] - c[0][1])
                            - (c[2][2] - c[0][2]) * (c[1][1] - c[0][1]))
                            / d,
                        ((c[1][0] - c[0][0]) * (c[2][2] - c[0][2])
                            - (c[2][0] - c[0][0]) * (c[1][2] - c[0][2]))
                            / d,
                    )
                };
                let grad = |kx: f64, ky: f64| (gx / kx).hypot(gy / ky);
                for r in &rings {
                    let p = clip_ring(r, &tc);
                    if p.len() < 3 || signed_area(&p) == 0.0 {
                        continue;
                    }
                    a += spheroid_integral(&p, &|_, _, _| 1.0);
                    a3 += spheroid_integral(&p, &|_, kx, ky| (1.0 + grad(kx, ky).powi(2)).sqrt());
                    zi += spheroid_integral(&p, &|q, _, _| z(q));
                    si += spheroid_integral(&p, &|_, kx, ky| grad(kx, ky).atan().to_degrees());
                    let up = half_plane(&p, &|q| z(q) - base);
                    if up.len() >= 3 {
                        cut += spheroid_integral(&up, &|q, _, _| z(q) - base);
                    }
                    let down = half_plane(&p, &|q| base - z(q));
                    if down.len() >= 3 {
                        fill += spheroid_integral(&down, &|q, _, _| base - z(q));
                    }
                }
            }
            let mut rel = |x: f64, o: f64, scale: f64, what: &str| {
                let e = (x - o).abs() / scale.abs();
                worst = worst.max(e);
                assert!(
                    e <= 1e-6,
                    "case {case} level {l}: {what} {x} against {o} ({e:.2e} relative)"
                );
            };
            assert!(
                a > 1e6,
                "case {case}: the polygon should cover square kilometres, not {a} m²"
            );
            rel(st.area2d, a, a, "area");
            rel(st.area3d, a3, a3, "surface area");
            rel(st.z_integral, zi, zi, "integral of z");
            rel(st.slope_integral, si, si, "integral of slope");
            rel(v.cut, cut, zi, "cut");
            rel(v.fill, fill, zi, "fill");
        }
    }
    eprintln!(
        "geographic statistics: worst relative difference from the spheroid oracle {worst:.2e}"
    );
}

/// The spheroid of a geographic SRID from its PROJ.4 text as PostGIS's
/// spatial_ref_sys holds it (EPSG's constants for the expected values).
#[test]
fn spheroids_from_spatial_ref_sys() {
    use tinmerge_core::geom::Spheroid;
    let of = |s: &str| Spheroid::from_proj4(s).map(|e| (e.a, 1.0 / e.f));
    let close = |got: Option<(f64, f64)>, a: f64, rf: f64| {
        let (ga, grf) = got.expect("a spheroid");
        assert!(
            (ga - a).abs() < 1e-6 && (grf - rf).abs() < 1e-6,
            "{ga} {grf} against {a} {rf}"
        );
    };
    close(
        of("+proj=longlat +datum=WGS84 +no_defs "),
        6_378_137.0,
        298.257_223_563,
    );
    close(
        of("+proj=longlat +ellps=GRS80 +towgs84=0,0,0,0,0,0,0 +no_defs "),
        6_378_137.0,
        298.257_222_101,
    );
    close(
        of("+proj=longlat +datum=NAD27 +no_defs "),
        6_378_206.4,
        294.978_698_213_898,
    );
    close(
        of("+proj=longlat +ellps=intl +towgs84=-87,-98,-121,0,0,0,0 +no_defs "),
        6_378_388.0,
        297.0,
    );
    close(
        of("+proj=longlat +a=6378137 +rf=298.257222101 +no_defs"),
        6_378_137.0,
        298.257_222_101,
    );
    close(
        of("+proj=longlat +a=6378137 +b=6356752.314140356 +no_defs"),
        6_378_137.0,
        298.257_222_101,
    );
    // a sphere: no flattening
    let s = Spheroid::from_proj4("+proj=longlat +R=6371000 +no_defs").unwrap();
    assert_eq!((s.a, s.f), (6_371_000.0, 0.0));
    // no definition at all (an SRID spatial_ref_sys does not hold): WGS84
    assert_eq!(Spheroid::from_proj4(""), Some(Spheroid::WGS84));
    assert_eq!(
        Spheroid::from_proj4("+proj=longlat +ellps=nosuch +no_defs"),
        None
    );
    assert_eq!(
        Spheroid::from_proj4("+proj=longlat +datum=nosuch +no_defs"),
        None
    );
    assert_eq!(Spheroid::from_proj4("+proj=longlat +a=-5 +rf=300"), None);
}
