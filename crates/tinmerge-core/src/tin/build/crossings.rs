//! Whether a vertex may stand at a crossing no sample mends
//! ([`Builder::measure`]'s last candidate): on a raster
//! ([`Builder::raster_crossing_ok`]) and among scattered samples
//! ([`Builder::free_crossing_ok`]), both keeping the triangles it would
//! make from being thin (on a raster in pixels, [`near_face_lines`];
//! among scattered samples in proportion to the faces it splits).

use super::builder::Builder;
use super::common::*;
use crate::tin::samples::Samples;
use crate::tin::surface::Crossing;
use spade::handles::{FaceHandle, FixedDirectedEdgeHandle, InnerTag};

impl<S: Samples, T: Tri> Builder<'_, S, T> {
    /// On a raster, where no pixel mends the crossing `x` of edge `e`
    /// (`u` to `w`): the two pixels of the segment are vertices and the
    /// edge between two others crosses it all the same, or the segment runs
    /// from a pixel to a side's vertex where it crosses that side (a ring's
    /// crossing: its other pixel is outside), crossed in between. Whether a
    /// vertex at the crossing may be inserted: at least a hundredth of a
    /// pixel from the ends of that stretch and from the lines of the
    /// triangles it makes (a vertex anywhere made triangles under 1e-3
    /// pixel high: pg_regress `exactness.sql`).
    pub(super) fn raster_crossing_ok(
        &self,
        e: FixedDirectedEdgeHandle,
        u: &[f64; 3],
        w: &[f64; 3],
        x: &Crossing,
    ) -> bool {
        let (u, w) = (*u, *w);
        let [p0, p1] = x.seg;
        let (seg_len, along) = along_segment(x);
        let faces = self.faces_beside(e);
        // the side's vertex on the segment, and whether a fixed
        // edge runs through the crossing or across the segment
        let (mut stop, mut across, mut on_fixed) = (None::<f64>, false, false);
        for f in &faces {
            for g in f.adjacent_edges() {
                if !self.fixed_edge(g.fix()) {
                    continue;
                }
                let [a, b] = g.vertices().map(|v| self.vert3(v.fix()));
                for q in [a, b] {
                    let t = along(&q);
                    if crate::geom::is_sliver(&p0, &p1, &q) && t > 0.0 && t < 1.0 {
                        stop = Some(t);
                    }
                }
                // never on a fixed edge up to rounding (its other
                // parent would not have the vertex)
                on_fixed |= crate::geom::is_sliver(&a, &b, &x.p);
                across |= crosses_between(&a, &b, &p0, &p1);
            }
        }
        let (lo, hi) = match stop {
            _ if on_fixed => (1.0, 0.0),
            Some(t) if x.s < t => (0.0, t),
            Some(t) => (t, 1.0),
            None if across => (1.0, 0.0),
            None => (0.0, 1.0),
        };
        // the triangles the vertex makes: its distance to the
        // lines from the crossed edge's ends to the faces' third
        // corners
        let thirds = faces.iter().map(|f| {
            f.vertices()
                .iter()
                .map(|v| self.vert3(v.fix()))
                .find(|q| q[..2] != u[..2] && q[..2] != w[..2])
        });
        let thin = near_face_lines(thirds, &u, &w, &x.p, 0.01 * seg_len);
        x.s > lo + 0.01 && x.s < hi - 0.01 && !thin
    }

    /// Where samples are not all there is (no sample can mend the crossing
    /// `x` of edge `e`): whether the crossing itself, on the reference, may
    /// be inserted (a rounding off this edge, the Delaunay triangulation
    /// flips the edge away rather than keep a sliver). A triangulation's
    /// edge between two samples need not be an edge of a triangulation of
    /// fewer of them (a vertex at a crossing can stand inside its circle),
    /// nor a grid segment between a pixel and a ring's crossing an edge at
    /// all, so inserting samples alone need not end it.
    pub(super) fn free_crossing_ok(&self, e: FixedDirectedEdgeHandle, x: &Crossing) -> bool {
        let faces = self.faces_beside(e);
        let near_fixed = faces.iter().any(|f| {
            f.adjacent_edges().iter().any(|g| {
                let [a, b] = g.vertices().map(|v| self.vert3(v.fix()));
                self.fixed_edge(g.fix())
                    && (crate::geom::is_sliver(&a, &b, &x.p)
                        || crosses_away(&a, &b, &x.seg[0], &x.seg[1]))
            })
        });
        // nor within a thousandth of the shorter of the crossed segment
        // and the crossed edge of the segment's ends (two samples) or of a
        // vertex already on it (vertices at crossings closing in on one
        // point until rounding made a crack: harness seed 2006391; in the
        // segment's length alone, a segment a hundred times the edge,
        // between two scan lines of a LiDAR-like cloud, refused a crossing
        // 2 m from a side's vertex on it: seed 73484), nor within a
        // ten-thousandth of the crossed edge of its ends: the triangles it
        // makes are then at least that part as thick as the faces they
        // split (their altitude over a line from an end to a face's third
        // corner is the crossing's part of the edge times the face's own).
        // A bound in the crossed segment's length instead refused every
        // crossing inside a needle along the samples' hull, a hundredth of
        // a pixel high, and left the level over its tolerance (seed 73000);
        // a hundredth for the gaps, crossings 0.6 % along a segment from a
        // sample that is a vertex (seed 73002).
        let [p0, p1] = x.seg;
        let (seg_len, along) = along_segment(x);
        const GAP: f64 = 1e-3;
        const THIN: f64 = 1e-4;
        let [eu, ew] = self
            .dt
            .directed_edge(e)
            .vertices()
            .map(|v| self.vert3(v.fix()));
        let gap = GAP * seg_len.min((ew[0] - eu[0]).hypot(ew[1] - eu[1])) / seg_len;
        let near_end = x.s.min(1.0 - x.s) < gap;
        let on_seg = faces.iter().any(|f| {
            f.vertices().iter().any(|v| {
                let q = self.vert3(v.fix());
                crate::geom::is_sliver(&p0, &p1, &q) && (along(&q) - x.s).abs() < gap
            })
        });
        let thin = x.t.min(1.0 - x.t) < THIN;
        !near_fixed && !near_end && !on_seg && !thin
    }
}

impl<S: Samples, T: Tri> Builder<'_, S, T> {
    /// The inner faces on either side of edge `e`.
    fn faces_beside(&self, e: FixedDirectedEdgeHandle) -> Vec<InnerFace<'_, T>> {
        let e = self.dt.directed_edge(e);
        [e.face(), e.rev().face()]
            .iter()
            .filter_map(|f| f.as_inner())
            .collect()
    }
}

/// An inner face of a builder's triangulation.
type InnerFace<'a, T> = FaceHandle<
    'a,
    InnerTag,
    <T as spade::Triangulation>::Vertex,
    <T as spade::Triangulation>::DirectedEdge,
    <T as spade::Triangulation>::UndirectedEdge,
    <T as spade::Triangulation>::Face,
>;

/// The crossed segment's length, and where a point lies along it (0 at
/// its first end, 1 at its second, by projection).
fn along_segment(x: &Crossing) -> (f64, impl Fn(&[f64; 3]) -> f64) {
    let [p0, p1] = x.seg;
    let seg_len = (p1[0] - p0[0]).hypot(p1[1] - p0[1]);
    let along = move |q: &[f64; 3]| {
        ((q[0] - p0[0]) * (p1[0] - p0[0]) + (q[1] - p0[1]) * (p1[1] - p0[1])) / (seg_len * seg_len)
    };
    (seg_len, along)
}

/// Whether a vertex at `p` on the edge `u`-`w` would be within `min_h` of
/// a line from `u` or `w` to the third corner of a face beside the edge
/// (`thirds`; None: a face without one, which counts as near): the
/// triangles it would make would be that thin.
fn near_face_lines(
    thirds: impl Iterator<Item = Option<[f64; 3]>>,
    u: &[f64; 3],
    w: &[f64; 3],
    p: &[f64; 3],
    min_h: f64,
) -> bool {
    thirds.into_iter().any(|o| {
        o.is_none_or(|o| {
            [u, w].iter().any(|q| {
                crate::geom::point_segment_distance([p[0], p[1]], [q[0], q[1]], [o[0], o[1]])
                    < min_h
            })
        })
    })
}

/// [`crosses_between`], and neither `a` nor `b` on the line of `p`-`q` up
/// to rounding: a side split where the segment crosses it has its vertex
/// a rounding off the segment's line, which put the crossing 5e-9 of the
/// piece from that end when the piece's other end is a hundredth of a
/// pixel from the line (harness seed 73029: a LiDAR-like cloud left over
/// its tolerance, every vertex in the strip refused).
fn crosses_away(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3], q: &[f64; 3]) -> bool {
    !(crate::geom::is_sliver(p, q, a) || crate::geom::is_sliver(p, q, b))
        && crosses_between(a, b, p, q)
}

/// Whether segment `p`-`q` crosses segment `a`-`b` away from `a` and `b`
/// (more than 1e-9 of its length from them): through one of them, it
/// meets that vertex.
fn crosses_between(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3], q: &[f64; 3]) -> bool {
    let (oa, ob) = (crate::geom::orient(p, q, a), crate::geom::orient(p, q, b));
    let (op, oq) = (crate::geom::orient(a, b, p), crate::geom::orient(a, b, q));
    if !(oa * ob < 0.0 && op * oq < 0.0) {
        return false;
    }
    let s = oa / (oa - ob);
    s > 1e-9 && s < 1.0 - 1e-9
}
