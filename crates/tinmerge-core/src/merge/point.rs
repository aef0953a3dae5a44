//! Point merge (Scarlatos §6.3): the triangle containing a point, the height of
//! the surface there, and the triangles under a rectangular footprint.
//!
//! Location is the grid index plus an exact walk ([`crate::tin::locate`]);
//! points on an edge or a vertex belong to the closed triangle with the
//! smallest id, so every function here agrees on them.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::point::{height, footprint, Rect};
//! // a plane z = x + 2y sampled on a 10 x 10 grid: one level, exact
//! let mut pts = Vec::new();
//! for i in 0..10 {
//!     for j in 0..10 {
//!         pts.push([i as f64, j as f64, i as f64 + 2.0 * j as f64]);
//!     }
//! }
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let z = height(&tin, 0, 2.5, 3.25).unwrap();
//! assert!((z - 9.0).abs() < 1e-12);
//! assert_eq!(height(&tin, 0, -1.0, 0.0), None);
//! // the plane needs only its four corners: two triangles
//! assert_eq!(tin.levels[0].tris.len(), 2);
//! // a point footprint off the diagonal meets one, the whole square both
//! let r = Rect::new(4.5, 3.0, 0.0, 0.0, 0.0).unwrap();
//! assert_eq!(footprint(&tin, 0, &r, &mut || Ok(())).unwrap().len(), 1);
//! let r = Rect::new(4.5, 4.5, 9.0, 9.0, 0.0).unwrap();
//! assert_eq!(footprint(&tin, 0, &r, &mut || Ok(())).unwrap(), vec![0, 1]);
//! ```

use crate::geom::{co, segments_intersect};
use crate::interrupt::Interrupt;
use crate::tin::locate;
use crate::tin::mesh::{Indexed, infallible};
use crate::tin::{NONE, Tin, TinError, interpolate};
use robust::{Coord, orient2d};
use std::collections::HashSet;

/// Triangle at `level` containing (x, y) (smallest id on shared edges and
/// vertices), or None outside the domain.
#[inline]
pub fn locate(tin: &Tin, level: usize, x: f64, y: f64) -> Option<u32> {
    locate::locate(tin, level, x, y)
}

/// Height of the surface of `level` at (x, y): linear interpolation on the
/// containing triangle; None outside the domain.
#[inline]
pub fn height(tin: &Tin, level: usize, x: f64, y: f64) -> Option<f64> {
    infallible(height_in(tin, level, x, y))
}

/// [`height`] on any indexed mesh (a stored value read in slices:
/// [`crate::tin::sliced`]).
#[inline]
pub fn height_in<M: Indexed>(m: &M, level: usize, x: f64, y: f64) -> Result<Option<f64>, M::Err> {
    Ok(match locate::locate_in(m, level, x, y)? {
        Some(t) => Some(interpolate(&m.corners(level, t)?, x, y)),
        None => None,
    })
}

/// [`height_in`], and for a point off the domain by a rounding (at most
/// [`locate::NEAR_ULPS`] units in the last place), the height of the
/// nearest point of the domain ([`locate::locate_near_in`]): what
/// `tin_height` answers, so that a pixel centre on the edge of the data
/// has its height however its coordinates were rounded. The line and area
/// merges clip to the exact domain.
pub fn height_near_in<M: Indexed>(
    m: &M,
    level: usize,
    x: f64,
    y: f64,
) -> Result<Option<f64>, M::Err> {
    Ok(match locate::locate_near_in(m, level, x, y)? {
        Some((t, qx, qy)) => Some(interpolate(&m.corners(level, t)?, qx, qy)),
        None => None,
    })
}

/// A rectangle `width` across and `length` along the direction `angle`
/// (degrees clockwise from north), centred on (cx, cy).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Corners, counter-clockwise (two or all four coincide when the width
    /// or the length is zero).
    pub corners: [[f64; 2]; 4],
}

impl Rect {
    /// Checked constructor: finite centre and angle, finite non-negative sizes.
    pub fn new(cx: f64, cy: f64, width: f64, length: f64, angle: f64) -> Result<Rect, TinError> {
        for (name, v) in [("width", width), ("length", length)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(TinError::InvalidParameter(format!(
                    "footprint {name} must be a finite number >= 0, got {v}"
                )));
            }
        }
        if !angle.is_finite() {
            return Err(TinError::InvalidParameter(format!(
                "footprint angle must be finite (degrees clockwise from north), got {angle}"
            )));
        }
        if !(cx.is_finite() && cy.is_finite()) {
            return Err(TinError::InvalidParameter(format!(
                "footprint centre must be finite, got ({cx}, {cy})"
            )));
        }
        let (s, c) = angle.to_radians().sin_cos();
        // along = (sin, cos) (north = +y, clockwise), across = (cos, -sin)
        let (ax, ay) = (s * length / 2.0, c * length / 2.0);
        let (wx, wy) = (c * width / 2.0, -s * width / 2.0);
        // back-left, back-right, front-right, front-left: counter-clockwise
        let corners = [
            [cx - ax - wx, cy - ay - wy],
            [cx - ax + wx, cy - ay + wy],
            [cx + ax + wx, cy + ay + wy],
            [cx + ax - wx, cy + ay - wy],
        ];
        Ok(Rect { corners })
    }

    /// [`Rect::new`] with the width and length cut to what can matter for a
    /// tin with bounding box `bbox`: every point of the tin is within `d`
    /// (the distance from the centre to the farthest bbox corner) of the
    /// centre, so its projections on the rectangle's axes are within `d`
    /// too, and half-sizes above `d` select the same triangles. Keeps the
    /// exact predicates away from overflow for huge sizes (1e308 m).
    pub fn within(
        cx: f64,
        cy: f64,
        width: f64,
        length: f64,
        angle: f64,
        bbox: &crate::tin::Bbox,
    ) -> Result<Rect, TinError> {
        let r = Rect::new(cx, cy, width, length, angle)?;
        let d = [
            (bbox.min_x, bbox.min_y),
            (bbox.max_x, bbox.min_y),
            (bbox.max_x, bbox.max_y),
            (bbox.min_x, bbox.max_y),
        ]
        .iter()
        .map(|&(x, y)| (x - cx).hypot(y - cy))
        .fold(0.0f64, f64::max);
        let cap = 2.0 * d * (1.0 + 1e-9) + 1.0;
        if width <= cap && length <= cap {
            return Ok(r);
        }
        Rect::new(cx, cy, width.min(cap), length.min(cap), angle)
    }

    /// Centre of the rectangle.
    pub fn centre(&self) -> (f64, f64) {
        let c = &self.corners;
        ((c[0][0] + c[2][0]) / 2.0, (c[0][1] + c[2][1]) / 2.0)
    }
}

/// Whether the closed counter-clockwise triangle `t` contains p.
#[inline]
fn triangle_contains(t: &[Coord<f64>; 3], p: Coord<f64>) -> bool {
    (0..3).all(|j| orient2d(t[j], t[(j + 1) % 3], p) >= 0.0)
}

/// Exact test: does the closed counter-clockwise triangle `t` meet the
/// closed quadrilateral `q`? Two convex regions meet exactly when one
/// contains a corner of the other or their boundaries cross. A quadrilateral
/// that is not strictly convex (a rectangle of zero width or length, a
/// point) is handled as its boundary segments.
pub(crate) fn triangle_meets_quad(t: &[Coord<f64>; 3], q: &[Coord<f64>; 4]) -> bool {
    if q.iter().any(|&c| triangle_contains(t, c)) {
        return true;
    }
    let proper = (0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], q[(i + 2) % 4]) > 0.0);
    if proper
        && t.iter()
            .any(|&p| (0..4).all(|i| orient2d(q[i], q[(i + 1) % 4], p) >= 0.0))
    {
        return true;
    }
    (0..3).any(|i| (0..4).any(|k| segments_intersect(t[i], t[(i + 1) % 3], q[k], q[(k + 1) % 4])))
}

/// Triangles of `level` whose closed area meets the closed rectangle, in
/// increasing id order. Found by a breadth-first search over neighbours from
/// the triangle under the centre (or, for a centre outside the domain, from
/// the hull triangles the rectangle touches), so the cost follows the answer,
/// not the size of the tin. `interrupt` is called every few thousand steps.
pub fn footprint(
    tin: &Tin,
    level: usize,
    rect: &Rect,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    let lv = &tin.levels[level];
    let r = rect.corners.map(co);
    let tri_of = |t: u32| {
        let c = tin.corners(level, t);
        [
            Coord {
                x: c[0][0],
                y: c[0][1],
            },
            Coord {
                x: c[1][0],
                y: c[1][1],
            },
            Coord {
                x: c[2][0],
                y: c[2][1],
            },
        ]
    };
    let hits = |t: u32| triangle_meets_quad(&tri_of(t), &r);
    let mut seen: HashSet<u32> = HashSet::new();
    let mut queue: Vec<u32> = Vec::new();
    let (cx, cy) = rect.centre();
    // the search runs through void triangles too (the rectangle may meet
    // the domain on both sides of a hole); they are left out at the end
    match infallible(locate::locate_hull_in(tin, level, cx, cy)) {
        Some(t) => queue.push(t),
        None => {
            // Centre outside: the rectangle, if it meets the domain, crosses
            // the hull, so it meets a hull triangle.
            for t in 0..lv.tris.len() as u32 {
                if t % 4096 == 0 {
                    interrupt()?;
                }
                if lv.nbrs[t as usize].contains(&NONE) && hits(t) {
                    queue.push(t);
                }
            }
        }
    }
    for &t in &queue {
        seen.insert(t);
    }
    let mut out = Vec::new();
    let mut head = 0;
    while head < queue.len() {
        let t = queue[head];
        head += 1;
        if head % 4096 == 0 {
            interrupt()?;
        }
        out.push(t);
        for &nb in &lv.nbrs[t as usize] {
            if nb != NONE && !seen.contains(&nb) {
                seen.insert(nb);
                if hits(nb) {
                    queue.push(nb);
                }
            }
        }
    }
    out.retain(|&t| !lv.is_void(t));
    out.sort_unstable();
    Ok(out)
}

/// Top-down location: locate at level 0 with its grid index, then at each
/// finer level test only the children of the triangle found. An alternative
/// to the per-level grid (kept for comparison in the benchmarks and for
/// callers that want every level at once).
#[cfg(feature = "bench")]
pub fn locate_descend(tin: &Tin, level: usize, x: f64, y: f64) -> Option<u32> {
    let mut t = locate::locate(tin, 0, x, y)?;
    for l in 1..=level {
        let prev = &tin.levels[l - 1];
        let (a, b) = (
            prev.child_start[t as usize],
            prev.child_start[t as usize + 1],
        );
        // a parent's children cover it up to rounding only (a vertex at a
        // grid-line crossing lies a rounding off the side it splits): a
        // point on that side can be in the neighbour's children alone
        // (the geographic DEM, level 2)
        match (a..b).find(|&c| locate::contains(tin, l, c, x, y)) {
            Some(c) => t = c,
            None => return locate::locate(tin, level, x, y),
        }
    }
    Some(locate::canonical(tin, level, t, x, y))
}
