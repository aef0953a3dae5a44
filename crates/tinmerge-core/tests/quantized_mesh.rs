//! Quantized-mesh tiles read back by a decoder written here from the spec
//! (github.com/CesiumGS/quantized-mesh; it shares no code with the
//! encoder), on both bundled DEMs: the geographic tin as it is, the UTM tin
//! through a smooth non-linear map to degrees (standing in for
//! `ST_Transform`, which the pg_regress and loaders.gl tests use).
//!
//! Against oracles: each tile's decoded area equals the area of the
//! level's triangles clipped to the tile by the tests' own clipper (only
//! the hull's quantization may move it); the zoom's tiles add up to the
//! level's area; every decoded vertex's height equals the level's surface
//! there (brute-force point location) within the quantization; the edge
//! vertices of neighbouring tiles coincide; the header's bounds and sphere
//! hold every vertex; normals point up; fill covers the whole tile.
use crate::common;

use std::collections::HashMap;
use tinmerge_core::serve::quantized_mesh::{
    NeedOptions, Source, TileOptions, ecef, encode, needed, split_length,
};
use tinmerge_core::serve::tiling::{
    TileBounds, geometric_error, level_for_zoom, max_zoom, tile_bounds, tile_range,
};
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::{NONE, Tin};

struct Decoded {
    min_h: f64,
    max_h: f64,
    sphere: ([f64; 3], f64),
    u: Vec<u32>,
    v: Vec<u32>,
    h: Vec<u32>,
    tris: Vec<[u32; 3]>,
    edges: [Vec<u32>; 4],
    normals: Option<Vec<[u8; 2]>>,
}

fn decode(b: &[u8]) -> Decoded {
    let f64at = |o: usize| f64::from_le_bytes(b[o..o + 8].try_into().unwrap());
    let f32at = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap()) as f64;
    let u32at = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    let u16at = |o: usize| u16::from_le_bytes(b[o..o + 2].try_into().unwrap()) as u32;
    let min_h = f32at(24);
    let max_h = f32at(28);
    let sphere = ([f64at(32), f64at(40), f64at(48)], f64at(56));
    let n = u32at(88) as usize;
    let mut pos = 92;
    let mut arrays = [vec![0u32; n], vec![0u32; n], vec![0u32; n]];
    for arr in arrays.iter_mut() {
        let mut acc: i64 = 0;
        for slot in arr.iter_mut() {
            let zz = u16at(pos) as i64;
            pos += 2;
            acc += (zz >> 1) ^ -(zz & 1);
            assert!(
                (0..=32767).contains(&acc),
                "quantized value {acc} out of range"
            );
            *slot = acc as u32;
        }
    }
    let wide = n > 65536;
    if wide && pos % 4 != 0 {
        pos += 4 - pos % 4;
    }
    let idx = |pos: &mut usize| {
        let v = if wide { u32at(*pos) } else { u16at(*pos) };
        *pos += if wide { 4 } else { 2 };
        v
    };
    let nt = u32at(pos) as usize;
    pos += 4;
    let mut highest = 0u32;
    let mut flat = Vec::with_capacity(nt * 3);
    for _ in 0..nt * 3 {
        let code = idx(&mut pos);
        assert!(code <= highest, "high-water mark broken");
        flat.push(highest - code);
        if code == 0 {
            highest += 1;
        }
    }
    assert_eq!(highest as usize, n, "every vertex is used");
    let tris = flat.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut edges: [Vec<u32>; 4] = Default::default();
    for e in edges.iter_mut() {
        let c = u32at(pos) as usize;
        pos += 4;
        for _ in 0..c {
            e.push(idx(&mut pos));
        }
    }
    let mut normals = None;
    while pos < b.len() {
        let id = b[pos];
        let len = u32at(pos + 1) as usize;
        pos += 5;
        if id == 1 {
            assert_eq!(len, 2 * n);
            normals = Some(b[pos..pos + len].chunks(2).map(|c| [c[0], c[1]]).collect());
        }
        pos += len;
    }
    assert_eq!(pos, b.len(), "trailing bytes");
    let [u, v, h] = arrays;
    Decoded {
        min_h,
        max_h,
        sphere,
        u,
        v,
        h,
        tris,
        edges,
        normals,
    }
}

impl Decoded {
    fn lonlat(&self, t: &TileBounds, i: usize) -> [f64; 3] {
        [
            t.west + self.u[i] as f64 / 32767.0 * (t.east - t.west),
            t.south + self.v[i] as f64 / 32767.0 * (t.north - t.south),
            self.min_h + self.h[i] as f64 / 32767.0 * (self.max_h - self.min_h),
        ]
    }
    fn area(&self, t: &TileBounds) -> f64 {
        self.tris
            .iter()
            .map(|tr| {
                let [a, b, c] = tr.map(|i| self.lonlat(t, i as usize));
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
            })
            .sum()
    }
}

fn area2(p: &[[f64; 2]]) -> f64 {
    let mut s = 0.0;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    s / 2.0
}

fn clip_rect(poly: Vec<[f64; 2]>, t: &TileBounds) -> Vec<[f64; 2]> {
    let (w, s, e, n) = (t.west, t.south, t.east, t.north);
    let mut p = poly;
    for (a, b) in [
        ([w, s], [e, s]),
        ([e, s], [e, n]),
        ([e, n], [w, n]),
        ([w, n], [w, s]),
    ] {
        if p.is_empty() {
            break;
        }
        p = common::clip_half(&p, a, b);
    }
    p
}

/// The area of the triangles clipped to the tile by the tests' clipper.
fn clipped_area(tris: &[[[f64; 3]; 3]], tb: &TileBounds) -> f64 {
    tris.iter()
        .map(|t| {
            let p = clip_rect(t.iter().map(|p| [p[0], p[1]]).collect(), tb);
            if p.len() < 3 { 0.0 } else { area2(&p) }
        })
        .sum()
}

struct Case {
    name: &'static str,
    tin: Tin,
    /// the tin's coordinates to degrees
    map: fn(f64, f64) -> [f64; 2],
}

fn cases() -> Vec<Case> {
    let geo_tin = common::geo_tin(2.0);
    fn identity(x: f64, y: f64) -> [f64; 2] {
        [x, y]
    }
    fn utm_like(x: f64, y: f64) -> [f64; 2] {
        let (dx, dy) = (x - 740_000.0, y - 4_070_000.0);
        [
            -84.4 + dx / 89_000.0 + dy * dy * 1e-15,
            36.5 + dy / 111_000.0 + dx * dy * 2e-16,
        ]
    }
    vec![
        Case {
            name: "geographic",
            tin: geo_tin,
            map: identity,
        },
        Case {
            name: "utm (mapped)",
            tin: common::dem_tin(),
            map: utm_like,
        },
        // over the data alone: void triangles around the domain and in a hole
        Case {
            name: "geographic data",
            tin: common::data_tin("jacksboro_fault_dem.tif", 4326, 2.0),
            map: identity,
        },
        Case {
            name: "utm data (mapped)",
            tin: common::data_tin("jacksboro_fault_dem_utm16n.tif", 32616, 2.0),
            map: utm_like,
        },
    ]
}

/// The level's domain triangles in degrees (with heights).
fn image(c: &Case, level: usize) -> Vec<[[f64; 3]; 3]> {
    (0..c.tin.levels[level].num_domain() as u32)
        .map(|t| {
            c.tin.corners(level, t).map(|p| {
                let g = (c.map)(p[0], p[1]);
                [g[0], g[1], p[2]]
            })
        })
        .collect()
}

/// Height of the image surface at (x, y) by brute force: a triangle
/// holding the point (barycentric weights within rounding).
fn oracle_height(tris: &[[[f64; 3]; 3]], x: f64, y: f64) -> Option<f64> {
    for c in tris {
        let d =
            (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
        let wb = ((x - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (y - c[0][1])) / d;
        let wc = ((c[1][0] - c[0][0]) * (y - c[0][1]) - (x - c[0][0]) * (c[1][1] - c[0][1])) / d;
        let wa = 1.0 - wb - wc;
        let eps = -1e-9;
        if wa >= eps && wb >= eps && wc >= eps {
            return Some(wa * c[0][2] + wb * c[1][2] + wc * c[2][2]);
        }
    }
    None
}

fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}

fn max_gradient(tris: &[[[f64; 3]; 3]]) -> f64 {
    tris.iter()
        .map(|c| {
            let (ax, ay, az) = (c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]);
            let (bx, by, bz) = (c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]);
            let d = ax * by - bx * ay;
            let gx = (az * by - bz * ay) / d;
            let gy = (ax * bz - bx * az) / d;
            (gx * gx + gy * gy).sqrt()
        })
        .fold(0.0, f64::max)
}

/// The longest straight edge for the case's map, from the bulge of the
/// terrain's diagonal (as the SQL layer measures it through ST_Transform).
fn max_len(c: &Case) -> Option<f64> {
    let b = &c.tin.bbox;
    let p = (c.map)(b.min_x, b.min_y);
    let q = (c.map)(b.max_x, b.max_y);
    let m = (c.map)((b.min_x + b.max_x) / 2.0, (b.min_y + b.max_y) / 2.0);
    let sag = ((p[0] + q[0]) / 2.0 - m[0]).hypot((p[1] + q[1]) / 2.0 - m[1]);
    split_length((b.max_x - b.min_x).hypot(b.max_y - b.min_y), sag)
}

fn tile(
    c: &Case,
    level: usize,
    tb: &TileBounds,
    normals: bool,
    fill: Option<f64>,
) -> Option<Vec<u8>> {
    tile_in(c, level, tb, normals, fill, None)
}

/// [`tile`] with the triangles picked from a footprint in the tin's frame.
fn tile_in(
    c: &Case,
    level: usize,
    tb: &TileBounds,
    normals: bool,
    fill: Option<f64>,
    footprint: Option<[f64; 4]>,
) -> Option<Vec<u8>> {
    let opts = TileOptions { normals, fill };
    let need = needed(&c.tin, level, footprint, opts.need(max_len(c)), &mut || {
        Ok(())
    })
    .unwrap();
    let geo: Vec<[f64; 2]> = need.points().iter().map(|p| (c.map)(p[0], p[1])).collect();
    let src = Source {
        need: &need,
        geo: &geo,
    };
    encode(src, tb, opts, &mut || Ok(())).unwrap()
}

fn bounds(tris: &[[[f64; 3]; 3]]) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for c in tris {
        for p in c {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
    }
    b
}

#[test]
fn tiles_cover_the_level_and_hold_its_heights() {
    for c in cases() {
        let errors: Vec<f64> = c
            .tin
            .levels
            .iter()
            .map(|l| l.tolerance.max(l.max_error))
            .collect();
        let top = max_zoom(&errors, 0);
        // every zoom from the root tiles to a few dozen tiles over the terrain
        for z in 0..=12 {
            let level = level_for_zoom(&errors, z);
            let tris = image(&c, level);
            let b = bounds(&tris);
            let hull: Vec<[[f64; 2]; 2]> = {
                let lv = &c.tin.levels[level];
                let mut h = Vec::new();
                // the domain's boundary: hull edges and edges to void triangles
                for (t, nb) in lv.nbrs.iter().enumerate().take(lv.num_domain()) {
                    for j in 0..3 {
                        if nb[j] == NONE || nb[j] as usize >= lv.num_domain() {
                            let p = tris[t][(j + 1) % 3];
                            let q = tris[t][(j + 2) % 3];
                            h.push([[p[0], p[1]], [q[0], q[1]]]);
                        }
                    }
                }
                h
            };
            let grad = max_gradient(&tris);
            let (x0, y0, x1, y1) = tile_range(z, &b);
            let level_area: f64 = tris.iter().map(|t| area2(&t.map(|p| [p[0], p[1]]))).sum();
            let mut total = 0.0;
            let mut total_tol = 0.0;
            let mut tiles = std::collections::HashMap::new();
            let mut checked = 0;
            for x in x0..=x1 {
                for y in y0..=y1 {
                    let tb = tile_bounds(z, x as i32, y as i32).unwrap();
                    let oracle: f64 = clipped_area(&tris, &tb);
                    let bytes = tile(&c, level, &tb, false, None);
                    if c.name == "geographic" {
                        // picking the triangles by the tile's own rectangle (the
                        // sweep) gives the same tile as taking them all
                        let f = [tb.west, tb.south, tb.east, tb.north];
                        assert_eq!(
                            tile_in(&c, level, &tb, true, Some(0.0), Some(f)),
                            tile(&c, level, &tb, true, Some(0.0)),
                            "{} z{z} {x}/{y}: footprint",
                            c.name
                        );
                    }
                    let Some(bytes) = bytes else {
                        assert!(
                            oracle < 1e-15,
                            "{} z{z} {x}/{y}: no tile but {oracle} deg² of terrain",
                            c.name
                        );
                        continue;
                    };
                    let d = decode(&bytes);
                    let area = d.area(&tb);
                    let ustep = (tb.east - tb.west) / 32767.0;
                    let hull_in: f64 = hull
                        .iter()
                        .map(|e| {
                            let p = clip_rect(vec![e[0], e[1], e[1]], &tb);
                            if p.len() < 2 {
                                0.0
                            } else {
                                ((p[0][0] - p[1][0]).powi(2) + (p[0][1] - p[1][1]).powi(2)).sqrt()
                                    * 2.0
                            }
                        })
                        .sum();
                    let tol = ustep * hull_in + 1e-12 * (tb.east - tb.west).powi(2);
                    assert!(
                        (area - oracle).abs() <= tol,
                        "{} z{z} {x}/{y}: decoded area {area}, clipped triangles {oracle}, tolerance {tol}",
                        c.name
                    );
                    total += area;
                    total_tol += tol;
                    // heights at (a sample of) the decoded vertices
                    let hstep = (d.max_h - d.min_h) / 32767.0;
                    let n = d.u.len();
                    for i in (0..n).step_by((n / 60).max(1)) {
                        let p = d.lonlat(&tb, i);
                        let h = oracle_height(&tris, p[0], p[1]);
                        let tol = hstep + grad * 2.0 * ustep + 1e-6;
                        match h {
                            Some(h) => assert!(
                                (h - p[2]).abs() <= tol,
                                "{} z{z} {x}/{y} vertex {i}: {} against {h} (tolerance {tol})",
                                c.name,
                                p[2]
                            ),
                            // a hull vertex quantized outwards: just off the terrain
                            None => {
                                let near = hull
                                    .iter()
                                    .any(|e| seg_dist([p[0], p[1]], e[0], e[1]) <= 2.0 * ustep);
                                assert!(
                                    near,
                                    "{} z{z} {x}/{y} vertex {i} at {p:?} is off the terrain, not by quantization on its edge",
                                    c.name
                                );
                            }
                        }
                        checked += 1;
                    }
                    // header: heights and sphere hold every vertex
                    for i in 0..n {
                        let p = d.lonlat(&tb, i);
                        let e = ecef(p[0], p[1], p[2]);
                        let r = ((e[0] - d.sphere.0[0]).powi(2)
                            + (e[1] - d.sphere.0[1]).powi(2)
                            + (e[2] - d.sphere.0[2]).powi(2))
                        .sqrt();
                        assert!(
                            r <= d.sphere.1 * (1.0 + 1e-9) + 1.0,
                            "{} z{z}: vertex outside the bounding sphere",
                            c.name
                        );
                    }
                    tiles.insert((x, y), (tb, d));
                }
            }
            assert!(
                (total - level_area).abs() <= total_tol,
                "{} z{z}: tiles add up to {total} deg², the level has {level_area} (tolerance {total_tol})",
                c.name
            );
            // neighbouring tiles' edge vertices coincide
            let mut shared = 0;
            for (&(x, y), (tb, d)) in &tiles {
                for (dx, dy, mine, theirs) in [(1, 0, 2usize, 0usize), (0, 1, 3, 1)] {
                    let Some((tb2, d2)) = tiles.get(&(x + dx, y + dy)) else {
                        continue;
                    };
                    let key = |d: &Decoded, tb: &TileBounds, side: usize| -> Vec<(u32, f64)> {
                        let mut k: Vec<(u32, f64)> = d.edges[side]
                            .iter()
                            .map(|&i| {
                                let along = if side.is_multiple_of(2) {
                                    d.v[i as usize]
                                } else {
                                    d.u[i as usize]
                                };
                                (along, d.lonlat(tb, i as usize)[2])
                            })
                            .collect();
                        k.sort_by(|a, b| a.partial_cmp(b).unwrap());
                        k
                    };
                    let a = key(d, tb, mine);
                    let b2 = key(d2, tb2, theirs);
                    let pa: Vec<u32> = a.iter().map(|k| k.0).collect();
                    let pb: Vec<u32> = b2.iter().map(|k| k.0).collect();
                    let mut ua = pa.clone();
                    ua.dedup();
                    let mut ub = pb.clone();
                    ub.dedup();
                    assert_eq!(
                        ua, ub,
                        "{} z{z}: edge vertices of {x}/{y} and its neighbour differ",
                        c.name
                    );
                    let hs = (d.max_h - d.min_h) / 32767.0 + (d2.max_h - d2.min_h) / 32767.0;
                    for (ka, kb) in a.iter().zip(&b2) {
                        if ka.0 == kb.0 {
                            assert!(
                                (ka.1 - kb.1).abs() <= hs + 1e-6,
                                "{} z{z}: heights on a shared side differ",
                                c.name
                            );
                        }
                    }
                    shared += pa.len();
                }
            }
            println!(
                "{} z{z} (level {level}, top {top}, error {:.1} m): {} tiles, {checked} heights, {shared} shared edge vertices",
                c.name,
                geometric_error(z),
                tiles.len()
            );
            assert!(tiles.len() > 1 || z <= 9);
        }
    }
}

/// WGS84 geodetic (degrees, metres) to ECEF (metres): the test's own.
fn ecef_wgs84(p: [f64; 3]) -> [f64; 3] {
    let (a, f) = (6_378_137.0, 1.0 / 298.257_223_563);
    let e2 = f * (2.0 - f);
    let (lo, la) = (p[0].to_radians(), p[1].to_radians());
    let n = a / (1.0 - e2 * la.sin() * la.sin()).sqrt();
    [
        (n + p[2]) * la.cos() * lo.cos(),
        (n + p[2]) * la.cos() * lo.sin(),
        (n * (1.0 - e2) + p[2]) * la.sin(),
    ]
}

/// Cesium's octDecode of an oct-encoded 8-bit normal, unit length.
fn oct_decode(n: [u8; 2]) -> [f64; 3] {
    let mut x = n[0] as f64 / 255.0 * 2.0 - 1.0;
    let mut y = n[1] as f64 / 255.0 * 2.0 - 1.0;
    let zc = 1.0 - x.abs() - y.abs();
    if zc < 0.0 {
        let ox = x;
        x = (1.0 - y.abs()) * ox.signum();
        y = (1.0 - ox.abs()) * y.signum();
    }
    let l = (x * x + y * y + zc * zc).sqrt();
    [x / l, y / l, zc / l]
}

/// Cesium's octEncode (toSNorm: rounded to the nearest of 256 steps) of a
/// vector, the test's own.
fn oct_encode(v: [f64; 3]) -> [u8; 2] {
    let l1 = v[0].abs() + v[1].abs() + v[2].abs();
    let (mut x, mut y) = (v[0] / l1, v[1] / l1);
    if v[2] < 0.0 {
        let ox = x;
        x = (1.0 - y.abs()) * if ox >= 0.0 { 1.0 } else { -1.0 };
        y = (1.0 - ox.abs()) * if y >= 0.0 { 1.0 } else { -1.0 };
    }
    let snorm = |t: f64| ((t.clamp(-1.0, 1.0) * 0.5 + 0.5) * 255.0).round() as u8;
    [snorm(x), snorm(y)]
}

/// The oracle's vertex normals: for every vertex of the level's image
/// (degrees), the sum of the ECEF cross products of the domain triangles
/// around it (each twice its area times its unit normal: an area-weighted
/// sum), by (lon, lat) bits.
fn oracle_normals(tris: &[[[f64; 3]; 3]]) -> HashMap<(u64, u64), [f64; 3]> {
    let mut out: HashMap<(u64, u64), [f64; 3]> = HashMap::new();
    for t in tris {
        let [a, b, c] = t.map(ecef_wgs84);
        let (u, v) = (
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        );
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        for p in t {
            let e = out.entry((p[0].to_bits(), p[1].to_bits())).or_default();
            for k in 0..3 {
                e[k] += n[k];
            }
        }
    }
    out
}

/// The served vertex normals against [`oracle_normals`] at the vertices
/// that are the level's own (a decoded vertex within half a quantization
/// step of exactly one image vertex, away from the tile's sides, whose
/// clip points take the normal of the triangle they lie in). The bound:
/// the served code is the oracle's own 8-bit octahedral code, or a
/// neighbour of it (one step in either byte: the two sums can round
/// differently near a step's middle); the angle is reported.
#[test]
fn normals_are_the_area_weighted_ecef_normals_of_the_level() {
    for c in cases() {
        let level = c.tin.levels.len() - 2;
        let tris = image(&c, level);
        let want = oracle_normals(&tris);
        // image vertices by a grid of cells 1e-3 degree across
        let mut cells: HashMap<(i64, i64), Vec<[f64; 2]>> = HashMap::new();
        for t in &tris {
            for p in t {
                let k = ((p[0] * 1e3).floor() as i64, (p[1] * 1e3).floor() as i64);
                let v = cells.entry(k).or_default();
                if !v.contains(&[p[0], p[1]]) {
                    v.push([p[0], p[1]]);
                }
            }
        }
        let b = bounds(&tris);
        let (mut checked, mut worst) = (0usize, 0.0f64);
        for z in [10, 12] {
            let (x0, y0, x1, y1) = tile_range(z, &b);
            for (x, y) in [(x0, y0), ((x0 + x1) / 2, (y0 + y1) / 2), (x1, y1)] {
                let tb = tile_bounds(z, x as i32, y as i32).unwrap();
                let Some(bytes) = tile(&c, level, &tb, true, None) else {
                    continue;
                };
                let d = decode(&bytes);
                let normals = d.normals.as_ref().unwrap();
                let step = (tb.east - tb.west) / 32767.0;
                for (i, n) in normals.iter().enumerate() {
                    if d.u[i] == 0 || d.u[i] == 32767 || d.v[i] == 0 || d.v[i] == 32767 {
                        continue;
                    }
                    let p = d.lonlat(&tb, i);
                    let k = ((p[0] * 1e3).floor() as i64, (p[1] * 1e3).floor() as i64);
                    let near: Vec<[f64; 2]> = (-1..=1)
                        .flat_map(|dx| (-1..=1).map(move |dy| (k.0 + dx, k.1 + dy)))
                        .filter_map(|k| cells.get(&k))
                        .flatten()
                        .filter(|q| {
                            (q[0] - p[0]).abs() <= 0.5 * step && (q[1] - p[1]).abs() <= 0.5 * step
                        })
                        .copied()
                        .collect();
                    let [q] = near.as_slice() else {
                        continue;
                    };
                    let w = want[&(q[0].to_bits(), q[1].to_bits())];
                    let l = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                    let got = oct_decode(*n);
                    let cos = (got[0] * w[0] + got[1] * w[1] + got[2] * w[2]) / l;
                    let angle = cos.clamp(-1.0, 1.0).acos().to_degrees();
                    let code = oct_encode(w);
                    assert!(
                        (0..2).all(|k| n[k].abs_diff(code[k]) <= 1),
                        "{} z{z} {x}/{y}: normal of vertex {i} at {p:?} is {n:?}, the oracle's {code:?} ({angle:.2} degrees off)",
                        c.name
                    );
                    assert!(
                        angle <= 2.0,
                        "{} z{z} {x}/{y}: normal of vertex {i} at {p:?} is {angle:.2} degrees off",
                        c.name
                    );
                    worst = worst.max(angle);
                    checked += 1;
                }
            }
        }
        eprintln!("{}: {checked} normals, worst {worst:.3} degrees", c.name);
        assert!(checked > 100, "{}: only {checked} normals checked", c.name);
    }
}

#[test]
fn fill_covers_the_tile_and_normals_point_up() {
    for c in cases() {
        let level = c.tin.levels.len() - 2;
        let tris = image(&c, level);
        let b = bounds(&tris);
        for z in [6, 10, 12] {
            let (x0, y0, x1, y1) = tile_range(z, &b);
            for (x, y) in [(x0, y0), (x1, y1), (x0 - 1, y0)] {
                let tb = tile_bounds(z, x as i32, y as i32).unwrap();
                let bytes = tile(&c, level, &tb, true, Some(0.0)).unwrap();
                let d = decode(&bytes);
                let full = (tb.east - tb.west) * (tb.north - tb.south);
                let area = d.area(&tb);
                assert!(
                    (area - full).abs() <= 1e-9 * full,
                    "{} z{z} {x}/{y}: fill covers {area} of {full}",
                    c.name
                );
                // the terrain part is still there, the same as without fill
                if let Some(t) = tile(&c, level, &tb, false, None) {
                    let d0 = decode(&t);
                    assert!(d0.tris.len() < d.tris.len());
                }
                let normals = d.normals.as_ref().unwrap();
                let mut steep = 0;
                for (i, n) in normals.iter().enumerate() {
                    let nv = oct_decode(*n);
                    let p = d.lonlat(&tb, i);
                    let (lo, la) = (p[0].to_radians(), p[1].to_radians());
                    let up = [la.cos() * lo.cos(), la.cos() * lo.sin(), la.sin()];
                    let cosang = nv[0] * up[0] + nv[1] * up[1] + nv[2] * up[2];
                    // never below the horizon (within the 8-bit encoding);
                    // steep only where the surface is: the UTM DEM's hull
                    // spans its nodata corners with long thin triangles
                    // whose slopes reach 86 degrees
                    assert!(
                        cosang > -0.02,
                        "{} z{z}: normal of vertex {i} at {p:?} is {:.0} degrees from up ({n:?})",
                        c.name,
                        cosang.acos().to_degrees()
                    );
                    steep += usize::from(cosang < 0.5);
                }
                assert!(
                    steep * 10 <= normals.len(),
                    "{} z{z}: {steep} of {} normals more than 60 degrees from up",
                    c.name,
                    normals.len()
                );
            }
        }
    }
}

#[test]
fn tile_addresses_are_checked() {
    assert!(tile_bounds(0, 2, 0).is_err());
    assert!(tile_bounds(3, 0, 8).is_err());
    assert!(tile_bounds(-1, 0, 0).is_err());
    assert!(tile_bounds(25, 0, 0).is_err());
    let b = tile_bounds(0, 0, 0).unwrap();
    assert_eq!(
        [b.west, b.south, b.east, b.north],
        [-180.0, -90.0, 0.0, 90.0]
    );
}

/// A vertex inside a tile within half a quantization step of its west
/// side quantizes onto that side, but it is not on the side: the west list
/// of that tile and the east list of its neighbour must still be the same
/// (on the UTM DEM served through PostGIS a split point 0.3 steps inside
/// made them differ by one: 30 against 29).
#[test]
fn a_vertex_near_a_side_is_not_an_edge_vertex() {
    let (a, b) = (
        tile_bounds(12, 1130, 1420).unwrap(),
        tile_bounds(12, 1131, 1420).unwrap(),
    );
    assert_eq!(a.east, b.west);
    let step = (b.east - b.west) / 32767.0;
    let (s, n) = (a.south, a.north);
    // a grid over both tiles, and one point just east of the shared side
    let mut pts = Vec::new();
    for i in 0..=6 {
        for j in 0..=6 {
            let x = a.west + (b.east - a.west) * (i as f64 + 0.3) / 6.5;
            let y = s + (n - s) * (j as f64 + 0.2) / 6.5;
            pts.push([x, y, 100.0 + 7.0 * i as f64 + 3.0 * ((i * j) % 5) as f64]);
        }
    }
    // two points 0.3 steps either side of it, 4 steps apart along it: the
    // edge between them crosses the side 2 steps from either
    let mid = s + 0.5 * (n - s);
    pts.push([b.west + 0.3 * step, mid, 180.0]);
    pts.push([b.west - 0.3 * step, mid + 4.0 * (n - s) / 32767.0, 181.0]);
    let tin = build(pts, &[0.0], 4326, &mut || Ok(())).unwrap();
    let c = Case {
        name: "near a side",
        tin,
        map: |x, y| [x, y],
    };
    let (da, db) = (
        decode(&tile(&c, 0, &a, false, None).unwrap()),
        decode(&tile(&c, 0, &b, false, None).unwrap()),
    );
    // each near point is in its tile's mesh, on the side once quantized
    let qv = |y: f64| ((y - s) / (n - s) * 32767.0).round() as u32;
    let (vp, vq) = (qv(mid), qv(mid + 4.0 * (n - s) / 32767.0));
    assert!((0..db.u.len()).any(|i| db.u[i] == 0 && db.v[i] == vp));
    assert!((0..da.u.len()).any(|i| da.u[i] == 32767 && da.v[i] == vq));
    let along = |d: &Decoded, side: usize| -> Vec<u32> {
        let mut v: Vec<u32> = d.edges[side].iter().map(|&i| d.v[i as usize]).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    assert_eq!(along(&da, 2), along(&db, 0));
}

/// A terrain stored as tiles (`build_tiles`: tins sharing their seams) cut
/// into quantized-mesh tiles from all of them at once: each tile's area is
/// that of every tin's triangles clipped by the tests' own clipper, heights
/// are the tiled surface's (brute force over every tin), vertices on the
/// seams are one vertex, and with fill the walls stand only on the
/// terrain's outer edge, never along a seam.
#[test]
fn tiled_terrain_is_one_mesh() {
    use tinmerge_core::serve::quantized_mesh::encode_many;
    let d = common::read_dem("jacksboro_fault_dem.tif");
    let tols = default_tolerances(2.0, 3).unwrap();
    let tins: Vec<Tin> = common::tiles_of(&d, 150, &tols, 4326)
        .into_iter()
        .map(|(_, _, t)| t)
        .collect();
    assert!(tins.len() >= 4);
    let whole = build(d.samples(), &tols, 4326, &mut || Ok(())).unwrap();
    for level in [0, 2] {
        let tris: Vec<[[f64; 3]; 3]> = tins
            .iter()
            .flat_map(|t| (0..t.levels[level].tris.len() as u32).map(move |i| t.corners(level, i)))
            .collect();
        let b = bounds(&tris);
        // the outer edge: the hull of every sample (the tins' union is convex)
        let outer: Vec<[[f64; 2]; 2]> = {
            let lv = &whole.levels[0];
            let mut h = Vec::new();
            for (t, nb) in lv.nbrs.iter().enumerate() {
                for j in 0..3 {
                    if nb[j] == NONE {
                        let tri = lv.tris[t];
                        let (p, q) = (
                            whole.verts[tri[(j + 1) % 3] as usize],
                            whole.verts[tri[(j + 2) % 3] as usize],
                        );
                        h.push([[p[0], p[1]], [q[0], q[1]]]);
                    }
                }
            }
            h
        };
        for z in [9, 11, 12] {
            let (x0, y0, x1, y1) = tile_range(z, &b);
            let mut seam_shared = 0;
            for x in x0..=x1 {
                for y in y0..=y1 {
                    let tb = tile_bounds(z, x as i32, y as i32).unwrap();
                    let needs: Vec<_> = tins
                        .iter()
                        .map(|t| {
                            needed(
                                t,
                                level,
                                None,
                                NeedOptions {
                                    normals: true,
                                    fill: true,
                                    max_len: None,
                                },
                                &mut || Ok(()),
                            )
                            .unwrap()
                        })
                        .collect();
                    let geos: Vec<Vec<[f64; 2]>> = needs.iter().map(|n| n.points()).collect();
                    let srcs: Vec<Source> = needs
                        .iter()
                        .zip(&geos)
                        .map(|(n, g)| Source { need: n, geo: g })
                        .collect();
                    let oracle: f64 = clipped_area(&tris, &tb);
                    let Some(bytes) = encode_many(
                        &srcs,
                        &tb,
                        TileOptions {
                            normals: true,
                            fill: None,
                        },
                        &mut || Ok(()),
                    )
                    .unwrap() else {
                        assert!(oracle < 1e-15);
                        continue;
                    };
                    let dq = decode(&bytes);
                    let ustep = (tb.east - tb.west) / 32767.0;
                    let tol = ustep * 2.0 * (tb.east - tb.west) * 4.0 + 1e-12;
                    assert!(
                        (dq.area(&tb) - oracle).abs() <= tol,
                        "level {level} z{z} {x}/{y}: {} against {oracle}",
                        dq.area(&tb)
                    );
                    // seam vertices are one vertex: no two vertices at one position
                    let mut pos: Vec<(u32, u32)> =
                        (0..dq.u.len()).map(|i| (dq.u[i], dq.v[i])).collect();
                    let n = pos.len();
                    pos.sort_unstable();
                    pos.dedup();
                    seam_shared += n - pos.len();
                    let hstep = (dq.max_h - dq.min_h) / 32767.0;
                    let grad = max_gradient(&tris);
                    for i in (0..dq.u.len()).step_by((dq.u.len() / 40).max(1)) {
                        let p = dq.lonlat(&tb, i);
                        if let Some(h) = oracle_height(&tris, p[0], p[1]) {
                            assert!(
                                (h - p[2]).abs() <= hstep + grad * 2.0 * ustep + 1e-6,
                                "level {level} z{z}: height {} against {h}",
                                p[2]
                            );
                        }
                    }
                    // with fill: walls (triangles without area) only on the outer edge
                    let filled = decode(
                        &encode_many(
                            &srcs,
                            &tb,
                            TileOptions {
                                normals: false,
                                fill: Some(0.0),
                            },
                            &mut || Ok(()),
                        )
                        .unwrap()
                        .unwrap(),
                    );
                    let full = (tb.east - tb.west) * (tb.north - tb.south);
                    assert!((filled.area(&tb) - full).abs() <= 1e-9 * full);
                    for tr in &filled.tris {
                        let [a, bb, c] = tr.map(|i| filled.lonlat(&tb, i as usize));
                        let ar = (bb[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (bb[1] - a[1]);
                        // a wall: no area, down to the fill (the terrain is
                        // hundreds of metres above it)
                        let flat = a[2] == bb[2] && bb[2] == c[2];
                        let down = [a, bb, c].iter().any(|p| p[2] == 0.0);
                        if ar == 0.0 && !flat && down {
                            for p in [a, bb, c] {
                                let dist = outer
                                    .iter()
                                    .map(|e| seg_dist([p[0], p[1]], e[0], e[1]))
                                    .fold(f64::INFINITY, f64::min);
                                assert!(
                                    dist <= 2.0 * ustep,
                                    "level {level} z{z} {x}/{y}: a wall at {p:?}, {dist} deg from the terrain's edge"
                                );
                            }
                        }
                    }
                }
            }
            println!(
                "tiled level {level} z{z}: {} duplicate positions (distinct vertices only by height)",
                seam_shared
            );
        }
    }
}

/// `pyramid_zooms` against its rule checked zoom by zoom (brute force):
/// zoom `z` is served by the coarsest layer, among those coarser than the
/// one below them, whose pixels are at most `180 / 2^z / 64` degrees, or
/// by the finest when none is; every zoom by exactly one layer.
#[test]
fn pyramid_zooms_serve_each_zoom_from_the_coarsest_fine_enough_layer() {
    use rand::{Rng, SeedableRng};
    use tinmerge_core::serve::tiling::{MAX_ZOOM, pyramid_zooms};
    let mut rng = rand::rngs::StdRng::seed_from_u64(48);
    let mut served_by_overview = 0;
    for case in 0..2000 {
        let n = rng.random_range(1..6);
        // pixel sizes from 1e-9 to 0.1 degrees, coarser layers after,
        // some repeating the one below
        let mut p = vec![10f64.powf(rng.random_range(-9.0..-1.0))];
        for _ in 1..n {
            let last = *p.last().unwrap();
            p.push(if rng.random_bool(0.15) {
                last
            } else {
                last * rng.random_range(1.01..20.0)
            });
        }
        let got = pyramid_zooms(&p);
        assert_eq!(got.len(), n);
        for z in 0..=MAX_ZOOM {
            let spacing = 180.0 / 2f64.powi(z) / 64.0;
            let want = (1..n)
                .rev()
                .find(|&i| p[i] > p[i - 1] && p[i] <= spacing)
                .unwrap_or(0);
            let serving: Vec<usize> = (0..n)
                .filter(|&i| got[i].is_some_and(|(lo, hi)| (lo..=hi).contains(&z)))
                .collect();
            assert_eq!(serving, [want], "case {case}: zoom {z}: {p:?} -> {got:?}");
            served_by_overview += usize::from(want > 0);
        }
    }
    assert!(
        served_by_overview > 1000,
        "overviews served only {served_by_overview} zooms"
    );
}
