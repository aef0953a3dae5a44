-- tinmerge 0.7.0 -> 0.8.0. Stored values read and answer as before.
-- Builds: tin_from_points and tin_from_points_agg refine parent by parent
-- (docs/upgrading.md). tin_raster_stats and tin_raster_pixels take
-- half_open (at the end). tin_from_raster and tin_from_points take
-- breaklines and soft_breaklines (at the end): both are dropped and made
-- anew, with three new internal functions. tin_validate also reports
-- holes (its comment).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

-- tin_raster_stats and tin_raster_pixels gain half_open (tiled terrains:
-- each seam pixel counted by one tile); they call the new internal
-- _tin_raster_zonal and _tin_raster_owners, and the old internal functions
-- are dropped (their symbols stay in the library)
DROP FUNCTION tin_raster_stats(tin, raster, int, int, boolean);
DROP FUNCTION tin_raster_pixels(tin, raster, int, int);
DROP FUNCTION _tin_raster_stats(tin, bytea, int, int, boolean);
DROP FUNCTION _tin_raster_pixels(tin, bytea, int, int);
CREATE FUNCTION _tin_raster_zonal("t" tin, "rast" bytea, "level" int, "band" int, "weighted" boolean, "half_open" boolean)
RETURNS TABLE ("triangle" int, "count" bigint, "sum" double precision, "mean" double precision, "min" double precision, "max" double precision, "mode" double precision)
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_raster_zonal_wrapper';
ALTER FUNCTION _tin_raster_zonal(tin, bytea, int, int, boolean, boolean) ROWS 10000;
COMMENT ON FUNCTION _tin_raster_zonal(tin, bytea, int, int, boolean, boolean) IS 'Internal: use tin_raster_stats(tin, raster, int, int, boolean, boolean).';
CREATE FUNCTION _tin_raster_owners("t" tin, "rast" bytea, "level" int, "band" int, "half_open" boolean)
RETURNS TABLE ("triangle" int, "col" int, "row" int, "value" double precision)
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_raster_owners_wrapper';
ALTER FUNCTION _tin_raster_owners(tin, bytea, int, int, boolean) ROWS 100000;
COMMENT ON FUNCTION _tin_raster_owners(tin, bytea, int, int, boolean) IS 'Internal: use tin_raster_pixels(tin, raster, int, int, boolean).';
CREATE FUNCTION tin_raster_stats(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1, weighted boolean DEFAULT false, half_open boolean DEFAULT false)
RETURNS TABLE(triangle int, count bigint, sum float8, mean float8, min float8, max float8, mode float8) AS
$$ SELECT * FROM @extschema@._tin_raster_zonal($1, $2::bytea, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_raster_stats(tin, raster, int, int, boolean, boolean) IS
'Zonal statistics of a raster band per triangle of a level (NULL = finest). By default (scanline sweep) a pixel belongs to the triangle containing its centre (a centre on a shared edge goes to the triangle east of it, north of an east-west edge; on a vertex to the triangle just east-north-east of it; on the outer boundary to the triangle it lies on). With weighted => true every pixel a triangle overlaps counts by the exact fraction of its area inside the triangle, as exactextract does: count = pixels overlapped, sum = sum of value x fraction, mean = sum / sum of fractions, mode = value of greatest total coverage. With half_open => true a centre on the domain''s outer boundary counts only where the domain continues east of it (north of an east-west side), the rule of shared edges: over a table of tiles sharing their seams (tin_tiles) every seam centre is then counted by exactly one tile, the one a single tin of their union gives it to, and centres on the union''s west and south sides are not counted (weighted statistics need no such option: coverage fractions add up across seams). Nodata pixels are skipped; triangles receiving no pixel are not returned; mode ties go to the smallest value. The raster must be north-up, in-db, with the tin''s SRID.';

CREATE FUNCTION tin_raster_pixels(t tin, rast raster, level int DEFAULT NULL, band int DEFAULT 1, half_open boolean DEFAULT false)
RETURNS TABLE(triangle int, col int, "row" int, value float8) AS
$$ SELECT * FROM @extschema@._tin_raster_owners($1, $2::bytea, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_raster_pixels(tin, raster, int, int, boolean) IS
'Every valid pixel of a raster band with the triangle of a level (NULL = finest) containing its centre (the rule of tin_raster_stats, half_open included), in raster order; col and row numbered from 1 as in ST_Value. Nodata pixels and pixels outside the tin are left out.';


-- breaklines: the builders gain two trailing arguments; they are no longer
-- STRICT (a NULL breaklines argument means none) but give NULL for any other
-- NULL argument, as before
DROP FUNCTION tin_from_raster(raster, float8, int, int, boolean);
DROP FUNCTION tin_from_raster(raster, float8[], int, boolean);
DROP FUNCTION tin_from_points(geometry, float8, int);
CREATE FUNCTION _tin_from_raster_breaklines("rast" bytea, "tolerance" double precision, "levels" int, "band" int, "keep_border" boolean, "breaklines" bytea, "soft_breaklines" bytea)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_raster_breaklines_wrapper';
COMMENT ON FUNCTION _tin_from_raster_breaklines(bytea, float8, int, int, boolean, bytea, bytea) IS 'Internal: use tin_from_raster(raster, ..., breaklines, soft_breaklines).';
CREATE FUNCTION _tin_from_raster_tolerances_breaklines("rast" bytea, "tolerances" double precision[], "band" int, "keep_border" boolean, "breaklines" bytea, "soft_breaklines" bytea)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_raster_tolerances_breaklines_wrapper';
COMMENT ON FUNCTION _tin_from_raster_tolerances_breaklines(bytea, float8[], int, boolean, bytea, bytea) IS 'Internal: use tin_from_raster(raster, float8[], ..., breaklines, soft_breaklines).';
CREATE FUNCTION _tin_from_points_breaklines("pts" bytea, "tolerance" double precision, "levels" int, "breaklines" bytea, "soft_breaklines" bytea)
RETURNS tin IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_from_points_breaklines_wrapper';
COMMENT ON FUNCTION _tin_from_points_breaklines(bytea, float8, int, bytea, bytea) IS 'Internal: use tin_from_points(geometry, ..., breaklines, soft_breaklines).';

CREATE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL)
RETURNS tin AS $$ SELECT CASE WHEN $6 IS NULL AND $7 IS NULL
  THEN @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5)
  ELSE @extschema@._tin_from_raster_breaklines($1::bytea, $2, $3, $4, $5, $6::bytea, $7::bytea) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). NULL for a NULL raster, tolerance, levels, band or keep_border.';

CREATE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL)
RETURNS tin AS $$ SELECT CASE WHEN $5 IS NULL AND $6 IS NULL
  THEN @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4)
  ELSE @extschema@._tin_from_raster_tolerances_breaklines($1::bytea, $2, $3, $4, $5::bytea, $6::bytea) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border, breaklines and soft_breaklines as for tin_from_raster(raster, float8, int, int, boolean, geometry, geometry).';

CREATE FUNCTION tin_from_points(pts geometry, tolerance float8, levels int DEFAULT 5, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL)
RETURNS tin AS $$ SELECT CASE WHEN $4 IS NULL AND $5 IS NULL
  THEN @extschema@._tin_from_points($1::bytea, $2, $3)
  ELSE @extschema@._tin_from_points_breaklines($1::bytea, $2, $3, $4::bytea, $5::bytea) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_points(geometry, float8, int, geometry, geometry) IS
'Builds a tin from every vertex of a geometry with Z (typically MULTIPOINT Z); points with equal x,y are merged (mean z). Error is measured at the samples. breaklines (LINESTRING Z / MULTILINESTRING Z, the points'' SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). NULL for NULL points, tolerance or levels.';

COMMENT ON FUNCTION tin_validate(tin) IS 'Problems of a stored tin, one row each: level, problem (''crack'': a triangle of zero area up to rounding whose corner lies on the opposite edge while the surfaces on the two sides disagree there, a vertical wall; ''sliver'': the same where they agree; ''hole'': an edge without a neighbour inside the domain, a gap between triangles that should meet), triangle id (as in tin_triangles) and a detail. No rows for a sound tin. Tins built by tinmerge 0.2.0 from rasters whose pixel centres do not round exactly (geographic grids, fractional origins) have them: rebuild those (docs/upgrading.md).';
