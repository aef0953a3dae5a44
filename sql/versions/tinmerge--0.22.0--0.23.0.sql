-- tinmerge 0.22.0 -> 0.23.0. Stored values read and answer as before.
-- tin_overviews (and its internal _tin_overviews) are new: the table of
-- raster tiles and its PostGIS overviews built as one pyramid, each row
-- with the zooms its layer serves. tin_quantized_mesh and
-- tin_quantized_mesh_layer choose a zoom's level by each level's error
-- bound (its tolerance, or its measured error where larger): their
-- comments say so.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE  FUNCTION "_tin_overviews"(
	"tab" oid, /* pg_sys :: Oid */
	"column" TEXT, /* & str */
	"tolerance" double precision, /* f64 */
	"levels" INT, /* i32 */
	"band" INT, /* i32 */
	"slice" INT, /* i32 */
	"slices" INT, /* i32 */
	"fill_gaps" bool /* bool */
) RETURNS TABLE (
	"factor" INT,  /* i32 */
	"minzoom" INT,  /* i32 */
	"maxzoom" INT,  /* i32 */
	"tx" INT,  /* i32 */
	"ty" INT,  /* i32 */
	"t" tin  /* TinOut */
)
STRICT STABLE PARALLEL RESTRICTED COST 100000 
LANGUAGE c /* Rust */
AS 'MODULE_PATHNAME', '_tin_overviews_wrapper';
ALTER FUNCTION _tin_overviews(oid, text, float8, int, int, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_overviews(oid, text, float8, int, int, int, int, boolean) IS 'Internal: use tin_overviews(regclass, float8, int, name, int, int, int, boolean).';

CREATE FUNCTION tin_overviews(tiles regclass, tolerance float8, levels int DEFAULT 5, rast_column name DEFAULT 'rast', band int DEFAULT 1, slice int DEFAULT 0, slices int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(factor int, minzoom int, maxzoom int, tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_overviews($1::oid, $4::text, $2, $3, $5, $6, $7, $8) $$
LANGUAGE sql STABLE STRICT PARALLEL RESTRICTED COST 100000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_overviews(regclass, float8, int, name, int, int, int, boolean) IS
'Builds one terrain from zoom 0 to the finest as a pyramid of tiled terrains: the table of raster tiles (factor 1) and each overview PostGIS lists for its raster column in raster_overviews (raster2pgsql -l 4,16,64, ST_CreateOverview), each built as tin_tiles_from_table(overview, tolerance * factor, levels, ...) builds it (an overview of factor f, its pixels f times larger, with f times the tolerance: the same error for its pixel size) (tx, ty in that layer''s grid of tiles; seams agree at every level), each row carrying the zooms its layer serves (minzoom..maxzoom): a zoom is served by the coarsest layer whose pixels are no larger than the detail Cesium expects of it (a tile of zoom z is 65 x 65 heights, 180 / 2^z / 64 degrees apart), the finest layer up to zoom 24, the coarsest from 0; so a tile reads the tins of one layer only, at most 2 x 2 of them when the tiles are 128 pixels a side or more; a layer whose pixels are no coarser than the next finer one''s gives no rows. Serve a tile from the rows with z BETWEEN minzoom AND maxzoom whose extent meets it (docs/serving.md). slice, slices and fill_gaps as for tin_tiles_from_table, for every layer. The layers must share the table''s SRID (22023), which must be set (the zooms are measured in degrees).';

COMMENT ON FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8, geometry, boolean) IS
'One Cesium quantized-mesh 1.0 tile (z, x, y in Cesium''s geographic TMS scheme: EPSG:4326, two root tiles, y from the south) of the terrain, from the coarsest level whose error bound (its tolerance, or its measured error where larger) is at most the tile''s geometric error (77,067 m / 2^z, Cesium''s own estimate; since 0.23.0 the bound, before the measured error), as bytea: triangles clipped exactly to the tile (neighbouring tiles share their side vertices), edge vertex lists for skirts, the oct-encoded vertex normals extension when normals is true. Positions go to longitude/latitude through PostGIS''s ST_Transform. NULL for a tile off the terrain, unless fill gives a height for the part of a tile off the terrain (then every tile is a tile, and Cesium draws a whole globe). water (polygons in any SRID, e.g. ST_Collect of the lakes meeting the tile) adds the water mask extension: 256 x 256 cells, water where the cell''s centre is in a polygon, or one byte when the tile is all land or all water. metadata adds the metadata extension: the tile''s availability for the 10 zooms below it, as tin_quantized_mesh_layer lists it. Serve with Content-Type application/vnd.quantized-mesh (see docs/serving.md).';
COMMENT ON FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8, geometry, boolean) IS
'tin_quantized_mesh of a terrain stored as tiles (tins sharing their seams: tin_tiles, or tin_from_raster with keep_border): one tile from every tin given, as one mesh (seam vertices one vertex, normals summed over the tins, no wall along a seam), at the level the zoom chooses from each level''s largest error bound over the tins (its tolerance, or its measured error where larger: the same for every tin built with the same tolerance and levels, so every tile of a zoom has the same level whichever tins its index finds). Pass the tins whose extent meets the tile, e.g. array_agg(t) over the tile table with a GiST index on the tins'' extent in degrees (docs/serving.md). The tins must share their SRID and number of levels. An empty array is off the terrain.';
COMMENT ON FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text, boolean, boolean) IS
'tin_quantized_mesh_layer of a terrain stored as tiles: the bounds of all the tins, the levels'' largest error bounds over them (as tin_quantized_mesh(tin[], ...) chooses a level).';
