-- tinmerge 0.4.0 -> 0.5.0: no answer changes. New values are stored in
-- format 3 (blocks with their own checksums, so the per-row point functions
-- read a stored terrain in slices); values stored before keep reading as
-- they are, and tin_rewrite converts them.
CREATE FUNCTION tin_rewrite(t tin) RETURNS tin
IMMUTABLE STRICT PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_rewrite_wrapper';
COMMENT ON FUNCTION tin_rewrite(tin) IS 'The same tin in the current storage format (format 3: blocks with their own checksums, read in slices by the per-row point functions); a value already in it is returned as it is. Answers do not change. UPDATE terrain SET t = tin_rewrite(t) converts stored values (docs/upgrading.md).';
COMMENT ON FUNCTION tin_info(tin) IS 'SRID, bounding box, size in bytes, storage format version and per level: tolerance, triangles, vertices and the max error measured at the source samples (header only).';

-- tin_cache_stats also reports the values read in slices
DROP FUNCTION tin_cache_stats();
CREATE FUNCTION tin_cache_stats()
RETURNS TABLE(hits bigint, misses bigint, entries int, bytes bigint, sliced_values int, sliced_blocks bigint, sliced_bytes bigint)
VOLATILE STRICT PARALLEL SAFE
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_cache_stats_wrapper';
ALTER FUNCTION tin_cache_stats() ROWS 1;
COMMENT ON FUNCTION tin_cache_stats() IS 'This backend''s decoded-tin cache: hits, misses, entries and bytes; and the stored values it reads in slices (per-row point functions on a value it has not decoded): values, blocks held, bytes held (see tinmerge.cache_size).';
--
-- tin_drape is a Rust function that reads its geometry and writes its result
-- in PostGIS's own serialisation (it was a SQL wrapper over _tin_drape,
-- converting to EWKB and back on every row): the same function, arguments,
-- defaults and comment, about 4x faster per row on points.
CREATE OR REPLACE FUNCTION tin_drape(t tin, geom geometry, level int DEFAULT NULL)
RETURNS geometry
IMMUTABLE PARALLEL SAFE COST 10000
LANGUAGE c AS 'MODULE_PATHNAME', 'tin_drape_wrapper';
DROP FUNCTION _tin_drape(tin, bytea, int);

-- The SQL-language functions run with a search_path pinned to what they
-- need: this extension's schema, PostGIS's schema (each once), pg_temp last
-- (0.2.0 to 0.4.0 captured the install's whole setting, e.g.
-- "public, public, public, pg_temp"). The same expression as in the install
-- script (sql/tinmerge.sql).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
DO $$
DECLARE f regprocedure;
BEGIN
  FOR f IN
    SELECT p.oid::regprocedure
    FROM pg_catalog.pg_proc p
    JOIN pg_catalog.pg_depend d ON d.classid = 'pg_catalog.pg_proc'::regclass AND d.objid = p.oid AND d.deptype = 'e'
    JOIN pg_catalog.pg_extension e ON d.refclassid = 'pg_catalog.pg_extension'::regclass AND d.refobjid = e.oid
    WHERE e.extname = 'tinmerge' AND p.prolang = (SELECT oid FROM pg_catalog.pg_language WHERE lanname = 'sql')
  LOOP
    EXECUTE pg_catalog.format('ALTER FUNCTION %s SET search_path FROM CURRENT', f);
  END LOOP;
END $$;
