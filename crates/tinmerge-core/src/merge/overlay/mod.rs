//! TIN/TIN overlay (Scarlatos §6.2, second problem): one triangulation of the
//! common domain of two TINs that holds every vertex and every edge of both,
//! edges cut where they cross, each output triangle labelled with the
//! triangle of A and of B that contains it.
//!
//! The crossings are found by walking every edge of A through B (spade's
//! [`LineIntersectionIterator`](spade::LineIntersectionIterator) over B's triangulation, loaded as a CDT whose
//! constraints are B's own edges, so the walk sees exactly B). Every
//! decision of the walk is an exact orientation test; a crossing point is
//! computed once, from the pair of edges, and shared by both edges' lists.
//! A's vertices are located in B exactly (on a vertex of B: the same output
//! vertex; on an edge of B: a point of that edge), B's vertices in A.
//! Every edge of A and of B is then a chain of pieces between consecutive
//! points along it; all points lie in the closed common domain, which is
//! convex, so every piece does too. The pieces go into one bulk-loaded
//! constrained Delaunay triangulation (spade); pieces that rounding of
//! crossing points made cross again (near-parallel edges) are added
//! afterwards, split where they cross at points computed as every crossing
//! is (`constrained::add_splitting`), so the result is always a valid
//! triangulation with strictly positive (exact) orientation.
//!
//! Cost: O(N + M + K) for the walks and the lists plus the CDT bulk load
//! (O(V log V) for V = output vertices), against the naive method
//! (`constrained::naive`, with the `bench` feature): every edge of both inserted into one CDT with splitting.
//!
//! Invariants of the output, for both paths (tests/overlay.rs against
//! independent oracles, tests/pg_regress/sql/overlay.sql against PostGIS):
//! triangles strictly counter-clockwise, no directed edge twice, areas summing
//! to the common domain's, every input vertex in the common domain an output
//! vertex, every clipped input edge a chain of output edges, every output
//! triangle inside its `tri_a` and `tri_b`.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::overlay::overlay;
//! let grid = |dx: f64| {
//!     let mut pts = Vec::new();
//!     for i in 0..4 {
//!         for j in 0..4 {
//!             pts.push([i as f64 + dx, j as f64, (i * j) as f64]);
//!         }
//!     }
//!     build(pts, &[0.0], 0, &mut || Ok(())).unwrap()
//! };
//! let (a, b) = (grid(0.0), grid(0.5));
//! let o = overlay(&a, 0, &b, 0, &mut || Ok(())).unwrap();
//! // the common domain is [0.5, 3] x [0, 3]
//! let area: f64 = (0..o.tris.len()).map(|t| o.area(t)).sum();
//! assert!((area - 7.5).abs() < 1e-9);
//! ```

pub mod constrained;
pub mod faces;
mod output;
mod outside;
mod split;
pub mod volume;

pub use output::{Overlay, SAME_PLANE, difference};

use crate::interrupt::Interrupt;
use crate::tin::{Tin, TinError, interpolate};
use constrained::overlay_cdt;

/// Overlay of A at `level_a` and B at `level_b`: face by face
/// ([`crate::merge::overlay::faces`]) when B's domain is convex and rounding never
/// gets in the way, else the constrained triangulation
/// ([`overlay_constrained`]); [`Overlay::fallback`] says which.
///
/// A panic inside spade (its internal assertions) is reported as an error.
pub fn overlay(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Overlay, TinError> {
    levels_exist(a, level_a, b, level_b)?;
    let mut o = guarded(interrupt, |check| {
        overlay_dispatch(a, level_a, b, level_b, check)
    })?;
    mark_void(&mut o, a, level_a, b, level_b);
    Ok(o)
}

/// `LevelOutOfRange` unless both levels exist (the SQL layer resolves
/// levels first; a core caller could pass any).
fn levels_exist(a: &Tin, level_a: usize, b: &Tin, level_b: usize) -> Result<(), TinError> {
    for (t, l) in [(a, level_a), (b, level_b)] {
        if l >= t.levels.len() {
            return Err(TinError::LevelOutOfRange {
                level: i64::try_from(l).unwrap_or(i64::MAX),
                num_levels: t.levels.len(),
            });
        }
    }
    Ok(())
}

/// The output triangles in a void triangle of A or of B.
fn mark_void(o: &mut Overlay, a: &Tin, level_a: usize, b: &Tin, level_b: usize) {
    let (la, lb) = (&a.levels[level_a], &b.levels[level_b]);
    if la.num_void == 0 && lb.num_void == 0 {
        return;
    }
    o.void = o
        .tri_a
        .iter()
        .zip(&o.tri_b)
        .map(|(&ta, &tb)| la.is_void(ta) || lb.is_void(tb))
        .collect();
}

/// Marks the output triangles over which A at `level_a` and B at
/// `level_b` are one plane ([`Overlay::same`]): each of the two owning
/// triangles' corners on the other's plane, within [`SAME_PLANE`] of its
/// height. [`difference`] then counts them unchanged whatever rounding did
/// to the heights interpolated at their corners.
pub fn mark_same(o: &mut Overlay, a: &Tin, level_a: usize, b: &Tin, level_b: usize) {
    let on = |p: &[f64; 3], c: &[[f64; 3]; 3]| {
        (interpolate(c, p[0], p[1]) - p[2]).abs() <= SAME_PLANE * p[2].abs().max(1.0)
    };
    o.same = o
        .tri_a
        .iter()
        .zip(&o.tri_b)
        .map(|(&ta, &tb)| {
            let (ca, cb) = (a.corners(level_a, ta), b.corners(level_b, tb));
            ca.iter().all(|p| on(p, &cb)) && cb.iter().all(|p| on(p, &ca))
        })
        .collect();
}

/// The overlay always built as one constrained triangulation (the robust
/// path; for tests and benchmarks of the two paths).
pub fn overlay_constrained(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Overlay, TinError> {
    levels_exist(a, level_a, b, level_b)?;
    let mut o = guarded(interrupt, |check| {
        overlay_cdt(a, level_a, b, level_b, check)
    })?;
    mark_void(&mut o, a, level_a, b, level_b);
    Ok(o)
}

/// Runs `f`, turning a panic inside spade into an error; a panic raised by
/// the caller's interrupt check (a cancel, through the host's error
/// handling) goes on unwinding untouched.
fn guarded(
    interrupt: &mut Interrupt<'_>,
    f: impl FnOnce(&mut Interrupt<'_>) -> Result<Overlay, TinError>,
) -> Result<Overlay, TinError> {
    let in_check = std::cell::Cell::new(false);
    let mut check = || {
        in_check.set(true);
        let r = interrupt();
        in_check.set(false);
        r
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&mut check))).map_err(|payload| {
        if in_check.get() {
            std::panic::resume_unwind(payload);
        }
        TinError::Degenerate(
            "overlay: the triangulation library failed on these inputs (edges crossing too \
                 near each other for double precision)"
                .into(),
        )
    })?
}

/// The face-by-face overlay when B's domain is convex and rounding never
/// gets in the way (checked exactly); otherwise the constrained
/// triangulation.
fn overlay_dispatch(
    a: &Tin,
    level_a: usize,
    b: &Tin,
    level_b: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Overlay, TinError> {
    if a.bbox.disjoint_xy(&b.bbox) {
        return Ok(Overlay::default()); // disjoint domains
    }
    let why = if faces::convex_domain(b, &b.levels[level_b]) {
        match faces::overlay_faces(a, level_a, b, level_b, interrupt) {
            Ok(o) => return Ok(o),
            Err(faces::Refused::Error(e)) => return Err(e),
            Err(faces::Refused::Rounding(why)) => why,
        }
    } else {
        "b's domain is not convex"
    };
    let mut o = overlay_cdt(a, level_a, b, level_b, interrupt)?;
    o.fallback = Some(why.to_string());
    Ok(o)
}

/// Least heap an overlay of `tris_a` and `tris_b` triangles needs: the
/// output has at least one triangle per input triangle met, each with its
/// vertices, labels and heights. Crossing edges make it larger; that part is
/// bounded while the overlay runs, not here.
pub fn overlay_bytes(tris_a: usize, tris_b: usize) -> usize {
    tris_a.saturating_add(tris_b).saturating_mul(96)
}

#[cfg(test)]
mod tests {

    use super::output::positive_part;

    #[test]
    fn positive_part_of_linear_functions() {
        // f = x on the triangle (0,0), (1,0), (0,1): integral of max(x - 0.5, 0)
        // = integral over x in [0.5, 1] of (x - 0.5)(1 - x) dx = 1/48
        let v = positive_part(0.5, [-0.5, 0.5, -0.5]);
        assert!((v - 1.0 / 48.0).abs() < 1e-15, "{v}");
        // and the other side: integral of max(0.5 - x, 0) = 1/48 + 1/4 - 1/6 ... = total + pos
        let total = 0.5 * (-0.5 + 0.5 - 0.5) / 3.0;
        let n = positive_part(0.5, [0.5, -0.5, 0.5]);
        assert!((n - (v - total)).abs() < 1e-15);
        assert_eq!(positive_part(2.0, [1.0, 1.0, 1.0]), 2.0);
        assert_eq!(positive_part(2.0, [-1.0, 0.0, -1.0]), 0.0);
    }
}
