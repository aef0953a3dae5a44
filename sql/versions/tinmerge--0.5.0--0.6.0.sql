-- tinmerge 0.5.0 -> 0.6.0: no answer changes. New values are stored in
-- format 4 (each array cut into groups of 1,024 elements, each coded,
-- compressed with zstd and checksummed: about a fifth of format 3, and
-- still read in slices). Values stored in formats 1 and 3 keep reading as
-- they are; tin_rewrite converts them.
COMMENT ON FUNCTION tin_rewrite(tin) IS 'The same tin in the current storage format (format 4: compressed groups with their own checksums, about a fifth of format 3, read in slices by the point, line and area functions); a value already in it is returned as it is. Answers do not change. UPDATE terrain SET t = tin_rewrite(t) converts stored values (docs/upgrading.md).';

-- tin_area_stats and tin_volume look the tin's SRID up in spatial_ref_sys
-- themselves (once per backend, and only when the tin's extent could be in
-- degrees), where each call used to plan and run _tin_srid_is_geographic.
-- The search_path they pin is the install script's (sql/tinmerge.sql).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);
CREATE OR REPLACE FUNCTION tin_area_stats(t tin, area geometry, level int DEFAULT NULL)
RETURNS TABLE(area2d float8, area3d float8, min_z float8, max_z float8, mean_z float8, mean_slope float8, max_slope float8) AS
$$ SELECT * FROM @extschema@._tin_area_stats($1, $2::bytea, $3, ST_IsValidReason($2), NULL) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
CREATE OR REPLACE FUNCTION tin_volume(t tin, area geometry, base_z float8, level int DEFAULT NULL)
RETURNS TABLE(cut float8, fill float8) AS
$$ SELECT * FROM @extschema@._tin_volume($1, $2::bytea, $3, $4, ST_IsValidReason($2), NULL) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 10000 ROWS 1
SET search_path FROM CURRENT;
DROP FUNCTION _tin_srid_is_geographic(int);
