#!/usr/bin/env bash
# Zonal statistics at the cost of the boundary (issue 76): tin_area_stats of
# circles of growing radius on the bundled DEM's tin (1 m, 6 levels), summed
# triangle by triangle (the flat path: a fresh backend, three calls, below
# the work that makes the sums) and with the level's subtree sums (made by a
# whole-domain call with a small hole first: without the hole the header's
# whole-level sums would answer it), side by side with what PostGIS users run:
# ST_SummaryStatsAgg(ST_Clip(rast, circle)) over the DEM as 64 x 64 tiles
# with a GiST index, in the same run. Medians in ms; not a test (timings
# are noisy). Needs tinmerge installed (make install, or make bench, which
# runs scripts/bench.sh first).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/cluster.sh start >/dev/null
db=tinmerge_bench_area
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null 2>&1
q -f scripts/bench-fn.sql
raster2pgsql -s 32616 -N -9999 -t 64x64 -I tests/data/jacksboro_fault_dem_utm16n.tif public.dem_tiles 2>/dev/null | q >/dev/null
q <<'SQL'
CREATE TABLE terrain AS SELECT tin_from_raster(rast, 1.0, 6) AS t FROM dem;
CREATE TABLE circles AS
SELECT r, ST_Buffer(ST_Centroid(tin_envelope(t)), r, 32) AS g FROM terrain, unnest(ARRAY[100, 500, 1000, 5000, 10000]) r;
ANALYZE;
SQL
echo "== tin_area_stats of a circle, tin at 1 m, 6 levels ($(q -c "SELECT tin_num_triangles(t) FROM terrain") triangles at the finest level); $(date -u '+%Y-%m-%d %H:%M') UTC, $(nproc) cores"
echo "radius m | inside triangles | flat ms | with sums ms | PostGIS ms | flat / sums | PostGIS / sums"
for r in 100 500 1000 5000 10000; do
  g="(SELECT g FROM circles WHERE r = $r)"
  stats="SELECT s.* FROM terrain, tin_area_stats(t, $g) s"
  flat=$(q -c "SELECT median_ms FROM bench('flat', \$\$$stats\$\$, 3)")
  sums=$(q -c "SELECT count(*) FROM terrain, tin_area_stats(t, ST_Difference(ST_Expand(tin_envelope(t), 10), ST_Buffer(ST_Centroid(tin_envelope(t)), 1)))" \
           -c "SELECT median_ms FROM bench('sums', \$\$$stats\$\$, 9)" | tail -1)
  pg=$(q -c "SELECT median_ms FROM bench('postgis', \$\$SELECT (ST_SummaryStatsAgg(ST_Clip(rast, $g), 1, true)).mean FROM dem_tiles WHERE ST_Intersects(rast, $g)\$\$, 5)")
  n=$(q -c "SELECT count(*) FROM terrain, tin_area_triangles(t, $g) a WHERE a.relation = 'inside'")
  awk -v r="$r" -v n="$n" -v f="$flat" -v s="$sums" -v p="$pg" \
    'BEGIN { printf "%s | %s | %.2f | %.2f | %.2f | %.1fx | %.1fx\n", r, n, f, s, p, f / s, p / s }'
done
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE $db"
