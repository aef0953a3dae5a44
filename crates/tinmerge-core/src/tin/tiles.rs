//! One raster built as a grid of tins in one call: the keep_border pattern
//! of docs/scaling.md ("tiled terrains") without cutting the raster in SQL.
//!
//! Tile `(tx, ty)` holds the pixels of columns `tx * n .. (tx + 1) * n` and
//! rows `ty * n .. (ty + 1) * n` of an `n`-pixel tiling, *plus the first
//! column of its right neighbour and the first row of the one below* (where
//! they exist), and is built with `keep_border`, so every sample on its
//! hull is a vertex of every level. Two neighbouring tiles then share a
//! column (or row) of samples that are vertices of both, and their surfaces
//! are the same along the seam at every level.
//!
//! Every tile is built on the raster's own pixel lattice with the pixels'
//! whole-raster column and row numbers, so a shared pixel centre is the very
//! same point (bit for bit) in both tiles and in a tin of the whole raster:
//! no tile origin is recomputed.
//!
//! ```
//! use tinmerge_core::tin::lattice::Lattice;
//! use tinmerge_core::tin::tiles::{build_tiles, tile_window};
//! // a 5 x 4 raster of 1 m pixels, cut into 2-pixel tiles: 3 x 2 tiles
//! let values: Vec<f64> = (0..20).map(|i| ((i * 7) % 5) as f64).collect();
//! let lat = Lattice { ip_x: 0.0, ip_y: 4.0, scale_x: 1.0, scale_y: -1.0, skew_x: 0.0, skew_y: 0.0 };
//! assert_eq!(tile_window(5, 4, 2, 1, 0), (2..5, 0..3)); // its own 2 columns, then the neighbours'
//! assert_eq!(tile_window(5, 4, 2, 2, 1), (4..5, 2..4)); // the last column and row: nothing to add
//! let mut tiles = Vec::new();
//! build_tiles(&values, 5, 4, &|_| true, &lat, 2, &[0.0], 0, &mut || Ok(()),
//!             &|tx, ty, tin| (tx, ty, tin.levels[0].tris.len()), &mut |t| { tiles.push(t); Ok(()) }).unwrap();
//! // the last column of tiles is one pixel wide plus nothing: too thin to
//! // triangulate, so it gives no tin
//! assert_eq!(tiles.iter().map(|t| (t.0, t.1)).collect::<Vec<_>>(), [(0, 0), (1, 0), (0, 1), (1, 1)]);
//! ```

use super::build::{build_lattice, BuildOptions};
use super::lattice::Lattice;
use super::par;
use super::{Tin, TinError};
use crate::interrupt::Interrupt;
use std::ops::Range;

/// Number of tiles across and down for `width x height` pixels in tiles of
/// `tile_px`.
pub fn tile_counts(width: usize, height: usize, tile_px: usize) -> (usize, usize) {
    if tile_px == 0 {
        return (0, 0);
    }
    (width.div_ceil(tile_px), height.div_ceil(tile_px))
}

/// Pixel columns and rows of tile `(tx, ty)`: its own, plus the first
/// column of the tile to its right and the first row of the one below when
/// there is one.
pub fn tile_window(
    width: usize,
    height: usize,
    tile_px: usize,
    tx: usize,
    ty: usize,
) -> (Range<usize>, Range<usize>) {
    let c0 = (tx * tile_px).min(width);
    let r0 = (ty * tile_px).min(height);
    (
        c0..(c0 + tile_px + 1).min(width),
        r0..(r0 + tile_px + 1).min(height),
    )
}

/// Build every tile of a band (`values` row-major, `width x height`,
/// `valid` telling data from nodata) on `lattice`, with `tolerances` per
/// level and keep_border. `each(tx, ty, tin)` runs on the build's thread
/// (on `tin::par`'s threads when there are several: encode there), and
/// `consume` gets its results on the calling thread in row-major tile
/// order. A tile without three non-collinear valid samples (nodata, or a
/// last row or column one pixel thick) gives nothing. Interrupts are
/// checked between tiles (on threads, between rounds of one tile per
/// thread; a tile's own build is not interrupted).
#[allow(clippy::too_many_arguments)]
pub fn build_tiles<R: Send>(
    values: &[f64],
    width: usize,
    height: usize,
    valid: &(dyn Fn(f64) -> bool + Sync),
    lattice: &Lattice,
    tile_px: usize,
    tolerances: &[f64],
    srid: i32,
    interrupt: &mut Interrupt<'_>,
    each: &(dyn Fn(usize, usize, Tin) -> R + Sync),
    consume: &mut dyn FnMut(R) -> Result<(), TinError>,
) -> Result<(), TinError> {
    if tile_px < 2 {
        return Err(TinError::InvalidParameter(format!(
            "tile_px must be at least 2 pixels, got {tile_px}"
        )));
    }
    if values.len() != width * height {
        return Err(TinError::InvalidParameter(format!(
            "raster band has {} values for {width} x {height} pixels",
            values.len()
        )));
    }
    let (nx, ny) = tile_counts(width, height, tile_px);
    let tiles: Vec<(usize, usize)> = (0..ny)
        .flat_map(|ty| (0..nx).map(move |tx| (tx, ty)))
        .collect();
    let opts = BuildOptions { keep_border: true };
    // one tile: Ok(None) when it has too few samples to triangulate
    let one = |&(tx, ty): &(usize, usize),
               interrupt: &mut Interrupt<'_>|
     -> Result<Option<R>, TinError> {
        let (cols, rows) = tile_window(width, height, tile_px, tx, ty);
        let mut samples = Vec::new();
        for r in rows {
            for c in cols.clone() {
                let v = values[r * width + c];
                if valid(v) {
                    samples.push([c as f64, r as f64, v]);
                }
            }
        }
        if samples.len() < 3 {
            return Ok(None);
        }
        match build_lattice(samples, lattice, tolerances, srid, opts, interrupt) {
            Ok(tin) => Ok(Some(each(tx, ty, tin))),
            Err(TinError::Degenerate(_)) => Ok(None),
            Err(e) => Err(e),
        }
    };
    if par::threads() <= 1 {
        for t in &tiles {
            interrupt()?;
            if let Some(r) = one(t, interrupt)? {
                consume(r)?;
            }
        }
        return Ok(());
    }
    // one tile per thread at a time (a tile is a whole build: interrupts
    // are seen between tiles, not within one)
    for batch in tiles.chunks(par::threads()) {
        interrupt()?;
        for r in par::map(batch, |t| one(t, &mut || Ok(()))) {
            if let Some(r) = r? {
                consume(r)?;
            }
        }
    }
    Ok(())
}
