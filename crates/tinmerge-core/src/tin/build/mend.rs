//! Slivers dropped between parents, mended after a level is refined
//! ([`mend_sliver_holes`]).
//!
//! A parent's refinement drops its children that are slivers (zero area up
//! to rounding: [`crate::geom::is_sliver`]); the vertex of such a sliver
//! lies on its long edge up to rounding, and [`close_chains`] makes the
//! triangle across that edge meet it when the edge is a side of the same
//! parent. At a corner of a needle parent the sliver can be an ear between
//! two of its sides: a vertex chosen on one side a millimetre from the
//! corner lies within rounding of the other side, and the parent across
//! that other side (which never sees the vertex) keeps the long edge
//! whole. The level then has a gap of three edges (harness seed 600387: a
//! raster with a boundary on a 0.81 m projected grid, level 3, a sliver of
//! 6e-8 m² beside a parent 0.28 mm wide at one end). The gap is mended
//! here as within one parent: the triangle across the long edge is split
//! at the sliver's vertex into two, both children of its parent. Only a
//! level where a parent reported such a gap among its own children
//! ([`leaves_gap`]) is searched: searching every level cost 0.5-1 µs a
//! triangle.
//!
//! [`close_chains`]: crate::tin::sides::close_chains

use rustc_hash::FxHashMap;

use super::common::RawLevel;
use crate::tin::NONE;
use crate::tin::hierarchy::compute_neighbours;

/// Whether a parent's children `tris` leave a gap inside it: an edge
/// without its twin among them whose ends are not on one side of the
/// parent (`same_side`). A sliver dropped along a side leaves none
/// ([`close_chains`] makes the triangle across meet its vertex); one
/// dropped at a corner, between vertices of two sides, does, and only
/// then is the level searched ([`mend_sliver_holes`]).
///
/// [`close_chains`]: crate::tin::sides::close_chains
pub(super) fn leaves_gap(tris: &[[u32; 3]], same_side: &dyn Fn(u32, u32) -> bool) -> bool {
    let edges: rustc_hash::FxHashSet<(u32, u32)> = tris
        .iter()
        .flat_map(|t| (0..3).map(move |j| (t[j], t[(j + 1) % 3])))
        .collect();
    edges
        .iter()
        .any(|&(u, v)| !edges.contains(&(v, u)) && !same_side(u, v))
}

/// Mend every gap of `level` (vertices `verts`) that is a sliver of three
/// edges: the triangle whose edge is the sliver's longest is split at the
/// sliver's third vertex. A gap that is not a sliver, or whose split would
/// make a sliver or a triangle turned over (or a level whose edges do not
/// match, [`compute_neighbours`]), is left for the build's own check to
/// refuse.
pub(super) fn mend_sliver_holes(verts: &[[f64; 3]], level: &mut RawLevel) {
    let Ok(nbrs) = compute_neighbours(&level.tris) else {
        return;
    };
    // the edges without a neighbour (triangle t's edge opposite corner j),
    // by their start (NONE: two start there)
    let mut next: FxHashMap<u32, (u32, u32, u8)> = FxHashMap::default();
    for (t, (tri, nb)) in level.tris.iter().zip(&nbrs).enumerate() {
        for j in 0..3 {
            if nb[j] == NONE {
                next.entry(tri[(j + 1) % 3])
                    .and_modify(|e| e.0 = NONE)
                    .or_insert((tri[(j + 2) % 3], t as u32, j as u8));
            }
        }
    }
    drop(nbrs);
    let mut splits: Vec<(u32, u8, u32)> = Vec::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    for a in starts {
        let Some(&(b, ta, ja)) = next.get(&a) else {
            continue;
        };
        let Some(&(c, tb, jb)) = next.get(&b) else {
            continue;
        };
        let Some(&(d, tc, jc)) = next.get(&c) else {
            continue;
        };
        // a cycle of three, each once (from its smallest vertex)
        if d != a || b == NONE || c == NONE || a > b || a > c {
            continue;
        }
        let p = [a, b, c].map(|v| verts[v as usize]);
        if !crate::geom::is_sliver(&p[0], &p[1], &p[2]) {
            continue;
        }
        // the longest of the gap's edges: k from p[k] to p[k + 1]
        let len = |k: usize| {
            let (u, w) = (&p[k], &p[(k + 1) % 3]);
            (u[0] - w[0]).hypot(u[1] - w[1])
        };
        let k = (0..3)
            .max_by(|&x, &y| len(x).total_cmp(&len(y)))
            .unwrap_or(0);
        let (t, j) = [(ta, ja), (tb, jb), (tc, jc)][k];
        splits.push((t, j, [a, b, c][(k + 2) % 3]));
    }
    let mut split = vec![false; level.tris.len()];
    for (t, j, v) in splits {
        if std::mem::replace(&mut split[t as usize], true) {
            continue;
        }
        // the edge u -> w opposite corner x
        let tri = level.tris[t as usize];
        let (x, u, w) = (
            tri[j as usize],
            tri[(j as usize + 1) % 3],
            tri[(j as usize + 2) % 3],
        );
        let (first, second) = ([u, v, x], [v, w, x]);
        let good = |f: &[u32; 3]| {
            let q = f.map(|i| verts[i as usize]);
            crate::geom::orient(&q[0], &q[1], &q[2]) > 0.0
                && !crate::geom::is_sliver(&q[0], &q[1], &q[2])
        };
        if !good(&first) || !good(&second) {
            continue;
        }
        level.tris[t as usize] = first;
        level.tris.push(second);
        if let Some(&p) = level.parents.get(t as usize) {
            level.parents.push(p);
        }
        if let Some(&void) = level.void.get(t as usize) {
            level.void.push(void);
        }
    }
}
