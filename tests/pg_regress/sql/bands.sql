-- band > 1: every function with a band argument reads that band, against
-- PostGIS's values of it. A two-band raster of the top-left 160 x 160
-- pixels of the DEM window: band 1 is 5000 m minus the DEM (a wrong band
-- gives heights thousands of metres off), band 2 the DEM, both with the
-- DEM's nodata.
SET extra_float_digits = 0;
CREATE TABLE b_rast AS
  SELECT ST_AddBand(ST_MapAlgebra(rast, 1, NULL, '5000 - [rast]'), rast) AS rast
  FROM (SELECT ST_Tile(rast, 160, 160) AS rast FROM dem_window LIMIT 1) w;
SELECT ST_NumBands(rast) AS bands, (ST_SummaryStats(rast, 1)).count = (ST_SummaryStats(rast, 2)).count AS same_valid FROM b_rast;
CREATE TABLE b_px AS SELECT p.x AS col, p.y AS "row", p.val, p.geom FROM b_rast, ST_PixelAsCentroids(rast, 2, true) p;
-- the builds from band 2: every vertex (a pixel centre, or a point of a grid
-- line between two, where an edge over the tolerance crosses it) has band
-- 2's height there (PostGIS's bilinear ST_Value: along a grid line, the
-- straight line between the two centres), every valid centre is within the
-- finest tolerance
CREATE TABLE b_tins AS
  SELECT 'float' AS form, tin_from_raster(rast, 8.0, 3, band => 2) AS t FROM b_rast
  UNION ALL SELECT 'text', tin_from_raster(rast, '8.0', 3, band => 2) FROM b_rast
  UNION ALL SELECT 'array', tin_from_raster(rast, ARRAY[32.0, 16.0, 8.0], band => 2) FROM b_rast;
SELECT b.form,
       count(*) AS vertices,
       count(*) FILTER (WHERE abs(ST_Z(v.geom) - ST_Value(r.rast, 2, v.geom, resample => 'bilinear')) > 1e-6) AS off_band_2,
       count(*) FILTER (WHERE ST_Value(r.rast, 2, v.geom, resample => 'bilinear') IS NULL) AS off_the_data
FROM b_tins b, b_rast r, LATERAL (SELECT DISTINCT (ST_DumpPoints(tr.geom)).geom FROM tin_triangles(b.t) tr) v
GROUP BY 1 ORDER BY 1;
SELECT b.form, count(*) AS centres,
       count(*) FILTER (WHERE abs(tin_height(b.t, p.geom) - p.val) > 8.0 + 1e-9) AS over_tolerance
FROM b_tins b, b_px p GROUP BY 1 ORDER BY 1;
-- tiles of band 2, from the raster and from a table of raster tiles: every
-- vertex of every tile at band 2's height there
CREATE TABLE b_tiles_src AS SELECT ST_Tile(rast, 100, 100) AS rast FROM b_rast;
CREATE TABLE b_tiles AS
  SELECT 'tin_tiles' AS form, t FROM b_rast, tin_tiles(rast, 100, 8.0, 2, band => 2)
  UNION ALL SELECT 'tin_tiles_from_table', t FROM tin_tiles_from_table('b_tiles_src', 8.0, 2, band => 2);
SELECT b.form, count(DISTINCT b.t::text) AS tiles, count(*) > 0 AS some_vertices,
       count(*) FILTER (WHERE abs(ST_Z(v.geom) - ST_Value(r.rast, 2, v.geom, resample => 'bilinear')) > 1e-6) AS off_band_2,
       count(*) FILTER (WHERE ST_Value(r.rast, 2, v.geom, resample => 'bilinear') IS NULL) AS off_the_data
FROM b_tiles b, b_rast r, LATERAL (SELECT DISTINCT (ST_DumpPoints(tr.geom)).geom FROM tin_triangles(b.t) tr) v
GROUP BY 1 ORDER BY 1;
-- the raster merge on band 2: the pixels handed over carry band 2's values
-- (PostGIS, by column and row), the same pixels as band 1 (the footprints
-- are equal), and the statistics are band 2's over them
CREATE TABLE b_pixels AS SELECT p.* FROM b_tins b, b_rast r, tin_raster_pixels(b.t, r.rast, 1, band => 2) p WHERE b.form = 'float';
SELECT count(*) AS pixels,
       count(*) FILTER (WHERE o.val IS NULL OR o.val <> p.value) AS not_band_2,
       count(*) = (SELECT count(*) FROM b_tins b, b_rast r, tin_raster_pixels(b.t, r.rast, 1) WHERE b.form = 'float') AS as_many_as_band_1
FROM b_pixels p LEFT JOIN b_px o USING (col, "row");
SELECT count(*) AS triangles,
       count(*) FILTER (WHERE s.count <> a.n OR abs(s.mean - a.m) > 1e-9 * abs(a.m) OR s.min <> a.lo OR s.max <> a.hi) AS differ
FROM b_tins b, b_rast r, tin_raster_stats(b.t, r.rast, 1, band => 2) s
JOIN (SELECT triangle, count(*) AS n, avg(o.val) AS m, min(o.val) AS lo, max(o.val) AS hi
      FROM b_pixels p JOIN b_px o USING (col, "row") GROUP BY 1) a USING (triangle)
WHERE b.form = 'float';
-- tin_validate against band 2 finds nothing; against band 1 (5000 m minus
-- the DEM) every level is out of tolerance
SELECT (SELECT count(*) FROM b_tins b, b_rast r, tin_validate(b.t, r.rast, band => 2) WHERE b.form = 'float') AS problems_band_2,
       (SELECT count(*) > 0 FROM b_tins b, b_rast r, tin_validate(b.t, r.rast) WHERE b.form = 'float') AS problems_band_1;
-- a band the raster does not have
SELECT try($$SELECT tin_from_raster(rast, 2.0, 3, band => 3) FROM b_rast$$);
SELECT try($$SELECT count(*) FROM b_tins b, b_rast r, tin_raster_pixels(b.t, r.rast, 1, band => 3)$$);
DROP TABLE b_rast, b_px, b_tins, b_tiles_src, b_tiles, b_pixels;
