//! The driver: greedy insertion (Garland and Heckbert) into one
//! triangulation that becomes every level in turn. Each triangle keeps its
//! worst error and what fixes it ([`measure`]); a queue of triangles by
//! error ([`Queue`], each triangle in it once) gives the next fix. A level
//! ends when the worst triangle is within its tolerance; its triangles are
//! copied out, each becomes the parent of what it holds at the next level,
//! and every edge is locked: it is never flipped again, and is split only
//! at a point on it (a pixel centre exactly on it, or the rounded point
//! where it crosses a grid segment, with the segment's height), so the
//! coarse edges persist as unions of finer ones and every triangle made
//! later lies in one parent. Nothing is decided twice and no level is
//! repaired after it is made. With more than one level, the levels before
//! the last start from [`aligned::cover`] and refine by bisection where a
//! triangle runs along the lattice, so their edges meet grid lines only at
//! pixel centres; on terraces (a raster resampled by nearest neighbour)
//! only down to a size ([`bisect_from`]), below which a triangle takes
//! its worst sample.

mod bisect;
mod cavity;
mod reserve;

use super::aligned;
use super::measure::{Fix, RESERVED, Source, Worst, measure};
use super::mesh::{Mesh, NONE, next, prev, proper};
use super::queue::Queue;
use crate::geom::{BEND, orient, orient_slack, strictly_between, within_roundings};
use crate::interrupt::{Interrupt, Ticker};
use crate::tin::TinError;
use crate::tin::build::common::RawLevel;

pub(super) struct Greedy<'g, S: Source + ?Sized> {
    m: Mesh,
    g: &'g S,
    /// the vertex at each sample, or `NONE`
    vid: Vec<u32>,
    worst: Vec<Worst>,
    /// the triangles over `floor`, by error
    queue: Queue,
    /// the finest tolerance: a triangle within it is never queued
    floor: f64,
    stack: Vec<u32>,
    touched: Vec<u32>,
    /// the most vertices a build may make before it is called runaway
    limit: usize,
    /// refine by bisection where a triangle is a lattice-aligned right
    /// triangle (the levels before the last)
    aligned: bool,
    /// the shortest longest side (across or along, in pixels) a triangle
    /// is bisected at ([`bisect_from`]); shorter ones take the sample
    bisect_from: f64,
    /// the hull's vertices are made only by [`Greedy::insert_kept`]
    keep_hull: bool,
    /// grid segments from a reserved sample that an edge crosses where no
    /// split makes proper triangles ([`Greedy::split_beside_kept`])
    stuck: rustc_hash::FxHashSet<(u32, u32)>,
}

/// How many pixels a row's runs of one height must hold on average
/// ([`super::measure::Heights::plateau`]) for a band to be terraces
/// (measured terrain: 1.00-1.04; a DEM resampled by nearest neighbour to
/// 1/k of its pixel: k to k + 0.3).
const PLATEAU: f64 = 3.5;

/// The shortest longest side a lattice-aligned triangle of `g` is
/// bisected at: any on measured terrain; on terraces (plateaus of `l`
/// pixels) `1.5 l`, shorter ones taking their worst sample. Right
/// triangles cannot follow the step between two plateaus, so bisecting
/// below that size lines every step with the smallest of them. The
/// finest of five levels at 2 m of the bundled DEMs resampled to 1/8 of
/// their pixel had 3.8-3.9x the triangles of one level; with this, 1.13x
/// (1/4: 2.0x, now 1.18x). At 1/2 and 1/3 bisecting all costs no more.
fn bisect_from<S: Source + ?Sized>(g: &S) -> f64 {
    match g.lattice().map(|h| h.plateau()) {
        Some(l) if l >= PLATEAU => 1.5 * l,
        _ => 0.0,
    }
}

/// How many roundings ([`orient_slack`]) off a line a point
/// may be and still be taken as on it when a segment is recovered or a
/// sample inserted: a vertex made closer than this to another would leave
/// the next split beside them a sliver.
const NEAR: f64 = 256.0;

/// Whether `c` is within [`NEAR`] roundings of the line through `a`, `b`.
fn close(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    within_roundings(a, b, c, NEAR)
}

/// How far off a segment being recovered (a fraction of its length) an
/// edge's end may be for the segment to be made through it rather than
/// split beside a thin fan.
const ROUTE: f64 = 1e-3;

fn internal(what: &str) -> TinError {
    TinError::Internal(format!("the greedy build {what}"))
}

impl<'g, S: Source + ?Sized> Greedy<'g, S> {
    /// The samples' hull, triangulated: Delaunay, or with `aligned` (a
    /// raster band only), along the lattice ([`aligned::cover`]) and
    /// refined by bisection until [`Greedy::aligned`] is cleared. Every
    /// triangle measured.
    ///
    /// With `keep_hull`, no vertex is made on the hull but by
    /// [`Greedy::insert_kept`] (and crossings on a side across no lattice
    /// line): the lattice-aligned triangles keep off it and are not
    /// bisected at it ([`super::kept`]).
    pub(super) fn new(
        g: &'g S,
        floor: f64,
        aligned: bool,
        keep_hull: bool,
    ) -> Result<Self, TinError> {
        let corners = g.hull()?;
        if let (true, Some(band)) = (aligned, g.lattice()) {
            let w = band.width;
            let lattice: Vec<[i64; 2]> = corners
                .iter()
                .map(|&i| [(i as usize % w) as i64, (i as usize / w) as i64])
                .collect();
            let m = aligned::cover(band.width, band.height, &lattice, keep_hull, &|c, r| {
                band.at(c, r)
            })?;
            let ids = m
                .pts
                .iter()
                .map(|p| (p[1] as usize * w + p[0] as usize) as u32)
                .collect();
            return Ok(Self::with(g, floor, m, ids, true, keep_hull));
        }
        let mut m = Mesh::new();
        for &id in &corners {
            m.add_point(g.point(id));
        }
        for i in 1..corners.len() as u32 - 1 {
            m.add_triangle(0, i, i + 1, 0);
        }
        m.link_all();
        Ok(Self::with(g, floor, m, corners, false, keep_hull))
    }

    /// `ids`: the sample at each of `m`'s vertices.
    fn with(g: &'g S, floor: f64, m: Mesh, ids: Vec<u32>, aligned: bool, keep_hull: bool) -> Self {
        let mut s = Greedy {
            m,
            g,
            vid: vec![NONE; g.count()],
            worst: Vec::new(),
            queue: Queue::default(),
            floor,
            stack: Vec::new(),
            touched: Vec::new(),
            limit: 4 * g.count() + 1024,
            aligned,
            bisect_from: if aligned { bisect_from(g) } else { 0.0 },
            keep_hull,
            stuck: Default::default(),
        };
        for (v, &id) in ids.iter().enumerate() {
            s.vid[id as usize] = v as u32;
        }
        if !aligned {
            s.stack.extend(0..s.m.v.len() as u32);
            s.legalize();
        }
        s.touched.clear();
        for t in 0..s.m.triangles() {
            s.rescan(t);
        }
        s
    }

    /// Flip every edge on the stack that is not locally Delaunay and may
    /// be flipped, and those it brings.
    fn legalize(&mut self) {
        while let Some(h) = self.stack.pop() {
            if self.m.wants_flip(h) && self.m.flippable(h) {
                let g = self.m.twin[h as usize];
                self.touched.push(h / 3);
                self.touched.push(g / 3);
                let e = self.m.flip(h);
                self.stack.extend_from_slice(&e);
            }
        }
    }

    fn rescan(&mut self, t: u32) {
        let n = self.m.triangles() as usize;
        if self.worst.len() < n {
            self.worst.resize(n, Worst::NONE);
        }
        let w = measure(&self.m, t, self.g, &self.vid);
        self.worst[t as usize] = w;
        let key = (w.err > self.floor && !self.is_stuck(&w.fix)).then(|| w.err.to_bits());
        self.queue.set(t, key);
    }

    /// The triangle holding point `p`, walking from `t`, and the
    /// half-edge it lies on (up to rounding), if any.
    fn locate(&self, mut t: u32, p: &[f64; 3]) -> Result<(u32, Option<u32>), TinError> {
        let limit = self.m.triangles() as usize + 16;
        for step in 0..limit {
            let c = self.m.corners(t);
            let mut on = None;
            let mut moved = false;
            for i in 0..3 {
                let k = (i + step) % 3;
                let (a, b) = (&c[k], &c[(k + 1) % 3]);
                let (o, s) = (orient(a, b, p), orient_slack(a, b, p));
                if o < -s {
                    let g = self.m.twin[3 * t as usize + k];
                    if g == NONE {
                        return Err(internal("placed a point outside the hull"));
                    }
                    t = g / 3;
                    moved = true;
                    break;
                }
                if o <= s {
                    if on.is_some() {
                        return Err(internal(&format!(
                            "placed a point on a vertex: {p:?} in {c:?}"
                        )));
                    }
                    on = Some(3 * t + k as u32);
                }
            }
            if !moved {
                return Ok((t, on));
            }
        }
        Err(internal("lost its way locating a point"))
    }

    /// Insert sample `id`, found in or near triangle `t`. A sample within
    /// [`NEAR`] roundings of a free interior edge of its triangle (pixel
    /// centres on one lattice line, their coordinates rounded) splits that
    /// edge at the sample, bending it by at most 7e-12 of the coordinates'
    /// magnitude (50 um at UTM northings), rather than make a nearly flat
    /// triangle with it. One within [`BEND`] roundings of a locked
    /// interior edge (a coarse level's) splits that edge at the sample,
    /// bending it by no more than the validator allows a child outside its
    /// parent: the triangles beside a sample that near would be too flat
    /// for any later split of the edge to be proper (harness seeds 143164,
    /// 158431). One further from a locked edge, or near the hull, is put
    /// inside: a vertex at its foot would not be on the surface where the
    /// samples' own triangulation is that flat (harness soak of
    /// 2026-12-06, seeds 120000..124428), nor the hull convex.
    fn insert_sample(&mut self, t: u32, id: u32) -> Result<(), TinError> {
        let p = self.g.point(id);
        let (t, on) = self.locate(t, &p)?;
        let on = on.or_else(|| self.beside(t, &p));
        let v = self.m.add_point(p);
        self.vid[id as usize] = v;
        match on {
            Some(h) => self.split_edge(h, v),
            None => {
                self.touched.push(t);
                let e = self.m.split3(t, v);
                self.stack.extend_from_slice(&e);
            }
        }
        self.legalize();
        Ok(())
    }

    /// The interior half-edge of triangle `t` whose line `p` (inside it) is
    /// nearest to, when within [`NEAR`] roundings of it ([`BEND`] for a
    /// locked one) and a split there at `p` would make proper triangles.
    fn beside(&self, t: u32, p: &[f64; 3]) -> Option<u32> {
        let mut best: Option<(f64, u32)> = None;
        for h in 3 * t..3 * t + 3 {
            if self.m.twin[h as usize] == NONE {
                continue;
            }
            let reach = if self.m.locked[h as usize] {
                BEND
            } else {
                NEAR
            };
            // roundings off the edge's line ([`close`]'s test)
            let (a, b) = (self.m.at(h), self.m.at(next(h)));
            let r = orient(a, b, p).abs() / orient_slack(a, b, p);
            if r <= reach && best.is_none_or(|(q, _)| r < q) {
                best = Some((r, h));
            }
        }
        let (_, h) = best?;
        (!self.thin_split(h, p, false)).then_some(h)
    }

    fn split_edge(&mut self, h: u32, v: u32) {
        let g = self.m.twin[h as usize];
        self.touched.push(h / 3);
        if g != NONE {
            self.touched.push(g / 3);
        }
        let mut out = std::mem::take(&mut self.stack);
        self.m.split_edge(h, v, &mut out);
        self.stack = out;
    }

    /// Split the edge of `h` at point `p` on it (where it crosses a grid
    /// segment, with the segment's height): the new vertex.
    ///
    /// Where a triangle beside the split would be a sliver, `p` lies on
    /// its far edge up to rounding: the split is made and that edge is
    /// split at `p` too ([`Mesh::fold`]), the sliver gone. This is the tip
    /// of a needle between two edges that cannot be flipped away (both
    /// locked), an angle so sharp that no point near its apex makes a
    /// proper triangle with both (harness seeds 211121, 320067: scattered
    /// samples along a scan line); `p` is then on both edges up to
    /// rounding, and the edges keep their lines.
    fn split_edge_at(&mut self, h: u32, p: [f64; 3]) -> Result<u32, TinError> {
        let folds = if self.thin_split(h, &p, false) {
            self.folds(h, &p).ok_or_else(|| {
                let (a, b) = (self.m.at(h), self.m.at(next(h)));
                internal(&format!(
                    "would make a sliver splitting the edge {a:?} - {b:?} at {p:?}"
                ))
            })?
        } else {
            0
        };
        let v = self.m.add_point(p);
        // the half-edges opposite the new vertex, pushed last: c -> a,
        // b -> c (and d -> b, a -> d across)
        let first = self.stack.len();
        self.split_edge(h, v);
        for (k, e) in self.stack.split_off(first).into_iter().enumerate() {
            if folds & (1 << k) == 0 {
                self.stack.push(e);
                continue;
            }
            let across = self.m.twin[e as usize];
            let Some(free) = self.m.fold(e) else {
                return Err(internal(&format!("could not fold a sliver at {p:?}")));
            };
            self.touched.push(e / 3);
            self.touched.push(across / 3);
            // the edge between them and their edges opposite p
            let (s, t) = (3 * (e / 3), 3 * (across / 3));
            self.stack.extend_from_slice(&[free, s + 1, t + 2]);
        }
        self.legalize();
        Ok(v)
    }

    /// Which of the triangles a split of `h` at `p` makes (a, p, c;
    /// p, b, c; b, p, d; p, a, d: bits 0-3) are slivers to fold
    /// ([`Mesh::fold`]), or `None` when one is not proper and cannot be.
    fn folds(&self, h: u32, p: &[f64; 3]) -> Option<u8> {
        let g = self.m.twin[h as usize];
        // each triangle's edge opposite p, as u -> w
        let mut far = vec![prev(h), next(h)];
        if g != NONE {
            far.extend_from_slice(&[prev(g), next(g)]);
        }
        let mut bits = 0u8;
        for (k, &e) in far.iter().enumerate() {
            let (u, w) = (self.m.at(e), self.m.at(next(e)));
            if proper(u, w, p) {
                continue;
            }
            let f = self.m.twin[e as usize];
            if f == NONE || !within_roundings(u, w, p, 1.0) || !strictly_between(u, w, p) {
                return None;
            }
            let x = self.m.at(prev(f));
            if !proper(p, u, x) || !proper(w, p, x) {
                return None;
            }
            bits |= 1 << k;
        }
        Some(bits)
    }

    /// Whether splitting the edge of `h` at `p` would make a triangle
    /// that is not proper (`p` within rounding of an end), or with `near`
    /// one within [`NEAR`] roundings of a line.
    fn thin_split(&self, h: u32, p: &[f64; 3], near: bool) -> bool {
        let (a, b, c) = (self.m.at(h), self.m.at(next(h)), self.m.at(prev(h)));
        let bad =
            |u: &[f64; 3], v: &[f64; 3], w: &[f64; 3]| !proper(u, v, w) || (near && close(u, v, w));
        let mut thin = bad(a, p, c) || bad(p, b, c);
        let g = self.m.twin[h as usize];
        if g != NONE {
            let d = self.m.at(prev(g));
            thin |= bad(b, p, d) || bad(p, a, d);
        }
        thin
    }

    /// The half-edge p -> x whose triangle (p, x, y) holds the direction
    /// from p to q (q left of or on p -> x, right of p -> y).
    fn wedge(&self, p: u32, q: &[f64; 3]) -> Option<u32> {
        let start = self.m.out[p as usize];
        let pp = &self.m.pts[p as usize];
        let mut h = start;
        // turn clockwise to the hull (or round), then counter-clockwise
        for _ in 0..64 {
            let g = self.m.twin[h as usize];
            if g == NONE {
                break;
            }
            h = next(g);
            if h == start {
                break;
            }
        }
        for _ in 0..64 {
            let (x, y) = (self.m.at(next(h)), self.m.at(prev(h)));
            if orient(pp, x, q) >= 0.0 && orient(pp, y, q) < 0.0 {
                return Some(h);
            }
            // p -> y, the next triangle counter-clockwise
            h = self.m.twin[prev(h) as usize];
            if h == NONE {
                return None;
            }
        }
        None
    }

    /// Make the grid segment between vertices `p` and `q` an edge and lock
    /// it (it has no crossings: no edge may cross it again). The free
    /// triangles it crosses are taken out and each side of it triangulated
    /// again (Delaunay in the pseudo-polygon, Anglada 1997); a locked edge
    /// across it is split where it crosses, a vertex on it splits it, and
    /// the parts are recovered alone. False, with nothing changed, when the
    /// new triangles would not all be proper.
    fn recover(&mut self, p: u32, q: u32, depth: u32) -> Result<bool, TinError> {
        // each level of depth splits the segment at a vertex: bounded by
        // the edges that cross it
        if depth > 256 {
            return Ok(false);
        }
        let (pp, qq) = (self.m.pts[p as usize], self.m.pts[q as usize]);
        let Some(h) = self.wedge(p, &qq) else {
            return Ok(false);
        };
        let x = self.m.v[next(h) as usize];
        if x == q {
            let g = self.m.twin[h as usize];
            self.m.link(h, g, true);
            return Ok(true);
        }
        // a vertex on the segment, or within a few roundings of it (a
        // crossing made on it before): the segment is made through it, or
        // the triangles beside it would not be proper
        let on = |c: &[f64; 3]| {
            orient(&pp, &qq, c) == 0.0 || (close(&pp, &qq, c) && strictly_between(&pp, &qq, c))
        };
        let y = self.m.v[prev(h) as usize];
        for v in [x, y] {
            if v != q && on(&self.m.pts[v as usize]) {
                return Ok(self.recover(p, v, depth + 1)? && self.recover(v, q, depth + 1)?);
            }
        }
        // the triangles the segment crosses, and the edges it crosses
        let mut cavity = vec![h / 3];
        let (mut left, mut right) = (Vec::new(), Vec::new());
        let mut e = next(h);
        loop {
            if self.m.locked[e as usize] {
                let cross = self.crossing_of(e, p, q);
                let (u3, w3) = (self.m.at(e), self.m.at(next(e)));
                let improper = self.thin_split(e, &cross, false);
                if improper && (close(u3, w3, &pp) || close(u3, w3, &qq)) {
                    // the edge passes within a few roundings of an end of
                    // the segment and a vertex where they cross would not
                    // be proper: nothing made (nor routed past that end).
                    // A proper one is made: the segment may start at a
                    // vertex just made on a locked edge that runs within
                    // a few roundings of this one (two sides of a needle
                    // near its tip, harness seed 104678)
                    return Ok(false);
                }
                let near = |v: &[f64; 3]| close(&pp, &qq, v);
                let (u, w) = (self.m.v[e as usize], self.m.v[next(e) as usize]);
                let off = |v: u32| orient(&pp, &qq, &self.m.pts[v as usize]).abs();
                let x = if off(u) <= off(w) { u } else { w };
                // made through the edge's end nearer the segment when the
                // segment passes within rounding of it (scattered samples),
                // when a split would not be proper, or when it would make a
                // triangle within a few roundings of a line (a thin fan: the
                // next split beside it would make a sliver) and that end is
                // within a thousandth of the segment's length of it
                let len2 = (qq[0] - pp[0]).powi(2) + (qq[1] - pp[1]).powi(2);
                let route = improper
                    || near(u3)
                    || near(w3)
                    || (off(x) <= ROUTE * len2 && self.thin_split(e, &cross, true));
                if route {
                    return Ok(self.recover(p, x, depth + 1)? && self.recover(x, q, depth + 1)?);
                }
                let v = self.split_edge_at(e, cross)?;
                return Ok(self.recover(p, v, depth + 1)? && self.recover(v, q, depth + 1)?);
            }
            // e runs from the right of p -> q to its left
            let (u, w) = (self.m.v[e as usize], self.m.v[next(e) as usize]);
            if right.last() != Some(&u) {
                right.push(u);
            }
            if left.last() != Some(&w) {
                left.push(w);
            }
            let g = self.m.twin[e as usize];
            if g == NONE {
                return Ok(false);
            }
            cavity.push(g / 3);
            let apex = self.m.v[prev(g) as usize];
            if apex == q {
                break;
            }
            let o = orient(&pp, &qq, &self.m.pts[apex as usize]);
            if on(&self.m.pts[apex as usize]) {
                return Ok(self.recover(p, apex, depth + 1)? && self.recover(apex, q, depth + 1)?);
            }
            // g runs w -> u (left to right) in w, u, apex: the segment
            // leaves by u -> apex when the apex is on its left, else by
            // apex -> w (both run right to left)
            e = if o > 0.0 { next(g) } else { prev(g) };
            if cavity.len() > 4096 {
                return Ok(false);
            }
        }
        let mut tris = Vec::with_capacity(cavity.len());
        let mut chain = vec![p];
        chain.extend_from_slice(&left);
        chain.push(q);
        self.fill(&chain, &mut tris);
        let mut chain = vec![q];
        chain.extend(right.iter().rev());
        chain.push(p);
        self.fill(&chain, &mut tris);
        let bad = |t: &[u32; 3]| {
            let c = t.map(|v| self.m.pts[v as usize]);
            !proper(&c[0], &c[1], &c[2])
        };
        if tris.len() != cavity.len() || tris.iter().any(bad) {
            return Ok(false);
        }
        self.replace(&cavity, &tris, (p, q));
        Ok(true)
    }

    /// Where the edge of `e` crosses the segment from vertex `p` to
    /// vertex `q` (two samples), with the segment's height.
    fn crossing_of(&self, e: u32, p: u32, q: u32) -> [f64; 3] {
        let (u, w) = (self.m.at(e), self.m.at(next(e)));
        let (pp, qq) = (&self.m.pts[p as usize], &self.m.pts[q as usize]);
        self.g.crossing_of(u, w, pp, qq)
    }

    /// Where the edge of `h` crosses the segment between samples `a` and
    /// `b`: the point its triangle's measure found.
    fn measured_crossing(&self, h: u32, a: u32, b: u32) -> Result<[f64; 3], TinError> {
        let (p, q) = (self.m.at(h), self.m.at(next(h)));
        self.g
            .crossing_point(p, q, a, b)
            .ok_or_else(|| internal("lost a crossing it measured"))
    }

    fn vertex_at(&self, id: u32) -> Option<u32> {
        let v = self.vid[id as usize];
        (v != NONE && v != RESERVED).then_some(v)
    }

    /// Whether triangle `t` is big enough to be bisected
    /// ([`Greedy::bisect_from`]).
    fn bisects(&self, t: u32) -> bool {
        if self.bisect_from == 0.0 {
            return true;
        }
        let c = self.m.corners(t);
        let d = |a: &[f64; 3], b: &[f64; 3]| (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
        d(&c[0], &c[1]).max(d(&c[1], &c[2])).max(d(&c[2], &c[0])) >= self.bisect_from
    }

    /// Apply triangle `t`'s fix.
    fn apply(&mut self, t: u32) -> Result<(), TinError> {
        if self.aligned && self.bisects(t) {
            let hull = if self.keep_hull {
                aligned::Hull::Kept
            } else {
                aligned::Hull::Free
            };
            if self.bisect(t, hull)?.is_some() {
                return Ok(());
            }
        }
        match self.worst[t as usize].fix {
            Fix::None => Err(internal(
                "found nothing to fix in a triangle over tolerance",
            )),
            Fix::Sample(id) => self.insert_sample(t, id),
            Fix::Crossing { k, a, b } => {
                let h = 3 * t + k as u32;
                if self.m.locked[h as usize] || self.m.twin[h as usize] == NONE {
                    let x = self.measured_crossing(h, a, b)?;
                    return self.split_edge_at(h, x).map(|_| ());
                }
                // a free edge: a sample of the segment it crosses, the one
                // on this triangle's side first
                let free = |id: u32| self.vid[id as usize] == NONE;
                let on_side =
                    |id: u32| orient(self.m.at(h), self.m.at(next(h)), &self.g.point(id)) > 0.0;
                let (first, second) = if on_side(a) { (a, b) } else { (b, a) };
                match (free(first), free(second)) {
                    (true, _) => self.insert_sample(t, first),
                    (false, true) => self.insert_sample(t, second),
                    (false, false) => {
                        let vp = self.vertex_at(a);
                        let vq = self.vertex_at(b);
                        let (Some(vp), Some(vq)) = (vp, vq) else {
                            if [a, b].iter().any(|&i| self.vid[i as usize] == RESERVED) {
                                return self.split_beside_kept(h, a, b);
                            }
                            return Err(internal("lost a pixel's vertex"));
                        };
                        let before = self.touched.len();
                        // made an edge, or flipped: measured again (edges
                        // already along the segment, bent by a vertex put
                        // on it within rounding, change nothing: split
                        // where it crosses)
                        self.recover(vp, vq, 0)?;
                        if self.touched.len() != before {
                            return Ok(());
                        }
                        // split where it crosses, and the segment's halves
                        // made edges, so that nothing crosses it again
                        let x = self.measured_crossing(h, a, b)?;
                        let v = self.split_edge_at(h, x)?;
                        self.recover(vp, v, 1)?;
                        self.recover(v, vq, 1)?;
                        Ok(())
                    }
                }
            }
        }
    }

    /// Refine until every triangle is within `tol`, the vertices made so
    /// far reported as `phase`'s progress ([`crate::progress::step`]).
    pub(super) fn run(
        &mut self,
        tol: f64,
        phase: &str,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<(), TinError> {
        let mut tick = Ticker::new(interrupt);
        let mut fixes = 0u32;
        // fixes since a vertex was last made: each of them makes an edge
        // of a segment, so as many as there are edges at most
        let (mut idle, mut made) = (0usize, self.m.pts.len());
        while let Some((bits, t)) = self.queue.peek() {
            if f64::from_bits(bits) <= tol {
                break;
            }
            self.queue.pop();
            let n0 = self.m.triangles();
            let fix = self.worst[t as usize];
            self.apply(t)?;
            if self.m.pts.len() == made {
                idle += 1;
                if idle > 3 * self.m.triangles() as usize + 1024 {
                    return Err(internal(&format!(
                        "made no progress: {fix:?} in {:?}",
                        self.m.corners(t)
                    )));
                }
            } else {
                (idle, made) = (0, self.m.pts.len());
            }
            let mut touched = std::mem::take(&mut self.touched);
            // t itself too: a pixel its crossing asked for may have gone
            // into a triangle beside it
            touched.push(t);
            touched.extend(n0..self.m.triangles());
            touched.sort_unstable();
            touched.dedup();
            for &u in &touched {
                self.rescan(u);
            }
            touched.clear();
            self.touched = touched;
            if self.m.pts.len() > self.limit {
                return Err(internal(
                    "did not converge (more vertices than four a pixel)",
                ));
            }
            tick.tick()?;
            fixes = fixes.wrapping_add(1);
            if fixes.is_multiple_of(1024) {
                crate::progress::step(phase, "vertices", self.m.pts.len() as u64, 0);
            }
        }
        Ok(())
    }

    /// The level just made, its triangles then made the parents of the
    /// next and its edges locked. After the `last` level the measures and
    /// the queue are let go before its triangles are copied out (the
    /// build's peak).
    pub(super) fn finish_level(&mut self, tol: f64, first: bool, last: bool) -> RawLevel {
        let max_error = self.worst.iter().map(|w| w.err).fold(0.0, f64::max);
        if last {
            self.worst = Vec::new();
            self.queue = Queue::default();
            self.vid = Vec::new();
            self.m.twin = Vec::new();
            self.m.locked = Vec::new();
            self.m.out = Vec::new();
        }
        let n = self.m.triangles();
        let tris = (0..n)
            .map(|t| {
                let h = 3 * t as usize;
                [self.m.v[h], self.m.v[h + 1], self.m.v[h + 2]]
            })
            .collect();
        let parents = if first {
            Vec::new()
        } else if last {
            std::mem::take(&mut self.m.parent)
        } else {
            self.m.parent.clone()
        };
        for (t, p) in self.m.parent.iter_mut().enumerate() {
            *p = t as u32;
        }
        self.m.locked.iter_mut().for_each(|l| *l = true);
        RawLevel {
            tolerance: tol,
            max_error,
            num_vertices: self.m.pts.len() as u32,
            tris,
            parents,
            void: Vec::new(),
        }
    }

    /// The last level refines by free insertion only.
    pub(super) fn finest(&mut self) {
        self.aligned = false;
    }

    pub(super) fn into_points(self) -> Vec<[f64; 3]> {
        self.m.pts
    }
}

/// Every level of the greedy build of a source, in its frame (a raster
/// band's lattice coordinates): its vertices and levels.
pub(super) fn levels<S: Source + ?Sized>(
    g: &S,
    tolerances: &[f64],
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<RawLevel>), TinError> {
    let floor = tolerances.last().copied().unwrap_or(0.0);
    // coarse levels along the lattice, the last by free insertion into
    // them
    let mut s = Greedy::new(g, floor, tolerances.len() > 1, false)?;
    let mut raw = Vec::with_capacity(tolerances.len());
    for (l, &tol) in tolerances.iter().enumerate() {
        if l + 1 == tolerances.len() {
            s.finest();
        }
        let phase = format!("building level {} of {}", l + 1, tolerances.len());
        s.run(tol, &phase, interrupt)?;
        raw.push(s.finish_level(tol, l == 0, l + 1 == tolerances.len()));
    }
    Ok((s.into_points(), raw))
}
