#!/usr/bin/env bash
# How long after statement_timeout (100 ms) each long operation stops:
# elapsed time of the cancelled statement minus 100 ms, median of 5. Needs
# the running cluster and a database with tables dem and terrain (argument,
# default tinmerge_bench).
set -euo pipefail
cd "$(dirname "$0")/.."
db="${1:-tinmerge_bench}"
q() { scripts/cluster.sh psql -qAt -d "$db" "$@"; }
q <<'SQL'
DROP TABLE IF EXISTS lat_b, lat_dem4;
CREATE TABLE lat_b AS SELECT tin_from_raster(rast, 1.5, 5) AS t FROM dem;
CREATE TABLE lat_dem4 AS SELECT ST_Rescale(rast, ST_ScaleX(rast) / 4, ST_ScaleY(rast) / 4) AS rast FROM dem;
SQL
echo "| operation (statement_timeout 100 ms) | median ms from timeout to error |"
echo "|---|---:|"
while IFS='|' read -r name sql; do
  ms=()
  for _ in 1 2 3 4 5; do
    t=$( { printf '\\timing on\nSET statement_timeout = 100;\n%s;\n' "$sql" | q 2>&1 || true; } | sed -n 's/^Time: \([0-9.]*\) ms.*/\1/p' | tail -1)
    ms+=("$t")
  done
  med=$(printf '%s\n' "${ms[@]}" | sort -n | sed -n 3p)
  printf '| %s | %.1f |\n' "$name" "$(echo "$med - 100" | bc -l)"
done <<'OPS'
tin_from_raster 0.5 m, 5 levels|SELECT tin_num_triangles(tin_from_raster(rast, 0.5, 5)) FROM dem
tin_difference, finest levels|SELECT * FROM terrain, lat_b, tin_difference(terrain.t, lat_b.t)
tin_overlay_tin, finest levels|SELECT tin_num_triangles(tin_overlay_tin(terrain.t, lat_b.t)) FROM terrain, lat_b
tin_raster_stats weighted, 1.9M px, finest|SELECT count(*) FROM terrain, lat_dem4, tin_raster_stats(t, rast, NULL, 1, true)
tin_raster_stats, 1.9M px, finest|SELECT count(*) FROM terrain, lat_dem4, tin_raster_stats(t, rast)
OPS
q -c "DROP TABLE lat_b, lat_dem4"
