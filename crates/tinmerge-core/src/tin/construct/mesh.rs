//! The triangulation the greedy refinement works on: flat arrays of
//! half-edges, three a triangle (half-edge `h` runs from `v[h]` to the start
//! of the next half-edge of its triangle), each with its twin (`NONE` on
//! the hull) and whether it is locked (an edge of a coarser level: never
//! flipped, split only at points on it, both halves locked). Triangles are
//! changed in place and new ones appended: a slot never dies, so a level's
//! triangles are the slots that exist when it ends.
//!
//! Points are lattice coordinates (column, row, height): pixel centres are
//! whole numbers, exact; a vertex at a crossing of a locked edge with a
//! grid line is the rounded crossing. Every test of which side a point is
//! on is `robust`'s exact orientation of those numbers.

use crate::geom::{is_sliver, orient};

/// No twin: the half-edge is on the hull.
pub(super) const NONE: u32 = u32::MAX;

/// Whether a, b, c make a proper triangle: counter-clockwise and not of
/// zero area up to rounding (what every new triangle must be).
#[inline]
pub(super) fn proper(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    orient(a, b, c) > 0.0 && !is_sliver(a, b, c)
}

#[inline]
pub(super) fn next(h: u32) -> u32 {
    if h % 3 == 2 { h - 2 } else { h + 1 }
}

#[inline]
pub(super) fn prev(h: u32) -> u32 {
    if h.is_multiple_of(3) { h + 2 } else { h - 1 }
}

pub(super) struct Mesh {
    /// vertices: column, row, height
    pub(super) pts: Vec<[f64; 3]>,
    /// each half-edge's first vertex
    pub(super) v: Vec<u32>,
    pub(super) twin: Vec<u32>,
    pub(super) locked: Vec<bool>,
    /// each triangle's parent: its triangle at the last level made
    pub(super) parent: Vec<u32>,
    /// a half-edge leaving each vertex
    pub(super) out: Vec<u32>,
}

impl Mesh {
    pub(super) fn new() -> Self {
        Mesh {
            pts: Vec::new(),
            v: Vec::new(),
            twin: Vec::new(),
            locked: Vec::new(),
            parent: Vec::new(),
            out: Vec::new(),
        }
    }

    pub(super) fn triangles(&self) -> u32 {
        (self.v.len() / 3) as u32
    }

    /// The three corners of triangle `t`, counter-clockwise.
    #[inline]
    pub(super) fn corners(&self, t: u32) -> [[f64; 3]; 3] {
        let h = 3 * t as usize;
        [
            self.pts[self.v[h] as usize],
            self.pts[self.v[h + 1] as usize],
            self.pts[self.v[h + 2] as usize],
        ]
    }

    /// The point at half-edge `h`'s start.
    #[inline]
    pub(super) fn at(&self, h: u32) -> &[f64; 3] {
        &self.pts[self.v[h as usize] as usize]
    }

    pub(super) fn add_point(&mut self, p: [f64; 3]) -> u32 {
        self.pts.push(p);
        self.out.push(NONE);
        (self.pts.len() - 1) as u32
    }

    /// A new triangle a, b, c (counter-clockwise), unlinked.
    pub(super) fn add_triangle(&mut self, a: u32, b: u32, c: u32, parent: u32) -> u32 {
        let t = self.triangles();
        self.v.extend_from_slice(&[a, b, c]);
        self.twin.extend_from_slice(&[NONE; 3]);
        self.locked.extend_from_slice(&[false; 3]);
        self.parent.push(parent);
        self.set_out(t);
        t
    }

    /// A new triangle of vertices `tri` turned counter-clockwise, unlinked.
    pub(super) fn add_ccw(&mut self, tri: [u32; 3], parent: u32) -> u32 {
        let c = tri.map(|v| self.pts[v as usize]);
        if orient(&c[0], &c[1], &c[2]) > 0.0 {
            self.add_triangle(tri[0], tri[1], tri[2], parent)
        } else {
            self.add_triangle(tri[0], tri[2], tri[1], parent)
        }
    }

    /// Record triangle `t`'s half-edges as leaving their vertices.
    #[inline]
    pub(super) fn refresh_out(&mut self, t: u32) {
        self.set_out(t)
    }

    #[inline]
    fn set_out(&mut self, t: u32) {
        for h in 3 * t..3 * t + 3 {
            self.out[self.v[h as usize] as usize] = h;
        }
    }

    /// Make `h` and `g` twins (`g` may be `NONE`), locked or not.
    #[inline]
    pub(super) fn link(&mut self, h: u32, g: u32, locked: bool) {
        self.twin[h as usize] = g;
        self.locked[h as usize] = locked;
        if g != NONE {
            self.twin[g as usize] = h;
            self.locked[g as usize] = locked;
        }
    }

    /// Link every half-edge with its twin, by the vertex pair (the first
    /// triangulation).
    pub(super) fn link_all(&mut self) {
        let mut by_pair = std::collections::HashMap::new();
        for h in 0..self.v.len() as u32 {
            by_pair.insert((self.v[h as usize], self.v[next(h) as usize]), h);
        }
        for h in 0..self.v.len() as u32 {
            let key = (self.v[next(h) as usize], self.v[h as usize]);
            if let Some(&g) = by_pair.get(&key) {
                self.twin[h as usize] = g;
            }
        }
    }

    /// Split triangle `t` at point `p` strictly inside it into three;
    /// returns the three half-edges opposite `p`.
    pub(super) fn split3(&mut self, t: u32, p: u32) -> [u32; 3] {
        let h0 = 3 * t;
        let (a, b, c) = (
            self.v[h0 as usize],
            self.v[h0 as usize + 1],
            self.v[h0 as usize + 2],
        );
        let (o1, l1) = (self.twin[h0 as usize + 1], self.locked[h0 as usize + 1]);
        let (o2, l2) = (self.twin[h0 as usize + 2], self.locked[h0 as usize + 2]);
        let par = self.parent[t as usize];
        let t1 = self.add_triangle(b, c, p, par);
        let t2 = self.add_triangle(c, a, p, par);
        self.v[h0 as usize + 1] = b;
        self.v[h0 as usize + 2] = p;
        // t: a->b (kept), b->p, p->a
        self.link(3 * t1, o1, l1);
        self.link(3 * t2, o2, l2);
        self.link(h0 + 1, 3 * t1 + 2, false);
        self.link(3 * t1 + 1, 3 * t2 + 2, false);
        self.link(3 * t2 + 1, h0 + 2, false);
        self.set_out(t);
        [h0, 3 * t1, 3 * t2]
    }

    /// Split the edge of half-edge `h` (a -> b) at point `p` on it: its
    /// triangle and its twin's each into two, the halves locked as the
    /// edge was. Returns the half-edges opposite `p` (two or four).
    pub(super) fn split_edge(&mut self, h: u32, p: u32, out: &mut Vec<u32>) {
        let g = self.twin[h as usize];
        let lock = self.locked[h as usize];
        let (hn, hp) = (next(h), prev(h));
        let (b, c) = (self.v[hn as usize], self.v[hp as usize]);
        let (o_bc, l_bc) = (self.twin[hn as usize], self.locked[hn as usize]);
        let t = h / 3;
        // t becomes a, p, c; t1 is p, b, c
        let t1 = self.add_triangle(p, b, c, self.parent[t as usize]);
        self.v[hn as usize] = p;
        self.link(3 * t1 + 1, o_bc, l_bc);
        self.link(hn, 3 * t1 + 2, false);
        self.set_out(t);
        out.push(hp);
        out.push(3 * t1 + 1);
        if g == NONE {
            self.link(h, NONE, lock);
            self.link(3 * t1, NONE, lock);
            return;
        }
        let (gn, gp) = (next(g), prev(g));
        let (a, d) = (self.v[gn as usize], self.v[gp as usize]);
        let (o_ad, l_ad) = (self.twin[gn as usize], self.locked[gn as usize]);
        let u = g / 3;
        // u (b, a, d) becomes b, p, d; t2 is p, a, d
        let t2 = self.add_triangle(p, a, d, self.parent[u as usize]);
        self.v[gn as usize] = p;
        self.link(3 * t2 + 1, o_ad, l_ad);
        self.link(gn, 3 * t2 + 2, false);
        self.set_out(u);
        self.link(h, 3 * t2, lock);
        self.link(g, 3 * t1, lock);
        out.push(gp);
        out.push(3 * t2 + 1);
    }

    /// Fold away the sliver of half-edge `e` (u -> w, in u, w, p with `p`
    /// on the line u - w up to rounding, between its ends): the triangle
    /// across (w, u, x) is split at `p` into p, u, x (in the sliver's
    /// slot) and w, p, x, and the sliver is gone. The halves p - u and
    /// w - p each join what was on both sides, locked when either was
    /// (an edge the split made and the edge folded). Both new triangles
    /// take the parent of the one across. Returns the free half-edge
    /// x -> p, to be legalized; `None`, with nothing changed, on the hull
    /// or when a new triangle would not be proper.
    pub(super) fn fold(&mut self, e: u32) -> Option<u32> {
        let f = self.twin[e as usize];
        if f == NONE {
            return None;
        }
        let (s, t) = (e / 3, f / 3);
        let (u, w, p) = (
            self.v[e as usize],
            self.v[next(e) as usize],
            self.v[prev(e) as usize],
        );
        let x = self.v[prev(f) as usize];
        let pt = |v: u32| &self.pts[v as usize];
        if !proper(pt(p), pt(u), pt(x)) || !proper(pt(w), pt(p), pt(x)) {
            return None;
        }
        let lock_e = self.locked[e as usize];
        let (o_wp, l_wp) = (self.twin[next(e) as usize], self.locked[next(e) as usize]);
        let (o_pu, l_pu) = (self.twin[prev(e) as usize], self.locked[prev(e) as usize]);
        let (o_ux, l_ux) = (self.twin[next(f) as usize], self.locked[next(f) as usize]);
        let (o_xw, l_xw) = (self.twin[prev(f) as usize], self.locked[prev(f) as usize]);
        let parent = self.parent[t as usize];
        // s: p -> u, u -> x, x -> p; t: w -> p, p -> x, x -> w
        let (h0, g0) = (3 * s, 3 * t);
        self.v[h0 as usize..h0 as usize + 3].copy_from_slice(&[p, u, x]);
        self.v[g0 as usize..g0 as usize + 3].copy_from_slice(&[w, p, x]);
        self.parent[s as usize] = parent;
        self.link(h0, o_pu, l_pu || lock_e);
        self.link(h0 + 1, o_ux, l_ux);
        self.link(g0, o_wp, l_wp || lock_e);
        self.link(g0 + 2, o_xw, l_xw);
        self.link(h0 + 2, g0 + 1, false);
        self.set_out(s);
        self.set_out(t);
        Some(h0 + 2)
    }

    /// Whether the free edge of `h` (a -> b, apex c; twin's apex d) may be
    /// flipped to c - d: both new triangles counter-clockwise and not
    /// slivers.
    pub(super) fn flippable(&self, h: u32) -> bool {
        let g = self.twin[h as usize];
        if g == NONE || self.locked[h as usize] {
            return false;
        }
        let (a, b) = (self.at(h), self.at(next(h)));
        let (c, d) = (self.at(prev(h)), self.at(prev(g)));
        proper(a, d, c) && proper(d, b, c)
    }

    /// Whether the edge of `h` is not locally Delaunay: the apex across it
    /// inside the circle of `h`'s triangle.
    pub(super) fn wants_flip(&self, h: u32) -> bool {
        let g = self.twin[h as usize];
        if g == NONE || self.locked[h as usize] {
            return false;
        }
        let (a, b, c, d) = (
            self.at(h),
            self.at(next(h)),
            self.at(prev(h)),
            self.at(prev(g)),
        );
        crate::geom::in_circle(a, b, c, d)
    }

    /// Flip the free edge of `h` (a -> b in a, b, c; b -> a in b, a, d) to
    /// c - d: the triangles become a, d, c and b, c, d. Returns the two
    /// half-edges opposite c (a -> d, d -> b).
    pub(super) fn flip(&mut self, h: u32) -> [u32; 2] {
        let g = self.twin[h as usize];
        let (hn, gn, gp) = (next(h), next(g), prev(g));
        let c = self.v[prev(h) as usize];
        let d = self.v[gp as usize];
        let (o_bc, l_bc) = (self.twin[hn as usize], self.locked[hn as usize]);
        let (o_ad, l_ad) = (self.twin[gn as usize], self.locked[gn as usize]);
        // h: a -> d, hn: d -> c, prev(h): c -> a (kept)
        self.v[hn as usize] = d;
        // g: b -> c, gn: c -> d, gp: d -> b (kept)
        self.v[gn as usize] = c;
        self.link(h, o_ad, l_ad);
        self.link(g, o_bc, l_bc);
        self.link(hn, gn, false);
        self.set_out(h / 3);
        self.set_out(g / 3);
        [h, gp]
    }
}
