#!/usr/bin/env bash
# The join forms users write, side by side: the heights of 200,000 random
# points on the bundled DEM's tin at 1 m, 6 levels, through every way of
# handing a terrain row to tin_height, against ST_Value over 64x64 raster
# tiles with a GiST index (the PostGIS way), in one run. The forms run in
# interleaved rounds (each round runs every form once), so a noisy moment
# hits all of them; medians of 9 rounds. One core per query
# (max_parallel_workers_per_gather = 0), JIT as the server has it (on).
# Part of `make bench`; the table goes to docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/cluster.sh start >/dev/null
db=tinmerge_joins
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
raster2pgsql -s 32616 -N -9999 -t 64x64 -I tests/data/jacksboro_fault_dem_utm16n.tif public.dem_tiles 2>/dev/null \
  | scripts/cluster.sh psql -q -d $db >/dev/null
q <<'SQL'
-- the terrain as users make it: CREATE TABLE AS, never analyzed (autovacuum
-- never analyzes a table of one row) ...
CREATE TABLE terrain_fresh AS SELECT 1 AS id, tin_from_raster(rast, 1.0, 6) AS t FROM dem;
-- ... and the same row in a table that was analyzed
CREATE TABLE terrain AS SELECT * FROM terrain_fresh;
ANALYZE terrain;
-- the same terrain as tiles of 128 pixels with a GiST index (docs/scaling.md)
CREATE TABLE terrain_tiles AS SELECT tx, ty, t FROM dem, tin_tiles(rast, 128, 1.0, 6);
CREATE INDEX ON terrain_tiles USING gist (tin_envelope(t));
ANALYZE terrain_tiles;
SELECT setseed(0.25);
CREATE TABLE pts AS
SELECT i AS id, ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616) AS geom
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
      FROM (SELECT tin_envelope(t)::box2d e FROM terrain) s) b, generate_series(1, 200000) i;
VACUUM ANALYZE pts;
VACUUM ANALYZE dem_tiles;
-- rounds(queries, n, ref): each round runs every query once, in turn;
-- the median of each query's n times in ms, and the median over the
-- rounds of its time over query ref's in the same round (a ratio a noisy
-- moment moves less)
CREATE FUNCTION rounds(labels text[], queries text[], n int, ref int DEFAULT 1)
RETURNS TABLE(k int, what text, median_ms float8, ratio_to_ref float8) LANGUAGE plpgsql AS $$
DECLARE t0 timestamptz; qi int; ms float8[] := array_fill(0::float8, ARRAY[n, array_length(queries, 1)]);
BEGIN
  FOR r IN 1..n LOOP
    -- each round starts one query later: no query always runs after the
    -- same one (ST_Value's raster tiles push the terrain out of the CPU
    -- cache, and the query after it pays to read it back)
    FOR j IN 0..array_length(queries, 1) - 1 LOOP
      qi := (r - 1 + j) % array_length(queries, 1) + 1;
      t0 := clock_timestamp();
      EXECUTE queries[qi];
      ms[r][qi] := extract(epoch FROM clock_timestamp() - t0) * 1000;
    END LOOP;
  END LOOP;
  RETURN QUERY
  SELECT i, labels[i], (SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY ms[r][i]) FROM generate_series(1, n) r),
         (SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY ms[r][i] / ms[r][ref]) FROM generate_series(1, n) r)
  FROM generate_series(1, array_length(queries, 1)) i;
END $$;
SQL
echo "== join forms: sum(tin_height(t, geom)) of 200,000 points, the DEM's tin at 1 m, 6 levels ($(q -c "SELECT tin_num_triangles(t) FROM terrain") finest triangles; $(q -c "SELECT count(*) FROM terrain_tiles") tiles of 128 px)"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
PREPARE heights(int) AS SELECT sum(tin_height(t.t, p.geom)) FROM pts p, terrain_fresh t WHERE t.id = $1;
-- warm: every value decoded once, every library loaded
SELECT count(tin_height(t, geom)) FROM pts, terrain;
SELECT count(tin_height(t, geom)) FROM pts p JOIN terrain_tiles k ON tin_envelope(k.t) && p.geom;
SELECT count(ST_Value(rast, 1, geom)) FROM pts p JOIN dem_tiles r ON ST_Intersects(r.rast, p.geom);
CREATE TEMP TABLE res AS SELECT * FROM rounds(ARRAY[
  'comma join, terrain never analyzed: FROM pts p, terrain t',
  'comma join, terrain analyzed',
  'JOIN terrain t ON true',
  'CROSS JOIN LATERAL (SELECT t FROM terrain) t',
  'WHERE filter on the terrain row: FROM pts p, terrain t WHERE t.id = 1',
  'scalar subquery: tin_height((SELECT t FROM terrain), p.geom)',
  'prepared statement: EXECUTE heights(1) (comma join, WHERE t.id = $1)',
  'GiST join over tiles: JOIN terrain_tiles k ON tin_envelope(k.t) && p.geom',
  'PostGIS: ST_Value(rast, 1, geom), 64x64 tiles JOIN ON ST_Intersects (GiST)'], ARRAY[
  'SELECT sum(tin_height(t.t, p.geom)) FROM pts p, terrain_fresh t',
  'SELECT sum(tin_height(t.t, p.geom)) FROM pts p, terrain t',
  'SELECT sum(tin_height(t.t, p.geom)) FROM pts p JOIN terrain_fresh t ON true',
  'SELECT sum(tin_height(t.t, p.geom)) FROM pts p CROSS JOIN LATERAL (SELECT t FROM terrain_fresh) t',
  'SELECT sum(tin_height(t.t, p.geom)) FROM pts p, terrain_fresh t WHERE t.id = 1',
  'SELECT sum(tin_height((SELECT t FROM terrain_fresh), p.geom)) FROM pts p',
  'EXECUTE heights(1)',
  'SELECT sum(tin_height(k.t, p.geom)) FROM pts p JOIN terrain_tiles k ON tin_envelope(k.t) && p.geom',
  'SELECT sum(ST_Value(rast, 1, geom)) FROM pts p JOIN dem_tiles r ON ST_Intersects(r.rast, p.geom)'], 9, 6);
SELECT what AS form, round(median_ms::numeric, 1) AS median_ms,
       round((median_ms * 1000 / 200000)::numeric, 3) AS us_per_row,
       round((median_ms / min(median_ms) FILTER (WHERE k < 9) OVER ())::numeric, 2) AS x_fastest,
       round(ratio_to_ref::numeric, 2) AS x_subquery_same_round,
       round((max(median_ms) FILTER (WHERE k = 9) OVER () / median_ms)::numeric, 1) AS st_value_over_this
FROM res ORDER BY k;
SQL
echo "== plans: the comma join on the never-analyzed terrain (rows as the planner sees them)"
q -c "SET max_parallel_workers_per_gather = 0" -c "EXPLAIN SELECT sum(tin_height(t.t, p.geom)) FROM pts p, terrain_fresh t"
echo "== floors: reading the points alone, and the GiST join over tiles alone (PostgreSQL's index probe per point, no tinmerge call)"
q -F ' | ' -c "SET max_parallel_workers_per_gather = 0" -c "SELECT what, round(median_ms::numeric, 1) AS median_ms, round((median_ms * 1000 / 200000)::numeric, 3) AS us_per_row FROM rounds(ARRAY['sum(ST_X(geom)) FROM pts', 'count(*) of the GiST join over tiles', 'sum(ST_X(p.geom)) over the GiST join over tiles'], ARRAY['SELECT sum(ST_X(geom)) FROM pts', 'SELECT count(*) FROM pts p JOIN terrain_tiles k ON tin_envelope(k.t) && p.geom', 'SELECT sum(ST_X(p.geom)) FROM pts p JOIN terrain_tiles k ON tin_envelope(k.t) && p.geom'], 9) ORDER BY k"

# The other per-call figures of issue 47, against what each is measured
# with: the overlay of the DEM's tin with a copy built a fraction of a
# pixel away (31 m east, 17 m south), per output row through SQL (both
# geometries made) and its cut and fill; tin_drape of 100-vertex lines
# against tin_line_segments of the same lines; tin_drape of 1,000
# polygons on a tin with void triangles (the default build over the
# DEM's data) and on the same DEM's tin without (fill_gaps); the first
# tin_quantized_mesh of a fresh backend, after PostGIS's own first
# ST_Transform (PROJ's set-up, which any transform pays once).
q <<'SQL'
CREATE TABLE ov_a AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
CREATE TABLE ov_b AS SELECT tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 31, ST_UpperLeftY(rast) - 17), 2.0, 5) AS t FROM dem;
CREATE TABLE ov_filled AS SELECT tin_from_raster(rast, 2.0, 5, fill_gaps => true) AS t FROM dem;
SELECT setseed(0.5);
CREATE TABLE lines100 AS
SELECT i, ST_SetSRID(ST_MakeLine(ARRAY(SELECT ST_MakePoint(x0 + j * 8 + random() * 3, y0 + 400 * sin(j / 15.0) + random() * 5) FROM generate_series(1, 100) j)), 32616) AS geom
FROM (SELECT ST_XMin(e) + 300 x0, (ST_YMin(e) + ST_YMax(e)) / 2 y0 FROM (SELECT tin_envelope(t)::box2d e FROM ov_a) s) b, generate_series(1, 200) i;
CREATE TABLE polys AS
SELECT i, ST_Buffer(ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616), 20 + random() * 60, 8) AS geom
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h FROM (SELECT tin_envelope(t)::box2d e FROM ov_a) s) b, generate_series(1, 1000) i;
CREATE TABLE layer AS SELECT tin_quantized_mesh_layer(t) AS j FROM ov_a;
CREATE TABLE tiles15 AS
SELECT x, y FROM layer, LATERAL (SELECT j->'available'->15->0 AS a) r,
     generate_series((a->>'startX')::int, (a->>'endX')::int) x, generate_series((a->>'startY')::int, (a->>'endY')::int) y;
SQL
echo "== overlay of the DEM's tin (2 m, 5 levels, $(q -c "SELECT tin_num_triangles(t) FROM ov_a") finest triangles) with a copy built 31 m east and 17 m south; median of 3"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT count(*) AS output_rows FROM ov_a a, ov_b b, tin_overlay(a.t, b.t);
CREATE TEMP TABLE ovr AS SELECT * FROM rounds(ARRAY[
  'tin_overlay: SELECT count(*) FROM a, b, tin_overlay(a.t, b.t)',
  'tin_overlay, geometries read: sum(ST_NPoints(geom_a) + ST_NPoints(geom_b))',
  'tin_difference (cut, fill: the overlay without rows)'], ARRAY[
  'SELECT count(*) FROM ov_a a, ov_b b, tin_overlay(a.t, b.t)',
  'SELECT sum(ST_NPoints(geom_a) + ST_NPoints(geom_b)) FROM ov_a a, ov_b b, tin_overlay(a.t, b.t)',
  'SELECT d.cut FROM ov_a a, ov_b b, tin_difference(a.t, b.t) d'], 3);
SELECT what, round(median_ms::numeric, 1) AS median_ms,
       round((median_ms * 1000 / (SELECT count(*) FROM ov_a a, ov_b b, tin_overlay(a.t, b.t)))::numeric, 3) AS us_per_output_row
FROM ovr ORDER BY k;
SQL
echo "== tin_drape: 200 lines of 100 vertices against tin_line_segments of them; 1,000 polygons on a tin with void triangles and without; median of 9"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT what, round(median_ms::numeric, 1) AS median_ms, round(ratio_to_ref::numeric, 2) AS x_first_same_round FROM rounds(ARRAY[
  'tin_line_segments of 200 lines', 'tin_drape of the same lines',
  'tin_drape of 1,000 polygons, tin with void', 'tin_drape of 1,000 polygons, tin without void'], ARRAY[
  'SELECT count(*) FROM ov_a, lines100, tin_line_segments(t, geom)',
  'SELECT sum(ST_NPoints(tin_drape(t, geom))) FROM ov_a, lines100',
  'SELECT sum(ST_NPoints(tin_drape(t, geom))) FROM ov_a, polys',
  'SELECT sum(ST_NPoints(tin_drape(t, geom))) FROM ov_filled, polys'], 9) ORDER BY k;
SQL
echo "== first tin_quantized_mesh of a fresh backend (zoom 15 tile, UTM terrain), after PostGIS's first ST_Transform; 7 fresh backends"
for i in 1 2 3 4 5 6 7; do
  scripts/cluster.sh psql -qAtX -d $db <<'SQL' | grep -o '[0-9.]* ms' | tr '\n' ' '
\timing on
SELECT ST_X(ST_Transform(ST_SetSRID(ST_MakePoint(740000, 4000000), 32616), 4326)) IS NOT NULL;
SELECT length(tin_quantized_mesh(t, 15, x, y)) > 0 FROM ov_a, (SELECT * FROM tiles15 ORDER BY x, y LIMIT 1 OFFSET 1700) s;
SQL
  echo
done | awk '{print "PostGIS first ST_Transform: " $1 " ms | first tile: " $3 " ms"}'
