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
use super::{TinError, NONE};

/// Neighbour links of a triangle list (edge matching by sort).
pub fn compute_neighbours(tris: &[[u32; 3]]) -> Result<Vec<[u32; 3]>, TinError> {
    let mut e: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(tris.len() * 3);
    for (t, tri) in tris.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = (tri[(j + 1) % 3], tri[(j + 2) % 3]);
            e.push((a.min(b), a.max(b), t as u32, j as u8));
        }
    }
    e.sort_unstable();
    let mut nbrs = vec![[NONE; 3]; tris.len()];
    let mut i = 0;
    while i < e.len() {
        let mut k = i + 1;
        while k < e.len() && e[k].0 == e[i].0 && e[k].1 == e[i].1 {
            k += 1;
        }
        match k - i {
            1 => {}
            2 => {
                nbrs[e[i].2 as usize][e[i].3 as usize] = e[i + 1].2;
                nbrs[e[i + 1].2 as usize][e[i + 1].3 as usize] = e[i].2;
            }
            _ => {
                return Err(TinError::Corrupt(format!(
                    "edge {}-{} is shared by {} triangles",
                    e[i].0,
                    e[i].1,
                    k - i
                )))
            }
        }
        i = k;
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
