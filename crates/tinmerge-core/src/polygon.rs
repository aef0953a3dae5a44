//! A polygonal area for the area merge: its rings oriented so the interior
//! is on the left of every ring (outer rings counter-clockwise, holes
//! clockwise), and an exact point-in-polygon test through a strip index.
//!
//! The test casts a ray to +x and counts ring segments crossing it, deciding
//! every crossing with `robust::orient2d` on the input coordinates, so a
//! point is classified exactly (inside, outside, or on the boundary). The
//! index cuts the area's y-range into horizontal strips and lists for each
//! strip the segments whose y-range meets it, so a test reads only the
//! segments near the point's y.
//!
//! The area is taken as valid (OGC: rings simple, holes inside their shell,
//! parts not overlapping); the SQL layer checks that with PostGIS's
//! `ST_IsValidReason` first. An invalid area gives wrong answers, never a
//! crash.
//!
//! ```
//! use tinmerge_core::polygon::{Area, Where};
//! let square = vec![vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [0.0, 0.0]]];
//! let hole = vec![[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0], [1.0, 1.0]];
//! let mut poly = square;
//! poly.push(hole);
//! let a = Area::new(vec![poly]);
//! assert_eq!(a.locate([3.0, 3.0]), Where::Inside);
//! assert_eq!(a.locate([1.5, 1.5]), Where::Outside);
//! assert_eq!(a.locate([4.0, 2.0]), Where::Boundary);
//! assert_eq!(a.locate([9.0, 2.0]), Where::Outside);
//! ```

use crate::geom::P2;
use crate::geom::{bbox2, co};
use robust::orient2d;

/// Where a point lies relative to the area (closed: the boundary belongs to
/// it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Where {
    Inside,
    Outside,
    Boundary,
}

/// Twice the signed area of a closed ring (positive counter-clockwise),
/// summed relative to its first point.
pub fn ring_area2(r: &[P2]) -> f64 {
    let Some(o) = r.first() else {
        return 0.0;
    };
    r.windows(2)
        .map(|w| {
            let (a, b) = (
                [w[0][0] - o[0], w[0][1] - o[1]],
                [w[1][0] - o[0], w[1][1] - o[1]],
            );
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

/// A polygonal area (POLYGON or MULTIPOLYGON) with its strip index.
#[derive(Clone, Debug)]
pub struct Area {
    /// Closed rings, interior on the left.
    pub rings: Vec<Vec<P2>>,
    /// min x, min y, max x, max y of all rings.
    pub bbox: [f64; 4],
    strip_y0: f64,
    strip_h: f64,
    nstrips: usize,
    /// Strip k lists `entries[offsets[k]..offsets[k + 1]]` as (ring, segment).
    offsets: Vec<u32>,
    entries: Vec<(u32, u32)>,
    /// Per ring, the bounding box (min x, min y, max x, max y) of each run
    /// of [`RUN`] consecutive segments: a merge over a small part of a large
    /// polygon (one tile of a county) skips the runs that miss it.
    runs: Vec<Vec<[f64; 4]>>,
}

/// Segments in a run of [`Area::run_box`].
pub const RUN: usize = 32;

/// The points of run `k` of closed ring `r`: its segments' ends.
fn run_points(r: &[P2], k: usize) -> &[P2] {
    &r[k * RUN..r.len().min((k + 1) * RUN + 1)]
}

impl Area {
    /// An area from polygons given as rings (the first of each polygon its
    /// shell, the others holes). Rings are closed if open and oriented;
    /// rings with fewer than 3 distinct positions are dropped (they bound
    /// nothing).
    pub fn new(polygons: Vec<Vec<Vec<P2>>>) -> Area {
        let mut rings = Vec::new();
        for poly in polygons {
            for (i, mut r) in poly.into_iter().enumerate() {
                if r.len() < 3 {
                    continue;
                }
                if r.first() != r.last() {
                    let f = r[0];
                    r.push(f);
                }
                if r.len() < 4 {
                    continue;
                }
                let a = ring_area2(&r);
                if a == 0.0 {
                    continue;
                }
                let shell = i == 0;
                if (shell && a < 0.0) || (!shell && a > 0.0) {
                    r.reverse();
                }
                rings.push(r);
            }
        }
        let mut bbox = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut nseg = 0usize;
        for r in &rings {
            nseg += r.len() - 1;
            for p in r {
                bbox[0] = bbox[0].min(p[0]);
                bbox[1] = bbox[1].min(p[1]);
                bbox[2] = bbox[2].max(p[0]);
                bbox[3] = bbox[3].max(p[1]);
            }
        }
        let runs = rings
            .iter()
            .map(|r| {
                (0..(r.len() - 1).div_ceil(RUN))
                    .map(|k| bbox2(run_points(r, k).iter().copied()))
                    .collect()
            })
            .collect();
        let mut area = Area {
            rings,
            bbox,
            strip_y0: bbox[1],
            strip_h: 0.0,
            nstrips: 1,
            offsets: vec![0, 0],
            entries: Vec::new(),
            runs,
        };
        if nseg == 0 {
            return area;
        }
        let span = bbox[3] - bbox[1];
        let strips = nseg.clamp(1, 1 << 16);
        area.strip_h = if span > 0.0 {
            span / strips as f64
        } else {
            0.0
        };
        let nstrips = if area.strip_h > 0.0 { strips } else { 1 };
        area.nstrips = nstrips;
        // counting pass, then fill (CSR)
        let mut counts = vec![0u32; nstrips + 1];
        area.each_segment_strips(|_, _, lo, hi| {
            for k in lo..=hi {
                counts[k + 1] += 1;
            }
        });
        for k in 0..nstrips {
            counts[k + 1] += counts[k];
        }
        let mut fill = counts.clone();
        let mut entries = vec![(0u32, 0u32); counts[nstrips] as usize];
        area.each_segment_strips(|r, s, lo, hi| {
            for f in &mut fill[lo..=hi] {
                entries[*f as usize] = (r as u32, s as u32);
                *f += 1;
            }
        });
        area.offsets = counts;
        area.entries = entries;
        area
    }

    /// The bounding box (min x, min y, max x, max y) of ring `r`'s segments
    /// `k * RUN .. (k + 1) * RUN` (fewer in its last run); None past the
    /// ring's last.
    pub fn run_box(&self, r: usize, k: usize) -> Option<[f64; 4]> {
        self.runs.get(r)?.get(k).copied()
    }

    /// Whether the area has no ring left.
    pub fn is_empty(&self) -> bool {
        self.rings.is_empty()
    }

    fn strip_of(&self, y: f64) -> usize {
        let n = self.nstrips;
        if self.strip_h <= 0.0 {
            return 0;
        }
        // (truncation is the floor of a positive k, without a libm call)
        let k = (y - self.strip_y0) / self.strip_h;
        if k > 0.0 { (k as usize).min(n - 1) } else { 0 }
    }

    fn each_segment_strips(&self, mut f: impl FnMut(usize, usize, usize, usize)) {
        for (ri, r) in self.rings.iter().enumerate() {
            for s in 0..r.len() - 1 {
                let (y0, y1) = (r[s][1].min(r[s + 1][1]), r[s][1].max(r[s + 1][1]));
                f(ri, s, self.strip_of(y0), self.strip_of(y1));
            }
        }
    }

    /// Whether the closed rectangle `b` (min x, min y, max x, max y, with
    /// min < max) lies within the area: no ring segment meets its open
    /// inside and its centre is inside ([`Area::box_side`]). Then every
    /// triangle in it is wholly inside, as the area sweep decides.
    pub fn contains_box(&self, b: [f64; 4]) -> bool {
        let [x0, y0, x1, y1] = b;
        if x0 < self.bbox[0] || y0 < self.bbox[1] || x1 > self.bbox[2] || y1 > self.bbox[3] {
            return false;
        }
        self.box_side(b) == Some(Where::Inside)
    }

    /// Whether the open inside of the rectangle `b` (min < max) lies
    /// outside the area ([`Area::box_relation`]). Then nothing of the area
    /// lies in the rectangle but parts of its edges, which bound no area (a
    /// tile met by a polygon's bounding box only).
    pub fn misses_box(&self, b: [f64; 4]) -> bool {
        self.box_relation(b) == Some(Where::Outside)
    }

    /// Where the open inside of the rectangle `b` (min x, min y, max x,
    /// max y) lies: `Outside` when it misses the area's bounding box or no
    /// ring segment meets it and its centre is outside, `Inside` when no
    /// segment meets it and its centre is inside ([`Area::box_side`]);
    /// None when a segment meets it, or `b` is empty.
    pub fn box_relation(&self, b: [f64; 4]) -> Option<Where> {
        let [x0, y0, x1, y1] = b;
        if !(x0 < x1 && y0 < y1) {
            return None;
        }
        if self.rings.is_empty()
            || x1 <= self.bbox[0]
            || x0 >= self.bbox[2]
            || y1 <= self.bbox[1]
            || y0 >= self.bbox[3]
        {
            return Some(Where::Outside);
        }
        self.box_side(b)
    }

    /// Which side of the area the open inside of the rectangle `b` (min x,
    /// min y, max x, max y, min < max) lies on, when no ring segment meets
    /// it (exact separating axes: the rectangle's sides and the segment's
    /// line): its centre's; None when a segment meets it (or `b` is empty).
    pub fn box_side(&self, b: [f64; 4]) -> Option<Where> {
        let [x0, y0, x1, y1] = b;
        if self.rings.is_empty() || !(x0 < x1 && y0 < y1) {
            return None;
        }
        let corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]].map(co);
        let meets = |a: P2, q: P2| {
            if a[0].max(q[0]) <= x0 || a[0].min(q[0]) >= x1 {
                return false;
            }
            if a[1].max(q[1]) <= y0 || a[1].min(q[1]) >= y1 {
                return false;
            }
            let o = corners.map(|c| orient2d(co(a), co(q), c));
            !(o.iter().all(|&v| v >= 0.0) || o.iter().all(|&v| v <= 0.0))
        };
        // the runs of segments whose box reaches the rectangle's open inside
        for (ring, runs) in self.rings.iter().zip(&self.runs) {
            for (k, rb) in runs.iter().enumerate() {
                if rb[2] <= x0 || rb[0] >= x1 || rb[3] <= y0 || rb[1] >= y1 {
                    continue;
                }
                if run_points(ring, k).windows(2).any(|w| meets(w[0], w[1])) {
                    return None;
                }
            }
        }
        // (the centre is in the open inside, which no segment meets: not
        // on the boundary)
        Some(self.locate([(x0 + x1) / 2.0, (y0 + y1) / 2.0]))
    }

    /// Exact point-in-polygon test.
    pub fn locate(&self, p: P2) -> Where {
        if self.rings.is_empty()
            || p[0] < self.bbox[0]
            || p[0] > self.bbox[2]
            || p[1] < self.bbox[1]
            || p[1] > self.bbox[3]
        {
            return Where::Outside;
        }
        let k = self.strip_of(p[1]);
        let (s, e) = (self.offsets[k] as usize, self.offsets[k + 1] as usize);
        let cp = co(p);
        let mut inside = false;
        for &(r, i) in &self.entries[s..e] {
            let ring = &self.rings[r as usize];
            let (a, b) = (ring[i as usize], ring[i as usize + 1]);
            if (a[1] > p[1] && b[1] > p[1]) || (a[1] < p[1] && b[1] < p[1]) {
                continue;
            }
            let o = orient2d(co(a), co(b), cp);
            if o == 0.0 && a[0].min(b[0]) <= p[0] && p[0] <= a[0].max(b[0]) {
                return Where::Boundary;
            }
            if (a[1] <= p[1] && p[1] < b[1] && o > 0.0) || (b[1] <= p[1] && p[1] < a[1] && o < 0.0)
            {
                inside = !inside;
            }
        }
        if inside {
            Where::Inside
        } else {
            Where::Outside
        }
    }
}

/// Whether the closed segment a-b meets the open inside of the
/// counter-clockwise triangle `t` (exact: separating axes among the
/// triangle's edges and the segment's line).
pub fn segment_meets_open_triangle(t: &[P2; 3], a: P2, b: P2) -> bool {
    let tc = t.map(co);
    let (ca, cb) = (co(a), co(b));
    for j in 0..3 {
        let (u, v) = (tc[j], tc[(j + 1) % 3]);
        if orient2d(u, v, ca) <= 0.0 && orient2d(u, v, cb) <= 0.0 {
            return false;
        }
    }
    if a == b {
        return true;
    }
    let o = tc.map(|v| orient2d(ca, cb, v));
    !(o.iter().all(|&x| x >= 0.0) || o.iter().all(|&x| x <= 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_touching_a_corner_does_not_meet_the_inside() {
        let t = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(!segment_meets_open_triangle(&t, [-1.0, 1.0], [1.0, -1.0]));
        assert!(!segment_meets_open_triangle(&t, [0.0, 0.0], [1.0, 0.0]));
        assert!(!segment_meets_open_triangle(&t, [2.0, 0.0], [-1.0, 0.0]));
        assert!(segment_meets_open_triangle(&t, [0.1, 0.1], [0.1, 0.1]));
        assert!(!segment_meets_open_triangle(&t, [0.5, 0.5], [0.5, 0.5]));
        assert!(segment_meets_open_triangle(&t, [-1.0, 0.2], [2.0, 0.2]));
        assert!(segment_meets_open_triangle(&t, [0.0, 0.0], [1.0, 1.0]));
    }

    /// A comb-shaped ring in 0..10: teeth x in [2k+1.5, 2k+2.5] (and the
    /// edges), gaps x in (2k+0.5, 2k+1.5) above y = 3.
    fn comb() -> Vec<P2> {
        let mut r = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]];
        for k in (0..5).rev() {
            let x = 2.0 * k as f64;
            r.push([x + 1.5, 10.0]);
            r.push([x + 1.5, 3.0]);
            r.push([x + 0.5, 3.0]);
            r.push([x + 0.5, 10.0]);
        }
        r.push([0.0, 10.0]);
        r.push([0.0, 0.0]);
        r
    }

    /// Brute-force parity: whether a ray from `p` to +x crosses the ring
    /// an odd number of times (for points off the ring).
    fn odd_crossings(r: &[P2], p: P2) -> bool {
        let mut n = 0;
        for w in r.windows(2) {
            let (a, b) = (w[0], w[1]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if x > p[0] {
                    n += 1;
                }
            }
        }
        n % 2 == 1
    }

    #[test]
    fn locate_matches_brute_force_parity() {
        // the comb, points on a fine lattice (many on the boundary)
        let r = comb();
        let a = Area::new(vec![vec![r.clone()]]);
        for i in -2..=42 {
            for j in -2..=42 {
                let p = [i as f64 * 0.25, j as f64 * 0.25];
                let on = r.windows(2).any(|w| {
                    orient2d(co(w[0]), co(w[1]), co(p)) == 0.0
                        && w[0][0].min(w[1][0]) <= p[0]
                        && p[0] <= w[0][0].max(w[1][0])
                        && w[0][1].min(w[1][1]) <= p[1]
                        && p[1] <= w[0][1].max(w[1][1])
                });
                let want = if on {
                    Where::Boundary
                } else if odd_crossings(&r, p) {
                    Where::Inside
                } else {
                    Where::Outside
                };
                assert_eq!(a.locate(p), want, "{p:?}");
            }
        }
    }

    /// Boxes against the comb of the test above: one held by a tooth, one
    /// in a gap between teeth (inside the polygon's bounding box, outside
    /// the polygon), one touching a tooth's side from the gap, one across
    /// a tooth; and every box of a lattice checked against point samples
    /// of its inside by brute-force parity (what a box is said to be
    /// inside or outside of, its samples are).
    #[test]
    fn boxes_held_missed_or_crossed() {
        let r = comb();
        let a = Area::new(vec![vec![r.clone()]]);
        assert!(a.contains_box([2.0, 4.0, 2.4, 9.0]));
        assert!(!a.misses_box([2.0, 4.0, 2.4, 9.0]));
        assert!(a.misses_box([0.7, 4.0, 1.3, 9.0]));
        assert!(!a.contains_box([0.7, 4.0, 1.3, 9.0]));
        assert!(
            a.misses_box([0.5, 3.0, 1.5, 10.0]),
            "touching the gap's sides and floor"
        );
        assert!(!a.misses_box([1.0, 4.0, 2.0, 9.0]) && !a.contains_box([1.0, 4.0, 2.0, 9.0]));
        assert!(a.misses_box([20.0, 20.0, 21.0, 21.0]));
        let parity = |p: P2| odd_crossings(&r, p);
        let (mut held, mut missed) = (0, 0);
        for i in -2..44 {
            for j in -2..44 {
                for (w, h) in [(1, 1), (2, 3), (4, 1), (1, 6)] {
                    let b = [
                        i as f64 * 0.25,
                        j as f64 * 0.25,
                        (i + w) as f64 * 0.25,
                        (j + h) as f64 * 0.25,
                    ];
                    let (c, m) = (a.contains_box(b), a.misses_box(b));
                    assert!(!(c && m), "{b:?}");
                    // samples strictly inside the box, off the 0.25 lattice
                    for fx in [0.13, 0.5, 0.87] {
                        for fy in [0.11, 0.5, 0.89] {
                            let p = [b[0] + fx * (b[2] - b[0]), b[1] + fy * (b[3] - b[1])];
                            if c {
                                assert!(parity(p), "{b:?} held, {p:?} outside");
                            }
                            if m {
                                assert!(!parity(p), "{b:?} missed, {p:?} inside");
                            }
                        }
                    }
                    held += c as usize;
                    missed += m as usize;
                }
            }
        }
        assert!(held > 500 && missed > 2000, "{held} held, {missed} missed");
    }
}
