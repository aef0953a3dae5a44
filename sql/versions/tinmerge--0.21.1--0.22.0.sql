-- tinmerge 0.21.1 -> 0.22.0. Stored values read and answer as before.
-- tin_tiles and tin_tiles_from_table take fill_gaps (default false, as
-- tin_from_raster: each tile over its valid pixels' squares only): they and
-- their internal functions are dropped and created again with the new
-- argument lists. A call of the old form now builds tiles over the data;
-- fill_gaps => true builds what it built before. tin_from_raster(...,
-- keep_border => true) builds a tile over its data where nodata cuts into
-- its hull (refused before): its comment says so.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
DROP FUNCTION tin_tiles(raster, int, float8, int, int);
DROP FUNCTION _tin_tiles(bytea, int, float8, int, int);
DROP FUNCTION tin_tiles_from_table(regclass, float8, int, name, int, int, int);
DROP FUNCTION _tin_tiles_table(oid, text, float8, int, int, int, int);
CREATE  FUNCTION "_tin_tiles"(
	"rast" bytea, /* & [u8] */
	"tile_px" INT, /* i32 */
	"tolerance" double precision, /* f64 */
	"levels" INT, /* i32 */
	"band" INT, /* i32 */
	"fill_gaps" bool /* bool */
) RETURNS TABLE (
	"tx" INT,  /* i32 */
	"ty" INT,  /* i32 */
	"t" tin  /* TinOut */
)
IMMUTABLE STRICT PARALLEL SAFE COST 10000 
LANGUAGE c /* Rust */
AS 'MODULE_PATHNAME', '_tin_tiles_wrapper';
ALTER FUNCTION _tin_tiles(bytea, int, float8, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_tiles(bytea, int, float8, int, int, boolean) IS 'Internal: use tin_tiles(raster, int, float8, int, int, boolean).';
CREATE  FUNCTION "_tin_tiles_table"(
	"tab" oid, /* pg_sys :: Oid */
	"column" TEXT, /* & str */
	"tolerance" double precision, /* f64 */
	"levels" INT, /* i32 */
	"band" INT, /* i32 */
	"slice" INT, /* i32 */
	"slices" INT, /* i32 */
	"fill_gaps" bool /* bool */
) RETURNS TABLE (
	"tx" INT,  /* i32 */
	"ty" INT,  /* i32 */
	"t" tin  /* TinOut */
)
STRICT STABLE PARALLEL RESTRICTED COST 100000 
LANGUAGE c /* Rust */
AS 'MODULE_PATHNAME', '_tin_tiles_table_wrapper';
ALTER FUNCTION _tin_tiles_table(oid, text, float8, int, int, int, int, boolean) ROWS 100;
COMMENT ON FUNCTION _tin_tiles_table(oid, text, float8, int, int, int, int, boolean) IS 'Internal: use tin_tiles_from_table(regclass, float8, int, name, int, int, int, boolean).';

CREATE FUNCTION tin_tiles(rast raster, tile_px int, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles($1::bytea, $2, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles(raster, int, float8, int, int, boolean) IS
'Builds one band of a raster as a grid of tins in one call: tile (tx, ty) (numbered from 0, west to east and north to south) holds tile_px x tile_px pixels plus the first column of its right neighbour and the first row of the one below, and is built as tin_from_raster(..., keep_border => true) does, so neighbouring tiles have the same vertices on their shared seam at every level and their surfaces agree along it. As for tin_from_raster, the terrain is where the raster has data (fill_gaps => false, the default): a tile whose nodata pixels reach into the hull of its valid centres has for domain the valid pixels'' squares within that hull, clipped to its seams (the centre lines of its shared column and row), so tin_height is NULL wherever ST_Value is; the outline''s pieces on a seam have the same vertices and heights seen from both tiles, so the tiles'' domains meet without gap or overlap. fill_gaps => true fills the gaps: each tile is the hull of its valid centres (the only form until 0.22.0). Tiles are built on tinmerge.threads threads; a tile without three non-collinear valid pixels gives no row. NULL arguments give no rows. Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';
CREATE FUNCTION tin_tiles_from_table(tiles regclass, tolerance float8, levels int DEFAULT 5, rast_column name DEFAULT 'rast', band int DEFAULT 1, slice int DEFAULT 0, slices int DEFAULT 1, fill_gaps boolean DEFAULT false)
RETURNS TABLE(tx int, ty int, t tin) AS
$$ SELECT * FROM @extschema@._tin_tiles_table($1::oid, $4::text, $2, $3, $5, $6, $7, $8) $$
LANGUAGE sql STABLE STRICT PARALLEL RESTRICTED COST 100000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_tiles_from_table(regclass, float8, int, name, int, int, int, boolean) IS
'Builds one band (of the raster column rast_column) of a table of raster tiles (raster2pgsql -t, ST_Tile: one pixel grid, tiles cut at multiples of one size) as a grid of tins in one call: tile (tx, ty) (numbered from 0 from the top-left tile, west to east and north to south) is built from its own pixels plus the first column of the tile to its right, the first row of the one below and the first pixel of the one below-right, as tin_tiles(raster, ...) builds the tiles of one raster, so seams agree at every level. Tiles are read a row at a time and built on tinmerge.threads threads, so memory stays bounded by two rows of tiles whatever the table''s size. Tiles whose pixel size, skew or SRID differ, or that are not a whole number of pixels apart, raise an ERROR (22023). slice => k, slices => n (0 <= k < n) returns only the k-th of n bands of tile rows (ty from k * rows / n up to the next band''s), each tile byte for byte what the whole build gives it: the seams are planned with 10 more rows of tiles on each side, so n sessions can each build and insert one slice at the same time (docs/scaling.md); a slice out of range raises 22023. fill_gaps as for tin_tiles: by default each tile is over its valid pixels'' squares only; fill_gaps => true fills the gaps (the only form until 0.22.0). Index the result with CREATE INDEX ON tiles USING gist (tin_envelope(t)) (docs/scaling.md).';
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample and of the raster''s surface between the samples too (with a boundary or soft breaklines too; hard breaklines keep their own heights, and the grid segments they cut are left out): on every grid line between two valid pixel centres (their straight line, what gdal_contour and bilinear ST_Value use), a vertex being put where an edge over the tolerance crosses one; with keep_border everywhere but the one-pixel strip along the hull, whose vertices are its own samples so that tiles agree (tin_validate(tin, raster) checks a value); levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. The terrain is where the raster has data: the domain is the union of the valid pixels'' squares (what ST_Value answers on) within the convex hull of their centres, nodata around and inside the data left out, so tin_height is NULL wherever ST_Value is NULL (a build with a boundary of those squares; a raster without nodata in that hull builds on its pixel lattice as before). fill_gaps => true fills the nodata gaps instead, the domain being the hull of the valid centres (the default until 0.9.0). With keep_border => true and nodata cutting into that hull, the tile is built over its data as tin_tiles builds it (since 0.22.0): the valid squares within the hull, clipped to its outer pixel centres, the outline''s pieces there chosen from their own samples so that the tile beside it agrees. NULL for a NULL raster, tolerance, levels, band, keep_border or fill_gaps.';
