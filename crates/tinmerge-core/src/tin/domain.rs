//! Where a raster has data, as polygons on its pixel lattice (issue 26):
//! [`cell_outline`] is the union of the valid pixels' own squares, what
//! `ST_Value` answers on; `tin_from_raster(..., fill_gaps => false)` builds
//! over it ([`outline_area`] as the build's boundary), so the terrain
//! stops where the data does, holes included.
//!
//! The rings are corners `(col, row)` of the pixel grid, exact integers.
//! Outer rings have positive area and holes negative area ([`ring_area2`],
//! shoelace in that frame). Where two rings touch at a corner they are kept
//! apart. Collinear corners are dropped: a ring keeps only the corners of
//! the outline.

use crate::polygon::Area;
use rustc_hash::{FxHashMap, FxHashSet};

/// A corner of the pixel grid: `(col, row)`, the top-left corner of pixel
/// `(col, row)`.
pub type LatticePoint = [i64; 2];

/// Twice the signed area of a ring (shoelace, exact).
pub fn ring_area2(r: &[LatticePoint]) -> i64 {
    let mut s = 0i64;
    for i in 0..r.len() {
        let (a, b) = (r[i], r[(i + 1) % r.len()]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    s
}

/// Add the directed edge a -> b of a piece, or cancel it against b -> a of
/// its neighbour (an edge met both ways is inside the union).
fn add_edge(edges: &mut FxHashSet<(LatticePoint, LatticePoint)>, a: LatticePoint, b: LatticePoint) {
    if !edges.remove(&(b, a)) {
        edges.insert((a, b));
    }
}

/// The boundary edges (each once, interior on the left) chained into
/// rings, turning most to the left where two rings touch at a corner.
fn rings_of(edges: &FxHashSet<(LatticePoint, LatticePoint)>) -> Vec<Vec<LatticePoint>> {
    let mut out: FxHashMap<LatticePoint, Vec<LatticePoint>> = FxHashMap::default();
    for &(a, b) in edges {
        out.entry(a).or_default().push(b);
    }
    for v in out.values_mut() {
        v.sort_unstable();
    }
    let mut starts: Vec<(LatticePoint, LatticePoint)> = edges.iter().copied().collect();
    starts.sort_unstable();
    let mut used: FxHashSet<(LatticePoint, LatticePoint)> = FxHashSet::default();
    let mut rings = Vec::new();
    for (a0, b0) in starts {
        if used.contains(&(a0, b0)) {
            continue;
        }
        let mut ring = vec![a0];
        let (mut a, mut b) = (a0, b0);
        loop {
            used.insert((a, b));
            if b == a0 {
                break;
            }
            ring.push(b);
            let din = [b[0] - a[0], b[1] - a[1]];
            let next = out
                .get(&b)
                .into_iter()
                .flatten()
                .copied()
                .filter(|&n| !used.contains(&(b, n)))
                .max_by(|&p, &q| {
                    let turn = |n: LatticePoint| {
                        let d = [n[0] - b[0], n[1] - b[1]];
                        let cross = (din[0] * d[1] - din[1] * d[0]) as f64;
                        let dot = (din[0] * d[0] + din[1] * d[1]) as f64;
                        cross.atan2(dot)
                    };
                    turn(p).total_cmp(&turn(q))
                });
            let Some(n) = next else { break };
            (a, b) = (b, n);
        }
        rings.push(drop_collinear(ring));
    }
    rings.retain(|r| r.len() >= 3);
    rings
}

/// The rings of the union of the valid pixels' own squares (what
/// `ST_Value` answers on) of a `width x height` raster, as corners of the
/// pixel grid: corner `(c, r)` is the top-left corner of pixel `(c, r)`, so
/// pixel `(c, r)` spans `c..c+1 x r..r+1`. Outer rings have positive area,
/// holes negative ([`ring_area2`]: twice the number of pixels). Where two
/// rings touch at a corner they are kept apart; collinear corners dropped.
///
/// ```
/// use tinmerge_core::tin::domain::{cell_outline, ring_area2};
/// // a 3 x 3 raster with a nodata pixel in the middle: a ring and a hole
/// let rings = cell_outline(3, 3, &|c, r| !(c == 1 && r == 1));
/// assert_eq!(rings.len(), 2);
/// let total: i64 = rings.iter().map(|r| ring_area2(r)).sum();
/// assert_eq!(total, 2 * 8);
/// ```
pub fn cell_outline(
    width: usize,
    height: usize,
    valid: &dyn Fn(usize, usize) -> bool,
) -> Vec<Vec<LatticePoint>> {
    let mut edges: FxHashSet<(LatticePoint, LatticePoint)> = FxHashSet::default();
    let mut add = |a: LatticePoint, b: LatticePoint| add_edge(&mut edges, a, b);
    for r in 0..height {
        for c in 0..width {
            if !valid(c, r) {
                continue;
            }
            let (ci, ri) = (c as i64, r as i64);
            let sq = [[ci, ri], [ci + 1, ri], [ci + 1, ri + 1], [ci, ri + 1]];
            for k in 0..4 {
                add(sq[k], sq[(k + 1) % 4]);
            }
        }
    }
    rings_of(&edges)
}

/// The ring without the points where it runs straight on.
fn drop_collinear(ring: Vec<LatticePoint>) -> Vec<LatticePoint> {
    let n = ring.len();
    if n < 3 {
        return ring;
    }
    (0..n)
        .filter(|&i| {
            let (p, c, q) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (d1, d2) = ([c[0] - p[0], c[1] - p[1]], [q[0] - c[0], q[1] - c[1]]);
            let cross = d1[0] * d2[1] - d1[1] * d2[0];
            let dot = d1[0] * d2[0] + d1[1] * d2[1];
            cross != 0 || dot < 0
        })
        .map(|i| ring[i])
        .collect()
}

/// The rings of [`cell_outline`] as a build's boundary: `corner(col, row)`
/// gives the world position of grid corner `(col, row)`. Inside is decided
/// by parity over all rings (each ring is its own polygon here: the holes
/// are not matched to their shells), which is all a build asks of it.
pub fn outline_area(rings: &[Vec<LatticePoint>], corner: &dyn Fn(f64, f64) -> [f64; 2]) -> Area {
    Area::new(
        rings
            .iter()
            .map(|r| vec![r.iter().map(|p| corner(p[0] as f64, p[1] as f64)).collect()])
            .collect(),
    )
}
