-- tinmerge.threads: raster statistics (zonal and weighted) and builds give
-- the very same answers on 1 and on 2 threads; the setting is range-checked.
SET extra_float_digits = 0;
-- the setting exists once the library is loaded; its default is the number
-- of cores (masked: machines differ)
SELECT tin_num_levels(t) FROM terrain;
SELECT current_setting('tinmerge.threads')::int BETWEEN 1 AND 64 AS default_in_range;
-- a 3x finer DEM (1,032 x 1,089 pixels: several bands of rows)
CREATE TEMP TABLE th_dem3 AS SELECT ST_Rescale(rast, ST_ScaleX(rast) / 3, ST_ScaleY(rast) / 3) AS rast FROM dem;
SET tinmerge.threads = 1;
CREATE TEMP TABLE th_1 AS
  SELECT l, w, s.* FROM terrain, th_dem3, unnest(ARRAY[0, 4]) l, unnest(ARRAY[false, true]) w,
         tin_raster_stats(t, rast, l, 1, w) s;
CREATE TEMP TABLE th_b1 AS SELECT tin_from_raster(rast, 4.0, 3) AS b FROM dem;
SET tinmerge.threads = 2;
SHOW tinmerge.threads;
CREATE TEMP TABLE th_2 AS
  SELECT l, w, s.* FROM terrain, th_dem3, unnest(ARRAY[0, 4]) l, unnest(ARRAY[false, true]) w,
         tin_raster_stats(t, rast, l, 1, w) s;
CREATE TEMP TABLE th_b2 AS SELECT tin_from_raster(rast, 4.0, 3) AS b FROM dem;
-- every row equal (float8 compared exactly)
SELECT l, w, count(*) AS triangles FROM th_1 GROUP BY 1, 2 ORDER BY 1, 2;
SELECT (SELECT count(*) FROM (SELECT * FROM th_1 EXCEPT ALL SELECT * FROM th_2) d)
     + (SELECT count(*) FROM (SELECT * FROM th_2 EXCEPT ALL SELECT * FROM th_1) d) AS rows_differ;
SELECT (SELECT b FROM th_b1) = (SELECT b FROM th_b2) AS builds_equal,
       tin_num_triangles((SELECT b FROM th_b1)) > 0 AS built;
-- out of range
\set VERBOSITY terse
SET tinmerge.threads = 0;
SET tinmerge.threads = 65;
\set VERBOSITY default
RESET tinmerge.threads;
DROP TABLE th_dem3, th_1, th_2, th_b1, th_b2;
