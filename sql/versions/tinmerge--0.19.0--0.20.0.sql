-- tinmerge 0.19.0 -> 0.20.0. Stored values read and answer as before.
-- tin_quantized_mesh (its three forms) takes water (polygons: the water
-- mask extension) and metadata (the tile's availability: the metadata
-- extension); tin_quantized_mesh_layer announces them (water, metadata).
-- The five functions are dropped and created again with their new
-- argument lists (a call of the old forms answers the same bytes).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
DROP FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8);
DROP FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8);
DROP FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8);
DROP FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text);
DROP FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text);
CREATE  FUNCTION "tin_quantized_mesh"(
	"t" tin,
	"level" INT,
	"z" INT,
	"x" INT,
	"y" INT,
	"normals" bool DEFAULT false,
	"fill" double precision DEFAULT NULL,
	"water" geometry DEFAULT NULL,
	"metadata" bool DEFAULT false
) RETURNS bytea
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support"  COST 5000
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_quantized_mesh_level_wrapper';
CREATE  FUNCTION "tin_quantized_mesh_layer"(
	"ts" tin[],
	"normals" bool DEFAULT false,
	"fill" bool DEFAULT false,
	"name" TEXT DEFAULT 'terrain',
	"water" bool DEFAULT false,
	"metadata" bool DEFAULT false
) RETURNS json
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support"  COST 10000
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_quantized_mesh_layer_tiles_wrapper';
CREATE  FUNCTION "tin_quantized_mesh"(
	"ts" tin[],
	"z" INT,
	"x" INT,
	"y" INT,
	"normals" bool DEFAULT false,
	"fill" double precision DEFAULT NULL,
	"water" geometry DEFAULT NULL,
	"metadata" bool DEFAULT false
) RETURNS bytea
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support"  COST 10000
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_quantized_mesh_tiles_wrapper';
CREATE  FUNCTION "tin_quantized_mesh_layer"(
	"t" tin,
	"normals" bool DEFAULT false,
	"fill" bool DEFAULT false,
	"name" TEXT DEFAULT 'terrain',
	"water" bool DEFAULT false,
	"metadata" bool DEFAULT false
) RETURNS json
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support" COST 1000
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_quantized_mesh_layer_wrapper';
CREATE  FUNCTION "tin_quantized_mesh"(
	"t" tin,
	"z" INT,
	"x" INT,
	"y" INT,
	"normals" bool DEFAULT false,
	"fill" double precision DEFAULT NULL,
	"water" geometry DEFAULT NULL,
	"metadata" bool DEFAULT false
) RETURNS bytea
IMMUTABLE PARALLEL SAFE SUPPORT "_tin_plan_support" COST 5000
LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_quantized_mesh_wrapper';
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8, geometry, boolean) IS
'One Cesium quantized-mesh 1.0 tile (z, x, y in Cesium''s geographic TMS scheme: EPSG:4326, two root tiles, y from the south) of the terrain, from the coarsest level whose measured error is at most the tile''s geometric error (77,067 m / 2^z, Cesium''s own estimate), as bytea: triangles clipped exactly to the tile (neighbouring tiles share their side vertices), edge vertex lists for skirts, the oct-encoded vertex normals extension when normals is true. Positions go to longitude/latitude through PostGIS''s ST_Transform. NULL for a tile off the terrain, unless fill gives a height for the part of a tile off the terrain (then every tile is a tile, and Cesium draws a whole globe). water (polygons in any SRID, e.g. ST_Collect of the lakes meeting the tile) adds the water mask extension: 256 x 256 cells, water where the cell''s centre is in a polygon, or one byte when the tile is all land or all water. metadata adds the metadata extension: the tile''s availability for the 10 zooms below it, as tin_quantized_mesh_layer lists it. Serve with Content-Type application/vnd.quantized-mesh (see docs/serving.md).';
COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8, geometry, boolean) IS
'tin_quantized_mesh of a given level (NULL = finest) instead of the one the zoom chooses: tin_quantized_mesh(t, level, z, x, y).';
COMMENT ON FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8, geometry, boolean) IS
'tin_quantized_mesh of a terrain stored as tiles (tins sharing their seams: tin_tiles, or tin_from_raster with keep_border): one tile from every tin given, as one mesh (seam vertices one vertex, normals summed over the tins, no wall along a seam), at the level the zoom chooses from each level''s largest error over the tins. Pass the tins whose extent meets the tile, e.g. array_agg(t) over the tile table with a GiST index on the tins'' extent in degrees (docs/serving.md). The tins must share their SRID and number of levels. An empty array is off the terrain.';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text, boolean, boolean) IS
'The layer.json Cesium''s CesiumTerrainProvider reads for the tiles of tin_quantized_mesh: format quantized-mesh-1.0, scheme tms, projection EPSG:4326, the terrain''s bounds in degrees, maxzoom (the first zoom served from the finest level; Cesium refines deeper by upsampling), the available tiles per zoom (those over the terrain; with fill both root tiles too), and in extensions octvertexnormals when normals is true, watermask when water is true, metadata when metadata is true (then metadataAvailability 10: Cesium learns availability from the tiles and takes both root tiles as available, so serve them with fill; the available list stays whole for other readers).';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text, boolean, boolean) IS
'tin_quantized_mesh_layer of a terrain stored as tiles: the bounds of all the tins, the levels'' largest errors over them.';
ALTER FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8, geometry, boolean) SET search_path FROM CURRENT;
ALTER FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8, geometry, boolean) SET search_path FROM CURRENT;
ALTER FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text, boolean, boolean) SET search_path FROM CURRENT;
ALTER FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8, geometry, boolean) SET search_path FROM CURRENT;
ALTER FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text, boolean, boolean) SET search_path FROM CURRENT;
