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
    // around each vertex a, each incident triangle once: the corner at a
    // and the vertices after and before it. The edge a -> b of one is
    // matched with the other triangle around a that has b (each triangle
    // read once a corner, not once an edge and candidate)
    let mut local: Vec<(u32, usize, u32, u32)> = Vec::new();
    for a in 0..nv {
        local.clear();
        let mut repeated = false;
        for &t in &inc[start[a] as usize..start[a + 1] as usize] {
            if local.last().is_some_and(|e| e.0 == t) {
                repeated = true;
                continue;
            }
            let tri = tris[t as usize];
            if let Some(i) = tri.iter().position(|&v| v as usize == a) {
                local.push((t, i, tri[(i + 1) % 3], tri[(i + 2) % 3]));
            }
        }
        // a triangle with a twice has an edge a - a, which every other
        // triangle around a has an end of
        if repeated && local.len() > 1 {
            return Err(shared(a as u32, a as u32, local.len()));
        }
        for &(t, i, b, _) in &local {
            let has_b = |e: &&(u32, usize, u32, u32)| e.0 != t && (e.2 == b || e.3 == b);
            let mut others = local.iter().filter(has_b);
            if let Some(&(u, ..)) = others.next() {
                let more = 1 + others.count();
                if more > 1 {
                    return Err(shared(a as u32, b, more + 1));
                }
                // the edge a -> b is opposite the corner after b
                nbrs[t as usize][(i + 2) % 3] = u;
            }
        }
    }
    Ok(nbrs)
}

fn shared(a: u32, b: u32, n: usize) -> TinError {
    TinError::Corrupt(format!(
        "edge {}-{} is shared by {n} triangles",
        a.min(b),
        a.max(b)
    ))
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

#[cfg(test)]
mod tests {
    use super::{NONE, compute_neighbours};
    use spade::{DelaunayTriangulation, Point2, Triangulation};

    /// The neighbours of a triangle list by brute force: every pair of
    /// triangles with two corners in common.
    fn brute(tris: &[[u32; 3]]) -> Vec<[u32; 3]> {
        let mut out = vec![[NONE; 3]; tris.len()];
        for (t, a) in tris.iter().enumerate() {
            for j in 0..3 {
                let (p, q) = (a[(j + 1) % 3], a[(j + 2) % 3]);
                for (u, b) in tris.iter().enumerate() {
                    if u != t && b.contains(&p) && b.contains(&q) {
                        out[t][j] = u as u32;
                    }
                }
            }
        }
        out
    }

    /// Random Delaunay triangulations (spade), their triangles shuffled
    /// and their corners turned: the links are the brute force's; a
    /// triangle given twice, or with a corner twice, is an error.
    #[test]
    fn neighbours_are_the_brute_forces() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = |n: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s % n
        };
        for trial in 0..60 {
            let n = 3 + rnd(150) as usize;
            let mut dt: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
            for _ in 0..n {
                // lattice points: many cocircular, so many equal choices
                let p = Point2::new(rnd(20) as f64, rnd(20) as f64);
                dt.insert(p).expect("insert");
            }
            let mut tris: Vec<[u32; 3]> = dt
                .inner_faces()
                .map(|f| f.vertices().map(|v| v.fix().index() as u32))
                .collect();
            if tris.is_empty() {
                continue;
            }
            for i in (1..tris.len()).rev() {
                tris.swap(i, rnd(i as u64 + 1) as usize);
            }
            for t in &mut tris {
                t.rotate_left(rnd(3) as usize);
            }
            assert_eq!(
                compute_neighbours(&tris).unwrap(),
                brute(&tris),
                "trial {trial}"
            );
            let mut twice = tris.clone();
            twice.push(tris[rnd(tris.len() as u64) as usize]);
            let e = compute_neighbours(&twice).expect_err("a triangle given twice");
            assert!(e.to_string().contains("is shared by 3 triangles"), "{e}");
            if tris.len() > 1 {
                let mut bent = tris.clone();
                let k = rnd(tris.len() as u64) as usize;
                bent[k][1] = bent[k][0];
                assert!(
                    compute_neighbours(&bent).is_err(),
                    "trial {trial}: a corner twice"
                );
            }
        }
    }
}
