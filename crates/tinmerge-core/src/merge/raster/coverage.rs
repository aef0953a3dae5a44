//! Exact coverage of raster pixels by triangles: for every pixel a triangle
//! of one level overlaps, the fraction of the pixel's area inside the
//! triangle (what exactextract computes for polygon zones). It backs the
//! coverage-weighted statistics of the raster merge, where small
//! triangles, which may own no pixel centre at all, still get values.
//!
//! Work is per triangle in pixel space (`u` = column, `v` = row, pixels are
//! unit squares): the triangle is clipped to each row strip it spans; the
//! columns where the strip polygon covers the whole strip height get 1
//! without arithmetic, the few partial columns at each end get the area of
//! the strip polygon clipped to the column. O(pixels touched + rows
//! spanned) per triangle, no allocation.
//!
//! Invariant (tests/raster.rs, and against exactextract in
//! tests/properties/check_raster_exactextract.py): the fractions of a pixel
//! wholly inside the domain sum to 1 (within 1e-12).
//!
//! ```
//! use tinmerge_core::io::raster::GeoTransform;
//! use tinmerge_core::merge::raster::{coverage::coverage, patch::TinLevel};
//! use tinmerge_core::tin::build::build;
//! // two triangles over the square (0,0)-(4,4), split along a diagonal
//! let pts = vec![[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [4.0, 4.0, 0.0], [0.0, 4.0, 0.0]];
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! let gt = GeoTransform { scale_x: 1.0, scale_y: -1.0, ip_x: 0.0, ip_y: 4.0, skew_x: 0.0, skew_y: 0.0 };
//! let mut area = [0.0; 2];
//! let mut on_diagonal = 0;
//! coverage(&TinLevel::new(&tin, 0).unwrap(), &gt, 4, 4, &mut || Ok(()), &mut |t, _r, _c, f| {
//!     area[t as usize] += f;
//!     if f < 1.0 { on_diagonal += 1 }
//! }).unwrap();
//! assert_eq!(area, [8.0, 8.0]); // 8 pixels' worth each
//! assert_eq!(on_diagonal, 8); // the 4 diagonal pixels, half in each triangle
//! ```

use crate::interrupt::{Interrupt, Ticker};
use crate::io::raster::GeoTransform;
use crate::merge::raster::patch::RasterLevel;
use crate::tin::TinError;

type P = [f64; 2];

/// Fractions at or below this share of a pixel are rounding noise (a
/// triangle edge running along a pixel edge) and are not reported.
pub const MIN_FRACTION: f64 = 1e-10;

/// A convex polygon of at most 8 vertices, on the stack.
#[derive(Clone, Copy)]
struct Poly {
    p: [P; 8],
    n: usize,
}

impl Poly {
    fn from(pts: &[P]) -> Poly {
        let mut p = [[0.0; 2]; 8];
        p[..pts.len()].copy_from_slice(pts);
        Poly { p, n: pts.len() }
    }

    /// The part where `side * (coord[axis] - at) >= 0` (Sutherland-Hodgman
    /// against one axis-parallel line; points on the line keep the exact
    /// coordinate `at`).
    fn clip(&self, axis: usize, at: f64, side: f64) -> Poly {
        let mut out = Poly {
            p: [[0.0; 2]; 8],
            n: 0,
        };
        if self.n == 0 {
            return out;
        }
        let mut push = |q: P| {
            if out.n < 8 {
                out.p[out.n] = q;
                out.n += 1;
            }
        };
        for i in 0..self.n {
            let a = self.p[i];
            let b = self.p[(i + 1) % self.n];
            let da = side * (a[axis] - at);
            let db = side * (b[axis] - at);
            if da >= 0.0 {
                push(a);
            }
            if (da > 0.0 && db < 0.0) || (da < 0.0 && db > 0.0) {
                let t = da / (da - db);
                let mut q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                q[axis] = at;
                // the other coordinate stays within the edge's span
                let o = 1 - axis;
                let (lo, hi) = (a[o].min(b[o]), a[o].max(b[o]));
                q[o] = q[o].clamp(lo, hi);
                push(q);
            }
        }
        out
    }

    fn area(&self) -> f64 {
        if self.n < 3 {
            return 0.0;
        }
        let o = self.p[0];
        let mut s = 0.0;
        for i in 1..self.n - 1 {
            let a = self.p[i];
            let b = self.p[i + 1];
            s += (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1]);
        }
        0.5 * s.abs()
    }

    fn range(&self, axis: usize) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for q in &self.p[..self.n] {
            lo = lo.min(q[axis]);
            hi = hi.max(q[axis]);
        }
        (lo, hi)
    }

    /// The `u` range of the vertices lying exactly on the line `v = at`.
    fn on_line(&self, at: f64) -> Option<(f64, f64)> {
        let mut r: Option<(f64, f64)> = None;
        for q in &self.p[..self.n] {
            if q[1] == at {
                r = Some(r.map_or((q[0], q[0]), |(a, b)| (a.min(q[0]), b.max(q[0]))));
            }
        }
        r
    }
}

/// Refuses what the coverage cannot handle: skewed or rotated grids, zero
/// or non-finite pixel sizes.
pub(crate) fn check_grid(gt: &GeoTransform) -> Result<(), TinError> {
    if gt.skew_x != 0.0 || gt.skew_y != 0.0 {
        return Err(TinError::InvalidParameter(format!(
            "rotated or skewed rasters are not supported (skew {} {}); resample it north-up first, e.g. with gdalwarp or ST_Transform(rast, ST_SRID(rast), scale_x, scale_y)",
            gt.skew_x, gt.skew_y
        )));
    }
    let ok = |v: f64| v.is_finite() && v != 0.0;
    if !ok(gt.scale_x) || !ok(gt.scale_y) || !gt.ip_x.is_finite() || !gt.ip_y.is_finite() {
        return Err(TinError::InvalidParameter(format!(
            "raster georeference is unusable (pixel size {} {}, upper left {} {})",
            gt.scale_x, gt.scale_y, gt.ip_x, gt.ip_y
        )));
    }
    Ok(())
}

/// Calls `on_cell(position, row, col, fraction)` for every pixel of the
/// `width x height` raster `gt` that a triangle of `lv` overlaps with a
/// positive area, `fraction` being the share of the pixel's area inside the
/// triangle (in ([`MIN_FRACTION`], 1]). Triangles in id order, rows top to bottom, columns
/// left to right. The fractions of a pixel sum to its share inside the
/// domain (1 for a pixel wholly inside), up to rounding.
pub fn coverage<L: RasterLevel>(
    lv: &L,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    interrupt: &mut Interrupt<'_>,
    on_cell: &mut dyn FnMut(u32, usize, usize, f64),
) -> Result<(), TinError> {
    let n = lv.count() as u32;
    let mut tk = Ticker::new(interrupt);
    coverage_of(lv, gt, width, height, 0..n, &mut tk, on_cell)
}

/// [`coverage`] of the triangles at positions `tris` only (in order).
pub(crate) fn coverage_of<L: RasterLevel>(
    lv: &L,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    tris: std::ops::Range<u32>,
    tk: &mut Ticker,
    on_cell: &mut dyn FnMut(u32, usize, usize, f64),
) -> Result<(), TinError> {
    check_grid(gt)?;
    let (w, h) = (width as f64, height as f64);
    let to_px =
        |p: &[f64; 2]| -> P { [(p[0] - gt.ip_x) / gt.scale_x, (p[1] - gt.ip_y) / gt.scale_y] };
    for t in tris {
        tk.tick()?;
        let cs = lv.corners(t as usize);
        let tri = Poly::from(&[to_px(&cs[0]), to_px(&cs[1]), to_px(&cs[2])]);
        let (u0, u1) = tri.range(0);
        let (v0, v1) = tri.range(1);
        if u1 <= 0.0 || v1 <= 0.0 || u0 >= w || v0 >= h {
            continue;
        }
        let r0 = v0.floor().max(0.0) as usize;
        let r1 = (v1.ceil().min(h) as usize).max(r0);
        for r in r0..r1 {
            // per row too: a coarse triangle over a fine raster is a lot of
            // pixels
            tk.tick()?;
            let (top, bot) = (r as f64, r as f64 + 1.0);
            let strip = tri.clip(1, top, 1.0).clip(1, bot, -1.0);
            if strip.n < 3 {
                continue;
            }
            let (su0, su1) = strip.range(0);
            let c0 = su0.floor().max(0.0) as usize;
            let c1 = (su1.ceil().min(w) as usize).max(c0);
            // columns wholly inside: the strip polygon spans the full row
            // height over [fa, fb] (convex: both its top and bottom sides
            // lie on the strip's lines there)
            let (f0, f1) = match (strip.on_line(top), strip.on_line(bot)) {
                (Some((a0, a1)), Some((b0, b1))) => {
                    let fa = a0.max(b0).ceil().max(c0 as f64);
                    let fb = a1.min(b1).floor().min(c1 as f64);
                    if fb > fa {
                        (fa as usize, fb as usize)
                    } else {
                        (c1, c1)
                    }
                }
                _ => (c1, c1),
            };
            for c in c0..c1 {
                if c >= f0 && c < f1 {
                    on_cell(t, r, c, 1.0);
                    continue;
                }
                let a = strip
                    .clip(0, c as f64, 1.0)
                    .clip(0, c as f64 + 1.0, -1.0)
                    .area();
                if a > MIN_FRACTION {
                    on_cell(t, r, c, a.min(1.0));
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_keeps_exact_coordinates() {
        let tri = Poly::from(&[[0.0, 0.0], [3.0, 0.3], [1.0, 2.7]]);
        let s = tri.clip(1, 1.0, 1.0).clip(1, 2.0, -1.0);
        assert!(s.n >= 3);
        assert!(s.p[..s.n].iter().all(|q| q[1] >= 1.0 && q[1] <= 2.0));
        assert!(s.on_line(1.0).is_some() && s.on_line(2.0).is_some());
    }
}
