//! The surface of a level as a raster: its height at every pixel centre
//! (`tin_as_raster`), by the raster merge's scanline sweep
//! ([`crate::merge::raster::sweep_bands`], bands of rows on `tin::par`'s
//! threads) rather than a point location per pixel.
//!
//! **The same heights as `tin_height`, bit for bit.** The sweep hands every
//! pixel centre of the closed domain to one triangle; a centre strictly
//! inside it is interpolated there with [`interpolate`], the formula
//! `tin_height` uses. A centre on an edge or a vertex (a tie: several
//! closed triangles hold it) is interpolated in the triangle `tin_height`
//! picks, the smallest id among them ([`locate::canonical`]), found from the
//! sweep's triangle across the edges through the centre (only the two end
//! centres of a row's run can be such a tie, unless the row passes through
//! a corner of the triangle). Centres off the
//! domain (off the hull, on void triangles) have no height: NaN here, the
//! nodata value in the raster written.
//!
//! ```
//! use tinmerge_core::analysis::rasterize::{aligned_grid, rasterize};
//! use tinmerge_core::tin::build::build;
//! // the plane z = x + 10 y over the square (0,0)-(4,4)
//! let pts = vec![[0.0, 0.0, 0.0], [4.0, 0.0, 4.0], [4.0, 4.0, 44.0], [0.0, 4.0, 40.0]];
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! // 2 m pixels on the grid through (0, 0): 2 x 2 pixels, centres at 1 and 3
//! let (gt, w, h) = aligned_grid(&[0.0, 0.0, 4.0, 4.0], 2.0, 2.0, 0.0, 0.0).unwrap();
//! assert_eq!((w, h, gt.ip_x, gt.ip_y, gt.scale_y), (2, 2, 0.0, 4.0, -2.0));
//! let z = rasterize(&tin, 0, &gt, w, h, &mut || Ok(())).unwrap();
//! assert_eq!(z, [31.0, 33.0, 11.0, 13.0]);
//! ```

use crate::error::TinError;
use crate::interrupt::Interrupt;
use crate::io::raster::GeoTransform;
use crate::merge::raster::patch::TinLevel;
use crate::merge::raster::{PixelGrid, sweep_bands};
use crate::tin::{Tin, interpolate, locate};
use robust::{Coord, orient2d};

/// Largest width or height of a PostGIS raster (its header holds 16 bits).
pub const MAX_SIDE: usize = 65535;

/// Heights of `level` at the centres of the `width` x `height` north-up
/// raster `gt` ([`GeoTransform::centre`], the centres `ST_PixelAsCentroid`
/// gives), row-major from the top row; NaN where the centre is off the
/// domain. Rotated or skewed grids are refused.
pub fn rasterize(
    tin: &Tin,
    level: usize,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<f64>, TinError> {
    Ok(sweep_centres(tin, level, gt, width, height, true, false, interrupt)?.0)
}

/// The triangle of `level` under each centre of the grid (as
/// [`rasterize`] hands them: tin_height's on a tie), row-major from the top
/// row; `u32::MAX` off the domain.
pub fn triangles_at(
    tin: &Tin,
    level: usize,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    Ok(sweep_centres(tin, level, gt, width, height, false, true, interrupt)?.1)
}

/// The sweep behind [`rasterize`] and [`triangles_at`]: each centre's
/// height and its triangle, those asked for (the other left empty).
#[allow(clippy::too_many_arguments)]
fn sweep_centres(
    tin: &Tin,
    level: usize,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    heights: bool,
    triangles: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<f64>, Vec<u32>), TinError> {
    let grid = PixelGrid::new(gt, width, height)?;
    let lv = TinLevel::new(tin, level)?;
    let n = width
        .checked_mul(height)
        .ok_or_else(|| TinError::TooLarge(format!("a {width} x {height} raster")))?;
    let mut z = if heights {
        vec![f64::NAN; n]
    } else {
        Vec::new()
    };
    let mut tris = if triangles {
        vec![u32::MAX; n]
    } else {
        Vec::new()
    };
    // bands of rows on the threads, each writing its own rows
    let rows = height.div_ceil(8 * crate::par::threads()).max(1);
    let step = (rows * width).max(1);
    let (mut zb, mut tb) = (z.chunks_mut(step), tris.chunks_mut(step));
    let parts: Vec<_> = (0..height.div_ceil(rows))
        .map(|k| {
            let zs: &mut [f64] = zb.next().unwrap_or_default();
            let ts: &mut [u32] = tb.next().unwrap_or_default();
            (k * rows..(k + 1) * rows, (k * rows, zs, ts))
        })
        .collect();
    sweep_bands(
        &lv,
        &grid,
        parts,
        interrupt,
        &|(r0, zs, ts), t, row, c0, c1| {
            let c = tin.corners(level, t);
            let v = c.map(|v| Coord { x: v[0], y: v[1] });
            let y = grid.ys.v[row];
            let base = (row - *r0) * width;
            // a row through no corner crosses the triangle's inside between
            // its two ends: only the end columns can be on an edge
            let through = c.iter().any(|p| p[1] == y);
            for col in c0..c1 {
                let x = grid.xs.v[col];
                let inside = (!through && col > c0 && col + 1 < c1) || {
                    let p = Coord { x, y };
                    orient2d(v[0], v[1], p) > 0.0
                        && orient2d(v[1], v[2], p) > 0.0
                        && orient2d(v[2], v[0], p) > 0.0
                };
                let u = if inside {
                    t
                } else {
                    // on an edge or a vertex: tin_height's triangle
                    locate::canonical(tin, level, t, x, y)
                };
                if let Some(slot) = zs.get_mut(base + col) {
                    *slot = if u == t {
                        interpolate(&c, x, y)
                    } else {
                        interpolate(&tin.corners(level, u), x, y)
                    };
                }
                if let Some(slot) = ts.get_mut(base + col) {
                    *slot = u;
                }
            }
        },
    )?;
    Ok((z, tris))
}

/// The north-up grid of `size_x` x `size_y` pixels whose edges lie on the
/// lines `grid_x + k size_x`, `grid_y + k size_y` (as `gdalwarp -tap` aligns
/// to the origin), covering the rectangle `[min x, min y, max x, max y]`
/// with the fewest pixels: its georeference, width and height. A side of
/// the rectangle on a grid line ends the raster there.
pub fn aligned_grid(
    bbox: &[f64; 4],
    size_x: f64,
    size_y: f64,
    grid_x: f64,
    grid_y: f64,
) -> Result<(GeoTransform, usize, usize), TinError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !ok(size_x) || !ok(size_y) {
        return Err(TinError::InvalidParameter(format!(
            "pixel size must be positive and finite, not {size_x} x {size_y}"
        )));
    }
    if !(grid_x.is_finite() && grid_y.is_finite()) {
        return Err(TinError::InvalidParameter(format!(
            "grid origin must be finite, not ({grid_x}, {grid_y})"
        )));
    }
    let [x0, y0, x1, y1] = *bbox;
    let (k0, k1) = ((x0 - grid_x) / size_x, (x1 - grid_x) / size_x);
    let (j0, j1) = ((y0 - grid_y) / size_y, (y1 - grid_y) / size_y);
    let (c0, c1, r0, r1) = (k0.floor(), k1.ceil(), j0.floor(), j1.ceil());
    let side = |lo: f64, hi: f64| (hi - lo).max(1.0);
    let (w, h) = (side(c0, c1), side(r0, r1));
    if !(w.is_finite() && h.is_finite()) || w > MAX_SIDE as f64 || h > MAX_SIDE as f64 {
        return Err(TinError::TooLarge(format!(
            "{size_x} x {size_y} pixels over the tin's extent make a raster of {w} x {h} pixels; a PostGIS raster has at most {MAX_SIDE} a side: use larger pixels, or tiles (tin_as_raster(t, tile) over ST_MakeEmptyCoverage)"
        )));
    }
    let gt = GeoTransform {
        scale_x: size_x,
        scale_y: -size_y,
        ip_x: grid_x + c0 * size_x,
        ip_y: grid_y + (r0 + h) * size_y,
        skew_x: 0.0,
        skew_y: 0.0,
    };
    Ok((gt, w as usize, h as usize))
}
