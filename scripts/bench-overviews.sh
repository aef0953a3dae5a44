#!/usr/bin/env bash
# Overview tins against the tiles alone, in one run: the bundled DEM
# FACTOR times finer with fractal detail (scripts/make-big-dem.py; FACTOR
# 16: 5,504 x 5,808 = 32 million pixels of 5.6 m), loaded with
# raster2pgsql -t 256x256 -l 4,16 (PostGIS's overview tables), built with
# tin_overviews (the tiles and both overviews) and, for the tiles alone,
# tin_tiles_from_table. Then one quantized-mesh tile at the terrain's
# centre at zooms from 0 to the finest: from the tiles alone through the
# index of docs/serving.md, and from the pyramid through its index with
# the zoom (docs/serving.md, "One terrain from zoom 0"), warm (median of
# 5), with the number of tins each reads and the tile's bytes. Prints
# tables; timings are not asserted.
#
# TINMERGE_OVERVIEWS sets the overview factors (raster2pgsql -l; default
# 4,16). TINMERGE_TILES_FROM_PYRAMID=1 skips the tiles' own build and
# serves "the tiles alone" from the pyramid's rows of factor 1, which are
# the same bytes (pg_regress overviews): the billion-pixel pyramid in
# under an hour, TINMERGE_OVERVIEWS=4,16,64 TINMERGE_TILES_FROM_PYRAMID=1
# scripts/bench-overviews.sh 89.
#
# usage: scripts/bench-overviews.sh [FACTOR]
set -euo pipefail
cd "$(dirname "$0")/.."
FACTOR="${1:-16}"
TOL=1.0
LEVELS=5
OVERVIEWS="${TINMERGE_OVERVIEWS:-4,16}"
FROM_PYRAMID="${TINMERGE_TILES_FROM_PYRAMID:-0}"
DB=tinmerge_overviews
scripts/cluster.sh start >/dev/null
q() { scripts/cluster.sh psql -v ON_ERROR_STOP=1 -qAt -d "$DB" "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $DB" -c "CREATE DATABASE $DB"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
dir=target/big
mkdir -p "$dir"
if [ "$dir/dem$FACTOR.vrt" -nt "$dir/dem$FACTOR.raw" ]; then
  echo "(the DEM x$FACTOR made before, reused)"
else
  scripts/python.sh scripts/make-big-dem.py "$FACTOR" "$dir/dem$FACTOR.vrt"
fi
t0=$(date +%s.%N)
raster2pgsql -s 32616 -N -9999 -t 256x256 -l "$OVERVIEWS" -I -Y "$dir/dem$FACTOR.vrt" public.dem_tiles 2>/dev/null \
  | scripts/cluster.sh psql -q -d "$DB" >/dev/null
q -c "ANALYZE"
t1=$(date +%s.%N)
echo "== load: raster2pgsql -t 256x256 -l $OVERVIEWS"
q -F ' | ' -c "SELECT o.overview_factor AS factor, o.o_table_name AS tab FROM raster_overviews o ORDER BY 1"
q -F ' | ' -c "SELECT sum(ST_Width(rast)::bigint * ST_Height(rast)) AS pixels, count(*) AS raster_tiles, round(($t1 - $t0)::numeric, 1) AS load_s FROM dem_tiles"

echo "== build (tinmerge.threads threads, one statement each)"
HWM_KB="(regexp_match(pg_read_file('/proc/self/status'), 'VmHWM:\\s+(\\d+) kB'))[1]"
t0=$(date +%s.%N)
[ "$FROM_PYRAMID" = 1 ] || q -c "CREATE TABLE tiles AS SELECT tx, ty, t FROM tin_tiles_from_table('dem_tiles', $TOL, $LEVELS)"
t1=$(date +%s.%N)
phwm=$(q -c "SET tinmerge.max_memory = -1" -c "CREATE TABLE pyramid AS SELECT * FROM tin_overviews('dem_tiles', $TOL, $LEVELS)" -c "SELECT $HWM_KB")
t2=$(date +%s.%N)
[ "$FROM_PYRAMID" = 1 ] && q -c "CREATE TABLE tiles AS SELECT tx, ty, t FROM pyramid WHERE factor = 1"
env="ST_Transform(ST_Segmentize(tin_envelope(t), 100), 4326)"
q -c "CREATE INDEX ON tiles USING gist (($env))" -c "CREATE INDEX ON pyramid USING gist (($env))" -c "ANALYZE"
echo "| build | seconds | tins | stored MB |"
echo "|---|---:|---:|---:|"
if [ "$FROM_PYRAMID" = 1 ]; then
  q -F ' | ' -c "SELECT '| the tiles (the pyramid''s rows of factor 1; not built alone)', '', count(*), round(sum(pg_column_size(t)) / 1e6, 1) || ' |' FROM tiles"
else
  q -F ' | ' -c "SELECT '| tin_tiles_from_table (the tiles)', round(($t1 - $t0)::numeric, 1), count(*), round(sum(pg_column_size(t)) / 1e6, 1) || ' |' FROM tiles"
fi
q -F ' | ' -c "SELECT '| tin_overviews (tiles, x$OVERVIEWS; backend peak RSS ' || round($phwm / 1024.0) || ' MB)', round(($t2 - $t1)::numeric, 1), count(*), round(sum(pg_column_size(t)) / 1e6, 1) || ' |' FROM pyramid"
q -F ' | ' -c "SELECT '| layer x' || factor || ': zooms ' || minzoom || '..' || maxzoom, '', count(*), round(sum(pg_column_size(t)) / 1e6, 1) || ' |' FROM pyramid GROUP BY factor, minzoom, maxzoom ORDER BY factor"

# the terrain's centre in degrees, and the layer's deepest zoom
read -r lon lat <<<"$(q -F ' ' -c "SELECT ST_X(c), ST_Y(c) FROM (SELECT ST_Transform(ST_Centroid(ST_Union(tin_envelope(t))), 4326) AS c FROM tiles) s")"
top=$(q -c "SELECT (tin_quantized_mesh_layer(array_agg(t))->>'maxzoom')::int FROM tiles")
echo "== one quantized-mesh tile at the centre ($lon, $lat), warm: median of 5 (ms)"
echo "| zoom | tiles alone: tins read | ms | bytes | pyramid: layer | tins read | ms | bytes |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|"
for z in 0 4 8 10 12 $top; do
  read -r x y <<<"$(q -F ' ' -c "SELECT floor(($lon + 180) / (180 / 2 ^ $z))::int, floor(($lat + 90) / (180 / 2 ^ $z))::int")"
  box="ST_MakeEnvelope(-180 + $x * 180 / 2 ^ $z, -90 + $y * 180 / 2 ^ $z, -180 + ($x + 1) * 180 / 2 ^ $z, -90 + ($y + 1) * 180 / 2 ^ $z, 4326)"
  plain="SELECT count(*), length(tin_quantized_mesh(array_agg(t), $z, $x, $y)) FROM tiles WHERE $env && $box"
  pyr="SELECT count(*), length(tin_quantized_mesh(array_agg(t), $z, $x, $y)), min(factor) FROM pyramid WHERE $z BETWEEN minzoom AND maxzoom AND $env && $box"
  timed() {
    # the query 6 times in one session (the first warms): its last row and
    # the median of the other 5 times
    local out
    out=$({ echo "\\timing on"; for _ in 1 2 3 4 5 6; do echo "$1;"; done; } \
      | scripts/cluster.sh psql -qAt -F ' ' -d "$DB" 2>&1)
    echo "$(grep -v '^Time:' <<<"$out" | tail -1) $(grep '^Time:' <<<"$out" | tail -5 | awk '{ print $2 }' | sort -n | sed -n 3p)"
  }
  read -r pn pb pms <<<"$(timed "$plain")"
  read -r yn yb yf yms <<<"$(timed "$pyr")"
  echo "| $z | $pn | $pms | $pb | x$yf | $yn | $yms | $yb |"
done
