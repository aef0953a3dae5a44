//! Tiles over their data only (`tin_tiles(..., fill_gaps => false)`, issue
//! 48): a tile's terrain is the valid pixels' squares within the hull of
//! its samples, holes included, as `tin_from_raster(..., fill_gaps =>
//! false)` is for one raster, and two tiles of a seam agree on it.
//!
//! A tile whose data fills the hull of its samples (no nodata pixel's
//! square reaches inside it, [`data_cuts_hull`]) is built on the lattice
//! with keep_border as with `fill_gaps => true` ([`build_tile_kept`]):
//! the same tin. Any other is built over its valid squares
//! ([`build_lattice_window_domain`]): the squares clipped to the window's
//! outer pixel centres (the seam lines, [`window_outline`]) are its
//! boundary, and the boundary's pieces on a seam line are chosen from their
//! samples alone, so they agree with the tile beside it:
//! - a tile built on the lattice beside it has no nodata on their shared
//!   column between its hull's ends, so the piece there is that hull side,
//!   the same samples in the same order, with the same kept ones;
//! - a tile built over its data beside it has the same pieces: the runs of
//!   valid pixels on the shared column (half a pixel past their end
//!   samples, a run's end taking its end sample's height), cut at the ends
//!   of the hull, which are the column's first and last valid pixels in
//!   both.
//!
//! Seen from both tiles, a seam has the same vertices and heights, and the
//! domains meet along it without a gap or an overlap.

use super::build::{Border, build_lattice_window_domain};
use super::dense::Dense;
use super::domain::cell_outline;
use super::lattice::Lattice;
use super::tile::{Wanted, build_tile_kept, strip_wanted};
use super::{Tin, TinError};
use crate::interrupt::Interrupt;
use crate::polygon::Area;

/// The valid pixels' squares of a window of `w x h` pixels (`valid(col,
/// row)` in its frame) clipped to its outer pixel centres (columns `0` and
/// `w - 1`, rows `0` and `h - 1`), as rings in that frame (exact: corners
/// at whole and half pixels). Outer rings have positive area in the frame,
/// holes negative; empty for a window less than two pixels wide or high.
///
/// ```
/// use tinmerge_core::tin::tile_domain::window_outline;
/// // 3 x 3 pixels, the middle one nodata: the square 0..2 less the hole
/// // of the middle pixel's square
/// let rings = window_outline(3, 3, &|c, r| !(c == 1 && r == 1));
/// let area = |r: &Vec<[f64; 2]>| (0..r.len()).map(|i| {
///     let (a, b) = (r[i], r[(i + 1) % r.len()]);
///     (a[0] * b[1] - b[0] * a[1]) / 2.0
/// }).sum::<f64>();
/// assert_eq!(rings.iter().map(area).sum::<f64>(), 4.0 - 1.0);
/// ```
pub fn window_outline(
    w: usize,
    h: usize,
    valid: &dyn Fn(usize, usize) -> bool,
) -> Vec<Vec<[f64; 2]>> {
    if w < 2 || h < 2 {
        return Vec::new();
    }
    // quarters of pixels: quarter i spans i / 2 .. (i + 1) / 2 of the frame,
    // in pixel (i + 1) / 2
    let rings = cell_outline(2 * (w - 1), 2 * (h - 1), &|i, j| {
        valid(i.div_ceil(2), j.div_ceil(2))
    });
    rings
        .into_iter()
        .map(|r| {
            r.into_iter()
                .map(|p| [p[0] as f64 / 2.0, p[1] as f64 / 2.0])
                .collect()
        })
        .collect()
}

/// Whether a nodata pixel's square of the window `d` (its frame, NaN
/// without data) reaches inside the convex hull of its valid pixel centres
/// (exact: separating axes of the square and the hull, in half pixels).
/// Such a tile's data does not fill its hull.
pub fn data_cuts_hull(d: &Dense) -> bool {
    let hull: Vec<(i64, i64)> = super::build::dense_hull(d)
        .into_iter()
        .map(|i| {
            let (c, r) = d.col_row(i);
            (2 * c, 2 * r)
        })
        .collect();
    let n = hull.len();
    if n < 3 {
        return false;
    }
    let orient = |a: (i64, i64), b: (i64, i64), p: (i64, i64)| -> i128 {
        (b.0 - a.0) as i128 * (p.1 - a.1) as i128 - (b.1 - a.1) as i128 * (p.0 - a.0) as i128
    };
    let area2: i128 = (0..n)
        .map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % n]);
            a.0 as i128 * b.1 as i128 - b.0 as i128 * a.1 as i128
        })
        .sum();
    let s: i128 = if area2 > 0 { 1 } else { -1 };
    let (x0, x1) = (
        hull.iter().map(|p| p.0).min(),
        hull.iter().map(|p| p.0).max(),
    );
    let (y0, y1) = (
        hull.iter().map(|p| p.1).min(),
        hull.iter().map(|p| p.1).max(),
    );
    let (Some(x0), Some(x1), Some(y0), Some(y1)) = (x0, x1, y0, y1) else {
        return false;
    };
    (0..d.z.len()).any(|i| {
        if d.valid(i) {
            return false;
        }
        let (c, r) = d.col_row(i);
        let (cx, cy) = (2 * c, 2 * r);
        // the square's own axes (it spans cx - 1 ..= cx + 1: separated when
        // cx + 1 <= x0, that is cx < x0 in whole half pixels)
        if cx < x0 || cx > x1 || cy < y0 || cy > y1 {
            return false;
        }
        let corners = [
            (cx - 1, cy - 1),
            (cx + 1, cy - 1),
            (cx + 1, cy + 1),
            (cx - 1, cy + 1),
        ];
        // the hull's sides: separated when the whole square is on or
        // outside one
        !(0..n).any(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % n]);
            corners.iter().all(|&p| s * orient(a, b, p) <= 0)
        })
    })
}

/// A tile of a grid (`tin_tiles`, `tin_tiles_from_table`): `samples`
/// (column, row, value on `lattice`) of its window of `size` pixels whose
/// first pixel is `origin`, keeping the seam samples `keep`. With
/// `fill_gaps`, or when its data fills the hull of its samples,
/// [`build_tile_kept`]'s tile; otherwise over its data only: the domain the
/// valid pixels' squares within that hull, and the tile asks of its seams
/// what [`build_tile_kept`]'s would (the seam samples at the ends of the
/// grid segments of the strip along its hull where an edge of its domain
/// crosses them over the tolerance). `Ok(None)` when the samples cannot be
/// triangulated.
#[allow(clippy::too_many_arguments)]
pub fn build_tile_window(
    samples: Vec<[f64; 3]>,
    lattice: &Lattice,
    origin: (i64, i64),
    size: (usize, usize),
    tolerances: &[f64],
    srid: i32,
    keep: &Border,
    fill_gaps: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Option<(Tin, Wanted)>, TinError> {
    if fill_gaps {
        return build_tile_kept(samples, lattice, origin, tolerances, srid, keep, interrupt);
    }
    let (w, h) = size;
    if samples.len() < 3 || w < 2 || h < 2 || w.saturating_mul(h) > 1 << 28 {
        return Ok(None);
    }
    let mut d = Dense {
        c0: 0,
        r0: 0,
        width: w,
        height: h,
        z: vec![f64::NAN; w * h],
    };
    for p in &samples {
        let (c, r) = (p[0] as i64 - origin.0, p[1] as i64 - origin.1);
        if c < 0
            || r < 0
            || c as usize >= w
            || r as usize >= h
            || p[0] != p[0].trunc()
            || p[1] != p[1].trunc()
        {
            return Err(TinError::InvalidParameter(format!(
                "sample ({}, {}) is not a pixel of its tile's window",
                p[0], p[1]
            )));
        }
        d.z[r as usize * w + c as usize] = p[2];
    }
    if !data_cuts_hull(&d) {
        return build_tile_kept(samples, lattice, origin, tolerances, srid, keep, interrupt);
    }
    drop(samples);
    let rings = window_outline(w, h, &|c, r| !d.z[r * w + c].is_nan());
    let boundary = Area::new(rings.into_iter().map(|r| vec![r]).collect());
    let mut wanted = Vec::new();
    match build_lattice_window_domain(
        &d,
        lattice,
        origin,
        &boundary,
        tolerances,
        srid,
        keep,
        &mut |tin| {
            wanted = strip_wanted(tin, &d, origin);
            Ok(())
        },
        interrupt,
    ) {
        Ok(tin) => Ok(Some((tin, wanted))),
        Err(TinError::Degenerate(_)) => Ok(None),
        Err(e) => Err(e),
    }
}
