//! Exact hierarchy on every grid: no slivers, no hidden cracks (issue 22).
//!
//! Many generated rasters (fractional origins, geographic and projected
//! pixel sizes, both row directions, nodata holes and rotated nodata
//! borders, partial tiles, keep_border) are built the way `tin_from_raster`
//! builds them and, as scattered points, the way `tin_from_points` does.
//! Every level of every build is then checked by an oracle of this file's
//! own, in exact integer arithmetic on the pixel lattice (vertex lattice
//! coordinates recovered from the world coordinates and checked to be the
//! pixel centres bit for bit):
//! - no triangle whose smallest altitude is under 1e-3 pixel (in world
//!   coordinates, where users see the triangles);
//! - every edge is used by one triangle or by two with the same two end
//!   vertices in opposite directions, and an edge used once lies on the
//!   convex hull of the valid pixels (no T-junction, hidden or not), and
//!   the triangles cover exactly the hull's area;
//! - every triangle lies in its parent; every valid pixel is within the
//!   level's tolerance of the surface.
use crate::common;

use common::grids::{Grid, generate};
use rand::SeedableRng;
use rand::rngs::StdRng;
use std::collections::HashMap;
use tinmerge_core::tin::build::{BuildOptions, build, build_lattice, default_tolerances};
use tinmerge_core::tin::check::problems;
use tinmerge_core::tin::lattice::Lattice;
use tinmerge_core::tin::{NONE, Tin};

fn cross(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Convex hull of lattice points (counter-clockwise in lattice terms,
/// collinear points dropped): the test's own monotone chain in i64.
fn hull(mut p: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    p.sort();
    p.dedup();
    let mut h: Vec<(i64, i64)> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let it: Box<dyn Iterator<Item = &(i64, i64)>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in it {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

/// Everything the oracle found wrong with one tin of one grid.
#[derive(Default, Debug)]
struct Found {
    slivers: usize,
    min_altitude_px: f64,
    bad_edges: usize,
    not_nested: usize,
    over_tolerance: usize,
    uncovered: usize,
    other: Vec<String>,
}

fn oracle(g: &Grid, tin: &Tin) -> Found {
    let mut f = Found {
        min_altitude_px: f64::INFINITY,
        ..Default::default()
    };
    let px = g.lat.scale_x.abs();
    // lattice coordinates of every vertex, and they must be pixel centres
    let mut lv_xy = Vec::with_capacity(tin.verts.len());
    for v in &tin.verts {
        let c = ((v[0] - g.lat.ip_x) / g.lat.scale_x - 0.5).round() as i64;
        let r = ((v[1] - g.lat.ip_y) / g.lat.scale_y - 0.5).round() as i64;
        if g.centre(c, r) != (v[0], v[1]) {
            f.other
                .push(format!("vertex ({}, {}) is not a pixel centre", v[0], v[1]));
        }
        lv_xy.push((c, r));
    }
    let valid = g.valid();
    let hl = hull(valid.iter().map(|p| (p.0, p.1)).collect());
    let hull_area2: i64 = (0..hl.len())
        .map(|i| {
            let (a, b) = (hl[i], hl[(i + 1) % hl.len()]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum();
    // lattice orientation sign of world-CCW triangles
    let sgn: i64 = if g.lat.scale_x * g.lat.scale_y < 0.0 {
        -1
    } else {
        1
    };
    let on_hull = |a: (i64, i64), b: (i64, i64)| {
        (0..hl.len()).any(|i| {
            let (p, q) = (hl[i], hl[(i + 1) % hl.len()]);
            cross(p, q, a) == 0 && cross(p, q, b) == 0
        })
    };
    for (l, lv) in tin.levels.iter().enumerate() {
        let mut edges: HashMap<(u32, u32), Vec<(u32, u32)>> = HashMap::new();
        let mut area2 = 0i64;
        let mut best: Vec<f64> = vec![f64::NAN; valid.len()];
        let idx: HashMap<(i64, i64), usize> = valid
            .iter()
            .enumerate()
            .map(|(i, p)| ((p.0, p.1), i))
            .collect();
        for (t, tri) in lv.tris.iter().enumerate() {
            let w = tri.map(|v| tin.verts[v as usize]);
            // altitude in world coordinates, in pixels
            let a2 = ((w[1][0] - w[0][0]) * (w[2][1] - w[0][1])
                - (w[2][0] - w[0][0]) * (w[1][1] - w[0][1]))
                .abs();
            let longest = (0..3)
                .map(|j| {
                    let (p, q) = (w[j], w[(j + 1) % 3]);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .fold(0.0, f64::max);
            let alt = a2 / longest / px;
            f.min_altitude_px = f.min_altitude_px.min(alt);
            if alt < 1e-3 {
                f.slivers += 1;
            }
            let c = tri.map(|v| lv_xy[v as usize]);
            let la2 = sgn * cross(c[0], c[1], c[2]);
            if la2 <= 0 {
                f.other
                    .push(format!("level {l} triangle {t}: lattice area2 {la2}"));
                continue;
            }
            area2 += la2;
            for j in 0..3 {
                let (u, v) = (tri[j], tri[(j + 1) % 3]);
                edges.entry((u.min(v), u.max(v))).or_default().push((u, v));
            }
            // nesting, in the lattice
            if l > 0 {
                let p = lv.parent[t];
                let pc = tin.levels[l - 1].tris[p as usize].map(|v| lv_xy[v as usize]);
                if c.iter()
                    .any(|&q| (0..3).any(|j| sgn * cross(pc[j], pc[(j + 1) % 3], q) < 0))
                {
                    f.not_nested += 1;
                }
            }
            // error at every valid pixel inside (exact lattice test)
            let (x0, x1) = (
                c.iter().map(|p| p.0).min().unwrap_or(0),
                c.iter().map(|p| p.0).max().unwrap_or(0),
            );
            let (y0, y1) = (
                c.iter().map(|p| p.1).min().unwrap_or(0),
                c.iter().map(|p| p.1).max().unwrap_or(0),
            );
            let zc = tri.map(|v| tin.verts[v as usize][2]);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let q = (x, y);
                    let (b0, b1, b2) = (
                        sgn * cross(c[1], c[2], q),
                        sgn * cross(c[2], c[0], q),
                        sgn * cross(c[0], c[1], q),
                    );
                    if b0 < 0 || b1 < 0 || b2 < 0 {
                        continue;
                    }
                    if let Some(&i) = idx.get(&q) {
                        let s = (b0 + b1 + b2) as f64;
                        let z = (b0 as f64 * zc[0] + b1 as f64 * zc[1] + b2 as f64 * zc[2]) / s;
                        let e = (z - valid[i].2).abs();
                        best[i] = if best[i].is_nan() { e } else { best[i].min(e) };
                    }
                }
            }
        }
        for uses in edges.values() {
            let ok = match uses.as_slice() {
                [(a, b)] => on_hull(lv_xy[*a as usize], lv_xy[*b as usize]),
                [(a, b), (c, d)] => a == d && b == c,
                _ => false,
            };
            if !ok {
                f.bad_edges += 1;
            }
        }
        if area2 != hull_area2.abs() {
            f.other.push(format!(
                "level {l}: triangles cover lattice area2 {area2}, the hull {hull_area2}"
            ));
        }
        let tol = lv.tolerance * (1.0 + 1e-12) + 1e-9;
        f.uncovered += best.iter().filter(|e| e.is_nan()).count();
        f.over_tolerance += best.iter().filter(|&&e| e > tol).count();
        // the neighbour links agree with the edges
        for (t, nb) in lv.nbrs.iter().enumerate() {
            for (j, &n) in nb.iter().enumerate() {
                let tri = lv.tris[t];
                let (u, v) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
                let shared = edges
                    .get(&(u.min(v), u.max(v)))
                    .is_some_and(|e| e.len() == 2);
                if shared != (n != NONE) {
                    f.bad_edges += 1;
                }
            }
        }
    }
    f
}

fn assert_clean(what: &str, f: &Found) {
    assert!(
        f.slivers == 0
            && f.bad_edges == 0
            && f.not_nested == 0
            && f.over_tolerance == 0
            && f.uncovered == 0
            && f.other.is_empty(),
        "{what}: {f:?}"
    );
}

/// Lattice-collinear triples of pixel centres that are not exactly collinear
/// in world coordinates: the data must provoke the bug for the test to mean
/// anything.
fn rounding_triples(g: &Grid) -> usize {
    let mut n = 0;
    for k in 1..20i64 {
        let (a, m, b) = (g.centre(0, 0), g.centre(k, k), g.centre(2 * k, 2 * k));
        let o = robust::orient2d(
            robust::Coord { x: a.0, y: a.1 },
            robust::Coord { x: m.0, y: m.1 },
            robust::Coord { x: b.0, y: b.1 },
        );
        if o != 0.0 {
            n += 1;
        }
    }
    n
}

#[test]
fn generated_grids_have_no_slivers_or_cracks() {
    let mut rng = StdRng::seed_from_u64(22);
    let n: usize = std::env::var("TINMERGE_EXACT_GRIDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(48);
    let (mut provoking, mut min_alt) = (0usize, f64::INFINITY);
    let mut triangles = 0usize;
    for k in 0..n {
        let g = generate(&mut rng, k);
        if rounding_triples(&g) > 0 {
            provoking += 1;
        }
        let valid = g.valid();
        let span = 70.0;
        let levels = 4;
        let tols = default_tolerances(span / 40.0, levels).unwrap();
        let keep_border = k % 5 == 2;
        let opts = BuildOptions {
            keep_border,
            ..Default::default()
        };
        // tin_from_raster's path: the lattice
        let lattice_samples: Vec<[f64; 3]> = valid
            .iter()
            .map(|p| [p.0 as f64, p.1 as f64, p.2])
            .collect();
        let t = build_lattice(
            lattice_samples.clone(),
            &g.lat,
            &tols,
            4326,
            opts,
            &mut || Ok(()),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", g.name));
        let f = oracle(&g, &t);
        assert_clean(&format!("{} (raster build)", g.name), &f);
        min_alt = min_alt.min(f.min_altitude_px);
        triangles += t.levels.iter().map(|l| l.tris.len()).sum::<usize>();
        assert!(
            problems(&t, &mut || Ok(())).unwrap().is_empty(),
            "{}",
            g.name
        );
        // the hierarchy's own invariants, exactly, in the frame it was built in
        let in_lattice = build_lattice(
            lattice_samples,
            &common::IDENTITY,
            &tols,
            4326,
            opts,
            &mut || Ok(()),
        )
        .unwrap();
        in_lattice
            .sanity_check()
            .unwrap_or_else(|e| panic!("{}: {e}", g.name));
        assert_eq!(g.lat.to_world(in_lattice), t, "{}", g.name);
        tinmerge_core::tin::check::validate_structure(&t).unwrap();
        // tin_from_points' path: the same pixel centres as scattered points
        let world: Vec<[f64; 3]> = valid
            .iter()
            .map(|p| {
                let (x, y) = g.centre(p.0, p.1);
                [x, y, p.2]
            })
            .collect();
        let tp = build(world, &tols, 4326, &mut || Ok(()))
            .unwrap_or_else(|e| panic!("{} (point build): {e}", g.name));
        let fp = oracle(&g, &tp);
        assert_clean(&format!("{} (point build)", g.name), &fp);
        assert!(problems(&tp, &mut || Ok(())).unwrap().is_empty());
        tinmerge_core::tin::check::validate_structure(&tp).unwrap();
    }
    println!(
        "{n} grids ({provoking} with rounded collinear pixel centres), {triangles} triangles, \
         smallest altitude {min_alt:.4} px"
    );
    assert!(
        provoking > n / 2,
        "the grids must provoke rounding: {provoking} of {n}"
    );
}

/// The oracle itself finds slivers and cracks: a triangulation with a
/// hidden T-junction (the constraint-edge sliver 0.2.0 built) fails it.
#[test]
fn oracle_sees_a_hidden_t_junction() {
    let g = Grid {
        name: "3x3".into(),
        lat: Lattice {
            ip_x: 65472.33979011844 - 400.0,
            ip_y: 120345.07014525152 + 400.0,
            scale_x: 800.0,
            scale_y: -800.0,
            skew_x: 0.0,
            skew_y: 0.0,
        },
        w: 3,
        h: 3,
        z: vec![1.0; 9],
    };
    // corners (0,0) (2,0) (2,2) (0,2) and the centre (1,1) on the diagonal
    let p = |c: i64, r: i64, z: f64| {
        let (x, y) = g.centre(c, r);
        [x, y, z]
    };
    let verts = vec![
        p(0, 0, 1.0),
        p(2, 0, 1.0),
        p(2, 2, 1.0),
        p(0, 2, 1.0),
        p(1, 1, 40.0),
    ];
    // world CCW (rows run down): (0,0) (0,2) (2,2) split at the centre on
    // one side of the diagonal, whole on the other, and the sliver
    // between them as 0.2.0 built it
    let o = robust::orient2d(
        robust::Coord {
            x: verts[0][0],
            y: verts[0][1],
        },
        robust::Coord {
            x: verts[4][0],
            y: verts[4][1],
        },
        robust::Coord {
            x: verts[2][0],
            y: verts[2][1],
        },
    );
    assert!(o != 0.0, "the centre must be off the diagonal by rounding");
    let sliver = if o > 0.0 { [0, 4, 2] } else { [0, 2, 4] };
    let tris = vec![[0, 2, 1], [0, 3, 4], [4, 3, 2], sliver];
    let mut tin = Tin {
        srid: 0,
        bbox: tinmerge_core::tin::Bbox::of(&verts),
        verts,
        levels: vec![],
    };
    let nbrs = tinmerge_core::tin::hierarchy::compute_neighbours(&tris).unwrap();
    tin.levels.push(tinmerge_core::tin::Level {
        tolerance: 0.0,
        max_error: 0.0,
        num_vertices: 5,
        num_void: 0,
        tris,
        nbrs,
        parent: vec![NONE; 4],
        child_start: vec![],
        grid: tinmerge_core::tin::Grid {
            cell: 1.0,
            nx: 1,
            ny: 1,
            cells: vec![0],
        },
        outline: Default::default(),
        hull: Default::default(),
    });
    let f = oracle(&g, &tin);
    assert!(f.slivers >= 1 && f.bad_edges >= 1, "{f:?}");
    let p = problems(&tin, &mut || Ok(())).unwrap();
    assert!(p.iter().any(|p| p.kind == "crack"), "{p:?}");
}

/// The bundled geographic DEM (EPSG:4326, 1/1200 degree pixels), where
/// tinmerge 0.2.0 built 700 / 2,424 / 5,037 / 7,329 slivers at levels 1-4:
/// none now, through the raster path and the point path.
#[test]
fn geographic_dem_has_no_slivers() {
    let dem = common::read_dem("jacksboro_fault_dem.tif");
    let g = Grid {
        name: "jacksboro_fault_dem.tif".into(),
        lat: dem.lattice(),
        w: dem.width,
        h: dem.height,
        z: dem
            .values
            .iter()
            .map(|&v| if Some(v) == dem.nodata { f64::NAN } else { v })
            .collect(),
    };
    assert!(rounding_triples(&g) > 0);
    let samples: Vec<[f64; 3]> = g
        .valid()
        .iter()
        .map(|p| [p.0 as f64, p.1 as f64, p.2])
        .collect();
    let tols = default_tolerances(2.0, 5).unwrap();
    let t0 = std::time::Instant::now();
    let t = build_lattice(
        samples,
        &g.lat,
        &tols,
        4326,
        BuildOptions::default(),
        &mut || Ok(()),
    )
    .unwrap();
    let secs = t0.elapsed().as_secs_f64();
    let f = oracle(&g, &t);
    assert_clean("geographic DEM, raster build", &f);
    assert!(problems(&t, &mut || Ok(())).unwrap().is_empty());
    println!(
        "geographic DEM, lattice build in {secs:.2} s: triangles per level {:?}, smallest altitude {:.4} px",
        t.levels.iter().map(|l| l.tris.len()).collect::<Vec<_>>(),
        f.min_altitude_px
    );
    let t0 = std::time::Instant::now();
    let tp = build(dem.samples(), &tols, 4326, &mut || Ok(())).unwrap();
    let secs = t0.elapsed().as_secs_f64();
    assert_clean("geographic DEM, point build", &oracle(&g, &tp));
    println!(
        "geographic DEM, point build in {secs:.2} s: triangles per level {:?}",
        tp.levels.iter().map(|l| l.tris.len()).collect::<Vec<_>>()
    );
}
