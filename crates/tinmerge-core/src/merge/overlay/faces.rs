//! TIN/TIN overlay by faces: every face of the overlay is `a ∩ b` for one
//! triangle `a` of A and one `b` of B (both convex, so the face is a convex
//! polygon), so the overlay is built triangle pair by triangle pair with no
//! global triangulation and with labels for free.
//!
//! For each triangle `a` of A, the triangles of B meeting the closed `a`
//! are found by a breadth-first search over B's neighbours, started from
//! the triangle of B holding a corner of `a` (or, for a triangle of A
//! sticking out of B, from B's hull triangles near it). For a pair (a, b)
//! the 18 orientations of the corners of each against the edge lines of the
//! other (`robust::orient2d`, exact) decide everything combinatorial:
//! which corners of `a` lie in the closed `b` and the reverse, which edge
//! pairs cross properly, which edges each vertex of the face lies on (the
//! search goes on across the edges of `b` that meet `a`). Vertices have
//! symbolic identities: a vertex of A, a vertex of B (a vertex of A at the
//! same place as a vertex of B is that vertex), or the crossing of an edge
//! of A with an edge of B, computed once from the two edges and shared by
//! the four faces around it. Neighbouring faces therefore agree exactly on
//! the vertices along their common boundary, whatever the rounding of the
//! crossing points.
//!
//! Only two steps use rounded coordinates: ordering a face's vertices
//! around their mean and cutting ears off the face. Both are checked
//! exactly (strictly increasing angle, no right turn, every output triangle
//! strictly counter-clockwise), and the whole result is checked for
//! conformity (every face boundary edge shared by exactly two faces in
//! opposite directions, or lying on the boundary of A or B). When a check
//! fails (crossings so close that rounding reorders them), the result is
//! refused with [`Refused`] and the caller falls back to the constrained
//! triangulation of [`super::overlay`], which is slower but handles any
//! rounding.
//!
//! Cost: O(N + M + K) for N, M input triangles and K crossings (each pair
//! (a, b) that meets is visited once, in constant time), plus a sort of the
//! face boundary edges for the conformity check.

// corners and edges are indexed 0..3 in several arrays at once
#![allow(clippy::needless_range_loop)]

use super::output::{Overlay, drop_unused};
use crate::geom::{co, crossing, xy, z_along};

use crate::interrupt::{Interrupt, Ticker};
use crate::tin::{Level, NONE, Tin, TinError, interpolate, locate};
use robust::orient2d;
use rustc_hash::FxHashMap;

/// Why the fast path gave up (the caller then uses the robust path).
#[derive(Debug)]
pub enum Refused {
    /// Rounded crossing points made a face non-convex or an output
    /// triangle flat or clockwise, or two faces disagree on a boundary.
    Rounding(&'static str),
    /// An error to pass on (interrupt, corrupt value).
    Error(TinError),
}

impl From<TinError> for Refused {
    fn from(e: TinError) -> Self {
        Refused::Error(e)
    }
}

/// Undirected edge ids of a level: `ids[t][j]` for the edge of triangle `t`
/// opposite its corner `j`, the same id from both sides.
fn edge_ids(lv: &Level) -> Result<Vec<[u32; 3]>, TinError> {
    let mut ids = vec![[NONE; 3]; lv.tris.len()];
    let mut next = 0u32;
    for t in 0..lv.tris.len() {
        for j in 0..3 {
            let n = lv.nbrs[t][j];
            if n == NONE || (t as u32) < n {
                ids[t][j] = next;
                next += 1;
            } else {
                let back = lv
                    .nbrs
                    .get(n as usize)
                    .and_then(|nb| nb.iter().position(|&x| x == t as u32))
                    .ok_or_else(|| TinError::Corrupt("neighbour links are not mirrored".into()))?;
                ids[t][j] = ids[n as usize][back];
            }
        }
    }
    Ok(ids)
}

/// Hull triangles of a level in a coarse bucket grid: to seed triangles
/// of A whose corners all lie outside B, and to find the hull triangle
/// nearest a point a rounding outside a level (the constrained path).
pub(super) struct HullBuckets {
    min: [f64; 2],
    /// a cell's width and height
    pub(super) cell: [f64; 2],
    n: usize,
    cells: Vec<Vec<u32>>,
}

impl HullBuckets {
    pub(super) fn new(tin: &Tin, lv: &Level) -> HullBuckets {
        let hull: Vec<u32> = (0..lv.tris.len() as u32)
            .filter(|&t| lv.nbrs[t as usize].contains(&NONE))
            .collect();
        let n = ((hull.len() as f64).sqrt().ceil() as usize).clamp(1, 256);
        let b = &tin.bbox;
        let cell = [
            ((b.max_x - b.min_x) / n as f64).max(f64::MIN_POSITIVE),
            ((b.max_y - b.min_y) / n as f64).max(f64::MIN_POSITIVE),
        ];
        let mut hb = HullBuckets {
            min: [b.min_x, b.min_y],
            cell,
            n,
            cells: vec![Vec::new(); n * n],
        };
        for t in hull {
            let c = lv.tris[t as usize].map(|v| xy(&tin.verts[v as usize]));
            let (lo, hi) = bounds(&c);
            let (x0, y0, x1, y1) = hb.range(lo, hi);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    hb.cells[y * n + x].push(t);
                }
            }
        }
        hb
    }

    fn range(&self, lo: [f64; 2], hi: [f64; 2]) -> (usize, usize, usize, usize) {
        let f = |v: f64, k: usize| {
            let c = ((v - self.min[k]) / self.cell[k]).floor();
            if c.is_nan() || c < 0.0 {
                0
            } else {
                (c as usize).min(self.n - 1)
            }
        };
        (f(lo[0], 0), f(lo[1], 1), f(hi[0], 0), f(hi[1], 1))
    }

    /// The hull triangles whose boxes may meet the box `lo`..`hi` (those
    /// of the cells it covers; one in several cells comes once per cell).
    pub(super) fn near(&self, lo: [f64; 2], hi: [f64; 2]) -> impl Iterator<Item = u32> + '_ {
        let (x0, y0, x1, y1) = self.range(lo, hi);
        (y0..=y1).flat_map(move |y| {
            (x0..=x1).flat_map(move |x| self.cells[y * self.n + x].iter().copied())
        })
    }
}

fn bounds(c: &[[f64; 2]; 3]) -> ([f64; 2], [f64; 2]) {
    let mut lo = c[0];
    let mut hi = c[0];
    for p in &c[1..] {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    (lo, hi)
}

/// True when the level's domain is convex (one boundary loop, no right
/// turn): the search for the triangles of B meeting a triangle of A relies
/// on `a ∩ B` being connected.
pub fn convex_domain(tin: &Tin, lv: &Level) -> bool {
    let nv = lv.num_vertices as usize;
    let mut next = vec![NONE; nv];
    let mut count = 0usize;
    for (tri, nb) in lv.tris.iter().zip(&lv.nbrs) {
        for j in 0..3 {
            if nb[j] == NONE {
                let (u, v) = (tri[(j + 1) % 3] as usize, tri[(j + 2) % 3] as usize);
                if u >= nv || v >= nv || next[u] != NONE {
                    return false;
                }
                next[u] = v as u32;
                count += 1;
            }
        }
    }
    let Some(start) = next.iter().position(|&n| n != NONE) else {
        return false;
    };
    let (mut prev, mut cur, mut seen) = (start, next[start] as usize, 1usize);
    loop {
        let nx = next[cur];
        if nx == NONE || seen > count {
            return false;
        }
        // convex up to rounding: a raster build's boundary vertex on a
        // hull edge of the pixel lattice may lie a hair inside it
        let v = |i: usize| &tin.verts[i];
        if !crate::geom::left_or_on_rounded(v(prev), v(cur), v(nx as usize)) {
            return false;
        }
        if cur == start {
            break;
        }
        prev = cur;
        cur = nx as usize;
        seen += 1;
    }
    seen == count
}

/// One vertex of a face: output id, position, and the edges of `a` and of
/// `b` it lies on (bit j: the edge opposite corner j).
#[derive(Clone, Copy, Debug)]
struct FaceVertex {
    id: u32,
    p: [f64; 2],
    on_a: u8,
    on_b: u8,
}

/// The edges of b (bits) that pass through the interior of a: at least two
/// face vertices on the edge, not all on one edge of a.
fn through_interior(fv: &[FaceVertex]) -> u8 {
    let mut out = 0u8;
    for j in 0..3 {
        let (mut n, mut common) = (0, 0b111u8);
        for f in fv.iter().filter(|f| (f.on_b >> j) & 1 == 1) {
            n += 1;
            common &= f.on_a;
        }
        if n >= 2 && common == 0 {
            out |= 1 << j;
        }
    }
    out
}

/// A crossing of two edges is the end of one of them when that end is
/// within this many ulps (of the crossing's largest coordinate) of the
/// other edge's line ([`Builder::face`]).
const SNAP_ULPS: f64 = 4.0;

/// Output being built, with the symbolic vertex identities.
struct Builder<'t> {
    a: &'t Tin,
    b: &'t Tin,
    la: &'t Level,
    lb: &'t Level,
    eid_a: Vec<[u32; 3]>,
    eid_b: Vec<[u32; 3]>,
    out_a: Vec<u32>,
    out_b: Vec<u32>,
    cross: FxHashMap<u64, u32>,
    o: Overlay,
    /// Face boundary edges: (smaller id, larger id), forward (smaller ->
    /// larger in the face's direction), and whether it may be unmatched.
    bnd: Vec<(u64, bool, bool)>,
}

impl Builder<'_> {
    fn push(&mut self, p: [f64; 2], za: f64, zb: f64) -> u32 {
        self.o.pts.push(p);
        self.o.za.push(za);
        self.o.zb.push(zb);
        (self.o.pts.len() - 1) as u32
    }

    fn vertex_b(&mut self, vb: u32, ca: &[[f64; 3]; 3]) -> u32 {
        let i = vb as usize;
        if self.out_b[i] == NONE {
            let v = self.b.verts[i];
            self.out_b[i] = self.push([v[0], v[1]], interpolate(ca, v[0], v[1]), v[2]);
        }
        self.out_b[i]
    }

    fn vertex_a(&mut self, va: u32, cb: &[[f64; 3]; 3]) -> u32 {
        let i = va as usize;
        if self.out_a[i] == NONE {
            let v = self.a.verts[i];
            self.out_a[i] = self.push([v[0], v[1]], v[2], interpolate(cb, v[0], v[1]));
        }
        self.out_a[i]
    }

    /// The face `ta ∩ tb`: its vertices are pushed to `fv` (none: the
    /// closed triangles do not meet); returns the edges of `tb` (bits) that
    /// meet the closed `ta`.
    fn face(&mut self, ta: u32, tb: u32, fv: &mut Vec<FaceVertex>) -> u8 {
        fv.clear();
        let (tra, trb) = (self.la.tris[ta as usize], self.lb.tris[tb as usize]);
        let ca3 = tra.map(|v| self.a.verts[v as usize]);
        let cb3 = trb.map(|v| self.b.verts[v as usize]);
        let (ca, cb) = (ca3.map(|v| xy(&v)), cb3.map(|v| xy(&v)));
        // sab[j][i]: corner i of a against the edge of b opposite corner j
        let mut sab = [[0.0f64; 3]; 3];
        let mut sba = [[0.0f64; 3]; 3];
        for j in 0..3 {
            let (u, v) = (co(cb[(j + 1) % 3]), co(cb[(j + 2) % 3]));
            for i in 0..3 {
                sab[j][i] = orient2d(u, v, co(ca[i]));
            }
            let (u, v) = (co(ca[(j + 1) % 3]), co(ca[(j + 2) % 3]));
            for m in 0..3 {
                sba[j][m] = orient2d(u, v, co(cb[m]));
            }
        }
        // corners of a in the closed b
        for i in 0..3 {
            if (0..3).all(|j| sab[j][i] >= 0.0) {
                let mut on_b = 0u8;
                for j in 0..3 {
                    if sab[j][i] == 0.0 {
                        on_b |= 1 << j;
                    }
                }
                let on_a = 0b111 & !(1u8 << i);
                let id = match (0..3).find(|&m| cb[m] == ca[i]) {
                    Some(m) => {
                        let id = self.vertex_b(trb[m], &ca3);
                        self.out_a[tra[i] as usize] = id;
                        id
                    }
                    None => self.vertex_a(tra[i], &cb3),
                };
                fv.push(FaceVertex {
                    id,
                    p: ca[i],
                    on_a,
                    on_b,
                });
            }
        }
        // corners of b in the closed a
        for m in 0..3 {
            if (0..3).all(|k| sba[k][m] >= 0.0) {
                let mut on_a = 0u8;
                for k in 0..3 {
                    if sba[k][m] == 0.0 {
                        on_a |= 1 << k;
                    }
                }
                let on_b = 0b111 & !(1u8 << m);
                let id = self.vertex_b(trb[m], &ca3);
                if let Some(f) = fv.iter_mut().find(|f| f.id == id) {
                    f.on_a |= on_a;
                    f.on_b |= on_b;
                } else {
                    fv.push(FaceVertex {
                        id,
                        p: cb[m],
                        on_a,
                        on_b,
                    });
                }
            }
        }
        // proper crossings of edge k of a with edge j of b
        for k in 0..3 {
            let (i1, i2) = ((k + 1) % 3, (k + 2) % 3);
            for j in 0..3 {
                let (m1, m2) = ((j + 1) % 3, (j + 2) % 3);
                let strict = |x: f64, y: f64| (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0);
                if !(strict(sab[j][i1], sab[j][i2]) && strict(sba[k][m1], sba[k][m2])) {
                    continue;
                }
                let key =
                    ((self.eid_a[ta as usize][k] as u64) << 32) | self.eid_b[tb as usize][j] as u64;
                let id = match self.cross.get(&key) {
                    Some(&id) => id,
                    None => {
                        let (mut p, mut q) = (ca[i1], ca[i2]);
                        if tra[i1] > tra[i2] {
                            std::mem::swap(&mut p, &mut q);
                        }
                        let (mut u, mut v) = (cb[m1], cb[m2]);
                        if trb[m1] > trb[m2] {
                            std::mem::swap(&mut u, &mut v);
                        }
                        let x = crossing(p, q, u, v);
                        // an edge of one tin passing within a few ulps of
                        // an end of the other edge (a vertex of the other
                        // tin) crosses the edges around that vertex in
                        // points that round on or around it: every such
                        // crossing is that vertex (decided on the vertex's
                        // distance to the line, the same for all of them),
                        // and the slivers between them, flat once rounded,
                        // are no faces
                        let mag = x[0].abs().max(x[1].abs());
                        let tol = SNAP_ULPS * f64::EPSILON * mag;
                        let off = |a: [f64; 2], b: [f64; 2], e: [f64; 2]| {
                            let near_x = (e[0] - x[0]).hypot(e[1] - x[1]) <= 1e-6 * mag;
                            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                            near_x && orient2d(co(a), co(b), co(e)).abs() <= tol * len
                        };
                        let id = if off(ca[i1], ca[i2], cb[m1]) {
                            self.vertex_b(trb[m1], &ca3)
                        } else if off(ca[i1], ca[i2], cb[m2]) {
                            self.vertex_b(trb[m2], &ca3)
                        } else if off(cb[m1], cb[m2], ca[i1]) {
                            self.vertex_a(tra[i1], &cb3)
                        } else if off(cb[m1], cb[m2], ca[i2]) {
                            self.vertex_a(tra[i2], &cb3)
                        } else {
                            // heights along the two edges (as the
                            // constrained path has them): exact where an
                            // edge is level, so equal surfaces stay equal
                            self.push(
                                x,
                                z_along(&ca3[i1], &ca3[i2], x),
                                z_along(&cb3[m1], &cb3[m2], x),
                            )
                        };
                        self.cross.insert(key, id);
                        self.o.crossings += 1;
                        id
                    }
                };
                if let Some(f) = fv.iter_mut().find(|f| f.id == id) {
                    f.on_a |= 1 << k;
                    f.on_b |= 1 << j;
                    continue;
                }
                let p = self.o.pts[id as usize];
                fv.push(FaceVertex {
                    id,
                    p,
                    on_a: 1 << k,
                    on_b: 1 << j,
                });
            }
        }
        fv.iter().fold(0u8, |acc, f| acc | f.on_b)
    }

    /// Triangulates the face in `fv` (convex; vertices in any order) and
    /// records its boundary edges.
    fn emit(&mut self, ta: u32, tb: u32, fv: &mut [FaceVertex]) -> Result<(), Refused> {
        let n = fv.len();
        if n < 3 {
            return Ok(());
        }
        // all collinear: a touching segment, no face
        let (p0, p1) = (co(fv[0].p), co(fv[1].p));
        let o2 = orient2d(p0, p1, co(fv[2].p));
        if o2 == 0.0 && fv[3..].iter().all(|f| orient2d(p0, p1, co(f.p)) == 0.0) {
            return Ok(());
        }
        if n == 3 {
            // a triangle: orient it
            if o2 < 0.0 {
                fv.swap(1, 2);
            }
            self.boundary(ta, tb, fv);
            let t = [fv[0], fv[1], fv[2]];
            self.o.tris.push(t.map(|f| f.id));
            self.o.tri_a.push(ta);
            self.o.tri_b.push(tb);
            return Ok(());
        }
        // order around the mean, checked exactly on the rounded points
        let mut c = [0.0, 0.0];
        for f in fv.iter() {
            c[0] += f.p[0];
            c[1] += f.p[1];
        }
        let c = [c[0] / n as f64, c[1] / n as f64];
        let upper = |p: [f64; 2]| p[1] > c[1] || (p[1] == c[1] && p[0] > c[0]);
        let cc = co(c);
        let before = |p: [f64; 2], q: [f64; 2]| -> bool {
            let (hp, hq) = (upper(p), upper(q));
            if hp != hq {
                return hp;
            }
            orient2d(cc, co(p), co(q)) > 0.0
        };
        for i in 1..n {
            let mut k = i;
            while k > 0 && before(fv[k].p, fv[k - 1].p) {
                fv.swap(k, k - 1);
                k -= 1;
            }
        }
        for i in 0..n {
            let (p, q) = (fv[i].p, fv[(i + 1) % n].p);
            if p == c || (i + 1 < n && !before(p, q)) {
                return Err(Refused::Rounding(
                    "face vertices not in strict angular order",
                ));
            }
        }
        self.boundary(ta, tb, fv);
        // ears: a strictly convex corner whose removal leaves a face that
        // is not flat, and whose triangle holds no other vertex of the face
        // (a face convex in exact arithmetic can be a rounding short of
        // convex once its points are rounded or snapped: still a simple
        // polygon, star-shaped around its mean, so it has ears)
        let mut ring: Vec<usize> = (0..n).collect();
        while ring.len() > 3 {
            let r = ring.len();
            let mut cut = None;
            for i in 0..r {
                let (u, v, w) = (
                    fv[ring[(i + r - 1) % r]].p,
                    fv[ring[i]].p,
                    fv[ring[(i + 1) % r]].p,
                );
                if orient2d(co(u), co(v), co(w)) <= 0.0 {
                    continue;
                }
                let holds = (0..r)
                    .filter(|&x| x != i && x != (i + r - 1) % r && x != (i + 1) % r)
                    .map(|x| co(fv[ring[x]].p))
                    .any(|x| {
                        orient2d(co(u), co(v), x) >= 0.0
                            && orient2d(co(v), co(w), x) >= 0.0
                            && orient2d(co(w), co(u), x) >= 0.0
                    });
                if holds {
                    continue;
                }
                let flat = (0..r)
                    .filter(|&x| x != i)
                    .all(|x| orient2d(co(u), co(w), co(fv[ring[x]].p)) == 0.0);
                if !flat {
                    cut = Some(i);
                    break;
                }
            }
            let i = cut.ok_or(Refused::Rounding("no ear in a face"))?;
            let t = [ring[(i + r - 1) % r], ring[i], ring[(i + 1) % r]];
            self.triangle(ta, tb, t.map(|x| fv[x]))?;
            ring.remove(i);
        }
        self.triangle(ta, tb, [fv[ring[0]], fv[ring[1]], fv[ring[2]]])
    }

    /// Records the face's boundary edges (vertices in counter-clockwise
    /// order), with whether each lies on the boundary of A or B.
    fn boundary(&mut self, ta: u32, tb: u32, fv: &[FaceVertex]) {
        let n = fv.len();
        let (na, nb) = (self.la.nbrs[ta as usize], self.lb.nbrs[tb as usize]);
        for i in 0..n {
            let (f, g) = (fv[i], fv[(i + 1) % n]);
            let (sa, sb) = (f.on_a & g.on_a, f.on_b & g.on_b);
            let hull = (0..3).any(|k| (sa >> k) & 1 == 1 && na[k] == NONE)
                || (0..3).any(|j| (sb >> j) & 1 == 1 && nb[j] == NONE);
            let (lo, hi) = (f.id.min(g.id), f.id.max(g.id));
            self.bnd
                .push((((lo as u64) << 32) | hi as u64, f.id < g.id, hull));
        }
    }

    fn triangle(&mut self, ta: u32, tb: u32, t: [FaceVertex; 3]) -> Result<(), Refused> {
        if orient2d(co(t[0].p), co(t[1].p), co(t[2].p)) <= 0.0 {
            return Err(Refused::Rounding("a face triangle is flat or clockwise"));
        }
        self.o.tris.push(t.map(|f| f.id));
        self.o.tri_a.push(ta);
        self.o.tri_b.push(tb);
        Ok(())
    }
}

/// Overlay of A at `level_a` and B at `level_b` by faces `a ∩ b`. B's
/// domain must be convex (checked by the caller with [`convex_domain`]).
/// Each triangle of A finds the triangles of B it meets ([`Search`]), their
/// faces emitted as it goes; then the faces are checked to agree on their
/// common boundaries ([`check_conformity`]) and the points no face uses
/// dropped ([`drop_unused`]).
pub(crate) fn overlay_faces(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Overlay, Refused> {
    let mut tk = Ticker::new(interrupt);
    let (la, lb) = (&a.levels[level_a], &b.levels[level_b]);
    let mut bd = Builder {
        a,
        b,
        la,
        lb,
        eid_a: edge_ids(la)?,
        eid_b: edge_ids(lb)?,
        out_a: vec![NONE; la.num_vertices as usize],
        out_b: vec![NONE; lb.num_vertices as usize],
        cross: FxHashMap::default(),
        o: Overlay::default(),
        bnd: Vec::with_capacity(4 * (la.tris.len() + lb.tris.len())),
    };
    let mut search = Search {
        b,
        level_b,
        hull: HullBuckets::new(b, lb),
        loc: vec![UNSET; la.num_vertices as usize],
        fv: Vec::with_capacity(12),
        seen: Vec::with_capacity(32),
        queue: Vec::with_capacity(32),
    };
    let bb = &b.bbox;
    for ta in 0..la.tris.len() as u32 {
        tk.tick()?;
        let tra = la.tris[ta as usize];
        let c = tra.map(|v| xy(&a.verts[v as usize]));
        let (lo, hi) = bounds(&c);
        if hi[0] < bb.min_x || lo[0] > bb.max_x || hi[1] < bb.min_y || lo[1] > bb.max_y {
            continue;
        }
        let interior = search.start(tra, &c, (lo, hi));
        search.faces(&mut bd, ta, interior)?;
    }
    let bnd = sorted_boundary(std::mem::take(&mut bd.bnd), bd.o.pts.len(), &mut tk)?;
    check_conformity(&bnd, &mut tk)?;
    let mut o = bd.o;
    drop_unused(&mut o);
    Ok(o)
}

/// [`Search::loc`]: not looked up yet.
const UNSET: u32 = NONE - 1;

/// The search, for each triangle `a` of A, of the triangles of B it meets.
struct Search<'t> {
    b: &'t Tin,
    level_b: usize,
    hull: HullBuckets,
    /// the triangle of B holding each vertex of A (NONE: outside; UNSET:
    /// not looked up yet)
    loc: Vec<u32>,
    fv: Vec<FaceVertex>,
    seen: Vec<u32>,
    queue: Vec<u32>,
}

impl Search<'_> {
    /// The search's first triangles of B for the triangle of A with
    /// vertices `tra` at `c` (bounding box `lo`, `hi`); whether the search
    /// may stay in its interior. The triangle of B holding a's centroid
    /// overlaps a with positive area; from it, the search crosses only
    /// edges of b passing through the interior of a (the faces of positive
    /// area are connected that way: a ∩ B is convex). A centroid that
    /// rounding put outside a, or that is outside B (a sticks out of B),
    /// falls back to the search over every triangle of B meeting the closed
    /// a, seeded from a corner or from B's hull.
    fn start(&mut self, tra: [u32; 3], c: &[[f64; 2]; 3], (lo, hi): ([f64; 2], [f64; 2])) -> bool {
        let (b, level_b) = (self.b, self.level_b);
        self.queue.clear();
        self.seen.clear();
        let g = [
            (c[0][0] + c[1][0] + c[2][0]) / 3.0,
            (c[0][1] + c[1][1] + c[2][1]) / 3.0,
        ];
        let inside_a = (0..3).all(|k| orient2d(co(c[k]), co(c[(k + 1) % 3]), co(g)) > 0.0);
        let mut interior = false;
        if inside_a {
            let s = locate::start_triangle(b, level_b, g[0], g[1]);
            if let locate::Walk::Inside(t) = locate::walk(b, level_b, s, g[0], g[1]) {
                self.queue.push(t);
                interior = true;
            }
        }
        if !interior {
            for (k, &v) in tra.iter().enumerate() {
                let v = v as usize;
                if self.loc[v] == UNSET {
                    let s = locate::start_triangle(b, level_b, c[k][0], c[k][1]);
                    self.loc[v] = match locate::walk(b, level_b, s, c[k][0], c[k][1]) {
                        locate::Walk::Inside(t) => t,
                        locate::Walk::Outside(_) => NONE,
                    };
                }
                if self.loc[v] != NONE {
                    self.queue.push(self.loc[v]);
                    break;
                }
            }
        }
        if self.queue.is_empty() {
            for t in self.hull.near(lo, hi) {
                if !self.queue.contains(&t) {
                    self.queue.push(t);
                }
            }
        }
        self.seen.extend_from_slice(&self.queue);
        interior
    }

    /// The faces of triangle `ta` of A with the triangles of B, from the
    /// queue [`Search::start`] filled, over B's adjacency: through edges
    /// of b crossing a's interior when `interior`, else through those
    /// meeting the closed a.
    fn faces(&mut self, bd: &mut Builder<'_>, ta: u32, interior: bool) -> Result<(), Refused> {
        let lb = bd.lb;
        let mut qi = 0;
        while qi < self.queue.len() {
            let tb = self.queue[qi];
            qi += 1;
            let meets = bd.face(ta, tb, &mut self.fv);
            if self.fv.is_empty() {
                continue;
            }
            let next = if interior {
                through_interior(&self.fv)
            } else {
                meets
            };
            bd.emit(ta, tb, &mut self.fv)?;
            let nb = lb.nbrs[tb as usize];
            for j in 0..3 {
                if (next >> j) & 1 == 1 && nb[j] != NONE && !self.seen.contains(&nb[j]) {
                    self.seen.push(nb[j]);
                    self.queue.push(nb[j]);
                }
            }
        }
        Ok(())
    }
}

/// The faces' boundary edges ([`Builder::bnd`]) sorted by key, bucket by
/// bucket (by the smaller vertex id of `npts`, so equal keys share a
/// bucket), with an interrupt check between buckets.
fn sorted_boundary(
    src: Vec<(u64, bool, bool)>,
    npts: usize,
    tk: &mut Ticker<'_, '_>,
) -> Result<Vec<(u64, bool, bool)>, Refused> {
    let nb = 64usize;
    let span = npts as u64 + 1;
    let bucket = |k: u64| ((k >> 32) * nb as u64 / span) as usize;
    let mut start = vec![0usize; nb + 1];
    for e in &src {
        start[bucket(e.0) + 1] += 1;
    }
    for i in 0..nb {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut out = vec![(0u64, false, false); src.len()];
    for e in src {
        let b = bucket(e.0);
        out[fill[b]] = e;
        fill[b] += 1;
    }
    for b in 0..nb {
        tk.check()?;
        out[start[b]..start[b + 1]].sort_unstable_by_key(|e| e.0);
    }
    Ok(out)
}

/// Conformity: every face boundary edge twice in opposite directions, or
/// once on the boundary of A or B (`bnd` sorted by key).
fn check_conformity(bnd: &[(u64, bool, bool)], tk: &mut Ticker<'_, '_>) -> Result<(), Refused> {
    let mut i = 0;
    while i < bnd.len() {
        tk.tick()?;
        let mut k = i + 1;
        while k < bnd.len() && bnd[k].0 == bnd[i].0 {
            k += 1;
        }
        let ok = match k - i {
            1 => bnd[i].2,
            2 => bnd[i].1 != bnd[i + 1].1,
            _ => false,
        };
        if !ok {
            return Err(Refused::Rounding(
                "two faces disagree on their common boundary",
            ));
        }
        i = k;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tin::build::from_triangles;

    /// A unit-square grid of n x n cells, two triangles per cell, with the
    /// cells in `skip` left out.
    fn grid(n: u32, skip: &[(u32, u32)]) -> Tin {
        let mut verts = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                verts.push([i as f64, j as f64, (i + 2 * j) as f64]);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if !skip.contains(&(i, j)) {
                    tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        from_triangles(verts, tris, 0, &mut || Ok(())).unwrap()
    }

    #[test]
    fn convex_domains_are_recognised() {
        let g = grid(3, &[]);
        assert!(convex_domain(&g, &g.levels[0]));
        // an L shape: a right turn at the missing corner cell
        let l = grid(3, &[(2, 2)]);
        assert!(!convex_domain(&l, &l.levels[0]));
        // a hole: two boundary loops
        let h = grid(3, &[(1, 1)]);
        assert!(!convex_domain(&h, &h.levels[0]));
    }

    #[test]
    fn edges_through_the_interior() {
        let v = |id, on_a, on_b| FaceVertex {
            id,
            p: [0.0, 0.0],
            on_a,
            on_b,
        };
        // edge 0 of b crosses a (two crossings on different edges of a);
        // edge 1 runs along edge 2 of a; edge 2 only touches at one point
        let fv = [
            v(1, 0b001, 0b001),
            v(2, 0b010, 0b001),
            v(3, 0b100, 0b110),
            v(4, 0b100, 0b010),
        ];
        assert_eq!(through_interior(&fv), 0b001);
    }

    #[test]
    fn faces_of_two_grids_tile_the_common_square() {
        // B: the grid shifted by (0.5, 0.25): crossings everywhere
        let a = grid(4, &[]);
        let mut b = grid(4, &[]);
        for v in &mut b.verts {
            v[0] += 0.5;
            v[1] += 0.25;
        }
        b.bbox = crate::tin::Bbox::of(&b.verts);
        let o = overlay_faces(&a, 0, &b, 0, &mut || Ok(())).unwrap();
        let area: f64 = (0..o.tris.len()).map(|t| o.area(t)).sum();
        assert!((area - 3.5 * 3.75).abs() < 1e-12, "{area}");
        assert!(o.tris.iter().enumerate().all(|(t, _)| o.area(t) > 0.0));
        // every output triangle inside its labelled triangles (corners of
        // the output triangle in the closed input triangles, exactly)
        for (t, tri) in o.tris.iter().enumerate() {
            for (tin, owner) in [(&a, o.tri_a[t]), (&b, o.tri_b[t])] {
                let c = tin.corners(0, owner).map(|v| co([v[0], v[1]]));
                for &v in tri {
                    let p = co(o.pts[v as usize]);
                    for j in 0..3 {
                        // crossings are rounded: allow a few ulps
                        assert!(orient2d(c[j], c[(j + 1) % 3], p) > -1e-12);
                    }
                }
            }
        }
        // B touching A at one corner: no face, and no stray vertex
        for v in &mut b.verts {
            v[0] += 3.5;
            v[1] += 3.75;
        }
        b.bbox = crate::tin::Bbox::of(&b.verts);
        let o = overlay_faces(&a, 0, &b, 0, &mut || Ok(())).unwrap();
        assert!(o.tris.is_empty() && o.pts.is_empty(), "{o:?}");
        // a disjoint B gives nothing
        for v in &mut b.verts {
            v[0] += 10.0;
        }
        b.bbox = crate::tin::Bbox::of(&b.verts);
        let o = overlay_faces(&a, 0, &b, 0, &mut || Ok(())).unwrap();
        assert!(o.tris.is_empty());
    }
}
