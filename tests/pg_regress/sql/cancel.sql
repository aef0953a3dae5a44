-- Cancellation: statement_timeout stops each long build and merge with the
-- cancel error (57014), never another error or a crash, and the session
-- goes on working. (That the stop is prompt is measured in make bench and
-- tested without timings in tests/cancel.rs.)
SET extra_float_digits = 0;
CREATE TABLE cancel_b AS SELECT tin_from_raster(rast, 1.5, 5) AS t FROM dem;
CREATE TABLE cancel_dem4 AS SELECT ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4) AS rast FROM dem;
CREATE TABLE cancel_line AS
  SELECT ST_SetSRID(ST_MakeLine(ARRAY(
    SELECT ST_MakePoint(ST_XMin(e) + (ST_XMax(e) - ST_XMin(e)) * (0.5 + 0.4 * cos(i / 5000.0 * 6.2832) * (1 + 0.05 * sin(i / 100.0))),
                        ST_YMin(e) + (ST_YMax(e) - ST_YMin(e)) * (0.5 + 0.4 * sin(i / 5000.0 * 6.2832)))
    FROM generate_series(0, 400000) i)), 32616) AS geom
  FROM terrain, tin_envelope(t) e;
-- terse: the message alone (a server started with RUST_BACKTRACE set adds
-- a backtrace as DETAIL)
\set VERBOSITY terse
SET statement_timeout = '100ms';
SELECT tin_num_triangles(tin_from_raster(rast, 0.5, 5)) FROM dem;
SELECT tin_num_triangles(t) FROM terrain;
SELECT * FROM terrain, cancel_b, tin_difference(terrain.t, cancel_b.t);
SELECT tin_num_triangles(t) FROM terrain;
SELECT tin_num_triangles(tin_overlay_tin(terrain.t, cancel_b.t)) FROM terrain, cancel_b;
SELECT tin_num_triangles(t) FROM terrain;
SELECT count(*) FROM terrain, cancel_dem4, tin_raster_stats(t, rast, NULL, 1, true);
SELECT tin_num_triangles(t) FROM terrain;
SELECT count(*) FROM terrain, cancel_line, tin_line_triangles(t, geom, NULL, 25.0);
SELECT tin_num_triangles(t) FROM terrain;
RESET statement_timeout;
\set VERBOSITY default
SELECT count(*) > 0 AS still_works FROM terrain, tin_overlay(t, t, 0, 0);
DROP TABLE cancel_b, cancel_dem4, cancel_line;
