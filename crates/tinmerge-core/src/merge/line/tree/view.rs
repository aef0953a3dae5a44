//! A stored line tree read in place: [`View`] checks the header, the size
//! and the hash once, then every accessor checks what it reads.

use super::{HEADER_LEN, MAGIC, NODE_LEN, Node, PART_LEN, VERSION, bad, farthest, hash};
use crate::geom::P2;
use crate::merge::line::Polyline;
use crate::tin::TinError;

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
    pub(super) v: &'v View<'a>,
    first: u32,
    pub(super) n: u32,
    pub(super) root: u32,
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
