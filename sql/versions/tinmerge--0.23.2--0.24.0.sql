-- tinmerge 0.23.2 -> 0.24.0. Stored values read and answer as before; what
-- is built is built as before. New: long builds report their progress
-- (tinmerge.progress_interval: NOTICE lines; the view tin_progress, over
-- the internal _tin_progress(), for every session).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE  FUNCTION "_tin_progress"() RETURNS TABLE (
	"pid" INT,  /* i32 */
	"backend_start" timestamp with time zone,  /* Option < TimestampWithTimeZone > */
	"query_start" timestamp with time zone,  /* Option < TimestampWithTimeZone > */
	"function" TEXT,  /* String */
	"phase" TEXT,  /* String */
	"unit" TEXT,  /* String */
	"done" bigint,  /* i64 */
	"total" bigint,  /* i64 */
	"elapsed" double precision,  /* f64 */
	"rate" double precision,  /* f64 */
	"time_left" double precision,  /* Option < f64 > */
	"updated" timestamp with time zone  /* Option < TimestampWithTimeZone > */
)
STRICT VOLATILE PARALLEL SAFE 
LANGUAGE c /* Rust */
AS 'MODULE_PATHNAME', '_tin_progress_wrapper';
COMMENT ON FUNCTION _tin_progress() IS 'Internal: use the view tin_progress.';
CREATE VIEW tin_progress AS
SELECT p.pid, a.datname, a.usename, p.function, p.phase, p.done, p.total, p.unit,
       round((100.0 * p.done / nullif(p.total, 0))::numeric, 1) AS percent,
       round(p.rate::numeric, 2) AS rate,
       make_interval(secs => round(p.elapsed::numeric, 1)::float8) AS phase_elapsed,
       make_interval(secs => round(p.time_left::numeric, 1)::float8) AS time_left,
       now() - a.query_start AS statement_elapsed,
       p.updated, a.query
FROM _tin_progress() p
JOIN pg_catalog.pg_stat_activity a
  ON a.pid = p.pid AND a.backend_start = p.backend_start AND a.query_start = p.query_start
 AND a.state = 'active'
WHERE pg_catalog.pg_has_role(a.usesysid, 'USAGE')
   OR pg_catalog.pg_has_role('pg_read_all_stats', 'USAGE');
COMMENT ON VIEW tin_progress IS 'The progress of every tinmerge build running now (tin_tiles_from_table, tin_overviews, tin_tiles, tin_from_raster, tin_from_points) that has run for a second or more, one row per session: the phase of its work, done of total units (percent), the rate in units per second, the phase''s time so far and the time left at that rate, the whole statement''s time so far, when the row was last updated (about every second) and the query. Rows of other roles'' sessions need pg_read_all_stats, as in pg_stat_activity. Works without shared_preload_libraries (each backend writes a small file in pg_stat_tmp).';
-- The functions that take no tin (the builders, tin_linetree) and
-- tin_viewshed_polygon name _tin_plan_support too: planning a query that
-- calls them loads tinmerge in the session, so a parallel worker loads it
-- before it takes the session's settings, and a tinmerge.* setting made
-- before the library was loaded (postgresql.conf, ALTER DATABASE ... SET,
-- PGOPTIONS) no longer gives 'parameter "tinmerge...." cannot be set during
-- a parallel operation' warnings from parallel builds.
ALTER FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_from_raster(raster, text, int, int, boolean, geometry, geometry, geometry, boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_from_raster(raster, float8[], int, boolean, geometry, geometry, geometry, boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_tiles(raster, int, float8, int, int, boolean) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_from_points(geometry, float8, int, geometry, geometry, geometry) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_linetree(geometry) SUPPORT _tin_plan_support;
ALTER FUNCTION tin_viewshed_polygon(tin, geometry, float8, float8, float8, float8, int, boolean, float8, float8, float8) SUPPORT _tin_plan_support;
