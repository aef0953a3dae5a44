//! Cesium's geographic tiling scheme (EPSG:4326, TMS: two root tiles, y
//! counted from the south) and how a tile's zoom chooses a level.
//!
//! At zoom `z` there are `2^(z+1)` columns and `2^z` rows of tiles
//! `180 / 2^z` degrees square; tile `(x, y)` spans longitudes
//! `-180 + x * size .. -180 + (x + 1) * size` and latitudes
//! `-90 + y * size .. -90 + (y + 1) * size`.
//!
//! Cesium refines a terrain tile when its *geometric error* projected on
//! the screen exceeds its maximum screen-space error. For a
//! `CesiumTerrainProvider` that error is
//! `6378137 * 2π * 0.25 / (65 * 2) / 2^z` metres (Cesium's
//! `getEstimatedLevelZeroGeometricErrorForAHeightmap` with its defaults),
//! [`geometric_error`]. A tile is served from the coarsest level whose
//! measured vertical error is at most that ([`level_for_zoom`]), so what
//! Cesium assumes of a tile holds for it.
//!
//! ```
//! use tinmerge_core::serve::tiling::{tile_bounds, geometric_error};
//! let b = tile_bounds(1, 1, 1).unwrap();
//! assert_eq!([b.west, b.south, b.east, b.north], [-90.0, 0.0, 0.0, 90.0]);
//! assert!((geometric_error(0) - 77067.34).abs() < 0.01);
//! ```

use crate::tin::TinError;

/// The deepest zoom served: tiles of 180 / 2^24 degrees are about a
/// metre wide, far finer than any level's error needs.
pub const MAX_ZOOM: i32 = 24;

/// Cesium's geometric error of a level-0 terrain tile (metres).
pub const LEVEL0_ERROR: f64 = 6_378_137.0 * 2.0 * std::f64::consts::PI * 0.25 / (65.0 * 2.0);

/// A tile's extent in degrees. Every bound is an exact multiple of a power
/// of two, so the shared side of two neighbouring tiles is the same double
/// in both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileBounds {
    pub west: f64,
    pub south: f64,
    pub east: f64,
    pub north: f64,
}

impl TileBounds {
    pub fn intersects(&self, b: &[f64; 4]) -> bool {
        !(b[2] < self.west || b[0] > self.east || b[3] < self.south || b[1] > self.north)
    }

    pub fn contains(&self, b: &[f64; 4]) -> bool {
        b[0] >= self.west && b[2] <= self.east && b[1] >= self.south && b[3] <= self.north
    }
}

/// The edge length of a tile at zoom `z`, in degrees.
pub(crate) fn tile_size(z: i32) -> f64 {
    180.0 / f64::powi(2.0, z)
}

/// The extent of tile `(z, x, y)`; an error for a zoom outside
/// `0..=MAX_ZOOM` or a column or row outside the zoom's grid.
pub fn tile_bounds(z: i32, x: i32, y: i32) -> Result<TileBounds, TinError> {
    if !(0..=MAX_ZOOM).contains(&z) {
        return Err(TinError::InvalidParameter(format!(
            "zoom {z} is out of range: quantized-mesh tiles have zooms 0..{MAX_ZOOM}"
        )));
    }
    let cols = 2i64 << z;
    let rows = 1i64 << z;
    if !(0..cols).contains(&(x as i64)) || !(0..rows).contains(&(y as i64)) {
        return Err(TinError::InvalidParameter(format!(
            "tile {z}/{x}/{y} does not exist: at zoom {z} x is 0..{} and y is 0..{} (geographic TMS scheme, y from the south)",
            cols - 1,
            rows - 1
        )));
    }
    let s = tile_size(z);
    Ok(TileBounds {
        west: -180.0 + x as f64 * s,
        south: -90.0 + y as f64 * s,
        east: -180.0 + (x + 1) as f64 * s,
        north: -90.0 + (y + 1) as f64 * s,
    })
}

/// Cesium's geometric error of a terrain tile at zoom `z`, in metres.
pub fn geometric_error(z: i32) -> f64 {
    LEVEL0_ERROR / f64::powi(2.0, z)
}

/// The coarsest level whose measured error (`max_errors`, coarsest first)
/// is at most the tile's geometric error; the finest when none is.
pub fn level_for_zoom(max_errors: &[f64], z: i32) -> usize {
    let e = geometric_error(z);
    max_errors
        .iter()
        .position(|&m| m <= e)
        .unwrap_or(max_errors.len().saturating_sub(1))
}

/// The first zoom served from the finest level: deeper tiles would only
/// cut the same triangles smaller, so the layer stops here (Cesium
/// upsamples below it). At least `min`, at most [`MAX_ZOOM`].
pub fn max_zoom(max_errors: &[f64], min: i32) -> i32 {
    let finest = max_errors.len().saturating_sub(1);
    (0..MAX_ZOOM)
        .find(|&z| level_for_zoom(max_errors, z) == finest)
        .unwrap_or(MAX_ZOOM)
        .clamp(min.min(MAX_ZOOM), MAX_ZOOM)
}

/// The range of tiles `(x0, y0, x1, y1)` (inclusive) at zoom `z` that meet
/// the extent `b` = `[west, south, east, north]` in degrees.
pub fn tile_range(z: i32, b: &[f64; 4]) -> (i64, i64, i64, i64) {
    let s = tile_size(z);
    let cols = 2i64 << z;
    let rows = 1i64 << z;
    let col = |lon: f64| (((lon + 180.0) / s).floor() as i64).clamp(0, cols - 1);
    let row = |lat: f64| (((lat + 90.0) / s).floor() as i64).clamp(0, rows - 1);
    (col(b[0]), row(b[1]), col(b[2]), row(b[3]))
}

/// The `layer.json` of a terrain with geographic extent `bounds`
/// (`[west, south, east, north]`, degrees) whose levels have errors
/// `max_errors`: tiles `{z}/{x}/{y}.terrain`, the TMS scheme, the
/// available tiles per zoom, and `octvertexnormals` when `normals`. With
/// `fill` every tile of zoom 0 is available too (tiles off the terrain
/// are then served flat), so Cesium draws the whole globe.
pub fn layer_json(
    name: &str,
    bounds: &[f64; 4],
    max_errors: &[f64],
    normals: bool,
    fill: bool,
) -> String {
    // the zoom where the terrain is smaller than one tile: always served
    let top = max_zoom(max_errors, 0);
    let mut available = Vec::new();
    for z in 0..=top {
        let (x0, y0, x1, y1) = if z == 0 && fill {
            (0, 0, 1, 0)
        } else {
            tile_range(z, bounds)
        };
        available.push(serde_json::json!([{ "startX": x0, "startY": y0, "endX": x1, "endY": y1 }]));
    }
    let extensions: Vec<&str> = if normals {
        vec!["octvertexnormals"]
    } else {
        vec![]
    };
    let v = serde_json::json!({
        "tilejson": "2.1.0",
        "name": name,
        "description": "a tinmerge terrain served by tin_quantized_mesh",
        "version": "1.0.0",
        "format": "quantized-mesh-1.0",
        "attribution": "",
        "scheme": "tms",
        "tiles": ["{z}/{x}/{y}.terrain"],
        "projection": "EPSG:4326",
        "bounds": bounds,
        "minzoom": 0,
        "maxzoom": top,
        "available": available,
        "extensions": extensions,
    });
    v.to_string()
}
