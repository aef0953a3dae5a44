//! The surface of a level as a raster: its height at every pixel centre
//! (`tin_as_raster`), by filling each triangle's rows of centres rather
//! than a point location per pixel.
//!
//! **The same heights as `tin_height`, bit for bit.** Every pixel centre of
//! the closed domain is given to the triangle `tin_height` interpolates in:
//! among the domain triangles whose closed triangle holds it, the smallest
//! id ([`canonical`](crate::tin::locate::canonical)). [`triangles_at`] finds it by letting each
//! triangle, in increasing id order, take the centres it holds that no
//! smaller id took; the height is then [`interpolate`] there, the formula
//! `tin_height` uses. A row's centres well inside a triangle's edges are
//! taken by comparing them with the row's rounded ends; those within the
//! rounding bound of an edge (centres on an edge or a vertex) by exact
//! orientation tests. Centres off the domain (off the hull, on void
//! triangles) have no height: NaN here, the nodata value in the raster
//! written.
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
use crate::interrupt::{Interrupt, Ticker};
use crate::io::raster::GeoTransform;
use crate::merge::raster::PixelGrid;
use crate::tin::{Tin, interpolate};
use robust::{Coord, orient2d};
use std::sync::Mutex;

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
    let grid = PixelGrid::new(gt, width, height)?;
    let tris = triangles_on(tin, level, &grid, interrupt)?;
    let mut z = vec![f64::NAN; tris.len()];
    in_bands(&mut z, width, 64, interrupt, |first, zs| {
        // the corners of the last triangle met (a row's centres come in
        // runs of one triangle)
        let mut last = (u32::MAX, [[0.0; 3]; 3]);
        for (i, slot) in zs.iter_mut().enumerate() {
            let t = tris[first * width + i];
            if t == u32::MAX {
                continue;
            }
            if t != last.0 {
                last = (t, tin.corners(level, t));
            }
            let (c, r) = (i % width, first + i / width);
            *slot = interpolate(&last.1, grid.xs.v[c], grid.ys.v[r]);
        }
    })?;
    Ok(z)
}

/// The triangle of `level` under each centre of the grid: the smallest id
/// among the domain triangles whose closed triangle holds it (the one
/// `tin_height` interpolates in, [`canonical`](crate::tin::locate::canonical)), row-major from the
/// top row; `u32::MAX` off the domain (off the hull, on void triangles).
///
/// Each domain triangle writes itself, in increasing id order, into the
/// centres it holds that no smaller id took ([`Rows`]). Bands of rows run
/// on `tin::par`'s threads, each band holding the triangles over it; the
/// answer does not depend on the thread count.
pub fn triangles_at(
    tin: &Tin,
    level: usize,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    triangles_on(tin, level, &PixelGrid::new(gt, width, height)?, interrupt)
}

/// [`triangles_at`] on the centres of `grid`.
fn triangles_on(
    tin: &Tin,
    level: usize,
    grid: &PixelGrid,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<u32>, TinError> {
    let (width, height) = (grid.width, grid.height);
    let lv = tin.levels.get(level).ok_or(TinError::LevelOutOfRange {
        level: level as i64,
        num_levels: tin.levels.len(),
    })?;
    let n = width
        .checked_mul(height)
        .ok_or_else(|| TinError::TooLarge(format!("a {width} x {height} raster")))?;
    let mut tris = vec![u32::MAX; n];
    if n == 0 {
        return Ok(tris);
    }
    // the triangles over each band of rows (with their rows), in
    // increasing id order
    let rows = height.div_ceil(8 * crate::par::threads()).max(1);
    let mut lists: Vec<Vec<(u32, u32, u32)>> = vec![Vec::new(); height.div_ceil(rows)];
    let (xa, xb) = (grid.xs.v[0], grid.xs.v[width - 1]);
    let (gx0, gx1) = (xa.min(xb), xa.max(xb));
    let mut tk = Ticker::new(interrupt);
    for t in 0..lv.num_domain() as u32 {
        tk.tick()?;
        let c = tin.corners(level, t);
        let xlo = c[0][0].min(c[1][0]).min(c[2][0]);
        let xhi = c[0][0].max(c[1][0]).max(c[2][0]);
        if xhi < gx0 || xlo > gx1 {
            continue;
        }
        let (r0, r1) = grid.ys.range(
            c[0][1].min(c[1][1]).min(c[2][1]),
            c[0][1].max(c[1][1]).max(c[2][1]),
        );
        if r0 < r1 {
            for list in &mut lists[r0 / rows..=(r1 - 1) / rows] {
                list.push((t, r0 as u32, r1 as u32));
            }
        }
    }
    in_bands(&mut tris, width, rows, tk.callback(), |first, out| {
        let band = first..(first + rows).min(height);
        for &(t, r0, r1) in &lists[first / rows] {
            let rs = (r0 as usize).max(band.start)..(r1 as usize).min(band.end);
            Rows::new(tin.corners(level, t)).fill(t, grid, rs, band.start, out);
        }
    })?;
    Ok(tris)
}

/// `f(first row, its rows of out)` for the bands of `rows` rows of the
/// row-major `out` (`width` values a row), on `tin::par`'s threads, each
/// band writing only its own rows; interrupts checked between batches of
/// bands.
fn in_bands<T: Send>(
    out: &mut [T],
    width: usize,
    rows: usize,
    interrupt: &mut Interrupt<'_>,
    f: impl Fn(usize, &mut [T]) + Sync + Send,
) -> Result<(), TinError> {
    let step = (rows * width).max(1);
    let parts: Vec<(usize, Mutex<&mut [T]>)> = out
        .chunks_mut(step)
        .enumerate()
        .map(|(b, s)| (b * rows, Mutex::new(s)))
        .collect();
    crate::par::map_batched(
        &parts,
        |(first, m)| f(*first, &mut m.lock().unwrap_or_else(|e| e.into_inner())),
        interrupt,
        &mut |()| Ok(()),
    )
}

/// One triangle's rows of centres: its corners, the y of the middle one
/// (sorted by y: `lo`, `mid`, `hi`) and its edges `lo`-`hi`, `lo`-`mid`,
/// `mid`-`hi`.
struct Rows {
    v: [Coord<f64>; 3],
    mid_y: f64,
    edges: [Edge; 3],
}

/// An edge as a row sees it: `x = ax + (y - ay) k` (`k = dx/dy`, 0 for a
/// horizontal one) kept within `lo..=hi`, rounded by at most `err`.
struct Edge {
    ax: f64,
    ay: f64,
    k: f64,
    lo: f64,
    hi: f64,
    err: f64,
}

impl Edge {
    #[inline]
    fn at(&self, y: f64) -> f64 {
        let x = self.ax + (y - self.ay) * self.k;
        if x < self.lo {
            self.lo
        } else if x > self.hi {
            self.hi
        } else {
            x
        }
    }
}

impl Rows {
    fn new(c: [[f64; 3]; 3]) -> Rows {
        let mut p = [[c[0][0], c[0][1]], [c[1][0], c[1][1]], [c[2][0], c[2][1]]];
        p.sort_by(|a, b| a[1].total_cmp(&b[1]));
        let ymax = p[0][1].abs().max(p[2][1].abs());
        let edge = |a: [f64; 2], b: [f64; 2]| {
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let k = if dy != 0.0 { dx / dy } else { 0.0 };
            Edge {
                ax: a[0],
                ay: a[1],
                k,
                lo: a[0].min(b[0]),
                hi: a[0].max(b[0]),
                // as the sweep's bound: a few ulps of each operand, the
                // slope amplifying those of y
                err: (ymax * k.abs() + a[1].abs() * k.abs() + a[0].abs() + dx.abs())
                    * (16.0 * f64::EPSILON),
            }
        };
        let mut edges = [edge(p[0], p[2]), edge(p[0], p[1]), edge(p[1], p[2])];
        if p[0][1] == p[2][1] {
            // no area, all on one row (the one that uses the long edge and
            // the upper one): from the least x to the greatest
            let (lo, hi) = (
                p.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min),
                p.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max),
            );
            edges[0] = edge([lo, p[0][1]], [hi, p[0][1]]);
            edges[2] = edge([hi, p[0][1]], [lo, p[0][1]]);
        }
        Rows {
            v: c.map(|q| Coord { x: q[0], y: q[1] }),
            mid_y: p[1][1],
            edges,
        }
    }

    /// Whether the closed triangle holds `(x, y)`, exactly (the corners
    /// are counter-clockwise).
    fn holds(&self, x: f64, y: f64) -> bool {
        let (v, p) = (&self.v, Coord { x, y });
        orient2d(v[0], v[1], p) >= 0.0
            && orient2d(v[1], v[2], p) >= 0.0
            && orient2d(v[2], v[0], p) >= 0.0
    }

    /// Writes `t` into the centres of `rows` (the rows of `out` start at
    /// `first`) that the closed triangle holds and no triangle took yet.
    fn fill(
        &self,
        t: u32,
        grid: &PixelGrid,
        rows: std::ops::Range<usize>,
        first: usize,
        out: &mut [u32],
    ) {
        let (xs, w) = (&grid.xs.v[..], grid.width);
        let (x0, inv) = (xs[0], 1.0 / grid.xs.step());
        let wf = w as f64;
        for r in rows {
            let y = grid.ys.v[r];
            // the row meets the long edge and one of the two short ones
            // (the upper where the middle corner is below or on it)
            let long = &self.edges[0];
            let short = &self.edges[if y < self.mid_y { 1 } else { 2 }];
            let (xa, xb) = (long.at(y), short.at(y));
            let (xl, xr) = if xa <= xb { (xa, xb) } else { (xb, xa) };
            let err = if long.err > short.err {
                long.err
            } else {
                short.err
            };
            let (lo_out, lo_in, hi_in, hi_out) = (xl - err, xl + err, xr - err, xr + err);
            // candidate columns from the index-space interval, with slack
            // for rounding (truncation is floor on the clamped values)
            let (ul, ur) = ((xl - x0) * inv, (xr - x0) * inv);
            let (ul, ur) = if ul <= ur { (ul, ur) } else { (ur, ul) };
            let d = err * inv.abs() + 1e-9 * (1.0 + ur.abs() + ul.abs());
            let a0 = (ul - d).clamp(0.0, wf) as usize;
            let a1 = ((ur + d).clamp(0.0, wf) as usize + 1).min(w);
            let Some(row) = out.get_mut((r - first) * w..(r - first + 1) * w) else {
                return;
            };
            let sure = |x: f64| x > lo_in && x < hi_in;
            let edge = |c: usize, row: &mut [u32]| {
                let x = xs[c];
                if row[c] == u32::MAX && x >= lo_out && x <= hi_out && self.holds(x, y) {
                    row[c] = t;
                }
            };
            // the candidates not surely inside, from each end; between
            // them every centre is inside
            let mut c = a0;
            while c < a1 && !sure(xs[c]) {
                edge(c, row);
                c += 1;
            }
            let mut e = a1;
            while e > c && !sure(xs[e - 1]) {
                edge(e - 1, row);
                e -= 1;
            }
            for slot in &mut row[c..e] {
                if *slot == u32::MAX {
                    *slot = t;
                }
            }
        }
    }
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
