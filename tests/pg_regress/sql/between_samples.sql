-- Issue 43: the tolerance holds on the whole surface, not only at the pixel
-- centres. Along a grid line between two valid pixel centres the DEM is the
-- straight line between them; gdal_contour puts its contour vertices on
-- those lines at their contour's height (GDAL's own interpolation, the
-- independent oracle here). Before 0.11.0 a coarse edge kept its coarse
-- heights into every finer level: contour vertices were up to 7.8x the
-- finest tolerance off.
SET extra_float_digits = 0;
CREATE TABLE bs_terrain AS
  SELECT 'utm' AS dem, tin_from_raster(rast, 2.0, 5) AS t FROM dem
  UNION ALL
  SELECT 'geographic', tin_from_raster(rast, 2.0, 5) FROM dem_geo;
CREATE TABLE bs_vertices AS
  SELECT 'utm' AS dem, elev, (ST_DumpPoints(geom)).geom AS p FROM contours
  UNION ALL
  SELECT 'geographic', elev, (ST_DumpPoints(geom)).geom FROM contours_geo;
CREATE TABLE bs_levels AS
  SELECT b.dem, l AS level, tin_tolerance(t, l) AS tolerance,
         (tin_info(t) -> 'levels' -> l ->> 'max_error')::float8 AS max_error,
         (SELECT array_agg(tin_height(b.t, v.p, l) - v.elev) FROM bs_vertices v WHERE v.dem = b.dem) AS err
  FROM bs_terrain b, generate_series(0, 4) l;
-- every contour vertex at every level: none further from its contour's
-- height than the level's tolerance (plus 1e-9 relative); the vertices
-- tin_height leaves out (NULL) are outside the surface's domain
SELECT dem, level, tolerance, cardinality(err) AS vertices,
       (SELECT count(e) FROM unnest(err) e) > 0.99 * cardinality(err) AS nearly_all_inside,
       (SELECT count(*) FROM unnest(err) e WHERE abs(e) > tolerance * (1 + 1e-9)) AS over
FROM bs_levels ORDER BY dem DESC, level;
-- tin_info's max_error is the surface's: at least the contours' worst
-- (they lie on grid lines), at most the tolerance
SELECT dem, level,
       (SELECT max(abs(e)) FROM unnest(err) e) <= max_error * (1 + 1e-9) AS max_error_covers_contours,
       max_error <= tolerance AS max_error_within_tolerance
FROM bs_levels ORDER BY dem DESC, level;
DROP TABLE bs_levels, bs_vertices, bs_terrain;
