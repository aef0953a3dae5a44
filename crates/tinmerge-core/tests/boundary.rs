//! A build's `boundary` (issue 26) on both bundled DEMs (geographic and
//! UTM with its nodata border), against `geo` as the oracle, at every
//! level. The boundary is a concave polygon with a hole, reaching past the
//! samples on one side, plus a second polygon (a MULTIPOLYGON):
//! - the domain (the triangles that are not void) has the area of
//!   boundary ∩ convex hull of the samples (`geo` BooleanOps), to 1e-9;
//! - every domain triangle lies in that region and every void one off it
//!   (centroids, `geo` point-in-polygon);
//! - every sample in the region is within the level's tolerance, and the
//!   height is None at every sample off it;
//! - the line merge: the pieces' planar length equals the length of the
//!   lines clipped to the region (`geo` clip);
//! - the area merge: coverage times triangle area sums to the area of the
//!   polygon ∩ region;
//! - the raster merge: the pixels handed to triangles are the pixel
//!   centres in the region (`geo`, away from its boundary by rounding);
//! - the overlay with a plain tin: its domain triangles cover the region
//!   ∩ the other tin's hull;
//! - the value survives encode/decode (format 5) and the hierarchy's
//!   invariants hold (`sanity_check`, `check::problems`).
use crate::common;

use common::{Dem, edge_on, read_dem};
use geo::{
    Area as _, BooleanOps, Contains, ConvexHull, Coord, Euclidean, Length, LineString,
    MultiLineString, MultiPoint, MultiPolygon, Point, Polygon,
};
use tinmerge_core::io::ewkb::Geom;
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::{Method, area_rows, sweep};
use tinmerge_core::merge::line::drape::drape;
use tinmerge_core::merge::line::{Part, pieces};
use tinmerge_core::merge::overlay::overlay;
use tinmerge_core::merge::point::height;
use tinmerge_core::merge::raster::PixelGrid;
use tinmerge_core::merge::raster::patch::TinLevel;
use tinmerge_core::merge::raster::stats::zonal_stats;
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::build::{boundary, build, build_domain, default_tolerances};
use tinmerge_core::tin::check::problems;
use tinmerge_core::tin::layout::{VERSION_5, decode, encode, read_header};
use tinmerge_core::tin::locate::locate;

/// World coordinates of fractional pixel position (col, row).
fn world(d: &Dem, c: f64, r: f64) -> [f64; 2] {
    [
        d.origin_x + (c + 0.5) * d.scale_x,
        d.origin_y - (r + 0.5) * d.scale_y,
    ]
}

/// The boundary's polygons in world coordinates: a concave shell reaching
/// past the east edge with a hole, and a small separate square.
fn polygons(d: &Dem) -> Vec<Vec<Vec<[f64; 2]>>> {
    let (w, h) = (d.width as f64, d.height as f64);
    let ring = |pts: &[(f64, f64)]| -> Vec<[f64; 2]> {
        let mut r: Vec<[f64; 2]> = pts.iter().map(|&(c, r)| world(d, c * w, r * h)).collect();
        r.push(r[0]);
        r
    };
    let shell = ring(&[
        (0.08, 0.10),
        (0.70, 0.06),
        (0.52, 0.43),
        (1.30, 0.50),
        (0.81, 0.77),
        (0.17, 0.70),
    ]);
    // a hole around (0.35, 0.40), clockwise in the picture
    let hole = ring(&[(0.30, 0.33), (0.42, 0.37), (0.40, 0.48), (0.27, 0.45)]);
    let square = ring(&[(0.10, 0.82), (0.25, 0.82), (0.25, 0.95), (0.10, 0.95)]);
    vec![vec![shell, hole], vec![square]]
}

fn geo_mp(polys: &[Vec<Vec<[f64; 2]>>]) -> MultiPolygon<f64> {
    let ls =
        |r: &Vec<[f64; 2]>| LineString::new(r.iter().map(|p| Coord { x: p[0], y: p[1] }).collect());
    MultiPolygon::new(
        polys
            .iter()
            .map(|p| Polygon::new(ls(&p[0]), p[1..].iter().map(ls).collect()))
            .collect(),
    )
}

fn tri_area(c: &[[f64; 3]; 3]) -> f64 {
    ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1])) / 2.0
}

/// The samples' convex hull as a polygon.
fn hull_of(samples: &[[f64; 3]]) -> Polygon<f64> {
    MultiPoint::new(samples.iter().map(|p| Point::new(p[0], p[1])).collect()).convex_hull()
}

/// Whether `p` is in `region` and at least `eps` from its boundary (the
/// oracle's verdict is safe from rounding there).
fn clearly(region: &MultiPolygon<f64>, p: [f64; 2], eps: f64) -> Option<bool> {
    use geo::Distance;
    let pt = Point::new(p[0], p[1]);
    let near = region
        .0
        .iter()
        .flat_map(|poly| std::iter::once(poly.exterior()).chain(poly.interiors()))
        .any(|r| Euclidean.distance(&pt, r) < eps);
    (!near).then(|| region.contains(&pt))
}

fn check(name: &str, srid: i32) {
    let d = read_dem(name);
    let samples = d.samples();
    let tols = default_tolerances(2.0, 4).unwrap();
    let polys = polygons(&d);
    let area = boundary(polys.clone()).unwrap();
    let tin = build_domain(samples.clone(), &[], &[&area], &tols, srid, &mut || Ok(())).unwrap();
    // the invariants, told that the rings' edges need not be Delaunay
    let segs: Vec<([f64; 3], [f64; 3])> = polys
        .iter()
        .flatten()
        .flat_map(|r| {
            r.windows(2)
                .map(|w| ([w[0][0], w[0][1], 0.0], [w[1][0], w[1][1], 0.0]))
        })
        .collect();
    tin.sanity_check_constrained(&|p, q| {
        segs.iter()
            .any(|(a, b)| edge_on(a, b, p, q, 1e-9).is_some())
    })
    .unwrap();
    assert!(problems(&tin, &mut || Ok(())).unwrap().is_empty());
    let region = geo_mp(&polys).intersection(&MultiPolygon::new(vec![hull_of(&samples)]));
    let want = region.unsigned_area();
    let scale = d.scale_x;
    let eps = 1e-6 * scale;
    for (l, lv) in tin.levels.iter().enumerate() {
        assert!(lv.num_void > 0, "{name} level {l}: no void triangle");
        let got: f64 = (0..lv.num_domain())
            .map(|t| tri_area(&tin.corners(l, t as u32)))
            .sum();
        assert!(
            (got - want).abs() <= 1e-9 * want,
            "{name} level {l}: domain area {got}, boundary ∩ hull {want}"
        );
        for t in 0..lv.tris.len() as u32 {
            let c = tin.corners(l, t);
            let g = [
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            ];
            if let Some(inside) = clearly(&region, g, 1e-9 * scale) {
                assert_eq!(inside, !lv.is_void(t), "{name} level {l} triangle {t}");
            }
        }
        // the error bound in the region, nothing off it
        let (mut n_in, mut n_out) = (0, 0);
        for s in &samples {
            match clearly(&region, [s[0], s[1]], eps) {
                Some(true) => {
                    let z =
                        height(&tin, l, s[0], s[1]).expect("a sample in the domain has a height");
                    assert!(
                        (z - s[2]).abs() <= lv.tolerance + 1e-9,
                        "{name} level {l}: error {} at ({} {})",
                        (z - s[2]).abs(),
                        s[0],
                        s[1]
                    );
                    n_in += 1;
                }
                Some(false) => {
                    assert_eq!(height(&tin, l, s[0], s[1]), None, "{name} level {l}");
                    n_out += 1;
                }
                None => {}
            }
        }
        assert!(
            n_in > 1000 && n_out > 1000,
            "{name}: {n_in} in, {n_out} out"
        );
    }

    // lines: three crossing the hole, the notch and the gap
    let (w, h) = (d.width as f64, d.height as f64);
    let lines: Vec<Vec<[f64; 2]>> = vec![
        vec![world(&d, -0.1 * w, 0.41 * h), world(&d, 1.1 * w, 0.39 * h)],
        vec![
            world(&d, 0.2 * w, 0.02 * h),
            world(&d, 0.6 * w, 0.6 * h),
            world(&d, 0.15 * w, 0.98 * h),
        ],
        vec![world(&d, 0.9 * w, 0.1 * h), world(&d, 0.45 * w, 0.35 * h)],
    ];
    let mls = MultiLineString::new(
        lines
            .iter()
            .map(|l| LineString::new(l.iter().map(|p| Coord { x: p[0], y: p[1] }).collect()))
            .collect(),
    );
    let want_len = Euclidean.length(&region.clip(&mls, false));
    let parts: Vec<Part> = lines.iter().map(|l| Part::new(l.clone())).collect();
    // a polygon over the hole, the notch and off the data
    let cover = vec![vec![
        world(&d, 0.2 * w, 0.2 * h),
        world(&d, 1.2 * w, 0.3 * h),
        world(&d, 0.6 * w, 0.9 * h),
        world(&d, 0.2 * w, 0.2 * h),
    ]];
    let want_cover = geo_mp(std::slice::from_ref(&cover))
        .intersection(&region)
        .unsigned_area();
    let cover = Area::new(vec![cover]);
    for l in 0..tin.levels.len() {
        let ps = pieces(&tin, l, &parts).unwrap();
        let got: f64 = ps.iter().map(|p| p.length2d()).sum();
        // geo's clip (i_overlay) rounds to a fixed grid over the extent:
        // about 1e-9 of it
        assert!(
            (got - want_len).abs() <= 1e-8 * want_len,
            "{name} level {l}: pieces {got}, clipped lines {want_len}"
        );
        assert!(ps.iter().all(|p| !tin.levels[l].is_void(p.triangle)));
        let s = sweep(&tin, l, &cover, Method::Hierarchy, &mut || Ok(())).unwrap();
        let rows = area_rows(&tin, &cover, &s, true, &mut || Ok(())).unwrap();
        let got: f64 = rows
            .iter()
            .map(|r| r.coverage * tri_area(&tin.corners(r.level, r.triangle)))
            .sum();
        assert!(
            (got - want_cover).abs() <= 1e-9 * want_cover,
            "{name} level {l}: area rows {got}, polygon ∩ domain {want_cover}"
        );
    }

    // the raster merge: the DEM's own pixels at the finest level
    let gt = d.geotransform();
    let g = PixelGrid::new(&gt, d.width, d.height).unwrap();
    let fin = tin.levels.len() - 1;
    let lv = TinLevel::new(&tin, fin).unwrap();
    let st = zonal_stats(&lv, &g, &d.values, d.nodata, false, &mut || Ok(())).unwrap();
    let got: usize = st.iter().map(|z| z.count as usize).sum();
    let (mut lo, mut hi) = (0usize, 0usize);
    for s in &samples {
        match clearly(&region, [s[0], s[1]], eps) {
            Some(true) => {
                lo += 1;
                hi += 1
            }
            None => hi += 1,
            Some(false) => {}
        }
    }
    assert!(
        lo <= got && got <= hi,
        "{name}: {got} pixels handed, {lo}..={hi} in the region"
    );
    assert!(st.iter().all(|z| !tin.levels[fin].is_void(z.triangle)));

    // the overlay with a plain tin of every other sample
    let other: Vec<[f64; 3]> = samples.iter().step_by(2).copied().collect();
    let b = build(other.clone(), &[tols[0]], srid, &mut || Ok(())).unwrap();
    let o = overlay(&tin, 1, &b, 0, &mut || Ok(())).unwrap();
    let got: f64 = o.domain().map(|t| o.area(t)).sum();
    let want_o = region
        .intersection(&MultiPolygon::new(vec![hull_of(&other)]))
        .unsigned_area();
    assert!(
        (got - want_o).abs() <= 1e-9 * want_o,
        "{name}: overlay {got}, region ∩ hull {want_o}"
    );

    // tin_drape of a polygon keeps its intersection with the domain, on
    // the surface: a strip whose corners are all on the terrain but which
    // crosses the hole (it was cut silently to one of its runs in 0.9.0),
    // one beside the hole (whole), one leaving the DEM and one off it
    // (nothing). Oracles: the strip ∩ boundary ∩ hull by geo (area), and
    // the level's own triangles by brute force (every vertex and edge
    // midpoint on the surface).
    let (w, h) = (d.width as f64, d.height as f64);
    // a rectangle from fractions (x0, y0) to (x1, y1) of the raster
    let rect = |x0: f64, x1: f64, y0: f64, y1: f64| {
        let (a, b) = (world(&d, x0 * w, y0 * h), world(&d, x1 * w, y1 * h));
        vec![
            [a[0], a[1], 0.0],
            [b[0], a[1], 0.0],
            [b[0], b[1], 0.0],
            [a[0], b[1], 0.0],
            [a[0], a[1], 0.0],
        ]
    };
    let fin = tin.levels.len() - 1;
    let surface = |l: usize, x: f64, y: f64| -> Option<f64> {
        let (lv, fin) = (&tin.levels[l], l);
        (0..lv.num_domain() as u32).find_map(|t| {
            let c = tin.corners(fin, t);
            let den = (c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
            let wb =
                ((x - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (y - c[0][1])) / den;
            let wc =
                ((c[1][0] - c[0][0]) * (y - c[0][1]) - (x - c[0][0]) * (c[1][1] - c[0][1])) / den;
            let wa = 1.0 - wb - wc;
            // within 1e-9 pixel of the triangle: a weight times the
            // corner's height over the opposite edge is the distance to
            // that edge (a barycentric tolerance alone is too tight on a
            // sliver: an edge midpoint rounded by an ulp is 1e-8 off it)
            let len = |a: usize, b: usize| (c[a][0] - c[b][0]).hypot(c[a][1] - c[b][1]);
            let eps = 1e-9 * scale;
            (wa * den.abs() / len(1, 2) >= -eps
                && wb * den.abs() / len(0, 2) >= -eps
                && wc * den.abs() / len(0, 1) >= -eps)
                .then(|| wa * c[0][2] + wb * c[1][2] + wc * c[2][2])
        })
    };
    // strips two pixels high, and a rectangle around the hole (its rings
    // all on the terrain, the hole inside: it comes back with a hole)
    // at the finest level; then 40 seeded random triangles over and around
    // the raster at level 0 (its few triangles keep the brute force short)
    let px = 2.0 / h;
    type Case = (String, usize, Vec<[f64; 3]>, Option<usize>);
    let mut cases: Vec<Case> = [
        (0.22, 0.48, 0.40, 0.40 - px, 2),
        (0.22, 0.26, 0.40, 0.40 - px, 1),
        (0.9, 1.3, 0.55, 0.55 - px, 1),
        (1.2, 1.3, 0.55, 0.55 - px, 0),
        (0.25, 0.46, 0.49, 0.31, 1),
    ]
    .into_iter()
    .map(|(x0, x1, y0, y1, n)| {
        (
            format!("rectangle {x0}..{x1} x {y0}..{y1}"),
            fin,
            rect(x0, x1, y0, y1),
            Some(n),
        )
    })
    .collect();
    {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(26);
        for i in 0..40 {
            let mut p = || {
                let q = world(
                    &d,
                    rng.random_range(-0.2..1.2) * w,
                    rng.random_range(-0.2..1.2) * h,
                );
                [q[0], q[1], 0.0]
            };
            let (a, b, c) = (p(), p(), p());
            cases.push((format!("random triangle {i}"), 0, vec![a, b, c, a], None));
        }
    }
    for (label, l, s, pieces_want) in cases {
        let got = drape(&tin, l, &Geom::Polygon(vec![s.clone()])).unwrap();
        let polys: Vec<Vec<Vec<[f64; 3]>>> = match got {
            None => vec![],
            Some(Geom::Polygon(rs)) => vec![rs],
            Some(Geom::MultiPolygon(ps)) => ps,
            other => panic!("{name}: {other:?}"),
        };
        let oracle = MultiPolygon::new(vec![Polygon::new(
            LineString::from(s.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
            vec![],
        )])
        .intersection(&region);
        assert_eq!(polys.len(), oracle.0.len(), "{name} {label}");
        if let Some(n) = pieces_want {
            assert_eq!(polys.len(), n, "{name} {label}");
        }
        let holes: usize = polys.iter().map(|p| p.len() - 1).sum();
        let holes_want: usize = oracle.0.iter().map(|p| p.interiors().len()).sum();
        assert_eq!(holes, holes_want, "{name} {label}: holes");
        let mut area = 0.0;
        for rs in &polys {
            for (k, r) in rs.iter().enumerate() {
                assert!(r.len() >= 4 && r.first() == r.last(), "{name}: {r:?}");
                // shoelace about the first vertex (no cancellation)
                let o = r[0];
                let a2: f64 = r
                    .windows(2)
                    .map(|p| {
                        (p[0][0] - o[0]) * (p[1][1] - o[1]) - (p[1][0] - o[0]) * (p[0][1] - o[1])
                    })
                    .sum::<f64>()
                    / 2.0;
                area += if k == 0 { a2.abs() } else { -a2.abs() };
                for wv in r.windows(2) {
                    let m = [
                        (wv[0][0] + wv[1][0]) / 2.0,
                        (wv[0][1] + wv[1][1]) / 2.0,
                        (wv[0][2] + wv[1][2]) / 2.0,
                    ];
                    for v in [wv[0], m] {
                        let z = surface(l, v[0], v[1]).unwrap_or_else(|| {
                            panic!("{name} {label}: {v:?} of {wv:?} is off the terrain")
                        });
                        assert!((z - v[2]).abs() < 1e-6, "{name}: {v:?} vs {z}");
                    }
                }
            }
        }
        // both cuts (geo's and the drape's) are i_overlay's, on a grid of
        // about 1e-9 of the extent: their areas differ by a few grid steps
        // times the strip's perimeter
        let want = oracle.unsigned_area();
        let extent = (d.width as f64 * d.scale_x).hypot(d.height as f64 * d.scale_y);
        let perimeter: f64 = s
            .windows(2)
            .map(|p| (p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]))
            .sum();
        assert!(
            (area - want).abs() <= 1e-8 * extent * perimeter,
            "{name} {label}: draped area {area}, polygon ∩ domain {want}"
        );
    }

    // storage: format 5, the same tin back
    let bytes = encode(&tin);
    assert_eq!(read_header(&bytes).unwrap().version, VERSION_5);
    let back: Tin = decode(&bytes).unwrap();
    assert_eq!(back, tin);
}

#[test]
fn boundary_on_the_utm_dem() {
    check("jacksboro_fault_dem_utm16n.tif", 32616);
}

#[test]
fn boundary_on_the_geographic_dem() {
    check("jacksboro_fault_dem.tif", 4326);
}

/// A boundary that holds the whole hull gives the plain build, byte for
/// byte; one that misses the samples, an error; an invalid one, an error
/// naming the problem.
#[test]
fn boundary_edge_cases() {
    let d = read_dem("jacksboro_fault_dem.tif");
    let samples = d.samples();
    let tols = default_tolerances(8.0, 3).unwrap();
    let (w, h) = (d.width as f64, d.height as f64);
    let big = vec![vec![vec![
        world(&d, -1.0, -1.0),
        world(&d, w + 1.0, -1.0),
        world(&d, w + 1.0, h + 1.0),
        world(&d, -1.0, h + 1.0),
        world(&d, -1.0, -1.0),
    ]]];
    let a = boundary(big).unwrap();
    let t = build_domain(samples.clone(), &[], &[&a], &tols, 4326, &mut || Ok(())).unwrap();
    let plain = build(samples.clone(), &tols, 4326, &mut || Ok(())).unwrap();
    assert_eq!(encode(&t), encode(&plain));
    let away = vec![vec![vec![
        world(&d, 2.0 * w, 0.0),
        world(&d, 3.0 * w, 0.0),
        world(&d, 3.0 * w, h),
        world(&d, 2.0 * w, 0.0),
    ]]];
    let a = boundary(away).unwrap();
    let e = build_domain(samples.clone(), &[], &[&a], &tols, 4326, &mut || Ok(())).unwrap_err();
    assert!(e.to_string().contains("does not overlap"), "{e}");
    // a bow tie
    let bow = vec![vec![vec![
        world(&d, 0.0, 0.0),
        world(&d, w, h),
        world(&d, w, 0.0),
        world(&d, 0.0, h),
        world(&d, 0.0, 0.0),
    ]]];
    let e = boundary(bow).unwrap_err();
    assert!(e.to_string().contains("ST_MakeValid"), "{e}");
    // tin_drape of polygons that are not finite or bow ties, partly off
    // the plain tin: an error naming the vertex, or a cut by the even-odd
    // rule, never a panic
    let l = plain.levels.len() - 1;
    let poly =
        |ps: &[[f64; 2]]| Geom::Polygon(vec![ps.iter().map(|p| [p[0], p[1], 0.0]).collect()]);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let g = poly(&[
            world(&d, -5.0, 5.0),
            world(&d, 5.0, 5.0),
            [bad, world(&d, 5.0, 10.0)[1]],
            world(&d, -5.0, 5.0),
        ]);
        let e = drape(&plain, l, &g).unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
    }
    let bow = poly(&[
        world(&d, -5.0, 5.0),
        world(&d, 5.0, 15.0),
        world(&d, 5.0, 5.0),
        world(&d, -5.0, 15.0),
        world(&d, -5.0, 5.0),
    ]);
    assert!(drape(&plain, l, &bow).unwrap().is_some());
}

/// The domain of the valid pixels (`fill_gaps => false`): the UTM DEM's
/// nodata border, the geographic DEM with a block of nodata inside. The
/// domain's area is that of the valid pixels' squares (`geo` union of
/// the squares) clipped to the hull of the valid centres, and the height
/// is None at every nodata centre.
#[test]
fn domain_of_the_valid_pixels() {
    use tinmerge_core::tin::domain::{cell_outline, outline_area};
    for (name, srid, hole) in [
        ("jacksboro_fault_dem_utm16n.tif", 32616, false),
        ("jacksboro_fault_dem.tif", 4326, true),
    ] {
        let mut d = read_dem(name);
        if hole {
            d.nodata = Some(-9999.0);
            for r in 150..170 {
                for c in 200..230 {
                    d.values[r * d.width + c] = -9999.0;
                }
            }
        }
        let ok = |v: f64| !(v.is_nan() || Some(v) == d.nodata);
        let (w, h) = (d.width, d.height);
        let rings = cell_outline(w, h, &|c, r| ok(d.values[r * w + c]));
        let area = outline_area(&rings, &|c, r| world(&d, c - 0.5, r - 0.5));
        let samples = d.samples();
        let tin = build_domain(
            samples.clone(),
            &[],
            &[&area],
            &[8.0, 2.0],
            srid,
            &mut || Ok(()),
        )
        .unwrap();
        // the oracle: the union of the valid squares, by geo
        let mut squares = Vec::new();
        for r in 0..h {
            for c in 0..w {
                if ok(d.values[r * w + c]) {
                    let p = |dc: f64, dr: f64| {
                        let q = world(&d, c as f64 - 0.5 + dc, r as f64 - 0.5 + dr);
                        Coord { x: q[0], y: q[1] }
                    };
                    squares.push(Polygon::new(
                        LineString::new(vec![
                            p(0., 0.),
                            p(1., 0.),
                            p(1., 1.),
                            p(0., 1.),
                            p(0., 0.),
                        ]),
                        vec![],
                    ));
                }
            }
        }
        let cells = geo::unary_union(&squares);
        let region = cells.intersection(&MultiPolygon::new(vec![hull_of(&samples)]));
        let want = region.unsigned_area();
        for (l, lv) in tin.levels.iter().enumerate() {
            let got: f64 = (0..lv.num_domain())
                .map(|t| tri_area(&tin.corners(l, t as u32)))
                .sum();
            assert!(
                (got - want).abs() <= 1e-9 * want,
                "{name} level {l}: domain {got}, valid squares ∩ hull {want}"
            );
            for r in 0..h {
                for c in 0..w {
                    if !ok(d.values[r * w + c]) {
                        let p = world(&d, c as f64, r as f64);
                        assert_eq!(height(&tin, l, p[0], p[1]), None, "{name} ({c}, {r})");
                    }
                }
            }
            // Every corner of a domain triangle is in the domain. Where the
            // outline is cut at the samples' hull the outer boundary bends
            // in by an ulp (a sliver dropped), and the walk ended "outside"
            // at a hull edge whose line passes a rounding beyond such a
            // corner: tin_height was NULL at a vertex of the terrain.
            let lv = &tin.levels[l];
            let mut lost = 0;
            for t in 0..lv.num_domain() {
                for v in tin.corners(l, t as u32) {
                    if locate(&tin, l, v[0], v[1]).is_none_or(|u| lv.is_void(u)) {
                        lost += 1;
                    }
                }
            }
            assert_eq!(
                lost, 0,
                "{name} level {l}: corners of domain triangles not located"
            );
        }
        // the overlay with a coarser build over the same data, both with
        // void triangles: the common domain is the tin's (pg_regress
        // `boundary` pins the stored UTM case the overlay refused as "not a
        // triangulation of the convex hull of its vertices")
        let b = build_domain(samples, &[], &[&area], &[8.0], srid, &mut || Ok(())).unwrap();
        let o = overlay(&tin, 1, &b, 0, &mut || Ok(())).unwrap();
        let got: f64 = o.domain().map(|t| o.area(t)).sum();
        let want = (0..tin.levels[1].num_domain())
            .map(|t| tri_area(&tin.corners(1, t as u32)))
            .sum::<f64>();
        assert!(
            (got - want).abs() <= 1e-9 * want,
            "{name}: overlay {got}, domain {want}"
        );
    }
}
