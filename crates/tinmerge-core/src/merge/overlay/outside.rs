//! The constrained overlay's faces outside the common domain
//! ([`super::constrained`]): flat slivers reached from the convex hull
//! ([`outside_slivers`]) and those in a rounding-wide notch of an input's
//! outer boundary ([`beyond_hull_edges`]).

use crate::interrupt::Ticker;
use crate::tin::{Level, NONE, TinError};
use spade::handles::{FaceHandle, InnerTag};
use spade::{CdtEdge, ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// The constrained triangulation the overlay is made in.
pub(super) type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// The faces of the CDT outside the common domain, by face index: those
/// reached from the convex hull without crossing a piece of an input edge,
/// through faces no wider than `band` (area at most `band` times the
/// longest side).
///
/// The CDT covers the convex hull of the output points, and both inputs'
/// outer boundaries may bend in by a rounding (see `load`): the faces in
/// such a concavity are flat slivers outside the common domain, up to
/// hundreds of metres long along it, in no one triangle of the tin they
/// leave, and none of the faces path's. Bounded by the pieces of both
/// boundaries on the inside; a face wider than `band` stops the fill
/// whatever it met, so a gap in those pieces cannot empty the overlay.
pub(super) fn outside_slivers(
    cdt: &Cdt,
    band: f64,
    tk: &mut Ticker<'_, '_>,
) -> Result<Vec<bool>, TinError> {
    let mut out = vec![false; cdt.num_all_faces()];
    let flat = |f| is_flat(f, band);
    let mut stack = Vec::new();
    for e in cdt.convex_hull() {
        for h in [e, e.rev()] {
            if let Some(f) = h.face().as_inner()
                && !h.is_constraint_edge()
                && !out[f.fix().index()]
                && flat(f)
            {
                out[f.fix().index()] = true;
                stack.push(f);
            }
        }
    }
    while let Some(f) = stack.pop() {
        tk.tick()?;
        for e in f.adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner()
                && !out[g.fix().index()]
                && flat(g)
            {
                out[g.fix().index()] = true;
                stack.push(g);
            }
        }
    }
    Ok(out)
}

/// Whether face `f` is no wider than `band`: its area at most `band` times
/// its longest side.
fn is_flat(f: FaceHandle<'_, InnerTag, Point2<f64>, (), CdtEdge<()>, ()>, band: f64) -> bool {
    let p: [Point2<f64>; 3] = f.positions();
    let longest = (0..3).fold(0.0f64, |m, j| {
        let (u, v) = (p[j], p[(j + 1) % 3]);
        m.max((v.x - u.x).hypot(v.y - u.y))
    });
    f.area().abs() <= band * longest
}

/// Marks in `outside` the faces of the CDT with two corners at the ends
/// of an outer edge of one input's level (`src`: each output point's
/// vertex of that input) and the third strictly beyond it (exact): a
/// flat face in a rounding-wide notch of that level's boundary, the
/// other input's edge running straight past a vertex where the boundary
/// bends in by an ulp. [`outside_slivers`] cannot reach it from the
/// convex hull (the other input's edge is a constraint); labelled, its
/// far corner lay a pixel outside the triangle it was given (harness seed
/// 73002).
pub(super) fn beyond_hull_edges(
    cdt: &Cdt,
    inputs: &[(&Level, &Vec<u32>)],
    band: f64,
    outside: &mut [bool],
    tk: &mut Ticker<'_, '_>,
) -> Result<(), TinError> {
    // each input's outer edges, directed with its level on their left
    let outer: Vec<rustc_hash::FxHashSet<(u32, u32)>> = inputs
        .iter()
        .map(|(s, _)| {
            let lv = *s;
            let mut e: rustc_hash::FxHashSet<(u32, u32)> = Default::default();
            for (tri, nb) in lv.tris.iter().zip(&lv.nbrs) {
                for j in 0..3 {
                    if nb[j] == NONE {
                        e.insert((tri[(j + 1) % 3], tri[(j + 2) % 3]));
                    }
                }
            }
            e
        })
        .collect();
    // the output points u, v on one input's outer edge, either way round
    let on_outer = |u: usize, v: usize, dir: bool| {
        inputs.iter().zip(&outer).any(|((_, src), e)| {
            let (a, b) = (
                src.get(u).copied().unwrap_or(NONE),
                src.get(v).copied().unwrap_or(NONE),
            );
            a != NONE && b != NONE && (e.contains(&(b, a)) || (!dir && e.contains(&(a, b))))
        })
    };
    let flat = |f| is_flat(f, band);
    let mut stack = Vec::new();
    for f in cdt.inner_faces() {
        tk.tick()?;
        if outside[f.fix().index()] || !flat(f) {
            continue;
        }
        let vs = f.vertices().map(|v| v.fix().index());
        // the face runs counter-clockwise: an outer edge v -> u of an
        // input (its level on the left) has the face on its right
        if (0..3).any(|k| on_outer(vs[k], vs[(k + 1) % 3], true)) {
            outside[f.fix().index()] = true;
            stack.push(f);
        }
    }
    // the rest of the notch: flat faces reached without crossing an outer
    // edge of either input (the notch's inner side)
    while let Some(f) = stack.pop() {
        tk.tick()?;
        for e in f.adjacent_edges() {
            let [u, v] = e.vertices().map(|v| v.fix().index());
            if on_outer(u, v, false) {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner()
                && !outside[g.fix().index()]
                && flat(g)
            {
                outside[g.fix().index()] = true;
                stack.push(g);
            }
        }
    }
    Ok(())
}
