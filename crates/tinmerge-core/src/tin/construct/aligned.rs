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

use super::mesh::{Mesh, NONE, next, prev};
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

/// Triangle `t`'s hypotenuse (half-edge) and its middle, when `t` is a
/// right isosceles triangle with its legs along the lattice (rows and
/// columns, or diagonals) and that middle is a lattice point.
fn shape(m: &Mesh, t: u32) -> Option<(u32, [i64; 2])> {
    let h = hypotenuse(m, t);
    let (a, b, c) = (m.at(h), m.at(next(h)), m.at(prev(h)));
    let (u, v) = ([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
    let along = |d: [f64; 2]| d[0] == 0.0 || d[1] == 0.0 || d[0].abs() == d[1].abs();
    let right =
        u[0] * v[0] + u[1] * v[1] == 0.0 && u[0] * u[0] + u[1] * u[1] == v[0] * v[0] + v[1] * v[1];
    if !right || !along(u) || !along(v) {
        return None;
    }
    let (sx, sy) = (a[0] + b[0], a[1] + b[1]);
    if sx.fract() != 0.0 || sy.fract() != 0.0 {
        return None;
    }
    let (sx, sy) = (sx as i64, sy as i64);
    (sx % 2 == 0 && sy % 2 == 0).then_some((h, [sx / 2, sy / 2]))
}

/// Which hull edges a bisection may split.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Hull {
    /// any (a band's own hull)
    Free,
    /// none: a kept side's vertices are its profile's ([`super::kept`])
    Kept,
    /// only at this lattice point: the kept side's vertex being made
    At([i64; 2]),
}

/// Split triangle `t` at the middle of its hypotenuse, and its neighbour
/// there with it: a coarser right triangle across it (whose leg it is) is
/// bisected first, as often as it takes, so that no vertex is left
/// hanging. `z` gives the middle's height (`None`: no data there);
/// `touched` gets every triangle changed. `None`, with nothing changed,
/// when `t` is not a lattice-aligned right triangle ([`shape`]) or its
/// middle has no data, or when its hypotenuse is on the hull and `hull`
/// does not allow a vertex at its middle.
pub(super) fn bisect(
    m: &mut Mesh,
    t: u32,
    z: &mut dyn FnMut(i64, i64) -> Option<f64>,
    touched: &mut Vec<u32>,
    scratch: &mut Vec<u32>,
    hull: Hull,
    depth: u32,
) -> Result<Option<u32>, TinError> {
    if depth > 128 {
        return Err(internal("split its neighbours too deep"));
    }
    let Some((h, mid)) = shape(m, t) else {
        return Ok(None);
    };
    if m.twin[h as usize] == NONE && hull != Hull::Free && hull != Hull::At(mid) {
        return Ok(None);
    }
    let Some(height) = z(mid[0], mid[1]) else {
        return Ok(None);
    };
    loop {
        let g = m.twin[h as usize];
        if g == NONE {
            break;
        }
        match shape(m, g / 3) {
            Some((hg, _)) if hg != g => {
                // coarser: split it first (t is left as it was); when it
                // cannot be, the shared edge is split in both
                if bisect(m, g / 3, z, touched, scratch, hull, depth + 1)?.is_none() {
                    break;
                }
            }
            _ => break,
        }
    }
    let g = m.twin[h as usize];
    let p = m.add_point([mid[0] as f64, mid[1] as f64, height]);
    touched.push(t);
    if g != NONE {
        touched.push(g / 3);
    }
    m.split_edge(h, p, scratch);
    scratch.clear();
    Ok(Some(p))
}

/// Whether triangle `c` and the convex polygon `hull` (counter-clockwise)
/// share no area: a separating line, one of the hull's sides or one of
/// the triangle's edges.
fn apart(c: &[[f64; 3]; 3], hull: &[[f64; 3]]) -> bool {
    let n = hull.len();
    (0..n).any(|k| {
        let (a, b) = (&hull[k], &hull[(k + 1) % n]);
        c.iter().all(|q| orient(a, b, q) <= 0.0)
    }) || (0..3).any(|k| {
        let (a, b) = (&c[k], &c[(k + 1) % 3]);
        hull.iter().all(|q| orient(a, b, q) <= 0.0)
    })
}

/// Whether every corner of `c` is in the closed convex polygon `hull`.
fn within(c: &[[f64; 3]; 3], hull: &[[f64; 3]]) -> bool {
    let n = hull.len();
    c.iter()
        .all(|q| (0..n).all(|k| orient(&hull[k], &hull[(k + 1) % n], q) >= 0.0))
}

/// Legs no shorter than this are split where a triangle reaches past the
/// valid centres' hull or over nodata.
const MIN_LEG: f64 = 4.0;

/// The coarsest lattice-aligned triangulation of a band's valid pixel
/// centres' hull `hull` (lattice corners, counter-clockwise): the RTIN of
/// the smallest power-of-two square over the band, bisected where a
/// triangle reaches past the hull or has a corner without data (down to
/// legs of [`MIN_LEG`]); the triangles within the hull with data at every
/// corner kept, and the rest of the hull (a strip along its slanting
/// sides, the nodata gaps) triangulated around them, constrained Delaunay
/// (spade). `z` gives the height of a valid pixel centre, `None`
/// elsewhere. With `keep_sides`, no vertex on the hull but its corners
/// (a kept side's vertices are its profile's, [`super::kept`]): a
/// triangle with a corner on a side is not kept.
pub(super) fn cover(
    width: usize,
    height: usize,
    hull: &[[i64; 2]],
    keep_sides: bool,
    z: &dyn Fn(i64, i64) -> Option<f64>,
) -> Result<Mesh, TinError> {
    let hull: Vec<[f64; 3]> = hull
        .iter()
        .map(|p| [p[0] as f64, p[1] as f64, 0.0])
        .collect();
    let n = hull.len();
    let off_sides = |q: &[f64; 3]| {
        hull.iter().any(|c| c[..2] == q[..2])
            || (0..n).all(|k| orient(&hull[k], &hull[(k + 1) % n], q) != 0.0)
    };
    let keep = |c: &[[f64; 3]; 3]| {
        within(c, &hull)
            && c.iter().all(|p| z(p[0] as i64, p[1] as i64).is_some())
            && (!keep_sides || c.iter().all(off_sides))
    };
    let big = square(width, height, &hull, &keep)?;
    let kept: Vec<[[f64; 3]; 3]> = (0..big.triangles())
        .map(|t| big.corners(t))
        .filter(|c| keep(c))
        .collect();
    around(&kept, &hull, z)
}

/// The RTIN of the smallest power-of-two square over a `width` x `height`
/// band (heights 0), bisected where a triangle is not `keep` but reaches
/// into `hull`, while its legs are longer than [`MIN_LEG`].
fn square(
    width: usize,
    height: usize,
    hull: &[[f64; 3]],
    keep: &dyn Fn(&[[f64; 3]; 3]) -> bool,
) -> Result<Mesh, TinError> {
    let (w, h) = (width as i64 - 1, height as i64 - 1);
    let mut s = 1i64;
    while s < w.max(h) {
        s *= 2;
    }
    let mut big = Mesh::new();
    for p in [[0, 0], [s, 0], [s, s], [0, s]] {
        big.add_point([p[0] as f64, p[1] as f64, 0.0]);
    }
    big.add_ccw([0, 1, 2], 0);
    big.add_ccw([0, 2, 3], 0);
    big.link_all();
    let leg = |m: &Mesh, t: u32| {
        let h = hypotenuse(m, t);
        let (a, b) = (m.at(h), m.at(next(h)));
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt() / std::f64::consts::SQRT_2
    };
    let (mut touched, mut scratch) = (Vec::new(), Vec::new());
    let mut flat = |_: i64, _: i64| Some(0.0);
    loop {
        let mut changed = false;
        let mut t = 0;
        while t < big.triangles() {
            let c = big.corners(t);
            if !keep(&c)
                && leg(&big, t) > MIN_LEG
                && !apart(&c, hull)
                && bisect(
                    &mut big,
                    t,
                    &mut flat,
                    &mut touched,
                    &mut scratch,
                    Hull::Free,
                    0,
                )?
                .is_some()
            {
                changed = true;
                continue;
            }
            t += 1;
        }
        if !changed {
            return Ok(big);
        }
    }
}

/// The constrained Delaunay triangulation (spade) of the hull's corners
/// and the `kept` triangles' corners, their edges constraints: the kept
/// triangles and the rest of the hull around them, heights from `z`.
fn around(
    kept: &[[[f64; 3]; 3]],
    hull: &[[f64; 3]],
    z: &dyn Fn(i64, i64) -> Option<f64>,
) -> Result<Mesh, TinError> {
    use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
    type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;
    let mut cdt = Cdt::default();
    let mut handle = std::collections::HashMap::new();
    let mut add = |cdt: &mut Cdt, p: &[f64; 3]| {
        let key = (p[0] as i64, p[1] as i64);
        if let Some(&v) = handle.get(&key) {
            return Ok(v);
        }
        let v = cdt
            .insert(Point2::new(p[0], p[1]))
            .map_err(|e| internal(&format!("could not place a vertex: {e:?}")))?;
        handle.insert(key, v);
        Ok::<_, TinError>(v)
    };
    for p in hull {
        add(&mut cdt, p)?;
    }
    let mut edges = Vec::with_capacity(3 * kept.len());
    for c in kept {
        let v = [
            add(&mut cdt, &c[0])?,
            add(&mut cdt, &c[1])?,
            add(&mut cdt, &c[2])?,
        ];
        for k in 0..3 {
            edges.push((v[k], v[(k + 1) % 3]));
        }
    }
    for (a, b) in edges {
        cdt.try_add_constraint(a, b);
    }
    let mut out = Mesh::new();
    let mut map = vec![NONE; cdt.num_vertices()];
    for f in cdt.inner_faces() {
        let mut tri = [0u32; 3];
        for (slot, v) in tri.iter_mut().zip(f.vertices()) {
            let i = v.fix().index();
            if map[i] == NONE {
                let p = v.position();
                let zz = z(p.x as i64, p.y as i64)
                    .ok_or_else(|| internal("made a vertex without data"))?;
                map[i] = out.add_point([p.x, p.y, zz]);
            }
            *slot = map[i];
        }
        out.add_ccw(tri, 0);
    }
    out.link_all();
    Ok(out)
}
