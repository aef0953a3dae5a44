//! Widened lines (Scarlatos §6.4: "if line width is a consideration, add the width
//! to the error"): every triangle within `width / 2` of a line, each once,
//! ordered by where the line first comes within that distance of it.
//!
//! Per segment, the triangles the segment itself passes through (from the
//! exact walk) seed a breadth-first search over neighbours that keeps the
//! triangles within the distance (the triangles meeting a convex region
//! are connected through edges); a segment outside the domain is seeded
//! from the hull triangles. Distances are floating point (a metric
//! tolerance, not a topological decision); a triangle touched exactly at
//! the distance counts.

use super::{Polyline, Sink, Walker};
use crate::geom::P2;
use crate::geom::{co, point_segment_distance};
use crate::interrupt::{Interrupt, Ticker};
use crate::tin::mesh::{Mesh, infallible};
use crate::tin::{NONE, Tin, TinError};
use robust::orient2d;
use std::collections::HashMap;

/// Exact: do the closed segments ab and cd meet?
fn seg_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    crate::geom::segments_intersect(co(a), co(b), co(c), co(d))
}

/// Distance in the plane between the closed triangle `t` (counter-clockwise)
/// and the segment pq (0 when they meet).
pub(crate) fn triangle_segment_distance(t: &[P2; 3], p: P2, q: P2) -> f64 {
    let inside = |x: P2| (0..3).all(|j| orient2d(co(t[j]), co(t[(j + 1) % 3]), co(x)) >= 0.0);
    if inside(p) || inside(q) || (0..3).any(|j| seg_meet(t[j], t[(j + 1) % 3], p, q)) {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for j in 0..3 {
        let (a, b) = (t[j], t[(j + 1) % 3]);
        d = d
            .min(point_segment_distance(p, a, b))
            .min(point_segment_distance(q, a, b))
            .min(point_segment_distance(a, p, q));
    }
    d
}

/// Smallest s in [0, 1] with the point p + s (q - p) within r of the
/// triangle (the distance is convex along the segment): ternary search for
/// the nearest point, then bisection before it.
fn first_approach(t: &[P2; 3], p: P2, q: P2, r: f64) -> f64 {
    let at = |s: f64| {
        let x = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
        triangle_segment_distance(t, x, x)
    };
    if at(0.0) <= r {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if at(m1) <= at(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let sm = (lo + hi) / 2.0;
    if at(sm) > r {
        return sm;
    }
    let (mut lo, mut hi) = (0.0, sm);
    for _ in 0..60 {
        let m = (lo + hi) / 2.0;
        if at(m) <= r {
            hi = m;
        } else {
            lo = m;
        }
    }
    hi
}

/// Records the triangles the exact walk visits for the current segment.
#[derive(Default)]
pub struct Visited {
    pub tris: Vec<u32>,
}

impl Sink for Visited {
    fn wants_points(&self) -> bool {
        false
    }
    /// The triangles walked are the seeds of the search near the line:
    /// void ones too (the search goes through them; [`Near::ordered`]
    /// leaves them out).
    fn wants_void(&self) -> bool {
        true
    }
    fn point(&mut self, tri: u32, _p: P2, _along: f64) {
        if self.tris.last() != Some(&tri) {
            self.tris.push(tri);
        }
    }
    fn brk(&mut self) {}
}

/// The triangles near a line, with the key of their first approach.
pub struct Near<'a> {
    tin: &'a Tin,
    level: usize,
    r: f64,
    /// triangle -> (global index of the segment's first vertex, parameter)
    pub found: HashMap<u32, (u64, f64)>,
    hull: Option<Vec<u32>>,
    queue: Vec<u32>,
    /// Triangles looked at for the current segment (few: a linear scan).
    seen: Vec<u32>,
}

impl<'a> Near<'a> {
    pub fn new(tin: &'a Tin, level: usize, half_width: f64) -> Self {
        Near {
            tin,
            level,
            r: half_width,
            found: HashMap::new(),
            hull: None,
            queue: Vec::new(),
            seen: Vec::new(),
        }
    }

    fn tri(&self, t: u32) -> [P2; 3] {
        let c = self.tin.corners(self.level, t);
        [[c[0][0], c[0][1]], [c[1][0], c[1][1]], [c[2][0], c[2][1]]]
    }

    /// Add every triangle within r of segment pq (number `seg`), searching
    /// from `seeds` (or from the hull when there are none).
    pub fn segment(
        &mut self,
        seg: u64,
        p: P2,
        q: P2,
        seeds: &[u32],
        interrupt: &mut Interrupt<'_>,
    ) -> Result<(), TinError> {
        let lv = &self.tin.levels[self.level];
        self.queue.clear();
        self.seen.clear();
        if seeds.is_empty() {
            // near the domain only if within r of its box
            let b = &self.tin.bbox;
            let r = self.r;
            if p[0].max(q[0]) < b.min_x - r
                || p[0].min(q[0]) > b.max_x + r
                || p[1].max(q[1]) < b.min_y - r
                || p[1].min(q[1]) > b.max_y + r
            {
                return Ok(());
            }
            if self.hull.is_none() {
                let mut h: Vec<u32> = infallible(self.tin.hull_edges(self.level))
                    .iter()
                    .map(|e| e.t)
                    .collect();
                h.dedup();
                self.hull = Some(h);
            }
            for &t in self.hull.as_deref().unwrap_or(&[]) {
                if triangle_segment_distance(&self.tri(t), p, q) <= r {
                    self.seen.push(t);
                    self.queue.push(t);
                }
            }
        } else {
            for &t in seeds {
                if !self.seen.contains(&t) {
                    self.seen.push(t);
                    self.queue.push(t);
                }
            }
        }
        let mut tk = Ticker::new(interrupt);
        let mut head = 0;
        while head < self.queue.len() {
            let t = self.queue[head];
            head += 1;
            tk.tick()?;
            if !self.found.contains_key(&t) {
                let s = first_approach(&self.tri(t), p, q, self.r);
                self.found.insert(t, (seg, s));
            }
            for &n in &lv.nbrs[t as usize] {
                if n != NONE && !self.seen.contains(&n) {
                    self.seen.push(n);
                    if triangle_segment_distance(&self.tri(n), p, q) <= self.r {
                        self.queue.push(n);
                    }
                }
            }
        }
        Ok(())
    }

    /// Record triangle `t`, holding the line's current point at vertex
    /// `key`, unless already found.
    pub fn touch(&mut self, t: u32, key: u64) {
        self.found.entry(t).or_insert((key, 0.0));
    }

    /// Whether every triangle within `r` of segment pq, searched from `t`
    /// (which must meet the segment), is already found; false also when
    /// more than `budget` triangles would have to be looked at.
    pub(crate) fn all_found_near(&mut self, t: u32, p: P2, q: P2, r: f64, budget: usize) -> bool {
        let lv = &self.tin.levels[self.level];
        self.queue.clear();
        self.seen.clear();
        self.seen.push(t);
        self.queue.push(t);
        let mut head = 0;
        while head < self.queue.len() {
            let u = self.queue[head];
            head += 1;
            if !self.found.contains_key(&u) || self.seen.len() > budget {
                return false;
            }
            for &n in &lv.nbrs[u as usize] {
                if n != NONE && !self.seen.contains(&n) {
                    self.seen.push(n);
                    if triangle_segment_distance(&self.tri(n), p, q) <= r {
                        self.queue.push(n);
                    }
                }
            }
        }
        true
    }

    /// A part that never moves, at p0 in triangle `start` (if inside):
    /// the triangles within r of the point.
    pub(crate) fn still_part(
        &mut self,
        key: u64,
        p0: P2,
        start: Option<u32>,
        interrupt: &mut Interrupt<'_>,
    ) -> Result<(), TinError> {
        let seeds: Vec<u32> = start.into_iter().collect();
        self.segment(key, p0, p0, &seeds, interrupt)
    }

    /// Triangles in order of first approach.
    pub fn ordered(&self) -> Vec<u32> {
        let lv = &self.tin.levels[self.level];
        let mut v: Vec<(u64, f64, u32)> = self
            .found
            .iter()
            .filter(|(t, _)| !lv.is_void(**t))
            .map(|(&t, &(s, a))| (s, a, t))
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
        v.into_iter().map(|x| x.2).collect()
    }
}

/// Walk segment `k` of `part` and add the triangles within r of it, keyed
/// by `key` (a zero-length segment adds nothing).
pub(crate) fn walk_near<L: Polyline + ?Sized>(
    near: &mut Near,
    w: &mut Walker<'_, Visited>,
    part: &L,
    k: usize,
    key: u64,
) -> Result<(), TinError> {
    let (p, q) = (part.pt(k)?, part.pt(k + 1)?);
    if p == q {
        return Ok(());
    }
    w.sink.tris.clear();
    w.segment(part, k)?;
    let seeds = std::mem::take(&mut w.sink.tris);
    near.segment(key, p, q, &seeds, &mut || w.interrupt_now())
}

/// Every triangle of `level` within `half_width` of the line, each once, in
/// order of first approach (plain walk over every segment).
pub fn near_line<L: Polyline>(
    tin: &Tin,
    level: usize,
    parts: &[L],
    half_width: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    let mut near = Near::new(tin, level, half_width);
    // a segment's key is the global index of its first vertex
    let mut base: u64 = 0;
    for part in parts {
        if part.is_empty() {
            continue;
        }
        let mut vis = Visited::default();
        let mut w = Walker::new(tin, level, &mut vis, interrupt);
        let p0 = part.pt(0)?;
        w.start_part(p0)?;
        let start = w.current();
        let mut moved = false;
        for k in 0..part.len() - 1 {
            moved |= part.pt(k)? != part.pt(k + 1)?;
            walk_near(&mut near, &mut w, part, k, base + k as u64)?;
        }
        if !moved {
            near.still_part(base, p0, start, &mut || w.interrupt_now())?;
        }
        base += part.len() as u64;
    }
    Ok(near.ordered())
}
