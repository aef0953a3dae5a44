//! SQL functions serving the terrain to Cesium: `tin_quantized_mesh` (one
//! quantized-mesh tile, the level chosen from the tile's zoom or given)
//! and `tin_quantized_mesh_layer` (its `layer.json`). Positions go to
//! WGS 84 longitude/latitude through PostGIS's own `ST_Transform`, called
//! by OID with a MULTIPOINT of the vertices a tile needs (nothing for a
//! tin already in EPSG:4326). Not STRICT: NULL level means finest, NULL
//! fill means none; a NULL tin or address gives NULL.

use pgrx::prelude::*;

use super::args::postgis_transform;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::{MeshSource, TinArg};
use pgrx::datum::Array;
use pgrx::Json;
use std::rc::Rc;
use std::sync::Arc;
use tinmerge_core::serve::quantized_mesh::{
    encode_many, hull, needed, needed_in, split_length, tile_bytes, NeedOptions, Needed, Source,
    TileOptions,
};
use tinmerge_core::serve::tiling::{layer_json, level_for_zoom, tile_bounds, TileBounds};
use tinmerge_core::tin::sliced::SlicedTin;
use tinmerge_core::tin::{resolve_level, Bbox, Tin};

/// WGS 84 longitude/latitude.
const WGS84: i32 = 4326;

/// One tin of a tile: the decoded value, or the stored value read in
/// slices (a tile reads only the triangles near it, so the first tile a
/// backend serves from a large terrain does not decode all of it).
enum Served<'a> {
    Decoded(Arc<Tin>),
    Sliced(Rc<SlicedTin>, &'a TinArg),
}

impl<'a> Served<'a> {
    /// The tin of `t` as a tile reads it: in slices when the argument's
    /// source is ([`TinArg::mesh_source`]) and no fill is asked (a fill
    /// needs the level's whole outline), else decoded.
    fn of(t: &'a TinArg, fill: bool) -> Served<'a> {
        if fill {
            return Served::Decoded(t.tin());
        }
        match t.mesh_source() {
            MeshSource::Decoded(tin) => Served::Decoded(tin),
            MeshSource::Sliced(s) => Served::Sliced(s, t),
        }
    }

    fn srid(&self) -> i32 {
        match self {
            Served::Decoded(t) => t.srid,
            Served::Sliced(s, _) => s.header().srid,
        }
    }

    fn bbox(&self) -> Bbox {
        match self {
            Served::Decoded(t) => t.bbox,
            Served::Sliced(s, _) => s.header().bbox,
        }
    }

    /// Each level's measured error.
    fn max_errors(&self) -> Vec<f64> {
        match self {
            Served::Decoded(t) => t.levels.iter().map(|l| l.max_error).collect(),
            Served::Sliced(s, _) => s.header().levels.iter().map(|l| l.max_error).collect(),
        }
    }

    /// What the tile needs of level `l` in `footprint` ([`needed`]).
    fn need(&self, l: usize, footprint: Option<[f64; 4]>, opts: NeedOptions) -> Needed {
        match self {
            Served::Decoded(t) => needed(t, l, footprint, opts, &mut interrupt).or_raise(),
            Served::Sliced(s, arg) => {
                let mut fetch = arg.fetch();
                let reader = s.reader(&mut fetch);
                needed_in(&reader, l, footprint, opts, &[], &mut interrupt).or_raise()
            }
        }
    }

    /// Only the hull of level `l` ([`hull`]): the whole outline, so from
    /// the decoded value.
    fn hull(&self, l: usize, max_len: Option<f64>) -> Needed {
        match self {
            Served::Decoded(t) => hull(t, l, max_len),
            Served::Sliced(_, arg) => hull(&arg.tin(), l, max_len),
        }
    }
}

fn check_srid(srid: i32, func: &str) {
    if srid == 0 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{func}: the tin has no SRID (0); Cesium tiles need to know where the terrain is: build it with an SRID or rebuild from a georeferenced raster"),
        );
    }
}

/// Points of the tin's frame (SRID `srid`) in degrees (themselves when it
/// is in 4326).
fn points_to_degrees(srid: i32, pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    if srid == WGS84 {
        pts
    } else {
        postgis_transform(&pts, srid, WGS84)
    }
}

/// The longest edge that stays straight in degrees (see
/// `quantized_mesh::split_length`): the bulge of the images of the
/// terrain's two diagonals, measured through ST_Transform.
fn max_edge(srid: i32, b: &Bbox) -> Option<f64> {
    if srid == WGS84 {
        return None;
    }
    let (cx, cy) = ((b.min_x + b.max_x) / 2.0, (b.min_y + b.max_y) / 2.0);
    let g = points_to_degrees(
        srid,
        vec![
            [b.min_x, b.min_y],
            [b.max_x, b.max_y],
            [b.min_x, b.max_y],
            [b.max_x, b.min_y],
            [cx, cy],
        ],
    );
    let bulge = |p: [f64; 2], q: [f64; 2]| {
        ((p[0] + q[0]) / 2.0 - g[4][0]).hypot((p[1] + q[1]) / 2.0 - g[4][1])
    };
    let sagitta = bulge(g[0], g[1]).max(bulge(g[2], g[3]));
    split_length((b.max_x - b.min_x).hypot(b.max_y - b.min_y), sagitta)
}

/// The bounding box `[min x, min y, max x, max y]` of points, widened by
/// `margin` on every side.
fn extent(pts: impl IntoIterator<Item = [f64; 2]>, margin: f64) -> [f64; 4] {
    let mut e = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in pts {
        e = [
            e[0].min(p[0]),
            e[1].min(p[1]),
            e[2].max(p[0]),
            e[3].max(p[1]),
        ];
    }
    [e[0] - margin, e[1] - margin, e[2] + margin, e[3] + margin]
}

/// The geographic extent `[west, south, east, north]` of level `l`: its
/// hull's vertices and the points splitting its long edges in degrees
/// (the tiles' triangles are straight between those, so this holds them
/// all).
fn geo_bounds(tin: &Tin, l: usize, max_len: Option<f64>) -> [f64; 4] {
    let hull = hull(tin, l, max_len);
    extent(points_to_degrees(tin.srid, hull.points()), 0.0)
}

/// A geographic extent holding the whole tin, cheaply: its bounding box's
/// outline (32 points a side) in degrees, widened by 1e-5 degrees (a
/// metre; the outline's pieces bulge far less).
fn geo_extent(srid: i32, b: &Bbox) -> [f64; 4] {
    let mut ring = Vec::with_capacity(128);
    for i in 0..32 {
        let f = i as f64 / 32.0;
        let (x, y) = (
            b.min_x + f * (b.max_x - b.min_x),
            b.min_y + f * (b.max_y - b.min_y),
        );
        ring.extend_from_slice(&[
            [x, b.min_y],
            [b.max_x, y],
            [b.max_x - (x - b.min_x), b.max_y],
            [b.min_x, b.max_y - (y - b.min_y)],
        ]);
    }
    let m = if srid == WGS84 { 0.0 } else { 1e-5 };
    extent(points_to_degrees(srid, ring), m)
}

/// The part of the tile over the terrain, in the tin's coordinates: the
/// rectangle `tile ∩ bounds` densified (16 points a side) and transformed,
/// its bounding box.
fn footprint(srid: i32, bbox: &Bbox, tb: &TileBounds, b: &[f64; 4]) -> [f64; 4] {
    let (w, s, e, n) = (
        tb.west.max(b[0]),
        tb.south.max(b[1]),
        tb.east.min(b[2]),
        tb.north.min(b[3]),
    );
    let mut ring = Vec::with_capacity(64);
    for i in 0..16 {
        let f = i as f64 / 16.0;
        ring.push([w + f * (e - w), s]);
        ring.push([e, s + f * (n - s)]);
        ring.push([e - f * (e - w), n]);
        ring.push([w, n - f * (n - s)]);
    }
    // widened by 1e-5 of the terrain's diagonal: the geographic image of a
    // triangle (split as needed) is within a millimetre of its footprint
    let b = bbox;
    if srid == WGS84 {
        extent(ring, 0.0)
    } else {
        let m = 1e-5 * (b.max_x - b.min_x).hypot(b.max_y - b.min_y);
        extent(postgis_transform(&ring, WGS84, srid), m)
    }
}

/// One tile of the terrain made of `tins` (one tin, or the tins of a
/// tiled terrain sharing their seams), at `level` (None: the level the
/// zoom chooses from the largest error of each level over the tins).
#[allow(clippy::too_many_arguments)]
fn tile(
    tins: &[Served],
    level: Option<Option<i32>>,
    z: i32,
    x: i32,
    y: i32,
    normals: bool,
    fill: Option<f64>,
) -> Option<Vec<u8>> {
    let tb = tile_bounds(z, x, y).or_raise();
    if let Some(h) = fill {
        if !h.is_finite() {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!("tin_quantized_mesh: fill height must be finite, got {h}"),
            );
        }
    }
    let Some(first) = tins.first() else {
        // no tin: off the terrain
        let empty = Vec::new();
        return encode_many(&empty, &tb, TileOptions { normals, fill }, &mut interrupt).or_raise();
    };
    let errors: Vec<Vec<f64>> = tins.iter().map(Served::max_errors).collect();
    for (tin, e) in tins.iter().zip(&errors) {
        check_srid(tin.srid(), "tin_quantized_mesh");
        if tin.srid() != first.srid() || e.len() != errors[0].len() {
            raise(
                PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
                format!(
                    "tin_quantized_mesh: the tins of one terrain must share their SRID and number of levels (SRID {} with {} levels, SRID {} with {} levels)",
                    first.srid(),
                    errors[0].len(),
                    tin.srid(),
                    e.len()
                ),
            );
        }
    }
    let l = match level {
        None => level_for_zoom(&max_errors(&errors), z),
        Some(lv) => resolve_level(lv, errors[0].len()).or_raise(),
    };
    let mut parts = Vec::with_capacity(tins.len());
    for tin in tins {
        let (srid, bbox) = (tin.srid(), tin.bbox());
        let b = geo_extent(srid, &bbox);
        let max_len = max_edge(srid, &bbox);
        let need = if !tb.intersects(&b) {
            if fill.is_none() {
                continue;
            }
            // only the hull, to tell the fill it is off the terrain
            tin.hull(l, max_len)
        } else {
            let f = if tb.contains(&b) {
                None
            } else {
                Some(footprint(srid, &bbox, &tb, &b))
            };
            tin.need(l, f, TileOptions { normals, fill }.need(max_len))
        };
        memory::reserve(tile_bytes(need.triangles.len() + need.ring.len()), || {
            format!(
                "tin_quantized_mesh: tile {z}/{x}/{y} of {} triangles",
                need.triangles.len()
            )
        });
        let geo = points_to_degrees(srid, need.points());
        parts.push((need, geo));
    }
    if parts.is_empty() {
        return None;
    }
    let sources: Vec<Source> = parts
        .iter()
        .map(|(need, geo)| Source { need, geo })
        .collect();
    encode_many(&sources, &tb, TileOptions { normals, fill }, &mut interrupt).or_raise()
}

/// Each level's largest measured error over the tins (each tin's errors
/// by level).
fn max_errors(errors: &[Vec<f64>]) -> Vec<f64> {
    let n = errors.iter().map(Vec::len).max().unwrap_or(0);
    (0..n)
        .map(|i| {
            errors
                .iter()
                .filter_map(|e| e.get(i).copied())
                .fold(0.0, f64::max)
        })
        .collect()
}

/// The tins of an array argument (NULL elements skipped).
fn tins_of(ts: &Array<'_, TinArg>) -> Vec<Arc<Tin>> {
    ts.iter().flatten().map(|t| t.tin()).collect()
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, name = "tin_quantized_mesh", requires = ["tin_type"])]
fn tin_quantized_mesh_tiles(
    ts: Option<Array<'_, TinArg>>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
) -> Option<Vec<u8>> {
    let (ts, z, x, y) = (ts?, z?, x?, y?);
    let tins: Vec<Served> = tins_of(&ts).into_iter().map(Served::Decoded).collect();
    tile(&tins, None, z, x, y, normals.unwrap_or(false), fill)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 5000, requires = ["tin_type"])]
fn tin_quantized_mesh(
    t: Option<TinArg>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
) -> Option<Vec<u8>> {
    let (t, z, x, y) = (t?, z?, x?, y?);
    let served = [Served::of(&t, fill.is_some())];
    tile(&served, None, z, x, y, normals.unwrap_or(false), fill)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 5000, name = "tin_quantized_mesh", requires = ["tin_type"])]
fn tin_quantized_mesh_level(
    t: Option<TinArg>,
    level: Option<i32>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
) -> Option<Vec<u8>> {
    let (t, z, x, y) = (t?, z?, x?, y?);
    tile(
        &[Served::of(&t, fill.is_some())],
        Some(level),
        z,
        x,
        y,
        normals.unwrap_or(false),
        fill,
    )
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8) IS
'One Cesium quantized-mesh 1.0 tile (z, x, y in Cesium''s geographic TMS scheme: EPSG:4326, two root tiles, y from the south) of the terrain, from the coarsest level whose measured error is at most the tile''s geometric error (77,067 m / 2^z, Cesium''s own estimate), as bytea: triangles clipped exactly to the tile (neighbouring tiles share their side vertices), edge vertex lists for skirts, the oct-encoded vertex normals extension when normals is true. Positions go to longitude/latitude through PostGIS''s ST_Transform. NULL for a tile off the terrain, unless fill gives a height for the part of a tile off the terrain (then every tile is a tile, and Cesium draws a whole globe). Serve with Content-Type application/vnd.quantized-mesh (see docs/serving.md).';
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8) IS
'tin_quantized_mesh of a given level (NULL = finest) instead of the one the zoom chooses: tin_quantized_mesh(t, level, z, x, y).';
COMMENT ON FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8) IS
'tin_quantized_mesh of a terrain stored as tiles (tins sharing their seams: tin_tiles, or tin_from_raster with keep_border): one tile from every tin given, as one mesh (seam vertices one vertex, normals summed over the tins, no wall along a seam), at the level the zoom chooses from each level''s largest error over the tins. Pass the tins whose extent meets the tile, e.g. array_agg(t) over the tile table with a GiST index on the tins'' extent in degrees (docs/serving.md). The tins must share their SRID and number of levels. An empty array is off the terrain.';
"#,
    name = "tin_quantized_mesh_sql",
    requires = [
        tin_quantized_mesh,
        tin_quantized_mesh_level,
        tin_quantized_mesh_tiles
    ]
);

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 1000, requires = ["tin_type"])]
fn tin_quantized_mesh_layer(
    t: Option<TinArg>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<bool>, "false"),
    name: default!(Option<String>, "'terrain'"),
) -> Option<Json> {
    layer(&[t?.tin()], normals, fill, name)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, name = "tin_quantized_mesh_layer", requires = ["tin_type"])]
fn tin_quantized_mesh_layer_tiles(
    ts: Option<Array<'_, TinArg>>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<bool>, "false"),
    name: default!(Option<String>, "'terrain'"),
) -> Option<Json> {
    let tins = tins_of(&ts?);
    if tins.is_empty() {
        return None;
    }
    layer(&tins, normals, fill, name)
}

fn layer(
    tins: &[Arc<Tin>],
    normals: Option<bool>,
    fill: Option<bool>,
    name: Option<String>,
) -> Option<Json> {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for tin in tins {
        check_srid(tin.srid, "tin_quantized_mesh_layer");
        let g = geo_bounds(tin, tin.levels.len() - 1, max_edge(tin.srid, &tin.bbox));
        b = [
            b[0].min(g[0]),
            b[1].min(g[1]),
            b[2].max(g[2]),
            b[3].max(g[3]),
        ];
    }
    let s = layer_json(
        name.as_deref().unwrap_or("terrain"),
        &b,
        &max_errors(
            &tins
                .iter()
                .map(|t| t.levels.iter().map(|l| l.max_error).collect())
                .collect::<Vec<_>>(),
        ),
        normals.unwrap_or(false),
        fill.unwrap_or(false),
    );
    match serde_json::from_str(&s) {
        Ok(v) => Some(Json(v)),
        Err(e) => raise(
            PgSqlErrorCode::ERRCODE_INTERNAL_ERROR,
            format!("tin_quantized_mesh_layer: {e}"),
        ),
    }
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text) IS
'The layer.json Cesium''s CesiumTerrainProvider reads for the tiles of tin_quantized_mesh: format quantized-mesh-1.0, scheme tms, projection EPSG:4326, the terrain''s bounds in degrees, maxzoom (the first zoom served from the finest level; Cesium refines deeper by upsampling), the available tiles per zoom (those over the terrain; with fill both root tiles too), and octvertexnormals when normals is true.';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text) IS
'tin_quantized_mesh_layer of a terrain stored as tiles: the bounds of all the tins, the levels'' largest errors over them.';
"#,
    name = "tin_quantized_mesh_layer_sql",
    requires = [tin_quantized_mesh_layer, tin_quantized_mesh_layer_tiles]
);
