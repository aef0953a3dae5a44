//! One Cesium quantized-mesh 1.0 tile of a level, clipped exactly to the
//! tile.
//!
//! The caller gives the triangles that may meet the tile (a superset:
//! [`needed()`] picks them by bounding box in the tin's own coordinates) and
//! the geographic position (longitude, latitude in degrees, WGS 84) of
//! each of their vertices; in PostgreSQL those come from PostGIS's
//! `ST_Transform`. A triangle's geographic image is the triangle through
//! its transformed corners (what Cesium draws between them).
//!
//! **Clipping.** Each triangle is clipped to the tile's rectangle
//! (Sutherland-Hodgman, sides in a fixed order). Every vertex of the result
//! is a corner of the triangle, a corner of the tile, or where an
//! *original* edge of the level crosses a side of the tile, and that
//! crossing is computed from the edge's two ends taken in a canonical
//! order (lexicographic), never from an already-clipped piece. So the two
//! triangles on either side of an edge, and the two tiles on either side of
//! a tile side, compute the same double for the same crossing: vertices on
//! a shared tile side coincide bit for bit before quantization and, as the
//! side is the same quantized row or column in both tiles, after it too. A
//! crossing's height is interpolated along its edge; a tile corner inside a
//! triangle takes the triangle's plane in longitude/latitude.
//!
//! **Fill.** With `fill = Some(h)` the part of the tile off the terrain is
//! covered too: a constrained Delaunay triangulation (spade) of the tile's
//! corners and the domain's boundary edges clipped to the tile (hull edges,
//! and edges between a domain and a void triangle: the outline of the
//! data and its holes), keeping the faces outside the domain, all at height `h`, and a vertical wall along
//! the boundary from the terrain's edge to that height (facing out; the wall's
//! top vertices are the terrain's own, so the mesh is closed). The fill is
//! flat and the walls follow the boundary, so neighbouring tiles and tiles of
//! different zooms agree (a fill sloping from the hull to the tile's
//! corners differed from zoom to zoom, and Cesium's skirts showed at the
//! seams). A tile off the terrain is then two flat triangles. Without fill
//! such a tile is `None`.
//!
//! **Encoding** ([spec](https://github.com/CesiumGS/quantized-mesh)): the
//! 88-byte header (centre and bounding sphere in ECEF, WGS 84; minimum and
//! maximum height as f32, rounded outwards; the horizon occlusion point in
//! ellipsoid-scaled space, computed as Cesium's `EllipsoidalOccluder`
//! does, NaN when no point exists, which Cesium treats as never
//! occluded); `u`, `v`, `height` quantized to 0..32767 and zig-zag delta
//! coded; vertices numbered in order of first use so the indices are
//! high-water-mark coded, 16-bit up to 65,536 vertices and 32-bit beyond
//! (aligned to 4); the west, south, east and north edge vertex lists (the
//! vertices exactly on that side before quantization, so two neighbours
//! list the same ones: a vertex inside within half a step of a side
//! quantizes onto it but is not listed), sorted along their side; the
//! oct-encoded vertex normals extension (id 1) when asked: per vertex, the
//! area-weighted sum of the ECEF normals of the level's triangles around
//! it (all of them, also those outside the tile, so normals agree across
//! tile sides), around an edge for a crossing, the triangle's for a tile
//! corner; the ellipsoid's normal for fill corners; the water mask
//! extension (id 2, [`water_mask`]) and the metadata extension (id 4, a
//! JSON text: the tile's availability, [`tile_metadata`](crate::serve::tiling::tile_metadata))
//! when given ([`encode_with`]).
//!
//! ```
//! use tinmerge_core::serve::quantized_mesh::{Source, TileOptions, encode, needed};
//! use tinmerge_core::serve::tiling::tile_bounds;
//! use tinmerge_core::tin::build::build;
//! let mut pts = Vec::new();
//! for i in 0..20 {
//!     for j in 0..20 {
//!         let (x, y) = (-84.0 + i as f64 * 0.01, 36.0 + j as f64 * 0.01);
//!         pts.push([x, y, 100.0 + 10.0 * (i * j % 7) as f64]);
//!     }
//! }
//! let tin = build(pts, &[5.0, 0.0], 4326, &mut || Ok(())).unwrap();
//! // a tin in EPSG:4326: its own coordinates are the geographic ones
//! let opts = TileOptions::default(); // no normals, no fill
//! let need = needed(&tin, 1, None, opts.need(None), &mut || Ok(())).unwrap();
//! let geo = need.points();
//! let tile = tile_bounds(8, 136, 179).unwrap();
//! let src = Source { need: &need, geo: &geo };
//! let bytes = encode(src, &tile, opts, &mut || Ok(())).unwrap().unwrap();
//! assert!(bytes.len() > 88);
//! ```
//!
//! The parts: `needed` (what a tile needs from a level), `clip` (a
//! triangle cut to the tile), `mesh` (the tile's vertices and triangles,
//! with the fill off the terrain), `water` (the water mask), `encode` (the
//! bytes).

mod clip;
mod encode;
mod mesh;
mod needed;
mod water;

pub use clip::Source;
pub use encode::{Extras, TileOptions, encode, encode_many, encode_with, tile_bytes};
pub use mesh::{TileMesh, ecef};
pub use needed::{NeedOptions, Needed, Split, hull, needed, needed_in, split_length};
pub use water::{MASK_SIZE, WaterPolygon, water_mask};
