//! The tile's bytes: header, quantized vertices, indices, edge lists and
//! the normals extension.

use rustc_hash::FxHashMap;

use super::clip::{Kind, Source, Tile};
use super::mesh::{A, B, TileMesh, cross, dot, ecef, norm, sub, tile_mesh, tiles_of};
use super::needed::NeedOptions;
use super::water::{WaterPolygon, water_mask};
use crate::interrupt::Interrupt;
use crate::serve::tiling::TileBounds;
use crate::tin::TinError;

/// The largest quantized coordinate.
const QMAX: f64 = 32767.0;

fn zigzag(v: i32) -> u16 {
    ((v << 1) ^ (v >> 31)) as u16
}

/// Cesium's horizon occlusion point (ellipsoid-scaled space) for points
/// seen in direction `dir` (ECEF), or NaNs when there is none.
fn horizon_point(dir: [f64; 3], points: &[[f64; 3]]) -> [f64; 3] {
    let scale = |p: [f64; 3]| [p[0] / A, p[1] / A, p[2] / B];
    let d = scale(dir);
    let dn = norm(d);
    let nan = [f64::NAN; 3];
    if dn == 0.0 {
        return nan;
    }
    let d = [d[0] / dn, d[1] / dn, d[2] / dn];
    let mut best = 0.0f64;
    for &p in points {
        let s = scale(p);
        let m2 = dot(s, s);
        let m = m2.sqrt();
        let dirp = [s[0] / m, s[1] / m, s[2] / m];
        let (m2, m) = (m2.max(1.0), m.max(1.0));
        let cos_a = dot(dirp, d);
        let sin_a = norm(cross(dirp, d));
        let cos_b = 1.0 / m;
        let sin_b = (m2 - 1.0).sqrt() * cos_b;
        let mag = 1.0 / (cos_a * cos_b - sin_a * sin_b);
        if mag < 0.0 {
            return nan;
        }
        best = best.max(mag);
    }
    if best <= 0.0 || !best.is_finite() {
        return nan;
    }
    [d[0] * best, d[1] * best, d[2] * best]
}

/// Cesium's oct encoding of a unit vector in two bytes.
fn oct_encode(n: [f64; 3]) -> [u8; 2] {
    let l = n[0].abs() + n[1].abs() + n[2].abs();
    if l == 0.0 || !l.is_finite() {
        return [128, 128];
    }
    let (mut x, mut y) = (n[0] / l, n[1] / l);
    if n[2] < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * if ox < 0.0 { -1.0 } else { 1.0 };
        y = (1.0 - ox.abs()) * if oy < 0.0 { -1.0 } else { 1.0 };
    }
    let snorm = |v: f64| ((v.clamp(-1.0, 1.0) * 0.5 + 0.5) * 255.0).round() as u8;
    [snorm(x), snorm(y)]
}

/// Vertex normals (ECEF, unnormalised sums) of the mesh's points, from the
/// level's triangles around each (see the module docs).
fn normals(cxs: &[Tile], mesh: &TileMesh) -> Result<Vec<[f64; 3]>, TinError> {
    // per source: the ECEF normal of each triangle around the tile's
    // vertices, and the triangles around each vertex
    struct Around {
        face: FxHashMap<u32, [f64; 3]>,
        around: FxHashMap<u32, Vec<u32>>,
    }
    let tri_normal = |cx: &Tile, t: u32| -> Result<[f64; 3], TinError> {
        let tri = cx.need.tri(t)?;
        let p = [cx.vertex(tri[0])?, cx.vertex(tri[1])?, cx.vertex(tri[2])?]
            .map(|p| ecef(p.x, p.y, p.h));
        Ok(cross(sub(p[1], p[0]), sub(p[2], p[0])))
    };
    let mut per: Vec<Around> = Vec::with_capacity(cxs.len());
    for cx in cxs {
        let mut a = Around {
            face: FxHashMap::default(),
            around: FxHashMap::default(),
        };
        for &t in &cx.need.ring {
            a.face.insert(t, tri_normal(cx, t)?);
            for v in cx.need.tri(t)? {
                a.around.entry(v).or_default().push(t);
            }
        }
        per.push(a);
    }
    // the level's triangles a vertex or split point of source `s` lies on
    let on = |s: usize, id: u32| -> Vec<u32> {
        let (cx, a) = (&cxs[s], &per[s]);
        if id >= cx.need.base {
            let [u, v] = cx.need.splits[(id - cx.need.base) as usize].edge;
            let tv = a.around.get(&v);
            a.around
                .get(&u)
                .into_iter()
                .flatten()
                .copied()
                .filter(|t| tv.is_some_and(|l| l.contains(t)))
                .collect()
        } else {
            a.around.get(&id).cloned().unwrap_or_default()
        }
    };
    let sum = |s: usize, ts: &[u32]| {
        let mut n = [0.0; 3];
        for t in ts {
            if let Some(f) = per[s].face.get(t) {
                n = [n[0] + f[0], n[1] + f[1], n[2] + f[2]];
            }
        }
        n
    };
    let up = |p: [f64; 3]| {
        let (l, f) = (p[0].to_radians(), p[1].to_radians());
        [f.cos() * l.cos(), f.cos() * l.sin(), f.sin()]
    };
    let mut out = Vec::with_capacity(mesh.points.len());
    for (i, ks) in mesh.kinds.iter().enumerate() {
        let p = mesh.points[i];
        // a vertex on a seam of tiled tins sums the triangles of each
        let mut n = [0.0; 3];
        for &(src, k) in ks {
            let s = src as usize;
            let m = match k {
                Kind::Vertex(v) => sum(s, &on(s, v)),
                Kind::Edge(a, b) => {
                    let tb = on(s, b);
                    let common: Vec<u32> =
                        on(s, a).into_iter().filter(|t| tb.contains(t)).collect();
                    sum(s, &common)
                }
                Kind::Inside(t) => match per[s].face.get(&t) {
                    Some(f) => *f,
                    None => tri_normal(&cxs[s], t)?,
                },
                Kind::Fill => up(p),
            };
            n = [n[0] + m[0], n[1] + m[1], n[2] + m[2]];
        }
        let n = if norm(n) > 0.0 { n } else { up(p) };
        let m = norm(n);
        out.push([n[0] / m, n[1] / m, n[2] / m]);
    }
    Ok(out)
}

/// How a tile is encoded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TileOptions {
    /// The oct-encoded vertex normals extension.
    pub normals: bool,
    /// The height of the fill where the terrain is not (`None`: no fill).
    pub fill: Option<f64>,
}

impl TileOptions {
    /// What [`needed()`](super::needed::needed) must pick for such a tile,
    /// with edges split longer than `max_len`.
    pub fn need(self, max_len: Option<f64>) -> NeedOptions {
        NeedOptions {
            normals: self.normals,
            fill: self.fill.is_some(),
            max_len,
        }
    }
}

/// The quantized-mesh tile `tile` of `level`: `None` when nothing of the
/// terrain (and no fill) meets it. `need` from [`needed()`](super::needed::needed) (with
/// [`TileOptions::need`] of the same `opts`), `geo` the geographic position
/// of each of [`Needed::points`](super::needed::Needed::points).
pub fn encode(
    src: Source<'_>,
    tile: &TileBounds,
    opts: TileOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Vec<u8>>, TinError> {
    encode_many(&[src], tile, opts, interrupt)
}

/// The mesh's vertices numbered in order of first use (the high-water-mark
/// coding of the indices): the mesh vertex of each new number, and the
/// triangles' corners by new number.
fn first_use_order(triangles: &[[u32; 3]], points: usize) -> (Vec<u32>, Vec<u32>) {
    let mut order = vec![u32::MAX; points];
    let mut seq = Vec::with_capacity(points);
    let mut idx = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        for &v in t {
            if order[v as usize] == u32::MAX {
                order[v as usize] = seq.len() as u32;
                seq.push(v);
            }
            idx.push(order[v as usize]);
        }
    }
    (seq, idx)
}

/// The heights' bounds as f32, rounded outwards.
fn height_bounds(pts: &[[f64; 3]]) -> (f32, f32) {
    let hmin = pts.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
    let hmax = pts.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max);
    let mut fmin = hmin as f32;
    if fmin as f64 > hmin {
        fmin = fmin.next_down();
    }
    let mut fmax = hmax as f32;
    if (fmax as f64) < hmax {
        fmax = fmax.next_up();
    }
    (fmin, fmax)
}

/// The bounding sphere (centre, radius) and horizon occlusion point of the
/// positions a reader decodes from the quantized `u`, `v` and `hq` (heights
/// between `lo_h` and `hi_h`); at zoom 0 a quantization step is 600 m.
fn bounding_sphere(
    tile: &TileBounds,
    u: &[i32],
    v: &[i32],
    hq: &[i32],
    lo_h: f64,
    hi_h: f64,
) -> ([f64; 3], f64, [f64; 3]) {
    let n = u.len();
    let ecefs: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            ecef(
                tile.west + u[i] as f64 / QMAX * (tile.east - tile.west),
                tile.south + v[i] as f64 / QMAX * (tile.north - tile.south),
                lo_h + hq[i] as f64 / QMAX * (hi_h - lo_h),
            )
        })
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for e in &ecefs {
        for k in 0..3 {
            lo[k] = lo[k].min(e[k]);
            hi[k] = hi[k].max(e[k]);
        }
    }
    let centre = [
        (lo[0] + hi[0]) / 2.0,
        (lo[1] + hi[1]) / 2.0,
        (lo[2] + hi[2]) / 2.0,
    ];
    // a centimetre more than the farthest, for the rounding of a reader
    let radius = ecefs
        .iter()
        .map(|e| norm(sub(*e, centre)))
        .fold(0.0, f64::max)
        + 0.01;
    let horizon = horizon_point(centre, &ecefs);
    (centre, radius, horizon)
}

/// [`encode`] of a terrain stored as several tins sharing their seams
/// (`tin_tiles`, keep_border): one mesh of every source's triangles in the
/// tile, their seam vertices one vertex (the same positions in each), the
/// normals there summed over the tins, and no wall along a seam.
pub fn encode_many(
    sources: &[Source],
    tile: &TileBounds,
    opts: TileOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Vec<u8>>, TinError> {
    encode_with(sources, tile, opts, Extras::default(), interrupt)
}

/// The extensions after the vertex normals, each written when given.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extras<'a> {
    /// The water mask extension (id 2) of these polygons in
    /// longitude/latitude ([`water_mask`]; none: no extension, an empty
    /// slice: the one-byte all-land mask).
    pub water: Option<&'a [WaterPolygon]>,
    /// The metadata extension (id 4): this JSON text, e.g. the tile's
    /// availability from [`tile_metadata`](crate::serve::tiling::tile_metadata).
    pub metadata: Option<&'a str>,
}

/// [`encode_many`] with the water mask and metadata extensions of `extras`.
pub fn encode_with(
    sources: &[Source],
    tile: &TileBounds,
    opts: TileOptions,
    extras: Extras<'_>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Vec<u8>>, TinError> {
    let TileOptions {
        normals: with_normals,
        fill,
    } = opts;
    let Some(mesh) = tile_mesh(sources, tile, fill, interrupt)? else {
        return Ok(None);
    };
    let cxs = tiles_of(sources, tile);
    let (seq, idx) = first_use_order(&mesh.triangles, mesh.points.len());
    let n = seq.len();
    let pts: Vec<[f64; 3]> = seq.iter().map(|&v| mesh.points[v as usize]).collect();
    let (fmin, fmax) = height_bounds(&pts);
    let q = |v: f64, lo: f64, hi: f64| -> i32 {
        if hi > lo {
            (((v - lo) / (hi - lo)) * QMAX).round().clamp(0.0, QMAX) as i32
        } else {
            0
        }
    };
    let u: Vec<i32> = pts.iter().map(|p| q(p[0], tile.west, tile.east)).collect();
    let v: Vec<i32> = pts
        .iter()
        .map(|p| q(p[1], tile.south, tile.north))
        .collect();
    let hq: Vec<i32> = pts
        .iter()
        .map(|p| q(p[2], fmin as f64, fmax as f64))
        .collect();
    let (centre, radius, horizon) = bounding_sphere(tile, &u, &v, &hq, fmin as f64, fmax as f64);

    let mut out = Vec::with_capacity(88 + 4 + n * 6 + idx.len() * 4 + 64);
    for v in centre {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&fmin.to_le_bytes());
    out.extend_from_slice(&fmax.to_le_bytes());
    for v in centre {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&radius.to_le_bytes());
    for v in horizon {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&(n as u32).to_le_bytes());
    for arr in [&u, &v, &hq] {
        let mut prev = 0;
        for &x in arr.iter() {
            out.extend_from_slice(&zigzag(x - prev).to_le_bytes());
            prev = x;
        }
    }
    let wide = n > 65536;
    let put = |out: &mut Vec<u8>, x: u32| {
        if wide {
            out.extend_from_slice(&x.to_le_bytes());
        } else {
            out.extend_from_slice(&(x as u16).to_le_bytes());
        }
    };
    if wide {
        while out.len() % 4 != 0 {
            out.push(0);
        }
    }
    out.extend_from_slice(&((idx.len() / 3) as u32).to_le_bytes());
    let mut highest = 0u32;
    for &i in &idx {
        put(&mut out, highest - i);
        if i == highest {
            highest += 1;
        }
    }
    let side = |pick: &dyn Fn(usize) -> bool, key: &dyn Fn(usize) -> i32| -> Vec<u32> {
        let mut s: Vec<usize> = (0..n).filter(|&i| pick(i)).collect();
        s.sort_by_key(|&i| (key(i), i));
        s.into_iter().map(|i| i as u32).collect()
    };
    // the vertices exactly on each side (crossings and tile corners, which
    // the tiles on both sides of it compute bit for bit); a vertex inside
    // within half a step of a side quantizes onto it too but is not listed,
    // or the lists of two neighbours would differ by it
    let west = side(&|i| pts[i][0] == tile.west, &|i| v[i]);
    let south = side(&|i| pts[i][1] == tile.south, &|i| u[i]);
    let east = side(&|i| pts[i][0] == tile.east, &|i| v[i]);
    let north = side(&|i| pts[i][1] == tile.north, &|i| u[i]);
    for list in [&west, &south, &east, &north] {
        out.extend_from_slice(&(list.len() as u32).to_le_bytes());
        for &i in list.iter() {
            put(&mut out, i);
        }
    }
    if with_normals {
        let ns = normals(&cxs, &mesh)?;
        out.push(1);
        out.extend_from_slice(&((2 * n) as u32).to_le_bytes());
        for &s in &seq {
            out.extend_from_slice(&oct_encode(ns[s as usize]));
        }
    }
    if let Some(polys) = extras.water {
        let mask = water_mask(tile, polys, interrupt)?;
        out.push(2);
        out.extend_from_slice(&(mask.len() as u32).to_le_bytes());
        out.extend_from_slice(&mask);
    }
    if let Some(json) = extras.metadata {
        out.push(4);
        out.extend_from_slice(&((json.len() + 4) as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(json.as_bytes());
    }
    Ok(Some(out))
}

/// Bytes of memory a tile of `triangles` candidate triangles needs at most
/// (clipping can add 4 vertices and 4 triangles per triangle).
pub fn tile_bytes(triangles: usize) -> usize {
    triangles * (7 * 48 + 5 * 12 + 64)
}
