//! The part of an area inside one convex polygon (a triangle, or a triangle
//! cut by a horizontal plane), integrated from local information only: the
//! pieces of the area's boundary inside the polygon (chains, from the line
//! walk) and where they enter and leave it.
//!
//! By Green's theorem the area and first moments of `Q = area ∩ C` are sums
//! over the directed edges of `Q`'s boundary, which is made of the chains
//! (interior on their left) and the arcs of `C`'s boundary lying in the
//! area. Walking `C`'s boundary counter-clockwise, an arc in the area starts
//! where a chain leaves `C` and ends where the next chain enters it; an arc
//! between two events at the same position is decided by the event at its
//! other end, and only when both ends are ambiguous (or there are no events)
//! by an exact point-in-polygon test. So a boundary triangle costs its own
//! pieces, not the whole polygon, and no polygon clipping library is needed.
//!
//! ```
//! use tinmerge_core::merge::area::clip::{clipped_moments, Chain};
//! use tinmerge_core::merge::area::polygon::{Area, Where};
//! // the triangle (0,0) (2,0) (0,2) cut by the area x <= 1
//! let area = Area::new(vec![vec![vec![[-5.0, -5.0], [1.0, -5.0], [1.0, 5.0], [-5.0, 5.0]]]]);
//! let tri = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
//! // the boundary piece inside the triangle, going up (interior on its left)
//! let chains = vec![Chain { pts: [[1.0, 0.0], [1.0, 1.0]].into_iter().collect(), enters: true, exits: true }];
//! let m = clipped_moments(&tri, tri[0], &chains, &mut |p| area.locate(p));
//! assert!((m.a - 1.5).abs() < 1e-12); // 2 - 1/2
//! ```

use crate::geom::P2;
use crate::polygon::Where;

/// The points of a [`Chain`]: a piece of a ring in one triangle is most
/// often two or three points, kept inline (a boundary triangle's pieces
/// cost no allocation).
pub type ChainPoints = smallvec::SmallVec<[P2; 4]>;

/// A piece of the area's boundary inside the convex polygon, in ring
/// order (interior on its left). `enters`: its first point is where it comes
/// in through the polygon's boundary; `exits`: its last point is where it
/// leaves. A chain that does neither is a closed ring inside the polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    pub pts: ChainPoints,
    pub enters: bool,
    pub exits: bool,
}

/// Area and first moments (integrals of 1, x, y) of a region, with x, y
/// taken relative to an origin chosen near the region (for precision).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    pub a: f64,
    pub mx: f64,
    pub my: f64,
}

impl Moments {
    /// Add the directed boundary edge p -> q (Green's theorem).
    #[inline]
    pub fn edge(&mut self, o: P2, p: P2, q: P2) {
        let (px, py, qx, qy) = (p[0] - o[0], p[1] - o[1], q[0] - o[0], q[1] - o[1]);
        let cr = px * qy - qx * py;
        self.a += cr / 2.0;
        self.mx += (px + qx) * cr / 6.0;
        self.my += (py + qy) * cr / 6.0;
    }

    /// Moments of a polygon given by its vertices (closing edge implied).
    pub(crate) fn of_polygon(o: P2, pts: &[P2]) -> Moments {
        let mut m = Moments::default();
        for i in 0..pts.len() {
            m.edge(o, pts[i], pts[(i + 1) % pts.len()]);
        }
        m
    }

    /// The integral of the linear function f0 + gx (x - o.x) + gy (y - o.y).
    #[inline]
    pub fn linear(&self, f0: f64, gx: f64, gy: f64) -> f64 {
        f0 * self.a + gx * self.mx + gy * self.my
    }

    pub fn add(&mut self, o: &Moments) {
        self.a += o.a;
        self.mx += o.mx;
        self.my += o.my;
    }
}

/// Position of a point of the boundary of the convex polygon `conv`
/// (counter-clockwise), as edge index + fraction along it, in [0, n).
fn perimeter_pos(conv: &[P2], p: P2) -> f64 {
    let n = conv.len();
    if let Some(k) = conv.iter().position(|&v| v == p) {
        return k as f64;
    }
    let mut best = (f64::INFINITY, 0.0);
    for k in 0..n {
        let (a, b) = (conv[k], conv[(k + 1) % n]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
        let d = ex * ex + ey * ey;
        if d < best.0 {
            best = (d, k as f64 + t);
        }
    }
    if best.1 >= n as f64 {
        best.1 - n as f64
    } else {
        best.1
    }
}

fn point_at(conv: &[P2], pos: f64) -> P2 {
    let n = conv.len();
    let pos = pos.rem_euclid(n as f64);
    let k = (pos.floor() as usize).min(n - 1);
    let t = pos - k as f64;
    let (a, b) = (conv[k], conv[(k + 1) % n]);
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// A triangle's events: a few (two a piece of the boundary), kept on the
/// stack.
type Events = smallvec::SmallVec<[Event; 8]>;

#[derive(Clone, Copy)]
struct Event {
    pos: f64,
    entry: bool,
    p: P2,
}

/// Moments of `area ∩ conv` (conv convex, counter-clockwise) from the
/// chains inside it; `locate` is the exact point-in-polygon test, used only
/// where the events do not decide. The chains' own edges and the events
/// where they enter and leave conv ([`chain_events`]); without events,
/// conv is wholly in or out ([`all_or_nothing`]); else the arcs of conv's
/// perimeter between events that are in the area are added ([`add_arcs`]).
pub fn clipped_moments(
    conv: &[P2],
    o: P2,
    chains: &[Chain],
    locate: &mut dyn FnMut(P2) -> Where,
) -> Moments {
    let mut m = Moments::default();
    if conv.len() < 3 {
        return m;
    }
    let mut events = chain_events(conv, o, chains, &mut m);
    if events.is_empty() {
        m.add(&all_or_nothing(conv, o, locate));
        return m;
    }
    events.sort_by(|a, b| a.pos.total_cmp(&b.pos).then(a.entry.cmp(&b.entry)));
    add_arcs(conv, o, &events, locate, &mut m);
    m
}

/// The chains' edges added to `m` (a chain neither entering nor leaving
/// closed on itself), and the events where they enter and leave conv.
/// A piece of the boundary within rounding of one corner of conv (a ring
/// passing an ulp from a vertex of the triangulation) cuts off nothing
/// measurable, but where it enters and leaves cannot be told apart from
/// the corner: ordered by position along the perimeter, its two events
/// may swap and flip the status of every arc. It is left out; the other
/// events (or the probes) decide the arcs.
fn chain_events(conv: &[P2], o: P2, chains: &[Chain], m: &mut Moments) -> Events {
    let scale = conv
        .iter()
        .fold(0.0_f64, |a, v| a.max(v[0].abs()).max(v[1].abs()));
    let band = 256.0 * f64::EPSILON * scale;
    let at_a_corner = |ch: &Chain| {
        conv.iter().any(|v| {
            ch.pts
                .iter()
                .all(|p| (p[0] - v[0]).abs() <= band && (p[1] - v[1]).abs() <= band)
        })
    };
    let mut events = Events::new();
    for ch in chains.iter().filter(|ch| !at_a_corner(ch)) {
        for w in ch.pts.windows(2) {
            m.edge(o, w[0], w[1]);
        }
        let (Some(&f), Some(&l)) = (ch.pts.first(), ch.pts.last()) else {
            continue;
        };
        if !ch.enters && !ch.exits {
            m.edge(o, l, f);
        }
        if ch.enters {
            events.push(Event {
                pos: perimeter_pos(conv, f),
                entry: true,
                p: f,
            });
        }
        if ch.exits {
            events.push(Event {
                pos: perimeter_pos(conv, l),
                entry: false,
                p: l,
            });
        }
    }
    events
}

/// Conv's moments when its boundary is wholly in the area, else none: up
/// to pieces the walk could not resolve (a ring passing within an ulp of a
/// corner crosses the corner's wedge where no crossing point is
/// representable, so that corner alone may be on the wrong side), the
/// corners and edge midpoints vote; points on the area's boundary abstain.
fn all_or_nothing(conv: &[P2], o: P2, locate: &mut dyn FnMut(P2) -> Where) -> Moments {
    let n = conv.len();
    let (mut ins, mut outs) = (0, 0);
    for p in (0..n)
        .map(|k| conv[k])
        .chain((0..n).map(|k| point_at(conv, k as f64 + 0.5)))
    {
        match locate(p) {
            Where::Inside => ins += 1,
            Where::Outside => outs += 1,
            Where::Boundary => {}
        }
    }
    if ins > outs {
        Moments::of_polygon(o, conv)
    } else {
        Moments::default()
    }
}

/// The arcs of conv's perimeter between the (sorted) `events` that lie in
/// the area, added to `m`. Events at the same position form a group; an
/// arc after exits is in, after entries out, and between mixed groups the
/// probes decide.
fn add_arcs(
    conv: &[P2],
    o: P2,
    events: &[Event],
    locate: &mut dyn FnMut(P2) -> Where,
    m: &mut Moments,
) {
    let n = conv.len();
    let mut groups: smallvec::SmallVec<[(usize, usize); 8]> = smallvec::SmallVec::new();
    let mut s = 0;
    for i in 1..=events.len() {
        if i == events.len() || events[i].pos != events[s].pos {
            groups.push((s, i));
            s = i;
        }
    }
    // all entries (true), all exits (false), or mixed
    let kind = |g: (usize, usize)| -> Option<bool> {
        let es = &events[g.0..g.1];
        if es.iter().all(|e| !e.entry) {
            Some(false)
        } else if es.iter().all(|e| e.entry) {
            Some(true)
        } else {
            None
        }
    };
    let ng = groups.len();
    for gi in 0..ng {
        let (g, h) = (groups[gi], groups[(gi + 1) % ng]);
        let (a, mut b) = (events[g.0].pos, events[h.0].pos);
        if b <= a {
            b += n as f64;
        }
        // status of the arc from a to b (true: in the area)
        let inside = match (kind(g), kind(h)) {
            // after exits: in; after entries: out
            (Some(entries), _) => !entries,
            // before entries: in; before exits: out
            (None, Some(entries)) => entries,
            (None, None) => probe_arc(conv, a, b, locate),
        };
        if !inside {
            continue;
        }
        let start = events[g.0..g.1]
            .iter()
            .find(|e| !e.entry)
            .map_or(events[g.0].p, |e| e.p);
        let end = events[h.0..h.1]
            .iter()
            .find(|e| e.entry)
            .map_or(events[h.0].p, |e| e.p);
        let mut prev = start;
        let mut k = a.floor() + 1.0;
        while k < b {
            let v = conv[(k as usize) % n];
            m.edge(o, prev, v);
            prev = v;
            k += 1.0;
        }
        m.edge(o, prev, end);
    }
}

/// Whether the arc of conv's perimeter from `a` to `b` is in the area:
/// the first of its middle and quarter points not on the area's boundary
/// decides (out when all are on it).
fn probe_arc(conv: &[P2], a: f64, b: f64, locate: &mut dyn FnMut(P2) -> Where) -> bool {
    for f in [0.5, 0.25, 0.75] {
        match locate(point_at(conv, a + f * (b - a))) {
            Where::Inside => return true,
            Where::Outside => return false,
            Where::Boundary => continue,
        }
    }
    false
}

/// The polygon `conv` cut to where `h >= 0` (Sutherland-Hodgman against
/// one half-plane; h linear). A non-convex polygon may come out with
/// zero-width bridges along the line, which add no area.
pub(crate) fn clip_convex(conv: &[P2], h: &dyn Fn(P2) -> f64) -> Vec<P2> {
    let n = conv.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..n {
        let (p, q) = (conv[i], conv[(i + 1) % n]);
        let (hp, hq) = (h(p), h(q));
        if hp >= 0.0 {
            out.push(p);
        }
        if (hp >= 0.0) != (hq >= 0.0) {
            out.push(crossing(p, q, hp, hq));
        }
    }
    out.dedup();
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

#[inline]
fn crossing(p: P2, q: P2, hp: f64, hq: f64) -> P2 {
    let t = hp / (hp - hq);
    [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
}

/// The chains cut to where `h >= 0`: a chain leaving the half-plane exits
/// there, one coming back enters.
pub(crate) fn clip_chains(chains: &[Chain], h: &dyn Fn(P2) -> f64) -> Vec<Chain> {
    let mut out = Vec::new();
    for ch in chains {
        let mut pts = ch.pts.clone();
        let (mut enters, mut exits) = (ch.enters, ch.exits);
        if !ch.enters && !ch.exits {
            // a closed ring: start it outside the half-plane, if it goes there
            if let Some(j) = pts.iter().position(|&p| h(p) < 0.0) {
                if pts.first() == pts.last() {
                    pts.pop();
                }
                pts.rotate_left(j);
                let f = pts[0];
                pts.push(f);
                enters = true;
                exits = true;
            } else {
                out.push(ch.clone());
                continue;
            }
        }
        let mut cur: Option<Chain> = None;
        for i in 0..pts.len() {
            let p = pts[i];
            let hp = h(p);
            if i == 0 {
                if hp >= 0.0 {
                    cur = Some(Chain {
                        pts: smallvec::smallvec![p],
                        enters,
                        exits: false,
                    });
                }
                continue;
            }
            let q = pts[i - 1];
            let hq = h(q);
            match (hq >= 0.0, hp >= 0.0) {
                (true, true) => {
                    if let Some(c) = cur.as_mut() {
                        c.pts.push(p);
                    }
                }
                (true, false) => {
                    if let Some(mut c) = cur.take() {
                        c.pts.push(crossing(q, p, hq, hp));
                        c.exits = true;
                        out.push(c);
                    }
                }
                (false, true) => {
                    let x = crossing(q, p, hq, hp);
                    let mut v: ChainPoints = smallvec::smallvec![x];
                    if x != p {
                        v.push(p);
                    }
                    cur = Some(Chain {
                        pts: v,
                        enters: true,
                        exits: false,
                    });
                }
                (false, false) => {}
            }
        }
        if let Some(mut c) = cur {
            c.exits = exits;
            out.push(c);
        }
    }
    out.retain(|c| c.pts.len() >= 2);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polygon::Area;

    fn tri() -> [P2; 3] {
        [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]
    }

    /// Pins the second: the ring's edge an ulp above the apex of a long
    /// thin triangle passes through it in a piece some 3e-8 long at the
    /// apex, whose entry and exit the perimeter positions ordered the wrong
    /// way round; with the piece the coverage was 0 instead of 0.0011.
    #[test]
    fn a_piece_at_a_corner_does_not_swap_the_arcs() {
        let t = [
            [742504.219465799, 4036871.162225269],
            [741671.719465799, 4036826.162225269],
            [742594.219465799, 4036871.162225269],
        ];
        let y = 4036826.16222527;
        let area = Area::new(vec![vec![vec![
            [741641.719465799, y],
            [741701.012207414, y],
            [741701.012207414, 4036901.162225269],
            [741641.719465799, 4036901.162225269],
        ]]]);
        let chains = vec![
            Chain {
                pts: smallvec::smallvec![
                    [741701.012207414, 4036827.591139494],
                    [741701.012207414, 4036827.7456167075],
                ],
                enters: true,
                exits: true,
            },
            Chain {
                pts: smallvec::smallvec![[741671.7194658249, y], [741671.7194658277, y]],
                enters: true,
                exits: true,
            },
        ];
        let m = clipped_moments(&t, t[0], &chains, &mut |p| area.locate(p));
        // the part of the triangle west of x = 741701.012207414: the wedge
        // at the apex between its two sides' slopes
        let dx = 741701.012207414 - t[1][0];
        let slope = |c: P2| (c[1] - t[1][1]) / (c[0] - t[1][0]);
        let want = 0.5 * dx * dx * (slope(t[0]) - slope(t[2]));
        assert!((m.a - want).abs() <= 1e-6 * want, "{} vs {}", m.a, want);
    }

    /// Pins the first pg_regress `area` failure of the 0.10.0 default
    /// domain: a contour polygon's edge one ulp above a staircase corner of
    /// the domain crosses that corner's thin wedge where no crossing point
    /// is representable, so the walk gives the triangle no chain; the
    /// corner alone (first probe) said "outside" and the triangle's
    /// coverage was 0 instead of 1.
    #[test]
    fn a_ring_an_ulp_past_a_corner_does_not_flip_the_triangle() {
        let v = [760189.219465799, 4037366.162225269];
        let t = [
            v,
            [760234.219465799, 4037951.162225269],
            [760234.219465799, 4038041.162225269],
        ];
        let y = 4037366.16222527_f64;
        assert!(y > v[1]);
        let area = Area::new(vec![vec![vec![
            [760139.219465799, y],
            [760284.219465799, y],
            [760284.219465799, 4038091.162225269],
            [760139.219465799, 4038091.162225269],
        ]]]);
        assert_eq!(area.locate(v), Where::Outside);
        let m = clipped_moments(&t, t[0], &[], &mut |p| area.locate(p));
        let full = Moments::of_polygon(t[0], &t).a;
        assert!((m.a - full).abs() <= 1e-9 * full, "{} vs {}", m.a, full);
    }

    #[test]
    fn hole_inside_the_triangle() {
        let hole = vec![[1.0, 1.0], [1.0, 2.0], [2.0, 1.0], [1.0, 1.0]];
        let area = Area::new(vec![vec![
            vec![
                [-9.0, -9.0],
                [9.0, -9.0],
                [9.0, 9.0],
                [-9.0, 9.0],
                [-9.0, -9.0],
            ],
            hole,
        ]]);
        let chains = vec![Chain {
            pts: area.rings[1].iter().copied().collect(),
            enters: false,
            exits: false,
        }];
        let m = clipped_moments(&tri(), [0.0, 0.0], &chains, &mut |p| area.locate(p));
        assert!((m.a - 7.5).abs() < 1e-12, "{}", m.a);
    }

    #[test]
    fn island_touching_an_edge() {
        // an island inside the triangle touching its bottom edge at (1, 0)
        let ring = vec![[1.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        let area = Area::new(vec![vec![ring.clone()]]);
        let chains = vec![Chain {
            pts: area.rings[0].iter().copied().collect(),
            enters: true,
            exits: true,
        }];
        let m = clipped_moments(&tri(), [0.0, 0.0], &chains, &mut |p| area.locate(p));
        assert!((m.a - 0.5).abs() < 1e-12, "{}", m.a);
    }

    #[test]
    fn half_plane_split() {
        let t = tri();
        let h = |p: P2| p[0] - 1.0;
        let c = clip_convex(&t, &h);
        let m = Moments::of_polygon([0.0, 0.0], &c);
        assert!((m.a - 4.5).abs() < 1e-12);
        let chains = vec![Chain {
            pts: smallvec::smallvec![[0.5, 0.0], [0.5, 1.0], [3.0, 1.0]],
            enters: true,
            exits: true,
        }];
        let cut = clip_chains(&chains, &h);
        assert_eq!(cut.len(), 1);
        assert_eq!(cut[0].pts.as_slice(), &[[1.0, 1.0], [3.0, 1.0]]);
        assert!(cut[0].enters && cut[0].exits);
    }
}
