//! The surface a point build follows between its samples: the Delaunay
//! triangulation of all of them.
//!
//! Scattered samples (`tin_from_points`, its aggregate, point-cloud
//! patches) say nothing about the ground between them but what a
//! triangulation of them says, and the Delaunay triangulation is the one
//! every tool makes of them (scipy, matplotlib, CGAL, PDAL, GDAL's
//! `gdal_grid -a linear`). A coarser level is linear inside each of its
//! triangles, as the reference is inside each of its own, so the error of a
//! level against it is largest at the reference's vertices (the samples,
//! measured as samples) or where an edge of the level crosses an edge of
//! the reference ([`Reference::for_each_crossing`]): those bound it on the
//! whole surface.
//!
//! ```
//! use tinmerge_core::tin::delaunay_ref::DelaunayReference;
//! use tinmerge_core::tin::surface::Reference;
//! // a rhombus: its Delaunay triangulation takes the short diagonal
//! // (2, -1)-(2, 1), whose far end is 4 m high
//! let r = DelaunayReference::new(&[
//!     [0.0, 0.0, 0.0], [2.0, -1.0, 0.0], [4.0, 0.0, 0.0], [2.0, 1.0, 4.0],
//! ]).unwrap();
//! let mut seen = Vec::new();
//! // the long diagonal crosses it at its middle: 2 m there
//! r.for_each_crossing(&[0.0, 0.0, 0.0], &[4.0, 0.0, 0.0], &mut |c| seen.push(c.p));
//! assert_eq!(seen, [[2.0, 0.0, 2.0]]);
//! //! ```

use super::TinError;
use super::surface::{Crossing, Reference};
use spade::{
    DelaunayTriangulation, FloatTriangulation, HasPosition, HierarchyHintGenerator, Intersection,
    LineIntersectionIterator, Point2, Triangulation,
};

/// A sample of the reference: position and height.
#[derive(Clone, Copy, Debug)]
struct Sample {
    p: Point2<f64>,
    z: f64,
}

impl HasPosition for Sample {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.p
    }
}

/// The Delaunay triangulation of samples, as a build's reference
/// ([`super::construct::build_points`]). About 200 bytes a sample
/// ([`DelaunayReference::BYTES_PER_SAMPLE`]).
pub struct DelaunayReference {
    dt: DelaunayTriangulation<Sample, (), (), (), HierarchyHintGenerator<f64>>,
    /// edges left out ([`DelaunayReference::cut_by`]), by their two ends'
    /// bits, the smaller in (x, y) first
    cut: rustc_hash::FxHashSet<EdgeKey>,
}

/// An edge of the reference by its two ends' (x, y) bits, the smaller
/// first.
type EdgeKey = [u64; 4];

fn edge_key(p: &[f64; 3], q: &[f64; 3]) -> EdgeKey {
    let (p, q) = if (q[0], q[1]) < (p[0], p[1]) {
        (q, p)
    } else {
        (p, q)
    };
    [
        p[0].to_bits(),
        p[1].to_bits(),
        q[0].to_bits(),
        q[1].to_bits(),
    ]
}

/// Where along an edge (0 to 1) a crossing is that edge's end: within it
/// of an end, the end (a sample, or a vertex at a crossing) is measured as
/// itself.
const AT_END: f64 = 1e-9;

impl DelaunayReference {
    /// Heap a reference holds per sample, about (for a build's memory
    /// estimate).
    pub const BYTES_PER_SAMPLE: usize = 200;

    /// The Delaunay triangulation of `samples` (x, y, z; finite, distinct
    /// in x, y: [`super::build::prepare_samples`]'s).
    pub fn new(samples: &[[f64; 3]]) -> Result<DelaunayReference, TinError> {
        let pts: Vec<Sample> = samples
            .iter()
            .map(|s| Sample {
                p: Point2::new(s[0], s[1]),
                z: s[2],
            })
            .collect();
        let dt = DelaunayTriangulation::bulk_load_stable(pts).map_err(|e| {
            TinError::InvalidParameter(format!("cannot triangulate the samples: {e:?}"))
        })?;
        Ok(DelaunayReference {
            dt,
            cut: Default::default(),
        })
    }

    /// This reference without the edges that lines of their own heights
    /// cut (hard breaklines, as segments): every edge crossing one, running
    /// along one, or with an end on one. The surface there is the line's,
    /// not the samples', so it is no measure of the build.
    ///
    /// ```
    /// use tinmerge_core::tin::delaunay_ref::DelaunayReference;
    /// use tinmerge_core::tin::surface::Reference;
    /// let r = DelaunayReference::new(&[
    ///     [0.0, 0.0, 0.0], [2.0, -1.0, 0.0], [4.0, 0.0, 0.0], [2.0, 1.0, 4.0],
    /// ]).unwrap();
    /// // a hard line across the short diagonal (2, -1)-(2, 1)
    /// let r = r.cut_by(&[([1.5, 0.5], [2.5, 0.5])]);
    /// let mut n = 0;
    /// r.for_each_crossing(&[0.0, 0.0, 0.0], &[4.0, 0.0, 0.0], &mut |_| n += 1);
    /// assert_eq!(n, 0);
    /// ```
    pub fn cut_by(mut self, lines: &[([f64; 2], [f64; 2])]) -> DelaunayReference {
        let pos = |d: &Sample| [d.p.x, d.p.y, d.z];
        let mut cut = rustc_hash::FxHashSet::default();
        for (a, b) in lines {
            if !(a.iter().chain(b).all(|v| v.is_finite())) || a == b {
                continue;
            }
            if self.dt.num_inner_faces() == 0 {
                break;
            }
            let (pa, pb) = (Point2::new(a[0], a[1]), Point2::new(b[0], b[1]));
            for x in LineIntersectionIterator::new(&self.dt, pa, pb) {
                match x {
                    Intersection::EdgeIntersection(e) | Intersection::EdgeOverlap(e) => {
                        cut.insert(edge_key(&pos(e.from().data()), &pos(e.to().data())));
                    }
                    Intersection::VertexIntersection(h) => {
                        for e in h.out_edges() {
                            cut.insert(edge_key(&pos(e.from().data()), &pos(e.to().data())));
                        }
                    }
                }
            }
        }
        self.cut = cut;
        self
    }
}

impl Reference for DelaunayReference {
    /// A triangulation's edge between two samples need not be an edge of a
    /// triangulation of fewer of them (a vertex at a crossing can stand
    /// inside its circle), so samples alone cannot always mend a crossing.
    fn mends_at_crossings(&self) -> bool {
        true
    }

    /// Linear in the triangle holding `(x, y)`; None outside the hull.
    fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        if !(x.is_finite() && y.is_finite()) || self.dt.num_inner_faces() == 0 {
            return None;
        }
        self.dt
            .barycentric()
            .interpolate(|v| v.data().z, Point2::new(x, y))
    }

    /// The crossings of `a -> b` with the reference's edges, in order: the
    /// height there is the crossed edge's (linear between its two samples).
    /// `seg` is the crossed edge from its smaller end in (x, y), so both
    /// directions of a query name it alike; `pix`, the edge's two samples
    /// nearest first, then the far corners of its two triangles.
    fn for_each_crossing(&self, a: &[f64; 3], b: &[f64; 3], f: &mut dyn FnMut(&Crossing)) {
        self.for_each_crossing_of(a, b, &mut |x, _| f(x));
    }
}

impl DelaunayReference {
    /// How many samples it holds (fewer than it was given when some were
    /// the same point).
    pub(crate) fn num_samples(&self) -> usize {
        self.dt.num_vertices()
    }

    /// [`Reference::for_each_crossing`], each crossing with the numbers of
    /// the crossed edge's two samples (in the order they were given to
    /// [`DelaunayReference::new`]), `seg`'s order.
    pub(crate) fn for_each_crossing_of(
        &self,
        a: &[f64; 3],
        b: &[f64; 3],
        f: &mut dyn FnMut(&Crossing, [usize; 2]),
    ) {
        if !(a[0].is_finite() && a[1].is_finite() && b[0].is_finite() && b[1].is_finite())
            || a[..2] == b[..2]
            || self.dt.num_inner_faces() == 0
        {
            return;
        }
        let (pa, pb) = (Point2::new(a[0], a[1]), Point2::new(b[0], b[1]));
        for x in LineIntersectionIterator::new(&self.dt, pa, pb) {
            let Intersection::EdgeIntersection(e) = x else {
                continue;
            };
            let (u, v) = (*e.from().data(), *e.to().data());
            let (u3, v3) = ([u.p.x, u.p.y, u.z], [v.p.x, v.p.y, v.z]);
            if !self.cut.is_empty() && self.cut.contains(&edge_key(&u3, &v3)) {
                continue;
            }
            // where the lines meet, from exact orientations
            let (oa, ob) = (
                crate::geom::orient(&u3, &v3, a),
                crate::geom::orient(&u3, &v3, b),
            );
            let (ou, ov) = (
                crate::geom::orient(a, b, &u3),
                crate::geom::orient(a, b, &v3),
            );
            if oa == ob || ou == ov {
                continue;
            }
            // an end on the crossed edge up to rounding (a vertex put at a
            // crossing of it, a profile point of a line): that crossing is
            // the end itself, however far the rounding moves it along a
            // nearly parallel query
            if crate::geom::is_sliver(&u3, &v3, a) || crate::geom::is_sliver(&u3, &v3, b) {
                continue;
            }
            let t = oa / (oa - ob);
            let s = ou / (ou - ov);
            if !(t > AT_END && t < 1.0 - AT_END && s > AT_END && s < 1.0 - AT_END) {
                continue;
            }
            // the edge from its smaller end
            let (iu, iv) = (e.from().fix().index(), e.to().fix().index());
            let (p, q, s, ends) = if (v3[0], v3[1]) < (u3[0], u3[1]) {
                (v3, u3, 1.0 - s, [iv, iu])
            } else {
                (u3, v3, s, [iu, iv])
            };
            let z = p[2] + s * (q[2] - p[2]);
            let (near, far) = if s <= 0.5 { (p, q) } else { (q, p) };
            let corner = |h: Option<Point2<f64>>| h.map_or([far[0], far[1]], |c| [c.x, c.y]);
            let left = e.face().as_inner().map(|_| e.next().to().position());
            let right = e
                .rev()
                .face()
                .as_inner()
                .map(|_| e.rev().next().to().position());
            let pix = [
                [near[0], near[1]],
                [far[0], far[1]],
                corner(left),
                corner(right),
                [far[0], far[1]],
                [far[0], far[1]],
            ];
            let pt = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), z];
            f(
                &Crossing {
                    t,
                    p: pt,
                    pix,
                    seg: [p, q],
                    s,
                },
                ends,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every crossing against a brute force over the reference's edges:
    /// the same edges, in order along the query, heights on the edge.
    #[test]
    fn crossings_are_every_edge_crossed_in_order() {
        // seeded scattered samples
        let mut s = 12345u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|_| [rnd() * 100.0, rnd() * 50.0, rnd() * 20.0])
            .collect();
        let r = DelaunayReference::new(&pts).unwrap();
        let edges: Vec<([f64; 3], [f64; 3])> =
            r.dt.undirected_edges()
                .map(|e| {
                    let [u, v] = e.vertices().map(|v| {
                        let d = v.data();
                        [d.p.x, d.p.y, d.z]
                    });
                    (u, v)
                })
                .collect();
        for _ in 0..50 {
            let a = pts[(rnd() * 300.0) as usize];
            let b = [rnd() * 90.0 + 5.0, rnd() * 40.0 + 5.0, 0.0];
            let mut got = Vec::new();
            r.for_each_crossing(&a, &b, &mut |c| got.push(*c));
            assert!(got.windows(2).all(|w| w[0].t < w[1].t));
            // brute force: proper crossings away from the ends
            let mut want = 0;
            for (u, v) in &edges {
                let o = |p: &[f64; 3], q: &[f64; 3], x: &[f64; 3]| {
                    (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0])
                };
                let (d1, d2) = (o(u, v, &a), o(u, v, &b));
                let (d3, d4) = (o(&a, &b, u), o(&a, &b, v));
                if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                    want += 1;
                    let t = d1 / (d1 - d2);
                    let s = d3 / (d3 - d4);
                    let z = u[2] + s * (v[2] - u[2]);
                    let c = got
                        .iter()
                        .find(|c| (c.t - t).abs() < 1e-9)
                        .expect("a crossing the brute force finds");
                    assert!((c.p[2] - z).abs() < 1e-9);
                }
            }
            assert_eq!(got.len(), want);
        }
    }
}
