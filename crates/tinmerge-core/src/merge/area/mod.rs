//! Area merge (Scarlatos §6.5): the triangles of a level on and inside a polygon,
//! found by the hierarchical polygonal sweep.
//!
//! 1. The boundary: the rings are walked once, at the target level, with
//!    the line merge's walker ([`crate::merge::line::Walker`]). A walked
//!    triangle is a *boundary* triangle when a ring segment meets its open
//!    inside (exact separating-axis test, [`segment_meets_open_triangle`]):
//!    then the polygon covers part of it, not all. The parent of a boundary
//!    triangle is a boundary triangle, so the coarser levels' boundary comes
//!    from parent links; a segment that only runs along the edges of the
//!    fine triangles it touches is tested again against their ancestors
//!    (it may cross a coarse triangle's inside). Every other triangle lies
//!    wholly inside or wholly outside.
//! 2. The sweep at the coarsest level: from the boundary inward, over
//!    triangle adjacency. A triangle that no ring touches has the status of
//!    its neighbour; next to the boundary the status is decided by an exact
//!    point-in-polygon test of a corner ([`Area::locate`]).
//! 3. Down the levels: a triangle wholly inside at a coarse level has all
//!    its descendants inside, so none is visited; one wholly outside has
//!    none in the polygon. Only the children of boundary triangles are
//!    examined at the next level: each is a boundary triangle there, or
//!    wholly inside (reported at this level: the coarsest whose triangle is
//!    inside), or outside.
//!
//! The work is the boundary at each level plus the inside of the coarsest
//! level, instead of every triangle of the target level ([`Method::Scan`])
//! or every triangle inside the polygon at the target level
//! ([`Method::Flat`], the plain sweep without the hierarchy).
//!
//! Coverage (the fraction of a boundary triangle inside the polygon) comes
//! from the boundary pieces in the triangle ([`crate::merge::area::clip`]).
//!
//! Invariants (tests/area.rs on contour bands with holes, multipolygons,
//! random star polygons and grid-aligned degenerate cases, at every level):
//! inside and boundary rows at a level are exactly the triangles whose inside
//! meets the polygon's inside (oracle: brute force with an independent
//! clipper, and PostGIS `ST_Within`/`ST_Intersection`); compact rows expanded
//! through parent links give the full list; the sum of coverage times
//! triangle area is the polygon's area within the domain.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::area::{area_rows, sweep, Method, Relation};
//! use tinmerge_core::merge::area::polygon::Area;
//! // a paraboloid on a 5 x 5 grid: 32 triangles of area 0.5
//! let mut pts = Vec::new();
//! for i in 0..5 { for j in 0..5 { pts.push([i as f64, j as f64, (i * i + j * j) as f64]); } }
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! // a square of side 2 along grid lines, and a strip cutting triangles
//! let sq = Area::new(vec![vec![vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]]]]);
//! let s = sweep(&tin, 0, &sq, Method::Hierarchy, &mut || Ok(())).unwrap();
//! let rows = area_rows(&tin, &sq, &s, false, &mut || Ok(())).unwrap();
//! assert_eq!(rows.len(), 8);
//! assert!(rows.iter().all(|r| r.relation == Relation::Inside && r.coverage == 1.0));
//! let strip = Area::new(vec![vec![vec![[0.0, 0.5], [4.0, 0.5], [4.0, 1.5], [0.0, 1.5]]]]);
//! let s = sweep(&tin, 0, &strip, Method::Hierarchy, &mut || Ok(())).unwrap();
//! let rows = area_rows(&tin, &strip, &s, false, &mut || Ok(())).unwrap();
//! let covered: f64 = rows.iter().map(|r| r.coverage * 0.5).sum();
//! assert!((covered - 4.0).abs() < 1e-12);
//! ```

pub mod clip;
pub use crate::polygon;
pub mod surface;

use crate::geom::P2;
use crate::geom::{co, tri_area};
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::clip::{Chain, clipped_moments};
use crate::merge::line::{Sink, Walker};
use crate::polygon::{Area, Where, segment_meets_open_triangle};
use crate::tin::hierarchy::{children, descendants};
use crate::tin::mesh::{Indexed, Mesh};
use crate::tin::{NONE, TinError};
use robust::orient2d;

/// How the inside triangles are found (the last two are the baselines the
/// benchmark compares with).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Scarlatos's hierarchical sweep (§6.5): coarsest level first, then only the
    /// children of boundary triangles.
    Hierarchy,
    /// The same sweep at the target level only.
    Flat,
    /// Scan-fill: every triangle of the target level is tested.
    Scan,
}

/// How a reported triangle relates to the polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    /// Wholly inside (touching the boundary allowed).
    Inside,
    /// Inside in part: the polygon's boundary crosses its inside.
    Boundary,
}

impl Relation {
    pub fn as_str(&self) -> &'static str {
        match self {
            Relation::Inside => "inside",
            Relation::Boundary => "boundary",
        }
    }
}

/// One reported triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaRow {
    pub triangle: u32,
    pub level: usize,
    pub relation: Relation,
    /// Fraction of the triangle's area inside the polygon.
    pub coverage: f64,
}

/// Result of the sweep down to a target level.
#[derive(Clone, Debug, Default)]
pub struct Sweep {
    /// The target level.
    pub level: usize,
    /// `inside[l]`: triangles of level l wholly inside whose parent is not
    /// (the compact form; empty above the first level examined).
    pub inside: Vec<Vec<u32>>,
    /// Boundary triangles of the target level, sorted.
    pub boundary: Vec<u32>,
    /// Pieces of the polygon's boundary in each boundary triangle, as
    /// (triangle, chain), sorted by triangle.
    pub chains: Vec<(u32, Chain)>,
    /// Triangles examined (walked, visited by the sweep, or tested).
    pub examined: usize,
}

const WALKED: u8 = 1;
const BOUNDARY: u8 = 2;
const SEEN: u8 = 4;
const SEED: u8 = 8;

/// The walker's output for the rings: (triangle, ring, segment) pairs and,
/// if wanted, the pieces of each ring per triangle.
struct RingSink {
    ring: u32,
    seg: u32,
    want_pieces: bool,
    pairs: Vec<(u32, u32, u32)>,
    /// (triangle, ring, points)
    pieces: Vec<(u32, u32, Vec<P2>)>,
    open: bool,
}

impl Sink for RingSink {
    fn wants_points(&self) -> bool {
        self.want_pieces
    }
    /// The sweep spreads over void triangles like any other (the polygon
    /// may reach the domain on both sides of a hole); [`sweep`] leaves
    /// them out of its answer.
    fn wants_void(&self) -> bool {
        true
    }
    fn point(&mut self, tri: u32, p: P2, _along: f64) {
        let pair = (tri, self.ring, self.seg);
        if self.pairs.last() != Some(&pair) {
            self.pairs.push(pair);
        }
        if self.want_pieces {
            match self.pieces.last_mut() {
                Some(last) if self.open && last.0 == tri && last.1 == self.ring => {
                    if last.2.last() != Some(&p) {
                        last.2.push(p);
                    }
                }
                _ => self.pieces.push((tri, self.ring, vec![p])),
            }
        }
        self.open = true;
    }
    fn brk(&mut self) {
        self.open = false;
    }
}

fn walk_rings<M: Indexed>(
    tin: &M,
    level: usize,
    area: &Area,
    want_pieces: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<RingSink, TinError>
where
    TinError: From<M::Err>,
{
    let mut sink = RingSink {
        ring: 0,
        seg: 0,
        want_pieces,
        pairs: Vec::new(),
        pieces: Vec::new(),
        open: false,
    };
    // one walker for all rings: the hull (for rings entering from outside
    // the domain) is found once per level
    let mut w = Walker::new(tin, level, &mut sink, interrupt);
    for (ri, ring) in area.rings.iter().enumerate() {
        w.sink.ring = ri as u32;
        w.start_part(ring[0])?;
        for k in 0..ring.len() - 1 {
            w.sink.seg = k as u32;
            w.walk_segment(ring[k], ring[k + 1], 0.0)?;
        }
        w.end_part(ring[0], true);
    }
    drop(w);
    Ok(sink)
}

/// Corners of triangle t of a level in the plane.
#[inline]
pub fn corners2<M: Mesh>(tin: &M, level: usize, t: u32) -> Result<[P2; 3], TinError>
where
    TinError: From<M::Err>,
{
    Ok(tin.corners(level, t)?.map(|v| [v[0], v[1]]))
}

/// Whether a triangle that is not a boundary triangle lies inside (exact:
/// a corner not on the polygon's boundary decides; else the centroid; else
/// the clipped area).
struct Status<'a, M: Mesh> {
    tin: &'a M,
    area: &'a Area,
    /// per vertex: 0 unknown, else 1 + Where as u8
    vert: Flags,
}

impl<'a, M: Mesh> Status<'a, M>
where
    TinError: From<M::Err>,
{
    fn new(tin: &'a M, area: &'a Area) -> Self {
        Status {
            tin,
            area,
            vert: Flags::new(tin.num_vertices()),
        }
    }

    fn vertex(&mut self, v: u32) -> Result<Where, TinError> {
        let i = v as usize;
        Ok(match self.vert.get(i) {
            Some(1) => Where::Inside,
            Some(2) => Where::Outside,
            Some(3) => Where::Boundary,
            _ => {
                let p = self.tin.vert(v)?;
                let w = self.area.locate([p[0], p[1]]);
                if let Some(s) = self.vert.get_mut(i) {
                    *s = match w {
                        Where::Inside => 1,
                        Where::Outside => 2,
                        Where::Boundary => 3,
                    };
                }
                w
            }
        })
    }

    fn inside(&mut self, level: usize, t: u32) -> Result<bool, TinError> {
        let tri = self.tin.tri(level, t)?;
        for v in tri {
            match self.vertex(v)? {
                Where::Inside => return Ok(true),
                Where::Outside => return Ok(false),
                Where::Boundary => {}
            }
        }
        let cs = corners2(self.tin, level, t)?;
        let g = [
            (cs[0][0] + cs[1][0] + cs[2][0]) / 3.0,
            (cs[0][1] + cs[1][1] + cs[2][1]) / 3.0,
        ];
        if (0..3).all(|j| orient2d(co(cs[j]), co(cs[(j + 1) % 3]), co(g)) > 0.0) {
            match self.area.locate(g) {
                Where::Inside => return Ok(true),
                Where::Outside => return Ok(false),
                Where::Boundary => {}
            }
        }
        Ok(clipped_fraction(self.area, &cs) > 0.5)
    }
}

/// Fraction of a counter-clockwise triangle inside the area, by clipping
/// every ring to it (Sutherland-Hodgman; O(polygon size), used only where
/// nothing cheaper decides).
pub fn clipped_fraction(area: &Area, t: &[P2; 3]) -> f64 {
    let o = t[0];
    let mut sum = 0.0;
    for r in &area.rings {
        let mut poly: Vec<P2> = r[..r.len() - 1].to_vec();
        for j in 0..3 {
            let (a, b) = (t[j], t[(j + 1) % 3]);
            let h = |p: P2| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            poly = crate::merge::area::clip::clip_convex(&poly, &h);
            if poly.len() < 3 {
                break;
            }
        }
        if poly.len() < 3 {
            continue;
        }
        sum += crate::merge::area::clip::Moments::of_polygon(o, &poly).a;
    }
    sum / tri_area(t)
}

/// Flag bytes of the triangles of one level (or of the vertices), zero
/// until set, kept in pages allocated when first written: a sweep of a
/// small polygon over a large terrain costs what it touches, not a byte per
/// triangle of every level it sweeps.
#[derive(Default)]
struct Flags {
    n: usize,
    pages: Vec<Option<Box<[u8; FLAG_PAGE]>>>,
}

const FLAG_PAGE: usize = 4096;

impl Flags {
    fn new(n: usize) -> Flags {
        Flags {
            n,
            pages: (0..n.div_ceil(FLAG_PAGE)).map(|_| None).collect(),
        }
    }

    /// The flags of triangle `t` (None out of range).
    fn get(&self, t: usize) -> Option<u8> {
        (t < self.n).then(|| self[t])
    }

    fn get_mut(&mut self, t: usize) -> Option<&mut u8> {
        if t >= self.n {
            return None;
        }
        let page = self.pages[t / FLAG_PAGE].get_or_insert_with(|| Box::new([0; FLAG_PAGE]));
        Some(&mut page[t % FLAG_PAGE])
    }
}

impl std::ops::Index<usize> for Flags {
    type Output = u8;
    fn index(&self, t: usize) -> &u8 {
        assert!(t < self.n, "flag {t} of {}", self.n);
        self.pages[t / FLAG_PAGE]
            .as_ref()
            .map_or(&0, |p| &p[t % FLAG_PAGE])
    }
}

impl std::ops::IndexMut<usize> for Flags {
    fn index_mut(&mut self, t: usize) -> &mut u8 {
        let n = self.n;
        self.get_mut(t).unwrap_or_else(|| panic!("flag {t} of {n}"))
    }
}

/// Find the boundary and the inside triangles down to `level` (see the
/// module documentation).
pub fn sweep<M: Indexed>(
    tin: &M,
    level: usize,
    area: &Area,
    method: Method,
    interrupt: &mut Interrupt<'_>,
) -> Result<Sweep, TinError>
where
    TinError: From<M::Err>,
{
    let num_levels = tin.num_levels();
    if level >= num_levels {
        return Err(TinError::LevelOutOfRange {
            level: level as i64,
            num_levels,
        });
    }
    let mut out = Sweep {
        level,
        inside: vec![Vec::new(); level + 1],
        ..Sweep::default()
    };
    if area.is_empty() {
        return Ok(out);
    }
    let first = if method == Method::Hierarchy {
        0
    } else {
        level
    };
    let mut status = Status::new(tin, area);
    // The boundary, found once at the target level with the line walk; at
    // coarser levels it is the ancestors' (a triangle's inside holds its
    // children's), found by following parent links (Scarlatos §6.5).
    let walk = walk_rings(tin, level, area, true, interrupt)?;
    let mut tk = Ticker::new(interrupt);
    let mut flags: Vec<Flags> = (0..=level)
        .map(|l| Flags::new(if l >= first { tin.num_triangles(l) } else { 0 }))
        .collect();
    let mut walked_at: Vec<Vec<u32>> = vec![Vec::new(); level + 1];
    let mut boundary_at: Vec<Vec<u32>> = vec![Vec::new(); level + 1];
    for &(t, r, s) in &walk.pairs {
        tk.tick()?;
        let f = flags[level]
            .get_mut(t as usize)
            .ok_or_else(|| TinError::corrupt("area sweep: triangle id"))?;
        if *f & WALKED == 0 {
            *f |= WALKED;
            walked_at[level].push(t);
        }
        if *f & BOUNDARY == 0 {
            let ring = &area.rings[r as usize];
            let (a, b) = (ring[s as usize], ring[s as usize + 1]);
            if segment_meets_open_triangle(&corners2(tin, level, t)?, a, b) {
                *f |= BOUNDARY;
                boundary_at[level].push(t);
            }
        }
    }
    // Segments that touch a triangle of the target level without crossing
    // its inside (running along its edges) may still cross the inside of an
    // ancestor: those are tested again going up.
    let mut pending: Vec<(u32, u32, u32)> = walk
        .pairs
        .iter()
        .filter(|&&(t, _, _)| flags[level][t as usize] & BOUNDARY == 0)
        .copied()
        .collect();
    for l in (first..level).rev() {
        let nl = tin.num_triangles(l);
        let up = |c: u32| -> Result<u32, TinError> {
            if c as usize >= tin.num_triangles(l + 1) {
                return Err(TinError::corrupt("area sweep: parent"));
            }
            let p = tin.parent(l + 1, c)?;
            if (p as usize) < nl {
                Ok(p)
            } else {
                Err(TinError::corrupt("area sweep: parent id"))
            }
        };
        for (lists, bit) in [(&mut walked_at, WALKED), (&mut boundary_at, BOUNDARY)] {
            let (coarse, fine) = lists.split_at_mut(l + 1);
            for &c in &fine[0] {
                tk.tick()?;
                let p = up(c)?;
                if flags[l][p as usize] & bit == 0 {
                    flags[l][p as usize] |= bit;
                    coarse[l].push(p);
                }
            }
        }
        let mut next = Vec::new();
        for &(c, r, s) in &pending {
            tk.tick()?;
            let p = up(c)?;
            if flags[l][p as usize] & BOUNDARY != 0 {
                continue;
            }
            let ring = &area.rings[r as usize];
            let (a, b) = (ring[s as usize], ring[s as usize + 1]);
            if segment_meets_open_triangle(&corners2(tin, l, p)?, a, b) {
                flags[l][p as usize] |= BOUNDARY;
                boundary_at[l].push(p);
            } else {
                next.push((p, r, s));
            }
        }
        next.sort_unstable();
        next.dedup();
        pending = next;
    }
    let mut chains_at_level = Some(walk.pieces);
    let mut prev_boundary: Vec<u32> = Vec::new();
    for l in first..=level {
        let n = tin.num_triangles(l);
        let walked = std::mem::take(&mut walked_at[l]);
        let mut boundary = std::mem::take(&mut boundary_at[l]);
        let mut flags = std::mem::take(&mut flags[l]);
        out.examined += walked.len();
        let inside = &mut out.inside[l];
        let open_sweep = l == first;
        if open_sweep && method == Method::Scan {
            for t in 0..n as u32 {
                tk.tick()?;
                if flags[t as usize] & BOUNDARY == 0 {
                    out.examined += 1;
                    if status.inside(l, t)? {
                        inside.push(t);
                    }
                }
            }
        } else if open_sweep && walked.is_empty() {
            // no ring enters the domain: all in or all out
            if n > 0 && status.inside(l, 0)? {
                inside.extend(0..n as u32);
                out.examined += n;
            }
        } else {
            // The seeds: at the first level, the triangles the rings touch
            // and their neighbours; below, the children of boundary
            // triangles. Every one that is not a boundary triangle is wholly
            // in or out.
            let mut seeds: Vec<u32> = Vec::new();
            let mut mark = |t: u32, flags: &mut Flags| -> Result<(), TinError> {
                let f = flags
                    .get_mut(t as usize)
                    .ok_or_else(|| TinError::corrupt("area sweep: triangle id"))?;
                if *f & (BOUNDARY | SEED) == 0 {
                    *f |= SEED;
                    seeds.push(t);
                }
                Ok(())
            };
            if open_sweep {
                for &t in &walked {
                    mark(t, &mut flags)?;
                    for nb in tin.nbrs(l, t)? {
                        if nb != NONE {
                            mark(nb, &mut flags)?;
                        }
                    }
                }
            } else {
                for &p in &prev_boundary {
                    for ch in children(tin, l - 1, p)? {
                        mark(ch, &mut flags)?;
                    }
                }
            }
            // The sweep: a seed's status comes from an exact
            // point-in-polygon test, then spreads over triangle adjacency:
            // two neighbours no ring touches have the same status (a ring
            // running along their shared edge would touch one of them).
            // Inside, the sweep runs on to the whole inside at the first
            // level; otherwise it stays among the seeds.
            let mut stack: Vec<(u32, bool)> = Vec::new();
            for &s0 in &seeds {
                if flags[s0 as usize] & SEEN != 0 {
                    continue;
                }
                flags[s0 as usize] |= SEEN;
                out.examined += 1;
                tk.tick()?;
                let st = status.inside(l, s0)?;
                if st {
                    inside.push(s0);
                }
                stack.push((s0, st));
                while let Some((u, su)) = stack.pop() {
                    let uw = flags[u as usize] & WALKED != 0;
                    for nb in tin.nbrs(l, u)? {
                        if nb == NONE {
                            continue;
                        }
                        let fnb = flags
                            .get_mut(nb as usize)
                            .ok_or_else(|| TinError::corrupt("area sweep: neighbour"))?;
                        if *fnb & (BOUNDARY | SEEN) != 0 {
                            continue;
                        }
                        if *fnb & SEED == 0 && !(open_sweep && su) {
                            continue;
                        }
                        *fnb |= SEEN;
                        let nw = *fnb & WALKED != 0;
                        out.examined += 1;
                        tk.tick()?;
                        let sn = if !uw && !nw {
                            su
                        } else {
                            status.inside(l, nb)?
                        };
                        if sn {
                            inside.push(nb);
                        }
                        stack.push((nb, sn));
                    }
                }
            }
        }
        inside.sort_unstable();
        boundary.sort_unstable();
        if l == level
            && let Some(pieces) = chains_at_level.take()
        {
            out.chains = chains(pieces, &flags, area);
        }
        prev_boundary = boundary;
    }
    out.boundary = prev_boundary;
    // void triangles are off the domain: no part of the answer (a void
    // triangle's descendants are void, a domain triangle's are not)
    for (l, ins) in out.inside.iter_mut().enumerate() {
        ins.retain(|&t| !tin.is_void(l, t));
    }
    out.boundary.retain(|&t| !tin.is_void(level, t));
    out.chains.retain(|(t, _)| !tin.is_void(level, *t));
    Ok(out)
}

/// The pieces of the boundary triangles as chains: a ring's last piece and
/// its first join when they meet in one triangle at the ring's start.
fn chains(pieces: Vec<(u32, u32, Vec<P2>)>, flags: &Flags, area: &Area) -> Vec<(u32, Chain)> {
    let mut out: Vec<(u32, Chain)> = Vec::new();
    let mut i = 0;
    while i < pieces.len() {
        let r = pieces[i].1;
        let mut j = i;
        while j < pieces.len() && pieces[j].1 == r {
            j += 1;
        }
        let ring = &pieces[i..j];
        let start = area.rings[r as usize][0];
        let mut used_first = false;
        let mut used_last = false;
        if ring.len() == 1 {
            let (t, _, pts) = &ring[0];
            let closed = pts.first() == Some(&start) && pts.last() == Some(&start);
            out.push((
                *t,
                Chain {
                    pts: pts.clone(),
                    enters: !closed,
                    exits: !closed,
                },
            ));
            used_first = true;
        } else {
            let (f, l) = (&ring[0], &ring[ring.len() - 1]);
            if f.0 == l.0 && f.2.first() == Some(&start) && l.2.last() == Some(&start) {
                let mut pts = l.2.clone();
                pts.extend_from_slice(&f.2[1..]);
                out.push((
                    f.0,
                    Chain {
                        pts,
                        enters: true,
                        exits: true,
                    },
                ));
                used_first = true;
                used_last = true;
            }
        }
        for (k, (t, _, pts)) in ring.iter().enumerate() {
            if (k == 0 && used_first) || (k == ring.len() - 1 && used_last) {
                continue;
            }
            out.push((
                *t,
                Chain {
                    pts: pts.clone(),
                    enters: true,
                    exits: true,
                },
            ));
        }
        i = j;
    }
    out.retain(|(t, ch)| {
        ch.pts.len() >= 2 && flags.get(*t as usize).is_some_and(|f| f & BOUNDARY != 0)
    });
    out.sort_by_key(|(t, _)| *t);
    out
}

/// Coverage of each boundary triangle of the sweep, in `boundary` order.
pub fn coverages<M: Mesh>(tin: &M, area: &Area, s: &Sweep) -> Result<Vec<f64>, TinError>
where
    TinError: From<M::Err>,
{
    let mut out = Vec::with_capacity(s.boundary.len());
    let mut k = 0;
    for &t in &s.boundary {
        while k < s.chains.len() && s.chains[k].0 < t {
            k += 1;
        }
        let mut e = k;
        while e < s.chains.len() && s.chains[e].0 == t {
            e += 1;
        }
        let cs = corners2(tin, s.level, t)?;
        let ch: Vec<Chain> = s.chains[k..e].iter().map(|(_, c)| c.clone()).collect();
        let m = clipped_moments(&cs, cs[0], &ch, &mut |p| area.locate(p));
        out.push((m.a / tri_area(&cs)).clamp(0.0, 1.0));
        k = e;
    }
    Ok(out)
}

/// The rows of `tin_area_triangles`: compact (inside triangles at the
/// coarsest level wholly inside, sorted by level then id) or full (every
/// triangle of the target level, sorted by id).
pub fn area_rows<M: Mesh>(
    tin: &M,
    area: &Area,
    s: &Sweep,
    compact: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<AreaRow>, TinError>
where
    TinError: From<M::Err>,
{
    let mut rows = Vec::new();
    let inside_row = |t: u32, level: usize| AreaRow {
        triangle: t,
        level,
        relation: Relation::Inside,
        coverage: 1.0,
    };
    let mut tk = Ticker::new(interrupt);
    for (l, ts) in s.inside.iter().enumerate() {
        if compact || l == s.level {
            rows.extend(ts.iter().map(|&t| inside_row(t, l)));
        } else {
            let mut d = Vec::new();
            for &t in ts {
                tk.tick()?;
                descendants(tin, l, t, s.level, &mut d)?;
            }
            rows.extend(d.into_iter().map(|t| inside_row(t, s.level)));
        }
    }
    for (&t, cov) in s.boundary.iter().zip(coverages(tin, area, s)?) {
        rows.push(AreaRow {
            triangle: t,
            level: s.level,
            relation: Relation::Boundary,
            coverage: cov,
        });
    }
    if compact {
        rows.sort_by_key(|r| (r.level, r.triangle));
    } else {
        rows.sort_by_key(|r| r.triangle);
    }
    Ok(rows)
}
