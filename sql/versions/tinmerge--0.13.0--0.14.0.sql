-- tinmerge 0.13.0 -> 0.14.0. Stored values read and answer as before.
-- tin_tiles and tin_tiles_from_table hold each level's tolerance in the
-- one-pixel strips along the tiles' seams too (docs/upgrading.md). Untyped
-- literals: text forms of the line functions (a quoted line matched both
-- the geometry and the linetree forms) and of tin_from_raster's tolerance
-- (NULL or 'Infinity' matched both the float8 and the float8[] forms).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

-- An untyped tolerance (NULL, 'Infinity', '{8,4,2}') matches both the
-- float8 and the float8[] forms; this text form, which PostgreSQL prefers
-- for it, reads it as one float8, or as the tolerances per level when it
-- is an array literal.
CREATE FUNCTION tin_from_raster(rast raster, tolerance text, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false, breaklines geometry DEFAULT NULL, soft_breaklines geometry DEFAULT NULL, boundary geometry DEFAULT NULL, fill_gaps boolean DEFAULT false)
RETURNS tin AS $$ SELECT CASE WHEN pg_catalog.btrim($2) LIKE '{%'
  THEN @extschema@.tin_from_raster($1, $2::float8[], $4, $5, $6, $7, $8, $9)
  ELSE @extschema@.tin_from_raster($1, $2::float8, $3, $4, $5, $6, $7, $8, $9) END $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_from_raster(raster, text, int, int, boolean, geometry, geometry, geometry, boolean) IS
'tin_from_raster with the tolerance given as text (e.g. an untyped literal: NULL, ''Infinity'', ''2.5''): tin_from_raster(rast, tolerance::float8, levels, ...); an array literal (''{8,4,2}'') is the tolerances per level, coarsest first: tin_from_raster(rast, tolerance::float8[], band, ...), levels unused.';

-- Untyped literals: a quoted line ('SRID=32616;LINESTRING(...)', as
-- PostGIS users write them) matches both the geometry and the linetree
-- forms, and PostgreSQL refused it as "not unique". PostgreSQL prefers a
-- text form for an untyped literal, so these take the text as a geometry
-- (PostGIS's own text forms, ST_AsText(text) and others, do the same).
CREATE FUNCTION tin_line_triangles(t tin, line text, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS
$$ SELECT * FROM @extschema@.tin_line_triangles($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_triangles(tin, text, int, float8) IS
'tin_line_triangles of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_segments(t tin, line text, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS
$$ SELECT * FROM @extschema@.tin_line_segments($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, text, int) IS
'tin_line_segments of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_profile(t tin, line text, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS
$$ SELECT * FROM @extschema@.tin_line_profile($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_profile(tin, text, int) IS
'tin_line_profile of a line given as text (WKT or EWKT, e.g. an untyped literal): the rows of line::geometry.';
CREATE FUNCTION tin_line_climb(t tin, line text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_line_climb($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_climb(tin, text, int) IS
'tin_line_climb of a line given as text (WKT or EWKT, e.g. an untyped literal): the value for line::geometry.';
