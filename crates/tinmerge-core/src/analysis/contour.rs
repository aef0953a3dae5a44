//! Exact contour lines of one level's surface (linear on each triangle),
//! joined across triangles into lines.
//!
//! For a height `z`, every triangle with corners on both sides of `z`
//! holds one straight piece of the isoline, between the points where `z`
//! crosses two of its edges. **A corner exactly at `z` counts as above
//! it** (simulation of simplicity), so every triangle gives at most one
//! piece, a horizontal triangle at `z` gives none, and the contour along
//! the edge of a flat area at height `z` runs along that area's lower
//! boundary (the line between `{f >= z}` and `{f < z}`). A crossing on an
//! edge is computed from the edge's end points in vertex-id order, so the
//! two triangles of the edge find the same point bit for bit; a crossing
//! at a corner is that corner.
//!
//! Pieces are directed with the higher ground on their left and joined end
//! to end through the crossing they share (an edge or a vertex): a line
//! ends where the contour leaves the domain, a ring is closed (its last
//! point is its first). Where several pieces meet at one vertex (a saddle
//! exactly at `z`), they are joined in triangle order.
//!
//! ```
//! use tinmerge_core::analysis::contour::contours;
//! use tinmerge_core::tin::build::build;
//! // a pyramid: apex 10 m at (1, 1) over a 2 x 2 square at 0
//! let pts = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0], [1.0, 1.0, 10.0]];
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let lines = contours(&tin, 0, 5.0, 0.0, &mut || Ok(())).unwrap();
//! // the 5 m contour: one closed ring around the apex (the 0 and 10 m ones
//! // touch the surface at its rim and apex only)
//! let at5: Vec<_> = lines.iter().filter(|l| l.z == 5.0).collect();
//! assert_eq!(at5.len(), 1);
//! assert_eq!(at5[0].points.first(), at5[0].points.last());
//! assert_eq!(at5[0].points.len(), 5);
//! ```

use crate::interrupt::{Interrupt, Ticker};
use crate::tin::{Tin, TinError};
use rustc_hash::FxHashMap;

/// One contour line: its height and its points (a ring repeats its first
/// point at the end).
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    pub z: f64,
    pub points: Vec<[f64; 2]>,
}

/// Where a contour crosses the mesh: at a vertex, or inside the edge
/// between two vertices (smaller id first).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Key {
    Vertex(u32),
    Edge(u32, u32),
}

/// The contour heights `base + k * interval` (k any integer) within
/// `[lo, hi]`, increasing; an error for a step that is not a positive
/// finite number or a range holding more than `max` of them.
pub fn heights(
    lo: f64,
    hi: f64,
    interval: f64,
    base: f64,
    max: usize,
) -> Result<Vec<f64>, TinError> {
    if !(interval.is_finite() && interval > 0.0 && base.is_finite()) {
        return Err(TinError::InvalidParameter(format!(
            "contour interval must be a positive number and base finite, got interval {interval} and base {base}"
        )));
    }
    if lo.is_nan() || hi.is_nan() || lo > hi {
        return Ok(Vec::new());
    }
    let k0 = ((lo - base) / interval).ceil();
    let k1 = ((hi - base) / interval).floor();
    let count = k1 - k0;
    if count.is_nan() || count >= max as f64 {
        return Err(TinError::TooLarge(format!(
            "{} contour heights from {lo} to {hi} every {interval}: at most {max}; use a larger interval",
            k1 - k0 + 1.0
        )));
    }
    let mut out = Vec::new();
    let mut k = k0;
    while k <= k1 {
        let z = base + k * interval;
        if z >= lo && z <= hi {
            out.push(z);
        }
        k += 1.0;
    }
    Ok(out)
}

/// Most contour heights one call draws.
pub const MAX_HEIGHTS: usize = 100_000;

/// The contours of `level` at the heights `base + k * interval`, by
/// increasing height, each height's lines in the order they are found.
pub fn contours(
    tin: &Tin,
    level: usize,
    interval: f64,
    base: f64,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<Contour>, TinError> {
    let lv = tin
        .levels
        .get(level)
        .ok_or_else(|| TinError::Corrupt("contours: level".into()))?;
    let nv = lv.num_vertices as usize;
    let verts = tin
        .verts
        .get(..nv)
        .ok_or_else(|| TinError::Corrupt("contours: vertex count".into()))?;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in verts {
        lo = lo.min(v[2]);
        hi = hi.max(v[2]);
    }
    let zs = heights(lo, hi, interval, base, MAX_HEIGHTS)?;
    let mut tk = Ticker::new(interrupt);
    // triangles by the height range they span, so each height visits only
    // the triangles it cuts: sorted by lowest corner
    let mut order: Vec<(f64, f64, u32)> = Vec::with_capacity(lv.tris.len());
    // the domain's triangles (the void ones are the last)
    for (t, tri) in lv.tris[..lv.num_domain()].iter().enumerate() {
        let mut z = [0.0; 3];
        for j in 0..3 {
            z[j] = verts
                .get(tri[j] as usize)
                .ok_or_else(|| TinError::Corrupt("contours: vertex id".into()))?[2];
        }
        order.push((z[0].min(z[1]).min(z[2]), z[0].max(z[1]).max(z[2]), t as u32));
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let mut out = Vec::new();
    let mut live: Vec<(f64, u32)> = Vec::new(); // (highest corner, triangle) of those begun
    let mut next = 0;
    for &z in &zs {
        // triangles whose lowest corner is below z; those whose highest
        // corner is below z no longer matter (a corner at z is above)
        while next < order.len() && order[next].0 < z {
            live.push((order[next].1, order[next].2));
            next += 1;
        }
        live.retain(|&(top, _)| top >= z);
        live.sort_unstable_by_key(|&(_, t)| t);
        let mut pieces: Vec<(Key, Key, [f64; 2], [f64; 2])> = Vec::new();
        for &(_, t) in &live {
            tk.tick()?;
            let tri = lv.tris[t as usize];
            if let Some(p) = piece(verts, tri, z) {
                pieces.push(p);
            }
        }
        join(z, &pieces, &mut out, &mut tk)?;
    }
    Ok(out)
}

/// The piece of the contour at `z` in the triangle with corners `tri`
/// (counter-clockwise), directed with the higher ground on its left.
fn piece(verts: &[[f64; 3]], tri: [u32; 3], z: f64) -> Option<(Key, Key, [f64; 2], [f64; 2])> {
    let above = |j: usize| verts[tri[j] as usize][2] >= z;
    let n_above = (0..3).filter(|&j| above(j)).count();
    if n_above == 0 || n_above == 3 {
        return None;
    }
    // the corner alone on its side, and the two crossings on its edges in
    // counter-clockwise order
    let lone = (0..3).find(|&j| above(j) == (n_above == 1))?;
    let (a, b) = ((lone + 1) % 3, (lone + 2) % 3);
    let c1 = crossing(verts, tri[lone], tri[a], z);
    let c2 = crossing(verts, tri[lone], tri[b], z);
    if c1.0 == c2.0 {
        // the lone corner is at z, the others below: a peak touching z
        return None;
    }
    // corners lone, a, b counter-clockwise: the lone corner is on the
    // left of c1 -> c2, so that is the direction when it is the one above
    Some(if n_above == 1 {
        (c1.0, c2.0, c1.1, c2.1)
    } else {
        (c2.0, c1.0, c2.1, c1.1)
    })
}

/// Where height `z` crosses the edge between vertices `u` and `v` (one at
/// or above `z`, the other below): the vertex itself when it is at `z`,
/// otherwise the interpolated point, computed from the end with the
/// smaller id so both triangles of the edge get the same bits.
fn crossing(verts: &[[f64; 3]], u: u32, v: u32, z: f64) -> (Key, [f64; 2]) {
    for w in [u, v] {
        let p = verts[w as usize];
        if p[2] == z {
            return (Key::Vertex(w), [p[0], p[1]]);
        }
    }
    let (s, e) = if u < v { (u, v) } else { (v, u) };
    let (p, q) = (verts[s as usize], verts[e as usize]);
    let r = (z - p[2]) / (q[2] - p[2]);
    (
        Key::Edge(s, e),
        [p[0] + r * (q[0] - p[0]), p[1] + r * (q[1] - p[1])],
    )
}

/// Join the directed pieces of one height into lines: first those starting
/// where no piece ends (lines that leave the domain), then rings.
fn join(
    z: f64,
    pieces: &[(Key, Key, [f64; 2], [f64; 2])],
    out: &mut Vec<Contour>,
    tk: &mut Ticker,
) -> Result<(), TinError> {
    let mut from: FxHashMap<Key, Vec<usize>> = FxHashMap::default();
    let mut ends: FxHashMap<Key, usize> = FxHashMap::default();
    for (i, p) in pieces.iter().enumerate() {
        from.entry(p.0).or_default().push(i);
        *ends.entry(p.1).or_default() += 1;
    }
    let mut used = vec![false; pieces.len()];
    let follow = |start: usize, used: &mut Vec<bool>| -> Contour {
        let mut pts = vec![pieces[start].2];
        let mut i = start;
        loop {
            used[i] = true;
            pts.push(pieces[i].3);
            let nxt = from
                .get(&pieces[i].1)
                .and_then(|c| c.iter().copied().find(|&k| !used[k]));
            match nxt {
                Some(k) => i = k,
                None => break,
            }
        }
        Contour { z, points: pts }
    };
    // open lines: from a start no piece ends at (more starts than ends)
    for i in 0..pieces.len() {
        tk.tick()?;
        if used[i] {
            continue;
        }
        let starts = from.get(&pieces[i].0).map_or(0, |c| c.len());
        if starts > ends.get(&pieces[i].0).copied().unwrap_or(0) {
            out.push(follow(i, &mut used));
        }
    }
    for i in 0..pieces.len() {
        tk.tick()?;
        if !used[i] {
            out.push(follow(i, &mut used));
        }
    }
    Ok(())
}
