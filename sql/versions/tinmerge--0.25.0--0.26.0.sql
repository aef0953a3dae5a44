-- tinmerge 0.25.0 -> 0.26.0. Stored values read and answer as before. New:
-- what is built is stored in format 6 (7 with void triangles): format 4
-- (5) with each level's whole statistics in the header, so tin_area_stats,
-- tin_surface_area and tin_volume answer a polygon that holds the whole
-- terrain (a tile wholly inside a county) from the header alone.
-- tin_rewrite(t) gives older values the sums. tin_surface_area is a Rust
-- function (an SQL wrapper before).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE OR REPLACE FUNCTION "tin_surface_area"(
	"t" tin, /* core::option::Option<tinmerge::pg::tin_type::TinArg> */
	"area" geometry, /* core::option::Option<tinmerge::pg::args::GeomArg> */
	"level" INT DEFAULT NULL /* core::option::Option<i32> */
) RETURNS double precision /* core::option::Option<f64> */
IMMUTABLE PARALLEL SAFE
COST 10000
SUPPORT _tin_plan_support
LANGUAGE c /* Rust */
AS 'MODULE_PATHNAME', 'tin_surface_area_wrapper';
ALTER FUNCTION tin_surface_area(tin, geometry, int) SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_surface_area(tin, geometry, int) IS
'Surface (3D) area of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: the area3d of tin_area_stats as a scalar (0 when the polygon misses the domain; NULL when an argument other than level is NULL), so it can be used where a set-returning call cannot, e.g. pushed down to a postgres_fdw shard. A tin in a geographic SRID answers in square metres on the SRID''s spheroid.';
COMMENT ON FUNCTION tin_rewrite(tin) IS 'The same tin in the current storage format (format 6, or 7 with void triangles: compressed groups with their own checksums, about a fifth of format 3, read in slices by the point, line and area functions, and each level''s whole statistics in the header, so a tile wholly inside a polygon is answered from its header); a value already in it is returned as it is. Answers do not change. UPDATE terrain SET t = tin_rewrite(t) converts stored values (docs/upgrading.md).';
