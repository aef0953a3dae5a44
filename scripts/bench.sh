#!/usr/bin/env bash
# Foundation benchmarks on the bundled DEM, side by side with the PostGIS way,
# in one run. Prints a table of medians (ms). Not a test: timings are noisy.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
scripts/cluster.sh start >/dev/null
q() { scripts/cluster.sh psql -qAt -d tinmerge_bench "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS tinmerge_bench" -c "CREATE DATABASE tinmerge_bench"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh tinmerge_bench
q <<'SQL'
CREATE FUNCTION bench(label text, query text, n int) RETURNS TABLE(what text, median_ms numeric, runs int)
LANGUAGE plpgsql AS $$
DECLARE t0 timestamptz; ms float8[] := '{}';
BEGIN
  FOR i IN 1..n LOOP
    t0 := clock_timestamp();
    EXECUTE query;
    ms := ms || extract(epoch FROM clock_timestamp() - t0) * 1000;
  END LOOP;
  RETURN QUERY SELECT label, round((SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY x) FROM unnest(ms) x)::numeric, 2), n;
END $$;
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
CREATE TABLE pts AS SELECT geom FROM dem, ST_PixelAsCentroids(rast, 1, true);
SQL
echo "== build (UTM DEM, 344 x 363, $(q -c "SELECT count(*) FROM pts") valid pixels)"
q -F ' | ' <<'SQL'
SELECT * FROM bench('tinmerge: tin_from_raster 2 m, 5 levels', 'SELECT tin_from_raster(rast, 2.0, 5) FROM dem', 5)
UNION ALL SELECT * FROM bench('tinmerge: tin_from_raster 2 m, 1 level (free greedy Delaunay)', 'SELECT tin_from_raster(rast, 2.0, 1) FROM dem', 5)
UNION ALL SELECT * FROM bench('PostGIS: ST_DelaunayTriangles of all valid pixel centres (no simplification)', 'SELECT ST_DelaunayTriangles(ST_Collect(geom), 0, 2) FROM pts', 3);
SQL
echo "== triangles at 2 m: nested finest level vs free greedy Delaunay (one level)"
q -F ' | ' -c "SELECT tin_num_triangles(t) AS nested, (SELECT tin_num_triangles(tin_from_raster(rast, 2.0, 1)) FROM dem) AS free, round(tin_num_triangles(t)::numeric / (SELECT tin_num_triangles(tin_from_raster(rast, 2.0, 1)) FROM dem), 3) AS ratio, (SELECT ST_NumGeometries(ST_DelaunayTriangles(ST_Collect(geom), 0, 2)) FROM pts) AS postgis_full FROM terrain"
echo "== per-row reads of one stored tin (10000 rows)"
q -F ' | ' <<'SQL'
SELECT * FROM bench('header only: tin_num_triangles(t, 0) x 10000', 'SELECT sum(tin_num_triangles(t, 0)) FROM terrain, generate_series(1, 10000)', 5)
UNION ALL SELECT * FROM bench('full value via cache: tin_as_geometry(t, 0) x 100', 'SELECT count(tin_as_geometry(t, 0)) FROM terrain, generate_series(1, 100)', 5);
SQL
