//! The surface a raster build follows between its samples.
//!
//! On a grid line between two adjacent valid pixel centres a DEM is the
//! straight line between them: `gdal_contour`, bilinear sampling (GDAL's,
//! PostGIS's `ST_Value(..., 'bilinear')`) and every triangulation of the
//! pixels agree there. A tin is linear inside each triangle, so along such
//! a grid segment its largest error is at a pixel centre or where one of its
//! edges crosses the segment. A build therefore measures every edge at its
//! crossings with those segments ([`Reference::for_each_crossing`]) as well
//! as at the samples: together they bound the error on every grid line
//! exactly.
//!
//! ```
//! use tinmerge_core::tin::dense::Dense;
//! use tinmerge_core::tin::surface::{GridReference, Reference};
//! // 3 x 2 pixels: heights 0 1 2 / 10 11 12
//! let d = Dense { c0: 0, r0: 0, width: 3, height: 2, z: vec![0.0, 1.0, 2.0, 10.0, 11.0, 12.0] };
//! let r = GridReference::on_lattice(&d);
//! let mut seen = Vec::new();
//! // from (0, 0) to (2, 1): crosses column 1 at row 0.5
//! r.for_each_crossing(&[0.0, 0.0, 0.0], &[2.0, 1.0, 0.0], &mut |c| seen.push((c.t, c.p)));
//! assert_eq!(seen, [(0.5, [1.0, 0.5, 6.0])]);
//! ```

use super::dense::Dense;
use super::lattice::Lattice;

/// Where an edge crosses a grid segment between two valid pixel centres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Parameter along the edge (0 at its first end, 1 at its second).
    pub t: f64,
    /// The crossing in the build's frame, with the reference's height
    /// there (the two pixels' straight line).
    pub p: [f64; 3],
    /// Pixel centres around the crossing, in the build's frame (bit for
    /// bit the samples' own coordinates), nearest first: the two whose
    /// segment it is, then the four others of the two pixel squares
    /// sharing that segment (some may be off the raster or without data).
    pub pix: [[f64; 2]; 6],
    /// The crossed grid segment: its two pixels (build frame, with their
    /// heights) in order, and the crossing's parameter along it.
    pub seg: [[f64; 3]; 2],
    pub s: f64,
}

impl Crossing {
    /// The error there of the straight edge `a -> b` this crosses (heights
    /// in `a[2]`, `b[2]`).
    pub fn error(&self, a: &[f64; 3], b: &[f64; 3]) -> f64 {
        (a[2] + self.t * (b[2] - a[2]) - self.p[2]).abs()
    }

    /// The point of the crossed grid segment at parameter `s`, with the
    /// reference's height there (the two pixels' line).
    pub fn on_segment(&self, s: f64) -> [f64; 3] {
        let [p, q] = self.seg;
        [
            p[0] + s * (q[0] - p[0]),
            p[1] + s * (q[1] - p[1]),
            p[2] + s * (q[2] - p[2]),
        ]
    }
}

/// A surface a build is measured against between its samples.
pub trait Reference: Sync {
    /// Calls `f` for every crossing strictly inside segment `a -> b` (the
    /// build's frame), in increasing `t`. Crossings within 1e-9 pixel of a
    /// pixel centre are left out (that sample is measured as a sample), and
    /// so are those within 1e-9 pixel of `a` or `b`.
    fn for_each_crossing(&self, a: &[f64; 3], b: &[f64; 3], f: &mut dyn FnMut(&Crossing));

    /// Whether a crossing no sample can mend may be mended by a vertex at
    /// the crossing itself ([`super::build`]'s `AT_CAND`). A raster's grid
    /// segments are mended by their pixels, or a parent's side split where
    /// they cross it; put on a raster build, such vertices made thin
    /// triangles (under 1e-3 pixel high: pg_regress `exactness.sql`), so
    /// only the samples' Delaunay triangulation asks for them.
    fn mends_at_crossings(&self) -> bool {
        false
    }

    /// The surface's height at `(x, y)` where it is defined everywhere
    /// (a triangulation of the samples): soft lines' heights are taken
    /// from it. None where it has none, or where it is defined on grid
    /// lines only (a raster's: the samples around give the height).
    fn height_at(&self, _x: f64, _y: f64) -> Option<f64> {
        None
    }

    /// The largest error of the straight edge `a -> b` (heights in `a[2]`,
    /// `b[2]`) at its crossings, and the worst crossing.
    fn edge_error(&self, a: &[f64; 3], b: &[f64; 3]) -> (f64, Option<Crossing>) {
        let mut worst = (0.0f64, None);
        self.for_each_crossing(a, b, &mut |c| {
            let e = c.error(a, b);
            if e > worst.0 {
                worst = (e, Some(*c));
            }
        });
        worst
    }
}

/// A raster's heights ([`Dense`], NaN without data) as the reference, in
/// its lattice frame (pixel `(col, row)` at `(col, row)`) or, through a
/// [`Lattice`], in world coordinates.
pub struct GridReference<'a> {
    d: &'a Dense,
    /// the build's frame: `None` for the lattice itself
    world: Option<Inverse>,
    /// grid segments left out ([`GridReference::cut_by`]): `(col, row,
    /// axis)` of their first pixel, axis 0 down a column (to `(col, row +
    /// 1)`), 1 along a row (to `(col + 1, row)`)
    cut: rustc_hash::FxHashSet<(i64, i64, u8)>,
    /// pixel centres on those lines (within [`CUT_SLACK`] pixel)
    cut_centres: rustc_hash::FxHashSet<(i64, i64)>,
}

/// Distance in pixels under which a grid segment counts as crossed by a
/// line of [`GridReference::cut_by`]: far above the rounding of world to
/// lattice coordinates, far below any pixel.
pub const CUT_SLACK: f64 = 1e-6;

/// A lattice and its inverse (world to lattice coordinates).
struct Inverse {
    lat: Lattice,
    /// rows of the inverse linear part
    m: [[f64; 2]; 2],
}

impl<'a> GridReference<'a> {
    /// The reference of a build on the lattice itself.
    pub fn on_lattice(d: &'a Dense) -> GridReference<'a> {
        GridReference {
            d,
            world: None,
            cut: Default::default(),
            cut_centres: Default::default(),
        }
    }

    /// The reference of a build on the pixel centres in world coordinates
    /// (`lat.centre(col, row)`, as `tin_from_raster`'s scattered builds
    /// take them).
    pub(crate) fn in_world(d: &'a Dense, lat: Lattice) -> GridReference<'a> {
        let det = lat.det();
        let m = [
            [lat.scale_y / det, -lat.skew_x / det],
            [-lat.skew_y / det, lat.scale_x / det],
        ];
        GridReference {
            d,
            world: Some(Inverse { lat, m }),
            cut: Default::default(),
            cut_centres: Default::default(),
        }
    }

    /// This reference without the grid segments that lines of their own
    /// heights cut: hard breaklines, `lines` in the build's frame (as
    /// segments, each within [`CUT_SLACK`] pixel of a grid segment leaves
    /// it out). On such a segment the surface is the line's, not the two
    /// pixels' line, so it is no measure of the build there.
    ///
    /// ```
    /// use tinmerge_core::tin::dense::Dense;
    /// use tinmerge_core::tin::surface::{GridReference, Reference};
    /// let d = Dense { c0: 0, r0: 0, width: 4, height: 4, z: (0..16).map(f64::from).collect() };
    /// // a line down column 1.5, from row 0.2 to 1.7: it cuts the row
    /// // segments (1, 1) - (2, 1), and no other
    /// let r = GridReference::on_lattice(&d).cut_by(&[([1.5, 0.2], [1.5, 1.7])]);
    /// let mut seen = Vec::new();
    /// r.for_each_crossing(&[0.0, 0.5, 0.0], &[3.0, 1.5, 0.0], &mut |c| seen.push(c.seg));
    /// // crossings of columns 1 and 2 (rows 0 to 1) are kept; row 1 at
    /// // x = 1.5 is cut
    /// assert_eq!(seen.len(), 2);
    /// assert!(seen.iter().all(|s| s[0][0] == s[1][0]));
    /// ```
    pub fn cut_by(mut self, lines: &[([f64; 2], [f64; 2])]) -> GridReference<'a> {
        let e = CUT_SLACK;
        for (a, b) in lines {
            let la = self.to_lattice(&[a[0], a[1], 0.0]);
            let lb = self.to_lattice(&[b[0], b[1], 0.0]);
            if !(la
                .iter()
                .chain(&lb)
                .all(|v| v.is_finite() && v.abs() < 1e12))
            {
                continue;
            }
            let (x0, x1) = (la[0].min(lb[0]), la[0].max(lb[0]));
            let (dx, dy) = (lb[0] - la[0], lb[1] - la[1]);
            // each column of pixel squares the line meets, and there the
            // rows it meets, each grid segment of those squares tested
            let mut c = (x0 - e).floor() as i64;
            while (c as f64) <= x1 + e {
                let (u0, u1) = ((c as f64 - e).max(x0), (c as f64 + 1.0 + e).min(x1));
                let (ya, yb) = if dx.abs() <= f64::EPSILON * (1.0 + x1.abs()) {
                    (la[1], lb[1])
                } else {
                    let y = |x: f64| la[1] + (x - la[0]) / dx * dy;
                    (y(u0), y(u1))
                };
                let (r0, r1) = (
                    (ya.min(yb) - e).floor() as i64,
                    (ya.max(yb) + e).floor() as i64,
                );
                for r in r0..=r1 {
                    if crate::geom::point_segment_distance([c as f64, r as f64], la, lb) <= e {
                        self.cut_centres.insert((c, r));
                    }
                    for (sc, sr, axis) in [(c, r, 0), (c + 1, r, 0), (c, r, 1), (c, r + 1, 1)] {
                        let p = [sc as f64, sr as f64];
                        let q = if axis == 0 {
                            [p[0], p[1] + 1.0]
                        } else {
                            [p[0] + 1.0, p[1]]
                        };
                        if segment_distance(p, q, la, lb) <= e {
                            self.cut.insert((sc, sr, axis));
                        }
                    }
                }
                c += 1;
            }
        }
        self
    }

    /// Whether pixel `(col, row)`'s centre lies on a line of
    /// [`GridReference::cut_by`] (within [`CUT_SLACK`] pixel): the
    /// surface there is the line's.
    pub(crate) fn cuts_centre(&self, col: i64, row: i64) -> bool {
        self.cut_centres.contains(&(col, row))
    }

    /// A point of the build's frame in lattice coordinates.
    #[inline]
    fn to_lattice(&self, p: &[f64; 3]) -> [f64; 2] {
        match &self.world {
            None => [p[0], p[1]],
            Some(inv) => {
                // centre(c, r) = ip + (c + 0.5, r + 0.5) * linear part
                let (x, y) = (p[0] - inv.lat.ip_x, p[1] - inv.lat.ip_y);
                [
                    inv.m[0][0] * x + inv.m[0][1] * y - 0.5,
                    inv.m[1][0] * x + inv.m[1][1] * y - 0.5,
                ]
            }
        }
    }

    /// Pixel centre `(c, r)` in the build's frame.
    #[inline]
    fn centre(&self, c: i64, r: i64) -> [f64; 2] {
        match &self.world {
            None => [c as f64, r as f64],
            Some(inv) => {
                let (x, y) = inv.lat.centre(c as f64, r as f64);
                [x, y]
            }
        }
    }

    /// Height of pixel `(c, r)`, if it is inside and has data.
    #[inline]
    fn z(&self, c: i64, r: i64) -> Option<f64> {
        let d = self.d;
        if c < d.c0 || r < d.r0 || c >= d.c0 + d.width as i64 || r >= d.r0 + d.height as i64 {
            return None;
        }
        let z = d.z[d.index(c, r)];
        (!z.is_nan()).then_some(z)
    }
}

/// Distance from a lattice point under which a crossing is that sample.
const AT_SAMPLE: f64 = 1e-9;

impl Reference for GridReference<'_> {
    fn for_each_crossing(&self, a: &[f64; 3], b: &[f64; 3], f: &mut dyn FnMut(&Crossing)) {
        let (la, lb) = (self.to_lattice(a), self.to_lattice(b));
        let (dx, dy) = (lb[0] - la[0], lb[1] - la[1]);
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        let len = dx.hypot(dy);
        // the columns crossed (x = c) and the rows (y = r), each in the
        // direction of travel, merged by t
        let lines = [axis_lines(la[0], dx), axis_lines(la[1], dy)];
        let mut at = [0usize, 0usize];
        let t_of = |axis: usize, n: usize| -> Option<(f64, i64)> {
            let (first, count, step) = lines[axis];
            if n >= count {
                return None;
            }
            let k = first + step * n as i64;
            let (s, d) = if axis == 0 { (la[0], dx) } else { (la[1], dy) };
            Some(((k as f64 - s) / d, k))
        };
        loop {
            let (ti, tj) = (t_of(0, at[0]), t_of(1, at[1]));
            let (t, axis, k) = match (ti, tj) {
                (None, None) => break,
                (Some((t, k)), None) => (t, 0, k),
                (None, Some((t, k))) => (t, 1, k),
                (Some((t, k)), Some((u, m))) => {
                    if t <= u {
                        (t, 0, k)
                    } else {
                        (u, 1, m)
                    }
                }
            };
            at[axis] += 1;
            // at an end (a vertex at a crossing lies on its grid line up
            // to rounding): that vertex is measured as such
            if !(t * len > AT_SAMPLE && (1.0 - t) * len > AT_SAMPLE) {
                continue;
            }
            // the other lattice coordinate at the crossing
            let o = if axis == 0 {
                la[1] + t * dy
            } else {
                la[0] + t * dx
            };
            let lo = o.floor();
            let s = o - lo;
            if !(AT_SAMPLE..=1.0 - AT_SAMPLE).contains(&s) {
                continue;
            }
            let lo = lo as i64;
            let (p0, p1) = if axis == 0 {
                ((k, lo), (k, lo + 1))
            } else {
                ((lo, k), (lo + 1, k))
            };
            if !self.cut.is_empty() && self.cut.contains(&(p0.0, p0.1, axis as u8)) {
                continue;
            }
            let (Some(z0), Some(z1)) = (self.z(p0.0, p0.1), self.z(p1.0, p1.1)) else {
                continue;
            };
            let z = z0 + s * (z1 - z0);
            let (c0, c1) = (self.centre(p0.0, p0.1), self.centre(p1.0, p1.1));
            // the segment's two pixels, then its neighbours across (unit
            // step perpendicular to the segment), nearest first
            let (near, far) = if s <= 0.5 { (p0, p1) } else { (p1, p0) };
            let step = if axis == 0 { (1, 0) } else { (0, 1) };
            let side = if (if axis == 0 { dx } else { dy }) >= 0.0 {
                1
            } else {
                -1
            };
            let (fw, bw) = (
                (step.0 * side, step.1 * side),
                (-step.0 * side, -step.1 * side),
            );
            let ring = [
                near,
                far,
                (near.0 + fw.0, near.1 + fw.1),
                (near.0 + bw.0, near.1 + bw.1),
                (far.0 + fw.0, far.1 + fw.1),
                (far.0 + bw.0, far.1 + bw.1),
            ];
            let pix = ring.map(|(c, r)| self.centre(c, r));
            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), z];
            let seg = [[c0[0], c0[1], z0], [c1[0], c1[1], z1]];
            f(&Crossing { t, p, pix, seg, s });
        }
    }
}

/// Distance between the closed segments `p -> q` and `a -> b` (geo's:
/// zero where they meet by its robust predicates).
fn segment_distance(p: [f64; 2], q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    use geo::{Distance, Euclidean, Line};
    let line = |u: [f64; 2], v: [f64; 2]| Line::new((u[0], u[1]), (v[0], v[1]));
    Euclidean.distance(&line(p, q), &line(a, b))
}

/// The grid lines one coordinate crosses going from `u` by `d`, strictly
/// between the ends, in the order met: (first, count, step).
#[inline]
fn axis_lines(u: f64, d: f64) -> (i64, usize, i64) {
    let v = u + d;
    if !(u.is_finite() && v.is_finite()) || d.abs() > 1e9 || d == 0.0 {
        return (0, 0, 1);
    }
    let (lo, hi) = (u.min(v), u.max(v));
    let mut a = lo.ceil();
    if a == lo {
        a += 1.0;
    }
    let mut b = hi.floor();
    if b == hi {
        b -= 1.0;
    }
    if a > b {
        return (0, 0, 1);
    }
    let count = (b - a) as usize + 1;
    if d > 0.0 {
        (a as i64, count, 1)
    } else {
        (b as i64, count, -1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_in_order_and_only_between_valid_pixels() {
        // 4 x 4, pixel (2, 1) without data
        let mut z: Vec<f64> = (0..16).map(|i| i as f64).collect();
        z[6] = f64::NAN;
        let d = Dense {
            c0: 0,
            r0: 0,
            width: 4,
            height: 4,
            z,
        };
        let r = GridReference::on_lattice(&d);
        let mut ts = Vec::new();
        r.for_each_crossing(&[0.0, 0.0, 0.0], &[3.0, 2.0, 0.0], &mut |c| {
            ts.push((c.t, c.p))
        });
        // column 1 at t = 1/3 (y = 2/3: pixels (1,0) = 1 and (1,1) = 5);
        // row 1 at t = 1/2 (x = 1.5: pixel (2,1) has no data) and column 2
        // at t = 2/3 (y = 4/3: pixel (2,1) again) are left out
        assert_eq!(ts.len(), 1);
        assert!((ts[0].0 - 1.0 / 3.0).abs() < 1e-15);
        assert!((ts[0].1[2] - (1.0 + 2.0 / 3.0 * 4.0)).abs() < 1e-12);
    }

    #[test]
    fn crossings_in_order_of_travel_both_ways() {
        let d = Dense {
            c0: 0,
            r0: 0,
            width: 8,
            height: 8,
            z: (0..64).map(|i| (i * i % 17) as f64).collect(),
        };
        let r = GridReference::on_lattice(&d);
        let (a, b) = ([6.0, 1.0, 0.0], [1.0, 6.5, 0.0]);
        let mut fw = Vec::new();
        r.for_each_crossing(&a, &b, &mut |c| fw.push(*c));
        let mut bw = Vec::new();
        r.for_each_crossing(&b, &a, &mut |c| bw.push(*c));
        assert!(fw.len() >= 8);
        assert!(fw.windows(2).all(|w| w[0].t < w[1].t));
        assert!(bw.windows(2).all(|w| w[0].t < w[1].t));
        assert_eq!(fw.len(), bw.len());
        for (f, g) in fw.iter().zip(bw.iter().rev()) {
            assert!((f.t - (1.0 - g.t)).abs() < 1e-12);
            assert!((f.p[2] - g.p[2]).abs() < 1e-9);
        }
    }

    #[test]
    fn world_frame_gives_the_samples_bits() {
        let lat = Lattice {
            ip_x: 49_072.339_790_118_44,
            ip_y: 4060000.7,
            scale_x: 30.0,
            scale_y: -30.0,
            skew_x: 0.0,
            skew_y: 0.0,
        };
        let d = Dense {
            c0: 0,
            r0: 0,
            width: 3,
            height: 3,
            z: vec![1.0; 9],
        };
        let r = GridReference::in_world(&d, lat);
        let (ax, ay) = lat.centre(0.0, 0.0);
        let (bx, by) = lat.centre(2.0, 1.0);
        let mut n = 0;
        r.for_each_crossing(&[ax, ay, 1.0], &[bx, by, 1.0], &mut |c| {
            n += 1;
            let want = lat.centre(1.0, 0.0);
            assert_eq!(c.pix[0], [want.0, want.1]);
            assert!((c.p[2] - 1.0).abs() < 1e-12);
        });
        assert_eq!(n, 1);
    }
}
