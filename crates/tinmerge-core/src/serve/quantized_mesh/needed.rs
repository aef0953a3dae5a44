//! What a tile needs from a level: the triangles that may meet it and
//! the points whose geographic positions the caller supplies.

use rustc_hash::FxHashMap;

use crate::interrupt::Interrupt;
use crate::merge::area::{Method, sweep};
use crate::polygon::Area;
use crate::tin::mesh::Indexed;
use crate::tin::{NONE, Tin, TinError};

/// What a tile needs from the level: the triangles that may meet it, the
/// triangles around their vertices (for normals), the hull edges (for
/// fill; pieces of split edges), the vertices of those and the points
/// that split their long edges, whose geographic positions the caller
/// supplies in the order of [`Needed::points`]. It holds what the tile's
/// encoding reads of the level (the corners of those triangles, the
/// vertices' coordinates), so the encoding never reads the tin itself.
#[derive(Clone, Debug, Default)]
pub struct Needed {
    pub triangles: Vec<u32>,
    pub ring: Vec<u32>,
    pub hull: Vec<[u32; 2]>,
    /// Vertex ids, ascending.
    pub vertices: Vec<u32>,
    /// x, y, z of each of [`Needed::vertices`].
    pub coords: Vec<[f64; 3]>,
    /// The vertex ids of each triangle of [`Needed::triangles`] and
    /// [`Needed::ring`].
    pub(super) corners: FxHashMap<u32, [u32; 3]>,
    /// Points on long edges: ids `num_vertices + i` (see [`needed()`]).
    pub splits: Vec<Split>,
    /// Edge (lower id first) -> index of its first split point and the
    /// number of pieces.
    pub(super) split_of: FxHashMap<(u32, u32), (u32, u32)>,
    /// The first split point's id (the tin's vertex count: above every
    /// vertex id).
    pub(super) base: u32,
}

/// A point splitting a long edge of the level: on the edge (lower id
/// first) at `i / n` of its length, with the surface's height there.
#[derive(Clone, Copy, Debug)]
pub struct Split {
    pub edge: [u32; 2],
    pub xyz: [f64; 3],
}

impl Needed {
    /// The points whose geographic positions [`encode`](super::encode::encode) needs, in the
    /// tin's coordinates: the vertices, then the split points.
    pub fn points(&self) -> Vec<[f64; 2]> {
        let mut p: Vec<[f64; 2]> = self.coords.iter().map(|q| [q[0], q[1]]).collect();
        p.extend(self.splits.iter().map(|s| [s.xyz[0], s.xyz[1]]));
        p
    }

    /// The vertex ids of needed triangle `t`.
    pub(super) fn tri(&self, t: u32) -> Result<[u32; 3], TinError> {
        self.corners
            .get(&t)
            .copied()
            .ok_or_else(|| TinError::Corrupt(format!("triangle {t} is not one the tile needs")))
    }

    /// The height of vertex `v` (one of [`Needed::vertices`]).
    pub(super) fn height(&self, v: u32) -> Result<f64, TinError> {
        self.vertices
            .binary_search(&v)
            .map(|i| self.coords[i][2])
            .map_err(|_| TinError::Corrupt(format!("vertex {v} is not one the tile needs")))
    }

    /// Index into [`Needed::points`] of vertex or split point `id`.
    pub(super) fn index(&self, id: u32) -> Option<usize> {
        if id >= self.base {
            let i = (id - self.base) as usize;
            (i < self.splits.len()).then_some(self.vertices.len() + i)
        } else {
            self.vertices.binary_search(&id).ok()
        }
    }

    /// The chain of ids from `a` to `b` along the level's edge (a, b): the
    /// ends and the edge's split points between them.
    pub(super) fn chain(&self, a: u32, b: u32) -> Vec<u32> {
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

    fn split_edge<M: Indexed>(
        &mut self,
        m: &M,
        a: u32,
        b: u32,
        max_len: f64,
    ) -> Result<(), M::Err> {
        let key = (a.min(b), a.max(b));
        if self.split_of.contains_key(&key) {
            return Ok(());
        }
        let (p, q) = (m.vert(key.0)?, m.vert(key.1)?);
        let len = (q[0] - p[0]).hypot(q[1] - p[1]);
        if len <= max_len {
            return Ok(());
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
        Ok(())
    }
}

/// What a tile asks of [`needed`] besides its triangles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeedOptions {
    /// The tile carries vertex normals: the triangles around the picked
    /// triangles' vertices are needed too.
    pub normals: bool,
    /// The tile is filled where the terrain is not: the level's hull edges
    /// are needed.
    pub fill: bool,
    /// Edges longer than this (the tin's units; `None`: never) are split
    /// (see [`needed`]).
    pub max_len: Option<f64>,
}

/// The triangles of `level` that meet `footprint` = `[min x, min y, max
/// x, max y]` in the tin's coordinates (`None`: all; the caller widens it
/// by what the geographic image of a triangle can differ from its own
/// footprint), found by the area merge's flat sweep of that rectangle,
/// with what [`encode`](super::encode::encode) needs about them
/// ([`NeedOptions`]).
///
/// `opts.max_len` (the tin's units; `None`: never) splits every edge longer
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
    opts: NeedOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Needed, TinError> {
    let boundary: &[[u32; 2]] = if opts.fill {
        &tin.outline(level).edges
    } else {
        &[]
    };
    needed_in(tin, level, footprint, opts, boundary, interrupt)
}

/// [`needed()`] on any indexed mesh (a stored value read in slices:
/// [`crate::tin::sliced`]), reading only the triangles the tile needs.
/// `boundary` is the level's domain boundary ([`Tin::outline`]'s edges)
/// when `opts.fill`, which only a decoded value keeps.
pub fn needed_in<M: Indexed>(
    m: &M,
    level: usize,
    footprint: Option<[f64; 4]>,
    opts: NeedOptions,
    boundary: &[[u32; 2]],
    interrupt: &mut Interrupt<'_>,
) -> Result<Needed, TinError>
where
    TinError: From<M::Err>,
{
    let NeedOptions {
        normals,
        fill,
        max_len,
    } = opts;
    let mut out = Needed {
        base: m.num_vertices() as u32,
        ..Needed::default()
    };
    let domain = m.num_domain(level);
    match footprint {
        None => out.triangles = (0..domain as u32).collect(),
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
            let s = sweep(m, level, &area, Method::Flat, interrupt)?;
            let mut ids = s.inside.get(level).cloned().unwrap_or_default();
            ids.extend_from_slice(&s.boundary);
            ids.sort_unstable();
            ids.dedup();
            out.triangles = ids;
        }
        Some(_) => {}
    }
    let mut used: Vec<u32> = Vec::with_capacity(out.triangles.len() * 3);
    for &t in &out.triangles {
        let tri = m.tri(level, t)?;
        out.corners.insert(t, tri);
        used.extend_from_slice(&tri);
    }
    if normals {
        // every triangle around a vertex of those: from each, the triangles
        // across its edges that hold the vertex too
        let mut ring = rustc_hash::FxHashSet::default();
        let mut stack = Vec::new();
        for &t in &out.triangles {
            for v in out.tri(t)? {
                stack.push(t);
                while let Some(u) = stack.pop() {
                    if !ring.insert((v, u)) {
                        continue;
                    }
                    for n in m.nbrs(level, u)? {
                        if n != NONE
                            && (n as usize) < domain
                            && m.tri(level, n)?.contains(&v)
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
            let tri = m.tri(level, t)?;
            out.corners.insert(t, tri);
            used.extend_from_slice(&tri);
        }
        out.ring = ts;
    }
    let mut hull = Vec::new();
    if fill {
        // the domain's boundary: hull edges, and edges between a domain
        // triangle and a void one (the outline of the data, its holes)
        for &e in boundary {
            used.extend_from_slice(&e);
            hull.push(e);
        }
    }
    if let Some(ml) = max_len.filter(|l| *l > 0.0 && l.is_finite()) {
        for i in 0..out.triangles.len() {
            let tri = out.tri(out.triangles[i])?;
            for k in 0..3 {
                out.split_edge(m, tri[k], tri[(k + 1) % 3], ml)?;
            }
        }
        for e in &hull {
            out.split_edge(m, e[0], e[1], ml)?;
        }
    }
    for e in hull {
        let c = out.chain(e[0], e[1]);
        out.hull.extend(c.windows(2).map(|w| [w[0], w[1]]));
    }
    used.sort_unstable();
    used.dedup();
    out.coords = used.iter().map(|&v| m.vert(v)).collect::<Result<_, _>>()?;
    out.vertices = used;
    Ok(out)
}

/// Only the hull of `level` (its edges, split as [`needed()`] splits them,
/// and their points): what the fill of a tile off the terrain needs, and
/// the terrain's exact geographic extent.
pub fn hull(tin: &Tin, level: usize, max_len: Option<f64>) -> Needed {
    // an empty footprint: no triangle, and nothing that can fail
    let opts = NeedOptions {
        normals: false,
        fill: true,
        max_len,
    };
    needed(tin, level, Some([0.0; 4]), opts, &mut || Ok(())).unwrap_or_default()
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
