-- tinmerge 0.6.0 -> 0.7.0: no answer changes. tin_area_triangles,
-- tin_area_stats and tin_volume become Rust functions that take the geometry
-- itself and ask PostGIS's ST_IsValidReason for its verdict by OID, where
-- each call used to plan a SQL wrapper (the first call of a backend is about
-- 0.13 ms faster, a call in a loop about 0.1 ms). Their signatures, flags,
-- costs, rows and comments are unchanged; the internal _tin_area_triangles,
-- _tin_area_stats and _tin_volume they called are dropped (their symbols
-- stay in the library for databases still on an older version).
-- The search_path they pin is the install script's (sql/tinmerge.sql).
-- New: tin_tiles, a raster (or a table of raster tiles) built as a grid of
-- tins sharing their seams
-- (docs/scaling.md), the aggregate tin_from_points_agg, and the surface
-- analyses tin_contours and tin_slope_aspect; Cesium quantized-mesh tiles
-- (tin_quantized_mesh, tin_quantized_mesh_layer).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE OR REPLACE FUNCTION tin_area_triangles(t tin, area geometry, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8)
IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_area_triangles_wrapper'
SET search_path FROM CURRENT;
CREATE OR REPLACE FUNCTION tin_area_stats(t tin, area geometry, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8)
IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_area_stats_wrapper'
SET search_path FROM CURRENT;
CREATE OR REPLACE FUNCTION tin_volume(t tin, area geometry, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8)
IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_volume_wrapper'
SET search_path FROM CURRENT;
DROP FUNCTION _tin_area_triangles(tin, bytea, int, boolean, text);
DROP FUNCTION _tin_area_stats(tin, bytea, int, text, boolean);
DROP FUNCTION _tin_volume(tin, bytea, float8, int, text, boolean);
CREATE FUNCTION _tin_tiles("rast" bytea, "tile_px" int, "tolerance" double precision, "levels" int, "band" int)
RETURNS TABLE ("tx" int, "ty" int, "t" tin)
IMMUTABLE STRICT PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_tiles_wrapper';
ALTER FUNCTION _tin_tiles(bytea, int, float8, int, int) ROWS 100;
COMMENT ON FUNCTION _tin_tiles(bytea, int, float8, int, int) IS 'Internal: use tin_tiles(raster, int, float8, int, int).';
CREATE FUNCTION tin_tiles(rast raster, tile_px int, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles($1::bytea, $2, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles(raster, int, float8, int, int) IS
'Builds one band of a raster as a grid of tins in one call: tile (tx, ty) (numbered from 0, west to east and north to south) holds tile_px x tile_px pixels plus the first column of its right neighbour and the first row of the one below, and is built as tin_from_raster(..., keep_border => true) does, so neighbouring tiles have the same vertices on their shared seam at every level and their surfaces agree along it. Tiles are built on tinmerge.threads threads; a tile without three non-collinear valid pixels gives no row. Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';
CREATE FUNCTION _tin_tiles_table("tab" oid, "column" text, "tolerance" double precision, "levels" int, "band" int)
RETURNS TABLE ("tx" int, "ty" int, "t" tin)
STABLE STRICT PARALLEL RESTRICTED COST 100000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_tiles_table_wrapper';
ALTER FUNCTION _tin_tiles_table(oid, text, float8, int, int) ROWS 100;
COMMENT ON FUNCTION _tin_tiles_table(oid, text, float8, int, int) IS 'Internal: use tin_tiles_from_table(regclass, float8, int, name, int).';
CREATE FUNCTION tin_tiles_from_table(tiles regclass, tolerance float8, levels int DEFAULT 5, rast_column name DEFAULT 'rast', band int DEFAULT 1)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles_table($1::oid, $4::text, $2, $3, $5) $$
LANGUAGE sql STABLE STRICT PARALLEL RESTRICTED COST 100000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles_from_table(regclass, float8, int, name, int) IS
'Builds one band (of the raster column rast_column) of a table of raster tiles (raster2pgsql -t, ST_Tile: one pixel grid, tiles cut at multiples of one size) as a grid of tins in one call: tile (tx, ty) (numbered from 0 from the top-left tile, west to east and north to south) is built from its own pixels plus the first column of the tile to its right, the first row of the one below and the first pixel of the one below-right, as tin_tiles(raster, ...) builds the tiles of one raster, so seams agree at every level. Tiles are read a row at a time and built on tinmerge.threads threads, so memory stays bounded by two rows of tiles whatever the table''s size. Tiles whose pixel size, skew or SRID differ, or that are not a whole number of pixels apart, raise an ERROR (22023). Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';
CREATE FUNCTION _tin_points_agg_step("state" internal, "pt" geometry, "tolerance" double precision, "levels" int)
RETURNS internal
IMMUTABLE PARALLEL SAFE
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_points_agg_step_wrapper';
CREATE FUNCTION _tin_points_agg_final("state" internal)
RETURNS tin
IMMUTABLE PARALLEL SAFE
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_points_agg_final_wrapper';
COMMENT ON FUNCTION _tin_points_agg_step(internal, geometry, float8, int) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int).';
COMMENT ON FUNCTION _tin_points_agg_final(internal) IS 'Internal: the final function of tin_from_points_agg(geometry, float8, int).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int) (
    SFUNC = _tin_points_agg_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int) IS
'Builds a tin from every vertex (with Z) of the rows aggregated, as tin_from_points(ST_Collect(pt), tolerance, levels) does but without building one collection geometry (which PostgreSQL caps at 1 GB): e.g. tin_from_points_agg(geom, 0.5, 5) FILTER (WHERE class = 2) over LiDAR returns keeps the ground. Points with equal x,y are merged (mean z); NULL and empty rows add nothing; no row gives NULL. All rows must have one SRID, and the same tolerance and levels.';
CREATE FUNCTION tin_contours("t" tin, "interval" double precision, "level" int DEFAULT NULL, "base" double precision DEFAULT 0)
RETURNS TABLE ("z" double precision, "geom" geometry)
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_contours_wrapper';
ALTER FUNCTION tin_contours(tin, float8, int, float8) ROWS 1000;
COMMENT ON FUNCTION tin_contours(tin, float8, int, float8) IS
'Exact contour lines of the surface of a level (NULL = finest) at the heights base + k * interval, as LINESTRINGs with the tin''s SRID, by increasing z: the isolines of the linear surface on each triangle, joined across triangles; a closed contour is a closed ring, an open one ends on the domain''s edge. A vertex exactly at a contour height counts as above it (a contour along a flat area at that height follows its lower edge; a horizontal triangle at it gives no line). At most 100,000 heights per call.';
CREATE FUNCTION tin_slope_aspect("t" tin, "level" int DEFAULT NULL)
RETURNS TABLE ("triangle" int, "slope" double precision, "aspect" double precision)
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_slope_aspect_wrapper'
SET search_path FROM CURRENT;
ALTER FUNCTION tin_slope_aspect(tin, int) ROWS 10000;
COMMENT ON FUNCTION tin_slope_aspect(tin, int) IS
'Slope and aspect of every triangle of a level (NULL = finest), exact for the plane of each triangle: slope in degrees from the horizontal, aspect the direction the triangle faces (steepest descent) in degrees clockwise from grid north, in [0, 360), NULL for a flat triangle; triangle as in tin_triangles. Planar SRIDs only (x, y in the unit of z): a geographic tin is an error.';
CREATE FUNCTION tin_quantized_mesh("t" tin, "z" int, "x" int, "y" int, "normals" boolean DEFAULT false, "fill" double precision DEFAULT NULL)
RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 5000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_quantized_mesh_wrapper'
SET search_path FROM CURRENT;
CREATE FUNCTION tin_quantized_mesh("t" tin, "level" int, "z" int, "x" int, "y" int, "normals" boolean DEFAULT false, "fill" double precision DEFAULT NULL)
RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 5000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_quantized_mesh_level_wrapper'
SET search_path FROM CURRENT;
CREATE FUNCTION tin_quantized_mesh_layer("t" tin, "normals" boolean DEFAULT false, "fill" boolean DEFAULT false, "name" text DEFAULT 'terrain')
RETURNS json
IMMUTABLE PARALLEL SAFE COST 1000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_quantized_mesh_layer_wrapper'
SET search_path FROM CURRENT;
CREATE FUNCTION tin_quantized_mesh("ts" tin[], "z" int, "x" int, "y" int, "normals" boolean DEFAULT false, "fill" double precision DEFAULT NULL)
RETURNS bytea
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_quantized_mesh_tiles_wrapper'
SET search_path FROM CURRENT;
CREATE FUNCTION tin_quantized_mesh_layer("ts" tin[], "normals" boolean DEFAULT false, "fill" boolean DEFAULT false, "name" text DEFAULT 'terrain')
RETURNS json
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_quantized_mesh_layer_tiles_wrapper'
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8) IS
'One Cesium quantized-mesh 1.0 tile (z, x, y in Cesium''s geographic TMS scheme: EPSG:4326, two root tiles, y from the south) of the terrain, from the coarsest level whose measured error is at most the tile''s geometric error (77,067 m / 2^z, Cesium''s own estimate), as bytea: triangles clipped exactly to the tile (neighbouring tiles share their side vertices), edge vertex lists for skirts, the oct-encoded vertex normals extension when normals is true. Positions go to longitude/latitude through PostGIS''s ST_Transform. NULL for a tile off the terrain, unless fill gives a height for the part of a tile off the terrain (then every tile is a tile, and Cesium draws a whole globe). Serve with Content-Type application/vnd.quantized-mesh (see docs/serving.md).';
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8) IS
'tin_quantized_mesh of a given level (NULL = finest) instead of the one the zoom chooses: tin_quantized_mesh(t, level, z, x, y).';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text) IS
'The layer.json Cesium''s CesiumTerrainProvider reads for the tiles of tin_quantized_mesh: format quantized-mesh-1.0, scheme tms, projection EPSG:4326, the terrain''s bounds in degrees, maxzoom (the first zoom served from the finest level; Cesium refines deeper by upsampling), the available tiles per zoom (those over the terrain; with fill both root tiles too), and octvertexnormals when normals is true.';
COMMENT ON FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8) IS
'tin_quantized_mesh of a terrain stored as tiles (tins sharing their seams: tin_tiles, or tin_from_raster with keep_border): one tile from every tin given, as one mesh (seam vertices one vertex, normals summed over the tins, no wall along a seam), at the level the zoom chooses from each level''s largest error over the tins. Pass the tins whose extent meets the tile, e.g. array_agg(t) over the tile table with a GiST index on the tins'' extent in degrees (docs/serving.md). The tins must share their SRID and number of levels. An empty array is off the terrain.';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text) IS
'tin_quantized_mesh_layer of a terrain stored as tiles: the bounds of all the tins, the levels'' largest errors over them.';

-- keep_border builds choose the vertices on the hull's sides per level (no
-- longer every border pixel at every level)
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains).';
