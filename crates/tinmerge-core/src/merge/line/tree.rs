//! The multi-scale line tree (seed 6.4, after Jones & Abraham 1986) and the
//! line merge through it.
//!
//! Each part (LINESTRING) of a line gets a tree of generalisations: the root
//! is the segment joining the part's ends; the children of a node are the
//! segments of its stretch generalised (Douglas-Peucker) to a quarter of the
//! node's error, down to stretches of at most [`BUCKET`] original segments,
//! which are walked directly (error 0 at the leaves). Every node stores its
//! own error bound `e`: every original vertex it stands for lies within `e`
//! of its segment, so the stretch of line lies in the capsule of radius `e`
//! around the segment (convex: it holds the line between those vertices).
//!
//! The merge descends the tree only where a capsule is not strictly inside
//! the triangle the walk is in; a stretch whose capsule is inside is handed
//! over whole, without looking at its vertices (or, for the triangles only,
//! without touching them at all). Only the stretches near triangle edges
//! are walked segment by segment, with the same exact walker as the plain
//! merge, so the results are identical to it.
//!
//! The tree is stored flat (see [`encode`]) and read in place through
//! [`View`], which checks every value it reads: a stored tree is not
//! decoded, so a merge costs what it visits, not the size of the line.

use super::widened::{walk_near, Near, Visited};
use super::{Polyline, Sink, Walker};
use crate::geom::co;
use crate::geom::point_segment_distance as seg_dist;
use crate::geom::P2;
use crate::interrupt::Interrupt;
use crate::tin::{Tin, TinError};
use robust::{orient2d, Coord};

/// Longest stretch (in original segments) a node may have without children.
pub const BUCKET: usize = 32;
/// Each level of children is generalised to this fraction of the parent's error.
pub const RATIO: f64 = 0.25;

const MAGIC: &[u8; 8] = b"TMLTREE1";
const VERSION: u32 = 1;
pub const HEADER_LEN: usize = 64;
const PART_LEN: usize = 16;
const NODE_LEN: usize = 24;

/// Errors of line-tree values.
fn bad(msg: impl Into<String>) -> TinError {
    TinError::CorruptLineTree(msg.into())
}

/// A node: the segment from vertex `first` to vertex `last` of its part
/// (indices within the part) standing for the vertices between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub first: u32,
    pub last: u32,
    /// Children are nodes `child_first..child_first + child_count`; none:
    /// the node's original segments are walked directly.
    pub child_first: u32,
    pub child_count: u32,
    /// Every original vertex of the stretch is within `err` of the segment.
    pub err: f64,
}

/// Largest distance of the vertices strictly between i and j from segment
/// i-j, and where it is.
fn farthest(pts: &[P2], i: usize, j: usize) -> (f64, usize) {
    let mut best = (0.0, i);
    for (k, p) in pts.iter().enumerate().take(j).skip(i + 1) {
        let d = seg_dist(*p, pts[i], pts[j]);
        if d > best.0 {
            best = (d, k);
        }
    }
    best
}

/// The stored error bound: the measured one grown by a little more than
/// its rounding error (a bound must never be too small).
fn grow(e: f64, pts: &[P2], i: usize, j: usize) -> f64 {
    let mag = pts[i][0]
        .abs()
        .max(pts[i][1].abs())
        .max(pts[j][0].abs())
        .max(pts[j][1].abs());
    if e == 0.0 && j == i + 1 {
        0.0
    } else {
        e * (1.0 + 1e-12) + 1e-12 * mag
    }
}

/// Split i..j at farthest vertices until every piece is within `tol`.
fn generalise(pts: &[P2], i: usize, j: usize, tol: f64, out: &mut Vec<usize>) {
    let mut stack = vec![(i, j)];
    let mut cuts = vec![i, j];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (d, k) = farthest(pts, a, b);
        if d > tol {
            cuts.push(k);
            stack.push((a, k));
            stack.push((k, b));
        }
    }
    cuts.sort_unstable();
    out.extend(cuts);
}

/// Nodes of one part's tree in breadth-first order (root first; node
/// indices relative to the part's first node).
fn build_part(pts: &[P2]) -> Vec<Node> {
    let n = pts.len();
    let last = n.saturating_sub(1);
    let root_err = grow(farthest(pts, 0, last).0, pts, 0, last);
    let mut nodes = vec![Node {
        first: 0,
        last: last as u32,
        child_first: 0,
        child_count: 0,
        err: root_err,
    }];
    let mut i = 0;
    let mut cuts = Vec::new();
    while i < nodes.len() {
        let nd = nodes[i];
        let (a, b) = (nd.first as usize, nd.last as usize);
        if b - a > BUCKET && nd.err > 0.0 {
            cuts.clear();
            generalise(pts, a, b, nd.err * RATIO, &mut cuts);
            let start = nodes.len() as u32;
            for w in cuts.windows(2) {
                let (f, l) = (w[0], w[1]);
                nodes.push(Node {
                    first: f as u32,
                    last: l as u32,
                    child_first: 0,
                    child_count: 0,
                    err: grow(farthest(pts, f, l).0, pts, f, l),
                });
            }
            nodes[i].child_first = start;
            nodes[i].child_count = nodes.len() as u32 - start;
        }
        i += 1;
    }
    nodes
}

/// Build the tree of a line (one entry per part) and store it flat.
///
/// Layout, little-endian: a 64-byte header (magic `TMLTREE1`, version,
/// SRID, part, point and node counts, total planar length, xxh3 hash of
/// everything but the hash itself), then per part (first point, point
/// count, root node), the points (x, y), the planar distance of each point
/// from the start of its part, and the nodes (first, last, first child,
/// child count, error; `first`/`last` within the part, children as global
/// node indices, always after their parent).
pub fn encode(srid: i32, parts: &[Vec<P2>]) -> Result<Vec<u8>, TinError> {
    let np: usize = parts.iter().map(|p| p.len()).sum();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(TinError::InvalidParameter("linetree: an empty part".into()));
    }
    for p in parts.iter().flatten() {
        crate::tin::check_xy("linetree: the line", p[0], p[1])?;
    }
    if np > u32::MAX as usize / 2 {
        return Err(TinError::TooLarge("linetree: too many points".into()));
    }
    let trees: Vec<Vec<Node>> = parts.iter().map(|p| build_part(p)).collect();
    let nn: usize = trees.iter().map(|t| t.len()).sum();
    let mut out = Vec::with_capacity(HEADER_LEN + parts.len() * PART_LEN + np * 24 + nn * NODE_LEN);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&srid.to_le_bytes());
    out.extend_from_slice(&(parts.len() as u32).to_le_bytes());
    out.extend_from_slice(&(np as u32).to_le_bytes());
    out.extend_from_slice(&(nn as u32).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    let mut total = 0.0;
    let mut cums: Vec<Vec<f64>> = Vec::new();
    for p in parts {
        let part = super::Part::new(p.clone());
        total += part.length();
        cums.push(part.cum);
    }
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&0u64.to_le_bytes()); // hash, filled below
    out.extend_from_slice(&[0u8; 16]);
    let (mut pfirst, mut nfirst) = (0u32, 0u32);
    for (p, t) in parts.iter().zip(&trees) {
        out.extend_from_slice(&pfirst.to_le_bytes());
        out.extend_from_slice(&(p.len() as u32).to_le_bytes());
        out.extend_from_slice(&nfirst.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        pfirst += p.len() as u32;
        nfirst += t.len() as u32;
    }
    for p in parts.iter().flatten() {
        out.extend_from_slice(&p[0].to_le_bytes());
        out.extend_from_slice(&p[1].to_le_bytes());
    }
    for c in cums.iter().flatten() {
        out.extend_from_slice(&c.to_le_bytes());
    }
    let mut base = 0u32;
    for t in &trees {
        for nd in t {
            out.extend_from_slice(&nd.first.to_le_bytes());
            out.extend_from_slice(&nd.last.to_le_bytes());
            let cf = if nd.child_count > 0 {
                nd.child_first + base
            } else {
                0
            };
            out.extend_from_slice(&cf.to_le_bytes());
            out.extend_from_slice(&nd.child_count.to_le_bytes());
            out.extend_from_slice(&nd.err.to_le_bytes());
        }
        base += t.len() as u32;
    }
    let h = hash(&out);
    out[40..48].copy_from_slice(&h.to_le_bytes());
    Ok(out)
}

/// Recompute the stored hash (for tests that craft values).
#[cfg(feature = "bench")]
pub fn rehash(b: &mut [u8]) {
    if b.len() >= HEADER_LEN {
        let h = hash(b);
        b[40..48].copy_from_slice(&h.to_le_bytes());
    }
}

fn hash(b: &[u8]) -> u64 {
    let mut h = xxhash_rust::xxh3::Xxh3::new();
    h.update(&b[..40]);
    h.update(&b[48..]);
    h.digest()
}

/// Header fields of a stored tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Header {
    pub srid: i32,
    pub num_parts: u32,
    pub num_points: u32,
    pub num_nodes: u32,
    pub length: f64,
}

/// A stored tree read in place. [`View::new`] checks the header, the size
/// and the hash; every accessor checks what it reads.
pub struct View<'a> {
    b: &'a [u8],
    pub header: Header,
    parts_at: usize,
    points_at: usize,
    cum_at: usize,
    nodes_at: usize,
}

#[inline]
fn u32_at(b: &[u8], at: usize) -> Result<u32, TinError> {
    b.get(at..at + 4)
        .and_then(|s| s.try_into().ok())
        .map(u32::from_le_bytes)
        .ok_or_else(|| bad("truncated"))
}

#[inline]
fn f64_at(b: &[u8], at: usize) -> Result<f64, TinError> {
    b.get(at..at + 8)
        .and_then(|s| s.try_into().ok())
        .map(f64::from_le_bytes)
        .ok_or_else(|| bad("truncated"))
}

impl<'a> View<'a> {
    pub fn new(b: &'a [u8]) -> Result<View<'a>, TinError> {
        if b.len() < HEADER_LEN || &b[..8] != MAGIC {
            return Err(bad("not a linetree value (bad magic or too short)"));
        }
        if u32_at(b, 8)? != VERSION {
            return Err(bad(format!("unsupported version {}", u32_at(b, 8)?)));
        }
        let header = Header {
            srid: u32_at(b, 12)? as i32,
            num_parts: u32_at(b, 16)?,
            num_points: u32_at(b, 20)?,
            num_nodes: u32_at(b, 24)?,
            length: f64_at(b, 32)?,
        };
        let (p, n, m) = (
            header.num_parts as u64,
            header.num_points as u64,
            header.num_nodes as u64,
        );
        let want = HEADER_LEN as u64 + p * PART_LEN as u64 + n * 24 + m * NODE_LEN as u64;
        if want != b.len() as u64 {
            return Err(bad(format!(
                "size {} does not match its counts ({want})",
                b.len()
            )));
        }
        if p == 0 || m < p || n < p {
            return Err(bad("counts are inconsistent"));
        }
        let stored = u64::from_le_bytes(b[40..48].try_into().map_err(|_| bad("truncated"))?);
        if stored != hash(b) {
            return Err(bad("hash mismatch: the value is damaged"));
        }
        let parts_at = HEADER_LEN;
        let points_at = parts_at + p as usize * PART_LEN;
        let cum_at = points_at + n as usize * 16;
        let nodes_at = cum_at + n as usize * 8;
        Ok(View {
            b,
            header,
            parts_at,
            points_at,
            cum_at,
            nodes_at,
        })
    }

    /// Part `i` as (first point, point count, root node).
    pub fn part(&self, i: u32) -> Result<(u32, u32, u32), TinError> {
        if i >= self.header.num_parts {
            return Err(bad("part index out of range"));
        }
        let at = self.parts_at + i as usize * PART_LEN;
        let (f, n, r) = (
            u32_at(self.b, at)?,
            u32_at(self.b, at + 4)?,
            u32_at(self.b, at + 8)?,
        );
        if n == 0
            || f as u64 + n as u64 > self.header.num_points as u64
            || r >= self.header.num_nodes
        {
            return Err(bad(format!("part {i} is out of range")));
        }
        Ok((f, n, r))
    }

    pub fn point(&self, i: u32) -> Result<P2, TinError> {
        if i >= self.header.num_points {
            return Err(bad("point index out of range"));
        }
        let at = self.points_at + i as usize * 16;
        let p = [f64_at(self.b, at)?, f64_at(self.b, at + 8)?];
        if crate::tin::check_xy("", p[0], p[1]).is_err() {
            return Err(bad("non-finite or out-of-range coordinate"));
        }
        Ok(p)
    }

    pub fn cum(&self, i: u32) -> Result<f64, TinError> {
        if i >= self.header.num_points {
            return Err(bad("point index out of range"));
        }
        let c = f64_at(self.b, self.cum_at + i as usize * 8)?;
        if !(c.is_finite() && c >= 0.0) {
            return Err(bad("bad distance along the line"));
        }
        Ok(c)
    }

    /// Node `i` of a part of `n` points, checked: its stretch inside the
    /// part, its children after it and inside the node array, its error a
    /// finite non-negative number.
    pub fn node(&self, i: u32, n: u32) -> Result<Node, TinError> {
        if i >= self.header.num_nodes {
            return Err(bad("node index out of range"));
        }
        let at = self.nodes_at + i as usize * NODE_LEN;
        let nd = Node {
            first: u32_at(self.b, at)?,
            last: u32_at(self.b, at + 4)?,
            child_first: u32_at(self.b, at + 8)?,
            child_count: u32_at(self.b, at + 12)?,
            err: f64_at(self.b, at + 16)?,
        };
        let ok = nd.first <= nd.last
            && nd.last < n
            && nd.err.is_finite()
            && nd.err >= 0.0
            && (nd.child_count == 0
                || (nd.child_first > i
                    && nd.child_first as u64 + nd.child_count as u64
                        <= self.header.num_nodes as u64));
        if !ok {
            return Err(bad(format!("node {i} is inconsistent")));
        }
        Ok(nd)
    }

    /// Full check (for values arriving as text or binary): every part,
    /// point and node, children tiling their parent, and every error bound
    /// recomputed.
    pub fn validate(&self) -> Result<(), TinError> {
        let mut next_node = 0u32;
        let mut next_point = 0u32;
        for pi in 0..self.header.num_parts {
            let (f, n, root) = self.part(pi)?;
            if f != next_point || root != next_node {
                return Err(bad(format!("part {pi} does not follow the previous one")));
            }
            next_point += n;
            let part = self.part_line(pi)?;
            let pts: Vec<P2> = (0..n as usize)
                .map(|k| part.pt(k))
                .collect::<Result<_, _>>()?;
            let mut prev = 0.0;
            for k in 0..n as usize {
                let c = part.cum(k)?;
                if k == 0 && c != 0.0 || c < prev {
                    return Err(bad("distances along the line are not increasing from 0"));
                }
                prev = c;
            }
            // walk the tree: every node once, in order
            let mut stack = vec![root];
            let mut count = 0u32;
            while let Some(i) = stack.pop() {
                count += 1;
                if count > self.header.num_nodes {
                    return Err(bad("the tree has a cycle"));
                }
                let nd = self.node(i, n)?;
                if i == root && (nd.first != 0 || nd.last != n - 1) {
                    return Err(bad("the root does not span its part"));
                }
                let (a, b) = (nd.first as usize, nd.last as usize);
                let need = farthest(&pts, a, b).0;
                if nd.err < need {
                    return Err(bad(format!(
                        "node {i}: error bound {} below {need}",
                        nd.err
                    )));
                }
                if nd.child_count > 0 {
                    let mut at = nd.first;
                    for c in nd.child_first..nd.child_first + nd.child_count {
                        let cn = self.node(c, n)?;
                        if cn.first != at || cn.last <= cn.first {
                            return Err(bad(format!("children of node {i} do not tile it")));
                        }
                        at = cn.last;
                        stack.push(c);
                    }
                    if at != nd.last {
                        return Err(bad(format!("children of node {i} do not tile it")));
                    }
                }
            }
            next_node += count;
        }
        if next_point != self.header.num_points || next_node != self.header.num_nodes {
            return Err(bad("parts do not cover the points and nodes"));
        }
        Ok(())
    }

    /// Part `i` as a [`Polyline`].
    pub fn part_line(&self, i: u32) -> Result<PartView<'_, 'a>, TinError> {
        let (first, n, root) = self.part(i)?;
        Ok(PartView {
            v: self,
            first,
            n,
            root,
        })
    }
}

/// One part of a stored tree.
pub struct PartView<'v, 'a> {
    v: &'v View<'a>,
    first: u32,
    n: u32,
    root: u32,
}

impl Polyline for PartView<'_, '_> {
    fn len(&self) -> usize {
        self.n as usize
    }
    fn pt(&self, i: usize) -> Result<P2, TinError> {
        if i >= self.n as usize {
            return Err(bad("point index out of range"));
        }
        self.v.point(self.first + i as u32)
    }
    fn cum(&self, i: usize) -> Result<f64, TinError> {
        if i >= self.n as usize {
            return Err(bad("point index out of range"));
        }
        self.v.cum(self.first + i as u32)
    }
}

/// Whether the capsule of radius `r` around segment pq lies strictly
/// inside triangle `t` (conservative: a margin covers rounding).
fn capsule_inside(tin: &Tin, level: usize, t: u32, p: P2, q: P2, r: f64) -> bool {
    let c = tin.corners(level, t);
    let mag = p[0].abs().max(p[1].abs()).max(q[0].abs()).max(q[1].abs());
    (0..3).all(|j| {
        let (a, b) = (c[(j + 1) % 3], c[(j + 2) % 3]);
        let (ca, cb) = (Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] });
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let need = r * len * (1.0 + 1e-9) + 1e-9 * len * len + 1e-12 * mag * len;
        let (op, oq) = (orient2d(ca, cb, co(p)), orient2d(ca, cb, co(q)));
        op > 0.0 && oq > 0.0 && op > need && oq > need
    })
}

/// What the descent does besides walking: the plain cut, or the widened
/// line.
trait Visit<S: Sink> {
    /// Added to every node's error for the containment test.
    fn radius(&self) -> f64 {
        0.0
    }
    /// The stretch from vertex `first` lies strictly inside triangle `t`.
    fn inside(&mut self, _t: u32, _first: usize) {}
    /// Whether the stretch p..q (error `e`), which starts in `t`, may be
    /// passed over without walking it.
    fn pass_over(&mut self, _t: u32, _p: P2, _q: P2, _e: f64) -> bool {
        false
    }
    /// Walk original segment `k`.
    fn leaf(&mut self, w: &mut Walker<'_, S>, part: &PartView, k: usize) -> Result<(), TinError>;
}

/// The plain cut: every sink.
struct Cut;

impl<S: Sink> Visit<S> for Cut {
    fn leaf(&mut self, w: &mut Walker<'_, S>, part: &PartView, k: usize) -> Result<(), TinError> {
        w.segment(part, k)
    }
}

/// The widened line: triangles within `r`, recorded in `near`; a segment's
/// key is `base` plus its index in the part.
struct Widen<'n, 't> {
    near: &'n mut Near<'t>,
    base: u64,
    r: f64,
}

impl Visit<Visited> for Widen<'_, '_> {
    fn radius(&self) -> f64 {
        self.r
    }
    fn inside(&mut self, t: u32, first: usize) {
        self.near.touch(t, self.base + first as u64);
    }
    fn pass_over(&mut self, t: u32, p: P2, q: P2, e: f64) -> bool {
        // every triangle the stretch could come near (within e + r of its
        // segment) is already found: it adds nothing
        self.near.all_found_near(t, p, q, e + self.r, 64)
    }
    fn leaf(
        &mut self,
        w: &mut Walker<'_, Visited>,
        part: &PartView,
        k: usize,
    ) -> Result<(), TinError> {
        walk_near(self.near, w, part, k, self.base + k as u64)
    }
}

fn descend<S: Sink, V: Visit<S>>(
    tin: &Tin,
    level: usize,
    part: &PartView,
    w: &mut Walker<'_, S>,
    (index, nd): (u32, Node),
    visit: &mut V,
    depth: usize,
) -> Result<(), TinError> {
    if depth > 64 {
        return Err(bad("the tree is too deep"));
    }
    let (f, l) = (nd.first as usize, nd.last as usize);
    if let Some(t) = w.current() {
        let (p, q) = (part.pt(f)?, part.pt(l)?);
        if capsule_inside(tin, level, t, p, q, nd.err + visit.radius()) {
            visit.inside(t, f);
            return w.run_inside(part, f, l);
        }
        if l > f + 1 && visit.pass_over(t, p, q, nd.err) {
            w.jump_to(q);
            return Ok(());
        }
    }
    if nd.child_count > 0 {
        let mut at = nd.first;
        for c in nd.child_first..nd.child_first + nd.child_count {
            let cn = part.v.node(c, part.n)?;
            if cn.first != at || cn.last <= cn.first || cn.last > nd.last {
                return Err(bad(format!("children of node {index} do not tile it")));
            }
            at = cn.last;
            descend(tin, level, part, w, (c, cn), visit, depth + 1)?;
        }
        if at != nd.last {
            return Err(bad(format!("children of node {index} do not tile it")));
        }
        return Ok(());
    }
    for k in f..l {
        visit.leaf(w, part, k)?;
    }
    Ok(())
}

impl PartView<'_, '_> {
    /// The root node, with its index.
    fn root(&self) -> Result<(u32, Node), TinError> {
        Ok((self.root, self.v.node(self.root, self.n)?))
    }
}

/// The line merge through a stored tree: the same reports to `sink` as
/// [`super::walk_parts`] on the same line.
pub fn walk_tree<S: Sink>(
    tin: &Tin,
    level: usize,
    tree: &View,
    sink: &mut S,
    on_part: &mut dyn FnMut(&mut S, usize),
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    for pi in 0..tree.header.num_parts {
        on_part(sink, pi as usize);
        interrupt()?;
        let part = tree.part_line(pi)?;
        let mut w = Walker::new(tin, level, sink, interrupt);
        let p0 = part.pt(0)?;
        w.start_part(p0);
        let root = part.root()?;
        descend(tin, level, &part, &mut w, root, &mut Cut, 0)?;
        w.end_part(p0, moves(&part, root.1)?);
    }
    Ok(())
}

/// Whether a part has two distinct points (its root segment has length or
/// its error is positive).
fn moves(part: &PartView, root: Node) -> Result<bool, TinError> {
    Ok(part.pt(root.first as usize)? != part.pt(root.last as usize)? || root.err > 0.0)
}

/// Widened line through a stored tree: the same triangles, in the same
/// order, as [`super::widened::near_line`].
pub fn near_tree(
    tin: &Tin,
    level: usize,
    tree: &View,
    half_width: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    let mut near = Near::new(tin, level, half_width);
    let mut base: u64 = 0;
    for pi in 0..tree.header.num_parts {
        let part = tree.part_line(pi)?;
        let mut vis = Visited::default();
        let mut w = Walker::new(tin, level, &mut vis, interrupt);
        w.interrupt_now()?;
        let p0 = part.pt(0)?;
        w.start_part(p0);
        let start = w.current();
        let root = part.root()?;
        let mut visit = Widen {
            near: &mut near,
            base,
            r: half_width,
        };
        descend(tin, level, &part, &mut w, root, &mut visit, 0)?;
        if !moves(&part, root.1)? {
            near.still_part(base, p0, start, &mut || w.interrupt_now())?;
        }
        base += part.len() as u64;
    }
    Ok(near.ordered())
}
