//! How far a triangle is from its source's surface, and where: the
//! largest vertical error at the samples in it and where its edges cross
//! a segment of the source's own surface between two samples (where that
//! surface is the straight line between them). The two together bound the
//! error on the whole surface: inside a triangle the tin is linear, and on
//! such a segment so is the surface between the points where edges cross
//! it.
//!
//! A [`Source`] gives both. A raster band ([`Heights`]): the valid pixel
//! centres in a triangle (its rows of centres found from its edges, the
//! centres near an edge decided by the exact orientation) and the grid
//! segments between two valid centres. Scattered samples
//! ([`super::points::Scattered`]): the samples in a triangle from their
//! buckets, and the edges of their Delaunay triangulation.

use super::mesh::{Mesh, NONE, next};
use crate::geom::{self, floor_fast, left_or_on_rounded, orient};
use crate::tin::TinError;
use crate::tin::build::common::lattice_hull;

/// What [`Greedy`](super::greedy::Greedy)'s `vid` holds at a sample that
/// is no vertex and may not be made one by the greedy refinement (a sample
/// of a kept hull side its own profile has not chosen, [`super::kept`]):
/// it is not measured, and an edge crossing a grid segment from it to a
/// vertex is split where it crosses.
pub(super) const RESERVED: u32 = NONE - 1;

/// A raster band's heights in place, row by row, `NaN` where no data.
pub struct Heights<'a> {
    pub z: &'a [f64],
    pub width: usize,
    pub height: usize,
}

/// Where an engine 2 build's samples and surface come from. Samples are
/// numbered `0..count()`; a build's vertices are samples or points on a
/// coarser edge where it crosses a segment between two samples.
pub(super) trait Source {
    /// How many sample numbers there are (some may have no sample: a
    /// raster's nodata pixels).
    fn count(&self) -> usize;
    /// Sample `id`: x, y, z in the build's frame.
    fn point(&self, id: u32) -> [f64; 3];
    /// The samples' convex hull, counter-clockwise, without collinear
    /// corners; an error when they have no area.
    fn hull(&self) -> Result<Vec<u32>, TinError>;
    /// The worst sample in the closed triangle `c` that is not a vertex
    /// (`vid[id] == NONE`).
    fn worst_sample(&self, c: &[[f64; 3]; 3], vid: &[u32]) -> Worst;
    /// The worst crossing of edge p -> q with a segment between two
    /// samples (`k` left 0).
    fn worst_crossing(&self, p: &[f64; 3], q: &[f64; 3]) -> Worst;
    /// Where edge p -> q crosses the segment between samples `a` and `b`
    /// (a crossing [`Source::worst_crossing`] gave), with the segment's
    /// height there: the very point it measured, so a triangle's worst
    /// keeps only the segment's ends.
    fn crossing_point(&self, p: &[f64; 3], q: &[f64; 3], a: u32, b: u32) -> Option<[f64; 3]>;
    /// Where edge u -> w crosses the segment from sample point `a` to
    /// sample point `b`, with the segment's height there.
    fn crossing_of(&self, u: &[f64; 3], w: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        let (oa, ob) = (orient(u, w, a), orient(u, w, b));
        let f = if oa == ob { 0.5 } else { oa / (oa - ob) };
        let (ou, ow) = (orient(a, b, u), orient(a, b, w));
        let s = if ou == ow { 0.5 } else { ou / (ou - ow) };
        [
            u[0] + s * (w[0] - u[0]),
            u[1] + s * (w[1] - u[1]),
            a[2] + f * (b[2] - a[2]),
        ]
    }
    /// The band's heights when the source is a raster band: its coarse
    /// levels may then run along the lattice ([`super::aligned`]).
    fn lattice(&self) -> Option<&Heights<'_>> {
        None
    }
}

impl Source for Heights<'_> {
    fn count(&self) -> usize {
        self.width * self.height
    }
    fn point(&self, id: u32) -> [f64; 3] {
        let (c, r) = (id as usize % self.width, id as usize / self.width);
        [c as f64, r as f64, self.z[id as usize]]
    }
    fn hull(&self) -> Result<Vec<u32>, TinError> {
        let corners = lattice_hull(self.width, self.height, &|i| !self.z[i].is_nan());
        if corners.len() < 3 {
            let n = self.z.iter().filter(|z| !z.is_nan()).count();
            return Err(TinError::Degenerate(if n < 3 {
                format!("need at least 3 valid pixels to build a tin, got {n}")
            } else {
                format!("all {n} valid pixels lie on one line: a tin needs 3 that do not")
            }));
        }
        Ok(corners.into_iter().map(|i| i as u32).collect())
    }
    fn worst_sample(&self, c: &[[f64; 3]; 3], vid: &[u32]) -> Worst {
        samples(c, self, vid)
    }
    fn worst_crossing(&self, p: &[f64; 3], q: &[f64; 3]) -> Worst {
        crossings(p, q, self)
    }
    /// [`Source::crossing_of`] of this band, the same arithmetic as
    /// [`crossings`]: the fraction along the edge from the segment's own
    /// coordinate, the height at the fraction along the segment.
    fn crossing_point(&self, p: &[f64; 3], q: &[f64; 3], a: u32, b: u32) -> Option<[f64; 3]> {
        Some(self.crossing_of(p, q, &self.point(a), &self.point(b)))
    }
    /// Exact in the segment's own coordinate (a column's x, a row's y).
    fn crossing_of(&self, u: &[f64; 3], w: &[f64; 3], a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        // along x = const (a column's segment) or y = const (a row's)
        let k = if a[0] == b[0] { 0 } else { 1 };
        let s = (a[k] - u[k]) / (w[k] - u[k]);
        let other = u[1 - k] + s * (w[1 - k] - u[1 - k]);
        let f = (other - a[1 - k]) / (b[1 - k] - a[1 - k]);
        let mut x = [0.0, 0.0, a[2] + f * (b[2] - a[2])];
        x[k] = a[k];
        x[1 - k] = other;
        x
    }
    fn lattice(&self) -> Option<&Heights<'_>> {
        Some(self)
    }
}

impl Heights<'_> {
    /// How many pixels a row's runs of one height hold on average (the
    /// valid pixels over the runs of equal valid heights along rows): near
    /// 1 on measured terrain, k on a raster resampled by nearest neighbour
    /// to 1/k of its pixel (terraces).
    pub(super) fn plateau(&self) -> f64 {
        let (mut valid, mut runs) = (0usize, 0usize);
        for row in self.z.chunks(self.width.max(1)) {
            let mut last = f64::NAN;
            for &z in row {
                if !z.is_nan() {
                    valid += 1;
                    runs += usize::from(z != last);
                }
                last = z;
            }
        }
        valid as f64 / runs.max(1) as f64
    }

    #[inline]
    pub(super) fn at(&self, c: i64, r: i64) -> Option<f64> {
        if c < 0 || r < 0 || c >= self.width as i64 || r >= self.height as i64 {
            return None;
        }
        let z = self.z[r as usize * self.width + c as usize];
        (!z.is_nan()).then_some(z)
    }
}

/// What refines a triangle most: a sample to insert, or a crossing of one
/// of its edges with a segment between two samples.
#[derive(Clone, Copy, Debug)]
pub(super) enum Fix {
    None,
    Sample(u32),
    /// edge `k` of the triangle (its half-edge `3t + k`) crosses the
    /// segment from sample `a` to sample `b` (where:
    /// [`Source::crossing_point`])
    Crossing {
        k: u8,
        a: u32,
        b: u32,
    },
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Worst {
    pub(super) err: f64,
    pub(super) fix: Fix,
}

impl Worst {
    pub(super) const NONE: Worst = Worst {
        err: 0.0,
        fix: Fix::None,
    };
}

/// The plane through three points: z at (x, y).
pub(super) struct Plane {
    x0: f64,
    y0: f64,
    z0: f64,
    zx: f64,
    zy: f64,
}

impl Plane {
    pub(super) fn of(c: &[[f64; 3]; 3]) -> Plane {
        let (ux, uy, uz) = (c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]);
        let (vx, vy, vz) = (c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]);
        let det = ux * vy - uy * vx;
        Plane {
            x0: c[0][0],
            y0: c[0][1],
            z0: c[0][2],
            zx: (uz * vy - vz * uy) / det,
            zy: (vz * ux - uz * vx) / det,
        }
    }
    #[inline]
    pub(super) fn z(&self, x: f64, y: f64) -> f64 {
        self.z0 + self.zx * (x - self.x0) + self.zy * (y - self.y0)
    }
}

/// The worst error of triangle `t` and its fix. `vid[sample]` is not
/// `NONE` at the samples that are vertices (their error is the rounding of
/// the plane, not the surface's).
pub(super) fn measure<S: Source + ?Sized>(m: &Mesh, t: u32, g: &S, vid: &[u32]) -> Worst {
    let c = m.corners(t);
    let mut worst = g.worst_sample(&c, vid);
    for k in 0..3u32 {
        let h = 3 * t + k;
        let (p, q) = (m.at(h), m.at(next(h)));
        let w = g.worst_crossing(p, q);
        if let (true, Fix::Crossing { a, b, .. }) = (w.err > worst.err, w.fix) {
            worst = Worst {
                err: w.err,
                fix: Fix::Crossing { k: k as u8, a, b },
            };
        }
    }
    worst
}

/// The worst valid pixel centre in the closed triangle (up to rounding:
/// a centre on an edge counts in both triangles).
fn samples(c: &[[f64; 3]; 3], g: &Heights<'_>, vid: &[u32]) -> Worst {
    let plane = Plane::of(c);
    let mut worst = Worst::NONE;
    if let Some(corners) = whole(c) {
        // corners at pixel centres: each row's span from the edges
        // exactly, in integers, stepped row by row
        let lo = corners.iter().map(|p| p[1]).min().unwrap_or(0).max(0);
        let hi = corners.iter().map(|p| p[1]).max().unwrap_or(-1);
        let hi = hi.min(g.height as i64 - 1);
        if lo > hi {
            return worst;
        }
        // each row's first centres asked of memory at once, before the
        // scan waits on them one row at a time
        let x0 = corners.iter().map(|p| p[0]).min().unwrap_or(0).max(0) as usize;
        if x0 < g.width {
            for r in lo..=hi {
                let i = r as usize * g.width + x0;
                prefetch(&g.z[i]);
                prefetch(&vid[i]);
            }
        }
        let mut rows = Spans::new(&corners, lo);
        for r in lo..=hi {
            if let Some((c0, c1)) = rows.next_row() {
                scan_row(g, vid, &plane, r, c0, c1, |_| true, &mut worst);
            }
        }
        return worst;
    }
    let lo = c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let hi = c.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    let r0 = (lo.ceil() as i64).max(0);
    let r1 = (hi.floor() as i64).min(g.height as i64 - 1);
    for r in r0..=r1 {
        let y = r as f64;
        let (mut xl, mut xr) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..3 {
            let (p, q) = (&c[k], &c[(k + 1) % 3]);
            if (p[1] - y) * (q[1] - y) > 0.0 {
                continue;
            }
            if p[1] == q[1] {
                xl = xl.min(p[0].min(q[0]));
                xr = xr.max(p[0].max(q[0]));
            } else {
                let x = p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]);
                xl = xl.min(x);
                xr = xr.max(x);
            }
        }
        if xl > xr {
            continue;
        }
        // centres more than a pixel inside both ends are inside; those
        // near an end are decided exactly
        let (sure0, sure1) = (xl.ceil() as i64 + 1, xr.floor() as i64 - 1);
        let inside = |col: i64| {
            let q = [col as f64, y, 0.0];
            (sure0..=sure1).contains(&col)
                || (0..3).all(|k| left_or_on_rounded(&c[k], &c[(k + 1) % 3], &q))
        };
        let (c0, c1) = (xl.ceil() as i64 - 1, xr.floor() as i64 + 1);
        scan_row(g, vid, &plane, r, c0, c1, inside, &mut worst);
    }
    worst
}

/// A hint that `x` will be read soon (nothing where there is no such
/// instruction).
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch reads nothing and cannot fault; `sse` is in
        // every x86-64 target
        unsafe { _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// The worst valid centre of row `r` from column `c0` to `c1` (clipped
/// to the band) that is no vertex and that `keep` takes, against `plane`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn scan_row(
    g: &Heights<'_>,
    vid: &[u32],
    plane: &Plane,
    r: i64,
    c0: i64,
    c1: i64,
    keep: impl Fn(i64) -> bool,
    worst: &mut Worst,
) {
    let (y, row) = (r as f64, r as usize * g.width);
    for col in c0.max(0)..=c1.min(g.width as i64 - 1) {
        let i = row + col as usize;
        let z = g.z[i];
        if z.is_nan() || vid[i] != NONE || !keep(col) {
            continue;
        }
        let e = (z - plane.z(col as f64, y)).abs();
        if e > worst.err {
            *worst = Worst {
                err: e,
                fix: Fix::Sample(i as u32),
            };
        }
    }
}

/// The corners as whole lattice numbers, when they all are (every corner
/// a pixel centre, under [`geom::WHOLE`]): "left or on up to rounding"
/// is then exactly "left or on", which [`Spans`] decides in integers.
fn whole(c: &[[f64; 3]; 3]) -> Option<[[i64; 2]; 3]> {
    Some([
        geom::whole(&c[0])?,
        geom::whole(&c[1])?,
        geom::whole(&c[2])?,
    ])
}

/// The columns of each row in the closed counter-clockwise triangle with
/// whole corners, row after row: on or left of each edge, exactly. Edge
/// p -> q holds x on row r when `a x + b >= 0`, with `a = -dy` and
/// `b = dx (r - py) + dy px`; each edge keeps `floor(b / |a|)` and its
/// remainder, stepped by `dx` a row, so a row costs no division.
struct Spans {
    edges: [EdgeRows; 3],
}

#[derive(Clone, Copy)]
struct EdgeRows {
    /// the sign of `a`: 1 a lower bound on x, -1 an upper one, 0 none
    /// (then the row is empty when `b < 0`)
    sign: i64,
    /// |a| (1 when `a` is 0)
    d: i64,
    /// `b`, or `floor(b / d)` when `a` is not 0
    q: i64,
    /// `b - q d`, in `0..d`
    rem: i64,
    /// `dx` split the same way: the step of `q` and of `rem` a row
    step_q: i64,
    step_rem: i64,
}

impl Spans {
    /// The spans of `c` from row `r` on.
    fn new(c: &[[i64; 2]; 3], r: i64) -> Spans {
        let edges = std::array::from_fn(|k| {
            let (p, q) = (c[k], c[(k + 1) % 3]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let (a, b) = (-dy, dx * (r - p[1]) + dy * p[0]);
            let d = a.abs().max(1);
            let q = b.div_euclid(d);
            let step_q = dx.div_euclid(d);
            EdgeRows {
                sign: a.signum(),
                d,
                q,
                rem: b - q * d,
                step_q,
                step_rem: dx - step_q * d,
            }
        });
        Spans { edges }
    }

    /// The columns of the current row (first and last), if any; then
    /// on to the next row.
    #[inline]
    fn next_row(&mut self) -> Option<(i64, i64)> {
        let (mut c0, mut c1) = (i64::MIN, i64::MAX);
        let mut empty = false;
        for e in &mut self.edges {
            match e.sign {
                1 => c0 = c0.max(-e.q),
                -1 => c1 = c1.min(e.q),
                _ => empty |= e.q < 0,
            }
            e.q += e.step_q;
            e.rem += e.step_rem;
            if e.rem >= e.d {
                e.rem -= e.d;
                e.q += 1;
            }
        }
        (!empty && c0 <= c1).then_some((c0, c1))
    }
}

/// The worst crossing of edge p -> q with a grid segment between two valid
/// pixel centres (not at a centre, which [`samples`] measures), the edge's
/// height there against the segment's.
pub(super) fn crossings(p: &[f64; 3], q: &[f64; 3], g: &Heights<'_>) -> Worst {
    let mut worst = Worst::NONE;
    // rows crossed: y = r, the segment from (c, r) to (c + 1, r)
    let mut each = |along_rows: bool| {
        let (pu, pv, qu, qv) = if along_rows {
            (p[1], p[0], q[1], q[0])
        } else {
            (p[0], p[1], q[0], q[1])
        };
        if pu == qu {
            return;
        }
        let (lo, hi) = (pu.min(qu), pu.max(qu));
        // the grid lines strictly between the ends
        let mut u = floor_fast(lo) as i64 + 1;
        while (u as f64) < hi {
            let s = (u as f64 - pu) / (qu - pu);
            let v = pv + s * (qv - pv);
            let v0 = floor_fast(v);
            // at a centre (up to rounding, where an end is a rounded
            // crossing): a sample, which the triangles measure
            let f = v - v0;
            if f > 1e-9 && 1.0 - f > 1e-9 {
                let (a, b) = if along_rows {
                    ([v0 as i64, u], [v0 as i64 + 1, u])
                } else {
                    ([u, v0 as i64], [u, v0 as i64 + 1])
                };
                if let (Some(za), Some(zb)) = (g.at(a[0], a[1]), g.at(b[0], b[1])) {
                    let zs = za + f * (zb - za);
                    let ze = p[2] + s * (q[2] - p[2]);
                    let e = (ze - zs).abs();
                    if e > worst.err {
                        worst = Worst {
                            err: e,
                            fix: Fix::Crossing {
                                k: 0,
                                a: (a[1] as usize * g.width + a[0] as usize) as u32,
                                b: (b[1] as usize * g.width + b[0] as usize) as u32,
                            },
                        };
                    }
                }
            }
            u += 1;
        }
    };
    each(true);
    each(false);
    worst
}

#[cfg(test)]
mod tests {
    use super::{Spans, whole};
    use crate::geom::{
        in_circle, left_or_on_rounded, left_or_within_roundings, orient, orient_slack,
    };

    /// A seeded xorshift, so a failure repeats.
    fn rng(mut s: u64) -> impl FnMut(i64) -> i64 {
        move |n| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % n as u64) as i64
        }
    }

    /// Every row's span against the exact side test at each centre of a
    /// wider range, on random whole triangles small and large (slivers
    /// and right triangles along the lattice among them).
    #[test]
    fn a_rows_span_is_what_the_side_tests_hold() {
        let mut r = rng(0x9e37_79b9_7f4a_7c15);
        for trial in 0..20_000 {
            let size = [3, 12, 200, 500_000][trial % 4];
            let base = r(1 << 19);
            let mut c: [[f64; 3]; 3] =
                std::array::from_fn(|_| [(base + r(size)) as f64, (base + r(size)) as f64, 0.0]);
            if trial % 7 == 0 {
                // along the lattice: a right isosceles triangle
                let (x, y, l) = (c[0][0], c[0][1], (1 + r(40)) as f64);
                c = [[x, y, 0.0], [x + l, y, 0.0], [x, y + l, 0.0]];
            }
            let o = orient(&c[0], &c[1], &c[2]);
            if o == 0.0 {
                continue;
            }
            if o < 0.0 {
                c.swap(1, 2);
            }
            let w = whole(&c).expect("whole corners");
            let lo = w.iter().map(|p| p[1]).min().unwrap();
            let hi = w.iter().map(|p| p[1]).max().unwrap();
            let (x0, x1) = (
                w.iter().map(|p| p[0]).min().unwrap(),
                w.iter().map(|p| p[0]).max().unwrap(),
            );
            for _ in 0..4 {
                let row = lo - 1 + r(hi - lo + 3);
                // stepped to the row from up to 40 rows before it
                let before = r(41);
                let mut rows = Spans::new(&w, row - before);
                for _ in 0..before {
                    rows.next_row();
                }
                // a window of columns around the span and the bounds
                let got = rows.next_row();
                let probe: Vec<i64> = match got {
                    Some((a, b)) => vec![a - 1, a, b, b + 1, x0 - 1, x1 + 1],
                    None => (0..8).map(|_| x0 - 1 + r(x1 - x0 + 3)).collect(),
                };
                for col in probe {
                    let q = [col as f64, row as f64, 0.0];
                    let inside = (0..3).all(|k| left_or_on_rounded(&c[k], &c[(k + 1) % 3], &q));
                    let spanned = got.is_some_and(|(a, b)| (a..=b).contains(&col));
                    assert_eq!(
                        inside, spanned,
                        "trial {trial}: {c:?} row {row} col {col} span {got:?}"
                    );
                }
            }
        }
    }

    /// The integer in-circle test against `robust`'s on lattice points,
    /// where four points are often on one circle.
    #[test]
    fn the_whole_in_circle_test_is_robusts() {
        let mut r = rng(0x2545_f491_4f6c_dd1d);
        let (mut inside, mut on) = (0, 0);
        for trial in 0..200_000 {
            // both sides of the 64-bit test's reach (2^14 from the fourth)
            let span = [3, 8, 1000, (1 << 14) + 300, 1 << 20][trial % 5];
            let base = if span == 1 << 20 { 0 } else { r(1 << 19) };
            let p: [[f64; 3]; 4] =
                std::array::from_fn(|_| [(base + r(span)) as f64, (base + r(span)) as f64, 0.0]);
            let (mut a, mut b, c) = (p[0], p[1], p[2]);
            let o = orient(&a, &b, &c);
            if o == 0.0 {
                continue;
            }
            if o < 0.0 {
                std::mem::swap(&mut a, &mut b);
            }
            let co = |q: &[f64; 3]| robust::Coord { x: q[0], y: q[1] };
            let want = robust::incircle(co(&a), co(&b), co(&c), co(&p[3]));
            assert_eq!(
                in_circle(&a, &b, &c, &p[3]),
                want > 0.0,
                "trial {trial}: {p:?}"
            );
            inside += usize::from(want > 0.0);
            on += usize::from(want == 0.0);
        }
        // the trials reach both sides and the circle itself
        assert!(inside > 1000 && on > 1000, "inside {inside}, on {on}");
    }

    /// The side test's float shortcut says what the exact test with its
    /// slack says, on points placed within a few roundings of lines at
    /// UTM and geographic magnitudes (where the slack decides).
    #[test]
    fn the_side_tests_shortcut_agrees_with_the_exact_test() {
        let mut r = rng(0x51_7cc1_b727_220a);
        let mut near = 0;
        for trial in 0..200_000 {
            let scale = [1.0, 1e-3, 5e5, 4e6][trial % 4];
            let f = |r: &mut dyn FnMut(i64) -> i64| (r(2_000_001) - 1_000_000) as f64 / 1e6;
            let a = [scale * (1.0 + f(&mut r)), scale * (2.0 + f(&mut r)), 0.0];
            let b = [
                a[0] + scale * f(&mut r) * 1e-2,
                a[1] + scale * f(&mut r) * 1e-2,
                0.0,
            ];
            // a point on the line a-b, moved a few ulps
            let s = f(&mut r) * 2.0;
            let mut c = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), 0.0];
            for v in c.iter_mut().take(2) {
                let ulps = r(9) - 4;
                *v = f64::from_bits((v.to_bits() as i64 + ulps) as u64);
            }
            for k in [1.0, 4.0, 256.0] {
                let exact = orient(&a, &b, &c) >= -k * orient_slack(&a, &b, &c);
                assert_eq!(
                    left_or_within_roundings(&a, &b, &c, k),
                    exact,
                    "trial {trial}: {a:?} {b:?} {c:?} k {k}"
                );
            }
            near += usize::from(orient(&a, &b, &c) < 0.0);
        }
        // the points fall on the wrong side often, where the slack decides
        assert!(near > 10_000, "{near}");
    }
}
