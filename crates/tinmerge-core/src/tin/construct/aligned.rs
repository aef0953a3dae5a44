//! Coarse levels whose edges run along the pixel lattice: a right
//! triangulated irregular network (RTIN: Evans, Kirkpatrick and Townsend
//! 2001; Lindstrom and Pascucci's longest-edge bisection), the triangles
//! right isosceles with their legs along rows and columns or along the
//! diagonals, each split in two at the middle of its longest edge (a pixel
//! centre while the legs are longer than a pixel), its neighbour across
//! that edge split with it so that no vertex is left hanging.
//!
//! An edge along a row, a column or a diagonal meets the grid segments
//! between pixel centres only at pixel centres, so the finer levels never
//! have to split a coarse edge where it crosses a grid line: a coarse
//! level built this way costs the finest level only the pixel centres on
//! its edges, where a level of free Delaunay edges costs a vertex at every
//! crossing that a finer tolerance refuses (issue 74: on the bundled UTM
//! DEM, a level at 8 m under one at 2 m made the finest 23 % bigger).

use super::mesh::{Mesh, NONE, next};
use crate::geom::orient;
use crate::tin::TinError;

fn internal(what: &str) -> TinError {
    TinError::Internal(format!("the lattice-aligned build {what}"))
}

/// Triangle `t`'s longest edge (its hypotenuse): the half-edge.
pub(super) fn hypotenuse(m: &Mesh, t: u32) -> u32 {
    let len = |h: u32| {
        let (a, b) = (m.at(h), m.at(next(h)));
        (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
    };
    let h = 3 * t;
    let (l0, l1, l2) = (len(h), len(h + 1), len(h + 2));
    if l0 >= l1 && l0 >= l2 {
        h
    } else if l1 >= l2 {
        h + 1
    } else {
        h + 2
    }
}

/// The middle of half-edge `h`, when it is a lattice point.
fn middle(m: &Mesh, h: u32) -> Option<[i64; 2]> {
    let (a, b) = (m.at(h), m.at(next(h)));
    let (sx, sy) = (a[0] + b[0], a[1] + b[1]);
    if sx.fract() != 0.0 || sy.fract() != 0.0 {
        return None;
    }
    let (sx, sy) = (sx as i64, sy as i64);
    (sx % 2 == 0 && sy % 2 == 0).then_some([sx / 2, sy / 2])
}

/// Split triangle `t` at the middle of its hypotenuse, and its neighbour
/// there with it (split first itself when its hypotenuse is longer, as
/// often as it takes). `z` gives the new vertex its height; `touched`
/// gets every triangle changed. `None` when the hypotenuse's middle is
/// not a lattice point (the legs are a pixel long: nothing is inside).
pub(super) fn bisect(
    m: &mut Mesh,
    t: u32,
    z: &mut dyn FnMut(i64, i64) -> f64,
    touched: &mut Vec<u32>,
    scratch: &mut Vec<u32>,
    depth: u32,
) -> Result<Option<u32>, TinError> {
    if depth > 128 {
        return Err(internal("split its neighbours too deep"));
    }
    let h = hypotenuse(m, t);
    let Some(mid) = middle(m, h) else {
        return Ok(None);
    };
    loop {
        let g = m.twin[h as usize];
        if g == NONE || hypotenuse(m, g / 3) == g {
            break;
        }
        // the neighbour is coarser: split it first; t is left as it was
        if bisect(m, g / 3, z, touched, scratch, depth + 1)?.is_none() {
            return Err(internal("met a neighbour it could not split"));
        }
    }
    let g = m.twin[h as usize];
    let p = m.add_point([mid[0] as f64, mid[1] as f64, z(mid[0], mid[1])]);
    touched.push(t);
    if g != NONE {
        touched.push(g / 3);
    }
    m.split_edge(h, p, scratch);
    scratch.clear();
    Ok(Some(p))
}

/// Whether triangle `c` (lattice corners) and the rectangle
/// `[0, w] x [0, h]` share no area (a separating line: one of the
/// rectangle's sides or one of the triangle's edges).
fn apart(c: &[[f64; 3]; 3], w: f64, h: f64) -> bool {
    if c.iter().all(|p| p[0] >= w)
        || c.iter().all(|p| p[0] <= 0.0)
        || c.iter().all(|p| p[1] >= h)
        || c.iter().all(|p| p[1] <= 0.0)
    {
        return true;
    }
    let corners = [[0.0, 0.0, 0.0], [w, 0.0, 0.0], [w, h, 0.0], [0.0, h, 0.0]];
    (0..3).any(|k| {
        let (a, b) = (&c[k], &c[(k + 1) % 3]);
        // counter-clockwise: the inside is on the left
        corners.iter().all(|q| orient(a, b, q) <= 0.0)
    })
}

fn inside(c: &[[f64; 3]; 3], w: f64, h: f64) -> bool {
    c.iter()
        .all(|p| p[0] >= 0.0 && p[0] <= w && p[1] >= 0.0 && p[1] <= h)
}

/// The coarsest lattice-aligned triangulation of the pixel centres of a
/// `width` x `height` band (corners (0, 0) and (width - 1, height - 1)):
/// the RTIN of the smallest power-of-two square over it, bisected where a
/// triangle reaches past it, and those past it left out. Heights from `z`.
pub(super) fn cover(
    width: usize,
    height: usize,
    z: &mut dyn FnMut(i64, i64) -> f64,
) -> Result<Mesh, TinError> {
    let (w, h) = (width as i64 - 1, height as i64 - 1);
    if w < 1 || h < 1 {
        return Err(TinError::Degenerate(
            "the valid pixels lie on one line: no surface to triangulate".into(),
        ));
    }
    let mut s = 1i64;
    while s < w.max(h) {
        s *= 2;
    }
    // the square, its heights 0 outside the band (those triangles go)
    let mut big = Mesh::new();
    let mut zz = |c: i64, r: i64| if c <= w && r <= h { z(c, r) } else { 0.0 };
    let sq = [[0, 0], [s, 0], [s, s], [0, s]];
    for p in sq {
        big.add_point([p[0] as f64, p[1] as f64, zz(p[0], p[1])]);
    }
    for tri in [[0u32, 1, 2], [0, 2, 3]] {
        let c = tri.map(|v| big.pts[v as usize]);
        if orient(&c[0], &c[1], &c[2]) > 0.0 {
            big.add_triangle(tri[0], tri[1], tri[2], 0);
        } else {
            big.add_triangle(tri[0], tri[2], tri[1], 0);
        }
    }
    big.link_all();
    let (wf, hf) = (w as f64, h as f64);
    let (mut touched, mut scratch) = (Vec::new(), Vec::new());
    loop {
        let mut changed = false;
        let mut t = 0;
        while t < big.triangles() {
            let c = big.corners(t);
            if !inside(&c, wf, hf) && !apart(&c, wf, hf) {
                if bisect(&mut big, t, &mut zz, &mut touched, &mut scratch, 0)?.is_none() {
                    return Err(internal("could not split a triangle across the band's side"));
                }
                changed = true;
                continue;
            }
            t += 1;
        }
        if !changed {
            break;
        }
    }
    // the triangles inside, their vertices numbered again
    let mut out = Mesh::new();
    let mut map = vec![NONE; big.pts.len()];
    for t in 0..big.triangles() {
        let c = big.corners(t);
        if !inside(&c, wf, hf) {
            continue;
        }
        let mut tri = [0u32; 3];
        for (k, slot) in tri.iter_mut().enumerate() {
            let v = big.v[3 * t as usize + k] as usize;
            if map[v] == NONE {
                map[v] = out.add_point(big.pts[v]);
            }
            *slot = map[v];
        }
        out.add_triangle(tri[0], tri[1], tri[2], 0);
    }
    out.link_all();
    Ok(out)
}
