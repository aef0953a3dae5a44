//! The links between triangles and levels, derived from the triangle and
//! parent arrays: neighbours across edges, the contiguous range of a
//! triangle's children at the next level (`Level::child_start`), and its
//! descendants at any finer level. Used by the builder, the decoder and the
//! checker alike (so decoding does not depend on the builder) and by the
//! merges that descend the hierarchy.
//!
//! ```
//! use tinmerge_core::tin::hierarchy::{child_starts, compute_neighbours};
//! use tinmerge_core::tin::NONE;
//! // two triangles sharing the edge 1-2
//! let nbrs = compute_neighbours(&[[0, 1, 2], [2, 1, 3]]).unwrap();
//! assert_eq!(nbrs[0], [1, NONE, NONE]);
//! assert_eq!(nbrs[1], [NONE, NONE, 0]);
//! // children of 2 parents, sorted by parent: 0, 0, 1
//! assert_eq!(child_starts(&[0, 0, 1], 2), vec![0, 2, 3]);
//! ```

use super::mesh::Mesh;
use super::{NONE, TinError};

/// Neighbour links of a triangle list: `nbrs[t][j]` is the triangle across
/// the edge of `t` opposite its corner `j`, or NONE. Edges are matched
/// through each vertex's incident triangles (a CSR list, 12 bytes a
/// triangle and 4 a vertex: a sort of every edge took 48 bytes a triangle,
/// the peak of a build's last step); an edge in more than two triangles is
/// an error.
pub fn compute_neighbours(tris: &[[u32; 3]]) -> Result<Vec<[u32; 3]>, TinError> {
    let nv = tris.iter().flatten().max().map_or(0, |&m| m as usize + 1);
    // start[v]..start[v + 1]: the triangles incident to v, in `inc`
    let mut start = vec![0u32; nv + 1];
    for &v in tris.iter().flatten() {
        start[v as usize + 1] += 1;
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut inc = vec![0u32; start[nv] as usize];
    for (t, tri) in tris.iter().enumerate() {
        for &v in tri {
            inc[start[v as usize] as usize] = t as u32;
            start[v as usize] += 1;
        }
    }
    // each start[v] now holds the old start[v + 1]: shift back
    for v in (1..=nv).rev() {
        start[v] = start[v - 1];
    }
    start[0] = 0;
    let mut nbrs = vec![[NONE; 3]; tris.len()];
    for (t, tri) in tris.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
            let around = &inc[start[a as usize] as usize..start[a as usize + 1] as usize];
            let mut others = around
                .iter()
                .filter(|&&u| u as usize != t && tris[u as usize].contains(&b));
            if let Some(&u) = others.next() {
                let more = 1 + others.count();
                if more > 1 || a == b {
                    return Err(TinError::Corrupt(format!(
                        "edge {}-{} is shared by {} triangles",
                        a.min(b),
                        a.max(b),
                        more + 1
                    )));
                }
                nbrs[t][j] = u;
            }
        }
    }
    Ok(nbrs)
}

/// CSR offsets of children from a parent array sorted ascending.
pub fn child_starts(parent: &[u32], num_parents: usize) -> Vec<u32> {
    let mut cs = vec![0u32; num_parents + 1];
    for &p in parent {
        if (p as usize) < num_parents {
            cs[p as usize + 1] += 1;
        }
    }
    for i in 0..num_parents {
        cs[i + 1] += cs[i];
    }
    cs
}

/// Children of triangle p (level l) at level l + 1.
pub fn children<M: Mesh>(m: &M, l: usize, p: u32) -> Result<std::ops::Range<u32>, TinError>
where
    TinError: From<M::Err>,
{
    Ok(m.children(l, p)?)
}

/// Descendants of triangle t (level l) at level `to`, appended to out.
pub fn descendants<M: Mesh>(
    m: &M,
    l: usize,
    t: u32,
    to: usize,
    out: &mut Vec<u32>,
) -> Result<(), TinError>
where
    TinError: From<M::Err>,
{
    if l == to {
        out.push(t);
        return Ok(());
    }
    for ch in m.children(l, t)? {
        descendants(m, l + 1, ch, to, out)?;
    }
    Ok(())
}
