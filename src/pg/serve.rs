//! SQL functions serving the terrain to Cesium: `tin_quantized_mesh` (one
//! quantized-mesh tile, the level chosen from the tile's zoom or given)
//! and `tin_quantized_mesh_layer` (its `layer.json`). Positions go to
//! WGS 84 longitude/latitude through PostGIS's own `ST_Transform`, called
//! by OID with a MULTIPOINT of the vertices a tile needs (nothing for a
//! tin already in EPSG:4326). Not STRICT: NULL level means finest, NULL
//! fill means none; a NULL tin or address gives NULL.

use pgrx::prelude::*;

use super::args::postgis_transform;
use super::args::GeomArg;
use super::errors::{raise, OrRaise};
use super::interrupt::interrupt;
use super::memory;
use super::tin_type::{MeshSource, TinArg};
use pgrx::datum::Array;
use pgrx::Json;
use std::rc::Rc;
use std::sync::Arc;
use tinmerge_core::io::ewkb::Geom;
use tinmerge_core::io::gserialized;
use tinmerge_core::serve::quantized_mesh::{
    encode_with, hull, needed, needed_in, split_length, tile_bytes, Extras, NeedOptions, Needed,
    Source, TileOptions, WaterPolygon,
};
use tinmerge_core::serve::tiling::{
    layer_json, level_for_zoom, tile_bounds, tile_metadata, LayerOptions, TileBounds,
};
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

    /// Each level's error bound ([`level_bound`]).
    fn bounds(&self) -> Vec<f64> {
        match self {
            Served::Decoded(t) => t
                .levels
                .iter()
                .map(|l| level_bound(l.tolerance, l.max_error))
                .collect(),
            Served::Sliced(s, _) => s
                .header()
                .levels
                .iter()
                .map(|l| level_bound(l.tolerance, l.max_error))
                .collect(),
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

/// The geographic extent `[west, south, east, north]` of the finest level
/// of the tins (the layer's bounds): each one's hull vertices and the
/// points splitting its long edges in degrees (the tiles' triangles are
/// straight between those, so this holds them all).
fn terrain_bounds(tins: &[Served]) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for tin in tins {
        let finest = tin.bounds().len().saturating_sub(1);
        let hull = tin.hull(finest, max_edge(tin.srid(), &tin.bbox()));
        let g = extent(points_to_degrees(tin.srid(), hull.points()), 0.0);
        b = [
            b[0].min(g[0]),
            b[1].min(g[1]),
            b[2].max(g[2]),
            b[3].max(g[3]),
        ];
    }
    b
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

/// What a tile carries besides its mesh, as the SQL call asks.
struct Asked {
    normals: bool,
    fill: Option<f64>,
    /// The water polygons in degrees (None: no water mask extension).
    water: Option<Vec<WaterPolygon>>,
    /// The metadata extension with the tile's availability.
    metadata: bool,
}

impl Asked {
    fn new(
        normals: Option<bool>,
        fill: Option<f64>,
        water: Option<GeomArg>,
        metadata: Option<bool>,
    ) -> Asked {
        Asked {
            normals: normals.unwrap_or(false),
            fill,
            water: water.map(|g| water_polygons(&g)),
            metadata: metadata.unwrap_or(false),
        }
    }
}

/// The polygons of the `water` argument in longitude/latitude: a POLYGON,
/// MULTIPOLYGON or a collection of them (`ST_Collect` of a table's lakes);
/// its vertices transformed to EPSG:4326 by PostGIS when in another SRID
/// (edges are then straight in degrees, as `ST_Transform` makes them).
fn water_polygons(g: &GeomArg) -> Vec<WaterPolygon> {
    const FUNC: &str = "tin_quantized_mesh";
    let e = gserialized::read(g.bytes()).or_raise();
    fn collect(g: Geom, out: &mut Vec<Vec<Vec<[f64; 2]>>>) -> Result<(), &'static str> {
        let ring =
            |r: Vec<tinmerge_core::io::ewkb::Coord3>| r.into_iter().map(|c| [c[0], c[1]]).collect();
        match g {
            Geom::Polygon(p) => out.push(p.into_iter().map(ring).collect()),
            Geom::MultiPolygon(ps) => {
                out.extend(ps.into_iter().map(|p| p.into_iter().map(ring).collect()))
            }
            Geom::Collection(gs) => {
                for g in gs {
                    collect(g, out)?;
                }
            }
            other => return Err(other.type_name()),
        }
        Ok(())
    }
    let mut polys = Vec::new();
    if let Err(t) = collect(e.geom, &mut polys) {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: water takes polygons (a POLYGON, MULTIPOLYGON or a collection of them), got a {t}"),
        );
    }
    // POLYGON EMPTY and empty rings are no water
    for p in polys.iter_mut() {
        p.retain(|r| !r.is_empty());
    }
    polys.retain(|p| !p.is_empty());
    if polys.is_empty() {
        return polys;
    }
    if e.srid == 0 {
        raise(
            PgSqlErrorCode::ERRCODE_INVALID_PARAMETER_VALUE,
            format!("{FUNC}: the water polygons have no SRID (0); give them one with ST_SetSRID (4326 for longitude/latitude)"),
        );
    }
    for c in polys.iter().flatten().flatten() {
        tinmerge_core::tin::check_xy(format_args!("{FUNC}: a water polygon"), c[0], c[1])
            .or_raise();
    }
    if e.srid != WGS84 {
        let flat: Vec<[f64; 2]> = polys.iter().flatten().flatten().copied().collect();
        let mut deg = postgis_transform(&flat, e.srid, WGS84).into_iter();
        for c in polys.iter_mut().flatten().flatten() {
            if let Some(d) = deg.next() {
                *c = d;
            }
        }
    }
    polys
}

/// One tile of the terrain made of `tins` (one tin, or the tins of a
/// tiled terrain sharing their seams), at `level` (None: the level the
/// zoom chooses from the largest bound of each level over the tins).
fn tile(
    tins: &[Served],
    level: Option<Option<i32>>,
    (z, x, y): (i32, i32, i32),
    asked: &Asked,
) -> Option<Vec<u8>> {
    let Asked { normals, fill, .. } = *asked;
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
        let metadata = asked
            .metadata
            .then(|| tile_metadata(z, x.into(), y.into(), &[0.0; 4], &[], fill.is_some()));
        let extras = Extras {
            water: asked.water.as_deref(),
            metadata: metadata.as_deref(),
        };
        let opts = TileOptions { normals, fill };
        return encode_with(&empty, &tb, opts, extras, &mut interrupt).or_raise();
    };
    let errors: Vec<Vec<f64>> = tins.iter().map(Served::bounds).collect();
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
        None => level_for_zoom(&largest(&errors), z),
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
    // the tile's availability below it: the layer's ranges (from the same
    // bounds and errors tin_quantized_mesh_layer uses) cut to the tile
    let metadata = asked.metadata.then(|| {
        let b = terrain_bounds(tins);
        tile_metadata(z, x.into(), y.into(), &b, &largest(&errors), fill.is_some())
    });
    let extras = Extras {
        water: asked.water.as_deref(),
        metadata: metadata.as_deref(),
    };
    encode_with(
        &sources,
        &tb,
        TileOptions { normals, fill },
        extras,
        &mut interrupt,
    )
    .or_raise()
}

/// A level's error bound, what a zoom chooses it by: its tolerance (the
/// same in every tin built with the same tolerance and levels), or its
/// measured error where that is larger (hard breaklines keep their own
/// heights). Not the measured error alone: that differs from tin to tin,
/// so two tiles of one zoom given different tins of a tiled terrain
/// (each the tins its index finds) would choose different levels and
/// not meet along their shared side.
fn level_bound(tolerance: f64, max_error: f64) -> f64 {
    tolerance.max(max_error)
}

/// Each level's largest bound over the tins (each tin's bounds by level).
fn largest(errors: &[Vec<f64>]) -> Vec<f64> {
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
#[allow(clippy::too_many_arguments)] // the SQL signature
fn tin_quantized_mesh_tiles(
    ts: Option<Array<'_, TinArg>>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
    water: default!(Option<GeomArg>, "NULL"),
    metadata: default!(Option<bool>, "false"),
) -> Option<Vec<u8>> {
    let (ts, z, x, y) = (ts?, z?, x?, y?);
    let tins: Vec<Served> = tins_of(&ts).into_iter().map(Served::Decoded).collect();
    tile(
        &tins,
        None,
        (z, x, y),
        &Asked::new(normals, fill, water, metadata),
    )
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 5000, requires = ["tin_type"])]
#[allow(clippy::too_many_arguments)] // the SQL signature
fn tin_quantized_mesh(
    t: Option<TinArg>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
    water: default!(Option<GeomArg>, "NULL"),
    metadata: default!(Option<bool>, "false"),
) -> Option<Vec<u8>> {
    let (t, z, x, y) = (t?, z?, x?, y?);
    let asked = Asked::new(normals, fill, water, metadata);
    // the metadata's availability needs the finest level's whole outline
    let served = [Served::of(&t, fill.is_some() || asked.metadata)];
    tile(&served, None, (z, x, y), &asked)
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 5000, name = "tin_quantized_mesh", requires = ["tin_type"])]
#[allow(clippy::too_many_arguments)] // the SQL signature
fn tin_quantized_mesh_level(
    t: Option<TinArg>,
    level: Option<i32>,
    z: Option<i32>,
    x: Option<i32>,
    y: Option<i32>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<f64>, "NULL"),
    water: default!(Option<GeomArg>, "NULL"),
    metadata: default!(Option<bool>, "false"),
) -> Option<Vec<u8>> {
    let (t, z, x, y) = (t?, z?, x?, y?);
    let asked = Asked::new(normals, fill, water, metadata);
    let served = [Served::of(&t, fill.is_some() || asked.metadata)];
    tile(&served, Some(level), (z, x, y), &asked)
}

extension_sql!(
    r#"
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8, geometry, boolean) IS
'One Cesium quantized-mesh 1.0 tile (z, x, y in Cesium''s geographic TMS scheme: EPSG:4326, two root tiles, y from the south) of the terrain, from the coarsest level whose error bound (its tolerance, or its measured error where larger) is at most the tile''s geometric error (77,067 m / 2^z, Cesium''s own estimate; since 0.23.0 the bound, before the measured error), as bytea: triangles clipped exactly to the tile (neighbouring tiles share their side vertices), edge vertex lists for skirts, the oct-encoded vertex normals extension when normals is true. Positions go to longitude/latitude through PostGIS''s ST_Transform. NULL for a tile off the terrain, unless fill gives a height for the part of a tile off the terrain (then every tile is a tile, and Cesium draws a whole globe). water (polygons in any SRID, e.g. ST_Collect of the lakes meeting the tile) adds the water mask extension: 256 x 256 cells, water where the cell''s centre is in a polygon, or one byte when the tile is all land or all water. metadata adds the metadata extension: the tile''s availability for the 10 zooms below it, as tin_quantized_mesh_layer lists it. Serve with Content-Type application/vnd.quantized-mesh (see docs/serving.md).';
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8, geometry, boolean) IS
'tin_quantized_mesh of a given level (NULL = finest) instead of the one the zoom chooses: tin_quantized_mesh(t, level, z, x, y).';
COMMENT ON FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8, geometry, boolean) IS
'tin_quantized_mesh of a terrain stored as tiles (tins sharing their seams: tin_tiles, or tin_from_raster with keep_border): one tile from every tin given, as one mesh (seam vertices one vertex, normals summed over the tins, no wall along a seam), at the level the zoom chooses from each level''s largest error bound over the tins (its tolerance, or its measured error where larger: the same for every tin built with the same tolerance and levels, so every tile of a zoom has the same level whichever tins its index finds). Pass the tins whose extent meets the tile, e.g. array_agg(t) over the tile table with a GiST index on the tins'' extent in degrees (docs/serving.md). The tins must share their SRID and number of levels. An empty array is off the terrain.';
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
    water: default!(Option<bool>, "false"),
    metadata: default!(Option<bool>, "false"),
) -> Option<Json> {
    let opts = layer_options(normals, fill, water, metadata);
    layer(&[t?.tin()], opts, name)
}

/// The layer's extensions and fill as the SQL call gives them (NULL: false).
fn layer_options(
    normals: Option<bool>,
    fill: Option<bool>,
    water: Option<bool>,
    metadata: Option<bool>,
) -> LayerOptions {
    LayerOptions {
        normals: normals.unwrap_or(false),
        fill: fill.unwrap_or(false),
        water: water.unwrap_or(false),
        metadata: metadata.unwrap_or(false),
    }
}

#[pg_extern(support = _tin_plan_support, immutable, parallel_safe, cost = 10000, name = "tin_quantized_mesh_layer", requires = ["tin_type"])]
fn tin_quantized_mesh_layer_tiles(
    ts: Option<Array<'_, TinArg>>,
    normals: default!(Option<bool>, "false"),
    fill: default!(Option<bool>, "false"),
    name: default!(Option<String>, "'terrain'"),
    water: default!(Option<bool>, "false"),
    metadata: default!(Option<bool>, "false"),
) -> Option<Json> {
    let tins = tins_of(&ts?);
    if tins.is_empty() {
        return None;
    }
    layer(&tins, layer_options(normals, fill, water, metadata), name)
}

fn layer(tins: &[Arc<Tin>], opts: LayerOptions, name: Option<String>) -> Option<Json> {
    for tin in tins {
        check_srid(tin.srid, "tin_quantized_mesh_layer");
    }
    let served: Vec<Served> = tins.iter().cloned().map(Served::Decoded).collect();
    let b = terrain_bounds(&served);
    let s = layer_json(
        name.as_deref().unwrap_or("terrain"),
        &b,
        &largest(&served.iter().map(Served::bounds).collect::<Vec<_>>()),
        opts,
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
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text, boolean, boolean) IS
'The layer.json Cesium''s CesiumTerrainProvider reads for the tiles of tin_quantized_mesh: format quantized-mesh-1.0, scheme tms, projection EPSG:4326, the terrain''s bounds in degrees, maxzoom (the first zoom served from the finest level; Cesium refines deeper by upsampling), the available tiles per zoom (those over the terrain; with fill both root tiles too), and in extensions octvertexnormals when normals is true, watermask when water is true, metadata when metadata is true (then metadataAvailability 10: Cesium learns availability from the tiles and takes both root tiles as available, so serve them with fill; the available list stays whole for other readers).';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text, boolean, boolean) IS
'tin_quantized_mesh_layer of a terrain stored as tiles: the bounds of all the tins, the levels'' largest error bounds over them (as tin_quantized_mesh(tin[], ...) chooses a level).';
"#,
    name = "tin_quantized_mesh_layer_sql",
    requires = [tin_quantized_mesh_layer, tin_quantized_mesh_layer_tiles]
);
