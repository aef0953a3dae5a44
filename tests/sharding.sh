#!/usr/bin/env bash
# Sharding with PostgreSQL's own postgres_fdw and declarative partitioning:
# three local clusters on loopback ports (node 0 is the coordinator and holds
# shard 0 itself; nodes 1 and 2 hold shards 1 and 2). The terrain is
# replicated (one row per shard, each on its node); the feature tables
# (200,000 random points, the DEM's 624 contour lines, its 50 m contour
# bands) are hash-distributed by id: shard = abs(hashint4(id)) % 3, a
# LIST-partitioned column shared with the terrain, so a join on it is done
# partition by partition, each on its own node. With the server option
# `extensions 'postgis,tinmerge'` postgres_fdw ships the joins with the merge
# calls to the shards (checked in EXPLAIN VERBOSE: the Remote SQL of every
# foreign partition calls the merge inside an aggregate the shard computes).
# Every per-row result must equal the single-node run on the coordinator's
# own copy of the same data. Then a tiled terrain is built on the shards,
# each node its own band of raster tile rows (the halo rows read from its
# neighbours), and must be byte for byte the single-node build. Timings
# are one run each, for orientation only:
# the three "nodes" share this machine's two cores.
# Usage: tests/sharding.sh (part of make test; about a minute).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=/usr/lib/postgresql/15/bin
BASE="$PWD/target/shard"
PORTS=(28831 28832 28833)
DB=tinmerge_shard
as_pg() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}
stop_all() {
  for i in 0 1 2; do
    [ -f "$BASE/n$i/data/PG_VERSION" ] && as_pg "$BIN/pg_ctl" -D "$BASE/n$i/data" -w -m fast stop >/dev/null 2>&1 || true
  done
}
[ -n "${TINMERGE_KEEP_SHARDS:-}" ] || trap stop_all EXIT
mkdir -p "$BASE"
[ "$(id -u)" -eq 0 ] && chown postgres "$BASE"
for i in 0 1 2; do
  d="$BASE/n$i"
  mkdir -p "$d"
  [ "$(id -u)" -eq 0 ] && chown postgres "$d"
  if [ ! -f "$d/data/PG_VERSION" ]; then
    as_pg "$BIN/initdb" -D "$d/data" -A trust -U postgres --no-sync >/dev/null
  fi
  as_pg "$BIN/pg_ctl" -D "$d/data" -w -m fast stop >/dev/null 2>&1 || true
  as_pg "$BIN/pg_ctl" -D "$d/data" -l "$d/log" -w \
    -o "-p ${PORTS[$i]} -k $d -c listen_addresses=127.0.0.1 -c fsync=off" start >/dev/null
done
n() { local i=$1; shift; psql -h 127.0.0.1 -p "${PORTS[$i]}" -U postgres -v ON_ERROR_STOP=1 -qAtX "$@"; }
for i in 0 1 2; do
  n "$i" -d postgres -c "DROP DATABASE IF EXISTS $DB" -c "CREATE DATABASE $DB" 2>/dev/null
  n "$i" -d $DB -c "CREATE EXTENSION tinmerge CASCADE" 2>/dev/null
done
echo "== 3 clusters on 127.0.0.1:${PORTS[*]}; loading the DEM and features on the coordinator"
TINMERGE_PSQL="psql -h 127.0.0.1 -p ${PORTS[0]} -U postgres" scripts/load-data.sh $DB
# single-node data on the coordinator
n 0 -d $DB <<'SQL'
CREATE TABLE terrain_src AS SELECT tin_from_raster(rast, 2.0, 5) AS t FROM dem;
SELECT setseed(0.5);
CREATE TABLE pts_all AS
SELECT i AS id, ST_SetSRID(ST_MakePoint(x0 + random() * w, y0 + random() * h), 32616) AS geom
FROM (SELECT ST_XMin(e) x0, ST_YMin(e) y0, ST_XMax(e) - ST_XMin(e) w, ST_YMax(e) - ST_YMin(e) h
      FROM (SELECT tin_envelope(t)::box2d e FROM terrain_src) s) b, generate_series(1, 200000) i;
CREATE TABLE lines_all AS SELECT id, geom FROM contours;
CREATE TABLE areas_all AS SELECT id, geom FROM contour_bands WHERE ST_IsValid(geom);
SQL
# the shards' tables (nodes 1 and 2)
for i in 1 2; do
  n "$i" -d $DB <<SQL
CREATE TABLE terrain_$i (shard int NOT NULL, name text, t tin);
CREATE TABLE pts_$i (id int NOT NULL, shard int NOT NULL, geom geometry(Point, 32616));
CREATE TABLE lines_$i (id int NOT NULL, shard int NOT NULL, geom geometry(LineString, 32616));
CREATE TABLE areas_$i (id int NOT NULL, shard int NOT NULL, geom geometry(MultiPolygon, 32616));
SQL
done
# the coordinator: partitioned tables, shard 0 local, shards 1 and 2 foreign
n 0 -d $DB <<SQL
CREATE EXTENSION postgres_fdw;
CREATE SERVER node1 FOREIGN DATA WRAPPER postgres_fdw
  OPTIONS (host '127.0.0.1', port '${PORTS[1]}', dbname '$DB', extensions 'postgis,tinmerge', fdw_tuple_cost '1', async_capable 'true');
CREATE SERVER node2 FOREIGN DATA WRAPPER postgres_fdw
  OPTIONS (host '127.0.0.1', port '${PORTS[2]}', dbname '$DB', extensions 'postgis,tinmerge', fdw_tuple_cost '1', async_capable 'true');
CREATE USER MAPPING FOR postgres SERVER node1 OPTIONS (user 'postgres');
CREATE USER MAPPING FOR postgres SERVER node2 OPTIONS (user 'postgres');
CREATE TABLE terrain (shard int NOT NULL, name text, t tin) PARTITION BY LIST (shard);
CREATE TABLE pts (id int NOT NULL, shard int NOT NULL, geom geometry(Point, 32616)) PARTITION BY LIST (shard);
CREATE TABLE lines (id int NOT NULL, shard int NOT NULL, geom geometry(LineString, 32616)) PARTITION BY LIST (shard);
CREATE TABLE areas (id int NOT NULL, shard int NOT NULL, geom geometry(MultiPolygon, 32616)) PARTITION BY LIST (shard);
CREATE TABLE terrain_0 PARTITION OF terrain FOR VALUES IN (0);
CREATE TABLE pts_0 PARTITION OF pts FOR VALUES IN (0);
CREATE TABLE lines_0 PARTITION OF lines FOR VALUES IN (0);
CREATE TABLE areas_0 PARTITION OF areas FOR VALUES IN (0);
CREATE FOREIGN TABLE terrain_1 PARTITION OF terrain FOR VALUES IN (1) SERVER node1 OPTIONS (table_name 'terrain_1');
CREATE FOREIGN TABLE terrain_2 PARTITION OF terrain FOR VALUES IN (2) SERVER node2 OPTIONS (table_name 'terrain_2');
CREATE FOREIGN TABLE pts_1 PARTITION OF pts FOR VALUES IN (1) SERVER node1 OPTIONS (table_name 'pts_1');
CREATE FOREIGN TABLE pts_2 PARTITION OF pts FOR VALUES IN (2) SERVER node2 OPTIONS (table_name 'pts_2');
CREATE FOREIGN TABLE lines_1 PARTITION OF lines FOR VALUES IN (1) SERVER node1 OPTIONS (table_name 'lines_1');
CREATE FOREIGN TABLE lines_2 PARTITION OF lines FOR VALUES IN (2) SERVER node2 OPTIONS (table_name 'lines_2');
CREATE FOREIGN TABLE areas_1 PARTITION OF areas FOR VALUES IN (1) SERVER node1 OPTIONS (table_name 'areas_1');
CREATE FOREIGN TABLE areas_2 PARTITION OF areas FOR VALUES IN (2) SERVER node2 OPTIONS (table_name 'areas_2');
-- replicate the terrain (one row per shard) and distribute the features;
-- inserts into foreign partitions are routed to their nodes
INSERT INTO terrain SELECT s, 'jacksboro', t FROM terrain_src, generate_series(0, 2) s;
INSERT INTO pts SELECT id, abs(hashint4(id)) % 3, geom FROM pts_all;
INSERT INTO lines SELECT id, abs(hashint4(id)) % 3, geom FROM lines_all;
INSERT INTO areas SELECT id, abs(hashint4(id)) % 3, ST_Multi(geom) FROM areas_all;
SQL
for i in 1 2; do n "$i" -d $DB -c "ANALYZE"; done
# statistics of the foreign partitions too (sampled from the nodes): without
# them the planner's guesses make it fetch rows and join locally
n 0 -d $DB -c "ANALYZE pts" -c "ANALYZE lines" -c "ANALYZE areas" -c "ANALYZE terrain" \
  -c "ANALYZE pts_1" -c "ANALYZE pts_2" -c "ANALYZE lines_1" -c "ANALYZE lines_2" \
  -c "ANALYZE areas_1" -c "ANALYZE areas_2" -c "ANALYZE terrain_1" -c "ANALYZE terrain_2"
echo "rows per shard (coordinator, node 1, node 2):"
n 0 -d $DB -c "SELECT 'points', count(*) FILTER (WHERE shard = 0), count(*) FILTER (WHERE shard = 1), count(*) FILTER (WHERE shard = 2) FROM pts
  UNION ALL SELECT 'lines', count(*) FILTER (WHERE shard = 0), count(*) FILTER (WHERE shard = 1), count(*) FILTER (WHERE shard = 2) FROM lines
  UNION ALL SELECT 'areas', count(*) FILTER (WHERE shard = 0), count(*) FILTER (WHERE shard = 1), count(*) FILTER (WHERE shard = 2) FROM areas
  UNION ALL SELECT 'terrain copies', count(*) FILTER (WHERE shard = 0), count(*) FILTER (WHERE shard = 1), count(*) FILTER (WHERE shard = 2) FROM terrain"
# the remote copies of the terrain are the very same value
same=$(n 0 -d $DB -c "SELECT bool_and(t = (SELECT t FROM terrain_src)) FROM terrain")
[ "$same" = t ] || { echo "a shard's terrain differs from the source"; exit 1; }

# workloads: per-row results (id, result), summarised per shard by
# aggregates postgres_fdw can ship (a count and a sum of a 64-bit hash of
# each row's id and result): the shards send one row each, not their rows,
# and any row that differs changes the sum
declare -a names=(point line-drape line-climb area)
declare -a single=(
  "SELECT id, tin_height(t, geom) AS r FROM pts_all, terrain_src"
  "SELECT id, ST_3DLength(tin_drape(t, geom)) AS r FROM lines_all, terrain_src"
  "SELECT id, tin_line_climb(t, geom) AS r FROM lines_all, terrain_src"
  "SELECT id, tin_surface_area(t, geom) AS r FROM areas_all, terrain_src"
)
declare -a sharded=(
  "SELECT p.shard, p.id, tin_height(t.t, p.geom) AS r FROM pts p JOIN terrain t USING (shard)"
  "SELECT l.shard, l.id, ST_3DLength(tin_drape(t.t, l.geom)) AS r FROM lines l JOIN terrain t USING (shard)"
  "SELECT l.shard, l.id, tin_line_climb(t.t, l.geom) AS r FROM lines l JOIN terrain t USING (shard)"
  "SELECT a.shard, a.id, tin_surface_area(t.t, a.geom) AS r FROM areas a JOIN terrain t USING (shard)"
)
declare -a merge_fn=(tin_height tin_drape tin_line_climb tin_surface_area)
settings="SET enable_partitionwise_join = on; SET enable_partitionwise_aggregate = on;"
# (a hash of the float8 result seeded by the id: text casts are I/O
# coercions, which postgres_fdw does not ship; a draped line is compared by
# its exact 3D length)
h="hashfloat8extended(r, id::bigint)"
declare -a hashes=("$h" "$h" "$h" "$h")
agg() { echo "count(*) AS n, count(r) AS nr, sum($1) AS h"; }
single_q() { echo "SELECT abs(hashint4(id)) % 3 AS shard, $(agg "$2") FROM ($1) s GROUP BY 1"; }
per_shard() { echo "SELECT shard, $(agg "$2") FROM ($1) s GROUP BY shard"; }
fail=0
echo "| workload | rows | single node ms | 3 nodes ms | results |"
echo "|---|---:|---:|---:|---|"
for k in "${!names[@]}"; do
  # the plan first: a join that is not shipped would fetch the terrain with
  # every feature row (15 MB each) to the coordinator
  plan=$(n 0 -d $DB -c "$settings" -c "EXPLAIN (VERBOSE, COSTS OFF) $(per_shard "${sharded[$k]}" "${hashes[$k]}")")
  pushed=$(echo "$plan" | grep "Remote SQL" | grep -c "${merge_fn[$k]}" || true)
  if [ "$pushed" -ne 2 ]; then
    echo "| ${names[$k]} | | | | NOT PUSHED DOWN |"
    echo "$plan"
    fail=1
    continue
  fi
  t0=$(date +%s%N)
  a=$(n 0 -d $DB -c "$settings" -c "$(single_q "${single[$k]}" "${hashes[$k]}")" | sort)
  t1=$(date +%s%N)
  b=$(n 0 -d $DB -c "$settings" -c "$(per_shard "${sharded[$k]}" "${hashes[$k]}")" | sort)
  t2=$(date +%s%N)
  rows=$(echo "$a" | awk -F'|' '{ s += $2 } END { print s }')
  if [ "$a" = "$b" ]; then verdict="identical on every shard; merge computed on nodes 1 and 2"; else verdict="DIFFER: $a vs $b"; fail=1; fi
  echo "| ${names[$k]} | $rows | $(( (t1 - t0) / 1000000 )) | $(( (t2 - t1) / 1000000 )) | $verdict |"
done
echo
for k in 0 3; do
  echo "-- EXPLAIN (VERBOSE, COSTS OFF) $(per_shard "${sharded[$k]}" "${hashes[$k]}")"
  n 0 -d $DB -c "$settings" -c "EXPLAIN (VERBOSE, COSTS OFF) $(per_shard "${sharded[$k]}" "${hashes[$k]}")" | grep -v "^ *Output:"
  echo
done

# A tiled terrain built on the shards (issue 48): the DEM's raster tiles
# (ST_Tile, 16 x 16 pixels: 23 rows of tiles) are partitioned by band of
# tile rows, shard k holding rows k * 23 / 3 .. (k + 1) * 23 / 3, as
# tin_tiles_from_table's slices cut them. On every node `rtiles` is a
# partitioned table: its own band local, the other two foreign. Each node
# builds its slice (slice => k, slices => 3) into a local table at the same
# time; the halo rows its seam planning needs come from its neighbours
# through postgres_fdw (read by place: raster && box, shipped). The tiles
# must be byte for byte the single-node build's, and points on the seams
# between shards get the same height from the tiles on both sides.
echo
echo "== a tiled terrain built on the shards: each node its own band of tile rows, the halo read from its neighbours"
for i in 0 1 2; do
  others=""
  for j in 0 1 2; do
    [ "$j" = "$i" ] && continue
    if [ "$i" != 0 ]; then
      others+="CREATE SERVER node$j FOREIGN DATA WRAPPER postgres_fdw OPTIONS (host '127.0.0.1', port '${PORTS[$j]}', dbname '$DB', extensions 'postgis,postgis_raster,tinmerge', fdw_tuple_cost '1');
CREATE USER MAPPING FOR postgres SERVER node$j OPTIONS (user 'postgres');
"
    else
      others+="ALTER SERVER node$j OPTIONS (SET extensions 'postgis,postgis_raster,tinmerge');
"
    fi
    others+="CREATE FOREIGN TABLE rtiles_$j PARTITION OF rtiles FOR VALUES IN ($j) SERVER node$j OPTIONS (table_name 'rtiles_$j');
"
  done
  n "$i" -d $DB <<SQL
$( [ "$i" != 0 ] && echo "CREATE EXTENSION IF NOT EXISTS postgres_fdw;" )
CREATE TABLE rtiles (shard int NOT NULL, rast raster) PARTITION BY LIST (shard);
CREATE TABLE rtiles_$i PARTITION OF rtiles FOR VALUES IN ($i);
CREATE INDEX ON rtiles_$i USING gist (ST_ConvexHull(rast));
$others
SQL
done
n 0 -d $DB <<'SQL'
CREATE TABLE rtiles_all AS
SELECT k AS shard, t AS rast
FROM dem, ST_Tile(rast, 16, 16) t,
     LATERAL (SELECT round((ST_UpperLeftY(dem.rast) - ST_UpperLeftY(t)) / (16 * abs(ST_ScaleY(t))))::int AS ty,
                     ceil(ST_Height(dem.rast) / 16.0)::int AS rows_) r,
     LATERAL (SELECT k FROM generate_series(0, 2) k WHERE r.ty >= k * r.rows_ / 3 AND r.ty < (k + 1) * r.rows_ / 3) s;
INSERT INTO rtiles SELECT shard, rast FROM rtiles_all;
SQL
for i in 0 1 2; do n "$i" -d $DB -c "ANALYZE rtiles_$i"; done
echo "raster tiles per shard: $(n 0 -d $DB -c "SELECT string_agg(c::text, ', ' ORDER BY shard) FROM (SELECT shard, count(*) c FROM rtiles GROUP BY shard) s") (node 0 through its partitioned table)"
# what a node asks its neighbours (tin_tiles_from_table's two reads, in
# the form it sends them): the headers, one aggregate per partition, and
# the rasters of a box; both must be computed on the remote node (a plain
# select of the headers would fetch every raster whole)
remote=$(n 1 -d $DB -c "EXPLAIN (VERBOSE, COSTS OFF) SELECT NULL::text, u.* FROM (SELECT array_agg(ST_UpperLeftX(rast)) AS a0, array_agg(ST_NumBands(rast)) AS a1 FROM rtiles_0 WHERE rast IS NOT NULL) s, unnest(s.a0, s.a1) u" \
  -c "EXPLAIN (VERBOSE, COSTS OFF) SELECT ST_MetaData(rast) AS m, rast::bytea AS r FROM rtiles WHERE rast && ST_MakeEnvelope(0, 0, 1, 1, 32616)" | grep "Remote SQL")
echo "$remote" | sed 's/^ */  /'
if [ "$(echo "$remote" | grep -c "array_agg(public.st_upperleftx")" != 1 ] || [ "$(echo "$remote" | grep -c "OPERATOR(public.&&)")" != 2 ]; then
  echo "sharding: a node's reads of its neighbours' raster tiles are not computed on the neighbours"
  fail=1
fi
t0=$(date +%s%N)
pids=()
for i in 0 1 2; do
  n "$i" -d $DB -c "SET tinmerge.threads = 1" \
    -c "CREATE TABLE tins_$i (shard int NOT NULL, tx int, ty int, t tin)" \
    -c "INSERT INTO tins_$i SELECT $i, tx, ty, t FROM tin_tiles_from_table('rtiles', 2.0, 5, slice => $i, slices => 3)" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p"; done
t1=$(date +%s%N)
n 0 -d $DB <<SQL
CREATE TABLE tins (shard int NOT NULL, tx int, ty int, t tin) PARTITION BY LIST (shard);
ALTER TABLE tins ATTACH PARTITION tins_0 FOR VALUES IN (0);
CREATE FOREIGN TABLE tins_1 PARTITION OF tins FOR VALUES IN (1) SERVER node1 OPTIONS (table_name 'tins_1');
CREATE FOREIGN TABLE tins_2 PARTITION OF tins FOR VALUES IN (2) SERVER node2 OPTIONS (table_name 'tins_2');
CREATE TABLE tins_single AS SELECT tx, ty, t FROM tin_tiles_from_table('rtiles_all', 2.0, 5);
SQL
t2=$(date +%s%N)
built=$(n 0 -d $DB -F ' ' -c "SELECT count(*), count(s.t), count(*) FILTER (WHERE a.t::text = s.t::text), count(*) FILTER (WHERE NOT (a.ty >= a.shard * 23 / 3 AND a.ty < (a.shard + 1) * 23 / 3)) FROM tins a FULL JOIN tins_single s USING (tx, ty)")
read -r tiles matched same foreign_rows <<<"$built"
# the seams between shards: points along the bottom edge of each shard's
# last row of tins, heights from every tin holding them
seams=$(n 0 -d $DB -F ' ' <<'SQL'
CREATE TEMP TABLE edge AS
SELECT ST_SetSRID(ST_MakePoint(ST_XMin(e) + f * (ST_XMax(e) - ST_XMin(e)), ST_YMin(e)), 32616) AS geom
FROM (SELECT tin_envelope(t)::box2d e FROM tins a WHERE a.shard < 2 AND a.ty = (SELECT max(ty) FROM tins b WHERE b.shard = a.shard)) s,
     (SELECT i / 17.0 AS f FROM generate_series(1, 16) i) g;
SELECT count(*), count(*) FILTER (WHERE shards = 2), count(*) FILTER (WHERE spread > 1e-9), coalesce(max(spread), 0)
FROM (SELECT e.geom, count(DISTINCT a.shard) AS shards, max(z) - min(z) AS spread
      FROM edge e JOIN tins a ON tin_envelope(a.t) && e.geom, LATERAL (SELECT tin_height(a.t, e.geom) z) h
      WHERE z IS NOT NULL GROUP BY e.geom) s;
SQL
)
read -r seam_pts two_shards disagree worst <<<"$seams"
echo "| tiles on 3 shards | single node | byte for byte the same | tiles outside their shard's rows | seam points | on tins of 2 shards | heights differ (> 1e-9 m) | worst | shards ms | single node ms |"
echo "| $tiles | $matched | $same | $foreign_rows | $seam_pts | $two_shards | $disagree | $worst | $(( (t1 - t0) / 1000000 )) | $(( (t2 - t1) / 1000000 )) |"
if [ "$tiles" != "$matched" ] || [ "$tiles" != "$same" ] || [ "$foreign_rows" != 0 ] || [ "$disagree" != 0 ] || [ "$two_shards" -lt 100 ]; then
  echo "sharding: the tiles built on the shards differ from the single-node build, or their seams disagree"
  fail=1
fi
[ $fail -eq 0 ] || { echo "sharding: results differ from the single-node run, or a merge was not pushed down"; exit 1; }
echo "sharding: point, line and area merges on 3 nodes give the single-node answers, computed on the shards; the tiled terrain built on the shards is the single-node build, byte for byte"
