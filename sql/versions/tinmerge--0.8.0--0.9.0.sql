-- tinmerge 0.8.0 -> 0.9.0. Stored values read and answer as before.
-- tin_from_raster (both forms) and tin_from_points take boundary, and
-- tin_from_raster fill_gaps (at the end): they are dropped and made anew over three new internal functions
-- (the three internal *_breaklines functions of 0.8.0 are dropped; their C
-- symbols stay for older install scripts). Values built with a boundary
-- are written in storage format 5, which 0.8.0 does not read.
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

DROP FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry);
DROP FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry);
DROP FUNCTION tin_from_points(geometry, float8, int, geometry, geometry);
DROP FUNCTION _tin_from_raster_breaklines(bytea, float8, int, int, boolean, bytea, bytea);
DROP FUNCTION _tin_from_raster_tolerances_breaklines(bytea, float8[], int, boolean, bytea, bytea);
DROP FUNCTION _tin_from_points_breaklines(bytea, float8, int, bytea, bytea);
CREATE FUNCTION _tin_from_raster_domain("rast" bytea, "tolerance" double precision, "levels" int, "band" int, "keep_border" boolean, "breaklines" bytea, "soft_breaklines" bytea, "boundary" bytea, "fill_gaps" boolean)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_raster_domain_wrapper';
COMMENT ON FUNCTION _tin_from_raster_domain(bytea, float8, int, int, boolean, bytea, bytea, bytea, boolean) IS 'Internal: use tin_from_raster(raster, ..., breaklines, soft_breaklines, boundary, fill_gaps).';
CREATE FUNCTION _tin_from_raster_tolerances_domain("rast" bytea, "tolerances" double precision[], "band" int, "keep_border" boolean, "breaklines" bytea, "soft_breaklines" bytea, "boundary" bytea, "fill_gaps" boolean)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_raster_tolerances_domain_wrapper';
COMMENT ON FUNCTION _tin_from_raster_tolerances_domain(bytea, float8[], int, boolean, bytea, bytea, bytea, boolean) IS 'Internal: use tin_from_raster(raster, float8[], ..., breaklines, soft_breaklines, boundary, fill_gaps).';
CREATE FUNCTION _tin_from_points_domain("pts" bytea, "tolerance" double precision, "levels" int, "breaklines" bytea, "soft_breaklines" bytea, "boundary" bytea)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_points_domain_wrapper';
COMMENT ON FUNCTION _tin_from_points_domain(bytea, float8, int, bytea, bytea, bytea) IS 'Internal: use tin_from_points(geometry, ..., breaklines, soft_breaklines, boundary).';

CREATE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT true)
RETURNS tin AS $$ SELECT CASE WHEN $6 IS NULL AND $7 IS NULL AND $8 IS NULL AND $9
  THEN @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5)
  ELSE @extschema@._tin_from_raster_domain($1::bytea, $2, $3, $4, $5, $6::bytea, $7::bytea, $8::bytea, $9) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. fill_gaps => false builds over the valid pixels only: the domain is the union of the valid pixels'' squares (what ST_Value answers on) within the convex hull of their centres, nodata holes left out, so tin_height is NULL wherever ST_Value is NULL (a build with a boundary of those squares); the default true fills nodata gaps, the domain being the hull. NULL for a NULL raster, tolerance, levels, band, keep_border or fill_gaps.';

CREATE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT true)
RETURNS tin AS $$ SELECT CASE WHEN $5 IS NULL AND $6 IS NULL AND $7 IS NULL AND $8
  THEN @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4)
  ELSE @extschema@._tin_from_raster_tolerances_domain($1::bytea, $2, $3, $4, $5::bytea, $6::bytea, $7::bytea, $8) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border, breaklines, soft_breaklines, boundary and fill_gaps as for tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean).';

CREATE FUNCTION tin_from_points(pts geometry, tolerance float8, levels int DEFAULT 5, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL)
RETURNS tin AS $$ SELECT CASE WHEN $4 IS NULL AND $5 IS NULL AND $6 IS NULL
  THEN @extschema@._tin_from_points($1::bytea, $2, $3)
  ELSE @extschema@._tin_from_points_domain($1::bytea, $2, $3, $4::bytea, $5::bytea, $6::bytea) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_points(geometry, float8, int, geometry, geometry, geometry) IS
'Builds a tin from every vertex of a geometry with Z (typically MULTIPOINT Z); points with equal x,y are merged (mean z). Error is measured at the samples. breaklines (LINESTRING Z / MULTILINESTRING Z, the points'' SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. NULL for NULL points, tolerance or levels.';

COMMENT ON FUNCTION tin_num_triangles(tin, int) IS 'Triangles at a level (NULL = finest; header only), in the domain: the void triangles outside a boundary are not counted.';
