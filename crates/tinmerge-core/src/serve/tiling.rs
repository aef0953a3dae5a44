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

/// The coarsest level whose error bound (`max_errors`, coarsest first: the
/// SQL layer passes each level's tolerance, or its measured error where
/// larger) is at most the tile's geometric error; the finest when none is.
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

/// The zooms each layer of a pyramid serves: the layers are one terrain
/// as tiled terrains of ever coarser pixels (`tin_overviews`: the table
/// of raster tiles and its PostGIS overviews, each built as tins sharing
/// their seams), `pixel_deg[i]` the size of layer `i`'s pixels in
/// degrees (the larger of their width and height), finest layer first.
///
/// Cesium's error model takes a tile of zoom `z` to be a heightmap of 65
/// x 65 samples ([`LEVEL0_ERROR`]): its spacing, `180 / 2^z / 64`
/// degrees, is the detail the zoom asks for. A zoom is served by the
/// coarsest layer whose pixels are no larger than that, or by the finest
/// when no coarser layer's are (the finest serves up to [`MAX_ZOOM`]). So
/// a tile is at most 128 pixels of the
/// next coarser layer wide, and meets at most 2 x 2 tins of its layer
/// when they are at least 128 pixels a side. `None` for a layer whose
/// pixels are no smaller than the next coarser one's (it serves no zoom).
///
/// ```
/// use tinmerge_core::serve::tiling::{pyramid_zooms, MAX_ZOOM};
/// // pixels of 1e-4° (about 10 m), and overviews of 4 and 16 times that:
/// // zoom 14's spacing is 1.7e-4°, zoom 12's 6.9e-4°, zoom 10's 2.7e-3°
/// assert_eq!(pyramid_zooms(&[1e-4, 4e-4, 16e-4]),
///            [Some((13, MAX_ZOOM)), Some((11, 12)), Some((0, 10))]);
/// // an overview no coarser than the layer below it serves nothing
/// assert_eq!(pyramid_zooms(&[1e-4, 1e-4, 4e-4]), [Some((13, MAX_ZOOM)), None, Some((0, 12))]);
/// assert_eq!(pyramid_zooms(&[1e-4]), [Some((0, MAX_ZOOM))]);
/// ```
pub fn pyramid_zooms(pixel_deg: &[f64]) -> Vec<Option<(i32, i32)>> {
    // the deepest zoom layer i's pixels are fine enough for
    let fine_to = |p: f64| -> i32 {
        if p > 0.0 && p.is_finite() {
            ((180.0 / 64.0 / p).log2().floor()).clamp(-1.0, MAX_ZOOM as f64) as i32
        } else {
            MAX_ZOOM
        }
    };
    let n = pixel_deg.len();
    let mut out = vec![None; n];
    // from the coarsest: each layer serves from the zoom after the next
    // coarser one's last
    let mut next = 0;
    for i in (0..n).rev() {
        let hi = if i == 0 {
            MAX_ZOOM
        } else {
            fine_to(pixel_deg[i])
        };
        // (not coarser than the layer below it: that one serves its zooms)
        let coarser = i == 0 || pixel_deg[i] > pixel_deg[i - 1];
        if hi >= next && coarser {
            out[i] = Some((next, hi));
            next = hi + 1;
        }
    }
    out
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

/// The zooms of availability a tile's metadata extension carries: those
/// of its descendants down to this many zooms deeper (Cesium World
/// Terrain's `metadataAvailability`).
pub const METADATA_ZOOMS: i32 = 10;

/// What a layer announces and its tiles carry besides the mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LayerOptions {
    /// The oct-encoded vertex normals extension (`octvertexnormals`).
    pub normals: bool,
    /// Tiles off the terrain are served flat: both tiles of zoom 0 are
    /// available.
    pub fill: bool,
    /// The water mask extension (`watermask`).
    pub water: bool,
    /// The metadata extension (`metadata`): each tile's availability below
    /// it ([`tile_metadata`]).
    pub metadata: bool,
}

/// The available tiles `(x0, y0, x1, y1)` (inclusive, TMS) at each zoom
/// from 0 to the layer's deepest, of a terrain with geographic extent
/// `bounds` and level errors `max_errors` (with `fill` both tiles of zoom 0).
pub fn available(bounds: &[f64; 4], max_errors: &[f64], fill: bool) -> Vec<(i64, i64, i64, i64)> {
    let top = max_zoom(max_errors, 0);
    (0..=top)
        .map(|z| {
            if z == 0 && fill {
                (0, 0, 1, 0)
            } else {
                tile_range(z, bounds)
            }
        })
        .collect()
}

/// The metadata extension's JSON of tile `(z, x, y)`: `{"available": [...]}`
/// with, for each of the [`METADATA_ZOOMS`] zooms below it (to the
/// layer's deepest), the ranges of its descendants the layer makes
/// available ([`available`] cut to the tile; an empty list where none
/// is), as Cesium reads it.
///
/// ```
/// use tinmerge_core::serve::tiling::tile_metadata;
/// // a terrain of a few kilometres near 84°W 36°N, levels 30 m to 2 m
/// let b = [-84.1, 35.9, -84.0, 36.0];
/// let j: serde_json::Value = serde_json::from_str(&tile_metadata(0, 0, 0, &b, &[30.0, 2.0], false)).unwrap();
/// let zoom1 = &j["available"][0][0];
/// // zoom 1 has 90° tiles: the terrain is in column 1 (90°W..0°), row 1 (0°..90°N)
/// assert_eq!((zoom1["startX"].as_i64(), zoom1["startY"].as_i64()), (Some(1), Some(1)));
/// ```
pub fn tile_metadata(
    z: i32,
    x: i64,
    y: i64,
    bounds: &[f64; 4],
    max_errors: &[f64],
    fill: bool,
) -> String {
    let avail = available(bounds, max_errors, fill);
    let mut levels = Vec::new();
    for k in 1..=METADATA_ZOOMS {
        let Some(&(x0, y0, x1, y1)) = avail.get((z + k) as usize) else {
            break;
        };
        let (dx0, dy0) = (x << k, y << k);
        let (dx1, dy1) = (((x + 1) << k) - 1, ((y + 1) << k) - 1);
        let r = (x0.max(dx0), y0.max(dy0), x1.min(dx1), y1.min(dy1));
        levels.push(if r.0 <= r.2 && r.1 <= r.3 {
            serde_json::json!([{ "startX": r.0, "startY": r.1, "endX": r.2, "endY": r.3 }])
        } else {
            serde_json::json!([])
        });
    }
    serde_json::json!({ "available": levels }).to_string()
}

/// The `layer.json` of a terrain with geographic extent `bounds`
/// (`[west, south, east, north]`, degrees) whose levels have errors
/// `max_errors`: tiles `{z}/{x}/{y}.terrain`, the TMS scheme, the
/// available tiles per zoom ([`available`]), and the extensions `opts`
/// asks for (`octvertexnormals`, `watermask`, `metadata`). With
/// `metadata`, `metadataAvailability` is [`METADATA_ZOOMS`]: Cesium then
/// takes both tiles of zoom 0 as available and learns the rest from the
/// tiles' metadata (it needs the field to read the extension at all), so
/// serve both root tiles (`fill`). The full `available` list stays for
/// other readers (Cesium ignores it then).
pub fn layer_json(name: &str, bounds: &[f64; 4], max_errors: &[f64], opts: LayerOptions) -> String {
    let top = max_zoom(max_errors, 0);
    let available: Vec<serde_json::Value> = available(bounds, max_errors, opts.fill)
        .into_iter()
        .map(|(x0, y0, x1, y1)| serde_json::json!([{ "startX": x0, "startY": y0, "endX": x1, "endY": y1 }]))
        .collect();
    let extensions: Vec<&str> = [
        (opts.normals, "octvertexnormals"),
        (opts.water, "watermask"),
        (opts.metadata, "metadata"),
    ]
    .into_iter()
    .filter_map(|(on, name)| on.then_some(name))
    .collect();
    let mut v = serde_json::json!({
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
    if opts.metadata {
        v["metadataAvailability"] = serde_json::json!(METADATA_ZOOMS);
    }
    v.to_string()
}
