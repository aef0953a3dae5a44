-- tinmerge 0.9.0 -> 0.10.0. Stored values read and answer as before.
-- tin_from_raster (both forms): fill_gaps now defaults to false, so a
-- raster build's terrain is where the raster has data (its valid pixels'
-- squares); fill_gaps => true is 0.9.0's default, the hull of the valid
-- pixel centres. Only the default and the comment change: the functions
-- are replaced in place and views that call them keep working.
-- tin_drape: a polygon partly off the domain is cut to it (0.9.0 raised
-- an ERROR); only its comment changes here, the code is the library's.
-- tin_from_points_agg gains a six-argument form with breaklines, soft
-- breaklines and a boundary (a new aggregate beside the old one).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

CREATE OR REPLACE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN $6 IS NULL AND $7 IS NULL AND $8 IS NULL AND $9
  THEN @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5)
  ELSE @extschema@._tin_from_raster_domain($1::bytea, $2, $3, $4, $5, $6::bytea, $7::bytea, $8::bytea, $9) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. The terrain is where the raster has data: the domain is the union of the valid pixels'' squares (what ST_Value answers on) within the convex hull of their centres, nodata around and inside the data left out, so tin_height is NULL wherever ST_Value is NULL (a build with a boundary of those squares; a raster without nodata in that hull builds on its pixel lattice as before). fill_gaps => true fills the nodata gaps instead, the domain being the hull of the valid centres (the default until 0.9.0); keep_border => true needs it where nodata cuts into that hull (tiles over the valid pixels only are not built yet). NULL for a NULL raster, tolerance, levels, band, keep_border or fill_gaps.';

CREATE OR REPLACE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN $5 IS NULL AND $6 IS NULL AND $7 IS NULL AND $8
  THEN @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4)
  ELSE @extschema@._tin_from_raster_tolerances_domain($1::bytea, $2, $3, $4, $5::bytea, $6::bytea, $7::bytea, $8) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border, breaklines, soft_breaklines, boundary and fill_gaps as for tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean).';

COMMENT ON FUNCTION tin_drape(tin, geometry, int) IS
'The geometry with Z from the surface of a level (NULL = finest) and a vertex added wherever a line or ring crosses a triangle edge (as ArcGIS Interpolate Shape or H2GIS ST_Drape). Any type, multi* and collections included. Points outside the domain are dropped; lines keep their stretches inside (a line leaving and coming back becomes a MULTILINESTRING); polygons keep their intersection with the domain (a polygon cut in pieces becomes a MULTIPOLYGON), the new edges along the domain''s edge. NULL when nothing is left.';

CREATE FUNCTION _tin_points_agg_domain_step("state" internal, "pt" geometry, "tolerance" double precision, "levels" int, "breaklines" geometry, "soft_breaklines" geometry, "boundary" geometry)
RETURNS internal
IMMUTABLE PARALLEL SAFE
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_points_agg_domain_step_wrapper';
COMMENT ON FUNCTION _tin_points_agg_domain_step(internal, geometry, float8, int, geometry, geometry, geometry) IS 'Internal: the transition function of tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry).';
CREATE AGGREGATE tin_from_points_agg(pt geometry, tolerance float8, levels int, breaklines geometry, soft_breaklines geometry, boundary geometry) (
    SFUNC = _tin_points_agg_domain_step,
    STYPE = internal,
    FINALFUNC = _tin_points_agg_final,
    FINALFUNC_MODIFY = READ_WRITE,
    PARALLEL = SAFE
);
COMMENT ON AGGREGATE tin_from_points_agg(geometry, float8, int, geometry, geometry, geometry) IS
'Builds a tin from every vertex (with Z) of the rows aggregated with breaklines, soft breaklines and a boundary (each NULL for none; aggregates take no named or default arguments), as tin_from_points(ST_Collect(pt), tolerance, levels, breaklines, soft_breaklines, boundary) does: e.g. tin_from_points_agg(geom, 0.5, 5, (SELECT ST_Collect(geom) FROM roads), NULL, (SELECT geom FROM survey_area)). The three geometries are taken from the first row, as PostGIS aggregates take their extra arguments (pass constants or scalar subqueries); the rest as tin_from_points_agg(geometry, float8, int).';
