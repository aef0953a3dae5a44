//! Each level's whole sums in the header (formats 6 and 7,
//! `merge::area::whole`): against an oracle written here (every triangle
//! that is not void, its area by the shoelace, its surface by the cross
//! product, its slope from its normal), against the sweep over the
//! triangles (the same bits), through storage and slices; and
//! `Area::contains_box`, which decides when the header answers, against
//! `geo`'s exact relate (covers).

use crate::common;

use geo::{Area as _, Coord, LineString, Polygon, Rect, Relate, Validation};
use rand::{Rng, SeedableRng, rngs::StdRng};
use tinmerge_core::geom::Units;
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::surface::{SubtreeSums, stats_with, volume_parts_with};
use tinmerge_core::merge::area::whole::{level_sums, stats_from_header, volume_from_header};
use tinmerge_core::merge::area::{Method, sweep};
use tinmerge_core::tin::Tin;
use tinmerge_core::tin::layout::{
    HEADER_LEN_V6, LevelSums, SUMS_AT, VERSION_6, VERSION_7, decode, encode_with_sums, read_header,
    reseal,
};

type P2 = [f64; 2];

fn no_interrupt() -> Result<(), tinmerge_core::tin::TinError> {
    Ok(())
}

/// The oracle: one level's sums over its triangles that are not void.
fn oracle(tin: &Tin, l: usize) -> LevelSums {
    let lv = &tin.levels[l];
    let live = lv.tris.len() - lv.num_void as usize;
    let mut o = LevelSums {
        area2d: 0.0,
        area3d: 0.0,
        min_z: f64::INFINITY,
        max_z: f64::NEG_INFINITY,
        z_integral: 0.0,
        slope_integral: 0.0,
        max_slope: 0.0,
    };
    for t in 0..live as u32 {
        let c = tin.corners(l, t);
        let n = common::normal(&c);
        let a = n[2] / 2.0;
        assert!(a > 0.0, "level {l} triangle {t} is not counter-clockwise");
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let slope = (n[2] / len).acos().to_degrees();
        o.area2d += a;
        o.area3d += len / 2.0;
        o.z_integral += a * (c[0][2] + c[1][2] + c[2][2]) / 3.0;
        o.slope_integral += a * slope;
        o.max_slope = o.max_slope.max(slope);
        for p in c {
            o.min_z = o.min_z.min(p[2]);
            o.max_z = o.max_z.max(p[2]);
        }
    }
    o
}

fn close(a: f64, b: f64, scale: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-9 * scale.abs().max(1e-300),
        "{what}: {a} against the oracle's {b}"
    );
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Area {
    Area::new(vec![vec![vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]]])
}

/// One tin: its sums against the oracle, stored in format 6 or 7 and read
/// back (the same tin, the same sums), and the header's answers against
/// the sweep over the triangles for polygons that hold the terrain (the
/// same bits for statistics; volumes within a rounding) and none for
/// polygons that do not.
fn check(name: &str, tin: &Tin) {
    let sums = level_sums(tin, &mut no_interrupt).unwrap();
    assert_eq!(sums.len(), tin.num_levels());
    for (l, s) in sums.iter().enumerate() {
        let o = oracle(tin, l);
        let what = |f: &str| format!("{name} level {l}: {f}");
        close(s.area2d, o.area2d, o.area2d, &what("planar area"));
        close(s.area3d, o.area3d, o.area3d, &what("surface area"));
        assert_eq!(
            (s.min_z, s.max_z),
            (o.min_z, o.max_z),
            "{}",
            what("extremes")
        );
        let zs = o.area2d * o.max_z.abs().max(o.min_z.abs());
        close(s.z_integral, o.z_integral, zs, &what("integral of z"));
        close(
            s.slope_integral,
            o.slope_integral,
            o.area2d * 90.0,
            &what("integral of slope"),
        );
        close(s.max_slope, o.max_slope, 90.0, &what("steepest slope"));
    }
    let stored = encode_with_sums(tin, None, &sums);
    let h = read_header(&stored).unwrap();
    let void = tin.levels.iter().any(|l| l.num_void > 0);
    assert_eq!(
        h.version,
        if void { VERSION_7 } else { VERSION_6 },
        "{name}"
    );
    assert_eq!(h.sums, sums, "{name}: sums read back");
    assert_eq!(&decode(&stored).unwrap(), tin, "{name}: the tin read back");

    let b = tin.bbox;
    let (w, hgt) = (b.max_x - b.min_x, b.max_y - b.min_y);
    let holding = [
        (
            "the bounding box itself",
            rect(b.min_x, b.min_y, b.max_x, b.max_y),
        ),
        (
            "a rectangle around",
            rect(b.min_x - w, b.min_y - hgt, b.max_x + w, b.max_y + hgt),
        ),
        (
            "a hexagon around",
            Area::new(vec![vec![vec![
                [b.min_x - w, b.min_y + hgt / 2.0],
                [b.min_x, b.min_y - hgt],
                [b.max_x, b.min_y - hgt],
                [b.max_x + w, b.min_y + hgt / 2.0],
                [b.max_x, b.max_y + hgt],
                [b.min_x, b.max_y + hgt],
            ]]]),
        ),
    ];
    for (what, area) in &holding {
        for l in 0..tin.num_levels() {
            let s = sweep(tin, l, area, Method::Hierarchy, &mut no_interrupt).unwrap();
            let subtree = (l > 0)
                .then(|| SubtreeSums::build(tin, l, Units::Planar, &mut no_interrupt).unwrap());
            let slow = stats_with(
                tin,
                area,
                &s,
                subtree.as_ref(),
                Units::Planar,
                &mut no_interrupt,
            )
            .unwrap();
            let fast = stats_from_header(&h, l, area)
                .unwrap_or_else(|| panic!("{name} level {l}: {what} not answered from the header"));
            assert_eq!(fast, slow, "{name} level {l}: {what}");
            for base in [b.min_z - 1.0, b.max_z + 1.0] {
                let v = volume_parts_with(
                    tin,
                    area,
                    &s,
                    base,
                    subtree.as_ref(),
                    Units::Planar,
                    &mut no_interrupt,
                )
                .unwrap();
                let f = volume_from_header(&h, l, area, base).unwrap();
                let scale = slow.area2d * (b.max_z - b.min_z + 2.0);
                close(
                    f.cut,
                    v.cut,
                    scale,
                    &format!("{name} level {l} {what}: cut"),
                );
                close(
                    f.fill,
                    v.fill,
                    scale,
                    &format!("{name} level {l} {what}: fill"),
                );
                assert_eq!((f.area_above, f.area_below), (v.area_above, v.area_below));
            }
            // a base the surface reaches: the triangles must say
            let mid = (slow.min_z + slow.max_z) / 2.0;
            assert!(volume_from_header(&h, l, area, mid).is_none());
        }
    }
    let cx = (b.min_x + b.max_x) / 2.0;
    let cy = (b.min_y + b.max_y) / 2.0;
    let not_holding = [
        (
            "a rectangle cut short",
            rect(b.min_x - w, b.min_y - hgt, b.max_x - w / 1e6, b.max_y + hgt),
        ),
        (
            "a rectangle around with a hole",
            Area::new(vec![vec![
                vec![
                    [b.min_x - w, b.min_y - hgt],
                    [b.max_x + w, b.min_y - hgt],
                    [b.max_x + w, b.max_y + hgt],
                    [b.min_x - w, b.max_y + hgt],
                ],
                vec![
                    [cx, cy],
                    [cx, cy + hgt / 10.0],
                    [cx + w / 10.0, cy + hgt / 10.0],
                    [cx + w / 10.0, cy],
                ],
            ]]),
        ),
    ];
    for (what, area) in &not_holding {
        for l in 0..tin.num_levels() {
            assert!(stats_from_header(&h, l, area).is_none(), "{name}: {what}");
        }
    }
}

#[test]
fn whole_sums_match_the_oracle_and_the_sweep() {
    for t in common::terrains() {
        check(t.name, &t.tin);
    }
    // tiles of the UTM DEM, each its own tin (the header is what a tile
    // wholly inside a polygon answers from)
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    for (tx, ty, t) in common::tiles_of(&d, 96, &[8.0, 4.0, 2.0], 32616) {
        check(&format!("UTM tile ({tx}, {ty})"), &t);
    }
}

/// A random star polygon around `c` with `n` corners, radii up to `r`.
fn star(rng: &mut StdRng, c: P2, r: f64, n: usize) -> Vec<P2> {
    (0..n)
        .map(|k| {
            let a = k as f64 / n as f64 * std::f64::consts::TAU;
            let rr = r * rng.random_range(0.3..1.0);
            [c[0] + rr * a.cos(), c[1] + rr * a.sin()]
        })
        .collect()
}

fn geo_ring(r: &[P2]) -> LineString<f64> {
    let mut v: Vec<Coord<f64>> = r.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    v.push(v[0]);
    LineString::new(v)
}

#[test]
fn contains_box_agrees_with_geo() {
    let mut rng = StdRng::seed_from_u64(76);
    let (mut yes, mut no) = (0, 0);
    for trial in 0..600 {
        let n = rng.random_range(3..40);
        let mut shell = star(&mut rng, [0.0, 0.0], 100.0, n);
        if trial % 2 == 1 {
            // on a grid of 4 units with boxes on it too: edges through box
            // corners and along box sides
            for p in &mut shell {
                *p = p.map(|c| (c / 4.0).round() * 4.0);
            }
            shell.dedup();
            if shell.len() < 3 || Polygon::new(geo_ring(&shell), vec![]).unsigned_area() == 0.0 {
                continue;
            }
        }
        let hole = (trial % 3 == 0).then(|| {
            let mut h = star(&mut rng, [10.0, 5.0], 12.0, 8);
            h.reverse();
            h
        });
        let mut rings = vec![shell.clone()];
        rings.extend(hole.clone());
        let area = Area::new(vec![rings]);
        let poly = Polygon::new(geo_ring(&shell), hole.iter().map(|h| geo_ring(h)).collect());
        if !poly.is_valid() {
            continue;
        }
        // corners at random, on the polygon's vertices' coordinates (boxes
        // that touch its boundary) and on a grid through its middle
        let coords: Vec<f64> = shell.iter().flat_map(|p| [p[0], p[1]]).collect();
        for k in 0..40 {
            let pick = |rng: &mut StdRng| -> f64 {
                match k % 3 {
                    0 => rng.random_range(-80.0..80.0),
                    1 => coords[rng.random_range(0..coords.len())],
                    _ => rng.random_range(-20i32..20) as f64 * 4.0,
                }
            };
            let (a, b) = (pick(&mut rng), pick(&mut rng));
            let (c, d) = (pick(&mut rng), pick(&mut rng));
            if a == b || c == d {
                continue;
            }
            let bx = [a.min(b), c.min(d), a.max(b), c.max(d)];
            let r = Rect::new(Coord { x: bx[0], y: bx[1] }, Coord { x: bx[2], y: bx[3] });
            let want = poly.relate(&r.to_polygon()).is_covers();
            assert_eq!(
                area.contains_box(bx),
                want,
                "trial {trial}: box {bx:?} in {shell:?} with hole {hole:?}"
            );
            if want {
                yes += 1;
            } else {
                no += 1;
            }
        }
    }
    assert!(yes > 300 && no > 300, "{yes} boxes inside, {no} not");
    // a diamond |x| + |y| <= 10: its edges run through the corners of the
    // square of side 10, which it covers; a hair more does not
    let diamond = Area::new(vec![vec![vec![
        [10.0, 0.0],
        [0.0, 10.0],
        [-10.0, 0.0],
        [0.0, -10.0],
    ]]]);
    assert!(diamond.contains_box([-5.0, -5.0, 5.0, 5.0]));
    assert!(!diamond.contains_box([-5.0, -5.0, 5.000001, 5.0]));
    assert!(diamond.contains_box([-1.0, -9.0, 1.0, 9.0]));
    assert!(!diamond.contains_box([-1.0, -9.5, 1.0, 9.5]));
}

/// Damaged sums are an error naming them: a changed byte fails the header
/// hash; sums that cannot be a surface's fail the reader's sense checks
/// even under a valid hash (a crafted value), never an answer.
#[test]
fn damaged_or_crafted_sums_are_errors() {
    let tin = common::dem_tin();
    let sums = level_sums(&tin, &mut no_interrupt).unwrap();
    let good = encode_with_sums(&tin, None, &sums);
    assert_eq!(read_header(&good).unwrap().sums, sums);
    let mut b = good.clone();
    b[SUMS_AT + 3] ^= 0x10;
    let e = read_header(&b).unwrap_err().to_string();
    assert!(e.contains("header hash"), "{e}");
    assert!(decode(&b).is_err());
    let put = |b: &mut Vec<u8>, level: usize, field: usize, v: f64| {
        let at = SUMS_AT + level * 64 + field * 8;
        b[at..at + 8].copy_from_slice(&v.to_le_bytes());
    };
    let cases: Vec<(&str, usize, usize, f64)> = vec![
        ("a NaN integral", 2, 4, f64::NAN),
        ("an infinite area", 0, 0, f64::INFINITY),
        ("a negative area", 4, 0, -1.0),
        (
            "a surface smaller than its plane",
            1,
            1,
            sums[1].area2d / 2.0,
        ),
        ("a height under the bbox", 3, 2, tin.bbox.min_z - 1.0),
        ("min over max", 3, 2, sums[3].max_z + 1.0),
        ("a slope over 90 degrees", 0, 6, 91.0),
    ];
    for (what, level, field, v) in cases {
        let mut b = good.clone();
        put(&mut b, level, field, v);
        reseal(&mut b);
        let e = read_header(&b).unwrap_err().to_string();
        assert!(
            e.contains(&format!("level {level}'s stored sums")),
            "{what}: {e}"
        );
        assert!(decode(&b).is_err(), "{what}");
    }
    assert!(good.len() > HEADER_LEN_V6);
}
