//! The greedy refinement of one triangulation ([`Builder`]): faces
//! measured at their samples and crossings, the worst mended first.

use super::common::*;
use crate::interrupt::Interrupt;
use crate::tin::samples::Samples;
use crate::tin::sides::{Pt, SegKey, SideKey, SidePlan, sample_key, seg_key, side_key};
use crate::tin::surface::{Crossing, Reference};
use crate::tin::{NONE, TinError, interpolate};
use spade::Point2;
use spade::handles::FixedVertexHandle;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

#[derive(Clone, Copy)]
pub(super) struct FaceState {
    pub(super) generation: u32,
    /// the face's worst error (samples and free edges' crossings)
    pub(super) err: f64,
    pub(super) cand: u32,
    /// a corner of the face: where spade's point location starts when the
    /// candidate is inserted (it lies in this face, so the walk is short)
    pub(super) corner: u32,
    /// the point to insert when `cand` is [`AT_CAND`]
    pub(super) at: [f64; 3],
}

/// [`FaceState::cand`]: no sample, the point [`FaceState::at`]: where a
/// free edge crosses the reference's edge (a grid segment, an edge of the
/// samples' Delaunay triangulation), at the reference's height.
pub(super) const AT_CAND: u32 = NONE - 1;

/// A face's measure: its worst error (samples and free edges' crossings),
/// the error and candidate sample (or NONE) that insertion can mend, a
/// corner.
#[derive(Clone, Copy)]
pub(super) struct Measure {
    pub(super) worst: f64,
    pub(super) best: f64,
    pub(super) cand: u32,
    pub(super) corner: u32,
    pub(super) at: [f64; 3],
}

#[derive(PartialEq)]
pub(super) struct Entry {
    pub(super) err: f64,
    pub(super) face: u32,
    pub(super) generation: u32,
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
            .then(self.generation.cmp(&o.generation))
    }
}

pub(super) struct Builder<'g, S: Samples, T: Tri = Dt> {
    pub(super) dt: T,
    /// z of each triangulation vertex (by spade vertex index).
    pub(super) vz: Vec<f64>,
    /// the sample (index in `grid.pts`) each triangulation vertex is
    pub(super) vsample: Vec<u32>,
    pub(super) grid: &'g S,
    pub(super) inserted: Vec<bool>,
    /// Samples on the hull's sides under `keep_border`: never a candidate of
    /// the greedy refinement (`choose_border` decides them, the same way in
    /// every tile sharing the side).
    pub(super) reserved: Vec<bool>,
    pub(super) faces: Vec<FaceState>,
    pub(super) heap: BinaryHeap<Entry>,
    /// the surface between the samples ([`crate::tin::surface`]): free edges
    /// are measured at their crossings too
    pub(super) reference: Option<&'g dyn Reference>,
    /// by vertex: bit k set when it is on the parent's side chain k (an
    /// edge between two vertices of one chain is a piece of that side)
    pub(super) vside: Vec<u8>,
    /// crossings ([`AT_CAND`]) still to be inserted at most (their
    /// vertices' sample: NONE)
    pub(super) at_budget: usize,
    /// a raster's last resort ([`Builder::refine`]): vertices at crossings
    /// no pixel mends, once the greedy insertion of samples is done
    pub(super) raster_at: bool,
}

impl<S: Samples, T: Tri> Builder<'_, S, T> {
    pub(super) fn vert3(&self, h: FixedVertexHandle) -> [f64; 3] {
        let p = self.dt.vertex(h).position();
        [p.x, p.y, self.vz[h.index()]]
    }

    /// Whether a directed edge is fixed: on the triangulation's hull, a
    /// constraint, or a piece of a parent's side. Fixed edges are chosen
    /// from their own profile; the others are measured at their crossings.
    pub(super) fn fixed_edge(&self, e: spade::handles::FixedDirectedEdgeHandle) -> bool {
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
    pub(super) fn measure(&self, face: FaceHandle) -> Measure {
        let f = self.dt.face(face);
        let vs = f.vertices();
        let c = [
            self.vert3(vs[0].fix()),
            self.vert3(vs[1].fix()),
            self.vert3(vs[2].fix()),
        ];
        // a sliver's plane says nothing about the samples in it (and
        // `snapshot` leaves slivers out): they must all become vertices
        let sliver = crate::geom::is_sliver(&c[0], &c[1], &c[2]);
        let (best, cand) = self.worst_sample(&c, sliver);
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
            if let Some(i) = self.pixel_near(e.from().fix(), &x) {
                (m.best, m.cand) = (err, i as u32);
            } else if self.at_budget > 0
                && if r.mends_at_crossings() {
                    self.free_crossing_ok(e.fix(), &x)
                } else {
                    self.raster_at && self.raster_crossing_ok(e.fix(), &u, &w, &x)
                }
            {
                (m.best, m.cand, m.at) = (err, AT_CAND, x.p);
            } else if r.mends_at_crossings() && m.cand != NONE && m.cand != AT_CAND {
                // a crossing no vertex may stand at (it would crowd one
                // already there): the face's worst sample goes in at the
                // crossing's error, a finer triangulation of the samples
                // being what ends it (vertices at crossings alone can
                // chase each other between two grid segments, each new
                // edge crossing the other segment as badly: 5 levels of a
                // terraced 1/9" window, harness seed 2006391, closed in on
                // one point until rounding made a crack)
                m.best = err;
            }
        }
        m
    }

    /// The worst sample not yet a vertex (nor reserved) inside the face at
    /// `c`: its error and number (NONE: none); every one is worst in a
    /// `sliver`.
    fn worst_sample(&self, c: &[[f64; 3]; 3], sliver: bool) -> (f64, u32) {
        let (inserted, reserved) = (&self.inserted, &self.reserved);
        let (mut best, mut cand) = (0.0f64, NONE);
        self.grid.for_each_in_triangle(&c[0], &c[1], &c[2], |i, p| {
            if inserted[i] || (!reserved.is_empty() && reserved[i]) {
                return;
            }
            let e = if sliver {
                f64::MAX
            } else {
                (interpolate(c, p[0], p[1]) - p[2]).abs()
            };
            if e > best {
                best = e;
                cand = i as u32;
            }
        });
        (best, cand)
    }

    /// The pixel nearest the crossing `x` that can be inserted (it is
    /// inside the triangulation: the domain or the parent; `hint`: a
    /// vertex near it): once the segment's two pixels are vertices the
    /// edge is no longer Delaunay unless the crossing is within about a
    /// quarter pixel of an end; the pixels beside them help where one is
    /// outside.
    fn pixel_near(&self, hint: FixedVertexHandle, x: &Crossing) -> Option<usize> {
        let (inserted, reserved) = (&self.inserted, &self.reserved);
        x.pix.iter().find_map(|q| {
            let i = self.grid.find(q[0], q[1])?;
            if inserted[i] || (!reserved.is_empty() && reserved[i]) {
                return None;
            }
            let p = self.grid.point(i);
            let at = Point2::new(p[0], p[1]);
            // spade's walk to a position can go round in a constrained
            // triangulation and panic ("Failed to locate position. This is
            // a bug in spade.": harness seeds 11002805, 11005163): then it
            // is walked again from spade's own start, and a pixel it still
            // cannot place is passed over, as one outside is
            let walk = |hinted: bool| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    if hinted {
                        self.dt.locate_with_hint(at, hint)
                    } else {
                        self.dt.locate(at)
                    }
                }))
            };
            matches!(
                walk(true).or_else(|_| walk(false)),
                Ok(spade::PositionInTriangulation::OnFace(_)
                    | spade::PositionInTriangulation::OnEdge(_))
            )
            .then_some(i)
        })
    }

    /// Store a face's measure and queue the face if it has a candidate.
    pub(super) fn record(&mut self, idx: usize, m: Measure) {
        if idx >= self.faces.len() {
            self.faces.resize(
                idx + 1,
                FaceState {
                    generation: 0,
                    err: 0.0,
                    cand: NONE,
                    corner: 0,
                    at: [f64::NAN; 3],
                },
            );
        }
        let st = &mut self.faces[idx];
        st.generation = st.generation.wrapping_add(1);
        st.err = m.worst;
        st.cand = m.cand;
        st.corner = m.corner;
        st.at = m.at;
        if m.cand != NONE {
            self.heap.push(Entry {
                err: m.best,
                face: idx as u32,
                generation: st.generation,
            });
        }
    }

    /// The vertices (positions, by triangulation index) and the sample
    /// each one is, the triangulation dropped.
    pub(super) fn finish(self) -> (Vec<[f64; 3]>, Vec<u32>) {
        let verts = (0..self.dt.num_vertices())
            .map(|i| self.vert3(FixedVertexHandle::from_index(i)))
            .collect();
        (verts, self.vsample)
    }

    /// Re-measure one inner face and queue it.
    pub(super) fn scan_face(&mut self, face: FaceHandle) {
        let m = self.measure(face);
        self.record(face.index(), m);
    }

    /// Samples a face's area holds, about (for deciding what is worth
    /// handing to threads).
    pub(super) fn face_samples(&self, face: FaceHandle) -> f64 {
        let vs = self.dt.face(face).vertices();
        let [a, b, c] = vs.map(|v| self.dt.vertex(v.fix()).position());
        ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)).abs() / 2.0 / self.grid.cell_area()
    }

    /// Insert sample `i`; `hint` is a vertex near it (spade's point
    /// location walks from there; without one it walks from the last
    /// inserted vertex, which in greedy order is anywhere: that walk was
    /// 58 % of the build).
    pub(super) fn insert_sample(
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
    pub(super) fn insert_point(
        &mut self,
        p: [f64; 3],
        hint: Option<FixedVertexHandle>,
    ) -> Result<FixedVertexHandle, TinError> {
        let before = self.dt.num_vertices();
        let pt = Point2::new(p[0], p[1]);
        // spade finds where the point goes before it changes anything, and
        // that walk can go round in a constrained triangulation and panic
        // ("Failed to locate position": harness seed 11005163): then it is
        // inserted again, walked from spade's own start
        let hinted = hint.filter(|v| v.index() < before);
        let dt = &mut self.dt;
        let first = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match hinted {
            Some(v) => dt.insert_with_hint(pt, v),
            None => dt.insert(pt),
        }));
        let inserted = match first {
            Ok(r) => r,
            Err(_) if hinted.is_some() && self.dt.num_vertices() == before => {
                let dt = &mut self.dt;
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| dt.insert(pt))).map_err(
                    |_| {
                        TinError::Internal(format!(
                            "spade could not find where ({}, {}) goes in the triangulation",
                            p[0], p[1]
                        ))
                    },
                )?
            }
            Err(_) => {
                return Err(TinError::Internal(format!(
                    "spade could not find where ({}, {}) goes in the triangulation",
                    p[0], p[1]
                )));
            }
        };
        let h = inserted
            .map_err(|e| TinError::InvalidParameter(format!("cannot insert sample: {e:?}")))?;
        if self.dt.num_vertices() > before {
            self.vz.push(p[2]);
            self.vside.push(0);
        }
        Ok(h)
    }

    /// Re-measure the faces around a new vertex: on threads when they are
    /// large (the first insertions of a level), results recorded in order.
    pub(super) fn rescan_around(&mut self, v: FixedVertexHandle) {
        let faces: Vec<_> = self
            .dt
            .vertex(v)
            .out_edges()
            .filter_map(|e| e.face().as_inner().map(|f| f.fix()))
            .collect();
        if crate::par::threads() > 1
            && faces.iter().map(|&f| self.face_samples(f)).sum::<f64>() > PAR_SAMPLES
        {
            let ms = crate::par::map(&faces, |&f| self.measure(f));
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
    pub(super) fn refine(
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
        crate::par::map_batched(
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
        loop {
            let top = self.heap.pop();
            if let Some(t) = &top
                && self.faces[t.face as usize].generation != t.generation
            {
                continue;
            }
            let full = self.dt.num_vertices() >= max_vertices;
            if full || top.as_ref().is_none_or(|t| t.err <= tol) {
                if let Some(t) = top {
                    self.heap.push(t);
                }
                // a raster build's faces still over the tolerance: measured
                // again with vertices at the crossings no pixel mends
                // (never before, so that the samples decide wherever they
                // can)
                let last = !full
                    && !self.raster_at
                    && self.at_budget > 0
                    && self.reference.is_some_and(|r| !r.mends_at_crossings());
                if !last {
                    break;
                }
                self.raster_at = true;
                let over: Vec<FaceHandle> = self
                    .dt
                    .fixed_inner_faces()
                    .filter(|f| self.faces.get(f.index()).is_some_and(|st| st.err > tol))
                    .collect();
                for f in over {
                    self.scan_face(f);
                }
                continue;
            }
            let Some(top) = top else { break };
            let st = self.faces[top.face as usize];
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
            if self.faces[idx].generation == st.generation
                && let Some(f) = self.dt.fixed_inner_faces().find(|f| f.index() == idx)
            {
                self.scan_face(f);
            }
        }
        self.raster_at = false;
        let mut max = 0.0f64;
        for f in self.dt.fixed_inner_faces() {
            max = max.max(self.faces[f.index()].err);
        }
        Ok(max)
    }

    /// One parent's refinement in this (emptied) builder: its `corners`
    /// inserted, then each of its fixed sides' chosen vertices ([`plan_side`](crate::tin::sides::plan_side):
    /// the side's other samples reserved, chain `k`'s vertices flagged),
    /// then greedy insertion to `tol`. The worst error left, and each
    /// side's chain by builder sample (`grid.len() + k`: extra `k`).
    pub(super) fn refine_parent(
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

    /// Whether vertices `u` and `v` lie on one side of the parent (corners
    /// `c`): both on one fixed side's chain, or both on a free side
    /// (`free[k]`, side `k` from corner `k`) up to rounding.
    pub(super) fn same_side(&self, u: u32, v: u32, c: &[[f64; 3]; 3], free: [bool; 3]) -> bool {
        let side = |w: u32| self.vside.get(w as usize).copied().unwrap_or(0);
        if side(u) & side(v) != 0 {
            return true;
        }
        let (p, q) = (
            self.vert3(FixedVertexHandle::from_index(u as usize)),
            self.vert3(FixedVertexHandle::from_index(v as usize)),
        );
        (0..3).any(|k| {
            let (a, b) = (&c[k], &c[(k + 1) % 3]);
            free[k]
                && crate::geom::within_roundings(a, b, &p, crate::geom::BEND)
                && crate::geom::within_roundings(a, b, &q, crate::geom::BEND)
        })
    }

    /// The crossings of free edges over `tol` that no pixel could mend,
    /// each with the side of the parent (corners `c`, counter-clockwise;
    /// side `k` from corner `k`, not `free[k]`) its grid segment crosses:
    /// the segment's far pixel lies across that side, in the neighbour.
    pub(super) fn unmended(
        &self,
        tol: f64,
        c: &[[f64; 3]; 3],
        free: [bool; 3],
    ) -> Vec<(SideKey, SegKey)> {
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
    /// [`refine_parent_general`](super::general::refine_parent_general)): a sample within rounding of a hull
    /// edge leaves a sliver between itself and the edge (spade keeps the
    /// convex hull; the edge cannot flip), and later samples there split
    /// that sliver into more. Leaving them out makes the boundary run
    /// through those samples (convex up to rounding) instead of hiding a
    /// crack behind a wall; along a parent's side [`close_chains`](crate::tin::sides::close_chains) then
    /// meets the neighbour's vertices. Raster builds, decided on the
    /// lattice, have none.
    pub(super) fn snapshot(&self) -> Vec<[u32; 3]> {
        self.snapshot_dropping().0
    }

    /// [`Builder::snapshot`], and whether it dropped a sliver.
    pub(super) fn snapshot_dropping(&self) -> (Vec<[u32; 3]>, bool) {
        let mut dropped = false;
        let tris = self
            .dt
            .inner_faces()
            .filter(|f| {
                let v = f.vertices().map(|v| self.vert3(v.fix()));
                let sliver = crate::geom::is_sliver(&v[0], &v[1], &v[2]);
                dropped |= sliver;
                !sliver
            })
            .map(|f| {
                let v = f.vertices();
                [
                    v[0].fix().index() as u32,
                    v[1].fix().index() as u32,
                    v[2].fix().index() as u32,
                ]
            })
            .collect();
        (tris, dropped)
    }
}

/// A builder's buffers, kept from one parent to the next on a thread: a
/// parent's triangulation is small, and allocating it anew for each (two
/// threads allocating at once through the counting allocator's shared
/// counters) made the build slower on 2 threads than on 1.
#[derive(Default)]
pub(super) struct Scratch<T: Tri = Dt> {
    pub(super) dt: T,
    pub(super) vz: Vec<f64>,
    pub(super) vsample: Vec<u32>,
    pub(super) inserted: Vec<bool>,
    pub(super) reserved: Vec<bool>,
    pub(super) faces: Vec<FaceState>,
    pub(super) heap: BinaryHeap<Entry>,
    pub(super) vside: Vec<u8>,
}

impl<T: Tri> Scratch<T> {
    /// A builder on `grid` (`n` samples; `reserve`: flags for reserved
    /// samples) made of these buffers, emptied.
    pub(super) fn builder<'g, S: Samples>(
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
            raster_at: false,
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
    pub(super) fn keep<S: Samples>(&mut self, b: Builder<'_, S, T>) {
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
