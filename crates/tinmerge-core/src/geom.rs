//! Geometric primitives shared by every algorithm, in one place (as spade's
//! `math.rs`): the 2D point type, the adapter to the `robust` crate's exact
//! predicates, orientation with and without the slack rounding can explain,
//! triangle area, segment tests and crossings.
//!
//! ```
//! use tinmerge_core::geom::{co, orient, tri_area, segments_intersect};
//! let (a, b, c) = ([0.0, 0.0, 5.0], [2.0, 0.0, 1.0], [0.0, 2.0, 0.0]);
//! assert!(orient(&a, &b, &c) > 0.0); // counter-clockwise
//! assert_eq!(tri_area(&[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]), 2.0);
//! assert!(segments_intersect(co([0.0, 0.0]), co([2.0, 2.0]), co([0.0, 2.0]), co([2.0, 0.0])));
//! ```

use robust::{Coord, orient2d};

/// A point in the plane (x, y).
pub type P2 = [f64; 2];

/// A plane point as the `robust` crate's coordinate.
#[inline]
pub fn co(p: P2) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

/// A vertex (x, y, z) as the `robust` crate's coordinate (z dropped).
#[inline]
pub(crate) fn vco(v: &[f64; 3]) -> Coord<f64> {
    Coord { x: v[0], y: v[1] }
}

/// The bounding box `[min x, min y, max x, max y]` of points (infinite,
/// min above max, for none).
pub fn bbox2(pts: impl Iterator<Item = [f64; 2]>) -> [f64; 4] {
    pts.fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        },
    )
}

/// The plane point of a vertex (x, y, z).
#[inline]
pub fn xy(v: &[f64; 3]) -> P2 {
    [v[0], v[1]]
}

/// Planar distance.
#[inline]
pub fn dist(a: P2, b: P2) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// Signed area of a triangle (positive counter-clockwise), rounded.
#[inline]
pub fn tri_area(t: &[P2; 3]) -> f64 {
    ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1])) / 2.0
}

/// How far from zero `orient2d(a, b, c)` (twice the signed area of a, b, c)
/// can be pushed by rounding the coordinates of the three points to
/// doubles: a generous bound (64 ulps of the largest coordinate, times the
/// side lengths). A triangle whose area is within it is degenerate up to
/// rounding (a *sliver*: its third corner lies on the opposite edge); a
/// point within it of an edge is on that edge up to rounding.
///
/// ```
/// use tinmerge_core::geom::{is_sliver, orient_slack};
/// let (a, b) = ([67072.33979011845, 118745.07014525152, 0.0], [68672.33979011845, 117145.07014525152, 0.0]);
/// let c = [65472.33979011844, 120345.07014525152, 0.0];  // collinear on the pixel lattice
/// assert!(is_sliver(&a, &b, &c));
/// assert!(!is_sliver(&a, &b, &[65472.0, 120346.0, 0.0]));
/// assert!(orient_slack(&a, &b, &c) < 1e-3);
/// ```
#[inline]
pub fn orient_slack(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let m = max_abs_xy(a, b, c);
    let d = |p: &[f64; 3], q: &[f64; 3]| (p[0] - q[0]).abs().max((p[1] - q[1]).abs());
    64.0 * f64::EPSILON * m * (d(a, b) + d(b, c) + d(c, a))
}

/// Largest |x| or |y| of three points: the magnitude their rounding is
/// relative to.
#[inline]
pub(crate) fn max_abs_xy(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    a[0].abs()
        .max(a[1].abs())
        .max(b[0].abs())
        .max(b[1].abs())
        .max(c[0].abs())
        .max(c[1].abs())
}

/// `orient2d(a, b, c)` by the exact predicate, as a plain number.
#[inline]
pub fn orient(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    orient2d(vco(a), vco(b), vco(c))
}

/// Whether triangle a, b, c has zero area up to rounding (see
/// [`orient_slack`]).
#[inline]
pub fn is_sliver(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    within_roundings(a, b, c, 1.0)
}

/// Whether c is within `k` roundings ([`orient_slack`]) of the line
/// through a and b: [`is_sliver`] with `k` 1.
#[inline]
pub(crate) fn within_roundings(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], k: f64) -> bool {
    orient(a, b, c).abs() <= k * orient_slack(a, b, c)
}

/// The largest |coordinate| a point may have for [`whole`] to give it:
/// below it a triangle of whole points has its rounding
/// ([`orient_slack`]) under one unit of orientation, so "left or on up
/// to rounding" is exactly "left or on", and [`in_circle`]'s determinant
/// fits an `i128`.
pub(crate) const WHOLE: f64 = (1u64 << 20) as f64;

/// The point's x and y as integers, when both are whole numbers under
/// [`WHOLE`] (a pixel centre in lattice coordinates).
#[inline]
pub(crate) fn whole(p: &[f64; 3]) -> Option<[i64; 2]> {
    let ok = |v: f64| v.abs() < WHOLE && v == (v as i64) as f64;
    (ok(p[0]) && ok(p[1])).then(|| [p[0] as i64, p[1] as i64])
}

/// Whether d lies strictly inside the circle through the
/// counter-clockwise a, b, c, exactly: in integers when all four are
/// [`whole`] (lattice points are often cocircular, where the adaptive
/// float test is slowest; in `i64` when a, b and c are within 2^14 of d,
/// else in `i128`), else by `robust::incircle`.
pub(crate) fn in_circle(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> bool {
    if let (Some(a), Some(b), Some(c), Some(d)) = (whole(a), whole(b), whole(c), whole(d)) {
        let rel = |p: [i64; 2]| [p[0] - d[0], p[1] - d[1]];
        let (a, b, c) = (rel(a), rel(b), rel(c));
        // within 2^14 of d (every triangle but the first few of a big
        // band): each product under 2^58, the sum of three fits an i64
        let near = |p: [i64; 2]| p[0].abs() < 1 << 14 && p[1].abs() < 1 << 14;
        if near(a) && near(b) && near(c) {
            let lift = |p: [i64; 2]| p[0] * p[0] + p[1] * p[1];
            let cross = |p: [i64; 2], q: [i64; 2]| p[0] * q[1] - p[1] * q[0];
            let det = lift(a) * cross(b, c) + lift(b) * cross(c, a) + lift(c) * cross(a, b);
            return det > 0;
        }
        let rel = |p: [i64; 2]| [p[0] as i128, p[1] as i128];
        let (a, b, c) = (rel(a), rel(b), rel(c));
        let lift = |p: [i128; 2]| p[0] * p[0] + p[1] * p[1];
        let cross = |p: [i128; 2], q: [i128; 2]| p[0] * q[1] - p[1] * q[0];
        let det = lift(a) * cross(b, c) + lift(b) * cross(c, a) + lift(c) * cross(a, b);
        return det > 0;
    }
    robust::incircle(vco(a), vco(b), vco(c), vco(d)) > 0.0
}

/// `v.floor()` without a call into libm (the baseline x86-64 target has
/// no rounding instruction), for |v| < 2^63.
#[inline]
pub(crate) fn floor_fast(v: f64) -> f64 {
    let t = (v as i64) as f64;
    if t > v { t - 1.0 } else { t }
}

/// Whether c lies strictly between a and b along the line from a to b
/// (its projection on that line inside the open segment).
#[inline]
pub(crate) fn strictly_between(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    (c[0] - a[0]) * dx + (c[1] - a[1]) * dy > 0.0 && (b[0] - c[0]) * dx + (b[1] - c[1]) * dy > 0.0
}

/// How many roundings ([`orient_slack`]) a child's vertex may lie outside
/// its parent's edge: a sample a rounding or two beside a coarse edge
/// (pixel centres on one scan line, collinear only up to rounding) splits
/// that edge at itself; every triangle beside it would otherwise be too
/// flat to split again (harness seeds 143164, 158431).
pub(crate) const BEND: f64 = 4.0;

/// Whether c is left of or on the line a -> b, up to rounding.
#[inline]
pub(crate) fn left_or_on_rounded(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    left_or_within_roundings(a, b, c, 1.0)
}

/// Whether c is left of the line a -> b or within `k` roundings
/// ([`orient_slack`]) right of it.
#[inline]
pub(crate) fn left_or_within_roundings(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], k: f64) -> bool {
    // the float determinant is within orient2d's error bound of the
    // exact one, and that bound is under one rounding: not negative, it
    // says yes, without the exact test or the slack
    let det = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
    if det >= 0.0 && k >= 1.0 {
        return true;
    }
    orient(a, b, c) >= -k * orient_slack(a, b, c)
}

/// Distance from p to the closed segment ab.
pub(crate) fn point_segment_distance(p: P2, a: P2, b: P2) -> f64 {
    point_segment_nearest(p, a, b).0
}

/// Distance from p to the closed segment ab, and where on it the nearest
/// point is (0 at a, 1 at b).
pub(crate) fn point_segment_nearest(p: P2, a: P2, b: P2) -> (f64, f64) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let s = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p[0] - a[0] - s * dx).hypot(p[1] - a[1] - s * dy), s)
}

/// Whether p, known to be collinear with a and b, lies on the closed segment.
#[inline]
fn on_segment(a: Coord<f64>, b: Coord<f64>, p: Coord<f64>) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Exact test: do segments p1p2 and q1q2 cross properly (each has its ends
/// strictly on both sides of the other's line)?
pub(crate) fn segments_cross(
    p1: Coord<f64>,
    p2: Coord<f64>,
    q1: Coord<f64>,
    q2: Coord<f64>,
) -> bool {
    let (d1, d2) = (orient2d(q1, q2, p1), orient2d(q1, q2, p2));
    let (d3, d4) = (orient2d(p1, p2, q1), orient2d(p1, p2, q2));
    ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
}

/// Exact test: do the closed segments p1p2 and q1q2 meet?
pub fn segments_intersect(p1: Coord<f64>, p2: Coord<f64>, q1: Coord<f64>, q2: Coord<f64>) -> bool {
    if segments_cross(p1, p2, q1, q2) {
        return true;
    }
    let d1 = orient2d(q1, q2, p1);
    let d2 = orient2d(q1, q2, p2);
    let d3 = orient2d(p1, p2, q1);
    let d4 = orient2d(p1, p2, q2);
    (d1 == 0.0 && on_segment(q1, q2, p1))
        || (d2 == 0.0 && on_segment(q1, q2, p2))
        || (d3 == 0.0 && on_segment(p1, p2, q1))
        || (d4 == 0.0 && on_segment(p1, p2, q2))
}

/// Position of `p` along the segment `a`–`b` (z ignored): 0 at `a`, 1 at
/// `b`, by projection onto the segment's line.
pub fn param_along(a: &[f64; 3], b: &[f64; 3], p: P2) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
}

/// Height at `p` of the segment `a`–`b` taken as a line in 3D, `p`
/// projected onto it and held to the segment: the height of a point on
/// an edge (a crossing, a vertex on it up to rounding) from that edge's
/// ends alone, whatever triangle the point would be located in.
///
/// ```
/// use tinmerge_core::geom::z_along;
/// assert_eq!(z_along(&[0.0, 0.0, 10.0], &[4.0, 0.0, 20.0], [1.0, 0.0]), 12.5);
/// assert_eq!(z_along(&[0.0, 0.0, 10.0], &[4.0, 0.0, 20.0], [9.0, 0.0]), 20.0);
/// ```
pub fn z_along(a: &[f64; 3], b: &[f64; 3], p: P2) -> f64 {
    let t = param_along(a, b, p).clamp(0.0, 1.0);
    a[2] + t * (b[2] - a[2])
}

/// Crossing point of segment pq with segment uv, known to cross properly
/// (all four orientations non-zero). Callers that need the same point
/// whoever asks (the overlay) give the ends of both segments in a canonical
/// order.
pub fn crossing(p: P2, q: P2, u: P2, v: P2) -> P2 {
    let op = orient2d(co(u), co(v), co(p));
    let oq = orient2d(co(u), co(v), co(q));
    let t = (op / (op - oq)).clamp(0.0, 1.0);
    [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
}

/// Whether a closed ring (its first point repeated last; z ignored) bounds a
/// strictly convex polygon: at least three corners, every corner turning the
/// same way by the exact orientation (no collinear corner; a point repeated
/// right after itself counts once), and
/// the ring going round once (a pentagram turns one way at every corner but
/// goes round twice). Such a ring is simple, so a polygon with it as its only
/// ring is valid in PostGIS's sense: the area functions skip asking GEOS for
/// it. Any ring this does not vouch for (non-finite coordinates included)
/// gets `false`, never an error.
///
/// ```
/// use tinmerge_core::geom::is_strictly_convex_ring;
/// let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
/// assert!(is_strictly_convex_ring(&square));
/// let bowtie = [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
/// assert!(!is_strictly_convex_ring(&bowtie));
/// // a 2D ring as the readers give it: z is NaN
/// let flat = square.map(|p| [p[0], p[1], f64::NAN]);
/// assert!(is_strictly_convex_ring(&flat));
/// ```
pub fn is_strictly_convex_ring(ring: &[[f64; 3]]) -> bool {
    let n = ring.len();
    // closed in x, y (a 2D ring's z is NaN, which equals nothing)
    if n < 4
        || ring[0][..2] != ring[n - 1][..2]
        || ring.iter().any(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return false;
    }
    // the corners, a point repeated right after itself counted once (as
    // PostGIS and GEOS count it)
    let mut corners: Vec<[f64; 3]> = Vec::with_capacity(n - 1);
    for p in &ring[..n - 1] {
        if corners.last().is_none_or(|q| q[..2] != p[..2]) {
            corners.push(*p);
        }
    }
    while corners.len() > 1 && corners[0][..2] == corners[corners.len() - 1][..2] {
        corners.pop();
    }
    let m = corners.len();
    if m < 3 {
        return false;
    }
    let mut left = None;
    for i in 0..m {
        let (a, b, c) = (corners[(i + m - 1) % m], corners[i], corners[(i + 1) % m]);
        let o = orient(&a, &b, &c);
        if o == 0.0 || left.is_some_and(|l| l != (o > 0.0)) {
            return false;
        }
        left = Some(o > 0.0);
    }
    // Every turn is one way and less than half a turn, so the sides'
    // direction goes round monotonically; each time round, the sign of
    // their x step changes twice (passing straight up and straight down;
    // a side straight up or down between two others is passed over: two
    // such in a row would be collinear). Exact: the sign of a difference
    // of two floats is the true one.
    let dx = |i: usize| corners[(i + 1) % m][0] - corners[i][0];
    let (mut first, mut prev, mut changes) = (None, None, 0);
    for i in 0..m {
        let d = dx(i);
        if d == 0.0 {
            continue;
        }
        let right = d > 0.0;
        match prev {
            Some(p) if p != right => changes += 1,
            Some(_) => {}
            None => first = Some(right),
        }
        prev = Some(right);
    }
    if first.is_some() && first != prev {
        changes += 1;
    }
    changes == 2
}

/// A spheroid: semi-major axis (metres) and flattening.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spheroid {
    pub a: f64,
    pub f: f64,
}

impl Spheroid {
    pub const WGS84: Spheroid = Spheroid {
        a: 6_378_137.0,
        f: 1.0 / 298.257_223_563,
    };

    /// Metres per degree of longitude and of latitude at latitude `lat`
    /// (degrees): the radii of curvature in the prime vertical (times the
    /// cosine of the latitude) and in the meridian.
    ///
    /// ```
    /// use tinmerge_core::geom::Spheroid;
    /// let (kx, ky) = Spheroid::WGS84.metres_per_degree(0.0);
    /// assert!((kx - 111_319.49).abs() < 0.01 && (ky - 110_574.27).abs() < 0.01);
    /// ```
    pub fn metres_per_degree(&self, lat: f64) -> (f64, f64) {
        let e2 = self.f * (2.0 - self.f);
        let phi = lat.to_radians();
        let s = phi.sin();
        let w = (1.0 - e2 * s * s).sqrt();
        let n = self.a / w;
        let m = self.a * (1.0 - e2) / (w * w * w);
        let k = std::f64::consts::PI / 180.0;
        (k * n * phi.cos(), k * m)
    }

    /// The point at longitude `lon`, latitude `lat` (degrees) on the
    /// spheroid, in earth-centred metres.
    pub fn ecef(&self, lon: f64, lat: f64) -> [f64; 3] {
        let e2 = self.f * (2.0 - self.f);
        let (l, p) = (lon.to_radians(), lat.to_radians());
        let n = self.a / (1.0 - e2 * p.sin() * p.sin()).sqrt();
        [
            n * p.cos() * l.cos(),
            n * p.cos() * l.sin(),
            n * (1.0 - e2) * p.sin(),
        ]
    }

    /// The spheroid a PROJ.4 definition names (`+a` with `+rf`, `+f` or
    /// `+b`; `+ellps`; `+datum`), WGS84 when it names none; None for an
    /// ellipsoid name this does not know.
    pub fn from_proj4(def: &str) -> Option<Spheroid> {
        let mut kv = std::collections::HashMap::new();
        for t in def.split_whitespace() {
            let t = t.trim_start_matches('+');
            let (k, v) = t.split_once('=').unwrap_or((t, ""));
            kv.insert(k, v);
        }
        let num = |k: &str| kv.get(k).and_then(|v| v.parse::<f64>().ok());
        if let Some(a) = num("a").or_else(|| num("R")) {
            let f = match (num("rf"), num("f"), num("b")) {
                (Some(rf), _, _) if rf != 0.0 => 1.0 / rf,
                (_, Some(f), _) => f,
                (_, _, Some(b)) => 1.0 - b / a,
                _ => 0.0,
            };
            return (a > 0.0 && (0.0..1.0).contains(&f)).then_some(Spheroid { a, f });
        }
        let named = |name: &str| -> Option<Spheroid> {
            let (a, rf) = match name {
                "WGS84" => (6_378_137.0, 298.257_223_563),
                "GRS80" => (6_378_137.0, 298.257_222_101),
                "WGS72" => (6_378_135.0, 298.26),
                "clrk66" => (6_378_206.4, 294.978_698_213_898),
                "clrk80" => (6_378_249.145, 293.4663),
                "intl" => (6_378_388.0, 297.0),
                "bessel" => (6_377_397.155, 299.152_812_8),
                "krass" => (6_378_245.0, 298.3),
                "airy" => (6_377_563.396, 299.324_964_6),
                "aust_SA" => (6_378_160.0, 298.25),
                _ => return None,
            };
            Some(Spheroid { a, f: 1.0 / rf })
        };
        if let Some(e) = kv.get("ellps") {
            return named(e);
        }
        match kv.get("datum").copied() {
            None | Some("WGS84") => Some(Spheroid::WGS84),
            Some("NAD83") => named("GRS80"),
            Some("NAD27") => named("clrk66"),
            Some(_) => None,
        }
    }
}

/// How a tin's x and y measure, for areas, slopes and volumes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Units {
    /// As they are (a projected SRID, heights in the same unit).
    Planar,
    /// Longitude and latitude in degrees on a spheroid, heights in metres:
    /// areas in square metres (the spheroid's area element at each part's
    /// latitude), slopes with the metres a degree spans there.
    Degrees(Spheroid),
}

impl Units {
    /// The area of one square unit at latitude `lat` (1 when planar).
    #[inline]
    pub fn area_scale(&self, lat: f64) -> f64 {
        self.local(lat, 0.0, 0.0).0
    }

    /// [`Units::area_scale`] at latitude `lat`, and the gradient (`gx`,
    /// `gy` per unit) per metre there.
    #[inline]
    pub fn local(&self, lat: f64, gx: f64, gy: f64) -> (f64, f64, f64) {
        match self {
            Units::Planar => (1.0, gx, gy),
            Units::Degrees(s) => {
                let (kx, ky) = s.metres_per_degree(lat);
                (kx * ky, gx / kx, gy / ky)
            }
        }
    }
}
