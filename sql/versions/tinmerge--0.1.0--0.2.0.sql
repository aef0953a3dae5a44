-- tinmerge 0.1.0 -> 0.2.0: equality on tin (=, <>, hash operator class) and
-- planner costs (COST, ROWS) on the merge functions; tin_surface_area;
-- tin_from_raster(..., keep_border); tin_as_svg, tin_as_gltf;
-- search_path set on the SQL-language wrappers.
-- The stored value format is unchanged (format version 1), so stored
-- values need no rewrite. tests/upgrade.sh checks that this script makes
-- exactly the catalog of a fresh 0.2.0 install.
\echo Use "ALTER EXTENSION tinmerge UPDATE TO '0.2.0'" to load this file. \quit

CREATE FUNCTION tin_eq(a tin, b tin) RETURNS bool
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_eq_wrapper';

CREATE FUNCTION tin_ne(a tin, b tin) RETURNS bool
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_ne_wrapper';

CREATE FUNCTION tin_hash(t tin) RETURNS int
IMMUTABLE STRICT PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_hash_wrapper';

COMMENT ON FUNCTION tin_eq(tin, tin) IS
'True when two tins are the same value (the same bytes; header hashes and lengths compared first). The function behind the = operator.';
COMMENT ON FUNCTION tin_ne(tin, tin) IS
'True when two tins are different values. The function behind the <> operator.';
COMMENT ON FUNCTION tin_hash(tin) IS
'32-bit hash of a tin (its stored content hash): hash operator class support for =.';

CREATE OPERATOR = (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_eq,
    COMMUTATOR = =, NEGATOR = <>,
    RESTRICT = eqsel, JOIN = eqjoinsel, HASHES
);
COMMENT ON OPERATOR =(tin, tin) IS 'same tin value (the same bytes)';

CREATE OPERATOR <> (
    LEFTARG = tin, RIGHTARG = tin, FUNCTION = tin_ne,
    COMMUTATOR = <>, NEGATOR = =,
    RESTRICT = neqsel, JOIN = neqjoinsel
);
COMMENT ON OPERATOR <>(tin, tin) IS 'different tin values';

CREATE OPERATOR CLASS tin_hash_ops DEFAULT FOR TYPE tin USING hash AS
    OPERATOR 1 = (tin, tin),
    FUNCTION 1 tin_hash(tin);

-- Planner costs (0.2.0), in PostGIS's tiers (COST 1 default, 50 low, 500
-- medium, 10000 high), on the public functions and on the internal ones an
-- inlined SQL wrapper exposes to the planner; ROWS for set-returning
-- functions. They let a join of a large feature table with a terrain use
-- parallel workers (docs/scaling.md).
ALTER FUNCTION tin_height(tin, geometry, integer) COST 50;
ALTER FUNCTION tin_locate(tin, geometry, integer) COST 50;
ALTER FUNCTION tin_footprint(tin, geometry, float8, float8, float8, integer) COST 500 ROWS 20;
ALTER FUNCTION tin_drape(tin, geometry, integer) COST 10000;
ALTER FUNCTION _tin_drape(tin, bytea, integer) COST 10000;
ALTER FUNCTION tin_as_geometry(tin, integer) COST 10000;
ALTER FUNCTION _tin_as_geometry(tin, integer) COST 10000;
ALTER FUNCTION tin_triangles(tin, integer) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_triangles(tin, integer) COST 10000 ROWS 10000;
ALTER FUNCTION tin_linetree(geometry) COST 500;
ALTER FUNCTION _tin_linetree(bytea) COST 500;
ALTER FUNCTION tin_line_triangles(tin, geometry, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_triangles(tin, linetree, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_triangles(tin, bytea, integer, float8) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_segments(tin, geometry, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_segments(tin, linetree, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_segments(tin, bytea, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_segments_tree(tin, linetree, integer) COST 500 ROWS 100;
ALTER FUNCTION tin_line_profile(tin, geometry, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_profile(tin, linetree, integer) COST 10000 ROWS 100;
ALTER FUNCTION _tin_line_profile(tin, bytea, integer) COST 10000 ROWS 100;
ALTER FUNCTION tin_line_climb(tin, geometry, integer) COST 10000;
ALTER FUNCTION tin_line_climb(tin, linetree, integer) COST 10000;
ALTER FUNCTION _tin_line_climb(tin, bytea, integer) COST 10000;
ALTER FUNCTION tin_area_triangles(tin, geometry, integer, boolean) COST 10000 ROWS 1000;
ALTER FUNCTION _tin_area_triangles(tin, bytea, integer, boolean, text) COST 10000 ROWS 1000;
ALTER FUNCTION tin_area_stats(tin, geometry, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_area_stats(tin, bytea, integer, text, boolean) COST 10000 ROWS 1;
ALTER FUNCTION _tin_area_examined(tin, bytea, integer, text) COST 10000 ROWS 1;
ALTER FUNCTION tin_volume(tin, geometry, float8, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_volume(tin, bytea, float8, integer, text, boolean) COST 10000 ROWS 1;
ALTER FUNCTION tin_from_points(geometry, float8, integer) COST 10000;
ALTER FUNCTION _tin_from_points(bytea, float8, integer) COST 10000;
ALTER FUNCTION tin_raster_stats(tin, raster, integer, integer, boolean) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_raster_stats(tin, bytea, integer, integer, boolean) COST 10000 ROWS 10000;
ALTER FUNCTION tin_raster_pixels(tin, raster, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION _tin_raster_pixels(tin, bytea, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION tin_paint(tin, raster, integer) COST 10000 ROWS 10000;
ALTER FUNCTION _tin_paint(tin, bytea, integer) COST 10000 ROWS 10000;
ALTER FUNCTION tin_overlay(tin, tin, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION _tin_overlay(tin, tin, integer, integer) COST 10000 ROWS 100000;
ALTER FUNCTION tin_overlay_tin(tin, tin, integer, integer) COST 10000;
ALTER FUNCTION _tin_overlay_tin(tin, tin, integer, integer) COST 10000;
ALTER FUNCTION tin_difference(tin, tin, integer, integer) COST 10000 ROWS 1;
ALTER FUNCTION _tin_difference(tin, tin, integer, integer) COST 10000 ROWS 1;
ALTER FUNCTION tin_cache_stats() ROWS 1;

-- 0.2.0: the surface area as a scalar (postgres_fdw ships scalar calls, not
-- set-returning ones)
CREATE FUNCTION tin_surface_area(t tin, area geometry, level int DEFAULT NULL)
RETURNS float8 AS
$$ SELECT s.area3d FROM @extschema@.tin_area_stats($1, $2, $3) s $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_surface_area(tin, geometry, int) IS
'Surface (3D) area of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: the area3d of tin_area_stats as a scalar (0 when the polygon misses the domain; NULL when an argument other than level is NULL), so it can be used where a set-returning call cannot, e.g. pushed down to a postgres_fdw shard. Planar SRIDs only.';

-- 0.2.0: tin_from_raster takes keep_border (tiles with shared border
-- samples); the old signatures are replaced, calls without it keep working
DROP FUNCTION tin_from_raster(raster, float8, int, int);
DROP FUNCTION tin_from_raster(raster, float8[], int);
DROP FUNCTION _tin_from_raster(bytea, float8, int, int);
DROP FUNCTION _tin_from_raster_tolerances(bytea, float8[], int);
CREATE FUNCTION _tin_from_raster(rast bytea, tolerance float8, levels int, band int, keep_border boolean)
RETURNS tin IMMUTABLE STRICT PARALLEL SAFE COST 10000 LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_from_raster_wrapper';
CREATE FUNCTION _tin_from_raster_tolerances(rast bytea, tolerances float8[], band int, keep_border boolean)
RETURNS tin IMMUTABLE STRICT PARALLEL SAFE COST 10000 LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_from_raster_tolerances_wrapper';
CREATE FUNCTION tin_from_raster(rast raster, tolerance float8, levels int DEFAULT 5, band int DEFAULT 1, keep_border boolean DEFAULT false)
RETURNS tin AS $$ SELECT @extschema@._tin_from_raster($1::bytea, $2, $3, $4, $5) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample; levels 1..16. keep_border => true makes every sample on the edges of the convex hull a vertex of every level, so tiles that share a border row or column of pixels have the same surface along it (see docs/scaling.md, tiled terrains).';

CREATE FUNCTION tin_from_raster(rast raster, tolerances float8[], band int DEFAULT 1, keep_border boolean DEFAULT false)
RETURNS tin AS $$ SELECT @extschema@._tin_from_raster_tolerances($1::bytea, $2, $3, $4) $$
LANGUAGE sql IMMUTABLE STRICT PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_from_raster(raster, float8[], int, boolean) IS
'Builds a tin from the valid pixel centres of one band with explicit per-level tolerances (coarsest first, strictly decreasing). keep_border as for tin_from_raster(raster, float8, int, int, boolean).';
COMMENT ON FUNCTION _tin_from_raster(bytea, float8, int, int, boolean) IS 'Internal: use tin_from_raster(raster, ...).';
COMMENT ON FUNCTION _tin_from_raster_tolerances(bytea, float8[], int, boolean) IS 'Internal: use tin_from_raster(raster, float8[], ...).';

-- 0.2.0: pictures (tin_as_svg, tin_as_gltf)
CREATE FUNCTION _tin_as_svg(t tin, level int, triangles int[], vals float8[], classes text[], features bytea, legend text, width int)
RETURNS text IMMUTABLE PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_as_svg_wrapper';
CREATE FUNCTION _tin_as_gltf(t tin, level int, texture bytea, z_factor float8)
RETURNS bytea IMMUTABLE PARALLEL SAFE LANGUAGE c
AS 'MODULE_PATHNAME', '_tin_as_gltf_wrapper';
COMMENT ON FUNCTION _tin_as_svg(tin, int, int[], float8[], text[], bytea, text, int) IS 'Internal: use tin_as_svg(tin, ...).';
COMMENT ON FUNCTION _tin_as_gltf(tin, int, bytea, float8) IS 'Internal: use tin_as_gltf(tin, ...).';
ALTER FUNCTION _tin_as_svg(tin, int, int[], float8[], text[], bytea, text, int) COST 10000;
ALTER FUNCTION _tin_as_gltf(tin, int, bytea, float8) COST 10000;

CREATE FUNCTION tin_as_svg(t tin, level int DEFAULT NULL, triangles int[] DEFAULT NULL,
                           vals float8[] DEFAULT NULL, classes text[] DEFAULT NULL,
                           features geometry DEFAULT NULL, legend text DEFAULT NULL, width int DEFAULT 800)
RETURNS text AS $$ SELECT @extschema@._tin_as_svg($1, $2, $3, $4, $5, $6::bytea, $7, $8) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_as_svg(tin, int, int[], float8[], text[], geometry, text, int) IS
'An SVG picture of one level (NULL = finest), width pixels wide, with a legend: triangles coloured by height; or, with triangles => ids and vals => values (e.g. array_agg of a merge''s output), by value (others grey); or with classes => labels, one colour per class (at most 20); triangles alone highlights them. features (a geometry in the tin''s SRID) is drawn on top. NULL when t is NULL.';

CREATE FUNCTION tin_as_gltf(t tin, level int DEFAULT NULL, texture raster DEFAULT NULL, z_factor float8 DEFAULT 1.0)
RETURNS bytea AS $$ SELECT @extschema@._tin_as_gltf($1, $2, $3::bytea, $4) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000;
COMMENT ON FUNCTION tin_as_gltf(tin, int, raster, float8) IS
'One level (NULL = finest) as a binary glTF 2.0 (.glb) mesh, y up, centred on the bounding box (the centre and SRID are in the node extras), heights times z_factor. With texture (a north-up raster in the tin''s SRID: 1 band grey, 3 RGB, 4 RGBA; at most 8192 pixels a side) the image is painted on the surface; without, vertices are coloured by height. NULL when t is NULL.';

-- search_path safety (0.2.0): every SQL-language wrapper runs with the
-- search_path of the install (this extension's schema, then PostGIS's), so
-- it works from sessions whose search_path lacks them: postgres_fdw's remote
-- sessions (pg_catalog only), pg_restore, SET search_path = ''. (PostgreSQL
-- 15 has no @extschema:postgis@ to qualify PostGIS names with; the price is
-- that the planner no longer inlines these wrappers.)
DO $$
DECLARE f regprocedure;
BEGIN
  FOR f IN
    SELECT p.oid::regprocedure
    FROM pg_proc p
    JOIN pg_depend d ON d.classid = 'pg_proc'::regclass AND d.objid = p.oid AND d.deptype = 'e'
    JOIN pg_extension e ON d.refclassid = 'pg_extension'::regclass AND d.refobjid = e.oid
    WHERE e.extname = 'tinmerge' AND p.prolang = (SELECT oid FROM pg_language WHERE lanname = 'sql')
  LOOP
    EXECUTE format('ALTER FUNCTION %s SET search_path FROM CURRENT', f);
  END LOOP;
END $$;
