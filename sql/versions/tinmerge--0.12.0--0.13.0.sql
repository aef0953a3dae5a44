-- tinmerge 0.12.0 -> 0.13.0. Stored values read and answer as before.
-- tin_from_raster builds with hard breaklines hold each level's tolerance
-- between the samples too, but on the grid segments the lines cut (their
-- heights are their own); tin_validate(tin, raster) takes those lines
-- (breaklines => ...) to leave the same segments out (docs/upgrading.md).
SELECT pg_catalog.set_config('search_path',
    (SELECT pg_catalog.string_agg(s, ', ' ORDER BY o)
     FROM (SELECT s, pg_catalog.min(o) AS o
           FROM (VALUES ('@extschema@'::regnamespace::text, 1),
                        ((SELECT e.extnamespace::regnamespace::text
                          FROM pg_catalog.pg_extension e WHERE e.extname = 'postgis'), 2)) v(s, o)
           WHERE s IS NOT NULL GROUP BY s) d) || ', pg_temp',
    true);

COMMENT ON FUNCTION tin_info(tin) IS 'SRID, bounding box, size in bytes, storage format version and per level: tolerance, triangles, vertices and the largest error measured when built: at the source samples and, for a raster build (since 0.11.0; with a boundary or soft breaklines since 0.12.0, with hard breaklines since 0.13.0, the grid segments they cut left out), also between them where edges cross the grid lines between valid pixel centres (header only; tin_validate(tin, raster) measures a value against a raster).';

COMMENT ON FUNCTION tin_from_raster(raster, float8, int, int, boolean, geometry, geometry, geometry, boolean) IS
'Builds a tin from the valid pixel centres of one band (nodata skipped). Level i is within tolerance * 2^(levels-1-i) of every sample and of the raster''s surface between the samples too (with a boundary or soft breaklines, but for a few crossings beside their rings and lines, up to 1.5x the tolerance on the bundled DEMs, that tin_validate(tin, raster) names; hard breaklines keep their own heights, and the grid segments they cut are left out since 0.13.0): on every grid line between two valid pixel centres (their straight line, what gdal_contour and bilinear ST_Value use), a vertex being put where an edge over the tolerance crosses one; with keep_border everywhere but the one-pixel strip along the hull, whose vertices are its own samples so that tiles agree (tin_validate(tin, raster) checks a value); levels 1..16. keep_border => true decides the vertices on each side of the convex hull from that side''s samples alone, simplified to each level''s tolerance, so tiles that share a border row or column of pixels have the same vertices and the same surface along it at every level (see docs/scaling.md, tiled terrains). breaklines (LINESTRING Z / MULTILINESTRING Z, the raster''s SRID) are hard: the surface follows their own heights along them; soft_breaklines (any lines, Z ignored) are edges whose heights follow the samples along them, simplified to each level''s tolerance. Every breakline is a union of edges at every level, level 0 included; crossing lines split each other; samples on a line (up to rounding) are left out and every other sample is within each level''s tolerance. Parts of breaklines outside the samples'' convex hull are cut off; hard lines crossing at different heights raise an ERROR (docs/breaklines.md). boundary (POLYGON / MULTIPOLYGON, holes allowed, valid, the same SRID) limits the terrain to its area within the samples'' convex hull, concave parts and holes included: its rings there are edges at every level with heights from the samples, the samples outside it are left out, and every merge answers NULL or no rows outside it (the triangles there are void, not returned by tin_triangles; docs/breaklines.md). Breaklines outside the boundary shape nothing that is returned. The terrain is where the raster has data: the domain is the union of the valid pixels'' squares (what ST_Value answers on) within the convex hull of their centres, nodata around and inside the data left out, so tin_height is NULL wherever ST_Value is NULL (a build with a boundary of those squares; a raster without nodata in that hull builds on its pixel lattice as before). fill_gaps => true fills the nodata gaps instead, the domain being the hull of the valid centres (the default until 0.9.0); keep_border => true needs it where nodata cuts into that hull (tiles over the valid pixels only are not built yet). NULL for a NULL raster, tolerance, levels, band, keep_border or fill_gaps.';

DROP FUNCTION tin_validate(tin, raster, int);
DROP FUNCTION _tin_validate_raster(tin, bytea, int);
CREATE FUNCTION _tin_validate_raster("t" tin, "rast" bytea, "band" int, "breaklines" bytea)
RETURNS TABLE ("level" int, "problem" text, "triangle" int, "detail" text)
IMMUTABLE STRICT PARALLEL SAFE COST 100000
LANGUAGE c AS 'MODULE_PATHNAME', '_tin_validate_raster_wrapper';
ALTER FUNCTION _tin_validate_raster(tin, bytea, int, bytea) ROWS 10;
COMMENT ON FUNCTION _tin_validate_raster(tin, bytea, int, bytea) IS 'Internal: use tin_validate(tin, raster, int, geometry).';

CREATE FUNCTION tin_validate(t tin, rast raster, band int DEFAULT 1, breaklines geometry DEFAULT NULL)
RETURNS TABLE(level int, problem text, triangle int, detail text) AS
$$ SELECT * FROM @extschema@._tin_validate_raster($1, $2::bytea, $3, COALESCE($4::bytea, ''::bytea)) $$
LANGUAGE sql IMMUTABLE PARALLEL SAFE COST 100000 ROWS 10
SET search_path FROM CURRENT;
COMMENT ON FUNCTION tin_validate(tin, raster, int, geometry) IS
'The rows of tin_validate(tin), and one row per level further from a raster band''s surface than its tolerance (problem ''over tolerance''): the surface is the band''s value at each valid pixel centre and, on every grid line between two valid pixel centres, the straight line between them (what gdal_contour and bilinear ST_Value use); a level is linear in each triangle, so its error there is largest at a pixel centre or where an edge crosses a grid line, and both are measured. triangle holds the worst place, detail its error, position and how many crossings and centres are over. Values built by 0.10.0 and earlier kept coarse heights along coarse edges into finer levels and show here; rebuild them (docs/upgrading.md). A tile (keep_border) can show for the one-pixel strip along its hull, whose vertices are its own samples so that neighbouring tiles agree. breaklines: the hard breaklines the tin was built with (tin_from_raster''s breaklines); the surface holds their own heights along them, so the grid segments they cut (within 1e-6 pixel) and the pixel centres on them are left out, as the build leaves them out. No rows for a sound value within its tolerances. The raster and the breaklines must have the tin''s SRID; nodata pixels are skipped. No rows for a NULL tin, raster or band.';
