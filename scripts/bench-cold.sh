#!/usr/bin/env bash
# First-call latency in a fresh backend (issue 24): every measurement opens a
# new connection, loads PostGIS (SELECT postgis_version()), then times one
# query with \timing; medians of 7. On two terrains: the bundled UTM DEM
# (tin_from_raster(rast, 2.0, 5)) and the same DEM upsampled x4 with
# ST_Rescale (22.5 m pixels). "sliced" is the default (point, line, area and,
# for a raster under an eighth of the terrain, raster functions read the
# stored value in slices); "whole value" sets
# tinmerge.cache_size = 0, which makes every call decode the whole value, as
# every first call did before format 3. PostGIS: ST_Value on the raster
# tiled 64 x 64 with a GiST index, also in a fresh backend.
# Part of `make bench`; the table goes to docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/cluster.sh start >/dev/null
db=tinmerge_cold
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d $db "$@"; }
scripts/cluster.sh psql -q -d postgres -c "DROP DATABASE IF EXISTS $db" -c "CREATE DATABASE $db"
q -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
scripts/load-data.sh $db >/dev/null
raster2pgsql -s 32616 -N -9999 -t 64x64 -I tests/data/jacksboro_fault_dem_utm16n.tif public.dem_tiles 2>/dev/null \
  | scripts/cluster.sh psql -q -d $db >/dev/null
q <<'SQL'
CREATE TABLE dem_x4 AS SELECT ST_Rescale(rast, 22.5, -22.5, 'Bilinear') AS rast FROM dem;
CREATE TABLE dem_x4_tiles AS SELECT ST_Tile(rast, 64, 64) AS rast FROM dem_x4;
CREATE INDEX ON dem_x4_tiles USING gist (ST_ConvexHull(rast));
CREATE TABLE rtile AS SELECT ST_Clip(rast, ST_MakeEnvelope(757500, 4051500, 758500, 4052500, 32616)) AS rast FROM dem;
CREATE TABLE terrains (name text, t tin);
INSERT INTO terrains SELECT 'small', tin_from_raster(rast, 2.0, 5) FROM dem;
SET tinmerge.max_memory = '4GB';
INSERT INTO terrains SELECT 'large', tin_from_raster(rast, 2.0, 5) FROM dem_x4;
INSERT INTO terrains SELECT 'geographic', tin_from_raster(rast, 2.0, 5) FROM dem_geo;
ANALYZE;
SQL
echo "== terrains"
q -F ' | ' -c "SELECT name, tin_num_triangles(t) AS finest_triangles, (SELECT sum((l->>'triangles')::bigint) FROM jsonb_array_elements(tin_info(t)->'levels') l) AS all_triangles, pg_column_size(t) AS bytes, round(pg_column_size(t)::numeric / tin_num_triangles(t), 1) AS bytes_per_finest_triangle FROM terrains ORDER BY name DESC"
# centre of the domain, a 2 km line and a 1 km2 square around it
centre="(SELECT ST_SetSRID(ST_MakePoint(758000.3, 4052000.7), 32616))"
line="(SELECT 'SRID=32616;LINESTRING(757000 4052000, 759000 4052100)'::geometry)"
square="(SELECT 'SRID=32616;POLYGON((757500 4051500, 758500 4051500, 758500 4052500, 757500 4052500, 757500 4051500))'::geometry)"
cold() { # label, setting, query: median ms of 7 fresh backends
  local ms=()
  for _ in 1 2 3 4 5 6 7; do
    ms+=("$(scripts/cluster.sh psql -qAtX -d $db -c "SELECT postgis_version()" -c "$2" -c '\timing on' -c "$3" 2>&1 \
      | sed -n 's/^Time: \([0-9.]*\) ms.*/\1/p' | tail -1)")
  done
  printf '%s | %s\n' "$1" "$(printf '%s\n' "${ms[@]}" | sort -n | sed -n 4p)"
}
warm() { # label, setting, query: median ms of 7 second calls in one backend
  local ms=()
  for _ in 1 2 3 4 5 6 7; do
    ms+=("$(scripts/cluster.sh psql -qAtX -d $db -c "SELECT postgis_version()" -c "$2" -c "$3" -c '\timing on' -c "$3" 2>&1 \
      | sed -n 's/^Time: \([0-9.]*\) ms.*/\1/p' | tail -1)")
  done
  printf '%s | %s\n' "$1" "$(printf '%s\n' "${ms[@]}" | sort -n | sed -n 4p)"
}
echo "== first call in a fresh backend (median ms of 7)"
for name in small large; do
  t="(SELECT t FROM terrains WHERE name = '$name')"
  cold "$name: tin_srid (header only: the floor of any first call)" "SELECT 1" "SELECT tin_srid($t)"
  cold "$name: tin_height, sliced" "SET tinmerge.cache_size = 256" "SELECT tin_height($t, $centre)"
  cold "$name: tin_height, whole value (cache_size = 0)" "SET tinmerge.cache_size = 0" "SELECT tin_height($t, $centre)"
  cold "$name: tin_height at level 0, sliced" "SET tinmerge.cache_size = 256" "SELECT tin_height($t, $centre, 0)"
  cold "$name: tin_line_segments of a 2 km line, sliced" "SET tinmerge.cache_size = 256" "SELECT count(*) FROM tin_line_segments($t, $line)"
  cold "$name: tin_line_segments of a 2 km line, whole value" "SET tinmerge.cache_size = 0" "SELECT count(*) FROM tin_line_segments($t, $line)"
  cold "$name: tin_area_stats of 1 km2, sliced" "SET tinmerge.cache_size = 256" "SELECT area3d FROM tin_area_stats($t, $square)"
  cold "$name: tin_area_stats of 1 km2, whole value" "SET tinmerge.cache_size = 0" "SELECT area3d FROM tin_area_stats($t, $square)"
  warm "$name: tin_area_stats of 1 km2, second call in the backend" "SET tinmerge.cache_size = 256" "SELECT area3d FROM tin_area_stats($t, $square)"
  # (postgis_raster loaded first: its own first load, GDAL's set-up, is
  # about 45 ms whatever the query)
  cold "$name: tin_raster_stats of a 1 km2 tile, sliced" "SET tinmerge.cache_size = 256; SELECT postgis_raster_lib_version()" "SELECT count(*) FROM rtile r, tin_raster_stats($t, r.rast) s"
  cold "$name: tin_raster_stats of a 1 km2 tile, whole value" "SET tinmerge.cache_size = 0; SELECT postgis_raster_lib_version()" "SELECT count(*) FROM rtile r, tin_raster_stats($t, r.rast) s"
done
cold "small: PostGIS ST_Value, 64x64 tiles + GiST" "SELECT 1" "SELECT ST_Value(rast, $centre) FROM dem_tiles WHERE ST_Intersects(rast, $centre)"
cold "large: PostGIS ST_Value, 64x64 tiles + GiST" "SELECT 1" "SELECT ST_Value(rast, $centre) FROM dem_x4_tiles WHERE ST_Intersects(rast, $centre)"
echo "== warm, per row: 200,000 random points, one backend (median ms of 3)"
q -F ' | ' <<'SQL'
SET max_parallel_workers_per_gather = 0;
SELECT setseed(0.5);
CREATE TEMP TABLE rp AS SELECT ST_SetSRID(ST_MakePoint(731000 + random() * 30800, 4036600 + random() * 32500), 32616) AS p FROM generate_series(1, 200000);
CREATE FUNCTION pg_temp.med(q text) RETURNS numeric LANGUAGE plpgsql AS $$
DECLARE t0 timestamptz; ms float8[] := '{}';
BEGIN
  FOR i IN 1..3 LOOP t0 := clock_timestamp(); EXECUTE q; ms := ms || extract(epoch FROM clock_timestamp() - t0) * 1000; END LOOP;
  RETURN round((SELECT percentile_cont(0.5) WITHIN GROUP (ORDER BY x) FROM unnest(ms) x)::numeric, 1);
END $$;
SELECT 'small: sum(tin_height(t, p))', pg_temp.med('SELECT sum(tin_height(t, p)) FROM rp, terrains WHERE name = ''small''')
UNION ALL SELECT 'PostGIS: sum(ST_Value(rast, p)), 64x64 tiles + GiST', pg_temp.med('SELECT sum(ST_Value(rast, p)) FROM rp JOIN dem_tiles ON ST_Intersects(rast, p)');
SQL
# The same first calls with tinmerge in shared_preload_libraries: the
# postmaster loads the library once, so a new backend does not (dlopen and
# _PG_init were about 0.4 ms of every first call). docs/sql-reference.md,
# "Settings".
echo "== first call in a fresh backend, shared_preload_libraries = 'tinmerge' (median ms of 7)"
scripts/cluster.sh psql -q -d postgres -c "ALTER SYSTEM SET shared_preload_libraries = 'tinmerge'"
restart() { scripts/cluster.sh stop; scripts/cluster.sh start >/dev/null; }
trap 'scripts/cluster.sh psql -q -d postgres -c "ALTER SYSTEM RESET shared_preload_libraries" && restart' EXIT
restart
for name in small large; do
  t="(SELECT t FROM terrains WHERE name = '$name')"
  cold "$name, preloaded: tin_srid" "SELECT 1" "SELECT tin_srid($t)"
  cold "$name, preloaded: tin_height" "SELECT 1" "SELECT tin_height($t, $centre)"
  cold "$name, preloaded: tin_line_segments of a 2 km line" "SELECT 1" "SELECT count(*) FROM tin_line_segments($t, $line)"
  cold "$name, preloaded: tin_area_stats of 1 km2" "SELECT 1" "SELECT area3d FROM tin_area_stats($t, $square)"
done
