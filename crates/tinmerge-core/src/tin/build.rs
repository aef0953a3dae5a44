//! Construction of the adaptive hierarchical triangulation.
//!
//! Level 0 is built by greedy insertion (Garland & Heckbert): start from the
//! convex hull of the samples, repeatedly insert the sample with the largest
//! vertical error in the worst triangle, keep the triangulation Delaunay
//! (spade), stop when every triangle is within tolerance 0. Errors are
//! measured exactly at every sample inside each triangle.
//!
//! A level 0 of more than 65,536 vertices is itself finished parent by
//! parent, over the triangles the greedy insertion had at that count.
//!
//! Every finer level is refined parent by parent ([`refine_by_parents`]): a
//! triangle of level `i` holds exactly its children at level `i+1`, so it
//! is refined alone, in a small triangulation of its own samples, after the
//! vertices on its edges are chosen from each edge's own samples by a
//! Douglas-Peucker split (so the two triangles sharing an edge agree without
//! knowing of each other, and coarse edges persist as unions of finer
//! ones). No triangulation of the whole finest level is ever alive. A
//! raster's build (samples on the pixel lattice, [`build_lattice`]) reads
//! the heights in place ([`super::dense`]), where the samples on an edge
//! are exactly on it; scattered samples are bucketed ([`SampleGrid`]) and an
//! edge's samples are those on it up to rounding
//! ([`refine_parent_scattered`]). On the DEM upsampled 4x (1.9 million
//! samples, 5 levels) the peak heap is about 100 bytes a sample against 220
//! in one triangulation of every level (0.6.0's build), and the build over
//! 2x faster on one core.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! // a 20 x 20 grid of samples of a tilted plane with one bump
//! let mut pts = Vec::new();
//! for i in 0..20 {
//!     for j in 0..20 {
//!         let (x, y) = (i as f64, j as f64);
//!         let bump = if i == 10 && j == 10 { 5.0 } else { 0.0 };
//!         pts.push([x, y, 0.5 * x + bump]);
//!     }
//! }
//! let tin = build(pts, &[4.0, 0.0], 0, &mut || Ok(())).unwrap();
//! assert_eq!(tin.levels.len(), 2);
//! assert!(tin.levels[1].max_error <= 1e-9);
//! tin.sanity_check().unwrap();
//! ```

use super::breaklines::{clip_to_hull, drops_sample, network, profile, Breakline, Network};
use super::delaunay_ref::DelaunayReference;
use super::dense::Dense;
use super::hierarchy::{child_starts, compute_neighbours};
use super::lattice::Lattice;
use super::samples::{c2, SampleGrid, Samples};
use super::sides::{
    choose_border, close_chains, plan_side, sample_key, seg_key, side_key, Forced, Pt, SegKey,
    SideKey, SidePlan,
};
use super::surface::{GridReference, Reference};
use super::{grid, interpolate, Bbox, Level, Tin, TinError, MAX_LEVELS, NONE};
use crate::interrupt::Interrupt;
use crate::merge::area::polygon::{Area, Where};
use robust::orient2d;
use spade::handles::FixedVertexHandle;
use spade::{
    ConstrainedDelaunayTriangulation, DelaunayTriangulation, FloatTriangulation, Point2,
    Triangulation,
};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

type Dt = DelaunayTriangulation<Point2<f64>>;
/// Level 0 of a build with breaklines: their segments are constraint edges.
type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// The triangulations a [`Builder`] runs on: spade's Delaunay one, or the
/// constrained one for a level 0 with breaklines.
trait Tri: Triangulation<Vertex = Point2<f64>> + Default + Sync {
    /// Whether an edge is a constraint (its vertices are chosen from its
    /// own profile, never measured as a free edge).
    fn is_constraint(&self, e: spade::handles::FixedUndirectedEdgeHandle) -> bool;
}
impl Tri for Dt {
    fn is_constraint(&self, _: spade::handles::FixedUndirectedEdgeHandle) -> bool {
        false
    }
}
impl Tri for Cdt {
    fn is_constraint(&self, e: spade::handles::FixedUndirectedEdgeHandle) -> bool {
        self.is_constraint_edge(e)
    }
}
type FaceHandle = spade::handles::FixedFaceHandle<spade::handles::InnerTag>;

/// Samples under the faces around a new vertex above which they are
/// measured on threads.
const PAR_SAMPLES: f64 = 32768.0;

/// Most samples one build accepts (bounds memory: about 100 bytes a sample).
pub const MAX_SAMPLES: usize = 50_000_000;

/// Per-level tolerances `tolerance * 2^(levels-1-i)`, checked.
pub fn default_tolerances(tolerance: f64, levels: i32) -> Result<Vec<f64>, TinError> {
    if !(1..=MAX_LEVELS as i32).contains(&levels) {
        return Err(TinError::InvalidParameter(format!(
            "levels must be between 1 and {MAX_LEVELS}, got {levels}"
        )));
    }
    check_tolerance(tolerance)?;
    Ok((0..levels)
        .map(|i| tolerance * 2f64.powi(levels - 1 - i))
        .collect())
}

fn check_tolerance(t: f64) -> Result<(), TinError> {
    if !t.is_finite() || t < 0.0 {
        return Err(TinError::InvalidParameter(format!(
            "tolerance must be a finite number >= 0, got {t}"
        )));
    }
    Ok(())
}

/// Check an explicit tolerance list (coarsest first, strictly decreasing).
pub fn check_tolerances(tols: &[f64]) -> Result<(), TinError> {
    if tols.is_empty() || tols.len() > MAX_LEVELS {
        return Err(TinError::InvalidParameter(format!(
            "tolerances must have between 1 and {MAX_LEVELS} elements, got {}",
            tols.len()
        )));
    }
    for &t in tols {
        check_tolerance(t)?;
    }
    for w in tols.windows(2) {
        if w[1] >= w[0] {
            return Err(TinError::InvalidParameter(format!(
                "tolerances must be strictly decreasing (level 0 = coarsest first), got {} then {}",
                w[0], w[1]
            )));
        }
    }
    Ok(())
}

/// Sort samples by (x, y), merge equal (x, y) by averaging z, reject non-finite.
pub fn prepare_samples(mut pts: Vec<[f64; 3]>) -> Result<Vec<[f64; 3]>, TinError> {
    if pts.len() > MAX_SAMPLES {
        return Err(TinError::TooLarge(format!(
            "{} samples exceed the limit of {MAX_SAMPLES} for one tin; split the terrain into tiles",
            pts.len()
        )));
    }
    if let Some(p) = pts.iter().find(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(TinError::InvalidParameter(format!(
            "sample coordinates must be finite, got ({}, {}, {})",
            p[0], p[1], p[2]
        )));
    }
    for p in &pts {
        crate::tin::check_xy("a sample", p[0], p[1])?;
    }
    // unstable: no buffer of half the samples (deterministic all the same)
    pts.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    // merged in place: `w` samples kept so far
    let mut w = 0usize;
    let mut run = 1.0;
    for i in 0..pts.len() {
        let p = pts[i];
        if w > 0 && pts[w - 1][0] == p[0] && pts[w - 1][1] == p[1] {
            // running mean of z over the duplicates
            run += 1.0;
            pts[w - 1][2] += (p[2] - pts[w - 1][2]) / run;
        } else {
            run = 1.0;
            pts[w] = p;
            w += 1;
        }
    }
    pts.truncate(w);
    Ok(pts)
}

/// Convex hull (counter-clockwise, no collinear points) by Andrew's monotone
/// chain on samples sorted by (x, y); returns sample indices.
fn convex_hull(pts: &[[f64; 3]]) -> Vec<usize> {
    let n = pts.len();
    let mut h: Vec<usize> = Vec::with_capacity(64);
    let turn = |h: &Vec<usize>, i: usize| {
        orient2d(
            c2(&pts[h[h.len() - 2]]),
            c2(&pts[h[h.len() - 1]]),
            c2(&pts[i]),
        )
    };
    for i in 0..n {
        while h.len() >= 2 && turn(&h, i) <= 0.0 {
            h.pop();
        }
        h.push(i);
    }
    let lower = h.len() + 1;
    for i in (0..n.saturating_sub(1)).rev() {
        while h.len() >= lower && turn(&h, i) <= 0.0 {
            h.pop();
        }
        h.push(i);
    }
    h.pop();
    h
}

/// The sides of the convex hull `hull`: for each edge, every sample exactly
/// on it, both corners included, ordered along it from its corner that is
/// smaller in (x, y) order. Two tiles sharing a seam list the seam's samples
/// in the same order whichever way round their hulls go.
fn hull_sides(
    pts: &[[f64; 3]],
    hull: &[usize],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Vec<usize>>, TinError> {
    let mut out = Vec::with_capacity(hull.len());
    for k in 0..hull.len() {
        interrupt()?;
        let (ia, ib) = (hull[k], hull[(k + 1) % hull.len()]);
        let (a, b) = (&pts[ia], &pts[ib]);
        let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
        let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
        let mut on: Vec<(f64, usize)> = vec![(0.0, ia)];
        for (i, p) in pts.iter().enumerate() {
            if p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1 {
                continue;
            }
            if orient2d(c2(a), c2(b), c2(p)) == 0.0 && p[..2] != a[..2] && p[..2] != b[..2] {
                let d = (p[0] - a[0]).abs() + (p[1] - a[1]).abs();
                on.push((d, i));
            }
        }
        on.push((f64::INFINITY, ib));
        on.sort_by(|u, v| u.0.total_cmp(&v.0));
        let mut side: Vec<usize> = on.into_iter().map(|(_, i)| i).collect();
        if (b[0], b[1]) < (a[0], a[1]) {
            side.reverse();
        }
        out.push(side);
    }
    Ok(out)
}

#[derive(Clone, Copy)]
struct FaceState {
    gen: u32,
    /// the face's worst error (samples and free edges' crossings)
    err: f64,
    cand: u32,
    /// a corner of the face: where spade's point location starts when the
    /// candidate is inserted (it lies in this face, so the walk is short)
    corner: u32,
    /// the point to insert when `cand` is [`AT_CAND`]
    at: [f64; 3],
}

/// [`FaceState::cand`]: no sample, the point [`FaceState::at`]: where a
/// free edge crosses the reference's edge (a grid segment, an edge of the
/// samples' Delaunay triangulation), at the reference's height.
const AT_CAND: u32 = NONE - 1;

/// A face's measure: its worst error (samples and free edges' crossings),
/// the error and candidate sample (or NONE) that insertion can mend, a
/// corner.
#[derive(Clone, Copy)]
struct Measure {
    worst: f64,
    best: f64,
    cand: u32,
    corner: u32,
    at: [f64; 3],
}

#[derive(PartialEq)]
struct Entry {
    err: f64,
    face: u32,
    gen: u32,
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        self.err
            .total_cmp(&o.err)
            .then(o.face.cmp(&self.face))
            .then(self.gen.cmp(&o.gen))
    }
}

struct Builder<'g, S: Samples, T: Tri = Dt> {
    dt: T,
    /// z of each triangulation vertex (by spade vertex index).
    vz: Vec<f64>,
    /// the sample (index in `grid.pts`) each triangulation vertex is
    vsample: Vec<u32>,
    grid: &'g S,
    inserted: Vec<bool>,
    /// Samples on the hull's sides under `keep_border`: never a candidate of
    /// the greedy refinement (`choose_border` decides them, the same way in
    /// every tile sharing the side).
    reserved: Vec<bool>,
    faces: Vec<FaceState>,
    heap: BinaryHeap<Entry>,
    /// the surface between the samples ([`super::surface`]): free edges
    /// are measured at their crossings too
    reference: Option<&'g dyn Reference>,
    /// by vertex: bit k set when it is on the parent's side chain k (an
    /// edge between two vertices of one chain is a piece of that side)
    vside: Vec<u8>,
    /// crossings ([`AT_CAND`]) still to be inserted at most (their
    /// vertices' sample: NONE)
    at_budget: usize,
}

impl<S: Samples, T: Tri> Builder<'_, S, T> {
    fn vert3(&self, h: FixedVertexHandle) -> [f64; 3] {
        let p = self.dt.vertex(h).position();
        [p.x, p.y, self.vz[h.index()]]
    }

    /// Whether a directed edge is fixed: on the triangulation's hull, a
    /// constraint, or a piece of a parent's side. Fixed edges are chosen
    /// from their own profile; the others are measured at their crossings.
    fn fixed_edge(&self, e: spade::handles::FixedDirectedEdgeHandle) -> bool {
        let e = self.dt.directed_edge(e);
        if e.face().is_outer() || e.rev().face().is_outer() {
            return true;
        }
        let [u, w] = e.vertices().map(|v| v.fix().index());
        if self
            .vside
            .get(u)
            .zip(self.vside.get(w))
            .is_some_and(|(a, b)| a & b != 0)
        {
            return true;
        }
        self.dt.is_constraint(e.as_undirected().fix())
    }

    /// The worst sample of one inner face, and the worst crossing of its
    /// free edges with the reference's grid segments (a sample next to it,
    /// or the crossing itself, is the candidate then). Read-only: runs on
    /// `tin::par`'s threads.
    fn measure(&self, face: FaceHandle) -> Measure {
        let f = self.dt.face(face);
        let vs = f.vertices();
        let c = [
            self.vert3(vs[0].fix()),
            self.vert3(vs[1].fix()),
            self.vert3(vs[2].fix()),
        ];
        let mut best = 0.0f64;
        let mut cand = NONE;
        let (inserted, reserved) = (&self.inserted, &self.reserved);
        // a sliver's plane says nothing about the samples in it (and
        // `snapshot` leaves slivers out): they must all become vertices
        let sliver = crate::geom::is_sliver(&c[0], &c[1], &c[2]);
        self.grid.for_each_in_triangle(&c[0], &c[1], &c[2], |i, p| {
            if inserted[i] || (!reserved.is_empty() && reserved[i]) {
                return;
            }
            let e = if sliver {
                f64::MAX
            } else {
                (interpolate(&c, p[0], p[1]) - p[2]).abs()
            };
            if e > best {
                best = e;
                cand = i as u32;
            }
        });
        let mut m = Measure {
            worst: best,
            best,
            cand,
            corner: vs[0].fix().index() as u32,
            at: [f64::NAN; 3],
        };
        let Some(r) = self.reference else {
            return m;
        };
        if sliver {
            return m;
        }
        for e in f.adjacent_edges() {
            if self.fixed_edge(e.fix()) {
                continue;
            }
            let [u, w] = e.vertices().map(|v| self.vert3(v.fix()));
            let (err, Some(x)) = r.edge_error(&u, &w) else {
                continue;
            };
            m.worst = m.worst.max(err);
            if err <= m.best {
                continue;
            }
            // the pixel nearest the crossing that can be inserted (it is
            // inside the triangulation: the domain or the parent): once the
            // segment's two pixels are vertices the edge is no longer
            // Delaunay unless the crossing is within about a quarter pixel
            // of an end; the pixels beside them help where one is outside
            let hint = e.from().fix();
            let sample = x.pix.iter().find_map(|q| {
                let i = self.grid.find(q[0], q[1])?;
                if inserted[i] || (!reserved.is_empty() && reserved[i]) {
                    return None;
                }
                let p = self.grid.point(i);
                matches!(
                    self.dt.locate_with_hint(Point2::new(p[0], p[1]), hint),
                    spade::PositionInTriangulation::OnFace(_)
                        | spade::PositionInTriangulation::OnEdge(_)
                )
                .then_some(i)
            });
            if let Some(i) = sample {
                (m.best, m.cand) = (err, i as u32);
            } else if self.at_budget > 0 {
                // no sample can: the crossing itself, on the reference (a
                // rounding off this edge, the Delaunay triangulation flips
                // the edge away rather than keep a sliver). A
                // triangulation's edge between two samples need not be an
                // edge of a triangulation of fewer of them (a vertex at a
                // crossing can stand inside its circle), nor a grid segment
                // between a pixel and a ring's crossing an edge at all, so
                // inserting samples alone need not end it
                // never on a fixed edge up to rounding (a parent's side:
                // its neighbour would not have the vertex), nor where the
                // crossed edge runs on across one (that side is split
                // there, `unmended`; points here would creep towards it)
                let near_fixed = [e.face(), e.rev().face()].iter().any(|f| {
                    f.as_inner().is_some_and(|f| {
                        f.adjacent_edges().iter().any(|g| {
                            let [a, b] = g.vertices().map(|v| self.vert3(v.fix()));
                            self.fixed_edge(g.fix())
                                && (crate::geom::is_sliver(&a, &b, &x.p)
                                    || crosses_between(&a, &b, &x.seg[0], &x.seg[1]))
                        })
                    })
                });
                // nor next to an end of the crossed segment (a pixel, a
                // sample: a point beside it would make a sliver with it)
                let [p0, p1] = x.seg;
                let seg_len = (p1[0] - p0[0]).hypot(p1[1] - p0[1]);
                let near_end = x.s.min(1.0 - x.s) * seg_len <= 1e-6 * seg_len;
                if !near_fixed && !near_end {
                    (m.best, m.cand, m.at) = (err, AT_CAND, x.p);
                }
            }
        }
        m
    }

    /// Store a face's measure and queue the face if it has a candidate.
    fn record(&mut self, idx: usize, m: Measure) {
        if idx >= self.faces.len() {
            self.faces.resize(
                idx + 1,
                FaceState {
                    gen: 0,
                    err: 0.0,
                    cand: NONE,
                    corner: 0,
                    at: [f64::NAN; 3],
                },
            );
        }
        let st = &mut self.faces[idx];
        st.gen = st.gen.wrapping_add(1);
        st.err = m.worst;
        st.cand = m.cand;
        st.corner = m.corner;
        st.at = m.at;
        if m.cand != NONE {
            self.heap.push(Entry {
                err: m.best,
                face: idx as u32,
                gen: st.gen,
            });
        }
    }

    /// The vertices (positions, by triangulation index) and the sample
    /// each one is, the triangulation dropped.
    fn finish(self) -> (Vec<[f64; 3]>, Vec<u32>) {
        let verts = (0..self.dt.num_vertices())
            .map(|i| self.vert3(FixedVertexHandle::from_index(i)))
            .collect();
        (verts, self.vsample)
    }

    /// Re-measure one inner face and queue it.
    fn scan_face(&mut self, face: FaceHandle) {
        let m = self.measure(face);
        self.record(face.index(), m);
    }

    /// Samples a face's area holds, about (for deciding what is worth
    /// handing to threads).
    fn face_samples(&self, face: FaceHandle) -> f64 {
        let vs = self.dt.face(face).vertices();
        let [a, b, c] = vs.map(|v| self.dt.vertex(v.fix()).position());
        ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)).abs() / 2.0 / self.grid.cell_area()
    }

    /// Insert sample `i`; `hint` is a vertex near it (spade's point
    /// location walks from there; without one it walks from the last
    /// inserted vertex, which in greedy order is anywhere: that walk was
    /// 58 % of the build).
    fn insert_sample(
        &mut self,
        i: usize,
        hint: Option<FixedVertexHandle>,
    ) -> Result<FixedVertexHandle, TinError> {
        let p = self.grid.point(i);
        let h = self.insert_point(p, hint)?;
        self.inserted[i] = true;
        if self.vsample.len() < self.vz.len() {
            self.vsample.push(i as u32);
        }
        Ok(h)
    }

    /// Insert a point into the triangulation; a new vertex gets its height
    /// and side flags (the caller pushes its `vsample`).
    fn insert_point(
        &mut self,
        p: [f64; 3],
        hint: Option<FixedVertexHandle>,
    ) -> Result<FixedVertexHandle, TinError> {
        let before = self.dt.num_vertices();
        let pt = Point2::new(p[0], p[1]);
        let h = match hint {
            Some(v) if v.index() < before => self.dt.insert_with_hint(pt, v),
            _ => self.dt.insert(pt),
        }
        .map_err(|e| TinError::InvalidParameter(format!("cannot insert sample: {e:?}")))?;
        if self.dt.num_vertices() > before {
            self.vz.push(p[2]);
            self.vside.push(0);
        }
        Ok(h)
    }

    /// Re-measure the faces around a new vertex: on threads when they are
    /// large (the first insertions of a level), results recorded in order.
    fn rescan_around(&mut self, v: FixedVertexHandle) {
        let faces: Vec<_> = self
            .dt
            .vertex(v)
            .out_edges()
            .filter_map(|e| e.face().as_inner().map(|f| f.fix()))
            .collect();
        if super::par::threads() > 1
            && faces.iter().map(|&f| self.face_samples(f)).sum::<f64>() > PAR_SAMPLES
        {
            let ms = super::par::map(&faces, |&f| self.measure(f));
            for (f, m) in faces.iter().zip(ms) {
                self.record(f.index(), m);
            }
        } else {
            for f in faces {
                self.scan_face(f);
            }
        }
    }

    /// Refine until every face is within `tol` or the triangulation has
    /// `max_vertices`; returns the measured max error.
    fn refine(
        &mut self,
        tol: f64,
        max_vertices: usize,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<f64, TinError> {
        self.heap.clear();
        // every face measured (on threads, in chunks, interrupts between
        // batches), then recorded in face order
        let all: Vec<_> = self.dt.fixed_inner_faces().collect();
        let chunks: Vec<&[FaceHandle]> = all.chunks(4096).collect();
        let mut ms: Vec<Vec<Measure>> = Vec::with_capacity(chunks.len());
        super::par::map_batched(
            &chunks,
            |c| c.iter().map(|&f| self.measure(f)).collect(),
            interrupt,
            &mut |m| {
                ms.push(m);
                Ok(())
            },
        )?;
        for (f, m) in all.iter().zip(ms.into_iter().flatten()) {
            self.record(f.index(), m);
        }
        let mut n = 0usize;
        while let Some(top) = self.heap.pop() {
            let st = self.faces[top.face as usize];
            if st.gen != top.gen {
                continue;
            }
            if top.err <= tol || self.dt.num_vertices() >= max_vertices {
                self.heap.push(top);
                break;
            }
            n += 1;
            if n.is_multiple_of(256) {
                interrupt()?;
            }
            let hint = Some(FixedVertexHandle::from_index(st.corner as usize));
            let v = if st.cand == AT_CAND {
                self.at_budget = self.at_budget.saturating_sub(1);
                let v = self.insert_point(st.at, hint)?;
                if self.vsample.len() < self.vz.len() {
                    self.vsample.push(NONE);
                }
                v
            } else {
                self.insert_sample(st.cand as usize, hint)?
            };
            self.rescan_around(v);
            // A sample that did not become a new vertex (cannot happen for
            // distinct samples, but never loop on it) is marked inserted;
            // its old face must be re-measured without it.
            let idx = top.face as usize;
            if self.faces[idx].gen == st.gen {
                if let Some(f) = self.dt.fixed_inner_faces().find(|f| f.index() == idx) {
                    self.scan_face(f);
                }
            }
        }
        let mut max = 0.0f64;
        for f in self.dt.fixed_inner_faces() {
            max = max.max(self.faces[f.index()].err);
        }
        Ok(max)
    }

    /// One parent's refinement in this (emptied) builder: its `corners`
    /// inserted, then each of its fixed sides' chosen vertices ([`plan_side`]:
    /// the side's other samples reserved, chain `k`'s vertices flagged),
    /// then greedy insertion to `tol`. The worst error left, and each
    /// side's chain by builder sample (`grid.len() + k`: extra `k`).
    fn refine_parent(
        &mut self,
        corners: [usize; 3],
        plans: &[SidePlan],
        tol: f64,
    ) -> Result<(f64, Vec<Vec<usize>>), TinError> {
        let mut hint = None;
        for s in corners {
            hint = Some(self.insert_sample(s, hint)?);
        }
        let mut err = 0.0f64;
        for plan in plans {
            for &i in &plan.reserve {
                self.reserved[i] = true;
            }
            err = err.max(plan.err);
        }
        let internal = || {
            TinError::Degenerate(
                "internal: a side's crossing was not made a sample of its parent".into(),
            )
        };
        for &p in plans.iter().flat_map(|p| &p.order) {
            let Pt::Sample(i) = p else {
                return Err(internal());
            };
            if !self.inserted[i] {
                hint = Some(self.insert_sample(i, hint)?);
            }
        }
        let mut chains = Vec::with_capacity(plans.len());
        for (k, plan) in plans.iter().enumerate() {
            let mut chain = Vec::with_capacity(plan.chosen.len());
            for &p in &plan.chosen {
                let Pt::Sample(i) = p else {
                    return Err(internal());
                };
                let q = self.grid.point(i);
                let h = self
                    .dt
                    .locate_vertex(Point2::new(q[0], q[1]))
                    .map(|v| v.fix())
                    .ok_or_else(|| {
                        TinError::Degenerate("internal: a side's vertex was lost".into())
                    })?;
                self.vside[h.index()] |= 1 << k;
                chain.push(self.vsample[h.index()] as usize);
            }
            chains.push(chain);
        }
        Ok((
            err.max(self.refine(tol, usize::MAX, &mut || Ok(()))?),
            chains,
        ))
    }

    /// The crossings of free edges over `tol` that no pixel could mend,
    /// each with the side of the parent (corners `c`, counter-clockwise;
    /// side `k` from corner `k`, not `free[k]`) its grid segment crosses:
    /// the segment's far pixel lies across that side, in the neighbour.
    fn unmended(&self, tol: f64, c: &[[f64; 3]; 3], free: [bool; 3]) -> Vec<(SideKey, SegKey)> {
        let Some(r) = self.reference else {
            return Vec::new();
        };
        let mut out: Vec<(SideKey, SegKey)> = Vec::new();
        for f in self.dt.fixed_inner_faces() {
            if self.faces.get(f.index()).is_none_or(|st| st.err <= tol) {
                continue;
            }
            for e in self.dt.face(f).adjacent_edges() {
                if self.fixed_edge(e.fix()) {
                    continue;
                }
                let [u, w] = e.vertices().map(|v| self.vert3(v.fix()));
                r.for_each_crossing(&u, &w, &mut |x| {
                    if x.error(&u, &w) <= tol {
                        return;
                    }
                    let [p, q] = x.seg;
                    for k in (0..3).filter(|&k| !free[k]) {
                        let (a, b) = (&c[k], &c[(k + 1) % 3]);
                        let crosses = crate::geom::segments_cross(
                            crate::geom::vco(a),
                            crate::geom::vco(b),
                            crate::geom::vco(&p),
                            crate::geom::vco(&q),
                        );
                        let mut push = |item: (SideKey, SegKey)| {
                            if !out.contains(&item) {
                                out.push(item);
                            }
                        };
                        if crosses {
                            push((side_key(a, b), seg_key(x)));
                        }
                        // a pixel of the segment on the side, reserved
                        // there: the side takes it as a vertex
                        for z in [p, q] {
                            let on_side = crate::geom::is_sliver(a, b, &z)
                                && (z[0] - a[0]) * (z[0] - b[0]) + (z[1] - a[1]) * (z[1] - b[1])
                                    < 0.0;
                            let reserved = self
                                .grid
                                .find(z[0], z[1])
                                .is_some_and(|i| self.reserved.get(i).copied().unwrap_or(false));
                            if on_side && reserved {
                                push((side_key(a, b), sample_key(&z)));
                            }
                        }
                    }
                });
            }
        }
        out
    }

    /// The current triangles, without slivers (zero area up to rounding).
    /// Only scattered samples make them, and only along the triangulation's
    /// hull (the domain's, or a parent's sides in
    /// [`refine_parent_scattered`]): a sample within rounding of a hull
    /// edge leaves a sliver between itself and the edge (spade keeps the
    /// convex hull; the edge cannot flip), and later samples there split
    /// that sliver into more. Leaving them out makes the boundary run
    /// through those samples (convex up to rounding) instead of hiding a
    /// crack behind a wall; along a parent's side [`close_chains`] then
    /// meets the neighbour's vertices. Raster builds, decided on the
    /// lattice, have none.
    fn snapshot(&self) -> Vec<[u32; 3]> {
        self.dt
            .inner_faces()
            .filter(|f| {
                let v = f.vertices().map(|v| self.vert3(v.fix()));
                !crate::geom::is_sliver(&v[0], &v[1], &v[2])
            })
            .map(|f| {
                let v = f.vertices();
                [
                    v[0].fix().index() as u32,
                    v[1].fix().index() as u32,
                    v[2].fix().index() as u32,
                ]
            })
            .collect()
    }
}

/// Choices of a build beyond samples and tolerances.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuildOptions {
    /// Decide the vertices on each side of the convex hull from that side's
    /// samples alone: at every level, a Douglas-Peucker split of the side's
    /// height profile to the level's tolerance (`choose_border`), and no
    /// other sample of the side. Tiles of one raster that share a border
    /// row or column of samples then have the same vertices along it at
    /// every level, so the very same surface there: heights are continuous
    /// across tile seams. (Until 0.7.0 every sample of the hull's sides was
    /// a vertex of every level: the coarse levels were fans of slivers from
    /// the border, whose edges persisted into the finest level and made its
    /// surface steep and jagged.)
    pub keep_border: bool,
    /// Hold the tolerance between the samples too (issue 43; what
    /// `tin_from_raster` asks for on the pixel lattice, tiles aside): every
    /// free edge of every level is measured where it
    /// crosses a grid segment between two valid pixel centres (the raster's
    /// own surface there, [`super::surface`]), mended by inserting a pixel
    /// beside the crossing, and the sides of each parent are split at the
    /// next level from their own profile of samples and crossings
    /// ([`plan_side`]), so a coarse edge is refined where it is too far
    /// from the surface instead of persisting with its coarse heights.
    /// Vertices then lie at grid-line crossings as well as at pixel centres.
    pub between_samples: bool,
}

/// Build a hierarchy from samples (x, y, z) with one tolerance per level
/// (coarsest first, strictly decreasing). `interrupt` is called regularly and
/// may abort the build by returning an error.
pub fn build(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_with(
        samples,
        tolerances,
        srid,
        BuildOptions::default(),
        interrupt,
    )
}

/// [`build`] with [`BuildOptions`].
pub fn build_with(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_inner(
        samples,
        &[],
        &[],
        tolerances,
        srid,
        opts,
        false,
        None,
        interrupt,
    )
}

/// [`build`] measured between the samples too: against the Delaunay
/// triangulation of all of them ([`DelaunayReference`]), every edge of
/// every level at its crossings with the reference's edges, coarse edges
/// split there level by level, so each level is within its tolerance of
/// that surface everywhere, not only at the samples. What
/// `tin_from_points` builds.
///
/// ```
/// use tinmerge_core::tin::build::build_points;
/// let mut pts = Vec::new();
/// for i in 0..30 {
///     for j in 0..30 {
///         let (x, y) = (i as f64 + 0.3 * ((i * j) % 7) as f64 / 7.0, j as f64);
///         pts.push([x, y, (x * 0.3).sin() * 5.0 + y * 0.1]);
///     }
/// }
/// let tin = build_points(pts, &[1.0, 0.25], 0, &mut || Ok(())).unwrap();
/// tin.sanity_check().unwrap();
/// assert!(tin.levels[1].max_error <= 0.25);
/// ```
pub fn build_points(
    samples: Vec<[f64; 3]>,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_points_domain(samples, &[], &[], tolerances, srid, interrupt)
}

/// [`build_domain`] of points, measured between the samples against
/// their whole Delaunay triangulation as [`build_points`] is: soft lines
/// and boundary rings take their heights from it, and the edges of it a
/// hard line cuts are left out ([`DelaunayReference::cut_by`]: the surface
/// there is the line's).
pub fn build_points_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    check_tolerances(tolerances)?;
    let samples = prepare_samples(samples)?;
    interrupt()?;
    // hard lines' heights are their own: the samples' edges they cut are
    // no measure of the build
    let cuts: Vec<([f64; 2], [f64; 2])> = lines
        .iter()
        .filter(|l| l.hard)
        .flat_map(|l| {
            l.pts
                .windows(2)
                .map(|w| ([w[0][0], w[0][1]], [w[1][0], w[1][1]]))
        })
        .collect();
    let reference = DelaunayReference::new(&samples)?.cut_by(&cuts);
    drop(cuts);
    interrupt()?;
    build_domain_with(
        samples,
        lines,
        boundaries,
        tolerances,
        srid,
        Some(&reference),
        interrupt,
    )
}

/// [`build`] with breaklines ([`super::breaklines`]): every line a union of
/// edges at every level, hard lines' heights along them, the samples on a
/// line up to rounding left out ([`super::breaklines::drops_sample`]).
/// The parts of the lines outside the samples' convex hull are cut off
/// ([`super::breaklines::clip_to_hull`]).
///
/// ```
/// use tinmerge_core::tin::breaklines::Breakline;
/// use tinmerge_core::tin::build::build_breaklines;
/// let mut pts = Vec::new();
/// for i in 0..20 {
///     for j in 0..20 {
///         pts.push([i as f64, j as f64, (i * j) as f64 * 0.1]);
///     }
/// }
/// // a road at 3 m from (2.5, 2.5) to (16.5, 12.5): an edge at level 0
/// let road = Breakline { pts: vec![[2.5, 2.5, 3.0], [16.5, 12.5, 3.0]], hard: true };
/// let tin = build_breaklines(pts, &[road], &[100.0, 0.5], 0, &mut || Ok(())).unwrap();
/// let (a, b) = ([2.5, 2.5], [16.5, 12.5]);
/// let l0 = &tin.levels[0];
/// let has_edge = l0.tris.iter().any(|t| {
///     let xy = |k: u32| [tin.verts[k as usize][0], tin.verts[k as usize][1]];
///     (0..3).any(|j| {
///         let (p, q) = (xy(t[j]), xy(t[(j + 1) % 3]));
///         (p == a && q == b) || (p == b && q == a)
///     })
/// });
/// assert!(has_edge);
/// tin.sanity_check().unwrap();
/// ```
pub fn build_breaklines(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_domain(samples, lines, &[], tolerances, srid, interrupt)
}

/// The `boundary` of a build ([`build_domain`]) from polygons given as
/// rings of (x, y) (the first ring of each polygon its shell, the others
/// holes): finite coordinates, and valid as OGC polygons are (rings
/// simple, holes inside their shell, polygons not overlapping), checked
/// with `geo`'s validation; an error says what is wrong.
pub fn boundary(polygons: Vec<Vec<Vec<[f64; 2]>>>) -> Result<Area, TinError> {
    use geo::algorithm::Validation;
    use geo::{Coord, LineString, MultiPolygon, Polygon};
    if let Some(p) = polygons
        .iter()
        .flatten()
        .flatten()
        .find(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(TinError::InvalidParameter(format!(
            "boundary coordinates must be finite, got ({} {})",
            p[0], p[1]
        )));
    }
    if polygons.iter().all(|p| p.is_empty()) {
        return Err(TinError::InvalidParameter("boundary is empty".into()));
    }
    let ring =
        |r: &Vec<[f64; 2]>| LineString::new(r.iter().map(|p| Coord { x: p[0], y: p[1] }).collect());
    let mp = MultiPolygon::new(
        polygons
            .iter()
            .filter(|p| !p.is_empty())
            .map(|p| Polygon::new(ring(&p[0]), p[1..].iter().map(ring).collect()))
            .collect(),
    );
    if let Err(e) = mp.check_validation() {
        return Err(TinError::InvalidParameter(format!(
            "boundary is not a valid polygon: {e} (ST_MakeValid repairs it)"
        )));
    }
    Ok(Area::new(polygons))
}

/// Whether `area` holds the samples' whole convex hull (no ring enters
/// it, no sample is outside): a build with it as boundary is the build
/// without ([`build_domain`] would give the same triangles; a raster
/// build then stays on its lattice).
pub fn boundary_holds_all(area: &Area, samples: &[[f64; 3]]) -> bool {
    if samples
        .iter()
        .any(|p| area.locate([p[0], p[1]]) == Where::Outside)
    {
        return false;
    }
    let hull: Vec<[f64; 3]> = convex_hull(samples)
        .into_iter()
        .map(|k| samples[k])
        .collect();
    if hull.len() < 3 {
        return true;
    }
    let rings: Vec<Breakline> = area
        .rings
        .iter()
        .map(|r| Breakline {
            pts: r.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            hard: false,
        })
        .collect();
    clip_to_hull(&rings, &hull).is_empty()
}

/// [`build_breaklines`] with a `boundary`: the domain is the boundary's
/// area clipped to the samples' convex hull, holes and concave parts
/// included. Its rings within the hull are edges at every level, like soft
/// breaklines (heights from the samples on both sides); the samples
/// outside it are left out; the triangles outside it (between the rings
/// and the hull, in the holes) are void ([`super::Level::num_void`]), so
/// every level still triangulates the hull of what is left and no merge
/// answers there. Breaklines outside the domain shape only void triangles.
///
/// ```
/// use tinmerge_core::merge::area::polygon::Area;
/// use tinmerge_core::tin::build::build_domain;
/// let mut pts = Vec::new();
/// for i in 0..=20 {
///     for j in 0..=20 {
///         pts.push([i as f64, j as f64, (i * j) as f64 * 0.1]);
///     }
/// }
/// // an L-shaped boundary with a square hole, reaching past the samples
/// let shell = vec![[-5.0, -5.0], [12.0, -5.0], [12.0, 10.0], [25.0, 10.0],
///                  [25.0, 25.0], [-5.0, 25.0], [-5.0, -5.0]];
/// let hole = vec![[2.0, 12.0], [6.0, 12.0], [6.0, 16.0], [2.0, 16.0], [2.0, 12.0]];
/// let b = Area::new(vec![vec![shell, hole]]);
/// let tin = build_domain(pts, &[], &[&b], &[5.0, 0.5], 0, &mut || Ok(())).unwrap();
/// tin.sanity_check().unwrap();
/// for l in &tin.levels {
///     // the domain: the square 0..20 less the corner 12..20 x 0..10 and the hole
///     let area: f64 = (0..l.num_domain())
///         .map(|t| {
///             let [a, b, c] = l.tris[t].map(|v| tin.verts[v as usize]);
///             ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2.0
///         })
///         .sum();
///     assert!((area - (400.0 - 80.0 - 16.0)).abs() < 1e-9);
/// }
/// ```
pub fn build_domain(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_domain_with(
        samples, lines, boundaries, tolerances, srid, None, interrupt,
    )
}

/// [`build_domain`] measured against a `reference` surface too (None: at
/// the samples only).
fn build_domain_with(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    reference: Option<&dyn Reference>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_inner(
        samples,
        lines,
        boundaries,
        tolerances,
        srid,
        BuildOptions::default(),
        false,
        reference,
        interrupt,
    )
}

/// [`build_domain`] for a raster's valid pixel centres in world
/// coordinates (`lat.centre(col, row)`, as `tin_from_raster` builds over
/// its data, with a boundary or with breaklines): every free edge of every
/// level is also measured where it crosses a grid segment between two valid
/// pixel centres, against the raster's `heights` ([`super::surface`]), and
/// coarse edges are split at those crossings level by level. Hard
/// breaklines keep heights of their own, not the raster's: the grid
/// segments they cut (within [`super::surface::CUT_SLACK`] pixel) are left
/// out ([`GridReference::cut_by`]), every other one is measured.
#[allow(clippy::too_many_arguments)]
pub fn build_domain_raster(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    heights: &Dense,
    lat: &Lattice,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    // hard lines' heights are their own: the grid segments they cut are
    // no measure of the build
    let cuts: Vec<([f64; 2], [f64; 2])> = lines
        .iter()
        .filter(|l| l.hard)
        .flat_map(|l| {
            l.pts
                .windows(2)
                .map(|w| ([w[0][0], w[0][1]], [w[1][0], w[1][1]]))
        })
        .collect();
    let reference = GridReference::in_world(heights, *lat).cut_by(&cuts);
    drop(cuts);
    build_domain_with(
        samples,
        lines,
        boundaries,
        tolerances,
        srid,
        lat.is_valid().then_some(&reference as &dyn Reference),
        interrupt,
    )
}

/// The samples' height at (x, y): linear in the Delaunay triangulation of
/// the samples around it (a box grown until it holds the point), None
/// outside the samples' hull.
fn sample_height(grid: &SampleGrid, x: f64, y: f64) -> Option<f64> {
    let mut r = 2.0 * grid.cell_area().sqrt();
    if !(r.is_finite() && r > 0.0) {
        r = 1.0;
    }
    let spacing = r / 2.0;
    for _ in 0..64 {
        let mut dt = Dt::new();
        let mut zs = Vec::new();
        let mut n = 0usize;
        grid.for_each_in_box(x - r, y - r, x + r, y + r, |_, p| {
            n += 1;
            if let Ok(h) = dt.insert(Point2::new(p[0], p[1])) {
                if h.index() == zs.len() {
                    zs.push(p[2]);
                }
            }
        });
        if dt.num_vertices() >= 3 {
            let z = dt
                .barycentric()
                .interpolate(|v| zs[v.fix().index()], Point2::new(x, y));
            if z.is_some() {
                return z;
            }
            // a point outside the hull of the samples around it by less
            // than a sample spacing: a line cut at the samples' hull, whose
            // long edges (a rotated raster's border) run up to a pixel
            // beside the outermost samples, or a boundary's corner beside
            // them. The height at the nearest point of that hull: the
            // samples' own, where growing the box would reach a far hull
            // vertex and a sliver across the whole raster
            if let Some(z) = near_hull_edge(&dt, &zs, x, y, spacing) {
                return Some(z);
            }
        }
        if n == grid.len() {
            return None;
        }
        r *= 2.0;
    }
    None
}

/// The height at (x, y) along the edge of `dt`'s convex hull nearest to
/// it, when that edge is within `eps` (linear along the edge).
fn near_hull_edge(dt: &Dt, zs: &[f64], x: f64, y: f64, eps: f64) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None;
    for e in dt.convex_hull() {
        let [a, b] = e.vertices();
        let (pa, pb) = (a.position(), b.position());
        let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
        let l2 = dx * dx + dy * dy;
        if l2 == 0.0 {
            continue;
        }
        let t = (((x - pa.x) * dx + (y - pa.y) * dy) / l2).clamp(0.0, 1.0);
        let (qx, qy) = (pa.x + t * dx, pa.y + t * dy);
        let d = ((x - qx).powi(2) + (y - qy).powi(2)).sqrt();
        if d <= eps && best.is_none_or(|(bd, _)| d < bd) {
            let (za, zb) = (zs[a.fix().index()], zs[b.fix().index()]);
            best = Some((d, za + t * (zb - za)));
        }
    }
    best.map(|(_, z)| z)
}

/// The samples of a build with breaklines, their network and each
/// segment's profile ([`with_breaklines`]).
type WithBreaklines = (Vec<[f64; 3]>, Network, Vec<Vec<[f64; 3]>>);

/// The breaklines as a network ([`super::breaklines::network`]), the
/// samples of a build with them (those not on a line, the network's
/// vertices and the soft segments' profiles, prepared
/// ([`prepare_samples`])) and each segment's profile
/// ([`super::breaklines::profile`]; empty for a hard one).
fn with_breaklines(
    pts: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tol: f64,
    reference: Option<&dyn Reference>,
    interrupt: &mut Interrupt<'_>,
) -> Result<WithBreaklines, TinError> {
    let hull: Vec<[f64; 3]> = convex_hull(&pts).into_iter().map(|k| pts[k]).collect();
    if hull.len() < 3 {
        return Err(TinError::Degenerate(
            "all samples are collinear: a tin needs at least 3 non-collinear samples".into(),
        ));
    }
    // the parts of the lines outside the samples' extent are cut off
    super::breaklines::validate(lines)?;
    let mut lines = lines.to_vec();
    for area in boundaries {
        // the boundary's rings: soft lines (heights from the samples)
        lines.extend(area.rings.iter().map(|r| Breakline {
            pts: r.iter().map(|p| [p[0], p[1], 0.0]).collect(),
            hard: false,
        }));
    }
    let lines = clip_to_hull(&lines, &hull);
    let grid = SampleGrid::new(pts, 1.0);
    // heights along soft lines: the reference's where it has them (the
    // samples' whole Delaunay triangulation), else the samples around
    let height = |x: f64, y: f64| {
        reference
            .and_then(|r| r.height_at(x, y))
            .or_else(|| sample_height(&grid, x, y))
    };
    let net = network(&lines, tol, &height, interrupt)?;
    drop(lines);
    for v in &net.verts {
        if (0..hull.len())
            .any(|k| orient2d(c2(&hull[k]), c2(&hull[(k + 1) % hull.len()]), c2(v)) < 0.0)
        {
            return Err(TinError::Degenerate(format!(
                "internal: breakline point ({} {}) outside the samples' extent after clipping",
                v[0], v[1]
            )));
        }
    }
    let mut dropped = vec![false; grid.len()];
    // with a reference, a soft segment's samples (dropped: the profile
    // stands for them) are points of its profile, their own heights
    let mut on_segment: Vec<Vec<[f64; 3]>> = vec![Vec::new(); net.segs.len()];
    for (k, s) in net.segs.iter().enumerate() {
        if k % 256 == 0 {
            interrupt()?;
        }
        let (a, b) = (net.verts[s[0] as usize], net.verts[s[1] as usize]);
        let keep_on = reference.is_some() && !net.hard[k];
        let m = 1e-9 * (a[0].abs().max(a[1].abs()).max(b[0].abs()).max(b[1].abs()) + 1.0);
        grid.for_each_in_box(
            a[0].min(b[0]) - m,
            a[1].min(b[1]) - m,
            a[0].max(b[0]) + m,
            a[1].max(b[1]) + m,
            |i, p| {
                if drops_sample(&a, &b, p) {
                    if keep_on && p[..2] != a[..2] && p[..2] != b[..2] {
                        on_segment[k].push(*p);
                    }
                    dropped[i] = true;
                }
            },
        );
    }
    // soft segments: their profiles, about one sample spacing apart
    let step = grid.cell_area().sqrt();
    let mut profiles = Vec::with_capacity(net.segs.len());
    let mut total = 0usize;
    for (k, s) in net.segs.iter().enumerate() {
        interrupt()?;
        let prof = if net.hard[k] {
            Vec::new()
        } else {
            let (a, b) = (net.verts[s[0] as usize], net.verts[s[1] as usize]);
            let even = profile(&a, &b, step, &height, interrupt)?;
            match reference {
                Some(r) => {
                    with_crossings(&a, &b, even, r, step, std::mem::take(&mut on_segment[k]))
                }
                None => even,
            }
        };
        total += prof.len();
        if total > super::breaklines::MAX_PROFILE_POINTS {
            return Err(TinError::TooLarge(format!(
                "soft breaklines hold more than {} sample spacings",
                super::breaklines::MAX_PROFILE_POINTS
            )));
        }
        profiles.push(prof);
    }
    // the samples outside the boundary: no vertex of the domain
    for area in boundaries {
        for (k, p) in grid.pts.iter().enumerate() {
            if k % 65536 == 0 {
                interrupt()?;
            }
            if area.locate([p[0], p[1]]) == Where::Outside {
                dropped[k] = true;
            }
        }
    }
    let mut kept: Vec<[f64; 3]> = grid
        .pts
        .iter()
        .zip(&dropped)
        .filter(|(_, &d)| !d)
        .map(|(p, _)| *p)
        .collect();
    drop(grid);
    kept.extend_from_slice(&net.verts);
    kept.extend(profiles.iter().flatten());
    Ok((prepare_samples(kept)?, net, profiles))
}

/// A soft segment's profile `even` (points about `step` apart from `a` to
/// `b`, heights from the samples) with the segment's crossings of the
/// `reference`'s grid segments (heights the reference's) and the samples
/// `on` it (within rounding, their own heights) among them, in order; an
/// even point within a thousandth of `step` of one of those left out. The
/// profile's vertices, chosen level by level as a seam's are
/// ([`plan_side`]), then hold the tolerance at every crossing of the line
/// and every pixel on it: a boundary's ring on the samples' hull (no
/// parent beside it measures it) as well as inside, and a line along a
/// pixel row.
fn with_crossings(
    a: &[f64; 3],
    b: &[f64; 3],
    even: Vec<[f64; 3]>,
    reference: &dyn Reference,
    step: f64,
    on: Vec<[f64; 3]>,
) -> Vec<[f64; 3]> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    if len.is_nan() || len <= 0.0 {
        return even;
    }
    let along =
        |p: &[f64; 3]| ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / len;
    let mut cross: Vec<(f64, [f64; 3])> = on.into_iter().map(|p| (along(&p), p)).collect();
    reference.for_each_crossing(a, b, &mut |c| cross.push((c.t * len, c.p)));
    if cross.is_empty() {
        return even;
    }
    cross.sort_by(|u, v| u.0.total_cmp(&v.0));
    let near = step * 1e-3;
    let mut out: Vec<(f64, [f64; 3])> = even
        .into_iter()
        .map(|p| (along(&p), p))
        .filter(|(d, _)| {
            let k = cross.partition_point(|c| c.0 < *d);
            let gap = |i: usize| cross.get(i).map_or(f64::INFINITY, |c| (c.0 - d).abs());
            gap(k).min(if k > 0 { gap(k - 1) } else { f64::INFINITY }) > near
        })
        .collect();
    out.extend(cross);
    out.sort_by(|u, v| u.0.total_cmp(&v.0));
    out.into_iter().map(|(_, p)| p).collect()
}

/// Level 0's constraint edges: the network's vertices inserted (they are
/// samples of `b`'s grid), then each segment with a profile (`sides[k]`:
/// its samples from end to end, or empty) split at the profile samples
/// [`choose_border`] picks at `tol` (inserted before the constraints, so
/// each piece is an edge of its own: they lie on the segment only up to
/// rounding), and every piece added as a constraint.
fn add_network<S: Samples>(
    b: &mut Builder<'_, S, Cdt>,
    net: &Network,
    sides: &[Vec<usize>],
    tol: f64,
    find: &dyn Fn(f64, f64) -> Option<usize>,
) -> Result<(), TinError> {
    let mut ends = Vec::with_capacity(net.verts.len());
    let mut handle: rustc_hash::FxHashMap<usize, FixedVertexHandle> = Default::default();
    let mut hint = None;
    for v in &net.verts {
        let i = find(v[0], v[1])
            .ok_or_else(|| TinError::Degenerate("internal: a breakline vertex was lost".into()))?;
        let h = b.insert_sample(i, hint)?;
        hint = Some(h);
        handle.insert(i, h);
        ends.push(i);
    }
    for (k, s) in net.segs.iter().enumerate() {
        let (p, q) = (ends[s[0] as usize], ends[s[1] as usize]);
        if p == q {
            continue;
        }
        let chain: Vec<usize> = match sides.get(k) {
            Some(side) if side.len() > 2 => {
                let mut chosen: Vec<bool> = (0..side.len())
                    .map(|j| j == 0 || j + 1 == side.len())
                    .collect();
                let grid = b.grid;
                let mut new = Vec::new();
                choose_border(&|i| grid.point(i), side, &mut chosen, tol, &mut new);
                for i in new {
                    let h = b.insert_sample(i, handle.get(&p).copied())?;
                    handle.insert(i, h);
                }
                side.iter()
                    .zip(&chosen)
                    .filter(|(_, &c)| c)
                    .map(|(&i, _)| i)
                    .collect()
            }
            _ => vec![p, q],
        };
        for w in chain.windows(2) {
            let (Some(&hp), Some(&hq)) = (handle.get(&w[0]), handle.get(&w[1])) else {
                return Err(TinError::Degenerate(
                    "internal: a breakline vertex was not inserted".into(),
                ));
            };
            if b.dt.try_add_constraint(hp, hq).is_empty() {
                let a = b.grid.point(w[0]);
                return Err(TinError::InvalidParameter(format!(
                    "breakline segment from ({} {}) cannot be an edge: it crosses another within rounding; snap the breaklines (ST_Snap, ST_Node) first",
                    a[0], a[1]
                )));
            }
        }
    }
    Ok(())
}

/// One level of the build before [`assemble`].
struct RawLevel {
    tolerance: f64,
    /// measured
    max_error: f64,
    /// vertices of this level and the coarser ones (a prefix of all)
    num_vertices: u32,
    /// counter-clockwise, by vertex index
    tris: Vec<[u32; 3]>,
    /// each triangle's parent, by index in the previous level's `tris`;
    /// (empty at level 0)
    parents: Vec<u32>,
    /// which triangles are void (outside the domain; empty: none): at
    /// level 0 by [`mark_void`], at the finer ones as their parents
    void: Vec<bool>,
}

/// The build. Lattice samples (`on_lattice`) that fill most of their
/// window of the lattice are built in place there ([`build_dense`]);
/// scattered samples, and lattice samples too sparse for that, are
/// bucketed ([`SampleGrid`]) and built the same way on them
/// ([`build_levels`]).
#[allow(clippy::too_many_arguments)]
fn build_inner(
    samples: Vec<[f64; 3]>,
    lines: &[Breakline],
    boundaries: &[&Area],
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    on_lattice: bool,
    reference: Option<&dyn Reference>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    check_tolerances(tolerances)?;
    let constrained = !lines.is_empty() || !boundaries.is_empty();
    if constrained && (on_lattice || opts.keep_border) {
        return Err(TinError::InvalidParameter(
            "internal: breaklines are built on scattered samples without keep_border".into(),
        ));
    }
    if on_lattice && samples.len() <= MAX_SAMPLES {
        if let Some(p) = samples.iter().find(|p| !p[2].is_finite()) {
            return Err(TinError::InvalidParameter(format!(
                "sample coordinates must be finite, got ({}, {}, {})",
                p[0], p[1], p[2]
            )));
        }
        if let Some(d) = dense_of(&samples) {
            drop(samples);
            return build_dense(d, tolerances, srid, opts, interrupt);
        }
    }
    let mut pts = prepare_samples(samples)?;
    let mut net = Network::default();
    let mut profiles = Vec::new();
    if constrained && pts.len() >= 3 {
        let tol = *tolerances.last().unwrap_or(&0.0);
        (pts, net, profiles) = with_breaklines(pts, lines, boundaries, tol, reference, interrupt)?;
    }
    if !boundaries.is_empty() && net.segs.is_empty() && pts.len() < 3 {
        return Err(no_domain());
    }
    if pts.len() < 3 {
        return Err(TinError::Degenerate(format!(
            "need at least 3 samples with distinct x,y to build a tin, got {}",
            pts.len()
        )));
    }
    // the hull on the (x, y)-sorted samples, found again once bucketed
    let hull_xy: Vec<[f64; 3]> = convex_hull(&pts).into_iter().map(|k| pts[k]).collect();
    let grid = SampleGrid::new(pts, 1.0);
    let hull = hull_xy
        .iter()
        .map(|p| grid.find(p[0], p[1]))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| TinError::Degenerate("internal: a hull sample was lost".into()))?;
    drop(hull_xy);
    let sides = if opts.keep_border {
        hull_sides(&grid.pts, &hull, interrupt)?
    } else {
        Vec::new()
    };
    let (verts, raw_levels) = if net.segs.is_empty() {
        let b: Builder<'_, _, Dt> = start(&grid, &hull, opts.keep_border, reference)?;
        build_levels(
            b, &grid, reference, &sides, boundaries, tolerances, opts, interrupt,
        )?
    } else {
        // each soft segment's samples from end to end (a hard one: none),
        // chosen level by level as a tile's seam is; reserved from the
        // greedy refinement of level 0
        let find = |p: &[f64; 3]| grid.find(p[0], p[1]);
        let segment_sides = net
            .segs
            .iter()
            .zip(&profiles)
            .map(|(s, prof)| {
                if prof.is_empty() {
                    return Some(Vec::new());
                }
                let mut side = vec![find(&net.verts[s[0] as usize])?];
                for p in prof {
                    side.push(find(p)?);
                }
                side.push(find(&net.verts[s[1] as usize])?);
                Some(side)
            })
            .collect::<Option<Vec<Vec<usize>>>>()
            .ok_or_else(|| TinError::Degenerate("internal: a profile sample was lost".into()))?;
        drop(profiles);
        let mut b: Builder<'_, _, Cdt> = start(&grid, &hull, true, reference)?;
        add_network(&mut b, &net, &segment_sides, tolerances[0], &|x, y| {
            grid.find(x, y)
        })?;
        let sides: Vec<Vec<usize>> = segment_sides
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect();
        build_levels(
            b, &grid, reference, &sides, boundaries, tolerances, opts, interrupt,
        )?
    };
    drop(grid);
    // on a lattice the grid indexes are built once, by `Lattice::to_world`
    assemble(verts, raw_levels, srid, !on_lattice, interrupt)
}

/// The error of a boundary that leaves nothing of the samples' extent.
fn no_domain() -> TinError {
    TinError::InvalidParameter(
        "the boundary does not overlap the samples' extent: the tin would have no domain".into(),
    )
}

/// Level 0's void triangles (or the seed's, [`build_levels`]): those whose
/// centroid is outside any of the `boundaries`. Their rings within the hull
/// are edges of level 0, so no triangle has parts on both sides; the finer
/// levels inherit ([`refine_by_parents`], [`assemble`]).
fn mark_void(
    verts: &[[f64; 3]],
    level0: &mut RawLevel,
    boundaries: &[&Area],
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let mut void = Vec::with_capacity(level0.tris.len());
    for (k, t) in level0.tris.iter().enumerate() {
        if k % 65536 == 0 {
            interrupt()?;
        }
        let [a, b, c] = t.map(|v| verts[v as usize]);
        let g = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
        void.push(boundaries.iter().any(|a| a.locate(g) == Where::Outside));
    }
    if void.iter().all(|&v| v) {
        return Err(no_domain());
    }
    level0.void = void;
    Ok(())
}

/// Every level: level 0 refined in `b` (the whole domain, its hull
/// inserted; the hull's `sides` under keep_border), the finer ones parent by
/// parent on `src`, void outside the `boundaries` (none: the whole hull).
/// The vertices and the levels, for [`assemble`].
#[allow(clippy::too_many_arguments)]
fn build_levels<S: Samples, T: Tri, P: ParentSamples>(
    mut b: Builder<'_, S, T>,
    src: &P,
    reference: Option<&dyn Reference>,
    sides: &[Vec<usize>],
    boundaries: &[&Area],
    tolerances: &[f64],
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<RawLevel>), TinError> {
    let mut level0 = refine_level0(&mut b, sides, tolerances[0], SEED_VERTICES, interrupt)?;
    let (mut verts, vsample) = b.finish();
    if !boundaries.is_empty() {
        mark_void(&verts, &mut level0, boundaries, interrupt)?;
    }
    // a level 0 of more than SEED_VERTICES vertices is refined parent by
    // parent too, over the triangles the whole-domain refinement had when
    // it stopped (the seed, then dropped)
    let seeded = level0.max_error > tolerances[0];
    let mut raw_levels = vec![level0];
    refine_by_parents(
        src,
        reference,
        &mut verts,
        vsample,
        &mut raw_levels,
        &tolerances[usize::from(!seeded)..],
        opts.keep_border,
        interrupt,
    )?;
    if seeded {
        raw_levels.remove(0);
        raw_levels[0].parents = Vec::new();
    }
    Ok((verts, raw_levels))
}

/// Vertices level 0 gets in one triangulation of the whole domain; a level
/// 0 needing more is refined on from there parent by parent (the
/// triangulation of a vertex costs about 150 bytes; a parent's, only while
/// it is refined).
const SEED_VERTICES: usize = 65536;

/// A builder of the whole domain on `grid`, its convex `hull` (sample
/// indices) inserted; `keep_border`: flags for the hull sides' samples.
fn start<'g, S: Samples, T: Tri>(
    grid: &'g S,
    hull: &[usize],
    keep_border: bool,
    reference: Option<&'g dyn Reference>,
) -> Result<Builder<'g, S, T>, TinError> {
    if hull.len() < 3 {
        return Err(TinError::Degenerate(
            "all samples are collinear: a tin needs at least 3 non-collinear samples".into(),
        ));
    }
    let mut b = Scratch::default().builder(grid, grid.len(), keep_border);
    b.reference = reference;
    for &i in hull {
        b.insert_sample(i, None)?;
    }
    Ok(b)
}

/// Level 0: refine `b` (its hull inserted) to `tol`, the vertices of the
/// hull's `sides` (keep_border) chosen first, from each side's samples
/// alone (a seam's two tiles agree on them).
fn refine_level0<S: Samples, T: Tri>(
    b: &mut Builder<'_, S, T>,
    sides: &[Vec<usize>],
    tol: f64,
    max_vertices: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<RawLevel, TinError> {
    for &i in sides.iter().flatten() {
        b.reserved[i] = true;
    }
    let mut border_error = 0.0f64;
    let mut new = Vec::new();
    for side in sides {
        interrupt()?;
        let mut chosen: Vec<bool> = (0..side.len())
            .map(|k| k == 0 || k + 1 == side.len())
            .collect();
        let grid = b.grid;
        border_error = border_error.max(choose_border(
            &|i| grid.point(i),
            side,
            &mut chosen,
            tol,
            &mut new,
        ));
    }
    for i in new {
        if !b.inserted[i] {
            b.insert_sample(i, None)?;
        }
    }
    let max_error = b.refine(tol, max_vertices, interrupt)?.max(border_error);
    Ok(RawLevel {
        tolerance: tol,
        max_error,
        num_vertices: b.dt.num_vertices() as u32,
        tris: b.snapshot(),
        parents: Vec::new(),
        void: Vec::new(),
    })
}

/// Largest lattice window, in pixels per sample, read in place
/// ([`build_dense`]); sparser samples are bucketed.
const DENSE_PIXELS_PER_SAMPLE: usize = 8;

/// The samples of a lattice build in place on their window of the lattice,
/// when it is not much larger than they are and no pixel is given twice.
fn dense_of(samples: &[[f64; 3]]) -> Option<Dense> {
    let (mut c0, mut r0, mut c1, mut r1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
    for p in samples {
        let (c, r) = (p[0] as i64, p[1] as i64);
        (c0, r0, c1, r1) = (c0.min(c), r0.min(r), c1.max(c), r1.max(r));
    }
    if samples.is_empty() {
        return None;
    }
    let (w, h) = ((c1 - c0 + 1) as usize, (r1 - r0 + 1) as usize);
    if w.checked_mul(h)? > DENSE_PIXELS_PER_SAMPLE * samples.len() + (1 << 20) {
        return None;
    }
    let mut d = Dense {
        c0,
        r0,
        width: w,
        height: h,
        z: vec![f64::NAN; w * h],
    };
    for p in samples {
        let i = d.index(p[0] as i64, p[1] as i64);
        if !d.z[i].is_nan() {
            return None;
        }
        d.z[i] = p[2];
    }
    Some(d)
}

/// A lattice build on the samples in place ([`Dense`]): the hull from each
/// row's first and last pixel with data, its sides' samples by gcd steps,
/// level 0 refined in one triangulation and the finer levels parent by
/// parent on windows of the lattice.
fn build_dense(
    d: Dense,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let mut ends: Vec<usize> = Vec::new();
    for r in 0..d.height {
        let row = r * d.width..(r + 1) * d.width;
        let first = row.clone().find(|&i| d.valid(i));
        let last = row.rev().find(|&i| d.valid(i));
        if let (Some(a), Some(b)) = (first, last) {
            ends.push(a);
            if b != a {
                ends.push(b);
            }
        }
    }
    let count = d.z.iter().filter(|z| !z.is_nan()).count();
    if count < 3 {
        return Err(TinError::Degenerate(format!(
            "need at least 3 samples with distinct x,y to build a tin, got {count}"
        )));
    }
    ends.sort_by_key(|&i| d.col_row(i));
    let pts: Vec<[f64; 3]> = ends.iter().map(|&i| d.point(i)).collect();
    let hull: Vec<usize> = convex_hull(&pts).into_iter().map(|k| ends[k]).collect();
    let whole = d.window(d.c0, d.r0, d.width, d.height);
    let grid_reference = GridReference::on_lattice(&d);
    let reference = opts
        .between_samples
        .then_some(&grid_reference as &dyn Reference);
    let b: Builder<'_, _, Dt> = start(&whole, &hull, opts.keep_border, reference)?;
    let sides: Vec<Vec<usize>> = if opts.keep_border {
        (0..hull.len())
            .map(|k| lattice_side(&d, hull[k], hull[(k + 1) % hull.len()]))
            .collect()
    } else {
        Vec::new()
    };
    let (verts, raw_levels) =
        build_levels(b, &d, reference, &sides, &[], tolerances, opts, interrupt)?;
    drop(d);
    assemble(verts, raw_levels, srid, false, interrupt)
}

/// The samples with data on the segment between samples `a` and `b` of a
/// lattice, both ends included, in the segment's canonical order (from its
/// end smaller in (x, y)), as [`hull_sides`] gives them.
fn lattice_side(d: &Dense, a: usize, b: usize) -> Vec<usize> {
    let mut side = vec![a];
    d.on_segment(a, b, &mut side);
    side.push(b);
    if d.col_row(b) < d.col_row(a) {
        side.reverse();
    }
    side
}

/// Rounds of forcing crossings onto sides per level (a round refines
/// again only the parents of the sides it split).
const FORCING_ROUNDS: usize = 8;

/// Refine the triangle of [`Dense`] samples `corners` (counter-clockwise;
/// slots past the lattice are `extras`) to `tol`. When its corners are
/// pixels and its sides are split at pixels only, on the window of the
/// lattice around it: the vertices on each edge `k` (corner `k` to `k + 1`,
/// its samples found by gcd steps) planned by [`plan_side`] unless `free[k]`
/// (a hull side without keep_border, whose samples are the greedy
/// refinement's candidates), then greedy insertion of the samples inside,
/// in a Delaunay triangulation of the triangle's own samples. Otherwise
/// (a corner or a side's vertex at a grid-line crossing) as scattered
/// samples are ([`refine_parent_general`]).
#[allow(clippy::too_many_arguments)]
fn refine_parent(
    d: &Dense,
    reference: Option<&dyn Reference>,
    extras: &[[f64; 3]],
    forced: &Forced,
    scratch: &mut Scratch,
    parent: u32,
    corners: [u32; 3],
    free: [bool; 3],
    void: Void,
    tol: f64,
) -> Result<ParentOut, TinError> {
    let n = d.z.len();
    let pos = |s: u32| -> [f64; 3] {
        let s = s as usize;
        if s < n {
            d.point(s)
        } else {
            extras.get(s - n).copied().unwrap_or([f64::NAN; 3])
        }
    };
    let c = corners.map(pos);
    if void.is_none() && corners.iter().all(|&s| (s as usize) < n) {
        let plans: Vec<SidePlan> = (0..3)
            .filter(|&k| !free[k])
            .map(|k| {
                let side = lattice_side(d, corners[k] as usize, corners[(k + 1) % 3] as usize);
                let on: Vec<(usize, [f64; 3])> = side[1..side.len() - 1]
                    .iter()
                    .map(|&g| (g, d.point(g)))
                    .collect();
                let (a, b) = (side[0], side[side.len() - 1]);
                plan_side(
                    [Pt::Sample(a), Pt::Sample(b)],
                    &d.point(a),
                    &d.point(b),
                    &on,
                    reference,
                    forced,
                    tol,
                )
            })
            .collect();
        if plans
            .iter()
            .all(|p| p.chosen.iter().all(|q| matches!(q, Pt::Sample(_))))
        {
            let cr = corners.map(|s| d.col_row(s as usize));
            let (c0, c1) = (
                cr.iter().map(|p| p.0).min().unwrap_or(0),
                cr.iter().map(|p| p.0).max().unwrap_or(0),
            );
            let (r0, r1) = (
                cr.iter().map(|p| p.1).min().unwrap_or(0),
                cr.iter().map(|p| p.1).max().unwrap_or(0),
            );
            let win = d.window(c0, r0, (c1 - c0 + 1) as usize, (r1 - r0 + 1) as usize);
            let wn = win.len();
            let local = |p: &Pt| match *p {
                Pt::Sample(g) => Pt::Sample(win.local(g)),
                at => at,
            };
            let plans: Vec<SidePlan> = plans
                .into_iter()
                .map(|p| SidePlan {
                    reserve: p.reserve.iter().map(|&g| win.local(g)).collect(),
                    chosen: p.chosen.iter().map(local).collect(),
                    order: p.order.iter().map(local).collect(),
                    err: p.err,
                })
                .collect();
            let mut b = scratch.builder(&win, wn, !free.iter().all(|&f| f));
            b.reference = reference;
            let (err, _) = b.refine_parent(corners.map(|s| win.local(s as usize)), &plans, tol)?;
            let unmended = b.unmended(tol, &c, free);
            let tris = b.snapshot();
            let verts = b
                .vsample
                .iter()
                .map(|&k| win.global(k as usize) as u32)
                .collect();
            scratch.keep(b);
            return Ok(ParentOut {
                parent,
                verts,
                at: Vec::new(),
                tris,
                err,
                unmended,
            });
        }
    }
    let gather = |x0: f64, y0: f64, x1: f64, y1: f64, f: &mut dyn FnMut(u32, &[f64; 3])| {
        let (cl, ch) = (
            x0.ceil().max(d.c0 as f64),
            x1.floor().min((d.c0 + d.width as i64 - 1) as f64),
        );
        let (rl, rh) = (
            y0.ceil().max(d.r0 as f64),
            y1.floor().min((d.r0 + d.height as i64 - 1) as f64),
        );
        if !(cl <= ch && rl <= rh) {
            return;
        }
        for r in rl as i64..=rh as i64 {
            for cc in cl as i64..=ch as i64 {
                let i = d.index(cc, r);
                if d.valid(i) {
                    f(i as u32, &d.point(i));
                }
            }
        }
    };
    let is_sample = corners.map(|s| (s as usize) < n);
    refine_parent_general(
        &gather, reference, forced, scratch, parent, corners, c, is_sample, free, void, tol,
    )
}

/// A builder's buffers, kept from one parent to the next on a thread: a
/// parent's triangulation is small, and allocating it anew for each (two
/// threads allocating at once through the counting allocator's shared
/// counters) made the build slower on 2 threads than on 1.
#[derive(Default)]
struct Scratch<T: Tri = Dt> {
    dt: T,
    vz: Vec<f64>,
    vsample: Vec<u32>,
    inserted: Vec<bool>,
    reserved: Vec<bool>,
    faces: Vec<FaceState>,
    heap: BinaryHeap<Entry>,
    vside: Vec<u8>,
}

impl<T: Tri> Scratch<T> {
    /// A builder on `grid` (`n` samples; `reserve`: flags for reserved
    /// samples) made of these buffers, emptied.
    fn builder<'g, S: Samples>(
        &mut self,
        grid: &'g S,
        n: usize,
        reserve: bool,
    ) -> Builder<'g, S, T> {
        let mut b = Builder {
            dt: std::mem::take(&mut self.dt),
            vz: std::mem::take(&mut self.vz),
            vsample: std::mem::take(&mut self.vsample),
            grid,
            inserted: std::mem::take(&mut self.inserted),
            reserved: std::mem::take(&mut self.reserved),
            faces: std::mem::take(&mut self.faces),
            heap: std::mem::take(&mut self.heap),
            reference: None,
            vside: std::mem::take(&mut self.vside),
            at_budget: 0,
        };
        b.dt.clear();
        b.vz.clear();
        b.vsample.clear();
        b.inserted.clear();
        b.inserted.resize(n, false);
        b.reserved.clear();
        b.reserved.resize(if reserve { n } else { 0 }, false);
        b.faces.clear();
        b.heap.clear();
        b.vside.clear();
        b
    }

    /// Take the buffers back from a finished builder.
    fn keep<S: Samples>(&mut self, b: Builder<'_, S, T>) {
        self.dt = b.dt;
        self.vz = b.vz;
        self.vsample = b.vsample;
        self.inserted = b.inserted;
        self.reserved = b.reserved;
        self.faces = b.faces;
        self.heap = b.heap;
        self.vside = b.vside;
    }
}

/// Samples' worth of parents handed to a thread at once.
const GROUP_SAMPLES: f64 = 16384.0;

/// The levels after the first, each refined parent by parent. A triangle of level `l` holds exactly the triangles of level
/// `l + 1` inside it, and no edge of level `l` crosses it, so its
/// refinement depends only on its own samples once the vertices on its
/// three edges are fixed. Those are chosen from each edge's own profile
/// ([`plan_side`]: its samples, exactly on it on a lattice, on it up to
/// rounding for scattered samples, see [`refine_parent_general`], and its
/// grid-line crossings with the `reference`), in the edge's canonical
/// order, so the two triangles sharing an edge choose the same vertices on
/// it without knowing of each other; the samples on the convex hull's
/// sides stay candidates of the greedy refinement (as in level 0) unless
/// `keep_border`. Parents are refined on `tin::par`'s threads, and their
/// vertices numbered in parent order (a vertex shared with an earlier
/// parent keeps its number: a sample by its slot, a vertex at a crossing by
/// its position, which both parents compute bit for bit), so the result
/// does not depend on the thread count. `vsample` is the slot of each
/// vertex in `verts`: a sample, or `d.slots() + k` for `extras[k]`.
#[allow(clippy::too_many_arguments)]
fn refine_by_parents<P: ParentSamples>(
    d: &P,
    reference: Option<&dyn Reference>,
    verts: &mut Vec<[f64; 3]>,
    mut vsample: Vec<u32>,
    raw: &mut Vec<RawLevel>,
    tolerances: &[f64],
    keep_border: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let slots = d.slots();
    // vertices at grid-line crossings (sides split at the crossings), slot
    // `slots + k`
    let mut extras: Vec<[f64; 3]> = Vec::new();
    let mut vertex_of = vec![NONE; slots];
    for (v, &s) in vsample.iter().enumerate() {
        vertex_of[s as usize] = v as u32;
    }
    let key = |p: &[f64; 3]| (p[0].to_bits(), p[1].to_bits());
    let mut extra_slot: rustc_hash::FxHashMap<(u64, u64), usize> = Default::default();
    for &tol in tolerances {
        let Some((prev, prev_void)) = raw.last().map(|r| (&r.tris, &r.void)) else {
            return Err(TinError::Degenerate("internal: no level to refine".into()));
        };
        // the hull sides' edges, whose samples stay greedy candidates
        // (bit k of a triangle: its edge from corner k to k + 1)
        // (and under keep_border, sides only their own samples decide);
        // a void parent's: its sides shared with the domain ([`Void`])
        let nbrs = if keep_border && reference.is_none() && prev_void.is_empty() {
            Vec::new()
        } else {
            compute_neighbours(prev)?
        };
        let hull: Vec<u8> = if keep_border && reference.is_none() {
            Vec::new()
        } else {
            nbrs.iter()
                .map(|n| {
                    (0..3)
                        .filter(|&k| n[(k + 2) % 3] == NONE)
                        .fold(0, |m, k| m | 1 << k)
                })
                .collect()
        };
        let is_void = |t: usize| prev_void.get(t).copied().unwrap_or(false);
        let void_of = |t: usize| -> Void {
            is_void(t).then(|| {
                [0, 1, 2].map(|k| {
                    let n = nbrs[t][(k + 2) % 3];
                    n != NONE && !is_void(n as usize)
                })
            })
        };
        let corner_samples = vsample.clone();
        let corner_extras = extras.clone();
        // a corner's position, from its slot (no borrow of `verts`, which
        // the merge grows)
        let corner_pos = |slot: u32| -> [f64; 3] {
            let s = slot as usize;
            if s < slots {
                d.sample(s)
            } else {
                corner_extras[s - slots]
            }
        };
        let free_of = |t: usize| {
            [0, 1, 2].map(|k| !keep_border && reference.is_none() && hull[t] & (1 << k) != 0)
        };
        // the parents `ts` in groups of about GROUP_SAMPLES samples
        let groups_of = |ts: &[usize]| -> Vec<std::ops::Range<usize>> {
            let mut groups = Vec::new();
            let (mut start, mut acc) = (0usize, 0.0f64);
            for (i, &t) in ts.iter().enumerate() {
                let [a, b, c] = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                // about the samples inside
                acc += ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs()
                    / 2.0
                    / d.cell_area()
                    + 1.0;
                if acc >= GROUP_SAMPLES {
                    groups.push(start..i + 1);
                    (start, acc) = (i + 1, 0.0);
                }
            }
            if start < ts.len() {
                groups.push(start..ts.len());
            }
            groups
        };
        // those parents refined (in order, on threads), their sides split
        // at `forced` crossings too, each batch's outputs handed to `take`
        let run = |ts: &[usize],
                   groups: &[std::ops::Range<usize>],
                   forced: &Forced,
                   interrupt: &mut Interrupt<'_>,
                   take: &mut dyn FnMut(ParentOut) -> Result<(), TinError>|
         -> Result<(), TinError> {
            super::par::map_batched(
                groups,
                |g| {
                    let mut scratch = Scratch::default();
                    ts[g.clone()]
                        .iter()
                        .map(|&t| {
                            let corners = prev[t].map(|v| corner_samples[v as usize]);
                            d.refine_parent(
                                reference,
                                &corner_extras,
                                forced,
                                &mut scratch,
                                t as u32,
                                corners,
                                free_of(t),
                                void_of(t),
                                tol,
                            )
                        })
                        .collect::<Result<Vec<_>, TinError>>()
                },
                interrupt,
                &mut |o: Result<Vec<ParentOut>, TinError>| {
                    for p in o? {
                        take(p)?;
                    }
                    Ok(())
                },
            )
        };
        let all: Vec<usize> = (0..prev.len()).collect();
        let all_groups = groups_of(&all);
        let mut tris: Vec<[u32; 3]> = Vec::new();
        let mut parents: Vec<u32> = Vec::new();
        let mut max_error = 0.0f64;
        let mut merge = |o: ParentOut| -> Result<(), TinError> {
            max_error = max_error.max(o.err);
            let ids: Vec<u32> = o
                .verts
                .iter()
                .map(|&src| {
                    let (slot, p) = if src & AT_FLAG == 0 {
                        (src as usize, None)
                    } else {
                        let p = o.at[(src & !AT_FLAG) as usize];
                        let slot = *extra_slot.entry(key(&p)).or_insert_with(|| {
                            extras.push(p);
                            vertex_of.push(NONE);
                            slots + extras.len() - 1
                        });
                        (slot, Some(p))
                    };
                    let v = &mut vertex_of[slot];
                    if *v == NONE {
                        *v = verts.len() as u32;
                        verts.push(p.unwrap_or_else(|| d.sample(slot)));
                        vsample.push(slot as u32);
                    }
                    *v
                })
                .collect();
            tris.extend(o.tris.iter().map(|t| t.map(|k| ids[k as usize])));
            parents.extend(std::iter::repeat_n(o.parent, o.tris.len()));
            Ok(())
        };
        if reference.is_none() {
            // measured at the samples only: each batch merged as it comes
            // (no level's parents held at once)
            run(&all, &all_groups, &Forced::default(), interrupt, &mut merge)?;
        } else {
            let mut forced = Forced::default();
            // under keep_border a hull side is a tile's seam: its vertices
            // are its own samples' choice, the same in the tile beside it,
            // so nothing is forced onto it
            let seams: rustc_hash::FxHashSet<SideKey> = if keep_border {
                (0..prev.len())
                    .flat_map(|t| (0..3).map(move |k| (t, k)))
                    .filter(|&(t, k)| hull[t] & (1 << k) != 0)
                    .map(|(t, k)| {
                        let c = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                        side_key(&c[k], &c[(k + 1) % 3])
                    })
                    .collect()
            } else {
                Default::default()
            };
            let mut outs: Vec<ParentOut> = Vec::with_capacity(prev.len());
            run(&all, &all_groups, &forced, interrupt, &mut |o| {
                outs.push(o);
                Ok(())
            })?;
            // a crossing inside a parent that no pixel could mend, in the
            // strip between a free edge and a side whose grid segment
            // crosses the side: that side is split where the segment
            // crosses it, in both its parents, and they are refined again
            for _ in 0..FORCING_ROUNDS {
                let mut touched: rustc_hash::FxHashSet<SideKey> = Default::default();
                for o in &outs {
                    for (side, seg) in &o.unmended {
                        if seams.contains(side) {
                            continue;
                        }
                        let v = forced.entry(*side).or_default();
                        if !v.contains(seg) {
                            v.push(*seg);
                            touched.insert(*side);
                        }
                    }
                }
                if touched.is_empty() {
                    break;
                }
                let redo: Vec<usize> = (0..prev.len())
                    .filter(|&t| {
                        let c = prev[t].map(|v| corner_pos(corner_samples[v as usize]));
                        (0..3).any(|k| touched.contains(&side_key(&c[k], &c[(k + 1) % 3])))
                    })
                    .collect();
                let redo_groups = groups_of(&redo);
                let mut k = 0;
                run(&redo, &redo_groups, &forced, interrupt, &mut |o| {
                    outs[redo[k]] = o;
                    k += 1;
                    Ok(())
                })?;
            }
            drop(forced);
            for o in outs {
                merge(o)?;
            }
        }
        drop(hull);
        drop(nbrs);
        tris.shrink_to_fit();
        parents.shrink_to_fit();
        // a child is void when its parent is
        let void: Vec<bool> = if prev_void.is_empty() {
            Vec::new()
        } else {
            parents.iter().map(|&p| is_void(p as usize)).collect()
        };
        raw.push(RawLevel {
            tolerance: tol,
            max_error,
            num_vertices: verts.len() as u32,
            tris,
            parents,
            void,
        });
    }
    Ok(())
}

/// The samples a build refined parent by parent reads: a raster's lattice
/// in place ([`Dense`]) or bucketed scattered samples ([`SampleGrid`]).
trait ParentSamples: Sync {
    /// Sample numbers are `0..slots()`.
    fn slots(&self) -> usize;
    /// Sample `s`: x, y, z.
    fn sample(&self, s: usize) -> [f64; 3];
    /// Area holding about one sample.
    fn cell_area(&self) -> f64;
    /// Refine the triangle of samples `corners` (counter-clockwise; slot
    /// `slots() + k` is `extras[k]`) to `tol`: its edges `k` (corner `k` to
    /// `k + 1`) not `free[k]` keep the vertices [`plan_side`] picks from the
    /// edge's own profile. `void`: the triangle is outside the domain
    /// ([`Void`]).
    #[allow(clippy::too_many_arguments)]
    fn refine_parent(
        &self,
        reference: Option<&dyn Reference>,
        extras: &[[f64; 3]],
        forced: &Forced,
        scratch: &mut Scratch,
        parent: u32,
        corners: [u32; 3],
        free: [bool; 3],
        void: Void,
        tol: f64,
    ) -> Result<ParentOut, TinError>;
}

impl ParentSamples for Dense {
    fn slots(&self) -> usize {
        self.z.len()
    }
    fn sample(&self, s: usize) -> [f64; 3] {
        self.point(s)
    }
    fn cell_area(&self) -> f64 {
        1.0
    }
    fn refine_parent(
        &self,
        reference: Option<&dyn Reference>,
        extras: &[[f64; 3]],
        forced: &Forced,
        scratch: &mut Scratch,
        parent: u32,
        corners: [u32; 3],
        free: [bool; 3],
        void: Void,
        tol: f64,
    ) -> Result<ParentOut, TinError> {
        refine_parent(
            self, reference, extras, forced, scratch, parent, corners, free, void, tol,
        )
    }
}

impl ParentSamples for SampleGrid {
    fn slots(&self) -> usize {
        self.pts.len()
    }
    fn sample(&self, s: usize) -> [f64; 3] {
        self.pts[s]
    }
    fn cell_area(&self) -> f64 {
        SampleGrid::cell_area(self)
    }
    fn refine_parent(
        &self,
        reference: Option<&dyn Reference>,
        extras: &[[f64; 3]],
        forced: &Forced,
        scratch: &mut Scratch,
        parent: u32,
        corners: [u32; 3],
        free: [bool; 3],
        void: Void,
        tol: f64,
    ) -> Result<ParentOut, TinError> {
        let n = self.pts.len();
        let c = corners.map(|s| {
            let s = s as usize;
            if s < n {
                self.pts[s]
            } else {
                extras.get(s - n).copied().unwrap_or([f64::NAN; 3])
            }
        });
        let gather = |x0: f64, y0: f64, x1: f64, y1: f64, f: &mut dyn FnMut(u32, &[f64; 3])| {
            self.for_each_in_box(x0, y0, x1, y1, |i, p| f(i as u32, p));
        };
        let is_sample = corners.map(|s| (s as usize) < n);
        refine_parent_general(
            &gather, reference, forced, scratch, parent, corners, c, is_sample, free, void, tol,
        )
    }
}

/// Calls `f(slot, sample)` for every sample in a closed box
/// (`x0, y0, x1, y1`).
type Gather<'a> = dyn Fn(f64, f64, f64, f64, &mut dyn FnMut(u32, &[f64; 3])) + 'a;

/// A parent's refinement where "on the edge" is decided up to rounding:
/// scattered samples, and on a lattice a parent with a corner or a side's
/// vertex at a grid-line crossing. No lattice decides which samples lie on
/// an edge: a sample within rounding of it (the triangle it makes with the
/// edge is a sliver, [`crate::geom::is_sliver`]), on either side, between
/// its ends, is the edge's sample. Both triangles sharing the edge find the
/// same ones (the test is symmetric and exact) and list them in the same
/// order (along the edge's longer axis from its canonical end), so
/// [`plan_side`] picks the same vertices there in both. The triangle's own
/// samples, its edges' and their chosen crossings are triangulated alone;
/// slivers along an edge are dropped ([`Builder::snapshot`]) and a triangle
/// whose side skips chosen vertices of the edge (they lie a rounding
/// outside it) is split into a fan through them, so both sides of the edge
/// meet at exactly the same vertices: no crack and no T-junction.
/// `corners`: slots, at `c`; `is_sample[k]`: corner `k` is a sample (else a
/// vertex at a crossing).
#[allow(clippy::too_many_arguments)]
fn refine_parent_general(
    gather: &Gather<'_>,
    reference: Option<&dyn Reference>,
    forced: &Forced,
    scratch: &mut Scratch,
    parent: u32,
    corners: [u32; 3],
    c: [[f64; 3]; 3],
    is_sample: [bool; 3],
    free: [bool; 3],
    void: Void,
    tol: f64,
) -> Result<ParentOut, TinError> {
    // each edge from its canonical end (the smaller in (x, y))
    let ends: [(usize, usize); 3] = [0, 1, 2].map(|k| {
        let (i, j) = (k, (k + 1) % 3);
        if (c[j][0], c[j][1]) < (c[i][0], c[i][1]) {
            (j, i)
        } else {
            (i, j)
        }
    });
    // the band of a sliver is within about 128 ulps of the largest
    // coordinate of an edge: the box searched is wider
    let m = crate::geom::max_abs_xy(&c[0], &c[1], &c[2]).max(f64::MIN_POSITIVE);
    let pad = 1024.0 * f64::EPSILON * m;
    let x0 = c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min) - pad;
    let x1 = c.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max) + pad;
    let y0 = c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min) - pad;
    let y1 = c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max) + pad;
    // the triangle's samples, corners first, in the order found; `on[k]`:
    // edge k's samples as (position along it, x, y, index in `pts`)
    let mut pts: Vec<[f64; 3]> = c.to_vec();
    let mut gid: Vec<u32> = (0..3)
        .map(|k| if is_sample[k] { corners[k] } else { NONE })
        .collect();
    let mut on: [Vec<(f64, f64, f64, u32)>; 3] = Default::default();
    gather(x0, y0, x1, y1, &mut |i, p| {
        if (0..3).any(|k| is_sample[k] && corners[k] == i) {
            return;
        }
        let mut keep = (0..3).all(|k| crate::geom::orient(&c[k], &c[(k + 1) % 3], p) >= 0.0);
        for k in 0..3 {
            if free[k] {
                continue;
            }
            let (a, b) = (&c[ends[k].0], &c[ends[k].1]);
            if !crate::geom::is_sliver(a, b, p) {
                continue;
            }
            // strictly between the ends along the edge's longer axis
            let ax = if (b[0] - a[0]).abs() >= (b[1] - a[1]).abs() {
                0
            } else {
                1
            };
            let (lo, hi) = (a[ax].min(b[ax]), a[ax].max(b[ax]));
            if p[ax] > lo && p[ax] < hi {
                on[k].push(((p[ax] - a[ax]).abs(), p[0], p[1], pts.len() as u32));
                keep = true;
            }
        }
        if keep {
            pts.push(*p);
            gid.push(i);
        }
    });
    // each fixed side's plan, by index in `pts`; its chosen crossings
    // become points of `pts` too (no sample: `gid` NONE)
    let mut plans: Vec<SidePlan> = Vec::new();
    for k in 0..3 {
        if free[k] {
            continue;
        }
        on[k].sort_by(|u, v| {
            u.0.total_cmp(&v.0)
                .then(u.1.total_cmp(&v.1))
                .then(u.2.total_cmp(&v.2))
        });
        let side: Vec<(usize, [f64; 3])> = on[k]
            .iter()
            .map(|e| (e.3 as usize, pts[e.3 as usize]))
            .collect();
        let (ea, eb) = ends[k];
        // a void parent's side between two void parents: left whole
        let (side_reference, side_tol) = match void {
            Some(domain) if !domain[k] => (None, VOID_TOL),
            _ => (reference, tol),
        };
        let mut plan = plan_side(
            [Pt::Sample(ea), Pt::Sample(eb)],
            &c[ea],
            &c[eb],
            &side,
            side_reference,
            forced,
            side_tol,
        );
        for q in &mut plan.chosen {
            if let Pt::At(p) = *q {
                *q = Pt::Sample(pts.len());
                pts.push(p);
                gid.push(NONE);
            }
        }
        // the same points in the split's order: the crossings by the index
        // just given them
        for q in &mut plan.order {
            if let Pt::At(p) = *q {
                let k = (0..pts.len())
                    .rev()
                    .find(|&k| gid[k] == NONE && pts[k][..2] == p[..2])
                    .ok_or_else(|| {
                        TinError::Degenerate("internal: a chosen crossing was lost".into())
                    })?;
                *q = Pt::Sample(k);
            }
        }
        plans.push(plan);
    }
    let n = pts.len();
    let local = SampleGrid::with_ids(pts, (0..n as u32).collect(), 1.0);
    // the local sample of each position in `pts`
    let mut pos = vec![0usize; n];
    for (l, &k) in local.ids.iter().enumerate() {
        pos[k as usize] = l;
    }
    for plan in &mut plans {
        for s in &mut plan.reserve {
            *s = pos[*s];
        }
        for q in plan.chosen.iter_mut().chain(plan.order.iter_mut()) {
            if let Pt::Sample(s) = q {
                *s = pos[*s];
            }
        }
    }
    let mut b = scratch.builder(&local, n, free.iter().any(|f| !f));
    b.reference = if void.is_some() { None } else { reference };
    b.at_budget = if b.reference.is_some_and(|r| r.mends_at_crossings()) {
        4 * n + 64
    } else {
        0
    };
    let (err, chains) = b.refine_parent(
        [pos[0], pos[1], pos[2]],
        &plans,
        if void.is_some() { VOID_TOL } else { tol },
    )?;
    // a void parent's error is no level's
    let err = if void.is_some() { 0.0 } else { err };
    let unmended = b.unmended(tol, &c, free);
    let mut tris = b.snapshot();
    if chains.iter().any(|ch| ch.len() > 2) {
        tris = close_chains(tris, &chains, &b.vsample, &|v| {
            b.vert3(FixedVertexHandle::from_index(v))
        });
    }
    let mut at: Vec<[f64; 3]> = Vec::new();
    let verts = b
        .vsample
        .iter()
        .enumerate()
        .map(
            |(v, &l)| match local.ids.get(l as usize).map_or(NONE, |&k| gid[k as usize]) {
                NONE => {
                    at.push(b.vert3(FixedVertexHandle::from_index(v)));
                    AT_FLAG | (at.len() - 1) as u32
                }
                g => g,
            },
        )
        .collect();
    scratch.keep(b);
    Ok(ParentOut {
        parent,
        verts,
        at,
        tris,
        err,
        unmended,
    })
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

/// Whether a parent is outside the domain (a build's boundary, a hole in
/// it), and then which of its sides border a parent inside: `Some(domain)`,
/// side `k` (corner `k` to `k + 1`) shared with a parent in the domain when
/// `domain[k]`. No merge reads a void triangle's surface, so a void parent
/// is split only where it must meet its neighbours: its sides shared with
/// the domain take the vertices the parent inside plans there (the same
/// plan, against the same reference), its other sides and its inside stay
/// as they are (but for samples in a sliver, which every triangulation
/// takes). Refining it against the reference, as before, grew crossings on
/// needles between a boundary's ring and the samples' hull that lay within
/// rounding of the needle's other side: holes and cracks at the finer
/// levels. `None`: a parent in the domain.
type Void = Option<[bool; 3]>;

/// The tolerance of a void parent: nothing is inserted but the samples in
/// a sliver (their error is `f64::MAX`).
const VOID_TOL: f64 = f64::MAX / 4.0;

/// [`ParentOut::verts`]: the vertex is a point of [`ParentOut::at`].
const AT_FLAG: u32 = 1 << 31;

/// One parent's refinement: its vertices (samples by slot, or points at
/// grid-line crossings; its corners first), its triangles by index into
/// them, the worst error left.
struct ParentOut {
    parent: u32,
    /// a sample's slot, or `AT_FLAG | k` for the point `at[k]`
    verts: Vec<u32>,
    at: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    err: f64,
    /// crossings over the tolerance that no pixel could mend, by the side
    /// their grid segment crosses ([`Builder::unmended`])
    unmended: Vec<(SideKey, SegKey)>,
}

/// Build a hierarchy from raster samples given on the pixel lattice,
/// `(col, row, z)` with integer `col`, `row`: topology is decided there,
/// where pixel centres on one line are exactly collinear, and the result is
/// mapped to world coordinates by `lattice` (see [`super::lattice`]).
pub fn build_lattice(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    build_lattice_window(samples, lattice, (0, 0), tolerances, srid, opts, interrupt)
}

/// [`build_lattice`] of a window of a raster (a tile), its decisions made
/// in the window's own frame: `samples` are numbered on `lattice`, and the
/// build runs on them renumbered from `origin` (the window's first pixel),
/// so every vertex it puts where an edge crosses a grid line is computed,
/// and rounds, as in a build of the window cut out as a raster of its own
/// (its first pixel at 0, 0). The tin is then put back on `lattice`
/// (vertices at `origin` + their window coordinates, samples exactly),
/// so a pixel centre two windows share is the same point in both.
pub fn build_lattice_window(
    mut samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let (c0, r0) = (origin.0 as f64, origin.1 as f64);
    if !(c0.abs() <= 1e9 && r0.abs() <= 1e9) {
        return Err(TinError::InvalidParameter(format!(
            "window origin ({}, {}) is too far from the raster's",
            origin.0, origin.1
        )));
    }
    for s in &mut samples {
        // whole numbers (checked below as the window's): exact
        s[0] -= c0;
        s[1] -= r0;
    }
    if !lattice.is_valid() {
        return Err(TinError::InvalidParameter(format!(
            "raster georeference is degenerate or not finite (scale {} x {}, skew {} x {})",
            lattice.scale_x, lattice.scale_y, lattice.skew_x, lattice.skew_y
        )));
    }
    if let Some(p) = samples.iter().find(|p| {
        p[0] != p[0].trunc() || p[1] != p[1].trunc() || p[0].abs() > 1e9 || p[1].abs() > 1e9
    }) {
        return Err(TinError::InvalidParameter(format!(
            "lattice samples need whole column and row numbers, got ({}, {})",
            p[0] + c0,
            p[1] + r0
        )));
    }
    let mut tin = build_inner(
        samples,
        &[],
        &[],
        tolerances,
        srid,
        opts,
        true,
        None,
        interrupt,
    )?;
    for v in &mut tin.verts {
        v[0] += c0;
        v[1] += r0;
    }
    let tin = lattice.to_world(tin);
    for v in &tin.verts {
        super::check_xy("a pixel centre", v[0], v[1])?;
    }
    Ok(tin)
}

/// Morton code of a point normalised to the bbox (16 bits per axis).
fn morton(b: &Bbox, x: f64, y: f64) -> u32 {
    let nx = ((x - b.min_x) / (b.max_x - b.min_x).max(f64::MIN_POSITIVE) * 65535.0) as u32;
    let ny = ((y - b.min_y) / (b.max_y - b.min_y).max(f64::MIN_POSITIVE) * 65535.0) as u32;
    fn spread(mut v: u32) -> u32 {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff00ff;
        v = (v | (v << 4)) & 0x0f0f0f0f;
        v = (v | (v << 2)) & 0x33333333;
        v = (v | (v << 1)) & 0x55555555;
        v
    }
    spread(nx) | (spread(ny) << 1)
}

/// Sort each level's block of new vertices (`num_vertices` of the previous
/// level up to its own) by Morton code, keeping the prefix property, and
/// renumber the triangles: vertices near in space are then near in memory,
/// which is what a walk between neighbouring triangles reads.
fn reorder_vertices(verts: Vec<[f64; 3]>, raw: &mut [RawLevel]) -> Vec<[f64; 3]> {
    let bbox = Bbox::of(&verts);
    let mut order: Vec<u32> = (0..verts.len() as u32).collect();
    let mut start = 0usize;
    for r in raw.iter() {
        let end = (r.num_vertices as usize).min(verts.len());
        if end > start {
            order[start..end].sort_by_key(|&v| {
                let p = verts[v as usize];
                (morton(&bbox, p[0], p[1]), v)
            });
            start = end;
        }
    }
    let mut new_id = vec![0u32; verts.len()];
    for (new, &old) in order.iter().enumerate() {
        new_id[old as usize] = new as u32;
    }
    for r in raw.iter_mut() {
        for t in r.tris.iter_mut() {
            for v in t.iter_mut() {
                *v = new_id[*v as usize];
            }
        }
    }
    order.iter().map(|&v| verts[v as usize]).collect()
}

/// Order triangles, link neighbours, place parents and
/// build grid indexes (when `grids`; else left empty for the caller).
fn assemble(
    verts: Vec<[f64; 3]>,
    mut raw: Vec<RawLevel>,
    srid: i32,
    grids: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let verts = reorder_vertices(verts, &mut raw);
    let bbox = Bbox::of(&verts);
    let mut tin = Tin {
        srid,
        bbox,
        verts,
        levels: Vec::with_capacity(raw.len()),
    };
    // the final position of each triangle of the previous level, by its
    // index in that level's `tris`
    let mut position: Vec<u32> = Vec::new();
    for (l, raw_level) in raw.into_iter().enumerate() {
        let RawLevel {
            tolerance,
            max_error,
            num_vertices,
            tris,
            parents,
            void,
        } = raw_level;
        // a triangle is void when its parent is; at level 0 when marked
        let prev_domain = match l {
            0 => 0,
            _ => tin.levels[l - 1].num_domain() as u32,
        };
        if !parents.is_empty() && parents.len() != tris.len() {
            return Err(TinError::Degenerate(format!(
                "internal: {} parents for {} triangles at level {l}",
                parents.len(),
                tris.len()
            )));
        }
        interrupt()?;
        let centroid = |t: &[u32; 3]| {
            let (a, b, c) = (
                tin.verts[t[0] as usize],
                tin.verts[t[1] as usize],
                tin.verts[t[2] as usize],
            );
            ((a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0)
        };
        // parents found on threads, chunk by chunk, kept in triangle order
        let key = |i: usize| -> Result<(u32, u32, [u32; 3], u32), TinError> {
            let t = &tris[i];
            let (x, y) = centroid(t);
            let parent = if l == 0 {
                NONE
            } else if let Some(&p) = parents.get(i) {
                match position.get(p as usize) {
                    Some(&q) => q,
                    None => {
                        return Err(TinError::Degenerate(format!(
                            "internal: parent {p} of a triangle of level {l} does not exist"
                        )))
                    }
                }
            } else {
                return Err(TinError::Degenerate(format!(
                    "internal: no parent at level {} for a triangle of level {l}",
                    l - 1
                )));
            };
            // void triangles last: at level 0 by their mark, below by
            // their parent (the void ones are the previous level's last)
            let first = if l == 0 {
                u32::from(void.get(i).copied().unwrap_or(false))
            } else {
                parent
            };
            Ok((first, morton(&tin.bbox, x, y), *t, i as u32))
        };
        let chunks: Vec<std::ops::Range<usize>> = (0..tris.len())
            .step_by(4096)
            .map(|s| s..(s + 4096).min(tris.len()))
            .collect();
        let mut keyed: Vec<(u32, u32, [u32; 3], u32)> = Vec::with_capacity(tris.len());
        super::par::map_batched(
            &chunks,
            |c| c.clone().map(key).collect::<Result<Vec<_>, TinError>>(),
            interrupt,
            &mut |part| {
                keyed.extend(part?);
                Ok(())
            },
        )?;
        // each copy gone as soon as the next is made: the last level's
        // arrays are the peak of a whole build
        drop(chunks);
        drop(tris);
        drop(parents);
        interrupt()?;
        keyed.sort_unstable();
        interrupt()?;
        let tris: Vec<[u32; 3]> = keyed.iter().map(|k| k.2).collect();
        let num_void = if l == 0 {
            keyed.iter().filter(|k| k.0 == 1).count()
        } else {
            keyed.iter().filter(|k| k.0 >= prev_domain).count()
        } as u32;
        let parent: Vec<u32> = if l == 0 {
            vec![NONE; keyed.len()]
        } else {
            keyed.iter().map(|k| k.0).collect()
        };
        position = vec![0; keyed.len()];
        for (k, e) in keyed.iter().enumerate() {
            position[e.3 as usize] = k as u32;
        }
        drop(keyed);
        if l > 0 {
            let prev = &mut tin.levels[l - 1];
            prev.child_start = child_starts(&parent, prev.tris.len());
        }
        let nbrs = compute_neighbours(&tris)?;
        interrupt()?;
        let mut level = Level {
            tolerance,
            max_error,
            num_vertices,
            num_void,
            tris,
            nbrs,
            parent,
            child_start: Vec::new(),
            grid: super::Grid {
                cell: 1.0,
                nx: 0,
                ny: 0,
                cells: Vec::new(),
            },
        };
        if grids {
            level.grid = grid::build_grid(&tin.verts, &tin.bbox, &level);
        }
        tin.levels.push(level);
    }
    Ok(tin)
}

/// A single-level tin from a triangulation given as vertices and
/// counter-clockwise triangles (an overlay, for instance). Tolerance and
/// maximum error of the level are 0: the triangles are the surface.
pub fn from_triangles(
    verts: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    from_triangles_void(verts, tris, Vec::new(), srid, interrupt)
}

/// [`from_triangles`] with the triangles that are void (`void[t]`; empty:
/// none): the overlay of tins with void triangles.
pub fn from_triangles_void(
    verts: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    void: Vec<bool>,
    srid: i32,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    if !void.is_empty() && void.len() != tris.len() {
        return Err(TinError::InvalidParameter(
            "internal: void flags and triangles differ in number".into(),
        ));
    }
    if !void.is_empty() && void.iter().all(|&v| v) {
        return Err(TinError::Degenerate("no triangles to make a tin of".into()));
    }
    if tris.is_empty() {
        return Err(TinError::Degenerate("no triangles to make a tin of".into()));
    }
    let n = verts.len();
    if tris.iter().flatten().any(|&v| v as usize >= n) {
        return Err(TinError::InvalidParameter(
            "a triangle refers to a vertex that does not exist".into(),
        ));
    }
    let level = RawLevel {
        tolerance: 0.0,
        max_error: 0.0,
        num_vertices: n as u32,
        tris,
        parents: Vec::new(),
        void,
    };
    assemble(verts, vec![level], srid, true, interrupt)
}

/// Upper bound of the heap a build from `samples` points with `levels`
/// levels uses at its peak, input samples included. The finer levels are
/// refined parent by parent, so the peak is level 0's triangulation or the
/// finished tin (measured on the DEM with `tests/memory.rs`: 209 bytes a
/// sample at one level of 2 m, 149 at 5 levels, 430 when nearly every
/// sample is a vertex of every level; `cargo bench --bench build`: 38-50
/// on point clouds of 1.9 and 9.5 million points).
pub fn build_bytes(samples: usize, levels: usize) -> usize {
    samples
        .saturating_mul(330 + 40 * levels)
        .saturating_add(1 << 20)
}

/// [`build_bytes`] for a build on a pixel lattice ([`build_lattice`]),
/// whose heights are read in place (8 bytes a pixel): the peak is level 0's triangulation or
/// the finished tin with the last level's arrays being made (measured with
/// `tests/memory.rs` on the DEM: 187 bytes a sample at 1 level, 135 at 5
/// levels and 2 m, 408 when nearly every sample is a vertex of every level;
/// `cargo bench --bench build` on the DEM upsampled 4x: 97 at 5 levels, 42
/// at one). Between samples ([`BuildOptions::between_samples`]) the peak
/// is larger: 308 bytes a sample at 1 level, 521 at 5, 913 when nearly
/// every sample is a vertex (`tests/memory.rs`), so its estimate is too.
pub fn lattice_build_bytes(samples: usize, levels: usize, between_samples: bool) -> usize {
    let per = if between_samples {
        1000 + 40 * levels
    } else {
        300 + 40 * levels
    };
    samples.saturating_mul(per).saturating_add(1 << 20)
}

/// [`build_bytes`] for [`build_points`] and [`build_points_domain`]: the
/// reference triangulation of all the samples
/// ([`DelaunayReference::BYTES_PER_SAMPLE`]) held through the build, whose
/// vertices at crossings cost as a raster's between samples do.
pub fn points_build_bytes(samples: usize, levels: usize) -> usize {
    samples
        .saturating_mul(1000 + DelaunayReference::BYTES_PER_SAMPLE + 40 * levels)
        .saturating_add(1 << 20)
}

/// [`build_bytes`] for [`build_domain_raster`] over `samples` valid pixels
/// of a raster of `pixels` (whose heights, 8 bytes a pixel, are part of
/// the request).
pub fn domain_raster_build_bytes(samples: usize, pixels: usize, levels: usize) -> usize {
    samples
        .saturating_mul(1000 + 40 * levels)
        .saturating_add(pixels.saturating_mul(8))
        .saturating_add(1 << 20)
}
