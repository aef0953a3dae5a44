-- tinmerge 0.2.0 -> 0.3.0: exact hierarchy (issue 22). Raster builds now
-- decide topology on the pixel lattice and point builds split constraint
-- edges at samples within rounding of them, so new tins have no slivers
-- and no hidden cracks. tin_validate finds the ones tins built by 0.2.0
-- have; rebuild those (docs/upgrading.md). The stored value format is
-- unchanged (format version 1): every stored value still reads.
-- tests/upgrade.sh checks that this script makes exactly the catalog of a
-- fresh 0.3.0 install.
\echo Use "ALTER EXTENSION tinmerge UPDATE TO '0.3.0'" to load this file. \quit

CREATE FUNCTION tin_validate(t tin)
RETURNS TABLE(level int, problem text, triangle int, detail text)
IMMUTABLE STRICT PARALLEL SAFE COST 10000 ROWS 10 LANGUAGE c
AS 'MODULE_PATHNAME', 'tin_validate_wrapper';
COMMENT ON FUNCTION tin_validate(tin) IS
'Problems of a stored tin, one row each: level, problem (''crack'': a triangle of zero area up to rounding whose corner lies on the opposite edge while the surfaces on the two sides disagree there, a vertical wall; ''sliver'': the same where they agree), triangle id (as in tin_triangles) and a detail. No rows for a sound tin. Tins built by tinmerge 0.2.0 from rasters whose pixel centres do not round exactly (geographic grids, fractional origins) have them: rebuild those (docs/upgrading.md).';
