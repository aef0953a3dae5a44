//! The plain walk ([`walk_parts`], [`Walker`]): a polyline followed
//! through the triangles of one level, cut wherever it crosses a triangle
//! edge, each point reported to a [`Sink`] (the rules are the module's,
//! [`super`]).

use crate::geom::{P2, co, dist, vco};
use crate::interrupt::Interrupt;
use crate::tin::locate;
use crate::tin::mesh::Indexed;
use crate::tin::{HullEdge, NONE, Tin, TinError};
use robust::{Coord, orient2d};
use std::borrow::Cow;

/// A polyline as the walker reads it: vertices and the planar distance of
/// each from the first. Reads may fail (a stored line tree is checked as it
/// is read).
pub trait Polyline {
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn pt(&self, i: usize) -> Result<P2, TinError>;
    /// Planar length of the line from vertex 0 to vertex `i`.
    fn cum(&self, i: usize) -> Result<f64, TinError>;
}

/// One part (a LINESTRING) held in memory.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub pts: Vec<P2>,
    pub cum: Vec<f64>,
}

impl Part {
    pub fn new(pts: Vec<P2>) -> Part {
        let mut cum = Vec::with_capacity(pts.len());
        let mut d = 0.0;
        for (i, p) in pts.iter().enumerate() {
            if i > 0 {
                d += dist(pts[i - 1], *p);
            }
            cum.push(d);
        }
        Part { pts, cum }
    }

    /// Planar length.
    pub fn length(&self) -> f64 {
        self.cum.last().copied().unwrap_or(0.0)
    }
}

impl Polyline for Part {
    fn len(&self) -> usize {
        self.pts.len()
    }
    fn pt(&self, i: usize) -> Result<P2, TinError> {
        self.pts
            .get(i)
            .copied()
            .ok_or_else(|| TinError::InvalidParameter(format!("no vertex {i}")))
    }
    fn cum(&self, i: usize) -> Result<f64, TinError> {
        self.cum
            .get(i)
            .copied()
            .ok_or_else(|| TinError::InvalidParameter(format!("no vertex {i}")))
    }
}

/// Receives the cut line from the walker.
pub trait Sink {
    /// Whether the sink needs the points (false: only the triangles, which
    /// lets the line tree skip the vertices of stretches inside a triangle).
    fn wants_points(&self) -> bool {
        true
    }
    /// Whether the sink is told of void triangles too (false: the walk
    /// reports a void triangle as leaving the domain).
    fn wants_void(&self) -> bool {
        false
    }
    /// Whether the sink reads `along` (false: the walk passes 0 and spares
    /// a square root per crossing; the area sweep's rings).
    fn wants_along(&self) -> bool {
        true
    }
    /// A point of the cut line, in the piece of triangle `tri`; `along` is
    /// the planar distance from the start of the part.
    fn point(&mut self, tri: u32, p: P2, along: f64);
    /// The line leaves the domain or a part ends: the next point starts a
    /// new run of pieces.
    fn brk(&mut self);
}

/// Where a closed triangle holds a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Spot {
    Inside,
    /// On the edge opposite corner `j`, not at a corner.
    Edge(usize),
    /// At corner `j`.
    Corner(usize),
}

/// How the line leaves a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Exit {
    /// Through the inside of the edge opposite corner `j`.
    Edge(usize),
    /// Through corner `j`.
    Corner(usize),
}

/// Follows lines through the triangles of one level of a mesh: a decoded
/// [`Tin`] (the default) or a stored value read in slices
/// ([`crate::tin::sliced`]), whose read errors end the walk.
pub struct Walker<'a, S: Sink, M: Indexed = Tin>
where
    TinError: From<M::Err>,
{
    tin: &'a M,
    level: usize,
    pub sink: &'a mut S,
    /// Triangle whose closed area holds the current point (None: outside).
    cur: Option<u32>,
    /// Whether the current point has been reported (a piece is open).
    open: bool,
    /// Hull edges, found on first need (kept by a decoded tin).
    hull: Option<Cow<'a, [HullEdge]>>,
    interrupt: &'a mut Interrupt<'a>,
    ticks: u32,
}

impl<'a, S: Sink, M: Indexed> Walker<'a, S, M>
where
    TinError: From<M::Err>,
{
    pub fn new(
        tin: &'a M,
        level: usize,
        sink: &'a mut S,
        interrupt: &'a mut Interrupt<'a>,
    ) -> Self {
        Walker {
            tin,
            level,
            sink,
            cur: None,
            open: false,
            hull: None,
            interrupt,
            ticks: 0,
        }
    }

    /// Call the interrupt check now.
    pub(crate) fn interrupt_now(&mut self) -> Result<(), TinError> {
        (self.interrupt)()
    }

    fn tick(&mut self) -> Result<(), TinError> {
        self.ticks = self.ticks.wrapping_add(1);
        if self.ticks.is_multiple_of(4096) {
            (self.interrupt)()?;
        }
        Ok(())
    }

    #[inline]
    fn corners(&self, t: u32) -> Result<[Coord<f64>; 3], TinError> {
        let cs = self.tin.corners(self.level, t)?;
        Ok([vco(&cs[0]), vco(&cs[1]), vco(&cs[2])])
    }

    #[inline]
    fn nbr(&self, t: u32, j: usize) -> Result<u32, TinError> {
        Ok(self.tin.nbrs(self.level, t)?[j])
    }

    /// Corner `j` of triangle `t`: its vertex id and position.
    #[inline]
    fn corner(&self, t: u32, j: usize) -> Result<(u32, [f64; 3]), TinError> {
        let vid = self.tin.tri(self.level, t)?[j];
        Ok((vid, self.tin.vert(vid)?))
    }

    #[inline]
    fn emit(&mut self, t: u32, p: P2, along: f64) {
        // a void triangle is off the domain: the line leaves it there
        if !self.sink.wants_void() && self.tin.is_void(self.level, t) {
            if self.open {
                self.sink.brk();
                self.open = false;
            }
            return;
        }
        self.sink.point(t, p, along);
        self.open = true;
    }

    /// Start a part at its first vertex.
    pub(crate) fn start_part(&mut self, p: P2) -> Result<(), TinError> {
        self.cur = locate::locate_hull_in(self.tin, self.level, p[0], p[1])?;
        self.open = false;
        Ok(())
    }

    /// End a part: a part that never moved but lies in the domain is
    /// reported as a single point in its triangle.
    pub(crate) fn end_part(&mut self, p0: P2, moved: bool) {
        if !moved
            && !self.open
            && let Some(t) = self.cur
        {
            self.emit(t, p0, 0.0);
        }
        self.sink.brk();
        self.cur = None;
        self.open = false;
    }

    /// Triangle holding the current point, when it is inside (for the line
    /// tree's containment tests).
    pub fn current(&self) -> Option<u32> {
        self.cur
    }

    /// Move to p without reporting anything (the widened-line merge skipping
    /// a stretch whose triangles are all known): the current triangle
    /// becomes one holding p, found by a walk from the current one.
    pub(crate) fn jump_to(&mut self, p: P2) -> Result<(), TinError> {
        let start = match self.cur {
            Some(t) => t,
            None => locate::start_in(self.tin, self.level, p[0], p[1])?,
        };
        self.cur = match locate::walk_in(self.tin, self.level, start, p[0], p[1])? {
            locate::Walk::Inside(t) => Some(t),
            locate::Walk::Outside(_) => None,
        };
        self.open = false;
        Ok(())
    }

    /// Report original vertices known to lie strictly inside the current
    /// triangle (the line tree's skip): `first` is the current point.
    pub(crate) fn run_inside<L: Polyline + ?Sized>(
        &mut self,
        line: &L,
        first: usize,
        last: usize,
    ) -> Result<(), TinError> {
        let Some(t) = self.cur else {
            return Err(TinError::corrupt(
                "line walk: run inside with no current triangle",
            ));
        };
        if !self.open {
            self.emit(t, line.pt(first)?, line.cum(first)?);
        }
        if self.sink.wants_points() {
            for k in first + 1..=last {
                self.emit(t, line.pt(k)?, line.cum(k)?);
            }
        }
        Ok(())
    }

    /// Follow the segment from vertex `k` to vertex `k + 1` of `line`.
    pub fn segment<L: Polyline + ?Sized>(&mut self, line: &L, k: usize) -> Result<(), TinError> {
        let (p, q) = (line.pt(k)?, line.pt(k + 1)?);
        let along = line.cum(k)?;
        self.walk_segment(p, q, along)
    }

    /// Follow the segment p -> q (`along` = distance of p from the start).
    pub(crate) fn walk_segment(&mut self, p: P2, q: P2, along: f64) -> Result<(), TinError> {
        if p == q {
            return Ok(());
        }
        self.tick()?;
        let mut t = match self.cur {
            Some(t) => match self.start_in(t, p, q)? {
                Some(u) => {
                    if !self.open || u != t {
                        self.emit(u, p, along);
                    }
                    u
                }
                None => {
                    // leaves the domain right at p
                    self.leave();
                    return Ok(());
                }
            },
            None => match self.enter(p, q)? {
                Some((u, x)) => {
                    self.emit(u, x, self.along(along, p, x));
                    u
                }
                None => return Ok(()),
            },
        };
        let (cp, cq) = (co(p), co(q));
        // steps left before the walk is declared broken
        let mut budget = 2 * self.tin.num_triangles(self.level) + 64;
        loop {
            if budget == 0 {
                return Err(TinError::corrupt("line walk: the walk did not end"));
            }
            budget -= 1;
            let tc = self.corners(t)?;
            if (0..3).all(|j| orient2d(tc[(j + 1) % 3], tc[(j + 2) % 3], cq) >= 0.0) {
                self.emit(t, q, self.along(along, p, q));
                self.cur = Some(t);
                return Ok(());
            }
            match exit(&tc, cp, cq)? {
                Exit::Edge(j) => {
                    let (a, b) = (tc[(j + 1) % 3], tc[(j + 2) % 3]);
                    let oa = orient2d(cp, cq, a);
                    let ob = orient2d(cp, cq, b);
                    let r = (oa / (oa - ob)).clamp(0.0, 1.0);
                    let x = [a.x + r * (b.x - a.x), a.y + r * (b.y - a.y)];
                    let ax = self.along(along, p, x);
                    self.emit(t, x, ax);
                    let n = self.nbr(t, j)?;
                    if n == NONE {
                        self.leave();
                        return Ok(());
                    }
                    self.emit(n, x, ax);
                    t = n;
                }
                Exit::Corner(j) => {
                    let (vid, v) = self.corner(t, j)?;
                    let x = [v[0], v[1]];
                    let ax = self.along(along, p, x);
                    self.emit(t, x, ax);
                    match self.fan(t, vid, cq)? {
                        Some(n) => {
                            if n != t {
                                self.emit(n, x, ax);
                            }
                            t = n;
                        }
                        None => {
                            self.leave();
                            return Ok(());
                        }
                    }
                }
            }
        }
    }

    /// The distance along the part at `x`, for a segment from `p` (at
    /// `along`), when the sink reads it.
    #[inline]
    fn along(&self, along: f64, p: P2, x: P2) -> f64 {
        if self.sink.wants_along() {
            along + dist(p, x)
        } else {
            0.0
        }
    }

    fn leave(&mut self) {
        self.sink.brk();
        self.cur = None;
        self.open = false;
    }

    /// The triangle holding the first stretch of p -> q, given a closed
    /// triangle `t` holding p (None: the segment leaves the domain at p).
    fn start_in(&mut self, t: u32, p: P2, q: P2) -> Result<Option<u32>, TinError> {
        let tc = self.corners(t)?;
        let (cp, cq) = (co(p), co(q));
        match spot(&tc, cp) {
            None => Err(TinError::corrupt(
                "line walk: current point is not in its triangle",
            )),
            Some(Spot::Inside) => Ok(Some(t)),
            Some(Spot::Edge(j)) => {
                let (a, b) = (tc[(j + 1) % 3], tc[(j + 2) % 3]);
                let n = self.nbr(t, j)?;
                let o = orient2d(a, b, cq);
                Ok(if o > 0.0 {
                    Some(t)
                } else if o < 0.0 {
                    (n != NONE).then_some(n)
                } else if n == NONE {
                    Some(t)
                } else {
                    Some(t.min(n))
                })
            }
            Some(Spot::Corner(j)) => {
                let vid = self.tin.tri(self.level, t)?[j];
                self.fan(t, vid, cq)
            }
        }
    }

    /// Around vertex `vid` (a corner of `t0`), the triangle whose closed
    /// wedge holds the direction towards q (smaller id of two when the
    /// direction runs along an edge); None when the direction leaves the
    /// domain.
    fn fan(&self, t0: u32, vid: u32, q: Coord<f64>) -> Result<Option<u32>, TinError> {
        let (m, l) = (self.tin, self.level);
        let v = vco(&m.vert(vid)?);
        let limit = m.num_triangles(l) + 1;
        // first counter-clockwise from t0, then (if the fan is open, on the
        // hull) clockwise
        for ccw in [true, false] {
            let mut u = t0;
            for _ in 0..limit {
                let tri = m.tri(l, u)?;
                let nb = m.nbrs(l, u)?;
                let i = tri
                    .iter()
                    .position(|&x| x == vid)
                    .ok_or_else(|| TinError::corrupt("line walk: vertex fan is inconsistent"))?;
                let b = vco(&m.vert(tri[(i + 1) % 3])?);
                let cc = vco(&m.vert(tri[(i + 2) % 3])?);
                let ob = orient2d(v, b, q);
                let oc = orient2d(v, cc, q);
                if ob >= 0.0 && oc <= 0.0 {
                    let other = if ob == 0.0 {
                        nb[(i + 2) % 3]
                    } else if oc == 0.0 {
                        nb[(i + 1) % 3]
                    } else {
                        NONE
                    };
                    return Ok(Some(if other == NONE { u } else { u.min(other) }));
                }
                let next = if ccw {
                    nb[(i + 1) % 3]
                } else {
                    nb[(i + 2) % 3]
                };
                if next == NONE {
                    break;
                }
                if next == t0 {
                    if ccw {
                        // a closed fan was searched whole
                        return Ok(None);
                    }
                    break;
                }
                u = next;
            }
        }
        Ok(None)
    }

    /// For p outside the domain: where p -> q enters it (triangle holding
    /// the first stretch inside, and the entry point), or None if it
    /// does not (touching the hull at a single point does not count).
    fn enter(&mut self, p: P2, q: P2) -> Result<Option<(u32, P2)>, TinError> {
        let b = self.tin.bbox();
        if p[0].max(q[0]) < b.min_x
            || p[0].min(q[0]) > b.max_x
            || p[1].max(q[1]) < b.min_y
            || p[1].min(q[1]) > b.max_y
        {
            return Ok(None);
        }
        let (cp, cq) = (co(p), co(q));
        // a segment that misses the terrain's box (exactly: the box's
        // corners all strictly on one side of its line) meets no hull edge
        let corners = [
            [b.min_x, b.min_y],
            [b.max_x, b.min_y],
            [b.max_x, b.max_y],
            [b.min_x, b.max_y],
        ]
        .map(|c| orient2d(co(p), co(q), co(c)));
        if corners.iter().all(|&o| o > 0.0) || corners.iter().all(|&o| o < 0.0) {
            return Ok(None);
        }
        if self.hull.is_none() {
            self.hull = Some(self.tin.hull_edges(self.level)?);
        }
        let hull = self.hull.take().unwrap_or_default();
        let r = self.enter_through(&hull, q, cp, cq);
        self.hull = Some(hull);
        r
    }

    /// [`Self::enter`] over the hull edges.
    fn enter_through(
        &mut self,
        hull: &[HullEdge],
        q: P2,
        cp: Coord<f64>,
        cq: Coord<f64>,
    ) -> Result<Option<(u32, P2)>, TinError> {
        let sb = [
            cp.x.min(cq.x),
            cp.y.min(cq.y),
            cp.x.max(cq.x),
            cp.y.max(cq.y),
        ];
        for e in hull {
            // an edge whose closed box misses the segment's cannot meet it
            if e.bbox[2] < sb[0] || e.bbox[0] > sb[2] || e.bbox[3] < sb[1] || e.bbox[1] > sb[3] {
                continue;
            }
            let (t, j, a, bb) = (e.t, e.j, co(e.a), co(e.b));
            // p strictly outside this edge's half-plane, q on or inside it
            if !(orient2d(a, bb, cp) < 0.0 && orient2d(a, bb, cq) >= 0.0) {
                continue;
            }
            let oa = orient2d(cp, cq, a);
            let ob = orient2d(cp, cq, bb);
            if oa > 0.0 && ob < 0.0 {
                // through the inside of the edge
                if orient2d(a, bb, cq) == 0.0 {
                    // reaches the hull only at q: nothing inside yet; q is
                    // the current point, in t
                    self.cur = Some(t);
                    self.open = false;
                    return Ok(None);
                }
                let r = (oa / (oa - ob)).clamp(0.0, 1.0);
                let x = [a.x + r * (bb.x - a.x), a.y + r * (bb.y - a.y)];
                return Ok(Some((t, x)));
            }
            for (o, k) in [(oa, (j + 1) % 3), (ob, (j + 2) % 3)] {
                if o == 0.0 {
                    // through a hull vertex: it lies on the segment (p and q
                    // are on either side of the edge's line)
                    let (vid, vv) = self.corner(t, k)?;
                    let x = [vv[0], vv[1]];
                    if x == q {
                        self.cur = Some(t);
                        self.open = false;
                        return Ok(None);
                    }
                    if let Some(u) = self.fan(t, vid, cq)? {
                        return Ok(Some((u, x)));
                    }
                }
            }
        }
        Ok(None)
    }
}

/// Where the closed triangle holds p (None: outside it).
fn spot(tc: &[Coord<f64>; 3], p: Coord<f64>) -> Option<Spot> {
    let o = [0, 1, 2].map(|j| orient2d(tc[(j + 1) % 3], tc[(j + 2) % 3], p));
    if o.iter().any(|&x| x < 0.0) {
        return None;
    }
    let zeros: Vec<usize> = (0..3).filter(|&j| o[j] == 0.0).collect();
    Some(match zeros.as_slice() {
        [] => Spot::Inside,
        [j] => Spot::Edge(*j),
        // on the edges opposite corners j and k: at the third corner
        [j, k] => Spot::Corner(3 - j - k),
        _ => return None,
    })
}

/// How the line p -> q leaves triangle `tc`, which holds a stretch of it
/// and not q.
fn exit(tc: &[Coord<f64>; 3], p: Coord<f64>, q: Coord<f64>) -> Result<Exit, TinError> {
    let o = [0, 1, 2].map(|k| orient2d(p, q, tc[k]));
    // corner a on the right of the line, b on its left: the line leaves
    // through the inside of the counter-clockwise edge a -> b
    for j in 0..3 {
        if o[(j + 1) % 3] < 0.0 && o[(j + 2) % 3] > 0.0 {
            return Ok(Exit::Edge(j));
        }
    }
    let zeros: Vec<usize> = (0..3).filter(|&k| o[k] == 0.0).collect();
    match zeros.as_slice() {
        [k] => Ok(Exit::Corner(*k)),
        [j, k] => {
            // along an edge: leave through the corner further on
            let (dx, dy) = (q.x - p.x, q.y - p.y);
            let key = |k: usize| {
                if dx.abs() >= dy.abs() {
                    tc[k].x * dx.signum()
                } else {
                    tc[k].y * dy.signum()
                }
            };
            Ok(Exit::Corner(if key(*j) >= key(*k) { *j } else { *k }))
        }
        _ => Err(TinError::corrupt(
            "line walk: the line does not cross the triangle it is in",
        )),
    }
}

/// Walk every segment of every part (Scarlatos's plain walk: O(N + M)).
pub fn walk_parts<S: Sink, L: Polyline, M: Indexed>(
    tin: &M,
    level: usize,
    parts: &[L],
    sink: &mut S,
    on_part: &mut dyn FnMut(&mut S, usize),
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    // one walker for all parts: the hull (for parts entering from outside
    // the domain) is found once
    let mut w = Walker::new(tin, level, sink, interrupt);
    for (i, part) in parts.iter().enumerate() {
        on_part(&mut *w.sink, i);
        if part.is_empty() {
            continue;
        }
        let p0 = part.pt(0)?;
        w.start_part(p0)?;
        let mut moved = false;
        for k in 0..part.len() - 1 {
            moved |= part.pt(k)? != part.pt(k + 1)?;
            w.segment(part, k)?;
        }
        w.end_part(p0, moved);
    }
    Ok(())
}
