//! One Cesium quantized-mesh 1.0 tile of a level, clipped exactly to the
//! tile.
//!
//! The caller gives the triangles that may meet the tile (a superset:
//! [`needed`] picks them by bounding box in the tin's own coordinates) and
//! the geographic position (longitude, latitude in degrees, WGS 84) of
//! each of their vertices; in PostgreSQL those come from PostGIS's
//! `ST_Transform`. A triangle's geographic image is the triangle through
//! its transformed corners (what Cesium draws between them).
//!
//! **Clipping.** Each triangle is clipped to the tile's rectangle
//! (Sutherland-Hodgman, sides in a fixed order). Every vertex of the result
//! is a corner of the triangle, a corner of the tile, or where an
//! *original* edge of the level crosses a side of the tile, and that
//! crossing is computed from the edge's two ends taken in a canonical
//! order (lexicographic), never from an already-clipped piece. So the two
//! triangles on either side of an edge, and the two tiles on either side of
//! a tile side, compute the same double for the same crossing: vertices on
//! a shared tile side coincide bit for bit before quantization and, as the
//! side is the same quantized row or column in both tiles, after it too. A
//! crossing's height is interpolated along its edge; a tile corner inside a
//! triangle takes the triangle's plane in longitude/latitude.
//!
//! **Fill.** With `fill = Some(h)` the part of the tile off the terrain is
//! covered too: a constrained Delaunay triangulation (spade) of the tile's
//! corners and the domain's boundary edges clipped to the tile (hull edges,
//! and edges between a domain and a void triangle: the outline of the
//! data and its holes), keeping the faces outside the domain, all at height `h`, and a vertical wall along
//! the boundary from the terrain's edge to that height (facing out; the wall's
//! top vertices are the terrain's own, so the mesh is closed). The fill is
//! flat and the walls follow the boundary, so neighbouring tiles and tiles of
//! different zooms agree (a fill sloping from the hull to the tile's
//! corners differed from zoom to zoom, and Cesium's skirts showed at the
//! seams). A tile off the terrain is then two flat triangles. Without fill
//! such a tile is `None`.
//!
//! **Encoding** ([spec](https://github.com/CesiumGS/quantized-mesh)): the
//! 88-byte header (centre and bounding sphere in ECEF, WGS 84; minimum and
//! maximum height as f32, rounded outwards; the horizon occlusion point in
//! ellipsoid-scaled space, computed as Cesium's `EllipsoidalOccluder`
//! does, NaN when no point exists, which Cesium treats as never
//! occluded); `u`, `v`, `height` quantized to 0..32767 and zig-zag delta
//! coded; vertices numbered in order of first use so the indices are
//! high-water-mark coded, 16-bit up to 65,536 vertices and 32-bit beyond
//! (aligned to 4); the west, south, east and north edge vertex lists (the
//! vertices exactly on that side before quantization, so two neighbours
//! list the same ones: a vertex inside within half a step of a side
//! quantizes onto it but is not listed), sorted along their side; the
//! oct-encoded vertex normals extension (id 1) when asked: per vertex, the
//! area-weighted sum of the ECEF normals of the level's triangles around
//! it (all of them, also those outside the tile, so normals agree across
//! tile sides), around an edge for a crossing, the triangle's for a tile
//! corner; the ellipsoid's normal for fill corners.
//!
//! ```
//! use tinmerge_core::serve::quantized_mesh::{encode, needed};
//! use tinmerge_core::serve::tiling::tile_bounds;
//! use tinmerge_core::tin::build::build;
//! let mut pts = Vec::new();
//! for i in 0..20 {
//!     for j in 0..20 {
//!         let (x, y) = (-84.0 + i as f64 * 0.01, 36.0 + j as f64 * 0.01);
//!         pts.push([x, y, 100.0 + 10.0 * (i * j % 7) as f64]);
//!     }
//! }
//! let tin = build(pts, &[5.0, 0.0], 4326, &mut || Ok(())).unwrap();
//! // a tin in EPSG:4326: its own coordinates are the geographic ones
//! let need = needed(&tin, 1, None, false, false, None, &mut || Ok(())).unwrap();
//! let geo = need.points(&tin);
//! let tile = tile_bounds(8, 136, 179).unwrap();
//! let bytes = encode(&tin, 1, &tile, &need, &geo, false, None, &mut || Ok(())).unwrap().unwrap();
//! assert!(bytes.len() > 88);
//! ```

use rustc_hash::FxHashMap;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::tiling::TileBounds;
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::polygon::Area;
use crate::merge::area::{Method, sweep};
use crate::tin::{NONE, Tin, TinError};

/// WGS 84 semi-major axis and flattening.
const A: f64 = 6_378_137.0;
const F: f64 = 1.0 / 298.257_223_563;
/// WGS 84 semi-minor axis.
const B: f64 = A * (1.0 - F);
const QMAX: f64 = 32767.0;

/// What a tile needs from the level: the triangles that may meet it, the
/// triangles around their vertices (for normals), the hull edges (for
/// fill; pieces of split edges), the vertices of those and the points
/// that split their long edges, whose geographic positions the caller
/// supplies in the order of [`Needed::points`].
#[derive(Clone, Debug, Default)]
pub struct Needed {
    pub triangles: Vec<u32>,
    pub ring: Vec<u32>,
    pub hull: Vec<[u32; 2]>,
    pub vertices: Vec<u32>,
    /// Points on long edges: ids `num_vertices + i` (see [`needed`]).
    pub splits: Vec<Split>,
    /// Edge (lower id first) -> index of its first split point and the
    /// number of pieces.
    split_of: FxHashMap<(u32, u32), (u32, u32)>,
    /// The first split point's id (the level's vertex count).
    base: u32,
}

/// A point splitting a long edge of the level: on the edge (lower id
/// first) at `i / n` of its length, with the surface's height there.
#[derive(Clone, Copy, Debug)]
pub struct Split {
    pub edge: [u32; 2],
    pub xyz: [f64; 3],
}

impl Needed {
    /// The points whose geographic positions [`encode`] needs, in the
    /// tin's coordinates: the vertices, then the split points.
    pub fn points(&self, tin: &Tin) -> Vec<[f64; 2]> {
        let mut p: Vec<[f64; 2]> = self
            .vertices
            .iter()
            .map(|&v| {
                let q = tin.verts[v as usize];
                [q[0], q[1]]
            })
            .collect();
        p.extend(self.splits.iter().map(|s| [s.xyz[0], s.xyz[1]]));
        p
    }

    /// Index into [`Needed::points`] of vertex or split point `id`.
    fn index(&self, id: u32) -> Option<usize> {
        if id >= self.base {
            let i = (id - self.base) as usize;
            (i < self.splits.len()).then_some(self.vertices.len() + i)
        } else {
            self.vertices.binary_search(&id).ok()
        }
    }

    /// The chain of ids from `a` to `b` along the level's edge (a, b): the
    /// ends and the edge's split points between them.
    fn chain(&self, a: u32, b: u32) -> Vec<u32> {
        let key = (a.min(b), a.max(b));
        let mut c = vec![key.0];
        if let Some(&(first, n)) = self.split_of.get(&key) {
            c.extend((0..n - 1).map(|i| self.base + first + i));
        }
        c.push(key.1);
        if a > b {
            c.reverse();
        }
        c
    }

    fn split_edge(&mut self, tin: &Tin, a: u32, b: u32, max_len: f64) {
        let key = (a.min(b), a.max(b));
        if self.split_of.contains_key(&key) {
            return;
        }
        let (p, q) = (tin.verts[key.0 as usize], tin.verts[key.1 as usize]);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        if len <= max_len {
            return;
        }
        // at most 4,096 pieces: the caller's length is a bound, not a promise
        let n = ((len / max_len).ceil() as u32).min(4096);
        self.split_of.insert(key, (self.splits.len() as u32, n));
        for i in 1..n {
            let t = i as f64 / n as f64;
            self.splits.push(Split {
                edge: [key.0, key.1],
                xyz: [
                    p[0] + t * (q[0] - p[0]),
                    p[1] + t * (q[1] - p[1]),
                    p[2] + t * (q[2] - p[2]),
                ],
            });
        }
    }
}

/// The triangles of `level` that meet `footprint` = `[min x, min y, max
/// x, max y]` in the tin's coordinates (`None`: all; the caller widens it
/// by what the geographic image of a triangle can differ from its own
/// footprint), found by the area merge's flat sweep of that rectangle,
/// with what [`encode`] needs about them.
///
/// `max_len` (the tin's units; `None`: never) splits every edge longer
/// than it into equal pieces ([`split_length`] gives it): a straight edge
/// of a projected tin is a curve in longitude/latitude, and the straight
/// line between its transformed ends can pass on the wrong side of a
/// vertex near it (on the UTM DEM's 30 km hull edges the curve bulges 11 m
/// from the line, folding the thin triangles that fill the DEM's nodata
/// corners). Split points are on the edge in the tin's frame, with its
/// height there, and are the same for both triangles of the edge.
pub fn needed(
    tin: &Tin,
    level: usize,
    footprint: Option<[f64; 4]>,
    normals: bool,
    fill: bool,
    max_len: Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Needed, TinError> {
    let lv = &tin.levels[level];
    let mut out = Needed {
        base: lv.num_vertices,
        ..Needed::default()
    };
    let mut used = vec![false; lv.num_vertices as usize];
    match footprint {
        None => out.triangles = (0..lv.num_domain() as u32).collect(),
        Some(f) if f[0] < f[2] && f[1] < f[3] => {
            // the triangles meeting the rectangle, by the area merge's flat
            // sweep at this level alone (no scan of the level)
            let area = Area::new(vec![vec![vec![
                [f[0], f[1]],
                [f[2], f[1]],
                [f[2], f[3]],
                [f[0], f[3]],
                [f[0], f[1]],
            ]]]);
            let s = sweep(tin, level, &area, Method::Flat, interrupt)?;
            let mut ids = s.inside.get(level).cloned().unwrap_or_default();
            ids.extend_from_slice(&s.boundary);
            ids.sort_unstable();
            ids.dedup();
            out.triangles = ids;
        }
        Some(_) => {}
    }
    for &t in &out.triangles {
        for &v in &lv.tris[t as usize] {
            used[v as usize] = true;
        }
    }
    if normals {
        // every triangle around a vertex of those: from each, the triangles
        // across its edges that hold the vertex too
        let mut ring = rustc_hash::FxHashSet::default();
        let mut stack = Vec::new();
        for &t in &out.triangles {
            for &v in &lv.tris[t as usize] {
                stack.push(t);
                while let Some(u) = stack.pop() {
                    if !ring.insert((v, u)) {
                        continue;
                    }
                    for &n in &lv.nbrs[u as usize] {
                        if n != NONE
                            && (n as usize) < lv.num_domain()
                            && lv.tris[n as usize].contains(&v)
                            && !ring.contains(&(v, n))
                        {
                            stack.push(n);
                        }
                    }
                }
            }
        }
        let mut ts: Vec<u32> = ring.into_iter().map(|(_, t)| t).collect();
        ts.sort_unstable();
        ts.dedup();
        for &t in &ts {
            for &v in &lv.tris[t as usize] {
                used[v as usize] = true;
            }
        }
        out.ring = ts;
    }
    let mut hull = Vec::new();
    if fill {
        // the domain's boundary: hull edges, and edges between a domain
        // triangle and a void one (the outline of the data, its holes)
        for e in lv.boundary_edges() {
            used[e[0] as usize] = true;
            used[e[1] as usize] = true;
            hull.push(e);
        }
    }
    if let Some(m) = max_len.filter(|m| *m > 0.0 && m.is_finite()) {
        for i in 0..out.triangles.len() {
            let tri = lv.tris[out.triangles[i] as usize];
            for k in 0..3 {
                out.split_edge(tin, tri[k], tri[(k + 1) % 3], m);
            }
        }
        for e in &hull {
            out.split_edge(tin, e[0], e[1], m);
        }
    }
    for e in hull {
        let c = out.chain(e[0], e[1]);
        out.hull.extend(c.windows(2).map(|w| [w[0], w[1]]));
    }
    out.vertices = (0..used.len() as u32)
        .filter(|&v| used[v as usize])
        .collect();
    Ok(out)
}

/// Only the hull of `level` (its edges, split as [`needed`] splits them,
/// and their points): what the fill of a tile off the terrain needs, and
/// the terrain's exact geographic extent.
pub fn hull(tin: &Tin, level: usize, max_len: Option<f64>) -> Needed {
    // an empty footprint: no triangle, and nothing that can fail
    needed(
        tin,
        level,
        Some([0.0; 4]),
        false,
        true,
        max_len,
        &mut || Ok(()),
    )
    .unwrap_or_default()
}

/// The longest edge that may stay straight in longitude/latitude: the
/// image of a straight line of length `d` bulges `sagitta` degrees from
/// its chord (measured by the caller on the terrain's own diagonals), and
/// a bulge grows with the square of the length, so pieces of
/// `d * sqrt(eps / sagitta)` bulge at most `eps` = 1e-8 degrees (about a
/// millimetre). `None` when the bulge is already below that (a
/// geographic tin), at least `d / 4096`.
pub fn split_length(d: f64, sagitta: f64) -> Option<f64> {
    const EPS: f64 = 1e-8;
    if sagitta.is_nan() || sagitta <= EPS || d.is_nan() || d <= 0.0 || !d.is_finite() {
        return None;
    }
    Some((d * (EPS / sagitta).sqrt()).max(d / 4096.0))
}

/// Where a point of a clipped polygon comes from.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Vertex(u32),
    /// On the level's edge between these vertices (canonical order).
    Edge(u32, u32),
    /// A tile corner inside this triangle.
    Inside(u32),
    /// A tile corner off the terrain (fill).
    Fill,
}

/// The line a polygon edge lies on: an edge of the level, or a tile side.
#[derive(Clone, Copy, Debug)]
enum Support {
    Edge(u32, u32),
    Side(u8),
}

#[derive(Clone, Copy, Debug)]
struct Pt {
    x: f64,
    y: f64,
    h: f64,
    kind: Kind,
    /// The source (tin) the point comes from.
    src: u32,
}

struct Tile<'a> {
    b: TileBounds,
    tin: &'a Tin,
    level: usize,
    need: &'a Needed,
    geo: &'a [[f64; 2]],
    src: u32,
}

/// One tin cut into a tile: its level, what [`needed`] found, and the
/// geographic positions of [`Needed::points`]. A terrain stored as tiles
/// (tins sharing their seams, `tin::tiles`) is one source per tin.
#[derive(Clone, Copy)]
pub struct Source<'a> {
    pub tin: &'a Tin,
    pub level: usize,
    pub need: &'a Needed,
    pub geo: &'a [[f64; 2]],
}

impl Tile<'_> {
    fn inside(&self, p: &Pt, side: u8) -> bool {
        match side {
            0 => p.x >= self.b.west,
            1 => p.x <= self.b.east,
            2 => p.y >= self.b.south,
            _ => p.y <= self.b.north,
        }
    }

    fn side_value(&self, side: u8) -> f64 {
        match side {
            0 => self.b.west,
            1 => self.b.east,
            2 => self.b.south,
            _ => self.b.north,
        }
    }

    fn vertex(&self, v: u32) -> Result<Pt, TinError> {
        let g = self
            .need
            .index(v)
            .and_then(|i| self.geo.get(i))
            .filter(|g| g[0].is_finite() && g[1].is_finite())
            .ok_or_else(|| {
                TinError::InvalidParameter(format!(
                    "point {v} has no finite geographic position (transform to EPSG:4326 failed)"
                ))
            })?;
        let h = if v >= self.need.base {
            self.need.splits[(v - self.need.base) as usize].xyz[2]
        } else {
            self.tin.verts[v as usize][2]
        };
        Ok(Pt {
            x: g[0],
            y: g[1],
            h,
            kind: Kind::Vertex(v),
            src: self.src,
        })
    }

    /// Where the level's edge (a, b) crosses tile side `side`, computed
    /// from the edge's ends in canonical order.
    fn crossing(&self, a: u32, b: u32, side: u8) -> Result<Pt, TinError> {
        let (pa, pb) = (self.vertex(a)?, self.vertex(b)?);
        let (p, q, ka, kb) = if (pa.x, pa.y) <= (pb.x, pb.y) {
            (pa, pb, a, b)
        } else {
            (pb, pa, b, a)
        };
        let s = self.side_value(side);
        let (x, y, t) = if side < 2 {
            let t = (s - p.x) / (q.x - p.x);
            (
                s,
                (p.y + t * (q.y - p.y)).clamp(p.y.min(q.y), p.y.max(q.y)),
                t,
            )
        } else {
            let t = (s - p.y) / (q.y - p.y);
            (
                (p.x + t * (q.x - p.x)).clamp(p.x.min(q.x), p.x.max(q.x)),
                s,
                t,
            )
        };
        let t = t.clamp(0.0, 1.0);
        Ok(Pt {
            x,
            y,
            h: p.h + t * (q.h - p.h),
            kind: Kind::Edge(ka, kb),
            src: self.src,
        })
    }

    /// The corner where tile sides `s1` and `s2` meet.
    fn corner(&self, s1: u8, s2: u8) -> (f64, f64) {
        let (v, hz) = if s1 < 2 { (s1, s2) } else { (s2, s1) };
        (self.side_value(v), self.side_value(hz))
    }

    /// The triangle `tri` (vertex or split point ids, CCW; a piece of the
    /// level's triangle `t`) clipped to the tile: the polygon's points, CCW.
    fn clip(&self, tri: [u32; 3], t: u32) -> Result<Vec<Pt>, TinError> {
        let c = [
            self.vertex(tri[0])?,
            self.vertex(tri[1])?,
            self.vertex(tri[2])?,
        ];
        let mut poly: Vec<(Pt, Support)> = (0..3)
            .map(|k| (c[k], Support::Edge(tri[k], tri[(k + 1) % 3])))
            .collect();
        for side in 0..4u8 {
            if poly.is_empty() {
                break;
            }
            let mut out = Vec::with_capacity(poly.len() + 2);
            for i in 0..poly.len() {
                let (cur, sup) = poly[i];
                let nxt = poly[(i + 1) % poly.len()].0;
                let (ci, ni) = (self.inside(&cur, side), self.inside(&nxt, side));
                if ci {
                    out.push((cur, sup));
                }
                if ci != ni {
                    let p = match sup {
                        Support::Edge(a, b) => self.crossing(a, b, side)?,
                        Support::Side(s2) => {
                            let (x, y) = self.corner(side, s2);
                            let h = plane(&c, x, y);
                            Pt {
                                x,
                                y,
                                h,
                                kind: Kind::Inside(t),
                                src: self.src,
                            }
                        }
                    };
                    if ci {
                        out.push((p, Support::Side(side)));
                    } else {
                        out.push((p, sup));
                    }
                }
            }
            poly = out;
        }
        let mut pts: Vec<Pt> = Vec::with_capacity(poly.len());
        for (p, _) in poly {
            if pts.last().is_none_or(|q: &Pt| (q.x, q.y) != (p.x, p.y)) {
                pts.push(p);
            }
        }
        while pts.len() > 1 && (pts[0].x, pts[0].y) == (pts[pts.len() - 1].x, pts[pts.len() - 1].y)
        {
            pts.pop();
        }
        Ok(pts)
    }
}

/// Height at (x, y) on the plane through the three points (longitude,
/// latitude, height).
fn plane(c: &[Pt; 3], x: f64, y: f64) -> f64 {
    let p = c.map(|p| [p.x, p.y, p.h]);
    crate::tin::interpolate(&p, x, y)
}

fn orient(a: &Pt, b: &Pt, c: &Pt) -> f64 {
    robust::orient2d(
        robust::Coord { x: a.x, y: a.y },
        robust::Coord { x: b.x, y: b.y },
        robust::Coord { x: c.x, y: c.y },
    )
}

/// Earth-centred, earth-fixed position of (longitude, latitude) in degrees
/// and height in metres on WGS 84.
pub fn ecef(lon: f64, lat: f64, h: f64) -> [f64; 3] {
    let (l, p) = (lon.to_radians(), lat.to_radians());
    let e2 = F * (2.0 - F);
    let n = A / (1.0 - e2 * p.sin() * p.sin()).sqrt();
    [
        (n + h) * p.cos() * l.cos(),
        (n + h) * p.cos() * l.sin(),
        (n * (1.0 - e2) + h) * p.sin(),
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

type Keys = FxHashMap<(u64, u64, bool), u32>;

/// The vertices and triangles of a tile before encoding (longitude,
/// latitude in degrees, height in metres; CCW triangles).
#[derive(Clone, Debug, Default)]
pub struct TileMesh {
    pub points: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// What each vertex is in each source that has it (one source, or
    /// two to four at a vertex on the seams of a tiled terrain).
    kinds: Vec<Vec<(u32, Kind)>>,
}

impl TileMesh {
    /// The vertex at `p`: one per position on the terrain, and one per
    /// position at the fill's height (a wall joins the two on the hull).
    fn add(&mut self, keys: &mut Keys, p: &Pt) -> u32 {
        let fill = matches!(p.kind, Kind::Fill);
        *keys
            .entry((p.x.to_bits(), p.y.to_bits(), fill))
            .and_modify(|&mut i| {
                let k = &mut self.kinds[i as usize];
                if !k.iter().any(|e| e.0 == p.src) {
                    k.push((p.src, p.kind));
                }
            })
            .or_insert_with(|| {
                self.points.push([p.x, p.y, p.h]);
                self.kinds.push(vec![(p.src, p.kind)]);
                (self.points.len() - 1) as u32
            })
    }
}

/// The clipped mesh of the tile (before quantization) from every source;
/// `None` when nothing of the terrain, and no fill, meets the tile.
pub fn tile_mesh(
    sources: &[Source],
    tile: &TileBounds,
    fill: Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<TileMesh>, TinError> {
    let cxs = tiles_of(sources, tile);
    let mut tick = Ticker::new(interrupt);
    let mut mesh = TileMesh::default();
    let mut keys: Keys = FxHashMap::default();
    let mut pieces: Vec<[u32; 3]> = Vec::new();
    for cx in &cxs {
        let lv = &cx.tin.levels[cx.level];
        for &t in &cx.need.triangles {
            tick.tick()?;
            let tri = lv.tris[t as usize];
            pieces.clear();
            if cx.need.split_of.is_empty() {
                pieces.push(tri);
            } else {
                split_triangle(cx, tri, &mut pieces)?;
            }
            for &piece in &pieces {
                let pts = cx.clip(piece, t)?;
                if pts.len() < 3 {
                    continue;
                }
                for i in 1..pts.len() - 1 {
                    if orient(&pts[0], &pts[i], &pts[i + 1]) > 0.0 {
                        let a = mesh.add(&mut keys, &pts[0]);
                        let b = mesh.add(&mut keys, &pts[i]);
                        let c = mesh.add(&mut keys, &pts[i + 1]);
                        mesh.triangles.push([a, b, c]);
                    }
                }
            }
        }
    }
    if let Some(h) = fill {
        fill_tile(&cxs, *tile, h, &mut mesh, &mut keys, &mut tick)?;
    }
    Ok(if mesh.triangles.is_empty() {
        None
    } else {
        Some(mesh)
    })
}

fn tiles_of<'a>(sources: &[Source<'a>], tile: &TileBounds) -> Vec<Tile<'a>> {
    sources
        .iter()
        .enumerate()
        .map(|(i, s)| Tile {
            b: *tile,
            tin: s.tin,
            level: s.level,
            need: s.need,
            geo: s.geo,
            src: i as u32,
        })
        .collect()
}

/// The triangle `tri` of the level cut at the split points of its edges:
/// the polygon of its corners and those points in degrees (the curved
/// image of the triangle, up to the split length's bulge) triangulated
/// there by a constrained Delaunay triangulation (spade) of its boundary,
/// the faces inside it kept, as triangles of ids (CCW). Triangulating in
/// degrees, not in the tin's frame, is what keeps every piece the right
/// way up: a piece along a curved edge would otherwise fold.
fn split_triangle(cx: &Tile, tri: [u32; 3], out: &mut Vec<[u32; 3]>) -> Result<(), TinError> {
    let need = cx.need;
    let mut ids: Vec<u32> = Vec::new();
    for k in 0..3 {
        let c = need.chain(tri[k], tri[(k + 1) % 3]);
        ids.extend_from_slice(&c[..c.len() - 1]);
    }
    if ids.len() == 3 {
        out.push(tri);
        return Ok(());
    }
    let pts: Vec<Pt> = ids
        .iter()
        .map(|&id| cx.vertex(id))
        .collect::<Result<_, _>>()?;
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut of_handle: Vec<u32> = Vec::with_capacity(ids.len());
    let mut handles = Vec::with_capacity(ids.len());
    for (k, p) in pts.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|e| TinError::InvalidParameter(format!("splitting a triangle: {e:?}")))?;
        if h.index() == of_handle.len() {
            of_handle.push(ids[k]);
        }
        handles.push(h);
    }
    for k in 0..handles.len() {
        let (a, b) = (handles[k], handles[(k + 1) % handles.len()]);
        if a != b {
            cdt.try_add_constraint(a, b);
        }
    }
    // inside the polygon: crossing number of the face's centroid
    let inside = |x: f64, y: f64| {
        let mut c = false;
        for k in 0..pts.len() {
            let (p, q) = (&pts[k], &pts[(k + 1) % pts.len()]);
            if (p.y > y) != (q.y > y) && x < p.x + (y - p.y) / (q.y - p.y) * (q.x - p.x) {
                c = !c;
            }
        }
        c
    };
    for f in cdt.inner_faces() {
        let v = f.vertices();
        let (x, y) = (
            (v[0].position().x + v[1].position().x + v[2].position().x) / 3.0,
            (v[0].position().y + v[1].position().y + v[2].position().y) / 3.0,
        );
        let i = v.map(|v| v.fix().index());
        if i.iter().all(|&i| i < of_handle.len()) && inside(x, y) {
            out.push(i.map(|i| of_handle[i]));
        }
    }
    Ok(())
}

/// Covers the tile outside the domain (see the module docs).
fn fill_tile(
    cxs: &[Tile],
    b: TileBounds,
    h: f64,
    mesh: &mut TileMesh,
    keys: &mut Keys,
    tick: &mut Ticker,
) -> Result<(), TinError> {
    // hull pieces inside the tile, their ends computed as the triangles' were
    let mut pieces: Vec<[Pt; 2]> = Vec::new();
    let mut ring: Vec<[Pt; 2]> = Vec::new();
    for cx in cxs {
        for &[u, v] in &cx.need.hull {
            tick.tick()?;
            let (mut p, mut q) = (cx.vertex(u)?, cx.vertex(v)?);
            ring.push([p, q]);
            let mut keep = true;
            for side in 0..4u8 {
                let (pi, qi) = (cx.inside(&p, side), cx.inside(&q, side));
                if !pi && !qi {
                    keep = false;
                    break;
                }
                if !pi {
                    p = cx.crossing(u, v, side)?;
                } else if !qi {
                    q = cx.crossing(u, v, side)?;
                }
            }
            if keep && (p.x, p.y) != (q.x, q.y) {
                pieces.push([p, q]);
            }
        }
    }
    // a seam between two tins of a tiled terrain is on the hull of both,
    // once each way: the terrain goes on, so no wall there
    let key = |p: &Pt| (p.x.to_bits(), p.y.to_bits());
    let directed: rustc_hash::FxHashSet<_> = pieces.iter().map(|[p, q]| (key(p), key(q))).collect();
    pieces.retain(|[p, q]| !directed.contains(&(key(q), key(p))));
    let corner = |x: f64, y: f64| Pt {
        x,
        y,
        h,
        kind: Kind::Fill,
        src: 0,
    };
    let corners = [
        corner(b.west, b.south),
        corner(b.east, b.south),
        corner(b.east, b.north),
        corner(b.west, b.north),
    ];
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::new();
    let mut at: FxHashMap<(u64, u64), (spade::handles::FixedVertexHandle, Pt)> =
        FxHashMap::default();
    let mut insert =
        |cdt: &mut ConstrainedDelaunayTriangulation<Point2<f64>>, p: &Pt| -> Result<_, TinError> {
            if let Some(&(hd, _)) = at.get(&(p.x.to_bits(), p.y.to_bits())) {
                return Ok(hd);
            }
            let hd = cdt
                .insert(Point2::new(p.x, p.y))
                .map_err(|e| TinError::InvalidParameter(format!("tile fill: {e:?}")))?;
            at.insert((p.x.to_bits(), p.y.to_bits()), (hd, *p));
            Ok(hd)
        };
    for c in &corners {
        insert(&mut cdt, c)?;
    }
    let low = |p: &Pt| Pt {
        h,
        kind: Kind::Fill,
        ..*p
    };
    let mut edges = Vec::with_capacity(pieces.len());
    for [p, q] in &pieces {
        edges.push((insert(&mut cdt, &low(p))?, insert(&mut cdt, &low(q))?));
    }
    for (p, q) in edges {
        tick.tick()?;
        cdt.try_add_constraint(p, q);
    }
    // a point is on the terrain when inside the hull ring (crossing number)
    let on_terrain = |x: f64, y: f64| {
        let mut inside = false;
        for [p, q] in &ring {
            if (p.y > y) != (q.y > y) && x < p.x + (y - p.y) / (q.y - p.y) * (q.x - p.x) {
                inside = !inside;
            }
        }
        inside
    };
    for face in cdt.inner_faces() {
        tick.tick()?;
        let v = face.vertices().map(|v| *v.data());
        let cxm = (v[0].x + v[1].x + v[2].x) / 3.0;
        let cym = (v[0].y + v[1].y + v[2].y) / 3.0;
        if on_terrain(cxm, cym) {
            continue;
        }
        let Some(p) = v
            .iter()
            .map(|q| at.get(&(q.x.to_bits(), q.y.to_bits())).map(|e| e.1))
            .collect::<Option<Vec<Pt>>>()
        else {
            continue;
        };
        if orient(&p[0], &p[1], &p[2]) > 0.0 {
            let a = mesh.add(keys, &p[0]);
            let b2 = mesh.add(keys, &p[1]);
            let c = mesh.add(keys, &p[2]);
            mesh.triangles.push([a, b2, c]);
        }
    }
    // walls from the terrain's edge down (or up) to the fill, facing out
    for [p, q] in &pieces {
        tick.tick()?;
        if p.h == h && q.h == h {
            continue;
        }
        let (pt, qt) = (mesh.add(keys, p), mesh.add(keys, q));
        let (pb, qb) = (mesh.add(keys, &low(p)), mesh.add(keys, &low(q)));
        mesh.triangles.push([pb, qb, qt]);
        mesh.triangles.push([pb, qt, pt]);
    }
    Ok(())
}

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
        let tri = cx.tin.levels[cx.level].tris[t as usize];
        let p = [cx.vertex(tri[0])?, cx.vertex(tri[1])?, cx.vertex(tri[2])?]
            .map(|p| ecef(p.x, p.y, p.h));
        Ok(cross(sub(p[1], p[0]), sub(p[2], p[0])))
    };
    let mut per: Vec<Around> = Vec::with_capacity(cxs.len());
    for cx in cxs {
        let lv = &cx.tin.levels[cx.level];
        let mut a = Around {
            face: FxHashMap::default(),
            around: FxHashMap::default(),
        };
        for &t in &cx.need.ring {
            a.face.insert(t, tri_normal(cx, t)?);
            for &v in &lv.tris[t as usize] {
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

/// The quantized-mesh tile `tile` of `level`: `None` when nothing of the
/// terrain (and no fill) meets it. `need` from [`needed`] (with the same
/// `normals` and fill), `geo` the geographic position of each of
/// [`Needed::points`].
#[allow(clippy::too_many_arguments)]
pub fn encode(
    tin: &Tin,
    level: usize,
    tile: &TileBounds,
    need: &Needed,
    geo: &[[f64; 2]],
    with_normals: bool,
    fill: Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Vec<u8>>, TinError> {
    let src = Source {
        tin,
        level,
        need,
        geo,
    };
    encode_many(&[src], tile, with_normals, fill, interrupt)
}

/// [`encode`] of a terrain stored as several tins sharing their seams
/// (`tin_tiles`, keep_border): one mesh of every source's triangles in the
/// tile, their seam vertices one vertex (the same positions in each), the
/// normals there summed over the tins, and no wall along a seam.
pub fn encode_many(
    sources: &[Source],
    tile: &TileBounds,
    with_normals: bool,
    fill: Option<f64>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<Vec<u8>>, TinError> {
    let Some(mesh) = tile_mesh(sources, tile, fill, interrupt)? else {
        return Ok(None);
    };
    let cxs = tiles_of(sources, tile);
    // number vertices in order of first use (high-water-mark coding)
    let mut order = vec![u32::MAX; mesh.points.len()];
    let mut seq = Vec::with_capacity(mesh.points.len());
    let mut idx = Vec::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        for &v in t {
            if order[v as usize] == u32::MAX {
                order[v as usize] = seq.len() as u32;
                seq.push(v);
            }
            idx.push(order[v as usize]);
        }
    }
    let n = seq.len();
    let pts: Vec<[f64; 3]> = seq.iter().map(|&v| mesh.points[v as usize]).collect();
    let hmin = pts.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
    let hmax = pts.iter().map(|p| p[2]).fold(f64::NEG_INFINITY, f64::max);
    // f32 bounds rounded outwards
    let mut fmin = hmin as f32;
    if fmin as f64 > hmin {
        fmin = fmin.next_down();
    }
    let mut fmax = hmax as f32;
    if (fmax as f64) < hmax {
        fmax = fmax.next_up();
    }
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
    // the bounding sphere and horizon point of the positions a reader
    // decodes (at zoom 0 a quantization step is 600 m)
    let (lo_h, hi_h) = (fmin as f64, fmax as f64);
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
    Ok(Some(out))
}

/// Bytes of memory a tile of `triangles` candidate triangles needs at most
/// (clipping can add 4 vertices and 4 triangles per triangle).
pub fn tile_bytes(triangles: usize) -> usize {
    triangles * (7 * 48 + 5 * 12 + 64)
}
