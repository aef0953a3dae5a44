//! The tile's vertices and triangles before encoding: the clipped
//! triangles, and the fill and walls off the terrain; and the ECEF
//! arithmetic of WGS 84.

use rustc_hash::FxHashMap;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::clip::{Kind, Pt, Source, Tile, orient};
use crate::interrupt::{Interrupt, Ticker};
use crate::serve::tiling::TileBounds;
use crate::tin::TinError;

/// WGS 84 semi-major axis and flattening.
pub(super) const A: f64 = 6_378_137.0;
pub(super) const F: f64 = 1.0 / 298.257_223_563;
/// WGS 84 semi-minor axis.
pub(super) const B: f64 = A * (1.0 - F);

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

pub(super) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(super) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub(super) type Keys = FxHashMap<(u64, u64, bool), u32>;

/// The vertices and triangles of a tile before encoding (longitude,
/// latitude in degrees, height in metres; CCW triangles).
#[derive(Clone, Debug, Default)]
pub struct TileMesh {
    pub points: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// What each vertex is in each source that has it (one source, or
    /// two to four at a vertex on the seams of a tiled terrain).
    pub(super) kinds: Vec<Vec<(u32, Kind)>>,
}

impl TileMesh {
    /// The vertex at `p`: one per position on the terrain, and one per
    /// position at the fill's height (a wall joins the two on the hull).
    pub(super) fn add(&mut self, keys: &mut Keys, p: &Pt) -> u32 {
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
pub(crate) fn tile_mesh(
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
        for &t in &cx.need.triangles {
            tick.tick()?;
            let tri = cx.need.tri(t)?;
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

pub(super) fn tiles_of<'a>(sources: &[Source<'a>], tile: &TileBounds) -> Vec<Tile<'a>> {
    sources
        .iter()
        .enumerate()
        .map(|(i, s)| Tile {
            b: *tile,
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

/// A piece of the domain's hull, from one point to the next.
type Piece = [Pt; 2];

/// The domain's hull in the tile: its pieces cut to the tile, their ends
/// computed as the triangles' were, without the seams between two tins of
/// a tiled terrain (on the hull of both, once each way: the terrain goes
/// on, so no wall there); and the whole hull ring, uncut, to tell the
/// terrain from the fill.
fn hull_pieces(cxs: &[Tile], tick: &mut Ticker) -> Result<(Vec<Piece>, Vec<Piece>), TinError> {
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
    Ok((pieces, ring))
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
    let (pieces, ring) = hull_pieces(cxs, tick)?;
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
