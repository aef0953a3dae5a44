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

-- Untyped literals for the point and area merges too: with the geography
-- forms below, a quoted geometry matched both, so each has a text form,
-- which PostgreSQL prefers for an untyped literal and reads as a geometry.
CREATE FUNCTION tin_area_stats(t tin, area text, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS $$ SELECT * FROM @extschema@.tin_area_stats($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_stats(tin, text, int) IS
'tin_area_stats of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_area_triangles(t tin, area text, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8) AS $$ SELECT * FROM @extschema@.tin_area_triangles($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_triangles(tin, text, int, boolean) IS
'tin_area_triangles of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_drape(t tin, geom text, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@.tin_drape($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_drape(tin, text, int) IS
'tin_drape of a geom given as text (WKT or EWKT, e.g. an untyped literal): the answer for geom::geometry.';
CREATE FUNCTION tin_footprint(t tin, pt text, width float8, length float8, angle float8, level int DEFAULT NULL)
RETURNS SETOF int AS $$ SELECT * FROM @extschema@.tin_footprint($1, $2::geometry, $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 20
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_footprint(tin, text, float8, float8, float8, int) IS
'tin_footprint of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_height(t tin, pt text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_height($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_height(tin, text, int) IS
'tin_height of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_locate(t tin, pt text, level int DEFAULT NULL)
RETURNS int AS $$ SELECT @extschema@.tin_locate($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_locate(tin, text, int) IS
'tin_locate of a pt given as text (WKT or EWKT, e.g. an untyped literal): the answer for pt::geometry.';
CREATE FUNCTION tin_surface_area(t tin, area text, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_surface_area($1, $2::geometry, $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_surface_area(tin, text, int) IS
'tin_surface_area of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';
CREATE FUNCTION tin_volume(t tin, area text, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS $$ SELECT * FROM @extschema@.tin_volume($1, $2::geometry, $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_volume(tin, text, float8, int) IS
'tin_volume of an area given as text (WKT or EWKT, e.g. an untyped literal): the answer for area::geometry.';

-- A geography argument: PostgreSQL has no implicit cast to geometry, and
-- without these forms the error was "function ... does not exist". They
-- raise 22023 with a hint that names the cast and the transform (the
-- geometry form called with an argument that raises it).
CREATE FUNCTION _tin_refuse_geography(func text, arg text, t tin) RETURNS geometry AS $$
BEGIN
  RAISE EXCEPTION '%: % is a geography; tinmerge merges geometry in the tin''s SRID', func, arg
    USING ERRCODE = '22023',
          HINT = format('cast it to geometry and transform it: ST_Transform(%s::geometry, %s)', arg,
                        COALESCE(@extschema@.tin_srid(t)::text, 'tin_srid(t)'));
END $$ LANGUAGE plpgsql IMMUTABLE PARALLEL SAFE
SET search_path FROM CURRENT;
COMMENT ON FUNCTION _tin_refuse_geography(text, text, tin) IS 'Internal: the error of the geography forms.';
CREATE FUNCTION tin_area_stats(t tin, area geography, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS $$ SELECT * FROM @extschema@.tin_area_stats($1, @extschema@._tin_refuse_geography('tin_area_stats', 'area', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_stats(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_area_triangles(t tin, area geography, level int DEFAULT NULL, compact boolean DEFAULT false)
RETURNS TABLE(triangle int, level int, relation text, coverage float8) AS $$ SELECT * FROM @extschema@.tin_area_triangles($1, @extschema@._tin_refuse_geography('tin_area_triangles', 'area', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_area_triangles(tin, geography, int, boolean) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_drape(t tin, geom geography, level int DEFAULT NULL)
RETURNS geometry AS $$ SELECT @extschema@.tin_drape($1, @extschema@._tin_refuse_geography('tin_drape', 'geom', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_drape(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(geom::geometry, tin_srid(t)).';
CREATE FUNCTION tin_footprint(t tin, pt geography, width float8, length float8, angle float8, level int DEFAULT NULL)
RETURNS SETOF int AS $$ SELECT * FROM @extschema@.tin_footprint($1, @extschema@._tin_refuse_geography('tin_footprint', 'pt', $1), $3, $4, $5, $6) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 20
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_footprint(tin, geography, float8, float8, float8, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_height(t tin, pt geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_height($1, @extschema@._tin_refuse_geography('tin_height', 'pt', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_height(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_climb(t tin, line geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_line_climb($1, @extschema@._tin_refuse_geography('tin_line_climb', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_climb(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_profile(t tin, line geography, level int DEFAULT NULL)
RETURNS TABLE(distance float8, z float8) AS $$ SELECT * FROM @extschema@.tin_line_profile($1, @extschema@._tin_refuse_geography('tin_line_profile', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_profile(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_segments(t tin, line geography, level int DEFAULT NULL)
RETURNS TABLE(seq int, triangle int, geom geometry, length2d float8, length3d float8, rise float8) AS $$ SELECT * FROM @extschema@.tin_line_segments($1, @extschema@._tin_refuse_geography('tin_line_segments', 'line', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_segments(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_line_triangles(t tin, line geography, level int DEFAULT NULL, width float8 DEFAULT 0)
RETURNS TABLE(seq int, triangle int) AS $$ SELECT * FROM @extschema@.tin_line_triangles($1, @extschema@._tin_refuse_geography('tin_line_triangles', 'line', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 100
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_line_triangles(tin, geography, int, float8) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(line::geometry, tin_srid(t)).';
CREATE FUNCTION tin_locate(t tin, pt geography, level int DEFAULT NULL)
RETURNS int AS $$ SELECT @extschema@.tin_locate($1, @extschema@._tin_refuse_geography('tin_locate', 'pt', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_locate(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(pt::geometry, tin_srid(t)).';
CREATE FUNCTION tin_surface_area(t tin, area geography, level int DEFAULT NULL)
RETURNS float8 AS $$ SELECT @extschema@.tin_surface_area($1, @extschema@._tin_refuse_geography('tin_surface_area', 'area', $1), $3) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_surface_area(tin, geography, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
CREATE FUNCTION tin_volume(t tin, area geography, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS $$ SELECT * FROM @extschema@.tin_volume($1, @extschema@._tin_refuse_geography('tin_volume', 'area', $1), $3, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_volume(tin, geography, float8, int) IS
'Refuses a geography with a hint: tinmerge merges geometry in the tin''s SRID; pass ST_Transform(area::geometry, tin_srid(t)).';
