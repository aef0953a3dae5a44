//! Breaklines cut to a convex hull ([`clip_to_hull`]): the parts of each
//! line inside the build's domain, heights interpolated where they are cut.

use super::graph::{Breakline, SNAP};
use crate::geom::orient;

/// The parts of `lines` inside the convex polygon `hull` (counter-clockwise,
/// at least 3 corners): each line cut where it leaves the polygon and
/// again where it comes back, the cut a hair inside (at most about 1e-9 of
/// the segment's length) so every point is inside by exact predicates; a
/// hard line's height at a cut interpolated along its segment. A segment
/// inside only up to about 2e-10 of its coordinates' magnitude (a vertex
/// on the hull, the rest outside) gives no piece, and parts of fewer than
/// two distinct points are left out, so a line wholly outside gives
/// nothing.
///
/// ```
/// use tinmerge_core::tin::breaklines::{clip_to_hull, Breakline};
/// let square = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0]];
/// let road = Breakline { pts: vec![[-5.0, 5.0, 0.0], [15.0, 5.0, 20.0]], hard: true };
/// let parts = clip_to_hull(&[road], &square);
/// assert_eq!(parts.len(), 1);
/// let [a, b] = [parts[0].pts[0], parts[0].pts[1]];
/// assert!((a[0] - 0.0).abs() < 1e-6 && (b[0] - 10.0).abs() < 1e-6);
/// assert!((a[2] - 5.0).abs() < 1e-6 && (b[2] - 15.0).abs() < 1e-6);
/// ```
pub fn clip_to_hull(lines: &[Breakline], hull: &[[f64; 3]]) -> Vec<Breakline> {
    let n = hull.len();
    let inside = |p: &[f64; 3]| (0..n).all(|k| orient(&hull[k], &hull[(k + 1) % n], p) >= 0.0);
    let at = |a: &[f64; 3], b: &[f64; 3], t: f64| {
        [
            a[0] + t * (b[0] - a[0]),
            a[1] + t * (b[1] - a[1]),
            a[2] + t * (b[2] - a[2]),
        ]
    };
    // a cut point at t, moved towards `toward` (the inside) until it is
    // inside
    let cut = |a: &[f64; 3], b: &[f64; 3], t: f64, toward: f64| -> Option<[f64; 3]> {
        let mut eps = 0.0;
        for _ in 0..40 {
            let u = t + (toward - t).signum() * eps;
            if (u - toward) * (t - toward) < 0.0 {
                return None;
            }
            let p = at(a, b, u);
            if inside(&p) {
                return Some(p);
            }
            eps = if eps == 0.0 { 1e-15 } else { eps * 2.0 };
        }
        None
    };
    let mut out = Vec::new();
    for line in lines {
        if line.pts.iter().all(&inside) {
            out.push(line.clone());
            continue;
        }
        let mut part: Vec<[f64; 3]> = Vec::new();
        let mut flush = |part: &mut Vec<[f64; 3]>| {
            part.dedup_by(|x, y| x[..2] == y[..2]);
            if part.len() >= 2 {
                out.push(Breakline {
                    pts: std::mem::take(part),
                    hard: line.hard,
                });
            }
            part.clear();
        };
        for w in line.pts.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            // the interval of t in which a-b is inside every side
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            for k in 0..n {
                let (fa, fb) = (
                    orient(&hull[k], &hull[(k + 1) % n], a),
                    orient(&hull[k], &hull[(k + 1) % n], b),
                );
                if fa < 0.0 && fb < 0.0 {
                    (t0, t1) = (1.0, 0.0);
                    break;
                }
                if fa >= 0.0 && fb >= 0.0 {
                    continue;
                }
                let t = fa / (fa - fb);
                if fa < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
            if t0 >= t1 {
                flush(&mut part);
                continue;
            }
            let mid = 0.5 * (t0 + t1);
            let start = if t0 > 0.0 || !inside(a) {
                cut(a, b, t0, mid)
            } else {
                Some(*a)
            };
            let end = if t1 < 1.0 || !inside(b) {
                cut(a, b, t1, mid)
            } else {
                Some(*b)
            };
            let (Some(p), Some(q)) = (start, end) else {
                flush(&mut part);
                continue;
            };
            // a cut within about a millimetre (at 1e6 m coordinates) of
            // the segment's inside end: only that end is inside, and a
            // piece that short would lie "on" every line near it up to
            // rounding
            let m = p[0].abs().max(p[1].abs()).max(1.0);
            if (p[0] - q[0]).abs().max((p[1] - q[1]).abs()) <= SNAP * m {
                flush(&mut part);
                continue;
            }
            if part.last().is_none_or(|l| l[..2] != p[..2]) {
                flush(&mut part);
                part.push(p);
            }
            part.push(q);
            if q[..2] != b[..2] {
                flush(&mut part);
            }
        }
        flush(&mut part);
    }
    out
}
