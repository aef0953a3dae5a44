//! The hierarchical polygonal sweep ([`sweep`]; the module above
//! documents it): the rings walked at the target level, the boundary carried
//! up the levels, each level swept from its seeds over triangle adjacency.

use crate::geom::{P2, co, tri_area};
use crate::interrupt::{Interrupt, Ticker};
use crate::merge::area::clip::{Chain, ChainPoints, Moments, clip_convex};
use crate::merge::area::scratch::{Flags, Pair, Scratch};
use crate::merge::line::{Sink, Walker};
use crate::polygon::{Area, RUN, Where, segment_meets_open_triangle};
use crate::tin::hierarchy::children;
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
    /// Pieces of the polygon's boundary in the boundary triangles, sorted
    /// by triangle ([`Sweep::chains_of`] gives one triangle's).
    pub chains: Vec<Chain>,
    /// The triangle of each of `chains`, in the same order.
    pub chain_triangles: Vec<u32>,
    /// Triangles examined (walked, visited by the sweep, or tested).
    pub examined: usize,
}

impl Sweep {
    /// The chains of boundary triangle `t`, for triangles asked for in
    /// increasing order: `k` is where the last one's ended (0 at first).
    pub fn chains_of(&self, t: u32, k: &mut usize) -> &[Chain] {
        let ts = &self.chain_triangles;
        while *k < ts.len() && ts[*k] < t {
            *k += 1;
        }
        let s = *k;
        while *k < ts.len() && ts[*k] == t {
            *k += 1;
        }
        &self.chains[s..*k]
    }
}

/// Corners of triangle t of a level in the plane.
#[inline]
pub(crate) fn corners2<M: Mesh>(tin: &M, level: usize, t: u32) -> Result<[P2; 3], TinError>
where
    TinError: From<M::Err>,
{
    Ok(tin.corners(level, t)?.map(|v| [v[0], v[1]]))
}

/// Fraction of a counter-clockwise triangle inside the area, by clipping
/// every ring to it (Sutherland-Hodgman; O(polygon size), used only where
/// nothing cheaper decides).
pub(crate) fn clipped_fraction(area: &Area, t: &[P2; 3]) -> f64 {
    let o = t[0];
    let mut sum = 0.0;
    for r in &area.rings {
        let mut poly: Vec<P2> = r[..r.len() - 1].to_vec();
        for j in 0..3 {
            let (a, b) = (t[j], t[(j + 1) % 3]);
            let h = |p: P2| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            poly = clip_convex(&poly, &h);
            if poly.len() < 3 {
                break;
            }
        }
        if poly.len() < 3 {
            continue;
        }
        sum += Moments::of_polygon(o, &poly).a;
    }
    sum / tri_area(t)
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
    pieces: Vec<(u32, u32, ChainPoints)>,
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
    fn wants_along(&self) -> bool {
        false
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
                _ => {
                    let mut pts = ChainPoints::new();
                    pts.push(p);
                    self.pieces.push((tri, self.ring, pts));
                }
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
    sc: &mut Scratch,
    interrupt: &mut Interrupt<'_>,
) -> Result<RingSink, TinError>
where
    TinError: From<M::Err>,
{
    let mut sink = RingSink {
        ring: 0,
        seg: 0,
        want_pieces,
        pairs: std::mem::take(&mut sc.pairs),
        pieces: std::mem::take(&mut sc.pieces),
        open: false,
    };
    // one walker for all rings: the hull (for rings entering from outside
    // the domain) is found once per level
    let b = tin.bbox();
    let misses = |r: [f64; 4]| r[2] < b.min_x || r[0] > b.max_x || r[3] < b.min_y || r[1] > b.max_y;
    let mut w = Walker::new(tin, level, &mut sink, interrupt);
    for (ri, ring) in area.rings.iter().enumerate() {
        w.sink.ring = ri as u32;
        w.start_part(ring[0])?;
        let mut k = 0;
        while k + 1 < ring.len() {
            // a run of segments wholly off the terrain's box is skipped:
            // its first point is off the domain, so the walk is outside
            // there and stays outside along the run, reporting nothing
            // (a county's ring over one of its tiles)
            if k % RUN == 0 && area.run_box(ri, k / RUN).is_some_and(misses) {
                k += RUN;
                continue;
            }
            w.sink.seg = k as u32;
            w.walk_segment(ring[k], ring[k + 1], 0.0)?;
            k += 1;
        }
        w.end_part(ring[0], true);
    }
    drop(w);
    Ok(sink)
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

impl Drop for Sweep {
    /// Its vectors back to the thread's [`Scratch`] for the next sweep.
    fn drop(&mut self) {
        let lists = self.inside.drain(..).chain([
            std::mem::take(&mut self.boundary),
            std::mem::take(&mut self.chain_triangles),
        ]);
        Scratch::keep(lists, std::mem::take(&mut self.chains));
    }
}

/// Find the boundary and the inside triangles down to `level` (see the
/// module documentation): the boundary marked at the target level
/// ([`Sweeper::mark_target`]) and carried up ([`Sweeper::mark_upward`]),
/// then each level swept from the first down ([`Sweeper::sweep_level`]),
/// the void triangles dropped last ([`drop_void`]).
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
    let mut sc = Scratch::take();
    let mut out = Sweep {
        level,
        inside: (0..=level).map(|_| sc.list()).collect(),
        boundary: Vec::new(),
        chains: Vec::new(),
        chain_triangles: Vec::new(),
        examined: 0,
    };
    if area.is_empty() {
        sc.give_back();
        return Ok(out);
    }
    let first = if method == Method::Hierarchy {
        0
    } else {
        level
    };
    // The boundary, found once at the target level with the line walk; at
    // coarser levels it is the ancestors' (a triangle's inside holds its
    // children's), found by following parent links (Scarlatos §6.5).
    let walk = walk_rings(tin, level, area, true, &mut sc, interrupt)?;
    let mut s = Sweeper {
        tin,
        area,
        method,
        first,
        level,
        status: Status::new(tin, area),
        seeds: std::mem::take(&mut sc.seeds),
        stack: std::mem::take(&mut sc.stack),
        tk: Ticker::new(interrupt),
    };
    let RingSink {
        pairs, mut pieces, ..
    } = walk;
    let mut marks = s.mark_target(&pairs, &mut sc)?;
    sc.pairs = pairs;
    s.mark_upward(&mut marks, &mut sc)?;
    let mut prev_boundary: Vec<u32> = sc.list();
    for l in first..=level {
        let walked = std::mem::take(&mut marks.walked_at[l]);
        let mut boundary = std::mem::take(&mut marks.boundary_at[l]);
        let mut flags = std::mem::take(&mut marks.flags[l]);
        out.examined += walked.len();
        s.sweep_level(l, &walked, &prev_boundary, &mut flags, &mut out)?;
        out.inside[l].sort_unstable();
        boundary.sort_unstable();
        if l == level {
            chains(&mut pieces, &flags, area, &mut sc, &mut out);
        }
        sc.lists.push(walked);
        sc.lists
            .push(std::mem::replace(&mut prev_boundary, boundary));
    }
    out.boundary = prev_boundary;
    sc.pieces = pieces;
    (sc.seeds, sc.stack) = (s.seeds, s.stack);
    for v in marks.walked_at.into_iter().chain(marks.boundary_at) {
        if v.capacity() > 0 {
            sc.lists.push(v);
        }
    }
    sc.give_back();
    drop_void(tin, &mut out);
    Ok(out)
}

/// Void triangles are off the domain: no part of the answer (a void
/// triangle's descendants are void, a domain triangle's are not).
fn drop_void<M: Indexed>(tin: &M, out: &mut Sweep) {
    let level = out.level;
    for (l, ins) in out.inside.iter_mut().enumerate() {
        ins.retain(|&t| !tin.is_void(l, t));
    }
    out.boundary.retain(|&t| !tin.is_void(level, t));
    if out.chain_triangles.iter().any(|&t| tin.is_void(level, t)) {
        let kept: Vec<(u32, Chain)> = std::mem::take(&mut out.chain_triangles)
            .into_iter()
            .zip(std::mem::take(&mut out.chains))
            .filter(|(t, _)| !tin.is_void(level, *t))
            .collect();
        (out.chain_triangles, out.chains) = kept.into_iter().unzip();
    }
}

/// The boundary marks of the levels swept: the triangles the rings' walk
/// met (`WALKED`) and those whose inside a ring crosses (`BOUNDARY`), as
/// flags and as lists per level.
struct Marks {
    flags: Vec<Flags>,
    walked_at: Vec<Vec<u32>>,
    boundary_at: Vec<Vec<u32>>,
}

/// One sweep's context: the tin, the polygon, the levels swept (`first` to
/// `level`), the inside test and the interrupt ticker.
struct Sweeper<'a, 't, 'i, M: Indexed> {
    tin: &'a M,
    area: &'a Area,
    method: Method,
    /// 0 for the hierarchy, else the target level
    first: usize,
    level: usize,
    status: Status<'a, M>,
    /// the current level's seeds and the spread's stack, kept for the next
    /// level
    seeds: Vec<u32>,
    stack: Vec<(u32, bool)>,
    tk: Ticker<'t, 'i>,
}

impl<M: Indexed> Sweeper<'_, '_, '_, M>
where
    TinError: From<M::Err>,
{
    /// Segment `s` of ring `r`.
    fn segment(&self, r: u32, s: u32) -> (P2, P2) {
        let ring = &self.area.rings[r as usize];
        (ring[s as usize], ring[s as usize + 1])
    }

    /// The marks at the target level, from the walk's (triangle, ring,
    /// segment) `pairs`; and, in `sc.pending`, the pairs whose segment
    /// touches its triangle without crossing its inside (running along its
    /// edges): those may still cross the inside of an ancestor, and are
    /// tested again going up.
    fn mark_target(&mut self, pairs: &[Pair], sc: &mut Scratch) -> Result<Marks, TinError> {
        let (tin, level, first) = (self.tin, self.level, self.first);
        let mut m = Marks {
            flags: (0..=level)
                .map(|l| Flags::new(if l >= first { tin.num_triangles(l) } else { 0 }))
                .collect(),
            walked_at: (0..=level).map(|_| sc.list()).collect(),
            boundary_at: (0..=level).map(|_| sc.list()).collect(),
        };
        m.walked_at[level].reserve(pairs.len());
        m.boundary_at[level].reserve(pairs.len());
        for &(t, r, s) in pairs {
            self.tk.tick()?;
            let f = m.flags[level]
                .get_mut(t as usize)
                .ok_or_else(|| TinError::corrupt("area sweep: triangle id"))?;
            if *f & WALKED == 0 {
                *f |= WALKED;
                m.walked_at[level].push(t);
            }
            if *f & BOUNDARY == 0 {
                let (a, b) = self.segment(r, s);
                if segment_meets_open_triangle(&corners2(tin, level, t)?, a, b) {
                    *f |= BOUNDARY;
                    m.boundary_at[level].push(t);
                }
            }
        }
        sc.pending.clear();
        sc.pending.extend(
            pairs
                .iter()
                .filter(|&&(t, _, _)| m.flags[level][t as usize] & BOUNDARY == 0)
                .copied(),
        );
        Ok(m)
    }

    /// The marks of the coarser levels: a triangle's parent is walked or
    /// boundary when it is, and the pending segments (`sc.pending`) are
    /// tested against the parents' insides.
    fn mark_upward(&mut self, m: &mut Marks, sc: &mut Scratch) -> Result<(), TinError> {
        let mut pending = std::mem::take(&mut sc.pending);
        let mut next = std::mem::take(&mut sc.next);
        let tin = self.tin;
        for l in (self.first..self.level).rev() {
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
            for (lists, bit) in [(&mut m.walked_at, WALKED), (&mut m.boundary_at, BOUNDARY)] {
                let (coarse, fine) = lists.split_at_mut(l + 1);
                coarse[l].reserve(fine[0].len());
                for &c in &fine[0] {
                    self.tk.tick()?;
                    let p = up(c)?;
                    if m.flags[l][p as usize] & bit == 0 {
                        m.flags[l][p as usize] |= bit;
                        coarse[l].push(p);
                    }
                }
            }
            next.clear();
            for &(c, r, s) in &pending {
                self.tk.tick()?;
                let p = up(c)?;
                if m.flags[l][p as usize] & BOUNDARY != 0 {
                    continue;
                }
                let (a, b) = self.segment(r, s);
                if segment_meets_open_triangle(&corners2(tin, l, p)?, a, b) {
                    m.flags[l][p as usize] |= BOUNDARY;
                    m.boundary_at[l].push(p);
                } else {
                    next.push((p, r, s));
                }
            }
            next.sort_unstable();
            next.dedup();
            std::mem::swap(&mut pending, &mut next);
        }
        (sc.pending, sc.next) = (pending, next);
        Ok(())
    }

    /// Level `l`'s inside triangles into `out`: every triangle tested
    /// (the scan's first level), all or none (no ring enters the domain),
    /// or the sweep from the seeds ([`find_seeds`], [`Sweeper::spread`]).
    fn sweep_level(
        &mut self,
        l: usize,
        walked: &[u32],
        prev_boundary: &[u32],
        flags: &mut Flags,
        out: &mut Sweep,
    ) -> Result<(), TinError> {
        let n = self.tin.num_triangles(l);
        let open_sweep = l == self.first;
        if open_sweep && self.method == Method::Scan {
            for t in 0..n as u32 {
                self.tk.tick()?;
                if flags[t as usize] & BOUNDARY == 0 {
                    out.examined += 1;
                    if self.status.inside(l, t)? {
                        out.inside[l].push(t);
                    }
                }
            }
        } else if open_sweep && walked.is_empty() {
            // no ring enters the domain: all in or all out
            if n > 0 && self.status.inside(l, 0)? {
                out.inside[l].extend(0..n as u32);
                out.examined += n;
            }
        } else {
            let mut seeds = std::mem::take(&mut self.seeds);
            seeds.clear();
            find_seeds(
                self.tin,
                l,
                open_sweep,
                walked,
                prev_boundary,
                flags,
                &mut seeds,
            )?;
            self.spread(l, open_sweep, &seeds, flags, out)?;
            self.seeds = seeds;
        }
        Ok(())
    }

    /// The sweep: a seed's status comes from an exact point-in-polygon
    /// test, then spreads over triangle adjacency: two neighbours no ring
    /// touches have the same status (a ring running along their shared
    /// edge would touch one of them). Inside, the sweep runs on to the
    /// whole inside at the first level (`open_sweep`); otherwise it stays
    /// among the seeds.
    fn spread(
        &mut self,
        l: usize,
        open_sweep: bool,
        seeds: &[u32],
        flags: &mut Flags,
        out: &mut Sweep,
    ) -> Result<(), TinError> {
        let Sweep {
            inside, examined, ..
        } = out;
        let inside = &mut inside[l];
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        for &s0 in seeds {
            if flags[s0 as usize] & SEEN != 0 {
                continue;
            }
            flags[s0 as usize] |= SEEN;
            *examined += 1;
            self.tk.tick()?;
            let st = self.status.inside(l, s0)?;
            if st {
                inside.push(s0);
            }
            stack.push((s0, st));
            while let Some((u, su)) = stack.pop() {
                let uw = flags[u as usize] & WALKED != 0;
                for nb in self.tin.nbrs(l, u)? {
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
                    *examined += 1;
                    self.tk.tick()?;
                    let sn = if !uw && !nw {
                        su
                    } else {
                        self.status.inside(l, nb)?
                    };
                    if sn {
                        inside.push(nb);
                    }
                    stack.push((nb, sn));
                }
            }
        }
        self.stack = stack;
        Ok(())
    }
}

/// The seeds of level `l`'s sweep: at the first level (`open_sweep`), the
/// triangles the rings touch (`walked`) and their neighbours; below, the
/// children of the level above's boundary triangles. Every one that is not
/// a boundary triangle is wholly in or out. Into `seeds`.
fn find_seeds<M: Indexed>(
    tin: &M,
    l: usize,
    open_sweep: bool,
    walked: &[u32],
    prev_boundary: &[u32],
    flags: &mut Flags,
    seeds: &mut Vec<u32>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    seeds.reserve(4 * walked.len().max(prev_boundary.len()));
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
        for &t in walked {
            mark(t, flags)?;
            for nb in tin.nbrs(l, t)? {
                if nb != NONE {
                    mark(nb, flags)?;
                }
            }
        }
    } else {
        for &p in prev_boundary {
            for ch in children(tin, l - 1, p)? {
                mark(ch, flags)?;
            }
        }
    }
    Ok(())
}

/// The pieces of the boundary triangles as chains, into `out.chains` and
/// `out.chain_triangles` in triangle order (a triangle's in ring order): a
/// ring's last piece and its first join when they meet in one triangle at
/// the ring's start. `pieces` is emptied.
fn chains(
    pieces: &mut Vec<(u32, u32, ChainPoints)>,
    flags: &Flags,
    area: &Area,
    sc: &mut Scratch,
    out: &mut Sweep,
) {
    // (triangle, order made, chain): sorted by the first two
    let mut tagged = std::mem::take(&mut sc.tagged);
    tagged.clear();
    let mut push = |t: u32, ch: Chain| {
        let k = tagged.len() as u32;
        tagged.push((t, k, ch));
    };
    let mut pieces = pieces.drain(..).peekable();
    let mut ring: Vec<(u32, u32, ChainPoints)> = Vec::new();
    while let Some(first) = pieces.next() {
        // this ring's pieces, moved (not copied) into chains
        let r = first.1;
        ring.clear();
        ring.push(first);
        while let Some(p) = pieces.next_if(|p| p.1 == r) {
            ring.push(p);
        }
        let start = area.rings[r as usize][0];
        if ring.len() == 1 {
            let (t, _, pts) = ring.pop().expect("one piece");
            let closed = pts.first() == Some(&start) && pts.last() == Some(&start);
            push(
                t,
                Chain {
                    pts,
                    enters: !closed,
                    exits: !closed,
                },
            );
            continue;
        }
        let n = ring.len();
        let joined = {
            let (f, l) = (&ring[0], &ring[n - 1]);
            f.0 == l.0 && f.2.first() == Some(&start) && l.2.last() == Some(&start)
        };
        let mut ring = ring.drain(..);
        if joined {
            let (t, _, first_pts) = ring.next().expect("first piece");
            let (_, _, mut pts) = ring.next_back().expect("last piece");
            pts.extend_from_slice(&first_pts[1..]);
            push(
                t,
                Chain {
                    pts,
                    enters: true,
                    exits: true,
                },
            );
        }
        for (t, _, pts) in ring {
            push(
                t,
                Chain {
                    pts,
                    enters: true,
                    exits: true,
                },
            );
        }
    }
    tagged.retain(|(t, _, ch)| {
        ch.pts.len() >= 2 && flags.get(*t as usize).is_some_and(|f| f & BOUNDARY != 0)
    });
    // (unstable on distinct keys: the order of a stable sort by triangle,
    // without its buffer)
    tagged.sort_unstable_by_key(|&(t, k, _)| (t, k));
    let mut cs = std::mem::take(&mut sc.chains);
    cs.clear();
    let mut ts = sc.list();
    for (t, _, ch) in tagged.drain(..) {
        ts.push(t);
        cs.push(ch);
    }
    (out.chain_triangles, out.chains) = (ts, cs);
    sc.tagged = tagged;
}
