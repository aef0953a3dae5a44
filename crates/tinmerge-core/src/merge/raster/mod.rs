//! Raster merge (Scarlatos §6.2, first problem): the pixels of a raster handed to
//! the triangles of one level by a scanline sweep.
//!
//! A horizontal line steps down the raster one row of pixel centres at a
//! time. Its cut is the set of triangles it crosses: a triangle enters the
//! cut at the first row at or below its top vertex and leaves after the last
//! row at or above its bottom vertex (the events, bucketed by row once:
//! O(N + rows)). In each row every triangle of the cut receives the run of
//! pixel centres it owns, found from where the row meets its edges and
//! settled at the two ends with exact predicates. No pixel is located on its
//! own: the work is O(M + N + rows x cut) for M pixels and N triangles.
//!
//! **Which triangle owns a centre.** A centre strictly inside a triangle
//! belongs to it. A centre on an edge or a vertex belongs to the triangle
//! that holds the point moved by an infinitesimal step east and a far
//! smaller step north (simulation of simplicity with the direction
//! (1, ε)): on a shared edge the triangle east of it (north of an east-west
//! edge), on a vertex the triangle just east-north-east of it. Exactly one
//! triangle owns each centre inside the domain, decided by `orient2d` and
//! coordinate comparisons only. On the domain's outer boundary, where the
//! moved point falls outside, the centre goes to the triangle of the hull
//! edge it lies on (of the hull edge starting at it, for a hull vertex), so
//! every centre in the closed domain is counted exactly once.
//!
//! The merges take the triangles of a level as a
//! [`patch::RasterLevel`]: the whole level of a decoded tin, or a
//! [`patch::Patch`] of a stored one read in slices (the triangles under the
//! raster). Callbacks get a triangle's *position* there (its id is
//! `lv.id(position)`; for a whole level they are equal).
//!
//! ```
//! use tinmerge_core::io::raster::GeoTransform;
//! use tinmerge_core::merge::raster::{patch::TinLevel, sweep, PixelGrid};
//! use tinmerge_core::tin::build::build;
//! // two triangles over the square (0,0)-(4,4), split along the diagonal
//! let pts = vec![[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 4.0, 0.0], [0.0, 4.0, 0.0]];
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! // a 4 x 4 raster of 1 x 1 pixels, north up
//! let gt = GeoTransform { scale_x: 1.0, scale_y: -1.0, ip_x: 0.0, ip_y: 4.0, skew_x: 0.0, skew_y: 0.0 };
//! let grid = PixelGrid::new(&gt, 4, 4).unwrap();
//! let mut per_tri = vec![0; 2];
//! let lv = TinLevel::new(&tin, 0).unwrap();
//! sweep(&lv, &grid, false, &mut || Ok(()), &mut |k, _row, c0, c1| per_tri[k as usize] += c1 - c0).unwrap();
//! // 16 centres: 6 strictly on each side of the diagonal, 4 on it (to the east)
//! assert_eq!(per_tri.iter().sum::<usize>(), 16);
//! assert!(per_tri.contains(&6) && per_tri.contains(&10));
//! ```

pub mod coverage;
pub mod patch;
pub mod stats;

use crate::geom::co;
use crate::interrupt::{Interrupt, Ticker};
use crate::io::raster::GeoTransform;
use crate::merge::raster::coverage::check_grid;
use crate::merge::raster::patch::RasterLevel;
use crate::tin::TinError;
use robust::orient2d;
use rustc_hash::FxHashMap;

/// The pixel centres of a north-up (unrotated) raster: `xs[col]`, `ys[row]`,
/// computed exactly as [`GeoTransform::centre`] does.
#[derive(Clone, Debug, PartialEq)]
pub struct PixelGrid {
    pub width: usize,
    pub height: usize,
    pub xs: Axis,
    pub ys: Axis,
    /// Count the domain as half-open: a centre on its outer boundary goes
    /// to a triangle only where the point moved east (north) is inside, as
    /// on a shared edge; the centres the boundary rule would add (see the
    /// module documentation) are left out. Over tiles whose seams are
    /// shared edges each seam centre is then handed to exactly one tile,
    /// the one on the side a single tin of their union hands it to.
    /// `false` from [`PixelGrid::new`].
    pub half_open: bool,
}

/// Monotone coordinates of pixel centres along one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub v: Vec<f64>,
    step: f64,
    increasing: bool,
}

impl Axis {
    fn new(v: Vec<f64>, step: f64) -> Axis {
        Axis {
            v,
            step,
            increasing: step > 0.0,
        }
    }

    /// The step between two centres (negative where they decrease).
    pub fn step(&self) -> f64 {
        self.step
    }

    /// Number of leading indices for which `pred` holds (a prefix, as the
    /// axis is monotone), starting from an estimate near `x`.
    #[inline]
    fn prefix(&self, x: f64, pred: impl Fn(f64) -> bool) -> usize {
        let n = self.v.len();
        let e = (x - self.v.first().copied().unwrap_or(0.0)) / self.step;
        let mut k = if e.is_nan() || e <= 0.0 {
            0
        } else if e >= n as f64 {
            n
        } else {
            e as usize
        };
        while k > 0 && !pred(self.v[k - 1]) {
            k -= 1;
        }
        while k < n && pred(self.v[k]) {
            k += 1;
        }
        k
    }

    /// Indices `i0..i1` of the centres with `lo <= v[i] <= hi` (empty when
    /// `i1 <= i0`).
    #[inline]
    pub fn range(&self, lo: f64, hi: f64) -> (usize, usize) {
        if self.increasing {
            (self.prefix(lo, |v| v < lo), self.prefix(hi, |v| v <= hi))
        } else {
            (self.prefix(hi, |v| v > hi), self.prefix(lo, |v| v >= lo))
        }
    }
}

impl PixelGrid {
    /// The centres of a `width` x `height` raster; rotated or skewed rasters
    /// are refused.
    pub fn new(gt: &GeoTransform, width: usize, height: usize) -> Result<PixelGrid, TinError> {
        check_grid(gt)?;
        let xs = (0..width).map(|c| gt.centre(c, 0).0).collect();
        let ys = (0..height).map(|r| gt.centre(0, r).1).collect();
        Ok(PixelGrid {
            width,
            height,
            xs: Axis::new(xs, gt.scale_x),
            ys: Axis::new(ys, gt.scale_y),
            half_open: false,
        })
    }
}

/// Whether the point on the line u -> v, moved by (ε, ε²), is left of it.
#[inline]
fn tie_left(u: [f64; 2], v: [f64; 2]) -> bool {
    if v[1] != u[1] {
        v[1] < u[1]
    } else {
        v[0] > u[0]
    }
}

/// Whether the counter-clockwise triangle owns the point (the rule in the
/// module documentation, without the hull case).
#[inline]
pub fn owns(t: &[[f64; 2]; 3], p: [f64; 2]) -> bool {
    for j in 0..3 {
        let (u, v) = (t[j], t[(j + 1) % 3]);
        let o = orient2d(co(u), co(v), co(p));
        if o < 0.0 || (o == 0.0 && !tie_left(u, v)) {
            return false;
        }
    }
    true
}

/// A triangle in the sweep's cut, with what each row needs precomputed:
/// the inverse slope `dx/dy` of each edge and the parts of the rounding
/// bound of `x = a.x + (y - a.y) * dx/dy` that do not depend on `y`.
struct CutTri {
    t: u32,
    /// first row after the triangle
    end_row: u32,
    cs: [[f64; 2]; 3],
    k: [f64; 3],
    e: [f64; 3],
}

impl CutTri {
    fn new(t: u32, end_row: u32, cs: [[f64; 2]; 3]) -> CutTri {
        let (mut k, mut e) = ([0.0; 3], [0.0; 3]);
        for j in 0..3 {
            let (a, b) = (cs[j], cs[(j + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            if dy != 0.0 {
                k[j] = dx / dy;
                e[j] = a[1].abs() * k[j].abs() + a[0].abs() + dx.abs();
            }
        }
        CutTri {
            t,
            end_row,
            cs,
            k,
            e,
        }
    }

    /// The x-interval where the row `y` meets the closed triangle, rounded,
    /// with a bound on the rounding error of its ends (a few ulps of each
    /// operand, the slope amplifying those of y; exact tests settle the
    /// centres within that bound).
    #[inline]
    fn row_interval(&self, y: f64) -> (f64, f64, f64) {
        let (mut lo, mut hi, mut err) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for j in 0..3 {
            let (a, b) = (self.cs[j], self.cs[(j + 1) % 3]);
            if (a[1] <= y && y <= b[1]) || (b[1] <= y && y <= a[1]) {
                if a[1] == b[1] {
                    lo = lo.min(a[0].min(b[0]));
                    hi = hi.max(a[0].max(b[0]));
                } else {
                    let x = (a[0] + (y - a[1]) * self.k[j]).clamp(a[0].min(b[0]), a[0].max(b[0]));
                    err = err.max(y.abs() * self.k[j].abs() + self.e[j]);
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        (lo, hi, err * (16.0 * f64::EPSILON))
    }
}

/// Centres on the domain's outer boundary that no triangle owns by the
/// perturbation rule, with the position of the triangle they go to:
/// `(row, col, position)`.
fn hull_extras<L: RasterLevel>(lv: &L, g: &PixelGrid) -> Result<Vec<(u32, u32, u32)>, TinError> {
    let hull = lv.hull_edges()?;
    // previous hull vertex of each hull vertex (the domain is on the left
    // of its counter-clockwise hull edges)
    let prev: FxHashMap<u32, [f64; 2]> = hull.iter().map(|e| (e.v, e.pu)).collect();
    let mut out = Vec::new();
    for e in &hull {
        let (t, u, v) = (e.k, e.pu, e.pv);
        // the hull vertex u, if it is a centre
        let (c0, c1) = g.xs.range(u[0], u[0]);
        let (r0, r1) = g.ys.range(u[1], u[1]);
        if c0 < c1 && r0 < r1 {
            let w = *prev
                .get(&e.u)
                .ok_or_else(|| TinError::Corrupt("raster sweep: vertex id".into()))?;
            let inside = if orient2d(co(w), co(u), co(v)) >= 0.0 {
                tie_left(w, u) && tie_left(u, v)
            } else {
                tie_left(w, u) || tie_left(u, v)
            };
            if !inside {
                for r in r0..r1 {
                    for col in c0..c1 {
                        out.push((r as u32, col as u32, t));
                    }
                }
            }
        }
        // centres strictly inside the edge, when the moved point is outside
        if tie_left(u, v) {
            continue;
        }
        let (ylo, yhi) = (u[1].min(v[1]), u[1].max(v[1]));
        let (r0, r1) = g.ys.range(ylo, yhi);
        for r in r0..r1 {
            let y = g.ys.v[r];
            let (xlo, xhi) = if u[1] == v[1] {
                (u[0].min(v[0]), u[0].max(v[0]))
            } else {
                if y == ylo || y == yhi {
                    continue;
                }
                let x = u[0] + (y - u[1]) / (v[1] - u[1]) * (v[0] - u[0]);
                (x, x)
            };
            let (c0, c1) = g.xs.range(xlo, xhi);
            for col in c0.saturating_sub(1)..(c1 + 1).min(g.width) {
                let p = [g.xs.v[col], y];
                if p == u || p == v {
                    continue;
                }
                let within = p[0] >= u[0].min(v[0]) && p[0] <= u[0].max(v[0]);
                if within && orient2d(co(u), co(v), co(p)) == 0.0 {
                    out.push((r as u32, col as u32, t));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// The sweep: calls `on_span(position, row, c0, c1)` for every run of
/// pixel centres `c0..c1` of `row` owned by a triangle of `lv`, row by
/// row from the first raster row. With `ordered`, the runs of a row come
/// left to right in column order (else in cut order). Every centre in the
/// closed domain is handed to exactly one triangle; centres outside are not
/// handed at all.
pub fn sweep<L: RasterLevel>(
    lv: &L,
    g: &PixelGrid,
    ordered: bool,
    interrupt: &mut Interrupt<'_>,
    on_span: &mut dyn FnMut(u32, usize, usize, usize),
) -> Result<(), TinError> {
    let mut tk = Ticker::new(interrupt);
    let ev = Events::new(lv, g, &mut tk)?;
    ev.run(0..g.height, ordered, &mut tk, on_span)
}

/// Pixels per band of rows in [`sweep_par`] (a band is a few milliseconds
/// of work).
const BAND_PIXELS: usize = 1 << 18;

/// [`sweep`] (unordered) on `tin::par`'s threads: the rows are cut into
/// bands, each band is swept on its own (its starting cut rebuilt from the
/// events, in the order the whole sweep would have it) and `span` maps each
/// run to a value there; `consume` then gets the values on this thread in
/// exactly the order [`sweep`] hands the runs, whatever the thread count.
/// Interrupts are checked between batches of bands.
pub fn sweep_par<S: Send, L: RasterLevel>(
    lv: &L,
    g: &PixelGrid,
    interrupt: &mut Interrupt<'_>,
    span: &(dyn Fn(u32, usize, usize, usize) -> S + Sync),
    consume: &mut dyn FnMut(S),
) -> Result<(), TinError> {
    let mut tk = Ticker::new(interrupt);
    let ev = Events::new(lv, g, &mut tk)?;
    if crate::par::threads() <= 1 {
        return ev.run(0..g.height, false, &mut tk, &mut |t, r, c0, c1| {
            consume(span(t, r, c0, c1))
        });
    }
    let rows = (BAND_PIXELS / g.width.max(1)).max(1);
    let bands: Vec<std::ops::Range<usize>> = (0..g.height)
        .step_by(rows)
        .map(|r| r..(r + rows).min(g.height))
        .collect();
    crate::par::map_batched(
        &bands,
        |b| {
            let mut out = Vec::new();
            let mut none = || Ok(());
            let mut quiet = Ticker::new(&mut none);
            ev.run(b.clone(), false, &mut quiet, &mut |t, r, c0, c1| {
                out.push(span(t, r, c0, c1))
            })
            .map(|()| out)
        },
        tk.callback(),
        &mut |band| {
            for v in band? {
                consume(v);
            }
            Ok(())
        },
    )
}

/// What the sweep needs before its first row: triangles bucketed by their
/// first row, and the extra centres on the domain's boundary.
struct Events<'a, L: RasterLevel> {
    lv: &'a L,
    g: &'a PixelGrid,
    /// `bucket[start[r]..start[r + 1]]`: (position, first row after it) of
    /// the triangles whose first row is `r`
    start: Vec<u32>,
    bucket: Vec<(u32, u32)>,
    extras: Vec<(u32, u32, u32)>,
}

impl<'a, L: RasterLevel> Events<'a, L> {
    fn new(lv: &'a L, g: &'a PixelGrid, tk: &mut Ticker) -> Result<Events<'a, L>, TinError> {
        let h = g.height;
        // events: triangles bucketed by their first row (counting sort)
        let mut first = vec![0u32; h + 1];
        let mut span_of = Vec::with_capacity(lv.count());
        for t in 0..lv.count() as u32 {
            tk.tick()?;
            let cs = lv.corners(t as usize);
            let ylo = cs[0][1].min(cs[1][1]).min(cs[2][1]);
            let yhi = cs[0][1].max(cs[1][1]).max(cs[2][1]);
            let (r0, r1) = g.ys.range(ylo, yhi);
            // a triangle whose x range holds no column's centre owns no
            // pixel: left out, so a window of a large level sweeps only the
            // triangles over it, not its whole band of rows
            let xlo = cs[0][0].min(cs[1][0]).min(cs[2][0]);
            let xhi = cs[0][0].max(cs[1][0]).max(cs[2][0]);
            let (c0, c1) = g.xs.range(xlo, xhi);
            if r0 < r1 && c0 < c1 {
                first[r0] += 1;
                span_of.push((t, r0 as u32, r1 as u32));
            }
        }
        let mut start = vec![0u32; h + 1];
        let mut acc = 0u32;
        for r in 0..h {
            start[r] = acc;
            acc += first[r];
        }
        start[h] = acc;
        let mut fill = start.clone();
        let mut bucket = vec![(0u32, 0u32); span_of.len()];
        for &(t, r0, r1) in &span_of {
            let k = &mut fill[r0 as usize];
            bucket[*k as usize] = (t, r1);
            *k += 1;
        }
        drop(span_of);
        let extras = if g.half_open {
            Vec::new()
        } else {
            hull_extras(lv, g)?
        };
        Ok(Events {
            lv,
            g,
            start,
            bucket,
            extras,
        })
    }

    /// Sweep the rows `rows` (see [`sweep`]).
    fn run(
        &self,
        rows: std::ops::Range<usize>,
        ordered: bool,
        tk: &mut Ticker,
        on_span: &mut dyn FnMut(u32, usize, usize, usize),
    ) -> Result<(), TinError> {
        let (lv, g) = (self.lv, self.g);
        let (start, bucket, extras) = (&self.start, &self.bucket, &self.extras);
        // the cut: triangle, end row, corners; at the first row of the band
        // it holds the triangles begun above that are still open, in the
        // order a sweep from row 0 would have them
        let mut cut: Vec<CutTri> = Vec::new();
        for r in 0..rows.start {
            for &(t, r1) in &bucket[start[r] as usize..start[r + 1] as usize] {
                if r1 as usize > rows.start {
                    cut.push(CutTri::new(t, r1, lv.corners(t as usize)));
                }
            }
        }
        let mut ex = extras.partition_point(|e| (e.0 as usize) < rows.start);
        let mut row_spans: Vec<(usize, usize, u32)> = Vec::new();
        let (xs, w) = (&g.xs.v[..], g.width);
        let (x0, sx) = (xs.first().copied().unwrap_or(0.0), g.xs.step);
        let inv_sx = 1.0 / sx;
        for r in rows {
            for &(t, r1) in &bucket[start[r] as usize..start[r + 1] as usize] {
                cut.push(CutTri::new(t, r1, lv.corners(t as usize)));
            }
            let y = g.ys.v[r];
            row_spans.clear();
            for ct in &cut {
                tk.tick()?;
                let (t, cs) = (&ct.t, &ct.cs);
                let (xl, xr, err) = ct.row_interval(y);
                if xl > xr {
                    continue;
                }
                // candidate columns from the index-space interval, with slack
                // for rounding; a candidate is decided by comparing its centre
                // with the rounded ends, and only within the error bound (or on
                // a row through a vertex, where the row may run along an edge)
                // by the exact rule
                let (ul, ur) = if sx > 0.0 {
                    ((xl - x0) * inv_sx, (xr - x0) * inv_sx)
                } else {
                    ((xr - x0) * inv_sx, (xl - x0) * inv_sx)
                };
                let d = err * inv_sx.abs() + 1e-9 * (1.0 + ul.abs().max(ur.abs()));
                let a0 = ((ul - d).floor() as isize).clamp(0, w as isize) as usize;
                let a1 =
                    (((ur + d).ceil() as isize).saturating_add(1)).clamp(0, w as isize) as usize;
                let on_vertex_row = cs.iter().any(|p| p[1] == y);
                let own = |i: usize| {
                    let x = xs[i];
                    if x < xl - err || x > xr + err {
                        false
                    } else if !on_vertex_row && x > xl + err && x < xr - err {
                        true
                    } else {
                        owns(cs, [x, y])
                    }
                };
                let Some(lo) = (a0..a1).find(|&i| own(i)) else {
                    continue;
                };
                let end = (lo..a1).rev().find(|&i| own(i)).map_or(lo + 1, |i| i + 1);
                if ordered {
                    row_spans.push((lo, end, *t));
                } else {
                    on_span(*t, r, lo, end);
                }
            }
            while ex < extras.len() && extras[ex].0 as usize == r {
                let (_, col, t) = extras[ex];
                if ordered {
                    row_spans.push((col as usize, col as usize + 1, t));
                } else {
                    on_span(t, r, col as usize, col as usize + 1);
                }
                ex += 1;
            }
            if ordered {
                row_spans.sort_unstable();
                for &(c0, c1, t) in &row_spans {
                    on_span(t, r, c0, c1);
                }
            }
            cut.retain(|ct| ct.end_row as usize > r + 1);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::stats::*;
    use super::*;

    #[test]
    fn axis_ranges_both_directions() {
        let inc = Axis::new(vec![0.5, 1.5, 2.5, 3.5], 1.0);
        assert_eq!(inc.range(1.5, 2.5), (1, 3));
        assert_eq!(inc.range(1.6, 2.4), (2, 2));
        assert_eq!(inc.range(-10.0, 10.0), (0, 4));
        assert_eq!(inc.range(9.0, 10.0), (4, 4));
        let dec = Axis::new(vec![3.5, 2.5, 1.5, 0.5], -1.0);
        assert_eq!(dec.range(1.5, 2.5), (1, 3));
        assert_eq!(dec.range(0.0, 0.4), (4, 4));
        assert_eq!(dec.range(3.6, 9.0), (0, 0));
    }

    /// `half_open`: tiles sharing a seam hand each centre of the seam to
    /// one of them, and together they hand out exactly the centres of the
    /// half-open rectangle (the oracle: x0 <= x < x1, y0 <= y < y1), as a
    /// single tin of their union does with the flag; without it each tile
    /// also takes the seam's centres and the single tin the closed square.
    #[test]
    fn half_open_tiles_count_each_seam_centre_once() {
        use crate::merge::raster::patch::TinLevel;
        use crate::tin::build::build;
        let rect = |x0: f64, x1: f64, y0: f64, y1: f64| {
            let mut pts = Vec::new();
            let (mut x, mut y) = (x0, y0);
            while y <= y1 {
                while x <= x1 {
                    // a bump so the tins have inner vertices and diagonals
                    pts.push([x, y, (x * 0.7).sin() * (y * 0.3).cos()]);
                    x += 1.0;
                }
                x = x0;
                y += 1.0;
            }
            build(pts, &[0.0], 0, &mut || Ok(())).unwrap()
        };
        let (west, east, whole) = (
            rect(0.0, 3.0, 0.0, 5.0),
            rect(3.0, 7.0, 0.0, 5.0),
            rect(0.0, 7.0, 0.0, 5.0),
        );
        // centres on the integers, and on the half-integers between
        for step in [1.0, 0.5] {
            let gt = GeoTransform {
                scale_x: step,
                scale_y: -step,
                ip_x: -1.0 - step / 2.0,
                ip_y: 6.0 + step / 2.0,
                skew_x: 0.0,
                skew_y: 0.0,
            };
            let (w, h) = ((9.0 / step) as usize + 1, (7.0 / step) as usize + 1);
            let mut g = PixelGrid::new(&gt, w, h).unwrap();
            let counts = |t: &crate::tin::Tin, g: &PixelGrid| {
                let mut seen = vec![0u32; w * h];
                let lv = TinLevel::new(t, 0).unwrap();
                sweep(&lv, g, false, &mut || Ok(()), &mut |_, r, c0, c1| {
                    for c in c0..c1 {
                        seen[r * w + c] += 1;
                    }
                })
                .unwrap();
                seen
            };
            let inside = |r: usize, c: usize, closed: bool| {
                let (x, y) = (g.xs.v[c], g.ys.v[r]);
                if closed {
                    (0.0..=7.0).contains(&x) && (0.0..=5.0).contains(&y)
                } else {
                    (0.0..7.0).contains(&x) && (0.0..5.0).contains(&y)
                }
            };
            for half_open in [false, true] {
                g.half_open = half_open;
                let (a, b, one) = (counts(&west, &g), counts(&east, &g), counts(&whole, &g));
                for r in 0..h {
                    for c in 0..w {
                        let k = r * w + c;
                        let on_seam = g.xs.v[c] == 3.0 && inside(r, c, true);
                        let tiles = a[k] + b[k];
                        if half_open {
                            assert_eq!(
                                tiles,
                                inside(r, c, false) as u32,
                                "tiles, step {step}, {r} {c}"
                            );
                            assert_eq!(
                                one[k],
                                inside(r, c, false) as u32,
                                "single, step {step}, {r} {c}"
                            );
                        } else {
                            assert_eq!(one[k], inside(r, c, true) as u32);
                            assert_eq!(tiles, inside(r, c, true) as u32 + on_seam as u32);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn tie_rule_is_a_partition_of_a_vertex_fan() {
        // eight triangles around the origin, every centre on an edge or the
        // vertex: each of the 5 x 5 lattice points inside is owned once
        let ring = [
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [-1.0, 1.0],
            [-1.0, 0.0],
            [-1.0, -1.0],
            [0.0, -1.0],
            [1.0, -1.0],
        ];
        for i in -2i32..=2 {
            for j in -2i32..=2 {
                let p = [i as f64 * 0.25, j as f64 * 0.25];
                let n = (0..8)
                    .filter(|&k| owns(&[[0.0, 0.0], ring[k], ring[(k + 1) % 8]], p))
                    .count();
                assert_eq!(n, 1, "{p:?} owned {n} times");
            }
        }
    }

    #[test]
    fn mode_smallest_on_ties() {
        assert_eq!(mode(&mut [3.0, 1.0, 3.0, 1.0, 2.0]), Some(1.0));
        assert_eq!(mode(&mut [5.0, 2.0, 5.0]), Some(5.0));
        assert_eq!(mode(&mut []), None);
    }
}
