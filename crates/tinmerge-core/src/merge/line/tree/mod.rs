//! The multi-scale line tree (Scarlatos §6.4, after Jones & Abraham 1986) and the
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
//!
//! Files: this module builds and encodes trees; [`view`] reads a stored
//! tree in place; [`walk`] is the merge through it.

mod view;
mod walk;

pub use view::{Header, PartView, View};
pub use walk::{near_tree, walk_tree};

use crate::geom::P2;
use crate::geom::point_segment_distance as seg_dist;
use crate::tin::TinError;

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
